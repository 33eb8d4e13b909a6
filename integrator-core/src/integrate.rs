//! Integrating many steps with an observer, with the checks a caller should
//! not have to write: dimensions, step size, finite values at every step.

use crate::error::StepError;
use crate::scheme::Step;
use crate::split::StateSpace;

/// First index and value of a non-finite entry.
fn first_non_finite(z: &[f64]) -> Option<(usize, f64)> {
    z.iter().position(|x| !x.is_finite()).map(|i| (i, z[i]))
}

/// Integrate `n` steps of size `h` from `(t0, z)`, calling
/// `observe(step, t, z)` before the first step and after every step.
/// Stops with [`StepError::Diverged`] at the first step that leaves a
/// non-finite value, and with [`StepError::Solve`] at a step that fails
/// (an implicit stage solve, or the flow of a part of a
/// [`Split`](crate::Split) system, named in the error). Consecutive steps reuse the last evaluation of the
/// previous step where the scheme allows (first same as last).
///
/// ```
/// use integrator_core::{butcher, integrate, Separable};
///
/// butcher! {
///     /// Leapfrog (drift–kick–drift).
///     Leapfrog {
///         claims: [symplectic, symmetric, order = 2],
///         drift: [1/2, 1/2],
///         kick: [1],
///     }
/// }
///
/// /// H = p²/2 + q²/2.
/// struct Oscillator;
/// impl Separable for Oscillator {
///     fn dof(&self) -> usize { 1 }
///     fn kinetic(&self, p: &[f64]) -> f64 { 0.5 * p[0] * p[0] }
///     fn potential(&self, q: &[f64]) -> f64 { 0.5 * q[0] * q[0] }
///     fn velocity(&self, p: &[f64], v: &mut [f64]) { v[0] = p[0] }
///     fn force(&self, q: &[f64], f: &mut [f64]) { f[0] = -q[0] }
/// }
///
/// let mut z = [1.0, 0.0];
/// let mut max_err: f64 = 0.0;
/// integrate(&Leapfrog, &Oscillator, &mut z, 0.0, 0.1, 1000, |_, _, z| {
///     max_err = max_err.max((0.5 * (z[0] * z[0] + z[1] * z[1]) - 0.5).abs());
/// })
/// .unwrap();
/// assert!(max_err < 2e-3); // bounded energy error over 1000 steps
/// ```
pub fn integrate<S, M>(
    method: &M,
    sys: &S,
    z: &mut [f64],
    t0: f64,
    h: f64,
    n: usize,
    mut observe: impl FnMut(usize, f64, &[f64]),
) -> Result<(), StepError>
where
    S: StateSpace + ?Sized,
    M: Step<S>,
{
    check_start(sys, z, h)?;
    let mut ws = method.workspace(sys);
    observe(0, t0, z);
    for k in 0..n {
        let t = t0 + k as f64 * h;
        method
            .step_reusing(sys, t, h, z, &mut ws, k > 0)
            .map_err(|source| StepError::Solve {
                step: k + 1,
                t,
                source,
            })?;
        let t_next = t0 + (k + 1) as f64 * h;
        if let Some((index, value)) = first_non_finite(z) {
            return Err(StepError::Diverged {
                step: k + 1,
                t: t_next,
                index,
                value,
            });
        }
        observe(k + 1, t_next, z);
    }
    Ok(())
}

/// The checks before the first step.
pub fn check_start<S: StateSpace + ?Sized>(sys: &S, z: &[f64], h: f64) -> Result<(), StepError> {
    if z.len() != sys.state_len() {
        return Err(StepError::Dimension {
            expected: sys.state_len(),
            got: z.len(),
        });
    }
    if h == 0.0 || !h.is_finite() {
        return Err(StepError::StepSize(h));
    }
    if let Some((index, value)) = first_non_finite(z) {
        return Err(StepError::NonFiniteInitial { index, value });
    }
    Ok(())
}
