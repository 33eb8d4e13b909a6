//! `--hard`: the largest stable step of every method on three hard
//! problems, by bisection.
//!
//! **Criterion.** A step size `h` is *stable* on a problem when the run from
//! the problem's start to its fixed end time `T` (`n = ⌈T/h⌉` steps of size
//! `T/n`) completes — no stage-solver failure, every state finite — with
//! `max |E(t) − E₀|/|E₀| ≤ 0.1` over all steps. The search starts at a
//! problem-specific `h₀`, doubles (or halves) until the verdict changes,
//! then bisects geometrically until the bracket is within 1 %. It assumes a
//! single threshold: where stability is not monotone in `h` (resonances),
//! it reports one of the thresholds, always a verified stable `h`. Steps
//! above `T` (one step) are not tried; steps below `T/10⁶` neither.

use std::fmt::Write as _;
use std::path::Path;

use integrator_core::search::{StepCounts, largest_passing};
use rayon::prelude::*;

use crate::error::{CompareError, Result, write as write_file};
use crate::method::Fixed;
use crate::problem::{Problem, Setup};
use crate::stepper::Status;

/// The energy-error bound of the criterion.
pub const BOUND: f64 = 0.1;

/// A hard case: the problem, its end time, the first step tried and the
/// largest frequency (for `h·ω_max`).
pub struct Case<P: Problem> {
    pub name: &'static str,
    pub setup: Setup<P>,
    pub h0: f64,
    pub omega_max: Option<f64>,
    /// A line for the report: what the case is.
    pub note: String,
}

/// The stiff FPU chain (ω = 50) over T = 10.
pub fn fpu_case() -> Result<Case<integrator_core::problems::Fpu>> {
    let name = "fpu (ω = 50)";
    let setup = crate::builtin::fpu(10.0, false)?;
    let omega = setup.sys.omega;
    Ok(Case {
        name,
        note: format!("{name}: T = 10, h·ω_max with ω_max = {omega}"),
        setup,
        h0: 0.01,
        omega_max: Some(omega),
    })
}

/// Kepler with e = 0.9 over 10 orbits.
pub fn kepler_case() -> Result<Case<integrator_core::problems::Kepler>> {
    let name = "kepler (e = 0.9)";
    let t = 20.0 * std::f64::consts::PI;
    Ok(Case {
        name,
        note: format!("{name}: T = 20π (10 orbits); no single frequency, so no h·ω_max"),
        setup: crate::builtin::kepler(true, t, false)?,
        h0: 0.01,
        omega_max: None,
    })
}

/// A stiff linear gyroscopic system, frequencies 1 … 10⁴, over T = 1.
pub fn gyroscopic_case() -> Result<Case<integrator_core::linear::LinearHamiltonian>> {
    let name = "gyroscopic (n = 10, spread 1e4)";
    let setup = crate::builtin::gyroscopic(10, 1, 1e4, 1.0, false)?;
    let omega = crate::builtin::omega_max(&setup.sys);
    Ok(Case {
        name,
        note: format!(
            "{name}: gyroscopic(10, seed 1, spread 1e4), q(0) = 0, p(0) = 1, T = 1, ω_max = {omega:.2} (power iteration)"
        ),
        setup,
        h0: 1e-4,
        omega_max: Some(omega),
    })
}

/// What lies just beyond the largest stable step.
#[derive(Clone, Debug, PartialEq)]
pub enum Beyond {
    Diverged,
    EnergyAboveBound,
    SolverFailed(String),
    /// The method or the problem panicked (the status label, which names
    /// the step and the message).
    Panicked(String),
}

impl Beyond {
    pub fn label(&self) -> String {
        match self {
            Beyond::Diverged => "diverged".into(),
            Beyond::EnergyAboveBound => format!("energy error above {BOUND}"),
            Beyond::SolverFailed(why) => format!("solver failed ({why})"),
            Beyond::Panicked(label) => label.clone(),
        }
    }
}

/// One method's result.
pub struct HardRow {
    pub problem: String,
    pub method: String,
    pub order: usize,
    pub symplectic: bool,
    pub t_end: f64,
    /// The largest step verified stable; `None` if none down to `T/10⁶`.
    pub h_stable: Option<f64>,
    /// The smallest step found unstable with what happened there; `None`
    /// if stable up to `h = T`.
    pub h_unstable: Option<(f64, Beyond)>,
    pub omega_max: Option<f64>,
    /// Runs made by the search.
    pub probes: usize,
}

/// `Ok(())` if `n` steps over `T` are stable, else what went wrong.
fn probe<P: Problem>(setup: &Setup<P>, f: &Fixed<P>, n: u64) -> Result<(), Beyond> {
    let h = setup.t_end / n as f64;
    let mut z = setup.z0.clone();
    let outcome = crate::stepper::observed_caught(
        &*f.stepper,
        &setup.sys,
        &mut z,
        h,
        n as usize,
        true,
        &mut |_, _, z| {
            let de = setup.energy_error(z);
            de.is_finite() && de <= BOUND
        },
    );
    match outcome.status {
        Status::Ok => Ok(()),
        Status::Diverged { .. } => Err(Beyond::Diverged),
        Status::Stopped { .. } => {
            if z.iter().all(|x| x.is_finite()) {
                Err(Beyond::EnergyAboveBound)
            } else {
                Err(Beyond::Diverged)
            }
        }
        Status::SolverFailed { reason, .. } => Err(Beyond::SolverFailed(short(&reason))),
        s @ Status::Panicked { .. } => Err(Beyond::Panicked(s.label())),
    }
}

/// The solver's message up to its first parenthesis (the numbers in it vary
/// from step to step).
fn short(reason: &str) -> String {
    reason
        .split(" (")
        .next()
        .unwrap_or(reason)
        .trim()
        .to_string()
}

/// The search for one method ([`integrator_core::search::largest_passing`]
/// over step counts). `tolerance`: stop when `h_hi/h_lo ≤ 1 + tolerance`
/// (or the counts are adjacent). Bounded as [`run_case`] says.
pub fn search<P: Problem>(
    case: &Case<P>,
    f: &Fixed<P>,
    tolerance: f64,
    floor: f64,
) -> Result<HardRow> {
    check(case, tolerance, floor)?;
    let t = case.setup.t_end;
    let steps = |h: f64| ((t / h).ceil() as u64).max(1);
    // In step counts over T (step T/n), so every probe is a whole number of
    // steps: one step at most, `T/floor` at least.
    let ladder = StepCounts {
        max: steps(floor * t),
        tolerance,
    };
    let found = largest_passing(&ladder, steps(case.h0), |n| probe(&case.setup, f, n));
    Ok(HardRow {
        problem: case.name.into(),
        method: f.id.clone(),
        order: f.order,
        symplectic: f.symplectic,
        t_end: t,
        h_stable: found.passed.map(|(n, ())| t / n as f64),
        h_unstable: found.failed.map(|(n, b)| (t / n as f64, b)),
        omega_max: case.omega_max,
        probes: found.probes,
    })
}

/// Every method on one case, in parallel across methods.
///
/// The search is bounded before it starts: `case.h0` a finite step in
/// `(0, T]` with at most [`MAX_PROBE_STEPS`] steps over `T`, `floor` (the
/// smallest step tried, relative to `T`) in `(0, 1]` with `1/floor` at most
/// [`MAX_PROBE_STEPS`], `tolerance` finite and > 0; anything else is an
/// error naming the setting, not a search of `u64::MAX` steps.
pub fn run_case<P: Problem>(
    case: &Case<P>,
    methods: &[Fixed<P>],
    tolerance: f64,
    floor: f64,
) -> Result<Vec<HardRow>> {
    check(case, tolerance, floor)?;
    methods
        .par_iter()
        .map(|f| search(case, f, tolerance, floor))
        .collect()
}

/// The bounds of [`run_case`] and [`search`].
fn check<P: Problem>(case: &Case<P>, tolerance: f64, floor: f64) -> Result<()> {
    let t = case.setup.t_end;
    if !(case.h0.is_finite() && case.h0 > 0.0 && case.h0 <= t && t / case.h0 <= MAX_PROBE_STEPS) {
        return Err(CompareError::setting(
            "h0",
            format!(
                "the first step must be finite, in (0, T = {t}] and at most {MAX_PROBE_STEPS:e} steps over T, got {}",
                case.h0
            ),
        ));
    }
    if !(floor.is_finite() && floor > 0.0 && floor <= 1.0 && 1.0 / floor <= MAX_PROBE_STEPS) {
        return Err(CompareError::setting(
            "floor",
            format!(
                "the smallest step relative to T must be in [1/{MAX_PROBE_STEPS:e}, 1], got {floor}"
            ),
        ));
    }
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(CompareError::setting(
            "tolerance",
            format!("the bisection's relative width must be finite and > 0, got {tolerance}"),
        ));
    }
    Ok(())
}

/// The most steps of one probe of the stability search: 10⁸.
pub const MAX_PROBE_STEPS: f64 = 1e8;

fn h_label(r: &HardRow) -> String {
    match (&r.h_stable, &r.h_unstable) {
        (Some(h), Some(_)) => format!("{h:.4e}"),
        (Some(h), None) => format!("≥ {h:.4e} (= T)"),
        (None, Some((h, _))) => format!("none ≥ {h:.1e}"),
        (None, None) => "—".into(),
    }
}

fn h_omega(r: &HardRow) -> String {
    match (r.h_stable, r.omega_max) {
        (Some(h), Some(w)) => format!("{:.3}", h * w),
        _ => "—".into(),
    }
}

fn beyond(r: &HardRow) -> String {
    r.h_unstable
        .as_ref()
        .map_or("stable at every h tried".into(), |(_, b)| b.label())
}

/// `hard.csv` and `hard.md`.
pub fn write(dir: &Path, rows: &[HardRow], notes: &[String]) -> Result<()> {
    use crate::output::csv_field;
    let mut s = String::from(
        "problem,method,order,symplectic,t_end,h_stable,h_unstable,h_omega_max,beyond,probes\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{:e},{:e},{:e},{:e},{},{}",
            csv_field(&r.problem),
            csv_field(&r.method),
            r.order,
            r.symplectic,
            r.t_end,
            r.h_stable.unwrap_or(f64::NAN),
            r.h_unstable.as_ref().map_or(f64::NAN, |x| x.0),
            match (r.h_stable, r.omega_max) {
                (Some(h), Some(w)) => h * w,
                _ => f64::NAN,
            },
            csv_field(&beyond(r)),
            r.probes
        );
    }
    let path = dir.join("hard.csv");
    write_file(&path, s)?;
    let path = dir.join("hard.md");
    write_file(&path, markdown(rows, notes))
}

/// The Markdown table (also printed).
pub fn markdown(rows: &[HardRow], notes: &[String]) -> String {
    let mut s = String::from("# Largest stable step\n\n");
    let _ = writeln!(
        s,
        "Stable: the run to the end time T completes (no solver failure, finite states) with \
         max |E − E₀|/|E₀| ≤ {BOUND}. Bisection to 1 % from a problem-specific start.\n"
    );
    for n in notes {
        let _ = writeln!(s, "- {n}");
    }
    s.push('\n');
    s.push_str("| problem | method | order | symplectic | largest stable h | h·ω_max | beyond |\n");
    s.push_str("|---|---|---:|---|---:|---:|---|\n");
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} |",
            r.problem,
            r.method,
            r.order,
            if r.symplectic { "yes" } else { "no" },
            h_label(r),
            h_omega(r),
            beyond(r)
        );
    }
    s
}
