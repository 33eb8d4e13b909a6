//! The set-up of the oscillator experiment and what makes one unmeasurable.

use std::fmt;

use integrator_core::energy;
use integrator_core::problems::Oscillator;

use crate::error::CompareError;

/// The most steps per run: every step is written to the series CSV and
/// drawn in the plots.
pub const MAX_STEPS: usize = 20_000;

/// The fewest steps per run: the findings compare the run's halves and its
/// first tenth, which need a few steps each.
pub const MIN_STEPS: usize = 20;

/// The set-up of the experiment.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    /// The frequency `k` of `H = ½(p² + k²q²)`.
    pub k: f64,
    pub q0: f64,
    pub p0: f64,
    /// Steps per run.
    pub steps: usize,
    /// The step sizes, one run of every method per step size.
    pub step_sizes: Vec<f64>,
}

impl Default for Config {
    /// The paper's set-up where it states one (h = 0.01, 0.05, 0.1 and 200
    /// steps), and k = 1, q₀ = 1, p₀ = 0 where it does not.
    fn default() -> Self {
        Config {
            k: 1.0,
            q0: 1.0,
            p0: 0.0,
            steps: 200,
            step_sizes: vec![0.01, 0.05, 0.1],
        }
    }
}

/// Why a set-up cannot be measured, with the values involved. It is data,
/// not a sentence, so that a front end can name its own flags (`symlab
/// paper` says `--k`, `--h`); its `Display` names the fields of [`Config`].
#[derive(Clone, Debug, PartialEq)]
pub enum Invalid {
    /// `k` is not a finite positive number.
    K(f64),
    /// `q0` or `p0` is not finite.
    StartNotFinite { q0: f64, p0: f64 },
    /// `q0 = p0 = 0`: the oscillator rests at its equilibrium.
    AtRest,
    /// Fewer than [`MIN_STEPS`] steps.
    TooFewSteps(usize),
    /// More than [`MAX_STEPS`] steps.
    TooManySteps(usize),
    /// `H(q0, p0)` is not a normal positive `f64`, so relative energy
    /// errors would be meaningless.
    Energy {
        k: f64,
        q0: f64,
        p0: f64,
        energy0: f64,
    },
    /// No step size.
    NoStepSizes,
    /// A step size that is not a finite positive number.
    StepSize(f64),
    /// A step size given twice.
    RepeatedStepSize(f64),
}

impl Invalid {
    /// The field of [`Config`] at fault (the first, where several are).
    pub fn field(&self) -> &'static str {
        match self {
            Invalid::K(_) | Invalid::Energy { .. } => "k",
            Invalid::StartNotFinite { .. } | Invalid::AtRest => "q0",
            Invalid::TooFewSteps(_) | Invalid::TooManySteps(_) => "steps",
            Invalid::NoStepSizes | Invalid::StepSize(_) | Invalid::RepeatedStepSize(_) => {
                "step_sizes"
            }
        }
    }
}

impl fmt::Display for Invalid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Invalid::K(k) => write!(f, "k must be a finite positive number (got {k})"),
            Invalid::StartNotFinite { q0, p0 } => {
                write!(f, "q0 and p0 must be finite (got q0 = {q0}, p0 = {p0})")
            }
            Invalid::AtRest => write!(
                f,
                "q0 and p0 are both 0: the oscillator would rest at its equilibrium with zero energy"
            ),
            Invalid::TooFewSteps(n) => write!(f, "steps must be at least {MIN_STEPS} (got {n})"),
            Invalid::TooManySteps(n) => write!(f, "steps must be at most {MAX_STEPS} (got {n})"),
            Invalid::Energy { k, q0, p0, energy0 } => write!(
                f,
                "k = {k:e}, q0 = {q0:e}, p0 = {p0:e}: the energy H(q0, p0) = {energy0:e} is not a \
                 normal positive f64"
            ),
            Invalid::NoStepSizes => write!(f, "step_sizes needs at least one step size"),
            Invalid::StepSize(h) => write!(
                f,
                "step_sizes: every step size must be a finite positive number (got {h})"
            ),
            Invalid::RepeatedStepSize(h) => write!(f, "step_sizes: {h} is given twice"),
        }
    }
}

impl From<Invalid> for CompareError {
    fn from(e: Invalid) -> Self {
        CompareError::setting(e.field(), e.to_string())
    }
}

impl Config {
    /// Refuse a set-up the experiment cannot measure, saying why.
    pub fn check(&self) -> Result<(), Invalid> {
        if !(self.k.is_finite() && self.k > 0.0) {
            return Err(Invalid::K(self.k));
        }
        if !(self.q0.is_finite() && self.p0.is_finite()) {
            return Err(Invalid::StartNotFinite {
                q0: self.q0,
                p0: self.p0,
            });
        }
        if self.q0 == 0.0 && self.p0 == 0.0 {
            return Err(Invalid::AtRest);
        }
        if self.steps < MIN_STEPS {
            return Err(Invalid::TooFewSteps(self.steps));
        }
        if self.steps > MAX_STEPS {
            return Err(Invalid::TooManySteps(self.steps));
        }
        let energy0 = self.energy0();
        if !(energy0.is_finite() && energy0 >= f64::MIN_POSITIVE) {
            return Err(Invalid::Energy {
                k: self.k,
                q0: self.q0,
                p0: self.p0,
                energy0,
            });
        }
        if self.step_sizes.is_empty() {
            return Err(Invalid::NoStepSizes);
        }
        if let Some(&h) = self
            .step_sizes
            .iter()
            .find(|h| !(h.is_finite() && **h > 0.0))
        {
            return Err(Invalid::StepSize(h));
        }
        for (i, &h) in self.step_sizes.iter().enumerate() {
            if self.step_sizes[..i].contains(&h) {
                return Err(Invalid::RepeatedStepSize(h));
            }
        }
        Ok(())
    }

    pub fn oscillator(&self) -> Oscillator {
        Oscillator { k: self.k }
    }

    pub fn z0(&self) -> [f64; 2] {
        [self.q0, self.p0]
    }

    /// `H(q₀, p₀)`.
    pub fn energy0(&self) -> f64 {
        energy(&self.oscillator(), &self.z0())
    }

    /// The largest and the smallest step size.
    pub fn h_range(&self) -> (f64, f64) {
        let h_max = self.step_sizes.iter().copied().fold(f64::MIN, f64::max);
        let h_min = self.step_sizes.iter().copied().fold(f64::MAX, f64::min);
        (h_max, h_min)
    }
}

/// A step size as it appears in file names: as written where that is short
/// (`0.01`), in scientific notation otherwise (`1e-300`, not 300 digits).
pub fn h_name(h: f64) -> String {
    let plain = format!("{h}");
    if plain.len() <= 10 {
        plain
    } else {
        format!("{h:e}")
    }
}
