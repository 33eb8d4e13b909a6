//! Why a Kepler drift was refused or failed.

/// What can go wrong in [`drift`](super::drift). Every variant carries the
/// numbers a caller needs to see what happened; none is ever replaced by a
/// silent NaN.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum KeplerError {
    #[error("Kepler drift: GM = {gm} must be finite and positive")]
    BadGm { gm: f64 },
    #[error("Kepler drift: the time step h = {h} is not finite")]
    BadStep { h: f64 },
    #[error("Kepler drift: {what}[{index}] = {value} is not finite")]
    NonFinite {
        /// `"x"` (position) or `"v"` (velocity).
        what: &'static str,
        index: usize,
        value: f64,
    },
    #[error("Kepler drift: the position is zero (a body on the central mass)")]
    ZeroPosition,
    #[error(
        "Kepler drift: the universal Kepler equation did not converge in {iterations} iterations \
         (residual {residual:e} in time, last correction {correction:e} of s = {s:e}; \
         h = {h:e}, GM = {gm:e}, 2GM/r − v² = {beta:e})"
    )]
    NotConverged {
        iterations: usize,
        /// `r₀s + η₀G₂ + ζ₀G₃ − h` at the last iterate (a time).
        residual: f64,
        correction: f64,
        s: f64,
        h: f64,
        gm: f64,
        beta: f64,
    },
    #[error(
        "Kepler drift: the new state is not finite (h = {h:e}, 2GM/r − v² = {beta:e}: \
         a hyperbolic orbit carried beyond the range of f64)"
    )]
    Overflow { h: f64, beta: f64 },
}
