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
/// `conditions`) and `designs`, best first; for a processed kernel
/// (`processed = true`) each design's `processor` is a dict with its
/// coefficients `z` and their `names` (`z1`, … for a composition kernel;
/// the drifts `u1`, … then the kicks `v1`, … for a drift–kick kernel), the
/// `claims` tableau decided on the processed table and
/// the `objective` it leaves, or with the `error` that stopped it (`None`
/// for other families).
#[pyfunction]
#[pyo3(signature = (family, *, seed = None, starts = None, out = None))]
pub fn design<'py>(
    py: Python<'py>,
    family: String,
    seed: Option<u64>,
    starts: Option<usize>,
    out: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let (origin, text) = if family.contains('\n') {
        ("<family>".to_string(), family.clone())
    } else {
        let path = PathBuf::from(&family);
        let text = ::design::read_family_text(&path).map_err(design_error)?;
        (path.display().to_string(), text)
    };
    if ::design::processed::is_corrector_family(&text) {
        return corrector(py, &origin, &text, seed, starts, out);
    }
    let parsed = ::design::parse_family(&origin, &text);
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
        e.set_item(
            "stability_per_stage",
            found.stability_per_stage(outcome.family.stages),
        )?;
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
        match &found.processor {
            None => e.set_item("processor", py.None())?,
            Some(Ok(p)) => {
                let pd = PyDict::new(py);
                let z: Vec<f64> = p.z.iter().map(::design::poly::to_f64).collect();
                pd.set_item("z", z)?;
                pd.set_item("names", &p.system.names)?;
                pd.set_item("claims", &p.claims)?;
                pd.set_item("objective", p.objective)?;
                e.set_item("processor", pd)?;
            }
            Some(Err(why)) => {
                let pd = PyDict::new(py);
                pd.set_item("error", why)?;
                e.set_item("processor", pd)?;
            }
        }
        designs.append(e)?;
    }
    d.set_item("designs", designs)?;
    let written: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
    d.set_item("written", written)?;
    Ok(d)
}

/// A second-corrector family (`form = "second-corrector"`,
/// `design::processed`), as `symlab design` runs it: one unknown solved
/// exactly, no search, so `seed` and `starts` are refused. Returns a dict:
/// `family`, `form`, `kernel`, `c_squared` and `c` (exact, as text),
/// `c_value` (a float), the effective generalised orders `orders_before` and
/// `orders_after`, and `designs` with the one emitted table (`name`,
/// `claims`, `toml`, `proof` = "exact").
fn corrector<'py>(
    py: Python<'py>,
    origin: &str,
    text: &str,
    seed: Option<u64>,
    starts: Option<usize>,
    out: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    for (name, given) in [("seed", seed.is_some()), ("starts", starts.is_some())] {
        if given {
            return Err(design_error(format!(
                "{name}: {origin} is a {} family, solved exactly with no random starts",
                ::design::processed::FORM
            )));
        }
    }
    let fam = ::design::processed::parse_corrector_family(origin, text).map_err(design_error)?;
    let (d, written) = py
        .detach(|| {
            let d =
                ::design::processed::design_corrector(&fam, origin).map_err(|e| e.to_string())?;
            let written = match &out {
                Some(dir) => d
                    .write(dir)
                    .map_err(|e| format!("out: writing into {}: {e}", dir.display()))?,
                None => Vec::new(),
            };
            Ok::<_, String>((d, written))
        })
        .map_err(design_error)?;
    let r = PyDict::new(py);
    r.set_item("family", &d.family.name)?;
    r.set_item("form", ::design::processed::FORM)?;
    r.set_item("kernel", &d.family.kernel)?;
    r.set_item("c_squared", d.c_squared.to_string())?;
    r.set_item("c", d.c.to_string())?;
    r.set_item("c_value", d.c.to_f64())?;
    r.set_item("orders_before", &d.orders_before)?;
    r.set_item("orders_after", &d.orders_after)?;
    let e = PyDict::new(py);
    e.set_item("rank", 1)?;
    e.set_item("proof", "exact")?;
    e.set_item("exact", d.c.to_string())?;
    e.set_item("name", &d.table.0)?;
    e.set_item("claims", claims(&d.table.1))?;
    e.set_item("toml", &d.table.1)?;
    let designs = PyList::empty(py);
    designs.append(e)?;
    r.set_item("designs", designs)?;
    let written: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
    r.set_item("written", written)?;
    Ok(r)
}
