//! A run's result as data: a row of `runs.csv` ([`Row`], its [`COLUMNS`]),
//! made by the run loops of [`sweep`](crate::sweep) and REBOUND's runs,
//! read and written by [`output`](crate::output), reported by
//! [`report`](crate::report).

use crate::format::csv_field;
use crate::problem::Family;

/// One run: a row of `runs.csv` (see [`sweep`](crate::sweep) for the columns).
#[derive(Clone, Debug)]
pub struct Row {
    pub problem: String,
    pub method: String,
    pub family: Family,
    pub order: usize,
    pub symplectic: bool,
    /// Step size (the average step for the adaptive peer and `logh:ID`).
    pub h: f64,
    /// `rtol = atol` of the adaptive peer; NaN for fixed-step methods.
    pub tol: f64,
    pub steps: u64,
    /// `‖z − z_ref‖₂/‖z_ref‖₂` at `t_end`; NaN unless `status` is ok.
    pub error: f64,
    /// `max |E − E₀|/|E₀|` over the run (the steps taken).
    pub energy_error: f64,
    /// Median wall time of the timed runs, seconds; NaN unless ok.
    pub time_s: f64,
    pub evals: u64,
    pub newton_iterations: usize,
    pub fixed_point_iterations: usize,
    pub factorizations: usize,
    pub status: String,
    /// Stepped by a run-time interpreter (a table file): the error and the
    /// evaluations compare with generated code, the wall time does not.
    pub interpreted: bool,
}

impl Row {
    pub fn ok(&self) -> bool {
        self.status == "ok"
    }
}

/// The CSV header of `runs.csv`.
pub const COLUMNS: &[&str] = &[
    "problem",
    "method",
    "order",
    "symplectic",
    "h",
    "tol",
    "steps",
    "error",
    "energy_error",
    "time_s",
    "evals",
    "newton_iterations",
    "fixed_point_iterations",
    "factorizations",
    "status",
];

impl Row {
    /// The row as a line of `runs.csv` (no newline); text fields quoted as
    /// RFC 4180 says ([`csv_field`]).
    pub fn csv(&self) -> String {
        format!(
            "{},{},{},{},{:e},{:e},{},{:e},{:e},{:e},{},{},{},{},{}",
            csv_field(&self.problem),
            csv_field(&self.method),
            self.order,
            self.symplectic,
            self.h,
            self.tol,
            self.steps,
            self.error,
            self.energy_error,
            self.time_s,
            self.evals,
            self.newton_iterations,
            self.fixed_point_iterations,
            self.factorizations,
            csv_field(&self.status)
        )
    }
}

/// The median of repeated timings (a row's `time_s`); NaN for none.
pub fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}
