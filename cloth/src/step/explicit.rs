//! A scheme's own step: every explicit library scheme, and any
//! `S: Step<ClothModel>` a user writes with `butcher!`.

use integrator_core::Step;

use super::{ClothStepper, SolverStats, StepError};
use crate::model::ClothModel;

/// Steps with `S`'s own code (generic, so fully specialised to the table;
/// no allocation per step: the workspace is built once per run).
pub struct SchemeStepper<S: Step<ClothModel>> {
    scheme: S,
    workspace: S::Workspace,
    /// Whether the previous step ended at the current state, so that a
    /// first-same-as-last table may reuse its last evaluation. The loop
    /// never touches the state between steps, only reads it at frames.
    reuse: bool,
}

impl<S: Step<ClothModel>> SchemeStepper<S> {
    pub fn new(scheme: S, model: &ClothModel) -> Self {
        let workspace = scheme.workspace(model);
        SchemeStepper {
            scheme,
            workspace,
            reuse: false,
        }
    }
}

impl<S: Step<ClothModel>> ClothStepper for SchemeStepper<S> {
    #[inline]
    fn step(&mut self, model: &ClothModel, t: f64, h: f64, z: &mut [f64]) -> Result<(), StepError> {
        let reuse = self.reuse;
        self.reuse = true;
        self.scheme
            .step_reusing(model, t, h, z, &mut self.workspace, reuse)
            .map_err(StepError::Solve)
    }

    fn stats(&self) -> SolverStats {
        SolverStats::None
    }
}
