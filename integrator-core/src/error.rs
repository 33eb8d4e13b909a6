//! Errors of the integration layer: bad arguments and steps that fail.

/// What can go wrong when stepping. Every variant names where it happened.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StepError {
    #[error("state has length {got}, but the system has dimension {expected}")]
    Dimension { expected: usize, got: usize },
    #[error("step size h = {0} must be finite and nonzero")]
    StepSize(f64),
    #[error("initial state is not finite: z[{index}] = {value}")]
    NonFiniteInitial { index: usize, value: f64 },
    #[error("the solution diverged at step {step} (t = {t}): z[{index}] = {value}")]
    Diverged { step: usize, t: f64, index: usize, value: f64 },
}
