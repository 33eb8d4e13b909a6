//! `symlab.Table` and `symlab.check`: a table read by `tableau`'s own
//! parser (whatever the Python form it came in, it is turned into the
//! table-file text first, so every message names the field as `symlab
//! check` does) and its exact analysis, returned as Python values.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde_json::{Value, json};
use tableau::algebraic::file::{AlgFile, Loaded};
use tableau::algebraic::generated::Generated;
use tableau::analysis::Analysis;
use tableau::catalogue;
use tableau::file::TableFile;

use crate::cli_check;
use crate::convert::json_to_py;
use crate::errors::{ClaimError, TableError, table_error};

/// The stack of the thread that parses and analyses a table: as `symlab
/// check`'s (its recursion is bounded by the nesting of an entry; 16 MiB is
/// margin), and its own thread turns a panic into an exception.
const ANALYSIS_STACK_BYTES: usize = 16 << 20;

/// The largest table file or text read (as `compare --table`).
const MAX_TEXT_BYTES: u64 = 1 << 20;

/// What a table holds, as read: one of the three kinds of table file.
#[derive(Clone, Debug)]
pub enum Kind {
    Classic(Box<TableFile>),
    Generated(Box<Generated>),
    Algebraic(Box<AlgFile>),
}

impl From<Loaded> for Kind {
    fn from(l: Loaded) -> Self {
        match l {
            Loaded::Classic(t) => Kind::Classic(t),
            Loaded::Generated(g) => Kind::Generated(g),
            Loaded::Algebraic(a) => Kind::Algebraic(a),
        }
    }
}

/// A Butcher table, a partitioned pair, a drift–kick sequence or a
/// composition, read exactly (entries are exact numbers, never floats).
///
/// Build one with ``Table(a=..., b=..., ...)`` (the fields of a table file,
/// entries as strings such as ``"1/4 - sqrt(3)/6"``), ``Table.from_toml``,
/// ``Table.from_file``, ``Table.builtin`` (a catalogue id such as
/// ``"gauss2"``) or ``Table.generate`` (``"gauss(8)"``).
///
/// >>> import symlab
/// >>> t = symlab.Table(name="midpoint", a=[["1/2"]], b=["1"], claims=["symplectic", "order = 2"])
/// >>> symlab.check(t)["symplectic"]
/// True
#[pyclass(module = "symlab", frozen)]
pub struct Table {
    /// How messages name the table: the file path, `builtin:ID`, `<string>`.
    pub origin: String,
    /// The method id in comparisons (a file's stem, a builtin's id).
    pub id: String,
    /// The file it was read from, if any.
    pub path: Option<PathBuf>,
    /// Behind a mutex: a root table caches its roots' refinements in
    /// cells, and a Python object may be shared between threads.
    pub kind: Arc<Mutex<Kind>>,
}

/// Run `f` on a thread with a large stack, the GIL released; a panic is a
/// `TableError` naming `origin`.
pub fn on_analysis_thread<T: Send>(
    py: Python<'_>,
    origin: &str,
    f: impl FnOnce() -> Result<T, String> + Send,
) -> PyResult<T> {
    let out = py.detach(|| {
        std::thread::scope(|scope| {
            let worker = std::thread::Builder::new()
                .name("symlab-check".into())
                .stack_size(ANALYSIS_STACK_BYTES)
                .spawn_scoped(scope, f)
                .map_err(|e| format!("{origin}: cannot start the analysis thread: {e}"))?;
            worker.join().unwrap_or_else(|panic| {
                let what = panic
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| panic.downcast_ref::<String>().cloned())
                    .unwrap_or_default();
                Err(format!(
                    "internal error: the analysis panicked ({what}); please report it with the table"
                ))
            })
        })
    });
    out.map_err(table_error)
}

/// Parse table-file text (any of the three kinds), checking the shape of
/// an ordinary table as `symlab check` does before its analysis.
fn parse_text(origin: &str, text: &str) -> Result<Kind, String> {
    let loaded = tableau::algebraic::file::parse(origin, text).map_err(|e| e.to_string())?;
    let kind = Kind::from(loaded);
    if let Kind::Classic(tf) = &kind {
        tf.table
            .check_shape()
            .map_err(|e| format!("{origin}: field {e}"))?;
    }
    Ok(kind)
}

/// `symlab check --builtin ID`'s reading of `id`: the catalogue's table,
/// else a generated one; `gauss(3)` (with parentheses) always generates.
/// Messages as the command line's.
fn builtin_kind(id: &str) -> Result<Kind, String> {
    let generator_syntax = id.contains('(');
    match catalogue::find(id) {
        Some(entry) if !generator_syntax => entry
            .load()
            .map(|tf| Kind::Classic(Box::new(tf)))
            .map_err(|e| e.to_string()),
        _ => match Generated::new(id) {
            Ok(g) => Ok(Kind::Generated(Box::new(g))),
            Err(gen_err) if generator_syntax => Err(format!("builtin:{id}: {gen_err}")),
            Err(gen_err) => match catalogue::load(id) {
                Err(e) if gen_err.contains("unknown generator") => Err(format!(
                    "{e} (or a generated table: gauss8, radau2a5, lobatto3a3b4, …)"
                )),
                _ => Err(format!("builtin:{id}: {gen_err}")),
            },
        },
    }
}

/// A Python value as TOML: strings, integers, booleans, floats (which the
/// table parser refuses, naming the field, as it refuses them in a file),
/// lists and dicts. Anything else is a `TypeError` naming the field.
fn toml_value(v: &Bound<'_, PyAny>, field: &str, out: &mut String) -> PyResult<()> {
    if let Ok(s) = v.cast::<PyString>() {
        let s = s.to_cow()?;
        out.push('"');
        for ch in s.chars() {
            match ch {
                '"' => out.push_str("\\\""),
                '\\' => out.push_str("\\\\"),
                '\n' => out.push_str("\\n"),
                '\t' => out.push_str("\\t"),
                '\r' => out.push_str("\\r"),
                c if (c as u32) < 0x20 || c as u32 == 0x7f => {
                    out.push_str(&format!("\\u{:04X}", c as u32))
                }
                c => out.push(c),
            }
        }
        out.push('"');
    } else if v.is_instance_of::<PyBool>() {
        out.push_str(if v.extract::<bool>()? {
            "true"
        } else {
            "false"
        });
    } else if v.is_instance_of::<PyInt>() {
        // Arbitrary size: the parser applies its own limit on digits.
        out.push_str(&v.str()?.to_cow()?);
    } else if v.is_instance_of::<PyFloat>() {
        let x: f64 = v.extract()?;
        if x.is_finite() {
            // Rust's shortest round-trip form, with a point so TOML reads a float.
            let s = format!("{x:?}");
            out.push_str(&s);
        } else {
            return Err(PyValueError::new_err(format!(
                "field {field}: {x} is not a number a table can hold; write entries as exact strings (\"1/3\", \"sqrt(3)/6\")"
            )));
        }
    } else if let Ok(d) = v.cast::<PyDict>() {
        out.push('{');
        for (i, (k, item)) in d.iter().enumerate() {
            let key: String = k.extract().map_err(|_| {
                PyTypeError::new_err(format!("field {field}: the keys must be strings"))
            })?;
            if i > 0 {
                out.push_str(", ");
            }
            toml_value(&PyString::new(v.py(), &key), field, out)?;
            out.push_str(" = ");
            toml_value(&item, &format!("{field}.{key}"), out)?;
        }
        out.push('}');
    } else if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        out.push('[');
        for (i, item) in v.try_iter()?.enumerate() {
            if i > 0 {
                out.push_str(", ");
            }
            toml_value(&item?, &format!("{field}[{i}]"), out)?;
        }
        out.push(']');
    } else {
        return Err(PyTypeError::new_err(format!(
            "field {field}: expected a string (an exact entry such as \"1/4 - sqrt(3)/6\"), an int or a list, got {}",
            v.get_type().name()?
        )));
    }
    Ok(())
}

fn read_limited(path: &Path) -> Result<String, String> {
    use std::io::Read;
    let shown = path.display();
    let f = std::fs::File::open(path).map_err(|e| format!("{shown}: cannot read the file: {e}"))?;
    let mut text = String::new();
    f.take(MAX_TEXT_BYTES + 1)
        .read_to_string(&mut text)
        .map_err(|e| format!("{shown}: cannot read the file: {e}"))?;
    if text.len() as u64 > MAX_TEXT_BYTES {
        return Err(format!(
            "{shown}: the file is larger than {MAX_TEXT_BYTES} bytes; a table file is a few hundred bytes"
        ));
    }
    Ok(text)
}

/// The method id of a file: its stem (as `symlab compare --table`).
fn stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "table".into())
}

#[pymethods]
impl Table {
    /// A table from the fields of a table file: ``name`` (required),
    /// ``a``, ``b``, ``c``, ``a_hat``, ``b_hat``, ``c_hat``, ``drift``,
    /// ``kick``, ``kick_gradient``, ``compose``, ``generate``, ``claims``,
    /// ``source``, and
    /// ``let`` (a dict; ``let_`` also works). Entries are strings in the
    /// table grammar (``"1/4 + sqrt(3)/6"``) or ints; floats are refused.
    /// ``id`` names the method in comparisons (default ``"table"``).
    #[new]
    #[pyo3(signature = (*, id = None, **fields))]
    fn new(
        py: Python<'_>,
        id: Option<String>,
        fields: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let mut text = String::new();
        if let Some(fields) = fields {
            for (k, v) in fields.iter() {
                let key: String = k.extract()?;
                let key = if key == "let_" {
                    "let".to_string()
                } else {
                    key
                };
                text.push_str(&key);
                text.push_str(" = ");
                toml_value(&v, &key, &mut text)?;
                text.push('\n');
            }
        }
        let origin = "<Table(...)>".to_string();
        let o = origin.clone();
        let kind = on_analysis_thread(py, &origin, move || parse_text(&o, &text))?;
        Ok(Table {
            origin,
            id: id.unwrap_or_else(|| "table".into()),
            path: None,
            kind: Arc::new(Mutex::new(kind)),
        })
    }

    /// A table from the text of a table file (TOML). ``origin`` names it in
    /// messages; ``id`` in comparisons.
    #[staticmethod]
    #[pyo3(signature = (text, *, origin = "<string>".to_string(), id = "table".to_string()))]
    fn from_toml(py: Python<'_>, text: String, origin: String, id: String) -> PyResult<Self> {
        if text.len() as u64 > MAX_TEXT_BYTES {
            return Err(TableError::new_err(format!(
                "{origin}: the text is larger than {MAX_TEXT_BYTES} bytes; a table file is a few hundred bytes"
            )));
        }
        let o = origin.clone();
        let kind = on_analysis_thread(py, &origin, move || parse_text(&o, &text))?;
        Ok(Table {
            origin,
            id,
            path: None,
            kind: Arc::new(Mutex::new(kind)),
        })
    }

    /// A table file (TOML), as ``symlab check FILE``; its id in
    /// comparisons is the file's stem.
    #[staticmethod]
    fn from_file(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let origin = path.display().to_string();
        let (o, p) = (origin.clone(), path.clone());
        let kind = on_analysis_thread(py, &origin, move || {
            let text = read_limited(&p)?;
            parse_text(&o, &text)
        })?;
        Ok(Table {
            origin,
            id: stem(&path),
            path: Some(path),
            kind: Arc::new(Mutex::new(kind)),
        })
    }

    /// A built-in table, as ``symlab check --builtin ID``: a catalogue id
    /// (``symlab.list_tables()``) or a generated table (``gauss8``,
    /// ``radau2a5``, ``gauss(8)``).
    #[staticmethod]
    fn builtin(py: Python<'_>, id: String) -> PyResult<Self> {
        let origin = format!("builtin:{id}");
        let i = id.clone();
        let kind = on_analysis_thread(py, &origin, move || builtin_kind(&i))?;
        Ok(Table {
            origin,
            id,
            path: None,
            kind: Arc::new(Mutex::new(kind)),
        })
    }

    /// A generated collocation table: ``gauss(s)``, ``radau1a(s)``,
    /// ``radau2a(s)``, ``lobatto3a(s)``, ``lobatto3b(s)``,
    /// ``lobatto3c(s)``, ``lobatto3a3b(s)``; verified exactly when made.
    #[staticmethod]
    fn generate(py: Python<'_>, generator: String) -> PyResult<Self> {
        let origin = format!("builtin:{generator}");
        let (o, g) = (origin.clone(), generator.clone());
        let kind = on_analysis_thread(py, &origin, move || {
            Generated::new(&g)
                .map(|g| Kind::Generated(Box::new(g)))
                .map_err(|e| format!("{o}: {e}"))
        })?;
        Ok(Table {
            origin,
            id: generator.replace(['(', ')'], ""),
            path: None,
            kind: Arc::new(Mutex::new(kind)),
        })
    }

    /// The table's name (its ``name`` field).
    #[getter]
    fn name(&self) -> String {
        match &*self.kind.lock().unwrap_or_else(|e| e.into_inner()) {
            Kind::Classic(t) => t.name.clone(),
            Kind::Generated(g) => g.name.clone(),
            Kind::Algebraic(a) => a.name.clone(),
        }
    }

    /// How messages name the table (a path, ``builtin:ID``, ``<string>``).
    #[getter]
    fn origin(&self) -> String {
        self.origin.clone()
    }

    /// The method id in ``symlab.compare`` and ``symlab.integrate``.
    #[getter]
    fn id(&self) -> String {
        self.id.clone()
    }

    /// ``"classic"`` (rationals and radicals), ``"generated"`` or
    /// ``"algebraic"`` (``root(...)`` entries).
    #[getter]
    fn entries(&self) -> &'static str {
        match &*self.kind.lock().unwrap_or_else(|e| e.into_inner()) {
            Kind::Classic(_) => "classic",
            Kind::Generated(_) => "generated",
            Kind::Algebraic(_) => "algebraic",
        }
    }

    fn __repr__(&self) -> String {
        format!(
            "symlab.Table({:?}, origin={:?}, id={:?})",
            self.name(),
            self.origin,
            self.id
        )
    }
}

/// The verdicts of a table as JSON (the fields of `symlab check --json`,
/// plus `report`, `origin`, `claims` and W's entries with exact strings and
/// floats), and the claims that fail, each as `compare --table` says it.
fn verdicts(t_origin: &str, kind: &Kind) -> Result<(Value, Vec<String>), String> {
    let failed_claim = |c: &dyn std::fmt::Display, e: &dyn std::fmt::Display| {
        format!("claim `{c}` does not hold: {e}")
    };
    let mut failed = Vec::new();
    let v = match kind {
        Kind::Classic(tf) => {
            let a = Analysis::of(&tf.table).map_err(|e| format!("{t_origin}: field {e}"))?;
            let mut v = cli_check::to_json(tf, &a);
            v["w_nonzero"] = a
                .w_nonzero
                .iter()
                .map(|e| {
                    json!({"i": e.i, "j": e.j, "value": e.value.to_string(), "value_f64": e.value.to_f64()})
                })
                .collect();
            let claims: Vec<Value> = tf
                .claims
                .iter()
                .map(|c| {
                    let r = tableau::analysis::check_claim(&tf.table, &a, c);
                    if let Err(e) = &r {
                        failed.push(failed_claim(c, e));
                    }
                    json!({"claim": c.to_string(), "holds": r.is_ok(), "reason": r.err().map(|e| e.to_string())})
                })
                .collect();
            v["claims"] = claims.into();
            v["steps"] = cli_check::steps(&tf.name).into();
            v["report"] = cli_check::readable(t_origin, tf, &a).into();
            v
        }
        Kind::Generated(g) => {
            for (c, r) in &g.claims {
                if let Err(e) = r {
                    failed.push(failed_claim(c, e));
                }
            }
            let mut v = cli_check::generated_json(g);
            v["report"] = cli_check::generated_readable(t_origin, g).into();
            v
        }
        Kind::Algebraic(f) => {
            let an = f.analyse();
            let claims: Vec<Value> = f
                .claims
                .iter()
                .map(|c| {
                    let r = f.check_claim(&an, c);
                    if let Err(e) = &r {
                        failed.push(failed_claim(c, e));
                    }
                    json!({"claim": c.to_string(), "holds": r.is_ok(), "reason": r.err()})
                })
                .collect();
            // As `symlab check --json` on a root table: W's entries i ≤ j,
            // each zero decided (`zero: null` beyond budget).
            let w: Vec<Value> =
                an.w.iter()
                    .filter(|e| e.zero != Some(true))
                    .map(|e| json!({"i": e.i, "j": e.j, "zero": e.zero, "value_f64": e.value}))
                    .collect();
            json!({
                "name": f.name,
                "kind": if an.pair { "prk" } else { "rk" },
                "stages": an.stages,
                "entries": "algebraic",
                "roots": f.field.names,
                "row_sums_ok": an.row_sums_ok,
                "symplectic": an.symplectic,
                "symplectic_separable": an.symplectic_separable,
                "w_nonzero": w,
                "b_levels": an.b_levels,
                "refusals": an.refusals,
                "claims": claims,
            })
        }
    };
    let mut v = v;
    v["origin"] = t_origin.into();
    Ok((v, failed))
}

/// Decide a table's properties exactly and return them as a dict: the
/// fields of ``symlab check --json`` (``symplectic``, ``order``,
/// ``symmetric``, ``stability_function``, ``w_nonzero`` with each entry as
/// an exact string and a float, …), ``claims`` with their verdicts and
/// ``report``, the text ``symlab check`` prints.
///
/// A claim that does not hold raises ``ClaimError`` naming the claim and
/// the evidence (``claims="report"`` returns them in the dict instead). A
/// table beyond a budget raises ``BudgetError``, a malformed one
/// ``TableError``, each naming the field. The GIL is released meanwhile.
///
/// >>> import symlab
/// >>> v = symlab.check(symlab.Table.builtin("gauss2"))
/// >>> (v["symplectic"], v["order"], v["symmetric"])
/// (True, 4, True)
#[pyfunction]
#[pyo3(signature = (table, *, claims = "raise"))]
pub fn check<'py>(
    py: Python<'py>,
    table: &Bound<'py, Table>,
    claims: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let raise = match claims {
        "raise" => true,
        "report" => false,
        other => {
            return Err(PyValueError::new_err(format!(
                "claims must be \"raise\" or \"report\", got {other:?}"
            )));
        }
    };
    let t = table.get();
    let kind = t.kind.clone();
    let origin = t.origin.clone();
    let o = origin.clone();
    let (v, failed) = on_analysis_thread(py, &origin, move || {
        verdicts(&o, &kind.lock().unwrap_or_else(|e| e.into_inner()))
    })?;
    if raise && !failed.is_empty() {
        return Err(ClaimError::new_err(format!(
            "{origin}: {}",
            failed.join("; ")
        )));
    }
    json_to_py(py, &v)
}

/// The built-in tables, as ``symlab list --json``: dicts of ``id``,
/// ``name``, ``form``, ``steps`` and ``source``.
#[pyfunction]
pub fn list_tables(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    let mut rows: Vec<Value> = Vec::new();
    for (id, info) in integrator_core::library::REGISTRY {
        let (name, form, source) = match catalogue::find(id) {
            Some(entry) => {
                let tf = entry.load().map_err(|e| table_error(e.to_string()))?;
                (tf.name, form_name(&tf.table), tf.source)
            }
            None => (
                info.name.to_string(),
                info.form,
                Some("generated by tableau::algebraic (symlab check --builtin ID)".to_string()),
            ),
        };
        rows.push(json!({"id": id, "name": name, "form": form, "steps": cli_check::steps(id), "source": source}));
    }
    for entry in catalogue::entries() {
        if !rows.iter().any(|r| r["id"] == entry.id) {
            let tf = entry.load().map_err(|e| table_error(e.to_string()))?;
            rows.push(json!({"id": entry.id, "name": tf.name, "form": form_name(&tf.table), "steps": cli_check::steps(entry.id), "source": tf.source}));
        }
    }
    json_to_py(py, &Value::Array(rows))
}

fn form_name(t: &tableau::Table) -> &'static str {
    match t {
        tableau::Table::Rk(_) => "rk",
        tableau::Table::Prk(_) => "prk",
        tableau::Table::Splitting(s) if s.has_gradient() => "gradient-drift-kick",
        tableau::Table::Splitting(_) => "drift-kick",
        tableau::Table::Composition(_) => "composition",
    }
}

impl Table {
    /// The table as a verified method for the comparisons: every claim must
    /// hold (as `symlab compare --table`: a `ClaimError` otherwise).
    pub fn verified(&self, py: Python<'_>) -> PyResult<compare::interpreted::VerifiedTable> {
        use compare::interpreted::{VerifiedForm, VerifiedTable, root_coefficients};
        let kind = self.kind.clone();
        let origin = self.origin.clone();
        let o = origin.clone();
        let form = on_analysis_thread(py, &origin, move || -> Result<_, String> {
            let kind = kind.lock().unwrap_or_else(|e| e.into_inner());
            let (_, failed) = verdicts(&o, &kind)?;
            if !failed.is_empty() {
                return Ok(Err(format!("{o}: {}", failed.join("; "))));
            }
            Ok(Ok(match &*kind {
                Kind::Classic(tf) => VerifiedForm::Classic {
                    analysis: Box::new(
                        Analysis::of(&tf.table).map_err(|e| format!("{o}: field {e}"))?,
                    ),
                    file: tf.clone(),
                },
                Kind::Generated(g) => VerifiedForm::Generated(g.clone()),
                Kind::Algebraic(f) => {
                    let analysis = f.analyse();
                    let coefficients =
                        root_coefficients(f, &analysis).map_err(|e| format!("{o}: {e}"))?;
                    VerifiedForm::Algebraic {
                        file: f.clone(),
                        analysis: Box::new(analysis),
                        coefficients: Box::new(coefficients),
                    }
                }
            }))
        })?
        .map_err(ClaimError::new_err)?;
        Ok(VerifiedTable {
            path: self
                .path
                .clone()
                .unwrap_or_else(|| PathBuf::from(&self.origin)),
            id: self.id.clone(),
            form,
        })
    }
}
