//! The one error type of the comparison library. Every variant names what
//! is wrong — the setting, the problem, the method id, the file — so that a
//! caller can print it as it is.

use std::path::PathBuf;

/// Why a comparison could not be set up or its output not written. A run
/// that fails (diverges, or whose stage solver fails at step k) is not an
/// error: it is a row with that status.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// A setting of an experiment is out of range (`name` is the field of
    /// the settings struct, e.g. `t_end`).
    #[error("{name}: {why}")]
    Setting { name: &'static str, why: String },
    /// A value the caller gave (or a problem file set) that is out of range
    /// or contradicts another: `names` are the values involved as the
    /// caller named them (`--h-min`, `FILE: field h_max`), `why` the
    /// sentence that names them.
    #[error("{why}")]
    Given { names: Vec<String>, why: String },
    /// The problem cannot be run as given: a start or reference of the
    /// wrong length, a non-finite start, energy or reference.
    #[error("problem '{problem}': {why}")]
    Problem { problem: String, why: String },
    /// The method does not exist or cannot step this problem (`why` is a
    /// sentence that names the method).
    #[error("{why}")]
    Method { id: String, why: String },
    /// Two methods of one sweep with the same id (a table's id is its
    /// file's stem): `index` is the second's place in the list the caller
    /// gave ([`sweep_methods`](crate::plan::sweep_methods): the methods
    /// named, or, when `added`, those added), for a message in the caller's
    /// terms.
    #[error("methods: the id '{id}' appears twice (a table's id is its file's stem)")]
    DuplicateMethod {
        id: String,
        index: usize,
        added: bool,
    },
    /// A table file that does not load, or whose claims do not hold.
    #[error("{}: {why}", path.display())]
    TableFile { path: PathBuf, why: String },
    /// A table that could not be read or analysed (the message names the
    /// table and, where there is one, the field).
    #[error(transparent)]
    Verdict(#[from] tableau::verdict::VerdictError),
    /// A problem file (e.g. a linear system) that does not load.
    #[error("{}: {why}", path.display())]
    ProblemFile { path: PathBuf, why: String },
    /// A `runs.csv` that cannot be read back.
    #[error("{}: {why}", path.display())]
    Csv { path: PathBuf, why: String },
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A plot that cannot be drawn (no drawable point, a backend error).
    #[error("plot {}: {why}", path.display())]
    Plot { path: PathBuf, why: String },
}

/// The library's result type.
pub type Result<T, E = CompareError> = std::result::Result<T, E>;

impl CompareError {
    pub(crate) fn setting(name: &'static str, why: impl Into<String>) -> Self {
        CompareError::Setting {
            name,
            why: why.into(),
        }
    }
    pub(crate) fn method(id: &str, why: impl Into<String>) -> Self {
        CompareError::Method {
            id: id.to_string(),
            why: why.into(),
        }
    }
    pub(crate) fn problem(problem: &str, why: impl Into<String>) -> Self {
        CompareError::Problem {
            problem: problem.to_string(),
            why: why.into(),
        }
    }
}

/// Write a file, naming it on failure.
pub(crate) fn write(path: &std::path::Path, contents: impl AsRef<[u8]>) -> Result<()> {
    std::fs::write(path, contents).map_err(|source| CompareError::Io {
        path: path.to_path_buf(),
        source,
    })
}
