//! What a front end hears of a running job ([`Observer`]) and how the job
//! ended ([`Outcome`]).

use std::path::PathBuf;

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
