//! Implicit steps as energy minimisation: Newton with a positive-definite
//! Hessian, a line search on the objective and faer's sparse Cholesky, for
//! the implicit midpoint family on separable systems with a sparse Hessian.
//!
//! # The midpoint step is a minimisation
//!
//! For `M q̈ = F(q) = −∇V(q)` (`M` diagonal), one implicit midpoint step of
//! size `τ` from `(q, v)` is
//!
//! ```text
//! q' = q + τ·(v + v')/2,   v' = v + τ·M⁻¹F(x̄),   x̄ = (q + q')/2.
//! ```
//!
//! Then `x̄ = q + (τ/2)(v + v')/2 = q + (τ/2)v + (τ²/4)M⁻¹F(x̄)`, i.e. with
//! the explicit predictor `y = q + (τ/2)v`, `(4/τ²)M(x̄ − y) − F(x̄) = 0`:
//! `x̄` is a stationary point of
//!
//! ```text
//! Φ(x) = (2/τ²)(x − y)ᵀM(x − y) + V(x),   ∇Φ = (4/τ²)M(x − y) − F(x),
//! ```
//!
//! and afterwards `q' = 2x̄ − q`, `v' = (2/τ)(q' − q) − v = (4/τ)(x̄ − q) − v`
//! (momenta `p = Mv`). This is a backward-Euler half step (`x̄` is the
//! backward-Euler position after `τ/2`) followed by an explicit half step
//! (the reflection `q' = 2x̄ − q`).
//!
//! A symplectic diagonally implicit RK method whose table has `aᵢᵢ = bᵢ/2`
//! and `aᵢⱼ = bⱼ` (`j < i`) is the composition of midpoint steps of sizes
//! `b₁h, …, b_sh` (Hairer–Lubich–Wanner VI.4): the library's `PaperDirk2`
//! (`b = (½, ½)`) and `PaperDirk4` (the triple jump, with a negative middle
//! weight) step as successive minimisations ([`MidpointStepper::step`]). A
//! negative `τ` changes nothing: the mass term `(2/τ²)M` is still positive.
//!
//! # The unknown: the correction `u = x̄ − y`
//!
//! Newton iterates on `u = x̄ − y`, not on `x̄`: `Φ(u) = ½·c·uᵀMu + V(y + u)`
//! with `c = 4/τ²`. `u = (τ²/4)M⁻¹F(x̄)` is the part of the step the solve
//! decides (the predictor `y` is explicit), the smallest quantity in it
//! (`O(τ²)`, where `x̄ − q` is `O(τ)` and `x̄` itself `O(1)`), so its
//! round-off, and that of the inertial term `c·Mu` of the gradient, is
//! relative to the kick and not to the absolute coordinates. The convergence
//! test is `‖∇Φ‖_∞ ≤ tol·S` with `S` the largest of the system's force scale
//! (the size of the terms whose round-off `F` carries, see
//! [`SparsePotential::force_and_scale`]) and `c·max|mᵢuᵢ|`; measured against
//! `c·|x̄|` instead (the size of the inertial term's terms when the unknown
//! is `x̄`), a converged `x̄` is only known to `tol·|x̄|`, and the momenta
//! `p' = (4/τ)M(x̄ − q) − p` carry `4·tol·m|x̄|/τ` per step: at `τ = 1/1200`
//! s on a cloth that was 1e-9 of the momenta after 120 steps.
//!
//! The new state is then formed as the generic stage solver forms it
//! ([`crate::implicit`] with the table `ImplicitMidpoint`, whose stage
//! increments are `Z_q = x̄ − q`, `Z_p = (τ/2)F(x̄)`):
//! `p' = p + τ·F(x̄)` and `q' = q + τ·M⁻¹(p + (τ/2)F(x̄))`, with `F(x̄)` the
//! force the last gradient test evaluated, added with compensated (Kahan)
//! summation carried from step to step ([`MidpointSettings::compensated`]).
//! `Σ F = 0` for internal forces, so a free system's momentum changes only
//! by the round-off of that sum, whatever the residual. Measured on a chain
//! of nonlinear springs and on the cloth, the steps equal the stage
//! solver's to round-off: positions within an ulp per step, momenta within
//! a few `R = ε·Σ|τ|·S/‖p‖_∞`, the round-off `ε·S` of every force
//! evaluation accumulated over the kicks (see the tests:
//! `integrator-core/tests/minimise.rs`, `cloth/tests/minimise.rs`).
//!
//! # The layer
//!
//! * [`Objective`]: `Φ(u) = ½·c·uᵀMu + U(base + u)` with `M` diagonal and
//!   `U`'s value, force `−∇U` (with its round-off scale) and PSD-projected
//!   Hessian on a fixed sparse pattern supplied by the system. The midpoint
//!   step's objective has `U = V`; an energy-conserving average vector field
//!   step (`q₁ = q + h·v̄`) is the same shape with `base = q + h·v`,
//!   `c = 2/h²` and `U(q₁) = ∫₀¹ (V(q + ξ(q₁ − q)) − V(q))/ξ dξ`, whose
//!   force is `−∫₀¹ ∇V(q + ξ(q₁ − q)) dξ`: the system computes those
//!   integrals ([`AveragedPotential`]) and [`AvfStepper`] steps it; Newton
//!   needs nothing else. A linear term of `Φ` belongs in `U`.
//! * [`Newton`]: Newton's method on `Φ` with the Hessian `c·M + ∇²U` where
//!   the system gives `∇²U` and that matrix is positive definite
//!   (quadratic convergence), else `c·M + K⁺`, `K⁺` the system's projection
//!   of `∇²U` onto the positive-semidefinite cone (block by block for
//!   springs), so that the Hessian is positive definite at any step size,
//!   every direction descends, and a backtracking (Armijo) line search on
//!   `Φ` decreases `Φ` at every iteration. faer's sparse
//!   Cholesky (`LLᵀ`, [`SparseLlt`]): symbolic analysis (AMD ordering) once
//!   per solver, a numeric factorisation per iteration, or the last factor
//!   (of the same `c`) reused while each iteration still shrinks the
//!   gradient 4×. Where `Φ`'s decrease is below its own round-off, the line
//!   search cannot judge a step: see [`Stats::roundoff_steps`] and
//!   [`Stats::floor_accepts`]. All scratch is allocated with the solver.
//! * [`SparsePotential`] and [`MidpointStepper`]: a separable system that
//!   gives `V`, the force and a projected sparse Hessian of `V` is stepped by
//!   the midpoint rule and its compositions.
//!
//! A solve that reaches its iteration cap is an error
//! ([`MinimiseError::NotConverged`]), never accepted, and so is a line
//! search that finds no decrease, a factorisation that is not positive
//! definite and a non-finite value: the state is then left as it was.
//!
//! ```
//! use integrator_core::Separable;
//! use integrator_core::minimise::{Mass, MidpointSettings, MidpointStepper, SparsePotential};
//!
//! /// One particle on a nonlinear spring: V = q²/2 + q⁴/4.
//! struct Anharmonic;
//! impl Separable for Anharmonic {
//!     fn dof(&self) -> usize { 1 }
//!     fn kinetic(&self, p: &[f64]) -> f64 { 0.5 * p[0] * p[0] }
//!     fn potential(&self, q: &[f64]) -> f64 { 0.5 * q[0] * q[0] + 0.25 * q[0].powi(4) }
//!     fn velocity(&self, p: &[f64], out: &mut [f64]) { out[0] = p[0]; }
//!     fn force(&self, q: &[f64], out: &mut [f64]) { out[0] = -q[0] - q[0].powi(3); }
//! }
//! impl SparsePotential for Anharmonic {
//!     fn mass(&self) -> Mass<'_> { Mass::Scalar(1.0) }
//!     fn force_and_scale(&self, q: &[f64], out: &mut [f64]) -> f64 {
//!         self.force(q, out);
//!         q[0].abs() + q[0].abs().powi(3)
//!     }
//!     fn hessian_pattern(&self) -> Vec<(usize, usize)> { vec![(0, 0)] }
//!     fn hessian_values_projected(&self, q: &[f64], out: &mut [f64]) {
//!         out[0] = 1.0 + 3.0 * q[0] * q[0];
//!     }
//! }
//!
//! let mut stepper = MidpointStepper::new(&Anharmonic, MidpointSettings::default())?;
//! let mut z = [1.0, 0.0];
//! let e0 = Anharmonic.kinetic(&z[1..]) + Anharmonic.potential(&z[..1]);
//! // Steps of 0.1 as the triple jump (a negative middle weight), order 4.
//! let x = 1.0 / (2.0 - 2f64.cbrt());
//! for _ in 0..1000 {
//!     stepper.step(&Anharmonic, &[x, 1.0 - 2.0 * x, x], 0.1, &mut z)?;
//! }
//! let e = Anharmonic.kinetic(&z[1..]) + Anharmonic.potential(&z[..1]);
//! assert!((e - e0).abs() < 1e-4 * e0, "{e} vs {e0}");
//! assert_eq!(stepper.stats().solves, 3000);
//! # Ok::<(), integrator_core::minimise::MinimiseError>(())
//! ```

mod avf;
mod llt;
mod midpoint;
mod newton;
mod update;

pub use avf::{AveragedPotential, AvfStepper};
pub use llt::{SparseLlt, UpperPattern};
pub use midpoint::{MidpointSettings, MidpointStepper, SparsePotential};
pub use newton::Newton;

/// The default convergence tolerance on `‖∇Φ‖_∞` relative to the force
/// scale: a few thousand ulps, so that converged steps are the method's
/// steps to round-off (symplectic in practice, not merely plausible).
pub const DEFAULT_TOLERANCE: f64 = 1e-12;

/// The default iteration cap of one Newton solve. Generous on purpose: at
/// steps far beyond the explicit limit the objective is dominated by stiff,
/// rotation-invariant springs (the inertial term `c·M` is 10⁻⁴ of a spring's
/// stiffness on the cloth at 1/60 s), so a solve is close to a static
/// equilibrium search along flat valleys; the average vector field step
/// on the paper cloth at one step per frame takes about 60 iterations on
/// average and up to about 300. A solve that reaches the cap is still an
/// error, never accepted.
pub const DEFAULT_NEWTON_ITERATIONS: usize = 1000;

/// A diagonal mass matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mass<'a> {
    /// `m·I`.
    Scalar(f64),
    /// `diag(m₀, m₁, …)`, one entry per coordinate.
    Diagonal(&'a [f64]),
}

impl Mass<'_> {
    /// `mₖ`.
    #[inline]
    pub fn get(&self, k: usize) -> f64 {
        match self {
            Mass::Scalar(m) => *m,
            Mass::Diagonal(d) => d[k],
        }
    }
}

/// The objective of one solve: `Φ(u) = ½·c·uᵀMu + U(x)`, `x = base + u`,
/// with `M` diagonal and positive and `U` supplied by the system together
/// with its force `−∇U`, the round-off scale of that force, and its Hessian
/// projected onto the positive-semidefinite cone, on the pattern given to
/// [`Newton::new`]. The midpoint step's objective has `U = V` (see the
/// [module documentation](self) for the average vector field's).
pub trait Objective {
    /// The length `n` of the unknown.
    fn dim(&self) -> usize;
    /// The point the unknown is measured from: `x = base + u`.
    fn base(&self) -> &[f64];
    /// `c > 0` of the inertial term.
    fn inertia(&self) -> f64;
    /// `M`.
    fn mass(&self) -> Mass<'_>;
    /// `(U(x), |U|ₐ)`: the value and the sum of the magnitudes of the terms
    /// it is summed from, the size its round-off is relative to.
    fn value(&self, x: &[f64]) -> (f64, f64);
    /// `force = −∇U(x)`; returns the force scale: the size of the terms
    /// whose round-off the force carries (for springs: the largest tension,
    /// and the stiffness times `‖x‖_∞`, since an ulp of position moves a
    /// force by the stiffness times it). The convergence test is relative
    /// to it.
    fn force(&self, x: &[f64], force: &mut [f64]) -> f64;
    /// The values of `∇²U(x)`, projected so that the matrix is positive
    /// semidefinite, in the order of the pattern given to [`Newton::new`].
    fn hessian_projected(&self, x: &[f64], values: &mut [f64]);
    /// The values of `∇²U(x)` itself, unprojected, where the system has
    /// them; returns whether it wrote them. Why: where `c·M + ∇²U` is
    /// positive definite (the inertial term outweighs a compressed spring's
    /// negative curvature) Newton with it converges quadratically, while
    /// the projected Hessian, which drops that curvature, converges only
    /// linearly, at a rate set by the dropped part against `c·M`. [`Newton`]
    /// tries its Cholesky factorisation first and falls back to the
    /// projected Hessian where it is not positive definite. Default: none.
    fn hessian(&self, x: &[f64], values: &mut [f64]) -> bool {
        let _ = (x, values);
        false
    }
}

/// Settings of a Newton solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonSettings {
    /// Converged when `‖∇Φ‖_∞ ≤ tolerance·S` ([module documentation](self)).
    pub tolerance: f64,
    /// Iterations per solve before [`MinimiseError::NotConverged`].
    pub max_iterations: usize,
}

impl Default for NewtonSettings {
    /// [`DEFAULT_TOLERANCE`], [`DEFAULT_NEWTON_ITERATIONS`].
    fn default() -> Self {
        NewtonSettings {
            tolerance: DEFAULT_TOLERANCE,
            max_iterations: DEFAULT_NEWTON_ITERATIONS,
        }
    }
}

impl NewtonSettings {
    /// Refuse a tolerance that is not a positive finite number and a zero
    /// cap, naming the field.
    pub fn check(&self) -> Result<(), String> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(format!(
                "tolerance: {} is not a positive finite number",
                self.tolerance
            ));
        }
        if self.max_iterations == 0 {
            return Err("max_iterations: must be at least 1".to_string());
        }
        Ok(())
    }
}

/// Counters of a minimisation run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Steps of the method.
    pub steps: usize,
    /// Midpoint solves (one per step and composition weight).
    pub solves: usize,
    /// Iterations over all solves (Newton steps or local/global rounds).
    pub iterations: usize,
    /// The most iterations one solve took.
    pub max_iterations: usize,
    /// Numeric factorisations (Newton: at most one per iteration;
    /// local/global: one per distinct step size).
    pub factorizations: usize,
    /// Symbolic analyses (once per run).
    pub symbolic_factorizations: usize,
    /// Solves started from the previous solve's correction (it lowered `Φ`).
    pub predicted: usize,
    /// Halvings of the line search over the run.
    pub backtracks: usize,
    /// Newton steps taken in full without the Armijo test because the
    /// predicted decrease of `Φ` was below its round-off, or (where the
    /// decrease Armijo asks for is within a few thousand ulps of `Φ`)
    /// judged by the gradient instead.
    pub roundoff_steps: usize,
    /// Solves accepted at their round-off floor above the tolerance: three
    /// Newton steps in a row (each with a fresh factorisation) whose
    /// predicted decrease of `Φ` was below its round-off or that moved no
    /// coordinate by more than 4 ulps of the largest, and that no longer
    /// halved the gradient. Counted and reported, with their residual in
    /// `max_residual`.
    pub floor_accepts: usize,
    /// The largest final residual `‖∇Φ‖_∞/S` over all solves.
    pub max_residual: f64,
    /// Factorisations of the unprojected Hessian ([`Objective::hessian`])
    /// that found it not positive definite; the projected one was then
    /// factorised (both are counted in `factorizations`).
    pub indefinite: usize,
    /// Wall time in factorisations (s).
    pub factor_seconds: f64,
}

impl Stats {
    /// Iterations per step.
    pub fn iterations_per_step(&self) -> f64 {
        self.iterations as f64 / self.steps.max(1) as f64
    }
    /// Factorisations per step.
    pub fn factorizations_per_step(&self) -> f64 {
        self.factorizations as f64 / self.steps.max(1) as f64
    }
}

/// The stopping test of every minimiser's iteration, once the residual
/// (`‖∇Φ‖` relative to the force scale) of `iteration` is known: `Ok(true)`
/// when it meets `tolerance`, `Ok(false)` to iterate again, and an error
/// for a non-finite residual or for `iteration == cap` — a cap is never
/// accepted silently.
pub fn converged(
    solver: &'static str,
    iteration: usize,
    residual: f64,
    tolerance: f64,
    cap: usize,
) -> Result<bool, MinimiseError> {
    if !residual.is_finite() {
        return Err(MinimiseError::NonFinite { solver, iteration });
    }
    if residual <= tolerance {
        return Ok(true);
    }
    if iteration == cap {
        return Err(MinimiseError::NotConverged {
            solver,
            iterations: iteration,
            residual,
            tolerance,
        });
    }
    Ok(false)
}

/// Why a minimisation solve failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MinimiseError {
    #[error(
        "the {solver} minimisation did not converge in {iterations} iterations (‖∇Φ‖ = {residual:e} of the force scale; tolerance {tolerance:e})"
    )]
    NotConverged {
        solver: &'static str,
        iterations: usize,
        residual: f64,
        tolerance: f64,
    },
    #[error(
        "the Newton line search found no decrease of the objective in {halvings} halvings at iteration {iteration} (‖∇Φ‖ = {residual:e} of the force scale)"
    )]
    LineSearch {
        iteration: usize,
        halvings: usize,
        residual: f64,
    },
    #[error("the Hessian is not numerically positive definite (pivot {pivot})")]
    NotDefinite { pivot: usize },
    #[error("a non-finite value appeared in the {solver} iteration {iteration}")]
    NonFinite {
        solver: &'static str,
        iteration: usize,
    },
    /// A setting or argument that cannot be used, named in the message.
    #[error("{0}")]
    Invalid(String),
}
