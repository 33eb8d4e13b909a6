//! Errors of the integration layer: bad arguments and steps that fail.

/// What can go wrong when stepping. Every variant names where it happened.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StepError {
    #[error("state has length {got}, but the system has dimension {expected}")]
    Dimension { expected: usize, got: usize },
    #[error("step size h = {} must be finite and nonzero", short(.0))]
    StepSize(f64),
    #[error("initial state is not finite: z[{index}] = {value}")]
    NonFiniteInitial { index: usize, value: f64 },
    #[error("the solution diverged at step {step} (t = {}): z[{index}] = {value}", short(.t))]
    Diverged {
        step: usize,
        t: f64,
        index: usize,
        value: f64,
    },
    #[error("step {step} (from t = {}) failed: {source}", short(.t))]
    Solve {
        step: usize,
        t: f64,
        #[source]
        source: SolveError,
    },
}

/// A time or step size for a message: as written where that is short
/// (`0.25`), in scientific notation otherwise (`1e300`, not 301 digits).
fn short(x: &f64) -> String {
    let plain = format!("{x}");
    if plain.len() <= 12 {
        return plain;
    }
    if (1e-4..1e7).contains(&x.abs()) {
        return format!("{x:.9}").trim_end_matches('0').to_string();
    }
    let sci = format!("{x:e}");
    if sci.len() <= 12 {
        sci
    } else {
        format!("{x:.9e}")
    }
}

/// Why one step could not be taken: an implicit stage solve that did not
/// converge or met a singular matrix, or the flow of a part of a split
/// system that failed. Returned by [`Step::step`](crate::Step::step);
/// [`integrate`](crate::integrate) adds the step number.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SolveError {
    #[error(
        "the stage equations did not converge in {iterations} iterations (last correction {correction:e})"
    )]
    NotConverged { iterations: usize, correction: f64 },
    #[error(
        "the stage iteration diverged (correction {correction:e} after {iterations} iterations)"
    )]
    Diverged { iterations: usize, correction: f64 },
    #[error("the stage matrix I − h·A⊗J is singular")]
    Singular,
    #[error(
        "the system has no Jacobian; Newton's method needs one (use fixed-point iteration or implement `jacobian`)"
    )]
    NoJacobian,
    /// A stepper prepared for one step size (a cached propagator or
    /// factorisation) was asked for another.
    #[error("this stepper was prepared for h = {prepared}, but the step asked for h = {asked}")]
    StepSizeMismatch { prepared: f64, asked: f64 },
    /// A stepper prepared for one system size was given a state of another.
    #[error(
        "this stepper was prepared for dimension {prepared}, but the state has dimension {got}"
    )]
    DimensionMismatch { prepared: usize, got: usize },
    /// The flow of one part of a split system failed (a solve inside it
    /// did not converge, or it left a non-finite value).
    #[error("the flow of part {part} failed: {source}")]
    Flow {
        part: Part,
        #[source]
        source: FlowError,
    },
}

/// One part of a split system: `A` (the part a drift-kick table's drifts
/// move with) or `B` (its kicks).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Part {
    A,
    B,
}

impl std::fmt::Display for Part {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Part::A => "A",
            Part::B => "B",
        })
    }
}

/// Why the flow of one part could not be taken. The step adds the part
/// ([`SolveError::Flow`]), [`integrate`](crate::integrate) the step. Used
/// by the flows of [`crate::split`] (which re-exports it).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FlowError {
    /// An iterative solve inside the flow did not converge (`what`: e.g.
    /// "Kepler's equation").
    #[error("{what} did not converge in {iterations} iterations (last correction {correction:e})")]
    NotConverged {
        what: &'static str,
        iterations: usize,
        correction: f64,
    },
    /// The flow left a value in the state that is not finite (checked by the
    /// step after every flow of a system with [`Split::CHECK_FINITE`](crate::Split::CHECK_FINITE)).
    #[error("the flow left a non-finite value: z[{index}] = {value}")]
    NonFinite { index: usize, value: f64 },
    /// Any other reason, in the flow's words.
    #[error("{0}")]
    Failed(String),
}

impl FlowError {
    /// A failure described by a message (e.g. another error's text).
    pub fn failed(why: impl std::fmt::Display) -> Self {
        FlowError::Failed(why.to_string())
    }
}
