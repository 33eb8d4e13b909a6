//! Why a Wisdom–Holman system was refused or a part of its step failed.

use crate::kepler::KeplerError;

/// What can go wrong with a [`Jacobi`](super::Jacobi) or
/// [`DemocraticHeliocentric`](super::DemocraticHeliocentric) split. Errors
/// about one body name it by index and, where the problem has names, by
/// name (`body 3 (Uranus)`); errors of a flow name the part, and the step
/// where the caller is an integration loop that knows it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum WhError {
    #[error("the gravitational constant G = {g} must be finite and positive")]
    BadG { g: f64 },
    #[error("an N-body problem needs at least 2 bodies (the central one first), got {n}")]
    TooFewBodies { n: usize },
    #[error("{} names given for {masses} masses", .names)]
    NameCount { names: usize, masses: usize },
    #[error("{}: mass {mass} must be finite and positive", who(*.body, .name))]
    BadMass {
        body: usize,
        name: Option<String>,
        mass: f64,
    },
    #[error("{what} has length {got}, but {n} bodies need {expected}", n = .expected / 6)]
    Length {
        what: &'static str,
        expected: usize,
        got: usize,
    },
    #[error("{}: {} coordinate {index} is not finite ({value})", who(*.body, .name), .what)]
    NonFiniteInput {
        what: &'static str,
        body: usize,
        name: Option<String>,
        index: usize,
        value: f64,
    },
    #[error("{}{}, {part} part: {source}", who(*.body, .name), at(.step))]
    Kepler {
        part: &'static str,
        body: usize,
        name: Option<String>,
        step: Option<usize>,
        #[source]
        source: Box<KeplerError>,
    },
    #[error("{}{}, {part} part: the new state is not finite", who(*.body, .name), at(.step))]
    NonFinite {
        part: &'static str,
        body: usize,
        name: Option<String>,
        step: Option<usize>,
    },
    #[error(
        "{}: the {coordinates} coordinates do not round-trip: the inertial state comes back \
         {error:e} away, more than the bound {bound:e}",
        who(*.body, .name)
    )]
    RoundTrip {
        coordinates: &'static str,
        body: usize,
        name: Option<String>,
        error: f64,
        bound: f64,
    },
    #[error(
        "a gradient kick needs a finite, nonzero kick time and a finite weight (h = {h}, γ = {gamma}): the lazy modified kick moves the positions by 2γ/h times the accelerations"
    )]
    GradientKick { h: f64, gamma: f64 },
    #[error("a Kepler history for {found} bodies given to a split of {expected}")]
    History { expected: usize, found: usize },
}

impl WhError {
    /// The same error, at integration step `step` (flows called on their
    /// own do not know it).
    pub fn at_step(mut self, k: usize) -> Self {
        match &mut self {
            WhError::Kepler { step, .. } | WhError::NonFinite { step, .. } => *step = Some(k),
            _ => {}
        }
        self
    }
}

fn who(body: usize, name: &Option<String>) -> String {
    match name {
        Some(n) => format!("body {body} ({n})"),
        None => format!("body {body}"),
    }
}

fn at(step: &Option<usize>) -> String {
    match step {
        Some(k) => format!(" at step {k}"),
        None => String::new(),
    }
}
