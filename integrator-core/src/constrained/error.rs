//! What can go wrong when stepping a constrained system. Every variant
//! names the input, or the step and time, where it happened.

/// Why a constrained run stopped.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ConstrainedError {
    #[error("state has length {got}, but the system has 2·dof = {expected}")]
    Dimension { expected: usize, got: usize },
    #[error("the system has {m} constraints for {d} coordinates (need 1 ≤ m ≤ d)")]
    ConstraintCount { m: usize, d: usize },
    /// A workspace used with another pair or system than it was made for.
    #[error("the workspace does not fit: {detail}")]
    Workspace { detail: String },
    #[error("step size h = {0} must be finite and nonzero")]
    StepSize(f64),
    #[error("initial state is not finite: z[{index}] = {value}")]
    NonFiniteInitial { index: usize, value: f64 },
    #[error("inverse mass M⁻¹[{index}] = {value} must be positive and finite")]
    Mass { index: usize, value: f64 },
    /// The initial position violates a constraint beyond round-off.
    #[error(
        "the initial position is off the constraint manifold: {name}: g = {value:e}, more than {tolerance:e} (= {ulps} ε·scale)"
    )]
    OffManifold {
        constraint: usize,
        name: String,
        value: f64,
        tolerance: f64,
        ulps: f64,
    },
    /// The initial momentum violates the hidden constraint `G M⁻¹ p = 0`.
    #[error(
        "the initial momentum is not tangent to the manifold: {name}: (G M⁻¹ p) = {value:e}, more than {tolerance:e} (= {ulps} ε·scale)"
    )]
    OffTangent {
        constraint: usize,
        name: String,
        value: f64,
        tolerance: f64,
        ulps: f64,
    },
    /// `G` has not full rank: the multipliers are not determined.
    #[error("{where_}: the constraint Jacobian G is rank-deficient ({detail})")]
    Degenerate { where_: Where, detail: String },
    /// Newton's iteration on the stages and multipliers reached its cap;
    /// `correction` is its last correction (`s ≥ 3`) or the constraint
    /// residual it left (RATTLE), in units of round-off.
    #[error(
        "{where_}: the stage and multiplier equations did not converge in {iterations} Newton iterations (last correction or residual {correction:.3e} of round-off scale)"
    )]
    NotConverged {
        where_: Where,
        iterations: usize,
        correction: f64,
    },
    /// A non-finite value appeared (in the iteration or in the new state).
    #[error("{where_}: the solution diverged ({detail})")]
    Diverged { where_: Where, detail: String },
}

/// Where a failure happened: at the start, or in a step (numbered from 1)
/// that began at time `t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Where {
    Start,
    Step { step: usize, t: f64 },
}

impl std::fmt::Display for Where {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Where::Start => write!(f, "at the initial state"),
            Where::Step { step, t } => write!(f, "step {step} (from t = {t})"),
        }
    }
}

impl ConstrainedError {
    /// The same error placed at a step (errors of a single step are made
    /// with [`Where::Start`] and placed by the caller that knows the step).
    pub(crate) fn at(self, w: Where) -> Self {
        match self {
            ConstrainedError::Degenerate { detail, .. } => {
                ConstrainedError::Degenerate { where_: w, detail }
            }
            ConstrainedError::NotConverged {
                iterations,
                correction,
                ..
            } => ConstrainedError::NotConverged {
                where_: w,
                iterations,
                correction,
            },
            ConstrainedError::Diverged { detail, .. } => {
                ConstrainedError::Diverged { where_: w, detail }
            }
            other => other,
        }
    }
}
