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
use crate::format;
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
    /// problem's (T = 10, h from 1e-4 to 0.1), a default step at most the
    /// file's `t_end`.
    pub defaults: Defaults,
    /// Which of `defaults` the file gave (`t_end`, `h_min`, `h_max`), so
    /// that a message about them names the file's field.
    pub given: Given,
}

/// Which sweep defaults a problem file gave.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Given {
    pub t_end: bool,
    pub h_min: bool,
    pub h_max: bool,
}

/// The most steps of one run that a file's `t_end` and `h_min` may ask for
/// (the same limit as the sweep's, [`SweepSettings::validate`](crate::SweepSettings::validate)).
pub const MAX_STEPS_PER_RUN: f64 = 1e8;

fn err(path: &Path, why: impl Into<String>) -> CompareError {
    CompareError::ProblemFile {
        path: path.to_path_buf(),
        why: why.into(),
    }
}

/// A TOML error as one line naming the line and the field the user wrote
/// (`line 4: field t_end: invalid type: string "x", expected f64`).
fn toml_message(text: &str, e: &toml::de::Error) -> String {
    let message = e.message().trim().replace('\n', " ");
    if let Some(rest) = message.strip_prefix("missing field ") {
        return format!("field {} is missing", rest.trim_matches('`'));
    }
    let Some(span) = e.span() else {
        return message;
    };
    let start = span.start.min(text.len());
    let line = text[..start].matches('\n').count() + 1;
    let line_text = text.lines().nth(line - 1).unwrap_or("");
    let key = line_text
        .split_once('=')
        .map(|(k, _)| k.trim().trim_matches('"'))
        .filter(|k| !k.is_empty() && !k.starts_with('#') && !k.starts_with('['));
    match key {
        Some(k) if !message.contains(&format!("`{k}`")) => {
            format!("line {line}: field {k}: {message}")
        }
        _ => format!("line {line}: {message}"),
    }
}

/// Read and check a linear problem file. Errors name the file and the field
/// (`m`, `q0`, `t_end`, …) and say what is wrong.
pub fn load(path: &Path) -> Result<LinearFile> {
    let text = crate::output::read_text(
        path,
        MAX_FILE_BYTES,
        "a problem file of the largest size allowed (400 degrees of freedom) is about 4 MB",
    )
    .map_err(|w| err(path, w))?;
    let raw: Raw = toml::from_str(&text).map_err(|e| err(path, toml_message(&text, &e)))?;
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
    let sys = LinearHamiltonian::from_rows(&raw.m, &g, &raw.k, &f).map_err(|e| {
        // The matrices' messages name them as the paper does (M, G, K, f);
        // the file's fields are m, g, k, f.
        let why = e.to_string();
        let field = match why.split_whitespace().next() {
            Some("M") => "field m",
            Some("G") => "field g",
            Some("K") => "field k",
            Some("f") => "field f",
            _ => "fields m, g, k, f",
        };
        err(path, format!("{field}: {why}"))
    })?;
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
    let given = Given {
        t_end: raw.t_end.is_some(),
        h_min: raw.h_min.is_some(),
        h_max: raw.h_max.is_some(),
    };
    for (field, x) in [
        ("t_end", raw.t_end),
        ("h_min", raw.h_min),
        ("h_max", raw.h_max),
    ] {
        if let Some(x) = x
            && !(x.is_finite() && x > 0.0)
        {
            return Err(err(
                path,
                format!(
                    "field {field} must be a finite number > 0, got {}",
                    format::plain(x)
                ),
            ));
        }
    }
    let base = sys.defaults();
    let t_end = raw.t_end.unwrap_or(base.t_end);
    // A default step is at most the run (one step of at most t_end), and
    // the smallest default at most the largest: a file's own values are
    // never moved, and contradictions among them are refused.
    let h_max = raw.h_max.unwrap_or(base.h_max.min(t_end));
    let h_min = raw.h_min.unwrap_or(base.h_min.min(h_max));
    let defaults = Defaults {
        t_end,
        h_min,
        h_max,
    };
    // Contradictions among the file's own fields are refused here, naming
    // both. A field against a default (the file gives h_min but not h_max)
    // is left to the caller, whose flags may replace the default
    // (`symlab compare` names the field and the flag);
    // [`SweepSettings::validate`](crate::SweepSettings::validate) refuses
    // what is left.
    if given.h_min && given.h_max && h_min > h_max {
        return Err(err(
            path,
            format!(
                "field h_min ({}) must not exceed field h_max ({})",
                format::plain(h_min),
                format::plain(h_max)
            ),
        ));
    }
    if given.h_max && given.t_end && h_max > t_end {
        return Err(err(
            path,
            format!(
                "field h_max ({}) exceeds field t_end ({})",
                format::plain(h_max),
                format::plain(t_end)
            ),
        ));
    }
    if given.h_min && given.t_end && t_end / h_min > MAX_STEPS_PER_RUN {
        return Err(err(
            path,
            format!(
                "field h_min ({}) over field t_end ({}) is {:.1e} steps per run; at most 1e8",
                format::plain(h_min),
                format::plain(t_end),
                t_end / h_min,
            ),
        ));
    }
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
        given,
    })
}

impl LinearFile {
    /// The problem from the file's start to `t_end`, its reference the
    /// exact flow.
    ///
    /// Errors name the file and the fields behind them: a start whose
    /// energy is not finite (`q0`, `p0` with `m`, `g`, `k`), an exact flow
    /// that cannot be computed to `t_end`.
    pub fn setup(&self, t_end: f64) -> Result<Setup<LinearHamiltonian>> {
        let setup = Setup::from_start(self.sys.clone(), self.z0.clone(), t_end).map_err(|e| {
            let why = match e {
                CompareError::Problem { why, .. } if why.contains("energy") => {
                    format!("fields q0 and p0 (with m, g, k, f): {why}")
                }
                CompareError::Problem { why, .. } => format!(
                    "the exact flow of fields m, g, k, f from q0, p0 to t_end = {}: {why}",
                    format::plain(t_end)
                ),
                CompareError::Setting { name, why } => format!("{name}: {why}"),
                other => other.to_string(),
            };
            err(&self.path, why)
        })?;
        Ok(setup.named(self.name.clone(), self.description.clone()))
    }
}
