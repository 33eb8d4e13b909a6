//! `symlab.cloth.run`: a cloth scene stepped by the `cloth` crate, the
//! positions of every particle at each frame returned as NumPy arrays.
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{IntegrationError, ProblemError};

/// Run `scene` (a path to a scene file, or its TOML text when it contains
/// a newline) with `method` (default: the scene's) for `frames` frames
/// (default: the scene's). Returns a dict: `positions` (shape
/// `(frames + 1, particles, 3)`, pinned particles included, particle id
/// `j·nx + i`), `time`, `energy` (total, per frame), `max_strain`, `method`,
/// `h`, `steps` and `stepping_seconds`. The GIL is released while it runs.
#[pyfunction]
#[pyo3(signature = (scene, method = None, frames = None, substeps = None))]
pub fn cloth_run<'py>(
    py: Python<'py>,
    scene: String,
    method: Option<String>,
    frames: Option<usize>,
    substeps: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let sc = if scene.contains('\n') {
        cloth::Scene::from_toml(&scene, "<scene>")
    } else {
        cloth::Scene::load(&scene)
    }
    .map_err(|e| ProblemError::new_err(format!("scene: {e}")))?;
    let method_id = method.unwrap_or_else(|| sc.simulation.method.clone());
    let m = cloth::Method::parse(&method_id)
        .map_err(|e| PyValueError::new_err(format!("method: {e}")))?;
    let mut options = cloth::RunOptions::from_scene(&sc);
    if let Some(f) = frames {
        options.frames = f;
    }
    if let Some(s) = substeps {
        options.substeps = s;
    }
    options
        .check()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let settings = cloth::RunSettings::new(options);
    struct Out {
        positions: Vec<f64>,
        particles: usize,
        time: Vec<f64>,
        energy: Vec<f64>,
        strain: Vec<f64>,
        report: cloth::RunReport,
    }
    let out = py
        .detach(|| -> Result<Out, String> {
            let mut sim = cloth::Simulation::new(&sc).map_err(|e| format!("scene: {e}"))?;
            let mut positions = Vec::new();
            let mut particles = 0;
            let mut time = Vec::new();
            let mut energy = Vec::new();
            let mut strain = Vec::new();
            let report = sim
                .run(&m, &settings, |frame| {
                    let ps = frame.positions();
                    particles = ps.len();
                    for p in ps {
                        positions.extend_from_slice(&[p.x, p.y, p.z]);
                    }
                    time.push(frame.stats.time);
                    energy.push(frame.stats.energy.total());
                    strain.push(frame.stats.max_strain);
                    Ok(())
                })
                .map_err(|e| e.to_string())?;
            Ok(Out {
                positions,
                particles,
                time,
                energy,
                strain,
                report,
            })
        })
        .map_err(IntegrationError::new_err)?;
    let n = out.time.len();
    let d = PyDict::new(py);
    d.set_item(
        "positions",
        PyArray1::from_vec(py, out.positions).reshape([n, out.particles, 3])?,
    )?;
    d.set_item("time", PyArray1::from_vec(py, out.time))?;
    d.set_item("energy", PyArray1::from_vec(py, out.energy))?;
    d.set_item("max_strain", PyArray1::from_vec(py, out.strain))?;
    d.set_item("method", out.report.method)?;
    d.set_item("h", out.report.h)?;
    d.set_item("steps", out.report.steps)?;
    d.set_item("stepping_seconds", out.report.stepping_seconds)?;
    Ok(d)
}
