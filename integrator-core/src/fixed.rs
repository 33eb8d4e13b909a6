//! Small systems on fixed-size state: the step code of [`Step`](crate::Step)
//! over `[f64; N]`, with every buffer on the stack.
//!
//! Why a second path: [`Step::step`](crate::Step::step) works on run-time
//! sized slices and heap workspaces, which is right for a cloth of 10⁵
//! unknowns and wrong for Kepler's four. There, the state and the stage
//! vectors of a hand-written loop live in registers for the whole run,
//! while the slice path stores and reloads them through the heap at every
//! stage: 1.2–1.4× the hand loop's time. With the length a constant of the
//! type, every loop of the generated code has a constant trip count
//! (unrolled), the stage vectors are stack arrays, and the carried state
//! (compensated-summation errors, first-same-as-last evaluations) is a
//! small struct the caller's loop keeps in registers.
//!
//! The size is declared by the state's type, `[f64; N]`, not by the system:
//! the same system (any [`OdeSystem`](crate::OdeSystem),
//! [`Separable`](crate::Separable) or [`Split`](crate::Split) one) runs on
//! either path, and [`integrate_fixed`] checks once, before the
//! first step, that `N` is its dimension. `butcher!` emits [`StepFixed`] for
//! every explicit table (Runge–Kutta, drift–kick, composition, explicit
//! partitioned pair); implicit tables keep the slice path, whose cost is the
//! stage solve, not the buffers.
//!
//! ```
//! use integrator_core::fixed::{integrate_fixed, StepFixed};
//! use integrator_core::library::Leapfrog;
//! use integrator_core::Separable;
//!
//! /// Kepler: H = |p|²/2 − 1/|q|.
//! struct Kepler;
//! impl Separable for Kepler {
//!     fn dof(&self) -> usize { 2 }
//!     fn kinetic(&self, p: &[f64]) -> f64 { 0.5 * (p[0] * p[0] + p[1] * p[1]) }
//!     fn potential(&self, q: &[f64]) -> f64 { -1.0 / q[0].hypot(q[1]) }
//!     fn velocity(&self, p: &[f64], v: &mut [f64]) { v[..2].copy_from_slice(&p[..2]) }
//!     fn force(&self, q: &[f64], f: &mut [f64]) {
//!         let r2 = q[0] * q[0] + q[1] * q[1];
//!         let c = -1.0 / (r2 * r2.sqrt());
//!         f[0] = c * q[0];
//!         f[1] = c * q[1];
//!     }
//! }
//!
//! let mut z = [1.0, 0.0, 0.0, 1.0]; // a circular orbit
//! let h = 2.0 * std::f64::consts::PI / 1000.0;
//! integrate_fixed(&Leapfrog, &Kepler, &mut z, 0.0, h, 1000, |_, _, _| {}).unwrap();
//! assert!((z[0] - 1.0).abs() < 1e-4 && z[1].abs() < 1e-2); // one period later
//!
//! // A state whose length is not the system's dimension is refused.
//! let mut short = [1.0, 0.0];
//! assert!(integrate_fixed(&Leapfrog, &Kepler, &mut short, 0.0, h, 1, |_, _, _| {}).is_err());
//! ```

use crate::error::{SolveError, StepError};
use crate::split::StateSpace;

/// One step of an explicit scheme on a state of compile-time length `N`
/// (the whole state: `N = 2·dof` for a Hamiltonian system), with the same
/// arithmetic as [`Step::step`](crate::Step::step): a step of either path
/// gives bit-identical results.
pub trait StepFixed<S: ?Sized, const N: usize> {
    /// What one step leaves for the next: carried rounding errors and, where
    /// the scheme has first same as last, the last evaluation. Stage
    /// vectors are locals of the step, not part of it.
    type Carry: Clone;
    /// A fresh carry; `compensated` selects compensated (Kahan) summation of
    /// the state updates, as the slice path's workspaces do (default on).
    fn carry(&self, compensated: bool) -> Self::Carry;
    /// `z ← Ψ_h(z)` for the step from `t` to `t + h`. With `reuse` the first
    /// evaluation is taken from `carry` (first same as last): valid only
    /// when `z` is what the previous call left.
    ///
    /// The caller guarantees that `N` is the system's dimension
    /// ([`integrate_fixed`] checks it); the step checks it in debug builds.
    ///
    /// Fails only where the slice path's step does: when a flow of a
    /// [`Split`](crate::Split) system fails (Runge–Kutta tables, pairs and
    /// drift–kick steps of separable systems always succeed, and the
    /// compiler removes the check after inlining).
    fn step_fixed(
        &self,
        sys: &S,
        t: f64,
        h: f64,
        z: &mut [f64; N],
        carry: &mut Self::Carry,
        reuse: bool,
    ) -> Result<(), SolveError>;
}

/// Carried state of an explicit Runge–Kutta step: the rounding error of
/// the last update.
#[derive(Clone, Debug)]
pub struct RkCarry<const N: usize> {
    pub e: [f64; N],
    pub compensated: bool,
}

impl<const N: usize> RkCarry<N> {
    pub fn new(compensated: bool) -> Self {
        RkCarry {
            e: [0.0; N],
            compensated,
        }
    }
}

/// Carried state of a drift–kick step: the last velocity and force (first
/// same as last) and the rounding errors of `q` and `p` (for a
/// [`Split`](crate::Split) system: the [`PartBuffers`](crate::PartBuffers)
/// of its parts `A`, `B`). Each array is the state's length `N`; a separable
/// step uses its first `N/2` entries (the length of `q` cannot be a
/// type-level `N/2` in stable Rust, and for the systems this path is for,
/// the unused half costs nothing).
#[derive(Clone, Debug)]
pub struct SplitCarry<const N: usize> {
    pub v: [f64; N],
    pub f: [f64; N],
    pub eq: [f64; N],
    pub ep: [f64; N],
    pub compensated: bool,
}

impl<const N: usize> SplitCarry<N> {
    pub fn new(compensated: bool) -> Self {
        SplitCarry {
            v: [0.0; N],
            f: [0.0; N],
            eq: [0.0; N],
            ep: [0.0; N],
            compensated,
        }
    }
}

/// Carried state of an explicit partitioned step: the stage evaluations
/// (the first force slot holds the first-same-as-last evaluation between
/// steps), the stage values and the rounding errors of `q` and `p`; arrays
/// of length `N`, of which `N/2` are used, as in [`SplitCarry`].
#[derive(Clone, Debug)]
pub struct PrkCarry<const N: usize, const S: usize> {
    pub fv: [[f64; N]; S],
    pub gf: [[f64; N]; S],
    pub q: [f64; N],
    pub p: [f64; N],
    pub eq: [f64; N],
    pub ep: [f64; N],
    pub compensated: bool,
}

impl<const N: usize, const S: usize> PrkCarry<N, S> {
    pub fn new(compensated: bool) -> Self {
        PrkCarry {
            fv: [[0.0; N]; S],
            gf: [[0.0; N]; S],
            q: [0.0; N],
            p: [0.0; N],
            eq: [0.0; N],
            ep: [0.0; N],
            compensated,
        }
    }
}

/// [`integrate`](crate::integrate) on a fixed-size state: `n` steps of size
/// `h` from `(t0, z)`, `observe(step, t, z)` before the first step and after
/// every step, compensated summation, first same as last where the scheme
/// has it, and the same checks: the state's length against the system's
/// dimension, the step size, finite values at the start and after every
/// step ([`StepError::Diverged`] names the first step that leaves one), and
/// a step that fails (a flow of a [`Split`](crate::Split) system) stops the
/// run with [`StepError::Solve`] naming the step and the part.
///
/// The state is copied into a local for the run and back at its end (also
/// when it stops early), so that it stays in registers between steps.
pub fn integrate_fixed<S, M, const N: usize>(
    method: &M,
    sys: &S,
    z: &mut [f64; N],
    t0: f64,
    h: f64,
    n: usize,
    observe: impl FnMut(usize, f64, &[f64]),
) -> Result<(), StepError>
where
    S: StateSpace + ?Sized,
    M: StepFixed<S, N>,
{
    integrate_fixed_with(method, sys, z, t0, h, n, true, observe)
}

/// [`integrate_fixed`] with compensated summation chosen by the caller
/// (`false`: plain summation, the arithmetic of a plain hand-written loop).
#[allow(clippy::too_many_arguments)] // integrate_fixed's arguments, plus one flag
pub fn integrate_fixed_with<S, M, const N: usize>(
    method: &M,
    sys: &S,
    z: &mut [f64; N],
    t0: f64,
    h: f64,
    n: usize,
    compensated: bool,
    mut observe: impl FnMut(usize, f64, &[f64]),
) -> Result<(), StepError>
where
    S: StateSpace + ?Sized,
    M: StepFixed<S, N>,
{
    crate::integrate::check_start(sys, z, h)?;
    let mut carry = method.carry(compensated);
    let mut x = *z;
    observe(0, t0, &x);
    for k in 0..n {
        let t = t0 + k as f64 * h;
        if let Err(source) = method.step_fixed(sys, t, h, &mut x, &mut carry, k > 0) {
            *z = x;
            return Err(StepError::Solve {
                step: k + 1,
                t,
                source,
            });
        }
        let t_next = t0 + (k + 1) as f64 * h;
        // One pass, no early exit: a vectorisable check the loop can keep.
        if !x.iter().fold(true, |ok, v| ok & v.is_finite()) {
            *z = x;
            let index = x.iter().position(|v| !v.is_finite()).unwrap_or(0);
            return Err(StepError::Diverged {
                step: k + 1,
                t: t_next,
                index,
                value: x[index],
            });
        }
        observe(k + 1, t_next, &x);
    }
    *z = x;
    Ok(())
}
