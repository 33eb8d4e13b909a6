//! A cloth scene run into files: `energy.csv`, the energy plot, OBJ frames,
//! PNG renderings and a one-screen summary, with the energy guard, the
//! blow-up replay and checkpoints — the one pipeline behind `symlab cloth`
//! and `symlab.cloth.run`.
//!
//! The phases are named, as in the cloth crate:
//! 1. [`Request`]: what the user asked, as they wrote it (a scene file or
//!    text, the method id, frames, substeps or a step size, the output
//!    folder, …). Every field is optional where the scene has a default.
//! 2. [`plan`]: the request checked and resolved against the scene (the
//!    method applies, the schedule fits the run limits, the output folder
//!    can be written), the model built. An error is an [`InputError`]
//!    whose [`Origin`] names the request's field — shown by the command
//!    line as its flag (`--dt 1e-3: …`) and by Python as its keyword — or
//!    the scene file's field (`scene.toml: simulation.method: …`).
//! 3. [`Job::run`]: the run, progress and stop requests through an
//!    [`Observer`]; it returns an [`Outcome`] (finished with its summary,
//!    blown up with what was kept, or stopped with its checkpoint). The
//!    library prints nothing: the front ends print the outcome's text.
//!
//! A run stopped by its observer (a signal, in the command line) writes a
//! checkpoint from which [`resume`] continues it to the same bits and the
//! same files as a run never stopped; the checkpoint holds the request and
//! the scene's text, so the run goes on even if the scene file changed.
//!
//! ```
//! use jobs::cloth::{Request, SceneSource, Outcome, Quiet, plan};
//!
//! let scene = "[cloth]\nwidth = 1.0\nheight = 1.0\nnx = 4\nny = 4\n\
//!              [material]\ndensity = 0.1\nstretch = 10.0\n\
//!              [pins]\nedges = [\"top\"]\n\
//!              [simulation]\nsubsteps = 20\nframes = 3\nmethod = \"stormer-verlet\"\n";
//! let out = std::env::temp_dir().join(format!("jobs-cloth-doc-{}", std::process::id()));
//! let request = Request {
//!     out: Some(out.clone()),
//!     render: Some("none".into()),
//!     ..Request::new(SceneSource::Text { name: "sheet.toml".into(), text: scene.into() })
//! };
//! let outcome = plan(&request)?.run(&mut Quiet)?;
//! let Outcome::Finished { summary, .. } = outcome else { panic!("not finished") };
//! assert!(summary.contains("stormer-verlet"));
//! assert!(out.join("energy.csv").exists());
//!
//! // A wrong field is named, for each front end in its own words.
//! let bad = Request { frames: Some(2_000_000), ..request };
//! let Err(err) = plan(&bad) else { panic!("two million frames were accepted") };
//! assert!(err.to_string().starts_with("--frames"), "{err}");
//! assert!(err.keyword_message().starts_with("frames"), "{err}");
//! # std::fs::remove_dir_all(&out).ok();
//! # Ok::<(), jobs::cloth::JobError>(())
//! ```

mod checkpoint;
mod energy;
mod plan;
mod render;
mod run;
pub mod stability;
mod summary;

use std::path::PathBuf;

use thiserror::Error;

pub use checkpoint::{interval, resume};
pub use integrator_core::checkpoint::Every;
pub use plan::{Job, plan};
pub use summary::facts;

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
/// (or the documented default); [`plan`] checks every field.
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
/// blew up is not an error but an [`Outcome`]: it keeps what was good.
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

/// Why the observer asked the run to stop (a signal's name, in the
/// command line).
#[derive(Clone, Debug)]
pub struct Stop {
    pub reason: String,
}

/// What a front end hears of a run while it goes: progress, and its one
/// question, whether to stop (between frames). Every method has a default.
pub trait Observer {
    /// The run starts: `frames` in all, `done` of them already (a resumed
    /// run).
    fn start(&mut self, _frames: usize, _done: usize) {}
    /// Frame `frame` (at simulated `time`) is done; `frame` 0 is the
    /// initial state. Python keeps the positions here.
    fn frame(&mut self, _frame: &cloth::Frame<'_>) {}
    /// Asked after every frame: `Some` stops the run, with a checkpoint.
    fn stop_requested(&mut self) -> Option<Stop> {
        None
    }
    /// The run loop ended (before the output of the outcome is written).
    fn finish(&mut self) {}
}

/// An observer that hears nothing and never stops the run.
pub struct Quiet;
impl Observer for Quiet {}

/// How a run ended. Each carries the text the front ends print, and the
/// notes (a picture simplified, the checkpoints written) they print as
/// notes.
#[derive(Debug)]
pub enum Outcome {
    /// The run reached its last frame: `summary` is the one-screen summary.
    Finished {
        summary: String,
        report: cloth::RunReport,
        notes: Vec<String>,
    },
    /// The run blew up (a non-finite state, a failed solve, the energy
    /// guard): `lines` say what happened, how the energy grew and what was
    /// kept up to the last good frame.
    BlownUp {
        error: String,
        lines: Vec<String>,
        notes: Vec<String>,
    },
    /// The observer stopped the run: `text` says where and how to go on
    /// (`checkpoint`, when one was written at the frame it stopped).
    Stopped {
        text: String,
        stop: Stop,
        checkpoint: Option<PathBuf>,
        notes: Vec<String>,
    },
}

impl Outcome {
    /// The notes of any outcome.
    pub fn notes(&self) -> &[String] {
        match self {
            Outcome::Finished { notes, .. }
            | Outcome::BlownUp { notes, .. }
            | Outcome::Stopped { notes, .. } => notes,
        }
    }
}
