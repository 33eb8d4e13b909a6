//! Stepping one method on one problem: the generic inner loop, instantiated
//! once per (scheme, problem) pair, behind the object-safe [`Stepper`] so
//! that the experiments themselves are written once. Two wrappers make a
//! scheme a stepper, named by the path they step on: [`StepStepper`], the
//! general path, through [`Step`] on a slice (any scheme: the library's, a
//! user's `butcher!` scheme, the run-time interpreters); and
//! [`FixedSizeStepper`], which times explicit schemes on fixed-size stack
//! state through [`StepFixed`] where the problem is small.

use integrator_core::fixed::StepFixed;
use integrator_core::implicit::ImplicitWorkspace;
use integrator_core::interp::RkInterpWorkspace;
use integrator_core::linear::Propagator;
use integrator_core::scheme::{PrkWorkspace, RkWorkspace, SplitWorkspace};
use integrator_core::{OdeSystem, Step, check_start};

use crate::problem::{Counted, Kind, OnSlices, Problem, Stacked};

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Status {
    Ok,
    /// A non-finite state after this step.
    Diverged {
        step: usize,
    },
    /// The implicit stage solve (or the propagator's construction) failed.
    SolverFailed {
        step: usize,
        reason: String,
    },
    /// The observer asked to stop after this step.
    Stopped {
        step: usize,
    },
    /// User code (a `Step` or a `Problem`) panicked during this step (0:
    /// before the first step, e.g. building the workspace); the panic was
    /// caught ([`observed_caught`]) and the experiment went on.
    Panicked {
        step: usize,
        message: String,
    },
}

impl Status {
    pub fn is_ok(&self) -> bool {
        matches!(self, Status::Ok)
    }
    /// The `status` column of the CSV files.
    pub fn label(&self) -> String {
        match self {
            Status::Ok => "ok".into(),
            Status::Diverged { step } => format!("diverged at step {step}"),
            Status::SolverFailed { step, reason } => {
                format!("solver failed at step {step}: {reason}")
            }
            Status::Stopped { step } => format!("stopped at step {step}"),
            Status::Panicked { step: 0, message } => {
                format!("panicked before the first step: {message}")
            }
            Status::Panicked { step, message } => format!("panicked at step {step}: {message}"),
        }
    }
}

/// What one observed run did.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub status: Status,
    /// Evaluations: force (separable problems) or right-hand side (linear);
    /// for a propagator, one matrix–vector product per step.
    pub evals: u64,
    pub newton_iterations: usize,
    pub fixed_point_iterations: usize,
    pub factorizations: usize,
    /// Steps taken, for a method whose step count is not the `n` it was
    /// asked for (a time-transformed scheme steps in a fictitious time and
    /// lands on `T` in however many steps that takes); `None`: `n`.
    pub steps: Option<u64>,
}

/// The workspace features the experiments use: the compensated-summation
/// switch and the implicit solver's counters.
pub trait Workspace {
    fn set_compensated(&mut self, on: bool);
    /// `(newton_iterations, fixed_point_iterations, factorizations)`;
    /// zero for explicit schemes.
    fn solver_counts(&self) -> (usize, usize, usize) {
        (0, 0, 0)
    }
}

impl<const S: usize> Workspace for RkWorkspace<S> {
    fn set_compensated(&mut self, on: bool) {
        self.compensated = on;
    }
}
impl Workspace for SplitWorkspace {
    fn set_compensated(&mut self, on: bool) {
        self.compensated = on;
    }
}
impl<const S: usize> Workspace for PrkWorkspace<S> {
    fn set_compensated(&mut self, on: bool) {
        self.compensated = on;
    }
}
impl Workspace for ImplicitWorkspace {
    fn set_compensated(&mut self, on: bool) {
        self.settings_mut().compensated = on;
    }
    fn solver_counts(&self) -> (usize, usize, usize) {
        let s = self.stats();
        (
            s.newton_iterations,
            s.fixed_point_iterations,
            s.factorizations,
        )
    }
}
impl Workspace for RkInterpWorkspace {
    fn set_compensated(&mut self, on: bool) {
        self.compensated = on;
    }
}
/// The propagator's scratch vector: nothing to switch, nothing to count.
impl Workspace for Vec<f64> {
    fn set_compensated(&mut self, _on: bool) {}
}

/// One method on problems of type `P`. Implement it directly for a method
/// that is not a [`Step`] (as the exact propagators are); wrap a `Step`
/// type in [`StepStepper`].
pub trait Stepper<P>: Send + Sync {
    /// `n` steps of size `h` from `z` (at `t = 0`) on the counting wrapper,
    /// calling `observe(step, t, z)` before the first step and after each;
    /// `observe` returning `false` stops the run. `compensated` switches
    /// compensated summation (the workspaces' default is on).
    fn observed(
        &self,
        sys: &P,
        z: &mut [f64],
        h: f64,
        n: usize,
        compensated: bool,
        observe: &mut dyn FnMut(usize, f64, &[f64]) -> bool,
    ) -> Outcome;
    /// The same run on the bare system, no observer, default settings: what
    /// is timed. `false` if it failed or ended non-finite.
    fn bare(&self, sys: &P, z: &mut [f64], h: f64, n: usize) -> bool;
}

/// [`Stepper::observed`] with a panic of the method or the problem caught:
/// the run then ends with [`Status::Panicked`] naming the step (the one
/// after the last observed) and the panic's message, nothing is printed,
/// and the caller goes on with the next run. Every experiment of this crate
/// steps user code through this (and [`bare_caught`]).
pub fn observed_caught<P>(
    stepper: &dyn Stepper<P>,
    sys: &P,
    z: &mut [f64],
    h: f64,
    n: usize,
    compensated: bool,
    observe: &mut dyn FnMut(usize, f64, &[f64]) -> bool,
) -> Outcome {
    let mut next = 0;
    let caught = crate::guard::catch(|| {
        stepper.observed(sys, z, h, n, compensated, &mut |k, t, z| {
            next = k + 1;
            observe(k, t, z)
        })
    });
    caught.unwrap_or_else(|message| Outcome {
        status: Status::Panicked {
            step: next,
            message,
        },
        evals: 0,
        newton_iterations: 0,
        fixed_point_iterations: 0,
        factorizations: 0,
        steps: None,
    })
}

/// [`Stepper::bare`] with a panic caught: `Err(message)`.
pub fn bare_caught<P>(
    stepper: &dyn Stepper<P>,
    sys: &P,
    z: &mut [f64],
    h: f64,
    n: usize,
) -> Result<bool, String> {
    crate::guard::catch(|| stepper.bare(sys, z, h, n))
}

/// The loop of [`integrate`](integrator_core::integrate), with the
/// workspace in the caller's hands and an observer that may stop it.
pub(crate) fn drive<S, M>(
    m: &M,
    sys: &S,
    ws: &mut M::Workspace,
    z: &mut [f64],
    h: f64,
    n: usize,
    mut observe: impl FnMut(usize, f64, &[f64]) -> bool,
) -> Status
where
    S: OdeSystem + ?Sized,
    M: Step<S>,
{
    if let Err(e) = check_start(sys, z, h) {
        return Status::SolverFailed {
            step: 0,
            reason: e.to_string(),
        };
    }
    if !observe(0, 0.0, z) {
        return Status::Stopped { step: 0 };
    }
    for k in 0..n {
        let t = k as f64 * h;
        if let Err(e) = m.step_reusing(sys, t, h, z, ws, k > 0) {
            return Status::SolverFailed {
                step: k + 1,
                reason: e.to_string(),
            };
        }
        if z.iter().any(|x| !x.is_finite()) {
            return Status::Diverged { step: k + 1 };
        }
        if !observe(k + 1, (k + 1) as f64 * h, z) {
            return Status::Stopped { step: k + 1 };
        }
    }
    Status::Ok
}

/// A scheme (a `butcher!` type, or anything that implements [`Step`] for
/// the problem and for its counting wrapper) as a [`Stepper`] on the
/// general path: every run steps the state as a slice through [`Step`].
pub struct StepStepper<M>(pub M);

impl<M, P> Stepper<P> for StepStepper<M>
where
    P: Problem,
    M: Step<P> + Step<Counted<P>> + Send + Sync,
    <M as Step<P>>::Workspace: Workspace,
    <M as Step<Counted<P>>>::Workspace: Workspace,
{
    fn observed(
        &self,
        sys: &P,
        z: &mut [f64],
        h: f64,
        n: usize,
        compensated: bool,
        observe: &mut dyn FnMut(usize, f64, &[f64]) -> bool,
    ) -> Outcome {
        let counted = <P::Kind as Kind<P>>::counted(sys);
        let mut ws = Step::<Counted<P>>::workspace(&self.0, &counted);
        ws.set_compensated(compensated);
        let status = drive(&self.0, &counted, &mut ws, z, h, n, observe);
        let counts = <P::Kind as Kind<P>>::counts(&counted);
        let (newton_iterations, fixed_point_iterations, factorizations) = ws.solver_counts();
        Outcome {
            status,
            evals: counts.force + counts.rhs,
            newton_iterations,
            fixed_point_iterations,
            factorizations,
            steps: None,
        }
    }

    fn bare(&self, sys: &P, z: &mut [f64], h: f64, n: usize) -> bool {
        let mut ws = Step::<P>::workspace(&self.0, sys);
        for k in 0..n {
            if self
                .0
                .step_reusing(sys, k as f64 * h, h, z, &mut ws, k > 0)
                .is_err()
            {
                return false;
            }
        }
        z.iter().all(|x| x.is_finite())
    }
}

/// An explicit scheme (a `butcher!` type with [`StepFixed`]) as a
/// [`Stepper`] that times small problems on fixed-size state: where the
/// state has 2, 4, 6, 12 or 36 entries and the problem names that size in
/// [`Problem::STACK_SIZES`] (the built-in problems' sizes, and the sizes the
/// DOP853 peer runs on stack vectors), [`Stepper::bare`] steps
/// a `[f64; N]` through `StepFixed::step_fixed`, so that both sides of a
/// timing keep the state in registers. A problem that names no size steps
/// slices; a state of a size it did not name takes the observed run's path
/// ([`bare_on_observed`]).
/// Both paths give the same bits (integrator-core's `tests/fixed.rs`), so
/// the observed run, which counts evaluations, is [`StepStepper`]'s.
pub struct FixedSizeStepper<M>(pub M);

/// The fixed-size sizes of [`FixedSizeStepper`].
macro_rules! fixed_sizes {
    ($m:expr, $sys:expr, $z:expr, $h:expr, $n:expr; $($size:literal),*) => {
        // `Stacked::<P, N>::ON` first: a constant, so that the sizes `P`
        // does not have are not compiled (`Problem::STACK_SIZES`).
        $(if Stacked::<P, $size>::ON && $z.len() == $size {
            return bare_fixed::<P, M, $size>($m, $sys, $z, $h, $n);
        })*
    };
}

impl<M, P> Stepper<P> for FixedSizeStepper<M>
where
    P: Problem,
    M: Step<P>
        + Step<Counted<P>>
        + StepFixed<P, 2>
        + StepFixed<P, 4>
        + StepFixed<P, 6>
        + StepFixed<P, 12>
        + StepFixed<P, 36>
        + Copy
        + Send
        + Sync,
    <M as Step<P>>::Workspace: Workspace,
    <M as Step<Counted<P>>>::Workspace: Workspace,
{
    fn observed(
        &self,
        sys: &P,
        z: &mut [f64],
        h: f64,
        n: usize,
        compensated: bool,
        observe: &mut dyn FnMut(usize, f64, &[f64]) -> bool,
    ) -> Outcome {
        StepStepper(self.0).observed(sys, z, h, n, compensated, observe)
    }

    fn bare(&self, sys: &P, z: &mut [f64], h: f64, n: usize) -> bool {
        if OnSlices::<P>::ON {
            return Stepper::<P>::bare(&StepStepper(self.0), sys, z, h, n);
        }
        if z.len() == sys.dim() {
            fixed_sizes!(&self.0, sys, z, h, n; 2, 4, 6, 12, 36);
        }
        bare_on_observed(self, sys, z, h, n)
    }
}

/// A timed run of a problem that names its stack sizes, on a state of
/// another size: the observed run's path (counted slices, the same bits,
/// a little slower), not a third copy of every scheme's step for the
/// problem ([`Problem::STACK_SIZES`]).
pub(crate) fn bare_on_observed<P: Problem>(
    stepper: &impl Stepper<P>,
    sys: &P,
    z: &mut [f64],
    h: f64,
    n: usize,
) -> bool {
    let outcome = stepper.observed(sys, z, h, n, true, &mut |_, _, _| true);
    outcome.status.is_ok() && z.iter().all(|x| x.is_finite())
}

/// [`StepStepper`]'s bare run on a `[f64; N]` (compensated, first same as last).
fn bare_fixed<P, M, const N: usize>(m: &M, sys: &P, z: &mut [f64], h: f64, n: usize) -> bool
where
    P: OdeSystem,
    M: StepFixed<P, N>,
{
    let Ok(mut x) = <[f64; N]>::try_from(&*z) else {
        return false;
    };
    let mut carry = m.carry(true);
    for k in 0..n {
        if m.step_fixed(sys, k as f64 * h, h, &mut x, &mut carry, k > 0)
            .is_err()
        {
            z.copy_from_slice(&x);
            return false;
        }
    }
    z.copy_from_slice(&x);
    x.iter().all(|v| v.is_finite())
}

/// The exact one-step map `z ← R(hH)z + φ` of a Runge–Kutta table on the
/// linear system ([`Propagator`]), built for each `h` (its construction is
/// part of the timed run). One matrix–vector product per step, counted as
/// one evaluation.
pub struct PropagatorStepper {
    pub p: Vec<f64>,
    pub q: Vec<f64>,
}

/// Why a propagator cannot step a problem that is not linear.
const NOT_LINEAR: &str = "the problem is not a linear system z' = Hz + u";

impl<P: Problem> Stepper<P> for PropagatorStepper {
    fn observed(
        &self,
        sys: &P,
        z: &mut [f64],
        h: f64,
        n: usize,
        _compensated: bool,
        observe: &mut dyn FnMut(usize, f64, &[f64]) -> bool,
    ) -> Outcome {
        let Some(sys) = sys.linear() else {
            return Outcome {
                status: Status::SolverFailed {
                    step: 0,
                    reason: NOT_LINEAR.into(),
                },
                evals: 0,
                newton_iterations: 0,
                fixed_point_iterations: 0,
                factorizations: 0,
                steps: None,
            };
        };
        let (status, steps) = match Propagator::new(sys, h, &self.p, &self.q) {
            Ok(prop) => {
                let mut ws = prop.workspace();
                let mut steps = 0;
                let status = drive(&prop, sys, &mut ws, z, h, n, |k, t, z| {
                    steps = k;
                    observe(k, t, z)
                });
                (status, steps as u64)
            }
            Err(e) => (
                Status::SolverFailed {
                    step: 0,
                    reason: e.to_string(),
                },
                0,
            ),
        };
        Outcome {
            status,
            evals: steps,
            newton_iterations: 0,
            fixed_point_iterations: 0,
            factorizations: 0,
            steps: None,
        }
    }

    fn bare(&self, sys: &P, z: &mut [f64], h: f64, n: usize) -> bool {
        let Some(sys) = sys.linear() else {
            return false;
        };
        let Ok(prop) = Propagator::new(sys, h, &self.p, &self.q) else {
            return false;
        };
        let mut ws = prop.workspace();
        for _ in 0..n {
            prop.step(z, &mut ws);
        }
        z.iter().all(|x| x.is_finite())
    }
}
