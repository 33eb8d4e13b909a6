//! "Typos in the paper (corrected here)", with the orders `butcher!`
//! proved and the abscissa the paper misprints.

use std::fmt::Write as _;

use compare::paper_oscillator::{Experiment, Findings};
use integrator_core::library::{GaussLegendre2, ImplicitMidpoint, PaperDirk2};

use super::sci2;

pub(super) fn write(w: &mut String, exp: &Experiment, f: &Findings) {
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
        exp.config.q0,
        sci2(f.closed_form_deviation)
    );
}
