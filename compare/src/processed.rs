//! A processed table file (`kernel` with `corrector_drift` / `corrector_kick`)
//! on a separable problem: stepped as `χ Kⁿ χ⁻¹` by
//! [`integrator_core::processed::Processed`], `χ⁻¹` once on entry, the
//! kernel every step on the carried state, `χ` only at output. Every output
//! is `n` steps of the one method `χ K χ⁻¹`, whose effective orders the table
//! file's claims state and `tableau` proves; running the kernel alone would
//! give a different method (the corrector silently lost).
//!
//! The kernel is the run-time interpreter of the kernel's drift–kick
//! sequence (the same one that steps the kernel as a plain table file), so
//! the carried state has the bits of the unprocessed kernel's run.

use integrator_core::interp::SplittingInterpreter;
use integrator_core::processed::Processed;
use integrator_core::scheme::SplitWorkspace;
use integrator_core::sequence::Sequence;
use integrator_core::split::Split;
use integrator_core::{Separable, Step, check_start};

use crate::counting::{AsSeparable, Counting};
use crate::problem::{Kind, Problem};
use crate::stepper::{Outcome, Status, Stepper, Workspace};

/// A processed method on a separable problem: see the module documentation.
pub struct ProcessedStepper(pub Processed<SplittingInterpreter>);

/// What [`Stepper::observed`] is handed: called at the start and after each
/// step with `(step, t, output)`; `false` stops the run.
type Observer<'a> = &'a mut dyn FnMut(usize, f64, &[f64]) -> bool;

impl ProcessedStepper {
    /// The run on `sys` (the counting wrapper for the observed run, the bare
    /// system for the timed one). With an observer, `χ` of the carried state
    /// is observed at the start and after every step; without one (the
    /// timed run) `χ` is applied once, after the last step, as a user who
    /// wants one output pays for it. `z` ends as the last output. The
    /// outputs before the last are computed on `quiet` (the bare system in
    /// the observed run), so the evaluations counted are what the timed run
    /// does: `χ⁻¹`, the kernel's steps and one `χ`; the observer's outputs
    /// along the way are the harness's, not the method's.
    #[allow(clippy::too_many_arguments)]
    fn run<S, Q>(
        &self,
        sys: &S,
        quiet: &Q,
        z: &mut [f64],
        h: f64,
        n: usize,
        compensated: bool,
        mut observe: Option<Observer<'_>>,
    ) -> Status
    where
        S: Split + integrator_core::OdeSystem,
        Q: Split,
        SplittingInterpreter: Step<S, Workspace = SplitWorkspace>,
    {
        let failed = |step: usize, reason: String| Status::SolverFailed { step, reason };
        if let Err(e) = check_start(sys, z, h) {
            return failed(0, e.to_string());
        }
        let mut chi_ws = SplitWorkspace::new(sys.buffer_len());
        let mut carried = z.to_vec();
        if let Err(e) = self.0.enter(sys, h, &mut carried, &mut chi_ws) {
            return failed(0, format!("the corrector's inverse on entry: {e}"));
        }
        if let Some(observe) = observe.as_mut()
            && !observe(0, 0.0, z)
        {
            return Status::Stopped { step: 0 };
        }
        let kernel = self.0.kernel();
        let mut ws = kernel.workspace(sys);
        ws.set_compensated(compensated);
        for k in 0..n {
            if let Err(e) = kernel.step_reusing(sys, k as f64 * h, h, &mut carried, &mut ws, k > 0)
            {
                return failed(k + 1, e.to_string());
            }
            if observe.is_none() && k + 1 < n {
                continue;
            }
            let done = if k + 1 == n {
                self.0.output(sys, h, &carried, z, &mut chi_ws)
            } else {
                self.0.output(quiet, h, &carried, z, &mut chi_ws)
            };
            if let Err(e) = done {
                return failed(k + 1, format!("the corrector at output: {e}"));
            }
            if z.iter().any(|x| !x.is_finite()) {
                return Status::Diverged { step: k + 1 };
            }
            if let Some(observe) = observe.as_mut()
                && !observe(k + 1, (k + 1) as f64 * h, z)
            {
                return Status::Stopped { step: k + 1 };
            }
        }
        Status::Ok
    }
}

impl<P> Stepper<P> for ProcessedStepper
where
    P: Problem<Kind = AsSeparable> + Separable,
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
        let counted: Counting<P> = <AsSeparable as Kind<P>>::counted(sys);
        let status = self.run(&counted, sys, z, h, n, compensated, Some(observe));
        let counts = counted.counts();
        Outcome {
            status,
            evals: counts.force + counts.rhs,
            newton_iterations: 0,
            fixed_point_iterations: 0,
            factorizations: 0,
            steps: None,
        }
    }

    fn bare(&self, sys: &P, z: &mut [f64], h: f64, n: usize) -> bool {
        self.run(sys, sys, z, h, n, true, None).is_ok() && z.iter().all(|x| x.is_finite())
    }
}

/// The processed method of a kernel table and its corrector, rounded as
/// `butcher!` rounds them.
pub(crate) fn processed(
    kernel: &tableau::Table,
    corrector: &tableau::Splitting,
) -> Result<ProcessedStepper, integrator_core::interp::InterpError> {
    let named = (corrector.drift.iter().map(|x| ("corrector_drift", x)))
        .chain(corrector.kick.iter().map(|x| ("corrector_kick", x)));
    for (field, x) in named {
        if !x.to_f64().is_finite() {
            return Err(integrator_core::interp::InterpError::NotFinite {
                what: format!("a coefficient of `{field}`"),
                value: format!(" (≈ {})", x.approx_text()),
            });
        }
    }
    Ok(ProcessedStepper(Processed::new(
        SplittingInterpreter::from_table(kernel)?,
        Sequence::from_splitting(corrector),
    )))
}
