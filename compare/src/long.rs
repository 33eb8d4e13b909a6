//! `--long`: 10⁶ (up to 10⁷) steps of same-order pairs, symplectic against
//! non-symplectic, each with and without compensated summation, recording
//! the energy error at log-spaced times and fitting its growth exponent.

use std::fmt::Write as _;
use std::path::Path;

use rayon::prelude::*;

use crate::error::{CompareError, Result, write as write_file};
use crate::format;
use crate::method::{Fixed, Method};
use crate::output::{csv_field, loglog_slope};
use crate::plot::{self, Plot, Series};
use crate::problem::{Problem, Setup};
use crate::stepper::Status;

/// The pairs compared: `(symplectic, non-symplectic, order)`.
pub const PAIRS: [(&str, &str, usize); 3] = [
    ("leapfrog", "heun", 2),
    ("forest-ruth", "rk4", 4),
    ("gauss2", "rk4", 4),
];

/// Energy-error samples per decade of steps.
const PER_DECADE: u32 = 20;

/// One long run.
pub struct LongRun {
    pub problem: String,
    pub method: String,
    pub order: usize,
    pub symplectic: bool,
    pub compensated: bool,
    pub h: f64,
    pub steps: u64,
    /// `(step, t, max |E − E₀|/|E₀| over the window of steps ending here)`;
    /// the windows are log-spaced, `PER_DECADE` per decade of steps.
    pub samples: Vec<(u64, f64, f64)>,
    pub status: Status,
    /// Least-squares slope of log energy error against log t over the last
    /// two decades of time.
    pub exponent: Option<f64>,
}

/// Window ends: `round(10^(j/PER_DECADE))`, distinct, ending with `n`.
pub fn window_ends(n: u64) -> Vec<u64> {
    let mut v: Vec<u64> = Vec::new();
    for j in 0.. {
        let b = 10f64.powf(j as f64 / PER_DECADE as f64).round() as u64;
        if b >= n {
            break;
        }
        if v.last() != Some(&b) {
            v.push(b);
        }
    }
    v.push(n);
    v
}

/// The growth exponent of the energy error: the slope over samples with
/// `t ≥ t_last/100` (the last two decades).
pub fn growth_exponent(samples: &[(u64, f64, f64)]) -> Option<f64> {
    let t_last = samples.last()?.1;
    let pts: Vec<(f64, f64)> = samples
        .iter()
        .filter(|s| s.1 >= t_last / 100.0)
        .map(|s| (s.1, s.2))
        .collect();
    loglog_slope(&pts)
}

/// The library's pairs of [`PAIRS`] as methods of `P`, each once.
pub fn pair_methods<P: Problem>(sys: &P) -> Result<Vec<Fixed<P>>> {
    let mut ids: Vec<&str> = Vec::new();
    for (a, b, _) in PAIRS {
        for id in [a, b] {
            if !ids.contains(&id) {
                ids.push(id);
            }
        }
    }
    ids.into_iter()
        .map(|id| match Method::by_id(id, sys)? {
            Method::Fixed(f) => Ok(f),
            Method::Dop853 | Method::Rebound(_) => {
                Err(CompareError::method(id, "the pairs are fixed-step schemes"))
            }
        })
        .collect()
}

/// The settings of long runs: `steps` steps of size `h`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LongSettings {
    pub h: f64,
    pub steps: u64,
}

impl LongSettings {
    /// At least 10 and at most 10⁹ steps of a finite `h > 0`.
    pub fn validate(&self) -> Result<()> {
        if !(self.h.is_finite() && self.h > 0.0) {
            return Err(CompareError::setting(
                "h",
                format!("the step must be a finite number > 0, got {}", self.h),
            ));
        }
        if !(10..=1_000_000_000).contains(&self.steps) {
            return Err(CompareError::setting(
                "steps",
                format!("between 10 and 10⁹ steps, got {}", self.steps),
            ));
        }
        Ok(())
    }
}

/// Each method, with and without compensated summation, for
/// `settings.steps` steps, in parallel (every run is independent and only
/// its energy errors are recorded). `setup` needs no reference.
pub fn run<P: Problem>(
    setup: &Setup<P>,
    methods: &[Fixed<P>],
    settings: LongSettings,
) -> Result<Vec<LongRun>> {
    settings.validate()?;
    let (h, n) = (settings.h, settings.steps);
    let mut jobs = Vec::new();
    for f in methods {
        for compensated in [true, false] {
            jobs.push((f, compensated));
        }
    }
    let ends = window_ends(n);
    let runs = jobs
        .par_iter()
        .map(|(f, compensated)| {
            let mut z = setup.z0.clone();
            let mut samples = Vec::with_capacity(ends.len());
            let mut next = 0;
            let mut window: f64 = 0.0;
            let outcome = crate::stepper::observed_caught(
                &*f.stepper,
                &setup.sys,
                &mut z,
                h,
                n as usize,
                *compensated,
                &mut |k, t, z| {
                    if k == 0 {
                        return true;
                    }
                    window = window.max(setup.energy_error(z));
                    if k as u64 == ends[next] {
                        samples.push((k as u64, t, window));
                        window = 0.0;
                        next += 1;
                    }
                    true
                },
            );
            let exponent = growth_exponent(&samples);
            LongRun {
                problem: setup.name.clone(),
                method: f.id.clone(),
                order: f.order,
                symplectic: f.symplectic,
                compensated: *compensated,
                h,
                steps: n,
                samples,
                status: outcome.status,
                exponent,
            }
        })
        .collect();
    Ok(runs)
}

fn label(r: &LongRun) -> String {
    format!(
        "{} ({})",
        r.method,
        if r.compensated {
            "compensated"
        } else {
            "plain"
        }
    )
}

/// `long.csv` (samples), `long_fit.csv` (exponents) and `long_energy.svg`.
pub fn write(dir: &Path, runs: &[LongRun]) -> Result<()> {
    let Some(first) = runs.first() else {
        return Err(CompareError::setting("methods", "no long runs to write"));
    };
    let mut s = String::from("problem,method,order,symplectic,compensated,h,step,t,energy_error\n");
    for r in runs {
        for (k, t, e) in &r.samples {
            let _ = writeln!(
                s,
                "{},{},{},{},{},{:e},{},{:e},{:e}",
                csv_field(&r.problem),
                csv_field(&r.method),
                r.order,
                r.symplectic,
                r.compensated,
                r.h,
                k,
                t,
                e
            );
        }
    }
    let path = dir.join("long.csv");
    write_file(&path, s)?;
    let mut s = String::from(
        "problem,method,order,symplectic,compensated,h,steps,exponent,final_energy_error,status\n",
    );
    for r in runs {
        let last = r.samples.last().map_or(f64::NAN, |x| x.2);
        let _ = writeln!(
            s,
            "{},{},{},{},{},{:e},{},{:e},{:e},{}",
            csv_field(&r.problem),
            csv_field(&r.method),
            r.order,
            r.symplectic,
            r.compensated,
            r.h,
            r.steps,
            r.exponent.unwrap_or(f64::NAN),
            last,
            csv_field(&r.status.label())
        );
    }
    let path = dir.join("long_fit.csv");
    write_file(&path, s)?;
    let series: Vec<Series> = runs
        .iter()
        .map(|r| Series {
            name: label(r),
            points: r.samples.iter().map(|s| (s.1, s.2)).collect(),
            markers: false,
        })
        .collect();
    let title = if runs
        .iter()
        .all(|r| r.h == first.h && r.steps == first.steps)
    {
        format!(
            "{}: energy error over {} steps of h = {}",
            first.problem, first.steps, first.h
        )
    } else {
        // Variable-step runs: each its own steps and mean step.
        let t = first.samples.last().map_or(f64::NAN, |s| s.1);
        format!(
            "{}: energy error over t = {t:.0} (steps and mean step of each: long_fit.csv)",
            first.problem
        )
    };
    plot::lines(
        &dir.join("long_energy.svg"),
        &Plot {
            title: &title,
            x_label: "t",
            y_label: "max |E − E₀|/|E₀| (log-spaced windows)",
            log_x: true,
            log_y: true,
            series: &series,
        },
    )
}

/// The printed table: each pair, each run's growth exponent.
pub fn summary(runs: &[LongRun]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Growth exponent of the energy error (slope of log max|ΔE/E| against log t over the last two decades):\n\
         ≈ 1 drift, ≈ 0.5 random walk (Brouwer), ≈ 0 bounded."
    );
    let line = |s: &mut String, r: &LongRun| {
        let last = r.samples.last().map_or(f64::NAN, |x| x.2);
        let _ = writeln!(
            s,
            "  {:<12} {:<12} exponent {:>6}   final max|ΔE/E| {:>9.2e}   {}",
            r.method,
            if r.compensated {
                "compensated"
            } else {
                "plain"
            },
            format::opt(r.exponent, |e| format::fixed(e, 2)),
            last,
            r.status.label()
        );
    };
    let has = |id: &str| runs.iter().any(|r| r.method == id);
    let mut shown: Vec<&str> = Vec::new();
    for (a, b, order) in PAIRS {
        if !(has(a) && has(b)) {
            continue;
        }
        let _ = writeln!(s, "order {order}: {a} (symplectic) vs {b}");
        for id in [a, b] {
            for r in runs.iter().filter(|r| r.method == id) {
                line(&mut s, r);
            }
            shown.push(id);
        }
    }
    let others: Vec<&LongRun> = runs
        .iter()
        .filter(|r| !shown.contains(&r.method.as_str()))
        .collect();
    if !others.is_empty() {
        let _ = writeln!(s, "runs:");
        for r in others {
            line(&mut s, r);
        }
    }
    s
}
