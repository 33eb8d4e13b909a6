//! One stepper per mechanism behind one trait, [`ClothStepper`]: explicit
//! schemes ([`explicit`]; drift–kick schemes also in bands of rows on two
//! threads, [`banded`]), the sparse stage solver ([`stage`]), the
//! minimisations ([`minimise`]: the midpoint family and the average vector
//! field), the discrete gradient ([`discrete_gradient`]) and RATTLE on the
//! inextensible cloth's constraint manifold ([`rattle`]). No frame loop
//! here: [`Simulation`](crate::Simulation) owns the one loop, its
//! non-finite check and its energy guard, and calls a stepper.

pub mod banded;
pub mod discrete_gradient;
pub mod dispatch;
pub mod explicit;
pub mod minimise;
pub mod rattle;
pub mod stage;
pub mod variable;

use integrator_core::SolveError;
use integrator_core::checkpoint::{CheckpointError, Decoder, Encoder};

use crate::model::ClothModel;

pub use banded::{BandedStepper, Banding, Sequence, sequence_of};
pub use dispatch::{SchemeVisitor, TableVisitor, with_explicit_scheme, with_scheme, with_table};
pub use explicit::SchemeStepper;
pub use minimise::{MinimiseSettings, MinimiseStepper, Minimiser, Solver};
pub use rattle::{RattleSettings, RattleStepper};
pub use stage::{StageSettings, StageStepper};
pub use variable::{VariableStats, VariableStep};

/// Why a step failed (the run loop adds the step, time and method).
#[derive(Debug, thiserror::Error)]
pub enum StepError {
    /// A stage solve (the stage solver, or a scheme's own implicit step).
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// A minimisation or the discrete gradient's Newton iteration.
    #[error(transparent)]
    Minimise(#[from] minimise::MinimiseError),
    /// RATTLE's constraint solve.
    #[error(transparent)]
    Constraint(#[from] rattle::RattleError),
}

/// Where [`ClothStepper::steps`] stopped: step `done` (from 0; `done`
/// steps went well before it) and why.
#[derive(Debug)]
pub struct Halt {
    pub done: usize,
    pub why: Halted,
}

/// Why a frame's steps stopped.
#[derive(Debug)]
pub enum Halted {
    /// The step failed.
    Failed(StepError),
    /// The step left a non-finite `value` at `index` of `z = [q; p]`.
    NonFinite { index: usize, value: f64 },
}

/// What the solver of a run did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SolverStats {
    /// An explicit run.
    None,
    /// The sparse stage solver ([`stage`]).
    Stage(integrator_core::implicit::Stats),
    /// A minimisation or discrete-gradient run, with its settings.
    Minimise(minimise::Stats, MinimiseSettings),
    /// A RATTLE run ([`rattle`]).
    Constrained(rattle::Stats),
}

/// The mark slot of a frame's start ([`ClothStepper::mark`]).
pub const MARK_START: usize = 0;
/// The mark slot of the end of the try a frame keeps while it tries
/// another count.
pub const MARK_KEPT: usize = 1;

/// One mechanism of stepping a cloth model. The run loop calls, per frame,
/// `enter`, `step` once per substep, then `leave`; between `leave` and the
/// next `enter` the state is only read. `enter` and `leave` let a stepper
/// work in coordinates of its own (the stage solver's shifted state) for a
/// whole frame; `step` works in them. Implementations are generic over
/// their scheme where they have one, so the loop is monomorphised and a
/// step costs no dynamic call.
pub trait ClothStepper {
    /// At the start of a frame at time `t`: move `z` into the stepper's
    /// coordinates (nothing for most).
    fn enter(&mut self, _model: &ClothModel, _t: f64, _z: &mut [f64]) {}
    /// One step from `t` to `t + h` in place. On error `z` may be anything:
    /// the loop restores the frame's start.
    fn step(&mut self, model: &ClothModel, t: f64, h: f64, z: &mut [f64]) -> Result<(), StepError>;
    /// The `n` steps of a frame from `enter` to `leave`, step `k` (from 0)
    /// from time `t(k)`, stopping at the first that fails or leaves a
    /// non-finite value in the state ([`Halt`]). The default calls
    /// [`step`](Self::step) `n` times and looks at `z` after each; a
    /// stepper that works in coordinates of its own looks at those.
    fn steps(
        &mut self,
        model: &ClothModel,
        t: &dyn Fn(usize) -> f64,
        h: f64,
        n: usize,
        z: &mut [f64],
    ) -> Result<(), Halt> {
        for done in 0..n {
            self.step(model, t(done), h, z).map_err(|e| Halt {
                done,
                why: Halted::Failed(e),
            })?;
            if let Some(index) = z.iter().position(|x| !x.is_finite()) {
                return Err(Halt {
                    done,
                    why: Halted::NonFinite {
                        index,
                        value: z[index],
                    },
                });
            }
        }
        Ok(())
    }
    /// At the end of a frame at time `t`: move `z` back to `[q; p]`.
    fn leave(&mut self, _model: &ClothModel, _t: f64, _z: &mut [f64]) {}
    /// What the solver did so far.
    fn stats(&self) -> SolverStats;
    /// The stability measure of the last step solved, for the variable
    /// step ([`variable`]): RATTLE's transverse-wave number `h·ω`; `None`
    /// for a stepper that has none (it cannot take the variable step).
    fn wave_number(&self) -> Option<f64> {
        None
    }
    /// After a failed step, before the frame is integrated again from its
    /// start (the variable step): drop what the failed step left as a
    /// guess for the next (RATTLE: its multipliers). Nothing by default.
    fn restart(&mut self) {}
    /// Keep, in slot `slot` ([`MARK_START`] or [`MARK_KEPT`]), what
    /// [`save`](Self::save) would write less the statistics, between
    /// `leave` and the next `enter`: the variable step marks a frame's
    /// start before its first try and the end of the try it keeps, and
    /// goes back with [`rewind`](Self::rewind), so that a frame integrated
    /// again costs no fresh start (RATTLE: no factorisation, no cold warm
    /// start) and ends on the bits a first try with the same count would
    /// have. Nothing by default.
    fn mark(&mut self, _slot: usize) {}
    /// Go back to what [`mark`](Self::mark) kept in `slot`; `false` (and
    /// nothing changed) when this stepper keeps no marks, and the caller
    /// falls back on [`restart`](Self::restart) after a failure.
    fn rewind(&mut self, _slot: usize) -> bool {
        false
    }
    /// Append everything the next steps depend on beyond the state `z`
    /// handed out at a frame (carried momenta, warm starts, factors and
    /// their schedule, compensated-summation residuals) and the solver
    /// statistics, exactly, for a checkpoint taken between `leave` and the
    /// next `enter`; `false` (and nothing written) when this stepper cannot
    /// save its data, so that its runs are not resumable.
    fn save(&self, _e: &mut Encoder) -> bool {
        false
    }
    /// Take back what [`save`](Self::save) wrote, on a stepper just made
    /// for the same model and settings, so that the steps go on to the
    /// bits they would have had.
    fn restore(&mut self, _model: &ClothModel, d: &mut Decoder<'_>) -> Result<(), CheckpointError> {
        Err(d.error("this method's stepper cannot be restored"))
    }
}

/// A run refused before it started: the settings, the scene or the size do
/// not suit the mechanism. The message names the field or flag.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct Refused(pub String);
