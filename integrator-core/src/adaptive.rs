//! Reversible adaptive step-size control for symmetric one-step methods
//! (Hairer 1997, "Variable time step integration with symplectic methods";
//! Hairer–Lubich–Wanner, *Geometric Numerical Integration*, VIII.3;
//! Huang & Leimkuhler 1997, "The adaptive Verlet method"; Hairer &
//! Söderlind 2005, "Explicit, time reversible, adaptive step size control").
//!
//! A standard controller (an embedded error estimate and a step rejected or
//! grown from it) destroys the symmetry of a symmetric method: the step
//! taken backwards from `y₁` is not the step taken forwards to it, so the
//! map is no longer time-reversible and the energy error drifts. Here the
//! step size is a function of the state through a user-chosen *step-size
//! function* `σ(y) > 0` (`h ≈ ε·σ(y)`, a small `ε`; the *step density* is
//! `1/σ`), imposed symmetrically:
//!
//! * [`Controller::Implicit`] (Hairer 1997, HLW VIII.3.1): the step from
//!   `yₙ` takes `h = ε·(σ(yₙ) + σ(yₙ₊₁))/2`, solved together with
//!   `yₙ₊₁ = Φ_h(yₙ)` by fixed-point iteration on `h` to round-off. The
//!   relation between `yₙ`, `yₙ₊₁` and `h` is unchanged when the two states
//!   are swapped and `h → −h`, so with a symmetric `Φ` the map is
//!   symmetric. Each iteration is one step of the method.
//! * [`Controller::Integrating`] (Hairer–Söderlind 2005, HLW VIII.3.2):
//!   the control variable `ζ ≈ 1/σ(y)` is integrated along with `y` by
//!   `dζ/dτ = G(y) = −σ̇(y)/σ(y)` (`σ̇ = ∇σ·f`, the rate of `σ` along the
//!   flow, which the [`StepDensity`] supplies) in a Störmer–Verlet fashion:
//!   `ζ ← ζ + ε/2·G(yₙ)`, `yₙ₊₁ = Φ_{ε/ζ}(yₙ)`, `ζ ← ζ + ε/2·G(yₙ₊₁)`.
//!   Explicit in `h`: one step of the method and one evaluation of `σ̇`
//!   per step. The map `(y, ζ) ↦ (y', ζ')` is symmetric.
//!
//! For a `ρ`-reversible problem (`ρ(q, p) = (q, −p)`, `f∘ρ = −ρf`) and a
//! density with `σ∘ρ = σ`, both maps are then `ρ`-reversible: stepping
//! from `ρ(yₙ)` (and, for the integrating controller, the same `ζ`) leads
//! back to `ρ(y₀)`, to round-off. Only symmetric methods qualify:
//! [`Reversible::new`] refuses any other with an error naming the method.
//!
//! For an implicit method (the Gauss methods) the map is symmetric only as
//! far as its stage equations are solved: the stage solver stops at
//! round-off, or where the corrections stagnate below
//! `Settings::stagnation_limit` (1e-12 by default), and then a step depends
//! on its starting values to that level. Set the limit lower in the
//! workspace (see the tests) for reversibility to round-off.
//!
//! The last step of a run to `t_end` is cut to land on `t_end` exactly;
//! that one step is not part of the reversible map.
//!
//! ```
//! use integrator_core::adaptive::{Controller, DistancePower, Reversible};
//! use integrator_core::library::{Leapfrog, Rk4};
//! use integrator_core::problems::Kepler;
//! use integrator_core::energy;
//!
//! let kepler = Kepler { e: 0.9 };
//! let mut z = kepler.initial_state();
//! let e0 = energy(&kepler, &z);
//! // h ≈ ε·r: the step density is the inverse distance.
//! let adaptive = Reversible::new(Leapfrog, DistancePower::new(1.0), Controller::Integrating).unwrap();
//! let run = adaptive.integrate(&kepler, &mut z, 0.0, 2.0 * std::f64::consts::PI, 0.01).unwrap();
//! assert!(run.steps > 100);
//! assert!((energy(&kepler, &z) - e0).abs() < 1e-3 * e0.abs());
//! // A method that is not symmetric is refused.
//! let err = Reversible::new(Rk4, DistancePower::new(1.0), Controller::Implicit).unwrap_err();
//! assert!(err.to_string().contains("not symmetric"));
//! ```

use crate::error::SolveError;
use crate::scheme::{Scheme, Step};
use crate::system::{OdeSystem, Separable};

/// Why a reversible adaptive run cannot start or could not go on.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AdaptiveError {
    #[error(
        "method '{name}' is not symmetric: reversible step-size control needs a symmetric one-step \
         method (its adjoint is itself), e.g. leapfrog, a symmetric composition or a Gauss method"
    )]
    NotSymmetric { name: &'static str },
    #[error("ε = {0} must be finite and > 0")]
    Epsilon(f64),
    #[error("the end time {t_end} must be finite and after the start {t0}")]
    EndTime { t0: f64, t_end: f64 },
    #[error("the state has {got} components, but the system has dimension {expected}")]
    Dimension { expected: usize, got: usize },
    #[error("the step-size function σ = {sigma} at t = {t} (it must be finite and > 0)")]
    Density { t: f64, sigma: f64 },
    #[error("step {step} (from t = {t}) failed: {source}")]
    Solve {
        step: u64,
        t: f64,
        #[source]
        source: SolveError,
    },
    #[error(
        "step {step} (from t = {t}): the symmetric step size did not converge in {iterations} \
         iterations (|Δh| = {correction:e}); take a smaller ε"
    )]
    StepSizeNotConverged {
        step: u64,
        t: f64,
        iterations: usize,
        correction: f64,
    },
    #[error("the solution diverged at step {step} (t = {t})")]
    Diverged { step: u64, t: f64 },
    #[error("more than {0} steps before the end time")]
    TooManySteps(u64),
}

/// The step-size function `σ(y) > 0` of a reversible controller
/// (`h ≈ ε·σ`), and its rate along the flow. For reversibility it must be
/// even in the momenta, `σ(q, −p) = σ(q, p)`.
pub trait StepDensity<S: ?Sized> {
    /// `σ(z)`.
    fn sigma(&self, sys: &S, z: &[f64]) -> f64;
    /// `σ̇(z) = ∇σ(z)·f(z)`, the rate of change of `σ` along the exact
    /// flow (needed by [`Controller::Integrating`] only).
    fn rate(&self, sys: &S, z: &[f64]) -> f64;
}

/// `σ = |q|^α` for a separable system: for a central force (Kepler in
/// relative coordinates) `|q|` is the distance, and `α = 1` makes the step
/// density the inverse distance (the default for gravity; Sundman's
/// `dt = r ds`), `α = 3/2` the inverse free-fall time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistancePower {
    pub alpha: f64,
}

impl DistancePower {
    pub fn new(alpha: f64) -> Self {
        DistancePower { alpha }
    }
}

impl<S: Separable + ?Sized> StepDensity<S> for DistancePower {
    fn sigma(&self, sys: &S, z: &[f64]) -> f64 {
        let q = &z[..sys.dof()];
        let r2: f64 = q.iter().map(|x| x * x).sum();
        r2.powf(0.5 * self.alpha)
    }
    /// `α·|q|^(α−2)·(q·q̇)` with `q̇ = ∂T/∂p`.
    fn rate(&self, sys: &S, z: &[f64]) -> f64 {
        let n = sys.dof();
        let (q, p) = z.split_at(n);
        let mut small = [0.0; 16];
        let mut large = Vec::new();
        let v: &mut [f64] = if n <= small.len() {
            &mut small[..n]
        } else {
            large.resize(n, 0.0);
            &mut large
        };
        sys.velocity(p, v);
        let r2: f64 = q.iter().map(|x| x * x).sum();
        let qv: f64 = q.iter().zip(v.iter()).map(|(a, b)| a * b).sum();
        self.alpha * r2.powf(0.5 * self.alpha - 1.0) * qv
    }
}

/// How the step size is tied to the state (see the [module
/// documentation](self)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Controller {
    /// `h = ε·(σ(yₙ) + σ(yₙ₊₁))/2`, solved by iteration (Hairer 1997).
    Implicit,
    /// `ζ` integrated with `y`, `h = ε/ζ` (Hairer–Söderlind 2005).
    Integrating,
}

/// The most fixed-point iterations of the implicit step-size equation.
pub const MAX_ITERATIONS: usize = 50;
/// The most steps of one [`Reversible::integrate`] run.
pub const MAX_STEPS: u64 = 100_000_000;

/// A symmetric method under a reversible step-size controller.
#[derive(Clone, Debug)]
pub struct Reversible<M, D> {
    pub scheme: M,
    pub density: D,
    pub controller: Controller,
}

/// What a run did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AdaptiveRun {
    /// Steps taken (the landing step included).
    pub steps: u64,
    /// Steps of the method tried (more than `steps` for the implicit
    /// controller: one per iteration).
    pub trial_steps: u64,
    /// The smallest and largest step taken (the landing step excluded).
    pub h_min: f64,
    pub h_max: f64,
}

impl<M: Scheme, D> Reversible<M, D> {
    /// The controller on `scheme`, or [`AdaptiveError::NotSymmetric`] if the
    /// scheme is not symmetric (its verified `INFO.symmetric`).
    pub fn new(scheme: M, density: D, controller: Controller) -> Result<Self, AdaptiveError> {
        if !M::INFO.symmetric {
            return Err(AdaptiveError::NotSymmetric { name: M::INFO.name });
        }
        Ok(Reversible {
            scheme,
            density,
            controller,
        })
    }
}

impl<M, D> Reversible<M, D> {
    /// The controller's starting value of `ζ`: `1/σ(z)`.
    pub fn start_control<S>(&self, sys: &S, t: f64, z: &[f64]) -> Result<f64, AdaptiveError>
    where
        S: OdeSystem + ?Sized,
        D: StepDensity<S>,
    {
        let sigma = self.density.sigma(sys, z);
        if !(sigma.is_finite() && sigma > 0.0) {
            return Err(AdaptiveError::Density { t, sigma });
        }
        Ok(1.0 / sigma)
    }

    /// One step of the reversible map from `(t, z)` with parameter `eps`
    /// (negative: backwards), updating `z` and, for the integrating
    /// controller, `zeta`. Returns the step size taken and the number of
    /// method steps it cost. `z` is unchanged on error.
    #[allow(clippy::too_many_arguments)]
    pub fn step<S>(
        &self,
        sys: &S,
        t: f64,
        z: &mut [f64],
        zeta: &mut f64,
        eps: f64,
        ws: &mut <M as Step<S>>::Workspace,
        trial: &mut Vec<f64>,
    ) -> Result<(f64, u64), SolveError>
    where
        S: OdeSystem + ?Sized,
        M: Step<S>,
        D: StepDensity<S>,
    {
        match self.controller {
            Controller::Integrating => {
                let half = *zeta + 0.5 * eps * self.g(sys, z);
                let h = eps / half;
                self.scheme.step(sys, t, h, z, ws)?;
                *zeta = half + 0.5 * eps * self.g(sys, z);
                Ok((h, 1))
            }
            Controller::Implicit => {
                let s0 = self.density.sigma(sys, z);
                // Predictor: σ extrapolated along the flow by its rate.
                let mut h = eps * s0;
                trial.clear();
                trial.extend_from_slice(z);
                let mut tries = 0u64;
                let mut last = f64::INFINITY;
                for it in 0..MAX_ITERATIONS {
                    trial.copy_from_slice(z);
                    self.scheme.step(sys, t, h, trial, ws)?;
                    tries += 1;
                    let next = 0.5 * eps * (s0 + self.density.sigma(sys, trial));
                    let dh = (next - h).abs();
                    if !next.is_finite() {
                        return Err(SolveError::Diverged {
                            iterations: it + 1,
                            correction: dh,
                        });
                    }
                    if dh <= 2.0 * f64::EPSILON * next.abs() || (dh >= last && it > 3) {
                        // Converged (or stalled at round-off: the changes no
                        // longer shrink).
                        if next != h {
                            trial.copy_from_slice(z);
                            self.scheme.step(sys, t, next, trial, ws)?;
                            tries += 1;
                        }
                        z.copy_from_slice(trial);
                        return Ok((next, tries));
                    }
                    last = dh;
                    h = next;
                }
                Err(SolveError::NotConverged {
                    iterations: MAX_ITERATIONS,
                    correction: last,
                })
            }
        }
    }

    /// `G = −σ̇/σ`.
    fn g<S>(&self, sys: &S, z: &[f64]) -> f64
    where
        S: OdeSystem + ?Sized,
        D: StepDensity<S>,
    {
        -self.density.rate(sys, z) / self.density.sigma(sys, z)
    }

    /// From `(t0, z)` to `t_end` with parameter `eps` (the step is about
    /// `eps·σ`); `z` ends as the state at `t_end`. `observe(t, z)` sees the
    /// state after each step. The last step is cut to land on `t_end`.
    pub fn integrate_observed<S>(
        &self,
        sys: &S,
        z: &mut [f64],
        t0: f64,
        t_end: f64,
        eps: f64,
        observe: impl FnMut(f64, &[f64]) -> bool,
    ) -> Result<AdaptiveRun, AdaptiveError>
    where
        S: OdeSystem + ?Sized,
        M: Step<S>,
        D: StepDensity<S>,
    {
        let mut ws = self.scheme.workspace(sys);
        self.integrate_in(sys, z, t0, t_end, eps, &mut ws, observe)
    }

    /// [`integrate_observed`](Self::integrate_observed) with the caller's
    /// workspace (its settings: compensated summation, the stage solver's).
    #[allow(clippy::too_many_arguments)]
    pub fn integrate_in<S>(
        &self,
        sys: &S,
        z: &mut [f64],
        t0: f64,
        t_end: f64,
        eps: f64,
        ws: &mut <M as Step<S>>::Workspace,
        mut observe: impl FnMut(f64, &[f64]) -> bool,
    ) -> Result<AdaptiveRun, AdaptiveError>
    where
        S: OdeSystem + ?Sized,
        M: Step<S>,
        D: StepDensity<S>,
    {
        if !(eps.is_finite() && eps > 0.0) {
            return Err(AdaptiveError::Epsilon(eps));
        }
        if !(t0.is_finite() && t_end.is_finite() && t_end > t0) {
            return Err(AdaptiveError::EndTime { t0, t_end });
        }
        if z.len() != sys.dim() {
            return Err(AdaptiveError::Dimension {
                expected: sys.dim(),
                got: z.len(),
            });
        }
        let mut zeta = self.start_control(sys, t0, z)?;
        let mut trial = Vec::with_capacity(z.len());
        let mut saved = z.to_vec();
        let mut run = AdaptiveRun {
            h_min: f64::INFINITY,
            h_max: 0.0,
            ..AdaptiveRun::default()
        };
        let mut t = t0;
        while t < t_end {
            if run.steps >= MAX_STEPS {
                return Err(AdaptiveError::TooManySteps(MAX_STEPS));
            }
            saved.copy_from_slice(z);
            let zeta0 = zeta;
            let (h, tries) = self
                .step(sys, t, z, &mut zeta, eps, ws, &mut trial)
                .map_err(|source| match source {
                    SolveError::NotConverged {
                        iterations,
                        correction,
                    } if self.controller == Controller::Implicit => {
                        AdaptiveError::StepSizeNotConverged {
                            step: run.steps + 1,
                            t,
                            iterations,
                            correction,
                        }
                    }
                    source => AdaptiveError::Solve {
                        step: run.steps + 1,
                        t,
                        source,
                    },
                })?;
            run.trial_steps += tries;
            if !(h.is_finite() && h > 0.0) || z.iter().any(|x| !x.is_finite()) {
                return Err(AdaptiveError::Diverged {
                    step: run.steps + 1,
                    t,
                });
            }
            run.steps += 1;
            if t + h >= t_end {
                // Land on t_end: redo the step with the remaining time.
                z.copy_from_slice(&saved);
                zeta = zeta0;
                let last = t_end - t;
                self.scheme
                    .step(sys, t, last, z, ws)
                    .map_err(|source| AdaptiveError::Solve {
                        step: run.steps,
                        t,
                        source,
                    })?;
                run.trial_steps += 1;
                t = t_end;
            } else {
                run.h_min = run.h_min.min(h);
                run.h_max = run.h_max.max(h);
                t += h;
            }
            if !observe(t, z) {
                break;
            }
        }
        Ok(run)
    }

    /// [`integrate_observed`](Self::integrate_observed) without an observer.
    pub fn integrate<S>(
        &self,
        sys: &S,
        z: &mut [f64],
        t0: f64,
        t_end: f64,
        eps: f64,
    ) -> Result<AdaptiveRun, AdaptiveError>
    where
        S: OdeSystem + ?Sized,
        M: Step<S>,
        D: StepDensity<S>,
    {
        self.integrate_observed(sys, z, t0, t_end, eps, |_, _| true)
    }
}
