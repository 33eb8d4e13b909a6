//! From what a caller asked for to validated sweep settings: the end time,
//! the step range, points and repeats, with the problem's defaults for what
//! was not given. Messages name each value as the caller wrote it (a flag
//! `--h-min`, or a problem file's field `FILE: field h_min`), so `symlab
//! compare` prints them as they are and a Rust caller names its own fields.
//!
//! ```
//! use compare::sweep_plan::{SweepRequest, sweep_plan};
//! let defaults = compare::Defaults { t_end: 10.0, h_min: 1e-3, h_max: 0.1 };
//! let plan = sweep_plan(&SweepRequest { h_max: Some(0.5), ..SweepRequest::default() }, defaults).unwrap();
//! assert_eq!((plan.t_end, plan.settings.h_max), (10.0, 0.5));
//!
//! let bad = SweepRequest { h_min: Some(1.0), h_max: Some(0.5), ..SweepRequest::default() };
//! let err = sweep_plan(&bad, defaults).unwrap_err().to_string();
//! assert_eq!(err, "--h-min (1) must not exceed --h-max (0.5)");
//! ```

use crate::error::{CompareError, Result};
use crate::format;
use crate::plan::{self, SweepDefaults};
use crate::problem::Defaults;
use crate::sweep::tolerances;
use crate::work_precision::SweepSettings;

/// The most steps one run of a sweep may take (`t_end / h_min`).
pub const MAX_STEPS_PER_RUN: f64 = 1e8;
/// The largest number of step sizes of a sweep.
pub const MAX_POINTS: usize = 200;
/// The largest number of timed repeats per point.
pub const MAX_REPEATS: usize = 100;
/// The error of the time-to-error table when the caller gives none.
pub const DEFAULT_TARGET: f64 = 1e-8;

/// What a caller asked for; `None` takes the problem's default (or the
/// quick sweep's). The names are how messages call each value.
#[derive(Clone, Debug, Default)]
pub struct SweepRequest {
    pub t_end: Option<f64>,
    pub h_min: Option<f64>,
    pub h_max: Option<f64>,
    pub points: Option<usize>,
    pub repeats: Option<usize>,
    pub target: Option<f64>,
    /// A smoke run: few points, one repeat, a larger default smallest step.
    pub quick: bool,
    pub names: Names,
    /// The problem's defaults that a file set, by the name of its field:
    /// these are not moved to fit a short end time, and a contradiction
    /// with a given value names both.
    pub from_file: FromFile,
}

/// How messages name the values a caller gives.
#[derive(Clone, Debug)]
pub struct Names {
    pub t_end: String,
    pub h_min: String,
    pub h_max: String,
    pub points: String,
    pub repeats: String,
    pub target: String,
}

impl Default for Names {
    /// The command line's flags.
    fn default() -> Self {
        Names {
            t_end: "--t-end".into(),
            h_min: "--h-min".into(),
            h_max: "--h-max".into(),
            points: "--points".into(),
            repeats: "--repeats".into(),
            target: "--target".into(),
        }
    }
}

impl SweepRequest {
    /// The name of the first value given of those only a work–precision
    /// sweep reads (end time, smallest and largest step, points), for the
    /// modes that refuse them.
    pub fn sweep_only_given(&self) -> Option<&str> {
        let n = &self.names;
        [
            (self.t_end.is_some(), &n.t_end),
            (self.h_min.is_some(), &n.h_min),
            (self.h_max.is_some(), &n.h_max),
            (self.points.is_some(), &n.points),
        ]
        .into_iter()
        .find_map(|(set, name)| set.then_some(name.as_str()))
    }

    /// The name of the first value given, of them all.
    pub fn any_given(&self) -> Option<&str> {
        let n = &self.names;
        self.sweep_only_given().or_else(|| {
            [
                (self.repeats.is_some(), &n.repeats),
                (self.target.is_some(), &n.target),
            ]
            .into_iter()
            .find_map(|(set, name)| set.then_some(name.as_str()))
        })
    }
}

/// A list of method ids as a caller gave it, each once, in its order; an
/// empty entry is an error naming `what` (the flag or argument).
pub fn method_list(what: &str, list: &[String]) -> Result<Vec<String>> {
    let mut out: Vec<String> = Vec::new();
    for m in list {
        let m = m.trim();
        if m.is_empty() {
            return Err(given(
                what,
                format!("{what} has an empty entry (ids are separated by single commas)"),
            ));
        }
        if !out.iter().any(|x| x == m) {
            out.push(m.to_string());
        }
    }
    Ok(out)
}

/// Defaults a problem file set, each named as the file's field
/// (`FILE: field h_min`); `None` where the problem's own default applies.
#[derive(Clone, Debug, Default)]
pub struct FromFile {
    pub t_end: Option<String>,
    pub h_min: Option<String>,
    pub h_max: Option<String>,
}

/// Validated sweep parameters.
#[derive(Clone, Debug)]
pub struct SweepPlan {
    pub t_end: f64,
    pub settings: SweepSettings,
}

impl SweepPlan {
    /// The line that says what the sweep of the problem described as
    /// `description` runs, with `methods` methods.
    pub fn headline(&self, description: &str, methods: usize) -> String {
        let steps = self.settings.step_counts(self.t_end);
        let (first, last) = (steps[0], *steps.last().expect("at least one"));
        format!(
            "{description}: T = {}, {methods} methods, {} step sizes from h = {:.3e} to {:.3e} ({first}–{last} steps), {} timed run(s) each",
            format::plain(self.t_end),
            steps.len(),
            self.t_end / first as f64,
            self.t_end / last as f64,
            self.settings.repeats
        )
    }
}

/// `x` if it is a finite, normal number > 0; otherwise an error naming it.
/// A subnormal time or step has lost its precision (5e-324 is the only
/// number between 0 and 1e-323): no run means anything there.
pub fn positive(name: &str, x: f64) -> Result<f64> {
    if !(x.is_finite() && x > 0.0) {
        return Err(given(
            name,
            format!(
                "{name} must be a finite number > 0, got {}",
                format::plain(x)
            ),
        ));
    }
    if !x.is_normal() {
        return Err(given(
            name,
            format!(
                "{name} must be at least {:e} (the smallest normal f64), got {}",
                f64::MIN_POSITIVE,
                format::plain(x)
            ),
        ));
    }
    Ok(x)
}

fn given(name: &str, why: String) -> CompareError {
    CompareError::Given {
        names: vec![name.to_string()],
        why,
    }
}

fn contradiction(names: [&Option<String>; 2], why: String) -> CompareError {
    CompareError::Given {
        names: names.into_iter().flatten().cloned().collect(),
        why,
    }
}

/// Validate a request against a problem's defaults. Defaults the caller
/// did not give adapt to a short end time (one step is at most the whole
/// run), so that an error names a value that was given.
pub fn sweep_plan(req: &SweepRequest, defaults: Defaults) -> Result<SweepPlan> {
    let names = &req.names;
    let file = &req.from_file;
    let target = match req.target {
        Some(t) => positive(&names.target, t)?,
        None => DEFAULT_TARGET,
    };
    let t_end = positive(&names.t_end, req.t_end.unwrap_or(defaults.t_end))?;
    // Who set each value: the caller, a problem file's field, or neither.
    let who = |value: Option<f64>, name: &str, field: &Option<String>| -> Option<String> {
        if value.is_some() {
            Some(name.to_string())
        } else {
            field.clone()
        }
    };
    let who_t = who(req.t_end, &names.t_end, &file.t_end);
    let who_min = who(req.h_min, &names.h_min, &file.h_min);
    let who_max = who(req.h_max, &names.h_max, &file.h_max);
    let h_max = match req.h_max {
        Some(h) => positive(&names.h_max, h)?,
        None if file.h_max.is_some() => defaults.h_max,
        None => defaults.h_max.min(t_end),
    };
    let h_min = match req.h_min {
        Some(h) => positive(&names.h_min, h)?,
        None if file.h_min.is_some() => defaults.h_min,
        None => {
            let h = if req.quick {
                plan::quick_h_min(defaults)
            } else {
                defaults.h_min
            };
            if req.h_max.is_none() { h.min(h_max) } else { h }
        }
    };
    let (lo, hi, t) = (
        format::plain(h_min),
        format::plain(h_max),
        format::plain(t_end),
    );
    let end = who_t
        .clone()
        .unwrap_or_else(|| "the default end time".into());
    if h_min > h_max {
        let why = match (&who_min, &who_max) {
            (Some(a), Some(b)) => format!("{a} ({lo}) must not exceed {b} ({hi})"),
            (Some(a), None) => format!(
                "{a} ({lo}) exceeds the default largest step {hi} (the problem's, at most {end}); give {} too",
                names.h_max
            ),
            (None, Some(b)) => format!(
                "{b} ({hi}) is below the default smallest step {lo}; give {} too",
                names.h_min
            ),
            (None, None) => format!(
                "the default smallest step {lo} exceeds the default largest step {hi}; give {} and {}",
                names.h_min, names.h_max
            ),
        };
        return Err(contradiction([&who_min, &who_max], why));
    }
    if h_max > t_end {
        let b = who_max
            .clone()
            .unwrap_or_else(|| "the default largest step".into());
        let why = match &who_t {
            Some(w) => format!("{b} ({hi}) exceeds the end time {w} ({t})"),
            None => format!(
                "{b} ({hi}) exceeds the default end time ({t}); give {} too",
                names.t_end
            ),
        };
        return Err(contradiction([&who_max, &who_t], why));
    }
    if t_end / h_min > MAX_STEPS_PER_RUN {
        let why = format!(
            "{} {lo} over {end} {t} is {:.1e} steps per run; at most 1e8{}",
            who_min
                .clone()
                .unwrap_or_else(|| "the default smallest step".into()),
            t_end / h_min,
            if who_min.is_some() {
                String::new()
            } else {
                format!(" (give {} too)", names.h_min)
            }
        );
        return Err(contradiction([&who_min, &who_t], why));
    }
    let quick = SweepDefaults::of(req.quick);
    let points = req.points.unwrap_or(quick.points);
    if !(1..=MAX_POINTS).contains(&points) {
        return Err(given(
            &names.points,
            format!(
                "{} must be between 1 and {MAX_POINTS}, got {points}",
                names.points
            ),
        ));
    }
    let repeats = req.repeats.unwrap_or(quick.repeats);
    if repeats == 0 || repeats > MAX_REPEATS {
        let why = if repeats == 0 {
            format!("{} must be at least 1", names.repeats)
        } else {
            format!(
                "{} must be at most {MAX_REPEATS}, got {repeats}",
                names.repeats
            )
        };
        return Err(given(&names.repeats, why));
    }
    let settings = SweepSettings {
        h_min,
        h_max,
        points,
        tolerances: tolerances(req.points.unwrap_or(quick.tolerances)),
        repeats,
        target,
    };
    // The sweep checks the same facts; its names are the settings' fields.
    settings.validate(t_end)?;
    Ok(SweepPlan { t_end, settings })
}
