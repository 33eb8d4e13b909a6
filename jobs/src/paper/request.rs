//! What to reproduce, and why a request is refused.
//!
//! A refusal is data (the field and the value), not a sentence: the front
//! ends name the field in their own words — the command line as its flag
//! (`--h`), Python as its keyword (`step_sizes`) — from the one sentence
//! written here.

use std::path::PathBuf;

use compare::CompareError;
use compare::paper_oscillator::{Config, Invalid, MAX_STEPS, MIN_STEPS};
use thiserror::Error;

/// The frames of the cloth comparison when the request does not say (5 s
/// at 60 Hz).
pub use cloth::study::figure5::DEFAULT_FRAMES as DEFAULT_CLOTH_FRAMES;

/// A reproduction as the user asked for it; [`Request::check`] (and
/// [`run`](super::run), which calls it) refuses what cannot be measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    /// The directory to write into (created if missing; files of the same
    /// names are overwritten).
    pub out: PathBuf,
    /// The oscillator's set-up (the paper's where it states one).
    pub oscillator: Config,
    /// Frames of the cloth comparison (figure 5) at 60 Hz; 0 skips it; at
    /// most [`cloth::MAX_FRAMES`].
    pub cloth_frames: usize,
}

impl Default for Request {
    /// The paper's set-up, into `out/paper` (the command line's default).
    fn default() -> Self {
        Request {
            out: PathBuf::from("out/paper"),
            oscillator: Config::default(),
            cloth_frames: DEFAULT_CLOTH_FRAMES,
        }
    }
}

impl Request {
    /// Refuse a request the reproduction cannot measure, naming the field:
    /// the oscillator's set-up first, then the cloth's frames. The output
    /// directory is checked when it is created.
    pub fn check(&self) -> Result<(), PaperError> {
        self.oscillator.check().map_err(PaperError::Oscillator)?;
        if self.cloth_frames > cloth::MAX_FRAMES {
            return Err(PaperError::ClothFrames(self.cloth_frames));
        }
        Ok(())
    }
}

/// A field of a [`Request`], for messages: the command line shows it as
/// its flag, Python as its keyword.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    Out,
    K,
    Q0,
    P0,
    Steps,
    StepSizes,
    ClothFrames,
}

impl Field {
    /// The keyword (Python's argument; the field of [`Request`] or of its
    /// oscillator's [`Config`]).
    pub fn keyword(self) -> &'static str {
        match self {
            Field::Out => "out",
            Field::K => "k",
            Field::Q0 => "q0",
            Field::P0 => "p0",
            Field::Steps => "steps",
            Field::StepSizes => "step_sizes",
            Field::ClothFrames => "cloth_frames",
        }
    }

    /// The command line's flag (the step sizes are `--h`, as the paper
    /// writes them).
    pub fn flag(self) -> String {
        match self {
            Field::StepSizes => "--h".to_string(),
            other => format!("--{}", other.keyword().replace('_', "-")),
        }
    }
}

/// Why a reproduction was refused or could not write its files. A method
/// that diverges on the oscillator, or a cloth run that blows up, is not
/// an error: it is a row of the tables, and the report says so.
///
/// `Display` is the command line's form (fields as flags);
/// [`PaperError::keyword_message`] is Python's.
#[derive(Debug, Error)]
pub enum PaperError {
    /// The oscillator's set-up cannot be measured (see [`Invalid::field`]).
    #[error("{}", oscillator_message(.0, &|f| f.flag(), " "))]
    Oscillator(Invalid),
    /// More cloth frames than [`cloth::MAX_FRAMES`].
    #[error("{}", cloth_frames_message(*.0, &|f| f.flag()))]
    ClothFrames(usize),
    /// The output directory cannot be created.
    #[error("{} {}: cannot create the directory", Field::Out.flag(), path.display())]
    OutDir {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A table or the report could not be written.
    #[error("writing {}", path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The oscillator experiment failed, or a plot could not be drawn.
    #[error(transparent)]
    Compare(#[from] CompareError),
    /// The cloth comparison could not be set up.
    #[error(transparent)]
    Cloth(#[from] cloth::RunError),
    /// The paper's cloth scene could not be built.
    #[error(transparent)]
    Scene(#[from] cloth::SceneError),
    /// A checkpoint could not be written, or one to resume from is damaged
    /// or not a paper run's (it names the file).
    #[error(transparent)]
    Checkpoint(#[from] cloth::checkpoint::CheckpointError),
    /// The front end asked the run to stop (a signal): `done` of `total`
    /// cloth runs are kept in `checkpoint`, from which `symlab resume` (or
    /// Python's `symlab.resume`) goes on to the same files.
    #[error(
        "stopped after {done} of {total} cloth runs; the checkpoint {} keeps them",
        checkpoint.display()
    )]
    Stopped {
        checkpoint: PathBuf,
        done: usize,
        total: usize,
    },
}

impl PaperError {
    /// The field of the request at fault, where the request was refused.
    pub fn field(&self) -> Option<Field> {
        match self {
            PaperError::Oscillator(why) => Some(match why {
                Invalid::K(_) | Invalid::Energy { .. } => Field::K,
                Invalid::StartNotFinite { .. } | Invalid::AtRest => Field::Q0,
                Invalid::TooFewSteps(_) | Invalid::TooManySteps(_) => Field::Steps,
                Invalid::NoStepSizes | Invalid::StepSize(_) | Invalid::RepeatedStepSize(_) => {
                    Field::StepSizes
                }
            }),
            PaperError::ClothFrames(_) => Some(Field::ClothFrames),
            PaperError::OutDir { .. } => Some(Field::Out),
            _ => None,
        }
    }

    /// The message with the fields named by their keywords (Python's form),
    /// followed by its causes as `: cause` (as the command line shows them).
    pub fn keyword_message(&self) -> String {
        let keyword = |f: Field| f.keyword().to_string();
        let mut text = match self {
            PaperError::Oscillator(why) => oscillator_message(why, &keyword, "="),
            PaperError::ClothFrames(n) => cloth_frames_message(*n, &keyword),
            PaperError::OutDir { path, .. } => format!(
                "{}={}: cannot create the directory",
                Field::Out.keyword(),
                path.display()
            ),
            other => other.to_string(),
        };
        let mut cause = std::error::Error::source(self);
        while let Some(why) = cause {
            text.push_str(&format!(": {why}"));
            cause = why.source();
        }
        text
    }
}

/// Why the oscillator's set-up is refused, with the fields named by `name`
/// (`sep` between a name and its value) and what the limit protects.
fn oscillator_message(why: &Invalid, name: &dyn Fn(Field) -> String, sep: &str) -> String {
    let (k, q0, p0, steps, h) = (
        name(Field::K),
        name(Field::Q0),
        name(Field::P0),
        name(Field::Steps),
        name(Field::StepSizes),
    );
    match why {
        Invalid::K(v) => format!("{k} must be a finite positive number (got {v})"),
        Invalid::StartNotFinite { q0: a, p0: b } => {
            format!("{q0} and {p0} must be finite (got q0 = {a}, p0 = {b})")
        }
        Invalid::AtRest => format!(
            "{q0} and {p0} are both 0: the oscillator would rest at its equilibrium with zero energy"
        ),
        Invalid::TooFewSteps(n) => format!(
            "{steps} must be at least {MIN_STEPS} (got {n}): the claims compare the run's halves and its first {MIN_STEPS} steps"
        ),
        Invalid::TooManySteps(n) => format!(
            "{steps} must be at most {MAX_STEPS} (got {n}): every step is plotted and written"
        ),
        Invalid::Energy {
            k: vk,
            q0: a,
            p0: b,
            energy0,
        } => format!(
            "{k}{sep}{vk:e}, {q0}{sep}{a:e}, {p0}{sep}{b:e}: the energy H(q0, p0) = {energy0:e} is not a normal positive f64, \
             so relative energy errors |H − H0|/H0 would be meaningless; choose values whose \
             energy lies between 1e-300 and 1e300"
        ),
        Invalid::NoStepSizes => format!("{h} needs at least one step size"),
        Invalid::StepSize(v) => {
            format!("{h}: every step size must be a finite positive number (got {v})")
        }
        Invalid::RepeatedStepSize(v) => format!("{h}: step size {v} is given twice"),
    }
}

/// Why too many cloth frames are refused, the field named by `name`.
fn cloth_frames_message(n: usize, name: &dyn Fn(Field) -> String) -> String {
    format!(
        "{} must be at most {} (got {n}): every frame's statistics stay in memory, and each of the comparison's runs simulates them all",
        name(Field::ClothFrames),
        cloth::MAX_FRAMES,
    )
}
