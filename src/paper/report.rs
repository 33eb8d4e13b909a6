//! `report.md`: what the paper claimed, what this run measured, where they
//! differ. Every number is taken from the runs of the experiment.

use std::fmt::Write as _;

use compare::format::{self, MISSING};
use integrator_core::library::{GaussLegendre2, ImplicitMidpoint, PaperDirk2};

use super::oscillator::{
    Config, ENERGY_FLOOR, Experiment, Method, Trajectory, h_name, paper_closed_form_deviation,
};

/// Numbers derived from the runs, beyond the per-run summaries.
#[derive(Clone, Debug)]
pub struct Findings {
    /// The largest and smallest step sizes of the set-up.
    pub h_max: f64,
    pub h_min: f64,
    /// Explicit Euler at `h_max`: `|ΔH|` after `n/10` steps and at the end.
    pub euler_early: f64,
    pub euler_final: f64,
    /// The prediction `H₀((1 + h²k²)ⁿ − 1)` for explicit Euler at `h_max`.
    pub euler_predicted: f64,
    /// Heun at `h_max`: `|ΔH|` after `n/10` steps and at the end, and the
    /// steps at which it did not grow.
    pub heun_early: f64,
    pub heun_final: f64,
    pub heun_decreases: usize,
    /// The prediction `H₀((1 + (hk)⁴/4)ⁿ − 1)` for Heun at `h_max`.
    pub heun_predicted: f64,
    /// Symplectic Euler: the largest drift of its modified energy
    /// `H̃ = H − (hk²/2)·qp`, relative to `H₀`, over all step sizes.
    pub symplectic_euler_modified_drift: f64,
    /// The implicit midpoint rule at `h_max`: the phase error after `n/2`
    /// and `n` steps, and the prediction `−n·(hk − 2·atan(hk/2))`.
    pub midpoint_phase_half: f64,
    pub midpoint_phase_final: f64,
    pub midpoint_phase_predicted: f64,
    /// Symplectic Euler at `h_max`: the phase error after `n/2` and `n` steps.
    pub symplectic_euler_phase_half: f64,
    pub symplectic_euler_phase_final: f64,
    /// Its secular part, `n·(acos(1 − (hk)²/2) − hk)`.
    pub symplectic_euler_phase_predicted: f64,
    /// The paper's printed closed form against the exact flow used here.
    pub closed_form_deviation: f64,
}

/// The run of `m` at `h`; the experiment runs every method at every step
/// size of its set-up, so this exists for those.
fn run(exp: &Experiment, m: Method, h: f64) -> &Trajectory {
    exp.get(m, h)
        .unwrap_or_else(|| unreachable!("every method runs at every step size"))
}

impl Findings {
    pub fn of(exp: &Experiment) -> Findings {
        let c = &exp.config;
        let h_max = c.step_sizes.iter().copied().fold(f64::MIN, f64::max);
        let h_min = c.step_sizes.iter().copied().fold(f64::MAX, f64::min);
        let n = c.steps;
        let (k, e0) = (c.k, c.energy0());
        let euler = run(exp, Method::ExplicitEuler, h_max);
        let heun = run(exp, Method::Heun, h_max);
        let mid = run(exp, Method::ImplicitMidpoint, h_max);
        let se = run(exp, Method::SymplecticEuler, h_max);
        let hk = h_max * k;
        let symplectic_euler_modified_drift = c
            .step_sizes
            .iter()
            .map(|&h| {
                let r = run(exp, Method::SymplecticEuler, h);
                let modified = |i: usize| {
                    r.energy_error[i] - 0.5 * h * k * k * (r.q[i] * r.p[i] - r.q[0] * r.p[0])
                };
                (0..r.t.len())
                    .map(modified)
                    .fold(0.0f64, |m, x| m.max(x.abs()))
                    / e0
            })
            .fold(0.0, f64::max);
        let (mid_phase, se_phase) = (mid.phase_error(), se.phase_error());
        Findings {
            h_max,
            h_min,
            euler_early: at(&euler.energy_error, n / 10).abs(),
            euler_final: at(&euler.energy_error, n).abs(),
            euler_predicted: e0 * ((1.0 + hk * hk).powi(n as i32) - 1.0),
            heun_early: at(&heun.energy_error, n / 10).abs(),
            heun_final: at(&heun.energy_error, n).abs(),
            heun_decreases: heun.energy_error_decreases(),
            heun_predicted: e0 * ((1.0 + hk.powi(4) / 4.0).powi(n as i32) - 1.0),
            symplectic_euler_modified_drift,
            midpoint_phase_half: at(&mid_phase, n / 2),
            midpoint_phase_final: at(&mid_phase, n),
            midpoint_phase_predicted: -(n as f64) * (hk - 2.0 * (hk / 2.0).atan()),
            symplectic_euler_phase_half: at(&se_phase, n / 2),
            symplectic_euler_phase_final: at(&se_phase, n),
            symplectic_euler_phase_predicted: n as f64 * ((1.0 - hk * hk / 2.0).acos() - hk),
            closed_form_deviation: paper_closed_form_deviation(euler, c),
        }
    }
}

/// `v[i]`, or NaN for a run that stopped before step `i` (printed as
/// [`MISSING`]; the report lists the runs that stopped and why).
fn at(v: &[f64], i: usize) -> f64 {
    v.get(i).copied().unwrap_or(f64::NAN)
}

/// An error or a size as the report prints it: three significant digits.
fn sci2(x: f64) -> String {
    format::sci(x, 2)
}

/// The measured table, Markdown: one row per (h, method).
pub fn markdown_table(exp: &Experiment) -> String {
    let mut s = String::from(
        "| h | method | order | symplectic | max \\|Δq\\| | max \\|Δp\\| | max \\|ΔH\\|/H₀ | final \\|Δq\\| | final phase error (rad) |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for r in &exp.runs {
        let m = r.summary();
        let info = r.method.info();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {:+.2e} |",
            h_name(r.h),
            match &r.failure {
                Some(why) => format!("{} ({why})", r.method.label()),
                None => r.method.label().to_string(),
            },
            info.order,
            if info.symplectic { "yes" } else { "no" },
            sci2(m.max_err_q),
            sci2(m.max_err_p),
            sci2(m.max_rel_energy_error),
            sci2(m.final_err_q.abs()),
            m.final_phase_error,
        );
    }
    s
}

/// The same table as plain text for the terminal.
pub fn text_table(exp: &Experiment) -> String {
    let mut s = format!(
        "{:>6}  {:<18} {:>10} {:>10} {:>12} {:>10}\n",
        "h", "method", "max|Δq|", "max|Δp|", "max|ΔH|/H₀", "phase"
    );
    for r in &exp.runs {
        let m = r.summary();
        let _ = writeln!(
            s,
            "{:>6}  {:<18} {:>10} {:>10} {:>12} {:>+10.2e}{}",
            h_name(r.h),
            r.method.label(),
            sci2(m.max_err_q),
            sci2(m.max_err_p),
            sci2(m.max_rel_energy_error),
            m.final_phase_error,
            r.failure
                .as_ref()
                .map_or(String::new(), |why| format!("  stopped: {why}"))
        );
    }
    s
}

/// `format::times` of `f(h₂)/f(h₁)` for consecutive step sizes, as "×N from h = a to h = b".
fn growth_with_h(sorted: &[f64], f: impl Fn(f64) -> f64) -> String {
    let parts: Vec<String> = sorted
        .windows(2)
        .map(|p| {
            format!(
                "{} from h = {} to h = {}",
                format::times(f(p[1]), f(p[0])),
                p[0],
                p[1]
            )
        })
        .collect();
    if parts.is_empty() {
        MISSING.into()
    } else {
        parts.join(", ")
    }
}

/// The relative difference of a measurement from a prediction.
fn rel_diff(measured: f64, predicted: f64) -> f64 {
    ((measured - predicted) / predicted).abs()
}

/// `hk` at step size `h`.
fn hk_max(c: &Config, h: f64) -> f64 {
    h * c.k
}

fn max_rel_energy(exp: &Experiment, m: Method, h: f64) -> f64 {
    run(exp, m, h).summary().max_rel_energy_error
}

/// The whole report. `cloth` is the cloth section (figure 5, without its
/// heading); `files` the names of the files written alongside.
pub fn markdown(exp: &Experiment, cloth: &str, files: &[String]) -> String {
    let c: &Config = &exp.config;
    let f = Findings::of(exp);
    let (h_max, h_min, n) = (f.h_max, f.h_min, c.steps);
    let mut s = String::new();
    let w = &mut s;

    let _ = writeln!(w, "# Tan et al., section 5, reproduced\n");
    let _ = writeln!(
        w,
        "Written by `symlab paper` (symlab {}). Every number in this report was computed in this run; \
         nothing in it is copied from the paper or typed in by hand.\n",
        env!("CARGO_PKG_VERSION")
    );

    // ---------------------------------------------------------------- set-up
    let _ = writeln!(w, "## Set-up\n");
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
        let paper_name = match m {
            Method::ExplicitEuler => "(general) Euler scheme",
            Method::Heun => "Heun–Runge–Kutta (fig. 3)",
            Method::ImplicitMidpoint => {
                "Euler midpoint formula, \"1-order Gauss–Legendre\" (eq. 20)"
            }
            Method::PaperDirk2 => "2-order 2-step semi-implicit symplectic RK (fig. 2)",
            Method::GaussLegendre2 => {
                "\"2-order Gauss–Legendre\", 4-order 2-step implicit RK (eq. 21)"
            }
            Method::SymplecticEuler => "symplectic Euler (fig. 5, conclusions)",
        };
        let _ = writeln!(
            w,
            "| {} | `{}` | {} | {} | {} | {} | {} |",
            m.label(),
            m.id(),
            info.stages,
            info.class,
            info.order,
            if info.symplectic { "yes" } else { "no" },
            paper_name
        );
    }
    let _ = writeln!(
        w,
        "\nThe paper does not print the table of its 2-stage semi-implicit method; `paper-dirk2` is the \
         standard symplectic DIRK it describes, A = [[1/4, 0], [1/2, 1/4]], b = (1/2, 1/2) (two implicit \
         midpoint steps of size h/2). Symplectic Euler is the variant that updates p first (a kick, then a \
         drift), the usual \"semi-implicit Euler\" of cloth simulation.\n"
    );

    // ---------------------------------------------------------------- claims
    let _ = writeln!(w, "## What the paper claims\n");
    let _ = writeln!(
        w,
        "- Abstract: the symplectic algorithms \"can preserve the system energy constant and can give the exact \
         results even at large time-step, however the ordinary non-symplectic explicit method exhibit large error \
         with the increasing of time-step\"."
    );
    let _ = writeln!(
        w,
        "- Figure 2 (the 2-stage semi-implicit symplectic RK at h = 0.05): \"the amplitudes of the displacement \
         and velocity keep constant\"."
    );
    let _ = writeln!(
        w,
        "- At h = 0.01 \"the former three methods are able to get the right results in short term simulation, but \
         the fourth one still gives the results with large error\"."
    );
    let _ = writeln!(
        w,
        "- Figures 2 and 3: \"when the computation step 0.1s is adopted, after 200 steps, only the symplectic \
         algorithms can carry out the right simulation, but the results from the other nonsymplectic methods are \
         unable to be convergent to the analytical results\"."
    );
    let _ = writeln!(
        w,
        "- Figure 4: \"The errors from symplectic schemes are far smaller than that of Heun-Runge-Kutta scheme\"; \
         \"The higher the order is, the higher the precision is.\"\n"
    );

    // ---------------------------------------------------------------- measured
    let _ = writeln!(w, "## What this run measured\n");
    let _ = writeln!(
        w,
        "Maximum errors over the {n} steps (and the errors at the last step):\n"
    );
    let _ = writeln!(w, "{}", markdown_table(exp));
    let stopped: Vec<_> = exp.runs.iter().filter(|r| r.failure.is_some()).collect();
    if !stopped.is_empty() {
        let _ = writeln!(
            w,
            "Runs that stopped before step {n} (their rows are over the steps they took; \
             figures that need a later step read {MISSING}):\n"
        );
        for r in stopped {
            let _ = writeln!(
                w,
                "- {} at h = {}: {}",
                r.method.label(),
                h_name(r.h),
                r.failure.as_deref().unwrap_or_default()
            );
        }
        let _ = writeln!(w);
    }

    let _ = writeln!(w, "### Energy\n");
    let euler_by_h: Vec<String> = c
        .step_sizes
        .iter()
        .map(|&h| {
            format!(
                "{} at h = {h}",
                sci2(max_rel_energy(exp, Method::ExplicitEuler, h))
            )
        })
        .collect();
    let mut sorted = c.step_sizes.clone();
    sorted.sort_by(f64::total_cmp);
    let _ = writeln!(
        w,
        "- **Explicit Euler** gains energy at every step: max |ΔH|/H₀ = {}; the error grows {} \
         (the paper's \"large error with the increasing of time-step\"). Within the run at h = {h_max} \
         |ΔH| grows from {} after {} steps to {} after {n} ({}; linear growth would give {}): exponential \
         growth, within a relative {} of the prediction H₀((1 + h²k²)ⁿ − 1) = {} from its stability function \
         R(z) = 1 + z, |R(ih)|² = 1 + h²k².",
        euler_by_h.join(", "),
        growth_with_h(&sorted, |h| max_rel_energy(exp, Method::ExplicitEuler, h)),
        sci2(f.euler_early),
        n / 10,
        sci2(f.euler_final),
        format::times(f.euler_final, f.euler_early),
        format::times(n as f64, (n / 10) as f64),
        sci2(rel_diff(f.euler_final, f.euler_predicted)),
        sci2(f.euler_predicted),
    );
    let heun_by_h: Vec<String> = c
        .step_sizes
        .iter()
        .map(|&h| format!("{} at h = {h}", sci2(max_rel_energy(exp, Method::Heun, h))))
        .collect();
    let _ = writeln!(
        w,
        "- **Heun** drifts: max |ΔH|/H₀ = {}. At h = {h_max} |ΔH| grows at every step ({} steps where it did \
         not), from {} after {} steps to {} after {n} ({}: linear growth, a drift), within a relative {} of the \
         prediction H₀((1 + (hk)⁴/4)ⁿ − 1) = {} (|R(ih)|² = 1 + (hk)⁴/4 for R(z) = 1 + z + z²/2). With h it grows \
         {} (the h⁴ of the prediction).",
        heun_by_h.join(", "),
        f.heun_decreases,
        sci2(f.heun_early),
        n / 10,
        sci2(f.heun_final),
        format::times(f.heun_final, f.heun_early),
        sci2(rel_diff(f.heun_final, f.heun_predicted)),
        sci2(f.heun_predicted),
        growth_with_h(&sorted, |h| max_rel_energy(exp, Method::Heun, h)),
    );
    let round_off: Vec<String> = [
        Method::ImplicitMidpoint,
        Method::PaperDirk2,
        Method::GaussLegendre2,
    ]
    .iter()
    .map(|&m| {
        let worst = c
            .step_sizes
            .iter()
            .map(|&h| max_rel_energy(exp, m, h))
            .fold(0.0, f64::max);
        format!("{} {}", m.label(), sci2(worst))
    })
    .collect();
    let _ = writeln!(
        w,
        "- **Implicit midpoint, paper DIRK2, Gauss–Legendre 2** keep the energy to round-off at every step size: \
         largest max |ΔH|/H₀ over all h: {}. In the energy plots their |ΔH| is drawn as max(|ΔH|, {ENERGY_FLOOR:e}) \
         because it is exactly 0 at some steps and a log axis cannot show 0.",
        round_off.join(", ")
    );
    let se = run(exp, Method::SymplecticEuler, h_max).summary();
    let se_by_h: Vec<String> = c
        .step_sizes
        .iter()
        .map(|&h| {
            format!(
                "{} at h = {h}",
                sci2(max_rel_energy(exp, Method::SymplecticEuler, h))
            )
        })
        .collect();
    let _ = writeln!(
        w,
        "- **Symplectic Euler**'s energy error is neither round-off nor growing: it oscillates with an amplitude \
         proportional to h (max |ΔH|/H₀ = {}; {}). At h = {h_max} its largest |ΔH| is {} over the first half of the \
         run and {} over the second ({}), and ΔH changes sign {} times. It conserves the modified energy \
         H̃ = H − (hk²/2)·qp exactly (largest drift of H̃ over all runs: {} of H₀), so ΔH = (hk²/2)(qp − q₀p₀) \
         is bounded by the orbit.\n",
        se_by_h.join(", "),
        growth_with_h(&sorted, |h| max_rel_energy(exp, Method::SymplecticEuler, h)),
        sci2(se.energy_error_first_half),
        sci2(se.energy_error_second_half),
        format::times(se.energy_error_second_half, se.energy_error_first_half),
        se.energy_sign_changes,
        sci2(f.symplectic_euler_modified_drift),
    );

    let _ = writeln!(
        w,
        "### Position and phase at h = {h_max} after {n} steps (t = {})\n",
        h_max * n as f64
    );
    let _ = writeln!(
        w,
        "| method | final \\|Δq\\| | max \\|Δq\\| | phase error after {} steps | after {n} steps | amplitude error r/r₀ − 1 |",
        n / 2
    );
    let _ = writeln!(w, "|---|---|---|---|---|---|");
    for r in exp.at(h_max) {
        let m = r.summary();
        let phase = r.phase_error();
        let _ = writeln!(
            w,
            "| {} | {} | {} | {} | {} | {} |",
            r.method.label(),
            sci2(m.final_err_q.abs()),
            sci2(m.max_err_q),
            format::signed_sci(at(&phase, n / 2), 3),
            format::signed_sci(at(&phase, n), 3),
            if r.failure.is_some() {
                MISSING.to_string()
            } else {
                format::signed_sci(m.final_amplitude_error, 2)
            }
        );
    }
    let linear_expected = n as f64 / (n / 2) as f64;
    let mid_ratio = f.midpoint_phase_final / f.midpoint_phase_half;
    let linear = if (mid_ratio / linear_expected - 1.0).abs() < 0.05 {
        "i.e. it grows linearly in time"
    } else {
        "not the linear growth expected"
    };
    let _ = writeln!(
        w,
        "\nThe implicit midpoint rule rotates by 2·atan(hk/2) per step instead of hk: predicted phase error \
         −n·(hk − 2·atan(hk/2)) = {:+.6e}, measured {:+.6e}; the phase error after {n} steps is {} that \
         after {} steps, {linear}.",
        f.midpoint_phase_predicted,
        f.midpoint_phase_final,
        format::times(f.midpoint_phase_final, f.midpoint_phase_half),
        n / 2,
    );
    if f.symplectic_euler_phase_predicted.is_finite() {
        let _ = writeln!(
            w,
            "Symplectic Euler's step matrix has trace 2 − (hk)², so it rotates by acos(1 − (hk)²/2) per step, \
             faster than hk: a secular phase drift of {:+.3e} after {n} steps. Its measured angle error ({:+.3e} \
             after {} steps, {:+.3e} after {n}) also contains an O(h) oscillation, because its orbit is the \
             ellipse H̃ = const, not the circle H = H₀.\n",
            f.symplectic_euler_phase_predicted,
            f.symplectic_euler_phase_half,
            n / 2,
            f.symplectic_euler_phase_final,
        );
    } else {
        let _ = writeln!(
            w,
            "At h = {h_max}, hk > 2 lies outside symplectic Euler's stability interval: its step matrix has real \
             eigenvalues and the solution does not rotate.\n"
        );
    }

    // ---------------------------------------------------------------- comparison
    let _ = writeln!(
        w,
        "## Where the paper and this run agree, and where they differ\n"
    );
    let mid = run(exp, Method::ImplicitMidpoint, h_max).summary();
    let heun = run(exp, Method::Heun, h_max).summary();
    let euler = run(exp, Method::ExplicitEuler, h_max).summary();
    let gl2 = run(exp, Method::GaussLegendre2, h_max).summary();
    let dirk = run(exp, Method::PaperDirk2, h_max).summary();
    let amplitude = c.q0.hypot(c.p0 / c.k);
    // The energy claim, checked rather than asserted: every symplectic run's
    // energy error is no larger over the second half than 1.5× the first
    // half; every explicit non-symplectic run's grows, and Euler's grows with h.
    let bounded = exp
        .runs
        .iter()
        .filter(|r| r.method.info().symplectic)
        .all(|r| {
            let (a, b) = r.energy_error_halves();
            b <= 1.5 * a || r.max_energy_error() <= 1e-13 * r.energy0
        });
    let growing = exp
        .runs
        .iter()
        .filter(|r| !r.method.info().symplectic)
        .all(|r| r.energy_error_decreases() == 0);
    let euler_grows_with_h = sorted.windows(2).all(|p| {
        max_rel_energy(exp, Method::ExplicitEuler, p[1])
            > max_rel_energy(exp, Method::ExplicitEuler, p[0])
    });
    let verdict = if bounded && growing && euler_grows_with_h {
        "agreed"
    } else {
        "only in part"
    };
    let _ = writeln!(
        w,
        "- **Energy: {verdict}.** Symplectic methods' energy error bounded (second half of every run at most 1.5× \
         the first, or round-off): {}; every explicit non-symplectic run's |ΔH| grows at every step: {}; \
         explicit Euler's max |ΔH| grows with h: {}.",
        if bounded { "yes" } else { "no" },
        if growing { "yes" } else { "no" },
        if euler_grows_with_h { "yes" } else { "no" },
    );
    if let Some(r) = exp.get(Method::PaperDirk2, 0.05) {
        let amp = r
            .amplitude_error()
            .iter()
            .fold(0.0f64, |m, x| m.max(x.abs()));
        let _ = writeln!(
            w,
            "- **Figure 2, \"the amplitudes keep constant\"** (the DIRK2 at h = 0.05): its largest amplitude error \
             |r/r₀ − 1| over the run is {}{}.",
            sci2(amp),
            if amp <= 1e-13 {
                ", constant to round-off: agreed"
            } else {
                ""
            }
        );
    }
    let _ = writeln!(
        w,
        "- **\"Exact results even at large time-step\": not literally.** A symplectic method has a bounded \
         energy error but a phase error that grows linearly in time. At h = {h_max} after {n} steps the implicit \
         midpoint rule is {:+.3e} rad out of phase, a position error of {} ({:.2}% of the amplitude {}); \
         symplectic Euler's final position error is {} and its largest {} ({:.2}%), of which the O(h) \
         distortion of its orbit (an ellipse, not the circle) is a part. The DIRK2 (final {}) and Gauss–Legendre 2 \
         (final {}) are closer, but not exact either.",
        mid.final_phase_error,
        sci2(mid.final_err_q.abs()),
        100.0 * mid.final_err_q.abs() / amplitude,
        amplitude,
        sci2(se.final_err_q.abs()),
        sci2(se.max_err_q),
        100.0 * se.max_err_q / amplitude,
        sci2(dirk.final_err_q.abs()),
        sci2(gl2.final_err_q.abs()),
    );
    // Which symplectic methods end further from the analytic position than Heun?
    let worse_than_heun: Vec<String> = exp
        .at(h_max)
        .filter(|r| r.method.info().symplectic && r.max_err_q() > heun.max_err_q)
        .map(|r| format!("{} ({})", r.method.label(), sci2(r.max_err_q())))
        .collect();
    let better_than_heun: Vec<String> = exp
        .at(h_max)
        .filter(|r| r.method.info().symplectic && r.max_err_q() <= heun.max_err_q)
        .map(|r| format!("{} ({})", r.method.label(), sci2(r.max_err_q())))
        .collect();
    let heun_energy_drift = heun.final_energy_error.abs() / c.energy0();
    let bounded_at_h_max = exp
        .at(h_max)
        .filter(|r| r.method.info().symplectic)
        .all(|r| {
            let (a, b) = r.energy_error_halves();
            b <= 1.5 * a || r.max_energy_error() <= 1e-13 * r.energy0
        });
    let euler_worst = exp
        .at(h_max)
        .filter(|r| r.method.info().symplectic)
        .all(|r| r.max_err_q() < euler.max_err_q);
    let energy_part = if bounded_at_h_max && euler_worst {
        "right for the energy and for explicit Euler"
    } else {
        "only in part"
    };
    if worse_than_heun.is_empty() {
        let _ = writeln!(
            w,
            "- **\"Only the symplectic algorithms are right at h = 0.1 after 200 steps\": {}.** \
             Explicit Euler's final position error is {} (its amplitude has grown {}); Heun's largest position \
             error, {}, is larger than every symplectic method's ({}), and its energy drifts ({} of H₀ at the end).",
            if bounded_at_h_max && euler_worst {
                format!("agreed at h = {h_max}")
            } else {
                "only in part".to_string()
            },
            sci2(euler.final_err_q.abs()),
            format::times(1.0 + euler.final_amplitude_error, 1.0),
            sci2(heun.max_err_q),
            better_than_heun.join(", "),
            sci2(heun_energy_drift),
        );
    } else {
        let _ = writeln!(
            w,
            "- **\"Only the symplectic algorithms are right at h = 0.1 after 200 steps\": {energy_part}; not for \
             Heun's position.** Explicit Euler's final position error is {} (its \
             amplitude has grown {}). Heun's largest position error over the run at h = {h_max}, {}, is smaller \
             than that of {} and larger than that of {}; what sets Heun apart is its energy drift ({} of H₀ at the \
             end, growing at every step), not its position after {n} steps.",
            sci2(euler.final_err_q.abs()),
            format::times(1.0 + euler.final_amplitude_error, 1.0),
            sci2(heun.max_err_q),
            worse_than_heun.join(", "),
            if better_than_heun.is_empty() {
                "none".to_string()
            } else {
                better_than_heun.join(", ")
            },
            sci2(heun_energy_drift),
        );
    }
    let vs_heun = |x: f64, heun: f64| {
        let verdict = if x < 0.1 * heun {
            "far smaller"
        } else if x < heun {
            "smaller"
        } else {
            "larger"
        };
        format!("{} of Heun's, {verdict}", format::times(x, heun))
    };
    let energy_vs_heun: Vec<String> = exp
        .at(h_max)
        .filter(|r| r.method.info().symplectic)
        .map(|r| {
            format!(
                "{} {} ({})",
                r.method.label(),
                sci2(r.max_energy_error() / r.energy0),
                vs_heun(r.max_energy_error(), heun.max_energy_error)
            )
        })
        .collect();
    let q_vs_heun: Vec<String> = exp
        .at(h_max)
        .filter(|r| r.method.info().symplectic)
        .map(|r| {
            format!(
                "{} {} ({})",
                r.method.label(),
                sci2(r.max_err_q()),
                vs_heun(r.max_err_q(), heun.max_err_q)
            )
        })
        .collect();
    let _ = writeln!(
        w,
        "- **\"Errors from symplectic schemes are far smaller than Heun's\"** (the paper's figure 4 compares only \
         its DIRK2, the midpoint rule and Heun). At h = {h_max}, largest |ΔH|/H₀: Heun {}; {}. Largest |Δq|: \
         Heun {}; {}.",
        sci2(heun.max_rel_energy_error),
        energy_vs_heun.join("; "),
        sci2(heun.max_err_q),
        q_vs_heun.join("; "),
    );
    if se.max_energy_error > heun.max_energy_error {
        // Heun's |ΔH| = H₀((1 + (hk)⁴/4)ⁿ − 1) passes symplectic Euler's bounded level at this n.
        let growth = (hk_max(c, h_max).powi(4) / 4.0).ln_1p();
        let crossing = (se.max_rel_energy_error).ln_1p() / growth;
        let _ = writeln!(
            w,
            "  Symplectic Euler, of order 1, has the larger energy error over these {n} steps: its error is \
             bounded but O(h), Heun's grows by a factor 1 + (hk)⁴/4 per step, and would pass symplectic Euler's \
             level after about {:.0} steps (t ≈ {:.0}). \"Long-time\" is the operative word.",
            crossing,
            crossing * h_max
        );
    }
    let higher_order_better = c.step_sizes.iter().all(|&h| {
        let gl = run(exp, Method::GaussLegendre2, h).max_err_q();
        gl < run(exp, Method::ImplicitMidpoint, h).max_err_q()
            && gl < run(exp, Method::PaperDirk2, h).max_err_q()
    });
    let order_ratios: Vec<String> = c
        .step_sizes
        .iter()
        .map(|&h| {
            let mid = run(exp, Method::ImplicitMidpoint, h).max_err_q();
            let gl = run(exp, Method::GaussLegendre2, h).max_err_q();
            let dirk = run(exp, Method::PaperDirk2, h).max_err_q();
            format!(
                "h = {h}: midpoint {}, DIRK2 {}, Gauss–Legendre 2 {}",
                sci2(mid),
                sci2(dirk),
                sci2(gl)
            )
        })
        .collect();
    let _ = writeln!(
        w,
        "- **\"The higher the order, the higher the precision\": {}.** Max |Δq| of the symplectic RK methods \
         (orders {}, {}, {}): {}. Order is not the whole story: the DIRK2 has the midpoint rule's order and its \
         error is {} of the midpoint rule's at h = {h_max}.",
        if higher_order_better {
            "agreed (Gauss–Legendre 2 is the most accurate at every h)"
        } else {
            "not at every h"
        },
        ImplicitMidpoint::ORDER,
        PaperDirk2::ORDER,
        GaussLegendre2::ORDER,
        order_ratios.join("; "),
        format::times(dirk.max_err_q, mid.max_err_q),
    );
    let ranked = |key: &dyn Fn(&Trajectory) -> f64| {
        let mut v: Vec<(f64, Method)> = exp.at(h_min).map(|r| (key(r), r.method)).collect();
        v.sort_by(|a, b| b.0.total_cmp(&a.0));
        v.truncate(2);
        v
    };
    let show = |v: &[(f64, Method)]| {
        v.iter()
            .map(|(x, m)| format!("{} ({})", m.label(), sci2(*x)))
            .collect::<Vec<_>>()
            .join(", then ")
    };
    let by_energy = ranked(&|r: &Trajectory| r.max_energy_error() / r.energy0);
    let by_q = ranked(&|r: &Trajectory| r.max_err_q());
    let first_order_lead = by_energy
        .iter()
        .chain(&by_q)
        .all(|(_, m)| m.info().order == 1);
    let _ = writeln!(
        w,
        "- **At h = 0.01 \"the fourth one still gives the results with large error\"**: the paper does not say \
         which method is the fourth. Here, at h = {h_min}, the largest energy errors (|ΔH|/H₀) are {}; the largest \
         position errors {}.{}",
        show(&by_energy),
        show(&by_q),
        if first_order_lead {
            format!(
                " Both are the first-order methods: over a run this short (t = {}) their O(h) error dominates.",
                h_min * n as f64
            )
        } else {
            String::new()
        }
    );
    let rk_round_off = exp
        .runs
        .iter()
        .filter(|r| {
            matches!(
                r.method,
                Method::ImplicitMidpoint | Method::PaperDirk2 | Method::GaussLegendre2
            )
        })
        .all(|r| r.max_energy_error() <= 1e-13 * r.energy0);
    let _ = writeln!(
        w,
        "- **Why three of the symplectic methods {} at round-off.** H is quadratic, and every symplectic \
         Runge–Kutta method (midpoint, DIRK2, Gauss–Legendre 2) conserves quadratic invariants exactly; their \
         round-off-level energy error here is a property of the linear oscillator, not of symplectic methods in \
         general. On a nonlinear Hamiltonian such as the cloth, a symplectic method's energy error is bounded \
         and oscillating, like symplectic Euler's here, not round-off. Symplectic Euler is a partitioned method, \
         not a symplectic RK, and conserves only the modified energy H̃.\n",
        if rk_round_off {
            "are"
        } else {
            "should be (but here are not all)"
        }
    );

    // ---------------------------------------------------------------- typos
    let _ = writeln!(w, "## Typos in the paper (corrected here)\n");
    let _ = writeln!(
        w,
        "- Eq. (6) swaps H_p and H_q: it defines H_p as the vector of ∂H/∂qᵢ and H_q as that of ∂H/∂pᵢ, \
         contradicting eq. (3) q̇ = ∂H/∂p = H_p; eq. (4) then reads ṗ = −∂H/∂q = H_q. Hamilton's equations \
         are q̇ = ∂H/∂p, ṗ = −∂H/∂q."
    );
    let _ = writeln!(
        w,
        "- Eq. (20) calls the implicit midpoint rule the \"1-order Gauss–Legendre method\": it is the 1-stage \
         Gauss method, of order {} (proved by `butcher!` for `midpoint`).",
        ImplicitMidpoint::ORDER
    );
    let printed_c1 = 0.25 - 3f64.sqrt() / 6.0;
    let _ = writeln!(
        w,
        "- Eq. (21), \"4-order 2-step implicit Runge–Kutta method (2-order Gauss–Legendre method)\", is the \
         2-stage Gauss method of order {}; its first abscissa is printed as 1/4 − √3/6 = {printed_c1:.6}, \
         but c₁ is the row sum 1/2 − √3/6 = {:.6} (the library's `gauss2`, whose c equals its row sums).",
        GaussLegendre2::ORDER,
        GaussLegendre2::C[0]
    );
    let _ = writeln!(
        w,
        "- Figure 2's \"2-order 2-step semi-implicit symplectic Runge–Kutta scheme\" has 2 stages (it is a \
         one-step method) and order {} (proved for `paper-dirk2`).",
        PaperDirk2::ORDER
    );
    let _ = writeln!(
        w,
        "- The closed form's arctg(p₀/(kq₀)) is the phase only for q₀ > 0 (for q₀ < 0 it is off by π); this \
         run's q₀ = {} gives a largest difference of {} from the exact flow.\n",
        c.q0,
        sci2(f.closed_form_deviation)
    );

    // ---------------------------------------------------------------- cloth
    let _ = writeln!(w, "## The cloth comparison (figure 5)\n");
    let _ = writeln!(w, "{}\n", cloth.trim_end());

    // ---------------------------------------------------------------- files
    let _ = writeln!(w, "## Files\n");
    for name in files {
        let _ = writeln!(w, "- `{name}`");
    }
    s
}
