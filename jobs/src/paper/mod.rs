//! The experiments of Tan et al.'s section 5, reproduced: the one job
//! behind `symlab paper`.
//!
//! 1. The oscillator `H = ½(p² + k²q²)` (their figures 2–4): six schemes at
//!    each step size against the analytic solution
//!    ([`compare::paper_oscillator`] runs them; this job writes the CSV of
//!    errors, the CSV of every step and the plots).
//! 2. The cloth comparison of their figure 5 (explicit Euler against
//!    symplectic Euler on the undamped scene at 16.7 ms frames, with
//!    Störmer–Verlet, implicit Euler and Gauss–Legendre 2; the runs are
//!    [`cloth::study::figure5`](::cloth::study::figure5)'s): a CSV, a plot and renderings.
//! 3. `report.md`: what the paper claims, what this run measured, where
//!    they differ. Every number in it is computed in the run.
//!
//! A [`Request`] is checked by the library; a refusal is a [`PaperError`]
//! whose [`Field`] each front end names in its own words (the command
//! line's flags in `Display`, Python's keywords in
//! [`PaperError::keyword_message`]). [`run`] writes the files and returns
//! what it wrote and the summary to show, as data: the library prints
//! nothing, and reports its stages to an [`Observer`].
//!
//! ```
//! use jobs::paper::{Field, Quiet, Request, run};
//!
//! let out = std::env::temp_dir().join(format!("jobs-paper-doc-{}", std::process::id()));
//! let request = Request { out: out.clone(), cloth_frames: 0, ..Request::default() };
//! let done = run(&request, &mut Quiet)?;
//! assert_eq!(done.files.first().map(String::as_str), Some("oscillator_errors.csv"));
//! assert!(done.report.exists() && done.cloth.is_none());
//! assert!(done.summary.oscillator.lines.iter().any(|l| l.contains("Gauss–Legendre 2")));
//!
//! // A refused field is named, for each front end in its own words.
//! let mut bad = request.clone();
//! bad.oscillator.step_sizes = vec![0.1, 0.1];
//! let err = run(&bad, &mut Quiet).unwrap_err();
//! assert_eq!(err.field(), Some(Field::StepSizes));
//! assert_eq!(err.to_string(), "--h: step size 0.1 is given twice");
//! assert_eq!(err.keyword_message(), "step_sizes: step size 0.1 is given twice");
//! # std::fs::remove_dir_all(&out).ok();
//! # Ok::<(), jobs::paper::PaperError>(())
//! ```

mod checkpoint;
mod cloth;
mod figures;
mod report;
mod request;

use std::path::{Path, PathBuf};

use ::cloth::study::figure5::{ClothExperiment, RUNS};
use compare::paper_oscillator::{Experiment, experiment};

pub use request::{DEFAULT_CLOTH_FRAMES, Field, PaperError, Request};

/// A part of the reproduction, as an [`Observer`] hears it begin.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// The oscillator's runs, tables and plots.
    Oscillator,
    /// The cloth comparison, `frames` frames per run (the longest part:
    /// about 30 s in release at the default frames).
    Cloth { frames: usize },
    /// `report.md`.
    Report,
}

/// What a front end hears of a reproduction while it goes. Every method
/// has a default that does nothing.
pub trait Observer {
    /// A part begins (the cloth part is skipped when the request asks for
    /// no frames).
    fn stage(&mut self, _stage: Stage) {}
    /// `done` of the `total` cloth runs are finished (and kept in the
    /// checkpoint).
    fn cloth_run(&mut self, _done: usize, _total: usize) {}
    /// Asked after each cloth run: whether the run should stop there (a
    /// front end's signal); it then ends with [`PaperError::Stopped`] and
    /// its checkpoint.
    fn stop(&mut self) -> bool {
        false
    }
}

/// An observer that hears nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Quiet;
impl Observer for Quiet {}

/// A summary's part: a heading and its lines, for a terminal.
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    pub heading: String,
    pub lines: Vec<String>,
}

/// What a front end shows when the reproduction is done.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// The set-up, then one line per (step size, method): the largest
    /// errors over the run.
    pub oscillator: Section,
    /// One line per cloth run: its step and how it ended; no lines when
    /// the comparison was skipped.
    pub cloth: Section,
}

/// A finished reproduction: what was written and what it measured.
#[derive(Clone, Debug)]
pub struct Reproduced {
    /// The directory written into.
    pub dir: PathBuf,
    /// The names of the files written, in the report's order (`report.md`
    /// last).
    pub files: Vec<String>,
    /// `report.md`, the file to read first.
    pub report: PathBuf,
    /// The oscillator's runs.
    pub oscillator: Experiment,
    /// The cloth comparison's runs; `None` when it was skipped.
    pub cloth: Option<ClothExperiment>,
    pub summary: Summary,
}

/// Check the request, run the experiments and write the tables, plots and
/// report into `request.out`. After each cloth run a checkpoint
/// ([`integrator_core::checkpoint::FILE_NAME`] in that folder) keeps the
/// request and the runs so far; the observer may stop the run there, and
/// [`resume`] goes on from it to the same files (apart from the wall times
/// in them). A finished run removes its checkpoint.
pub fn run(request: &Request, observer: &mut dyn Observer) -> Result<Reproduced, PaperError> {
    run_from(request, observer, Vec::new())
}

/// Continue the paper run whose checkpoint `path` (read and checked:
/// [`integrator_core::checkpoint::read_any`]) holds `payload`, writing
/// into `dir`, the folder it was found in.
pub fn resume(
    dir: &Path,
    path: &Path,
    payload: &[u8],
    observer: &mut dyn Observer,
) -> Result<Reproduced, PaperError> {
    let (mut request, done) = checkpoint::decode(path, payload)?;
    request.out = dir.to_path_buf();
    run_from(&request, observer, done)
}

fn run_from(
    request: &Request,
    observer: &mut dyn Observer,
    done: Vec<::cloth::study::figure5::ClothRun>,
) -> Result<Reproduced, PaperError> {
    request.check()?;
    let dir = &request.out;
    std::fs::create_dir_all(dir).map_err(|source| PaperError::OutDir {
        path: dir.clone(),
        source,
    })?;

    observer.stage(Stage::Oscillator);
    let exp = experiment(&request.oscillator)?;
    figures::write_oscillator(&exp, dir)?;

    if request.cloth_frames > 0 {
        observer.stage(Stage::Cloth {
            frames: request.cloth_frames,
        });
    }
    let checkpoint = dir.join(integrator_core::checkpoint::FILE_NAME);
    let mut failed = None;
    let section = cloth::section(dir, request.cloth_frames, done, |runs| {
        if let Err(e) = checkpoint::write(&checkpoint, request, runs) {
            failed = Some(e);
            return false;
        }
        observer.cloth_run(runs.len(), RUNS);
        !observer.stop()
    })?;
    if let Some(e) = failed {
        return Err(e.into());
    }
    let Some(cloth) = section else {
        let done = checkpoint::runs_in(&checkpoint)?;
        return Err(PaperError::Stopped {
            checkpoint,
            done,
            total: RUNS,
        });
    };
    integrator_core::checkpoint::remove(&checkpoint)?;

    observer.stage(Stage::Report);
    let mut files = figures::oscillator_files(&request.oscillator);
    files.extend(cloth.files.iter().cloned());
    files.push("report.md".into());
    let report = dir.join("report.md");
    write(&report, &report::markdown(&exp, &cloth.markdown, &files))?;

    let c = &request.oscillator;
    let summary = Summary {
        oscillator: Section {
            heading: format!(
                "Oscillator H = ½(p² + k²q²), k = {}, q₀ = {}, p₀ = {}, {} steps: maximum errors over the run",
                c.k, c.q0, c.p0, c.steps
            ),
            lines: lines(&report::text_table(&exp)),
        },
        cloth: Section {
            heading: "Cloth comparison (figure 5), paper scene at 60 Hz frames:".into(),
            lines: cloth
                .experiment
                .as_ref()
                .map_or_else(Vec::new, |e| lines(&cloth::terminal(e))),
        },
    };
    Ok(Reproduced {
        dir: dir.clone(),
        files,
        report,
        oscillator: exp,
        cloth: cloth.experiment,
        summary,
    })
}

/// The lines of a text that ends each with a newline.
fn lines(text: &str) -> Vec<String> {
    text.lines().map(str::to_string).collect()
}

/// Write a file, naming it on failure.
fn write(path: &Path, text: &str) -> Result<(), PaperError> {
    std::fs::write(path, text).map_err(|source| PaperError::Write {
        path: path.to_path_buf(),
        source,
    })
}
