//! `symlab.Table` and `symlab.check`: a table read by `tableau`'s own
//! parser (whatever the Python form it came in, it is turned into the
//! table-file text first, so every message names the field as `symlab
//! check` does) and its verdict, `tableau::verdict`'s, as `symlab check`
//! prints it: the dict is that JSON object.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use tableau::algebraic::file::Loaded as Kind;
use tableau::algebraic::generated::Generated;
use tableau::verdict::{self, Options, Source, Verdict, VerdictError};

use crate::convert::json_to_py;
use crate::errors::{ClaimError, TableError, table_error};

/// The largest table text read (as a table file: `tableau::budget::MAX_FILE_BYTES`).
const MAX_TEXT_BYTES: u64 = tableau::budget::MAX_FILE_BYTES;

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

/// Run `f` on the verdict's analysis thread
/// (`tableau::verdict::on_analysis_thread`), the GIL released; an error or
/// a panic is a `TableError` (or `BudgetError`) with the command line's
/// message.
pub fn on_analysis_thread<T: Send>(
    py: Python<'_>,
    origin: &str,
    f: impl FnOnce() -> Result<T, VerdictError> + Send,
) -> PyResult<T> {
    py.detach(|| verdict::on_analysis_thread(origin, f))
        .map_err(|e| table_error(e.to_string()))
}

/// `source` read and its kind decided, on the analysis thread.
fn resolve(py: Python<'_>, source: Source<'_>) -> PyResult<Kind> {
    on_analysis_thread(py, &source.origin(), || {
        verdict::resolve(&source).map(|r| r.table)
    })
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
        Table::from_text(
            py,
            "<Table(...)>".to_string(),
            id.unwrap_or_else(|| "table".into()),
            &text,
        )
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
        Table::from_text(py, origin, id, &text)
    }

    /// A table file (TOML), as ``symlab check FILE``; its id in
    /// comparisons is the file's stem.
    #[staticmethod]
    fn from_file(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let origin = path.display().to_string();
        let kind = resolve(py, Source::File(&path))?;
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
        let kind = resolve(py, Source::Builtin(&id))?;
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
        let kind = on_analysis_thread(py, &origin, || {
            Generated::new(&generator)
                .map(|g| Kind::Generated(Box::new(g)))
                .map_err(|e| VerdictError::Input(format!("{origin}: {e}")))
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

impl Table {
    /// A table from table-file text, named `origin` in messages and `id` in
    /// comparisons.
    fn from_text(py: Python<'_>, origin: String, id: String, text: &str) -> PyResult<Self> {
        let kind = resolve(
            py,
            Source::Text {
                origin: &origin,
                text,
            },
        )?;
        Ok(Table {
            origin,
            id,
            path: None,
            kind: Arc::new(Mutex::new(kind)),
        })
    }

    /// The table's verdict, on the analysis thread.
    fn verdict(&self, py: Python<'_>, options: Options) -> PyResult<Verdict> {
        on_analysis_thread(py, &self.origin, || {
            let table = self.kind.lock().unwrap_or_else(|e| e.into_inner());
            Verdict::of(&self.origin, &table, &options)
        })
    }
}

/// Decide a table's properties exactly and return them as a dict: the
/// object ``symlab check --json`` prints, field for field (``symplectic``,
/// ``order``, ``symmetric``, ``stability_function``, ``w_nonzero`` with
/// each entry as an exact string and a float, ``claims`` with their
/// verdicts, ``report``, the text ``symlab check`` prints, …; the fields
/// are listed in the documentation of ``tableau::verdict``).
/// ``near_integrable=True`` also decides the generalised (h, ε) orders, as
/// ``symlab check --near-integrable``.
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
#[pyo3(signature = (table, *, claims = "raise", near_integrable = false))]
pub fn check<'py>(
    py: Python<'py>,
    table: &Bound<'py, Table>,
    claims: &str,
    near_integrable: bool,
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
    let v = t.verdict(py, Options { near_integrable })?;
    let failed = v.failed_claims();
    if raise && !failed.is_empty() {
        return Err(ClaimError::new_err(format!(
            "{}: {}",
            t.origin,
            failed.join("; ")
        )));
    }
    let v = v.to_json();
    json_to_py(py, &v)
}

/// The built-in tables, as ``symlab list --json``: dicts of ``id``,
/// ``name``, ``form``, ``steps``, ``source`` and ``processed``.
#[pyfunction]
pub fn list_tables(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    let rows = integrator_core::library::listing().map_err(|e| table_error(e.to_string()))?;
    let rows = serde_json::to_value(rows).map_err(|e| table_error(e.to_string()))?;
    json_to_py(py, &rows)
}

impl Table {
    /// The table as a verified method for the comparisons: every claim must
    /// hold (as `symlab compare --table`: a `ClaimError` otherwise).
    pub fn verified(&self, py: Python<'_>) -> PyResult<compare::interpreted::VerifiedTable> {
        let verdict = self.verdict(py, Options::default())?;
        let path = self
            .path
            .clone()
            .unwrap_or_else(|| PathBuf::from(&self.origin));
        use compare::interpreted::{Unverified, VerifiedTable};
        VerifiedTable::from_verdict(path, self.id.clone(), verdict).map_err(|why| match why {
            Unverified::Claims(_) => ClaimError::new_err(format!("{}: {why}", self.origin)),
            Unverified::Coefficients(_) => table_error(format!("{}: {why}", self.origin)),
        })
    }
}
