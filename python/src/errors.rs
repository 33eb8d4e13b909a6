//! The exceptions of `symlab`. Each carries the message the command line
//! prints for the same input (after `error: `).
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyValueError};

create_exception!(
    symlab,
    SymlabError,
    PyException,
    "Base class of symlab's own errors."
);
create_exception!(
    symlab,
    TableError,
    PyValueError,
    "A table that does not parse or has the wrong shape; the message names the field."
);
create_exception!(
    symlab,
    BudgetError,
    TableError,
    "A table beyond one of the verifier's budgets (tableau::budget); the message names the field and the limit."
);
create_exception!(
    symlab,
    ClaimError,
    PyValueError,
    "A claim of a table that does not hold; the message names the claim and the evidence."
);
create_exception!(
    symlab,
    IntegrationError,
    SymlabError,
    "A run that diverged, whose stage solver failed, or whose problem raised."
);
create_exception!(
    symlab,
    ProblemError,
    PyValueError,
    "A problem or setting that cannot be run (unknown name, wrong lengths, a method that cannot step it)."
);
create_exception!(
    symlab,
    DesignError,
    PyValueError,
    "A design family that does not parse or cannot be designed; the message names the file and the field."
);

/// A table refused while reading or analysing it: [`BudgetError`] when a
/// budget of `tableau::budget` refused it (every such message names its
/// constant), else [`TableError`].
pub fn table_error(msg: String) -> pyo3::PyErr {
    if msg.contains("tableau::budget::") {
        BudgetError::new_err(msg)
    } else {
        TableError::new_err(msg)
    }
}
