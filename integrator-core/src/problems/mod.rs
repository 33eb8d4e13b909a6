//! Smooth test problems with exact solutions and invariants, and seeded
//! random problems for property tests.
//!
//! | problem | trait | exact flow | invariants |
//! |---|---|---|---|
//! | [`Oscillator`] `H = ½(p² + k²q²)` | [`Separable`](crate::Separable) | closed form | `H` |
//! | [`Pendulum`] `H = p²/2 − cos q` | `Separable` | Jacobi elliptic functions (libration) | `H` |
//! | [`QuarticPendulum`] `H = p²/2 + αp⁴/4 − cos q` | `Separable` (`T` not quadratic) | — | `H` |
//! | [`Kepler`] `H = ½|p|² − 1/|q|` (2D) | `Separable` | Kepler's equation (bound orbits) | `H`, `L` |
//! | [`NonSeparable`] `H = ½|p|²(1 + εq₁²) + ½|q|²` | [`Hamiltonian`](crate::Hamiltonian) only | — | `H` |
//! | [`RandomSeparable`] quadratic + cubic + quartic `V`, optional quartic `T` | `Separable` | — | `H` |
//! | [`HenonHeiles`] chaotic at `H = 1/8` | `Separable` | numerical reference | `H` |
//! | [`Fpu`] stiff FPU chain, `ω = 50` | `Separable` | numerical reference | `H`, `Σ Iⱼ` (adiabatic) |
//! | [`OuterSolarSystem`] Sun and five outer planets (HLW I.2.3) | `Separable` | numerical reference | `H`, angular momentum |
//! | [`wisdom_holman`]: any N-body problem split for Wisdom–Holman (Jacobi, democratic heliocentric) | inherent flows of the parts | Kepler part exact ([`kepler`](crate::kepler)) | `H` |
//! | [`SphericalPendulum`] on `|q|² = L²` in ℝ³ | [`Constrained`](crate::constrained::Constrained) | local-coordinate ODE ([`local_rhs`](SphericalPendulum::local_rhs)) | `H`, `L₃` |
//! | [`PendulumChain`] `n` rods, plane or space | `Constrained` | — | `H` |
//! | [`gyroscopic`](crate::linear::gyroscopic) `Mq̈ + Gq̇ + Kq = f` | `OdeSystem` | matrix exponential | quadratic energy |
//!
//! The exact flows implement [`ExactFlow`]; they are exact up to a few
//! rounding errors, so that integration errors down to ~1e-14 can be
//! measured against them.

mod elliptic;
mod fpu;
mod henon_heiles;
mod kepler;
mod nonseparable;
mod oscillator;
pub mod outer_solar;
mod pendulum;
mod pendulum_chain;
mod random;
mod spherical_pendulum;
pub mod wisdom_holman;

pub use elliptic::{carlson_rf, complete_k, incomplete_f, jacobi};
pub use fpu::Fpu;
pub use henon_heiles::HenonHeiles;
pub use kepler::Kepler;
pub use nonseparable::NonSeparable;
pub use oscillator::Oscillator;
pub use outer_solar::OuterSolarSystem;
pub use pendulum::{Pendulum, QuarticPendulum};
pub use pendulum_chain::{ChainError, PendulumChain};
pub use random::{RandomSeparable, SplitMix64};
pub use spherical_pendulum::SphericalPendulum;

/// A problem whose flow is known in closed form.
pub trait ExactFlow {
    /// The exact state at time `t` of the solution with `z(0) = z0`, or
    /// `None` where `z0` lies outside the case the formula covers (a
    /// rotating pendulum, an unbound Kepler orbit) or has the wrong length.
    fn flow(&self, z0: &[f64], t: f64) -> Option<Vec<f64>>;
}

/// The most steps [`try_reference_solution`] takes: about 30 s of the
/// order-10 composition on the outer solar system (10⁸ days at its
/// reference step), far beyond every built-in experiment (10⁵ days: 2·10⁴
/// steps).
pub const MAX_REFERENCE_STEPS: u64 = 10_000_000;

/// A high-accuracy numerical solution for problems without a closed-form
/// flow: Sofroniou–Spaletta's order-10 composition with about
/// `steps_per_unit` steps per unit time (rounded up to a whole number over
/// `[0, t]`).
///
/// # Panics
/// Where [`try_reference_solution`] returns an error (a time span beyond
/// [`MAX_REFERENCE_STEPS`], or a solution that leaves the finite numbers):
/// for tests and examples whose spans are fixed; code that takes `t` from
/// a user calls [`try_reference_solution`].
pub fn reference_solution<S: crate::Separable>(
    sys: &S,
    z0: &[f64],
    t: f64,
    steps_per_unit: f64,
) -> Vec<f64> {
    try_reference_solution(sys, z0, t, steps_per_unit).unwrap_or_else(|e| panic!("{e}"))
}

/// [`reference_solution`], or why there is none: the span needs more than
/// [`MAX_REFERENCE_STEPS`] steps (checked before any step is taken, so a
/// `t = 1e15` is refused at once rather than run for years), `t` is not
/// finite, or the integration failed or left the finite numbers.
pub fn try_reference_solution<S: crate::Separable>(
    sys: &S,
    z0: &[f64],
    t: f64,
    steps_per_unit: f64,
) -> Result<Vec<f64>, String> {
    let steps = (t.abs() * steps_per_unit).ceil();
    if !steps.is_finite() {
        return Err(format!(
            "the reference solution to t = {t} cannot be computed: the time is not finite"
        ));
    }
    if steps > MAX_REFERENCE_STEPS as f64 {
        return Err(format!(
            "the reference solution to t = {t} needs {steps:.3e} steps of the order-10 composition ({steps_per_unit} per unit time), more than its budget of {MAX_REFERENCE_STEPS} (integrator_core::problems::MAX_REFERENCE_STEPS); a shorter span is at most t = {:.4e}",
            MAX_REFERENCE_STEPS as f64 / steps_per_unit
        ));
    }
    let n = (steps as usize).max(1);
    let h = t / n as f64;
    let mut z = z0.to_vec();
    if t != 0.0 {
        crate::integrate(
            &crate::library::SofroniouSpaletta10,
            sys,
            &mut z,
            0.0,
            h,
            n,
            |_, _, _| {},
        )
        .map_err(|e| format!("the reference solution to t = {t} failed: {e}"))?;
    }
    if z.iter().any(|x| !x.is_finite()) {
        return Err(format!(
            "the reference solution to t = {t} left the finite numbers"
        ));
    }
    Ok(z)
}
