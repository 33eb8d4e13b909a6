//! `symlab.cloth.run` and `symlab.cloth.resume`: the cloth job
//! ([`jobs::cloth`]) that `symlab cloth` runs — the same plan, energy
//! guard, files and summary — with the positions of every particle at each
//! frame returned as NumPy arrays.
use std::path::PathBuf;

use jobs::cloth::{Job, JobError, Observer, Outcome, Request, SceneSource, Stop};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{IntegrationError, ProblemError};

/// A job's error as Python's exception: a refused argument is a
/// `ValueError` naming the keyword, a scene that cannot be read or
/// simulated a `ProblemError`, an output that cannot be written an
/// `OSError`, a failed run an `IntegrationError`.
fn job_error(e: JobError) -> PyErr {
    let msg = e.keyword_message();
    match e {
        JobError::Input(_) => PyValueError::new_err(msg),
        JobError::Scene(_) => ProblemError::new_err(msg),
        JobError::Io { .. } | JobError::Output(_) | JobError::Checkpoint(_) => {
            PyOSError::new_err(msg)
        }
        JobError::Run(_) => IntegrationError::new_err(msg),
    }
}

/// What Python keeps of each frame, and Ctrl-C (checked between frames
/// with the GIL taken back for a moment) as a stop with a checkpoint.
#[derive(Default)]
struct Keep {
    positions: Vec<f64>,
    particles: usize,
    time: Vec<f64>,
    energy: Vec<f64>,
    strain: Vec<f64>,
}

impl Observer for Keep {
    fn frame(&mut self, frame: &cloth::Frame<'_>) {
        let ps = frame.positions();
        self.particles = ps.len();
        for p in ps {
            self.positions.extend_from_slice(&[p.x, p.y, p.z]);
        }
        self.time.push(frame.stats.time);
        self.energy.push(frame.stats.energy.total());
        self.strain.push(frame.stats.max_strain);
    }
    fn stop_requested(&mut self) -> Option<Stop> {
        Python::attach(|py| py.check_signals().err()).map(|_| Stop {
            reason: "KeyboardInterrupt".into(),
        })
    }
}

/// Run `job` with the GIL released, and turn its outcome into the dict.
fn run_job<'py>(py: Python<'py>, job: Job) -> PyResult<Bound<'py, PyDict>> {
    let dir = job.dir().to_path_buf();
    let (keep, outcome) = py.detach(|| {
        let mut keep = Keep::default();
        let outcome = job.run(&mut keep);
        (keep, outcome)
    });
    let (summary, report, notes) = match outcome.map_err(job_error)? {
        Outcome::Finished {
            summary,
            report,
            notes,
        } => (summary, report, notes),
        Outcome::BlownUp { error, lines, .. } => {
            return Err(IntegrationError::new_err(format!(
                "{error}\n{}",
                lines.join("\n")
            )));
        }
        Outcome::Stopped { text, .. } => return Err(PyKeyboardInterrupt::new_err(text)),
    };
    // The frames this call ran (a resumed run's arrays start after the
    // frame it resumed from).
    let n = keep.time.len();
    let d = PyDict::new(py);
    d.set_item(
        "positions",
        PyArray1::from_vec(py, keep.positions).reshape([n, keep.particles, 3])?,
    )?;
    d.set_item("time", PyArray1::from_vec(py, keep.time))?;
    d.set_item("energy", PyArray1::from_vec(py, keep.energy))?;
    d.set_item("max_strain", PyArray1::from_vec(py, keep.strain))?;
    d.set_item("method", report.method)?;
    d.set_item("h", report.h)?;
    d.set_item("steps", report.steps)?;
    d.set_item("stepping_seconds", report.stepping_seconds)?;
    d.set_item("summary", summary)?;
    d.set_item("notes", notes)?;
    d.set_item("dir", dir)?;
    Ok(d)
}

/// Run `scene` (a path to a scene file, or its TOML text when it contains
/// a newline) as `symlab cloth` does; see `symlab.cloth.run`.
#[pyfunction]
#[pyo3(signature = (scene, method = None, frames = None, substeps = None, dt = None, grid = None, out = None, obj_every = 10, render = None, tolerance = None, solver = None, checkpoint_every = None))]
#[allow(clippy::too_many_arguments)] // the job's request, one keyword each
pub fn cloth_run<'py>(
    py: Python<'py>,
    scene: String,
    method: Option<String>,
    frames: Option<usize>,
    substeps: Option<usize>,
    dt: Option<f64>,
    grid: Option<String>,
    out: Option<PathBuf>,
    obj_every: usize,
    render: Option<String>,
    tolerance: Option<f64>,
    solver: Option<String>,
    checkpoint_every: Option<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let source = if scene.contains('\n') {
        SceneSource::Text {
            name: "<scene>".into(),
            text: scene,
        }
    } else {
        SceneSource::File(PathBuf::from(scene))
    };
    let checkpoint_every = checkpoint_every
        .map(|t| {
            integrator_core::checkpoint::parse_every(&t)
                .map_err(|e| PyValueError::new_err(format!("checkpoint_every: {e}")))
        })
        .transpose()?;
    let request = Request {
        method,
        frames,
        substeps,
        dt,
        grid,
        out,
        obj_every,
        render,
        tolerance,
        solver,
        checkpoint_every,
        ..Request::new(source)
    };
    let job = py
        .detach(|| jobs::cloth::plan(&request))
        .map_err(job_error)?;
    run_job(py, job)
}

/// Continue the interrupted cloth run whose output folder is `dir` (from
/// its checkpoint), as `symlab resume DIR` does.
#[pyfunction]
pub fn cloth_resume<'py>(py: Python<'py>, dir: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    use integrator_core::checkpoint::{FILE_NAME, Kind, read};
    let path = dir.join(FILE_NAME);
    let payload = read(&path, Kind::Cloth).map_err(|e| PyOSError::new_err(e.to_string()))?;
    let job = py
        .detach(|| jobs::cloth::resume(&dir, &path, &payload))
        .map_err(job_error)?;
    run_job(py, job)
}
