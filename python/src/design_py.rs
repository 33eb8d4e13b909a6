//! `symlab.design`: a family of methods (a file, or its TOML text) through
//! the design library's pipeline (`design::design`), as `symlab design`
//! runs it; the found tables returned as Python data and, with `out`,
//! written with the report as the command line writes them.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::errors::DesignError;

/// The family's error as `DesignError`, with the command line's message
/// (which names the file and the field).
fn design_error(e: impl std::fmt::Display) -> PyErr {
    DesignError::new_err(e.to_string())
}

/// The claims of an emitted table (its `claims` field), as written.
fn claims(text: &str) -> Vec<String> {
    text.parse::<toml::Table>()
        .ok()
        .and_then(|t| t.get("claims").cloned())
        .and_then(|c| match c {
            toml::Value::Array(items) => Some(
                items
                    .into_iter()
                    .filter_map(|v| v.as_str().map(str::to_string))
                    .collect(),
            ),
            _ => None,
        })
        .unwrap_or_default()
}

/// Run the family `family` (a path, or the TOML text itself when it has a
/// line break) with `seed` and `starts` overriding the file's; write the
/// tables and report.md into `out` when given. Returns a dict: the search
/// (`starts_run`, `distinct`, `capped`, `seconds`), the system (`unknowns`,
/// `conditions`) and `designs`, best first.
#[pyfunction]
#[pyo3(signature = (family, *, seed = None, starts = None, out = None))]
pub fn design<'py>(
    py: Python<'py>,
    family: String,
    seed: Option<u64>,
    starts: Option<usize>,
    out: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let (origin, parsed) = if family.contains('\n') {
        let origin = "<family>".to_string();
        let parsed = ::design::parse_family(&origin, &family);
        (origin, parsed)
    } else {
        let path = PathBuf::from(&family);
        (path.display().to_string(), ::design::load_family(&path))
    };
    let mut fam = parsed.map_err(design_error)?;
    if let Some(seed) = seed {
        fam.seed = seed;
    }
    if let Some(starts) = starts {
        fam.starts = starts;
    }
    fam.validate(&origin).map_err(design_error)?;
    let (outcome, written) = py
        .detach(|| {
            let outcome =
                ::design::design(&fam, &origin, &mut |_| {}).map_err(|e| e.to_string())?;
            let written = match &out {
                Some(dir) => outcome
                    .write(dir)
                    .map_err(|e| format!("out: writing into {}: {e}", dir.display()))?,
                None => Vec::new(),
            };
            Ok::<_, String>((outcome, written))
        })
        .map_err(design_error)?;

    let d = PyDict::new(py);
    let s = &outcome.search;
    d.set_item("family", &outcome.family.name)?;
    d.set_item("order", outcome.family.order_text())?;
    d.set_item("unknowns", &outcome.system.names)?;
    let conditions: Vec<&str> = outcome
        .system
        .conditions
        .iter()
        .map(|c| c.word.as_str())
        .collect();
    d.set_item("conditions", conditions)?;
    d.set_item("starts_run", s.starts_run)?;
    d.set_item("distinct", s.solutions.len())?;
    d.set_item("capped", s.capped)?;
    d.set_item("seconds", s.elapsed.as_secs_f64())?;
    let designs = PyList::empty(py);
    for (i, found) in outcome.designs.iter().enumerate() {
        let e = PyDict::new(py);
        e.set_item("rank", i + 1)?;
        e.set_item("effective_error", found.solution.effective_error)?;
        e.set_item("objective", found.solution.objective)?;
        e.set_item("hits", found.solution.hits)?;
        let x = PyDict::new(py);
        for (name, v) in outcome.system.names.iter().zip(&found.solution.x) {
            x.set_item(name, v)?;
        }
        e.set_item("x", x)?;
        let (proof, exact, radius) = match (&found.exact, &found.certificate) {
            (Some(ex), _) => (
                "exact",
                Some(ex.radicals.clone().unwrap_or_else(|| ex.root.clone())),
                None,
            ),
            (_, Some(Ok(c))) => ("certified", None, Some(c.radius.to_string())),
            (_, Some(Err(_))) => ("not certified", None, None),
            (None, None) => ("not polished", None, None),
        };
        e.set_item("proof", proof)?;
        e.set_item("exact", exact)?;
        e.set_item("radius", radius)?;
        match &found.table {
            Some((name, text)) => {
                e.set_item("name", name)?;
                e.set_item("claims", claims(text))?;
                e.set_item("toml", text)?;
            }
            None => {
                e.set_item("name", py.None())?;
                e.set_item("claims", PyList::empty(py))?;
                e.set_item("toml", py.None())?;
            }
        }
        designs.append(e)?;
    }
    d.set_item("designs", designs)?;
    let written: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
    d.set_item("written", written)?;
    Ok(d)
}
