//! The title and "Set-up": the oscillator, the start, the step sizes, how
//! errors are measured, and the methods as `butcher!` proved them.

use std::fmt::Write as _;

use compare::paper_oscillator::{Experiment, Findings, Method};

use super::{sci2, yes_no};

pub(super) fn write(w: &mut String, exp: &Experiment, f: &Findings) {
    title(w);
    let _ = writeln!(w, "## Set-up\n");
    problem(w, exp, f);
    methods(w);
}

/// The title, and the version that wrote the report: this crate's (the
/// jobs crate is released with the `symlab` program; both are 0.1.0).
fn title(w: &mut String) {
    let _ = writeln!(w, "# Tan et al., section 5, reproduced\n");
    let _ = writeln!(
        w,
        "Written by `symlab paper` (symlab {}). Every number in this report was computed in this run; \
         nothing in it is copied from the paper or typed in by hand.\n",
        env!("CARGO_PKG_VERSION")
    );
}

/// The oscillator, its start, the step sizes and the error measures.
fn problem(w: &mut String, exp: &Experiment, f: &Findings) {
    let c = &exp.config;
    let (h_max, n) = (f.h_max, c.steps);
    let k_note = if c.k == 1.0 {
        "the paper does not state k (its closed form is written for any k), so k = 1 is our choice"
    } else {
        "chosen on the command line (the paper does not state k)"
    };
    let z_note = if c.q0 == 1.0 && c.p0 == 0.0 {
        "the paper does not state the initial state either; q₀ = 1, p₀ = 0 is our choice"
    } else {
        "chosen on the command line (the paper does not state the initial state)"
    };
    let _ = writeln!(
        w,
        "- The oscillator H = ½(p² + k²q²) of the paper's section 5, with k = {}: {k_note}.",
        c.k
    );
    let _ = writeln!(
        w,
        "- Initial state q₀ = {}, p₀ = {} (H₀ = {}): {z_note}.",
        c.q0,
        c.p0,
        c.energy0()
    );
    let hs: Vec<String> = c.step_sizes.iter().map(|h| h.to_string()).collect();
    let _ = writeln!(
        w,
        "- {n} steps at each step size h = {} (the paper's 0.01, 0.05 and 0.1 s and 200 steps).",
        hs.join(", ")
    );
    let _ = writeln!(
        w,
        "- Errors are numerical minus analytic (the paper's definition for its figure 4), with the analytic \
         solution q(t) = q₀ cos kt + (p₀/k) sin kt, p(t) = p₀ cos kt − kq₀ sin kt. The paper's printed form \
         √(q₀² + p₀²/k²)·cos(kt − arctg(p₀/(kq₀))) differs from it by at most {} over the run at h = {h_max}.",
        sci2(f.closed_form_deviation)
    );
    let _ = writeln!(
        w,
        "- Phase error: the angle of (q, −p/k) of the numerical solution minus that of the analytic one \
         (negative: the numerical solution lags).\n"
    );
}

/// The paper's name for a method.
fn paper_name(m: Method) -> &'static str {
    match m {
        Method::ExplicitEuler => "(general) Euler scheme",
        Method::Heun => "Heun–Runge–Kutta (fig. 3)",
        Method::ImplicitMidpoint => "Euler midpoint formula, \"1-order Gauss–Legendre\" (eq. 20)",
        Method::PaperDirk2 => "2-order 2-step semi-implicit symplectic RK (fig. 2)",
        Method::GaussLegendre2 => "\"2-order Gauss–Legendre\", 4-order 2-step implicit RK (eq. 21)",
        Method::SymplecticEuler => "symplectic Euler (fig. 5, conclusions)",
    }
}

/// The methods' table, with what `butcher!` proved of each.
fn methods(w: &mut String) {
    let _ = writeln!(
        w,
        "The methods, as `butcher!` proved them at compile time from their tables:\n"
    );
    let _ = writeln!(
        w,
        "| method | catalogue id | stages | class | order | symplectic | paper's name |"
    );
    let _ = writeln!(w, "|---|---|---|---|---|---|---|");
    for m in Method::ALL {
        let info = m.info();
        let _ = writeln!(
            w,
            "| {} | `{}` | {} | {} | {} | {} | {} |",
            m.label(),
            m.id(),
            info.stages,
            info.class,
            info.order,
            yes_no(info.symplectic),
            paper_name(m)
        );
    }
    let _ = writeln!(
        w,
        "\nThe paper does not print the table of its 2-stage semi-implicit method; `paper-dirk2` is the \
         standard symplectic DIRK it describes, A = [[1/4, 0], [1/2, 1/4]], b = (1/2, 1/2) (two implicit \
         midpoint steps of size h/2). Symplectic Euler is the variant that updates p first (a kick, then a \
         drift), the usual \"semi-implicit Euler\" of cloth simulation.\n"
    );
}
