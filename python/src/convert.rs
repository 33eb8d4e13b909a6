//! JSON values (the fields `symlab check --json` prints) as Python values,
//! through Python's own `json` module, so that numbers, nulls and nested
//! lists come out exactly as `json.loads` of the CLI's output would.
use pyo3::prelude::*;
use serde_json::Value;

pub fn json_to_py<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(v)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}
