//! Phase 1: what the user asked ([`Request`]) and how a refusal names the
//! field they wrote ([`InputError`], [`JobError`]).

use std::path::PathBuf;

use integrator_core::checkpoint::Every;
use thiserror::Error;

/// Where the scene comes from.
#[derive(Clone, Debug)]
pub enum SceneSource {
    /// A scene file (TOML).
    File(PathBuf),
    /// A scene's TOML text; `name` stands for the file in messages and in
    /// the summary.
    Text { name: String, text: String },
}

impl SceneSource {
    /// The name messages give the scene's file.
    pub fn file_name(&self) -> String {
        match self {
            SceneSource::File(p) => p.display().to_string(),
            SceneSource::Text { name, .. } => name.clone(),
        }
    }
}

/// A cloth run as the user asked for it. `None` means the scene's value
/// (or the documented default); `plan.rs` checks every field.
#[derive(Clone, Debug)]
pub struct Request {
    pub scene: SceneSource,
    /// A method id that steps cloth (default: the scene's
    /// `simulation.method`).
    pub method: Option<String>,
    /// Frames after the initial one.
    pub frames: Option<usize>,
    /// Steps per frame; exclusive with `dt`.
    pub substeps: Option<usize>,
    /// The step size (s): the frame is split into round(1/(rate·dt)) steps
    /// and the frame rate adjusted so that the step is exactly `dt`.
    pub dt: Option<f64>,
    /// `NXxNY`: the scene at another resolution.
    pub grid: Option<String>,
    /// The output folder (default `out/cloth/<scene name>/`).
    pub out: Option<PathBuf>,
    /// An OBJ file every this many frames (and the last); 0: none.
    pub obj_every: usize,
    /// Frames to render, comma-separated, or `none` (default: first,
    /// middle and last).
    pub render: Option<String>,
    /// The minimisation solver's tolerance (midpoint family, avf,
    /// discrete-gradient).
    pub tolerance: Option<f64>,
    /// The minimisation solver: `newton` (default) or `local-global`.
    pub solver: Option<String>,
    /// Checkpoints' interval (default: every minute where the method's
    /// runs can be resumed).
    pub checkpoint_every: Option<Every>,
}

impl Request {
    /// The scene with every choice left to it (OBJ every 10 frames, the
    /// command line's default).
    pub fn new(scene: SceneSource) -> Request {
        Request {
            scene,
            method: None,
            frames: None,
            substeps: None,
            dt: None,
            grid: None,
            out: None,
            obj_every: 10,
            render: None,
            tolerance: None,
            solver: None,
            checkpoint_every: None,
        }
    }
}

/// A field of a [`Request`] (or of the stability study's), for messages:
/// the command line shows it as its flag, Python as its keyword.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    Method,
    Methods,
    Frames,
    Substeps,
    Dt,
    Grid,
    Out,
    Render,
    Tolerance,
    Solver,
    Duration,
    CheckpointEvery,
    Stability,
}

impl Field {
    /// The keyword (Python's argument, the request's field).
    pub fn keyword(self) -> &'static str {
        match self {
            Field::Method => "method",
            Field::Methods => "methods",
            Field::Frames => "frames",
            Field::Substeps => "substeps",
            Field::Dt => "dt",
            Field::Grid => "grid",
            Field::Out => "out",
            Field::Render => "render",
            Field::Tolerance => "tolerance",
            Field::Solver => "solver",
            Field::Duration => "duration",
            Field::CheckpointEvery => "checkpoint_every",
            Field::Stability => "stability",
        }
    }
    /// The command line's flag.
    pub fn flag(self) -> String {
        format!("--{}", self.keyword().replace('_', "-"))
    }
}

/// Where a refused value came from.
#[derive(Clone, Debug, PartialEq)]
pub enum Origin {
    /// A field of the request, with the value as the message shows it.
    Field(Field, Option<String>),
    /// The scene file (or one of its fields, `simulation.method`).
    Scene { file: String, field: Option<String> },
}

/// A request refused before anything runs.
#[derive(Clone, Debug, PartialEq)]
pub struct InputError {
    pub origin: Origin,
    pub message: String,
}

impl InputError {
    pub(crate) fn field(field: Field, message: impl Into<String>) -> InputError {
        InputError {
            origin: Origin::Field(field, None),
            message: message.into(),
        }
    }
    pub(crate) fn field_value(
        field: Field,
        value: impl Into<String>,
        message: impl Into<String>,
    ) -> InputError {
        InputError {
            origin: Origin::Field(field, Some(value.into())),
            message: message.into(),
        }
    }
    pub(crate) fn scene(file: &str, field: Option<&str>, message: impl Into<String>) -> InputError {
        InputError {
            origin: Origin::Scene {
                file: file.to_string(),
                field: field.map(str::to_string),
            },
            message: message.into(),
        }
    }
    /// The message with the field named by `name` (its flag or keyword).
    fn shown(&self, name: impl Fn(Field) -> String, sep: &str) -> String {
        match &self.origin {
            Origin::Field(f, None) => format!("{}: {}", name(*f), self.message),
            Origin::Field(f, Some(v)) => format!("{}{sep}{v}: {}", name(*f), self.message),
            Origin::Scene { file, field: None } => format!("{file}: {}", self.message),
            Origin::Scene {
                file,
                field: Some(field),
            } => format!("{file}: {field}: {}", self.message),
        }
    }
}

impl std::fmt::Display for InputError {
    /// The command line's form: the field as its flag.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.shown(Field::flag, " "))
    }
}

/// Why a cloth job could not be planned or run to its end. A run that
/// blew up is not an error but an [`Outcome`](super::Outcome): it keeps what was good.
#[derive(Debug, Error)]
pub enum JobError {
    #[error("{0}")]
    Input(InputError),
    /// The scene file cannot be read or is not a valid scene (the message
    /// names the file and the field).
    #[error("{0}")]
    Scene(String),
    /// An output file could not be written.
    #[error("{}: {what}: {source}", path.display())]
    Io {
        path: PathBuf,
        what: &'static str,
        #[source]
        source: std::io::Error,
    },
    /// An output file (energy.csv, an OBJ frame, a plot, a PNG) could not
    /// be written; the message names it.
    #[error("{0}")]
    Output(String),
    #[error(transparent)]
    Checkpoint(#[from] cloth::checkpoint::CheckpointError),
    /// The run failed other than by blowing up (an output callback).
    #[error("{0}")]
    Run(String),
}

impl JobError {
    /// The message with a refused field named by its keyword (Python's
    /// form); other errors read as their `Display`.
    pub fn keyword_message(&self) -> String {
        match self {
            JobError::Input(e) => e.shown(|f| f.keyword().to_string(), "="),
            other => other.to_string(),
        }
    }
    pub(crate) fn io(path: impl Into<PathBuf>, what: &'static str, source: std::io::Error) -> Self {
        JobError::Io {
            path: path.into(),
            what,
            source,
        }
    }
}

impl From<cloth::OutputError> for JobError {
    fn from(e: cloth::OutputError) -> Self {
        JobError::Output(e.to_string())
    }
}

impl From<InputError> for JobError {
    fn from(e: InputError) -> Self {
        JobError::Input(e)
    }
}
