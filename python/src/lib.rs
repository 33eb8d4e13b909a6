//! `symlab` from Python: the extension module `symlab._symlab`, built by
//! maturin with the `python` feature (see `python/pyproject.toml`). The
//! Python package `symlab` (python/symlab/) re-exports it and adds what is
//! better written in Python: DataFrames and the Dask client.
//!
//! Without the feature the crate is empty, so that `cargo test --workspace`
//! neither compiles PyO3 nor links a test binary against libpython.
#![cfg(feature = "python")]

mod cloth_py;
mod convert;
mod design_py;
mod errors;
mod problem;
mod run;
mod table;

use pyo3::prelude::*;

#[pymodule]
fn _symlab(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("SymlabError", py.get_type::<errors::SymlabError>())?;
    m.add("TableError", py.get_type::<errors::TableError>())?;
    m.add("BudgetError", py.get_type::<errors::BudgetError>())?;
    m.add("ClaimError", py.get_type::<errors::ClaimError>())?;
    m.add(
        "IntegrationError",
        py.get_type::<errors::IntegrationError>(),
    )?;
    m.add("ProblemError", py.get_type::<errors::ProblemError>())?;
    m.add("DesignError", py.get_type::<errors::DesignError>())?;
    m.add_class::<table::Table>()?;
    m.add_function(wrap_pyfunction!(table::check, m)?)?;
    m.add_function(wrap_pyfunction!(table::list_tables, m)?)?;
    m.add_class::<problem::Problem>()?;
    m.add_function(wrap_pyfunction!(run::integrate, m)?)?;
    m.add_function(wrap_pyfunction!(run::integrate_ensemble, m)?)?;
    m.add_function(wrap_pyfunction!(run::sweep_plan, m)?)?;
    m.add_function(wrap_pyfunction!(run::run_point, m)?)?;
    m.add_function(wrap_pyfunction!(run::compare_local, m)?)?;
    m.add_function(wrap_pyfunction!(run::problems, m)?)?;
    m.add_function(wrap_pyfunction!(cloth_py::cloth_run, m)?)?;
    m.add_function(wrap_pyfunction!(cloth_py::cloth_resume, m)?)?;
    m.add_function(wrap_pyfunction!(design_py::design, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
