//! The paper's linear model `M q̈ + G q̇ + K q = f` from a TOML file, as a
//! problem of the comparisons with its exact flow as the reference.
//!
//! ```toml
//! name = "two-masses"                 # optional (default: the file name)
//! description = "two coupled masses"  # optional
//! m = [[2.0, 0.0], [0.0, 1.0]]        # symmetric positive definite
//! g = [[0.0, 0.5], [-0.5, 0.0]]       # skew (optional, default 0)
//! k = [[3.0, -1.0], [-1.0, 2.0]]      # symmetric
//! f = [0.1, 0.0]                      # constant force (optional, default 0)
//! q0 = [1.0, 0.0]                     # start position
//! p0 = [0.0, 0.0]                     # start momentum p = M q̇ + G q/2 (optional, default 0)
//! t_end = 10.0                        # optional defaults of the sweep
//! h_min = 1e-3
//! h_max = 0.5
//! ```
//!
//! Numbers are TOML floats or integers (this is data, not an exact table).
//! The state is `z = [q; p]`; the energy is the system's Hamiltonian.

use std::path::{Path, PathBuf};

use integrator_core::linear::LinearHamiltonian;
use serde::Deserialize;

use crate::error::{CompareError, Result};
use crate::problem::{Defaults, Problem, Setup};

/// The largest problem file read.
pub const MAX_FILE_BYTES: u64 = 8 << 20;
/// The most degrees of freedom: the reference is a dense matrix
/// exponential of size `2n`, `O(n³)`.
pub const MAX_DOF: usize = 400;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Raw {
    name: Option<String>,
    description: Option<String>,
    m: Vec<Vec<f64>>,
    g: Option<Vec<Vec<f64>>>,
    k: Vec<Vec<f64>>,
    f: Option<Vec<f64>>,
    q0: Vec<f64>,
    p0: Option<Vec<f64>>,
    t_end: Option<f64>,
    h_min: Option<f64>,
    h_max: Option<f64>,
}

/// A linear problem read from a file.
#[derive(Clone, Debug)]
pub struct LinearFile {
    pub path: PathBuf,
    pub name: String,
    pub description: String,
    pub sys: LinearHamiltonian,
    pub z0: Vec<f64>,
    /// The sweep defaults: the file's where given, else the gyroscopic
    /// problem's (T = 10, h from 1e-4 to 0.1).
    pub defaults: Defaults,
}

fn err(path: &Path, why: impl Into<String>) -> CompareError {
    CompareError::ProblemFile {
        path: path.to_path_buf(),
        why: why.into(),
    }
}

/// Read and check a linear problem file. Errors name the file and the field
/// (`m`, `q0`, `t_end`, …) and say what is wrong.
pub fn load(path: &Path) -> Result<LinearFile> {
    let text = crate::interpreted::read_limited(path, MAX_FILE_BYTES).map_err(|w| err(path, w))?;
    let raw: Raw =
        toml::from_str(&text).map_err(|e| err(path, e.to_string().trim().replace('\n', " ")))?;
    let n = raw.m.len();
    if n > MAX_DOF {
        return Err(err(
            path,
            format!(
                "field m: {n} degrees of freedom; at most {MAX_DOF} (the reference is a dense matrix exponential)"
            ),
        ));
    }
    let zeros = || vec![vec![0.0; n]; n];
    let g = raw.g.unwrap_or_else(zeros);
    let f = raw.f.unwrap_or_else(|| vec![0.0; n]);
    let sys = LinearHamiltonian::from_rows(&raw.m, &g, &raw.k, &f)
        .map_err(|e| err(path, e.to_string()))?;
    let p0 = raw.p0.unwrap_or_else(|| vec![0.0; n]);
    for (field, v) in [("q0", &raw.q0), ("p0", &p0)] {
        if v.len() != n {
            return Err(err(
                path,
                format!("field {field} has {} entries, but M is {n}×{n}", v.len()),
            ));
        }
        if let Some(x) = v.iter().find(|x| !x.is_finite()) {
            return Err(err(path, format!("field {field}: {x} is not finite")));
        }
    }
    let base = sys.defaults();
    let mut defaults = Defaults {
        t_end: raw.t_end.unwrap_or(base.t_end),
        h_min: raw.h_min.unwrap_or(base.h_min),
        h_max: raw.h_max.unwrap_or(base.h_max),
    };
    for (field, x) in [
        ("t_end", defaults.t_end),
        ("h_min", defaults.h_min),
        ("h_max", defaults.h_max),
    ] {
        if !(x.is_finite() && x > 0.0) {
            return Err(err(
                path,
                format!("field {field} must be a finite number > 0, got {x}"),
            ));
        }
    }
    defaults.h_max = defaults.h_max.min(defaults.t_end);
    defaults.h_min = defaults.h_min.min(defaults.h_max);
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "linear".into());
    let name = raw.name.unwrap_or(stem);
    if name.is_empty() || name.contains([',', '"', '\n', '/', '\\']) {
        return Err(err(
            path,
            format!(
                "field name {name:?}: a name is non-empty, without commas, quotes, slashes or newlines"
            ),
        ));
    }
    Ok(LinearFile {
        path: path.to_path_buf(),
        description: raw
            .description
            .unwrap_or_else(|| format!("linear system {name} (n = {n})")),
        name,
        sys,
        z0: raw.q0.into_iter().chain(p0).collect(),
        defaults,
    })
}

impl LinearFile {
    /// The problem from the file's start to `t_end`, its reference the
    /// exact flow.
    pub fn setup(&self, t_end: f64) -> Result<Setup<LinearHamiltonian>> {
        Ok(Setup::from_start(self.sys.clone(), self.z0.clone(), t_end)?
            .named(self.name.clone(), self.description.clone()))
    }
}
