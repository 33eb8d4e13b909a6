//! `symlab cloth SCENE --stability`: the largest stable step of each
//! method on a scene, found by bisection on `h`, beside the linear
//! estimates `2/ω_max` and `2/ω_bound`.
//!
//! A trial runs the scene for a fixed simulated time at one step size, with
//! frames at about 60 Hz (whole steps per frame); it is **stable** when it
//! finishes — no NaN or infinity, every Newton solve converged — and the
//! relative energy error `|H − H₀|/E_ref` stays within the tolerance at
//! every frame (a trial is cut short as soon as it does not). The search
//! starts at `2/ω_max`, doubles or halves until it brackets the threshold,
//! then bisects (in log h) until the bracket is within 1 %; it gives up
//! below a floor (too many steps for a trial) or above a cap (a few steps
//! over the whole run). Stability need not be monotone in `h` (resonances):
//! this finds a threshold, the largest one only if there is one. Methods
//! run in parallel (rayon), one per thread; the time to simulate the
//! duration at the step found is then measured again alone, one method
//! after the other.

use compare::output::csv_field;
use std::fmt::Write as _;
use std::fs;
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, Result, anyhow};
use cloth::implicit as cloth_implicit;
use cloth::{RunError, RunOptions, STEPPABLE, Scene, Simulation};
use rayon::prelude::*;

use super::energy;

/// The default methods: the explicit symplectic ones, explicit Euler, RK4,
/// and the implicit Gauss–Legendre 2, midpoint and implicit Euler.
pub fn default_methods() -> Vec<String> {
    let mut out: Vec<String> = STEPPABLE
        .iter()
        .filter(|id| {
            integrator_core::library::info(id)
                .is_some_and(|i| i.symplectic || i.symplectic_separable)
        })
        .map(|s| s.to_string())
        .collect();
    out.extend(["euler", "rk4", "gauss2", "midpoint", "implicit-euler"].map(String::from));
    out
}

/// Largest number of steps a trial may take (explicit, implicit).
const MAX_STEPS: [f64; 2] = [400_000.0, 20_000.0];
/// The search stops expanding at `duration / MIN_STEPS`.
const MIN_STEPS: f64 = 8.0;
/// Bisect until `hi/lo` is at most this.
const RESOLUTION: f64 = 1.01;

/// How one trial ended.
#[derive(Clone, Debug)]
enum Outcome {
    Stable { max_error: f64 },
    Energy { error: f64, time: f64 },
    Blowup { step: usize, time: f64 },
    Newton { step: usize, time: f64 },
    Other(String),
}

impl Outcome {
    fn stable(&self) -> bool {
        matches!(self, Outcome::Stable { .. })
    }
    fn describe(&self) -> String {
        match self {
            Outcome::Stable { max_error } => format!("stable (error {max_error:.2e})"),
            Outcome::Energy { error, time } if error.is_finite() => {
                format!("energy error {error:.2e} at t = {time:.3} s")
            }
            Outcome::Energy { time, .. } => {
                format!("energy error not finite (overflow) at t = {time:.3} s")
            }
            Outcome::Blowup { step, time } => format!("blew up at step {step} (t = {time:.3} s)"),
            Outcome::Newton { step, time } => {
                format!("Newton failed at step {step} (t = {time:.3} s)")
            }
            Outcome::Other(m) => m.clone(),
        }
    }
}

/// Run options with step exactly `h`, about 60 frames per simulated second
/// (a frame no longer than the duration), covering at least `duration`.
/// The steps of a frame are bounded by the steps of the whole trial, so a
/// tiny duration cannot ask for 1/(60·h) steps (a hang at `--duration
/// 1e-300`).
fn options(h: f64, duration: f64) -> RunOptions {
    let per_frame = (1.0 / 60.0 / h).round().min((duration / h).ceil());
    let substeps = (per_frame.min(MAX_STEPS[0]) as usize).max(1);
    let frame = substeps as f64 * h;
    RunOptions {
        frames: ((duration / frame).ceil() as usize).max(1),
        substeps,
        frame_rate: 1.0 / frame,
    }
}

#[derive(Debug)]
struct EnergyExceeded;
impl std::fmt::Display for EnergyExceeded {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("energy error above the tolerance")
    }
}
impl std::error::Error for EnergyExceeded {}

/// One trial: the outcome and the stepping time.
fn trial(
    scene: &Scene,
    method: &str,
    h: f64,
    duration: f64,
    (tol, e_ref): (f64, f64),
    settings: cloth::minimise::Settings,
) -> (Outcome, f64) {
    let mut sim = match Simulation::new(scene) {
        Ok(s) => s,
        Err(e) => return (Outcome::Other(e.to_string()), 0.0),
    };
    let opts = options(h, duration);
    let mut h0 = None;
    let mut worst: f64 = 0.0;
    let mut over = (0.0, 0.0);
    let result = cloth::minimise::run_any(&mut sim, method, &opts, settings, |frame| {
        let e = frame.stats.energy.total();
        let e0 = *h0.get_or_insert(e);
        let rel = ((e - e0) / e_ref).abs();
        if rel.is_nan() || rel > tol {
            over = (rel, frame.stats.time);
            return Err(Box::new(EnergyExceeded));
        }
        worst = worst.max(rel);
        Ok(())
    });
    match result {
        Ok((report, _)) => (
            Outcome::Stable { max_error: worst },
            report.stepping_seconds,
        ),
        Err(RunError::Callback { .. }) => (
            Outcome::Energy {
                error: over.0,
                time: over.1,
            },
            0.0,
        ),
        Err(RunError::Diverged { step, time, .. }) => (Outcome::Blowup { step, time }, 0.0),
        Err(RunError::Solve { step, time, .. } | RunError::Minimise { step, time, .. }) => {
            (Outcome::Newton { step, time }, 0.0)
        }
        Err(e) => (Outcome::Other(e.to_string()), 0.0),
    }
}

/// What the search found for one method.
#[derive(Clone, Debug)]
struct Found {
    method: String,
    /// The largest step found stable, if any.
    h: Option<f64>,
    /// Why the next larger step failed (or why none was found).
    limit: String,
    /// `"bracketed"`, `"at the cap"` or `"below the floor"`.
    status: &'static str,
    max_error: f64,
    trials: usize,
    /// Stepping time per simulated second at `h`, measured alone (s).
    seconds: Option<f64>,
}

fn search(
    scene: &Scene,
    method: &str,
    h_lin: f64,
    duration: f64,
    (tol, e_ref): (f64, f64),
    settings: cloth::minimise::Settings,
) -> Found {
    let implicit = cloth_implicit::is_implicit(method) || cloth::minimise::is_minimisation(method);
    let floor = duration / MAX_STEPS[implicit as usize];
    let cap = duration / MIN_STEPS;
    let mut trials = 0;
    let mut test = |h: f64| {
        trials += 1;
        trial(scene, method, h, duration, (tol, e_ref), settings).0
    };
    let start = h_lin.clamp(floor, cap);
    let first = test(start);
    let (mut lo, mut hi, mut lo_out, mut hi_out);
    if first.stable() {
        lo = start;
        lo_out = first;
        loop {
            let h = (lo * 2.0).min(cap);
            if h <= lo {
                return finish(
                    method,
                    Some(lo),
                    "at the cap",
                    format!("stable up to the cap {cap:.3e} s"),
                    &lo_out,
                    trials,
                );
            }
            let o = test(h);
            if o.stable() {
                lo = h;
                lo_out = o;
            } else {
                hi = h;
                hi_out = o;
                break;
            }
        }
    } else {
        hi = start;
        hi_out = first;
        loop {
            let h = (hi / 2.0).max(floor);
            if h >= hi {
                let limit = format!(
                    "unstable down to the floor {floor:.3e} s: {}",
                    hi_out.describe()
                );
                return finish(method, None, "below the floor", limit, &hi_out, trials);
            }
            let o = test(h);
            if o.stable() {
                lo = h;
                lo_out = o;
                break;
            }
            hi = h;
            hi_out = o;
        }
    }
    while hi / lo > RESOLUTION {
        let h = (lo * hi).sqrt();
        let o = test(h);
        if o.stable() {
            lo = h;
            lo_out = o;
        } else {
            hi = h;
            hi_out = o;
        }
    }
    finish(
        method,
        Some(lo),
        "bracketed",
        hi_out.describe(),
        &lo_out,
        trials,
    )
}

fn finish(
    method: &str,
    h: Option<f64>,
    status: &'static str,
    limit: String,
    at: &Outcome,
    trials: usize,
) -> Found {
    Found {
        method: method.to_string(),
        h,
        limit,
        status,
        max_error: match at {
            Outcome::Stable { max_error } => *max_error,
            _ => f64::NAN,
        },
        trials,
        seconds: None,
    }
}

pub fn run(
    scene: &Scene,
    file: &str,
    methods: &[String],
    tol: f64,
    duration: f64,
    dir: &Path,
    settings: cloth::minimise::Settings,
) -> Result<ExitCode> {
    let sim = Simulation::new(scene).map_err(|e| match e {
        cloth::SceneError::Field { field, message, .. } => anyhow!("{file}: {field}: {message}"),
        other => anyhow!("{other}"),
    })?;
    let e_ref =
        energy::reference_energy_checked(scene, &sim).map_err(|e| anyhow!("{file}: {e}"))?;
    let stab = sim.model.stability();
    let h_lin = stab.h_max;
    let h_bound = 2.0 / stab.omega_bound;
    let clock = Instant::now();
    let mut found: Vec<Found> = methods
        .par_iter()
        .map(|m| search(scene, m, h_lin, duration, (tol, e_ref), settings))
        .collect();
    let search_seconds = clock.elapsed().as_secs_f64();
    // Time each method alone at its step.
    for f in &mut found {
        if let Some(h) = f.h {
            let (o, secs) = trial(scene, &f.method, h, duration, (tol, e_ref), settings);
            if o.stable() {
                let opts = options(h, duration);
                f.seconds = Some(secs / (opts.frames as f64 * opts.substeps as f64 * h));
            }
        }
    }
    let (nx, ny) = sim.model.grid();
    let mut out = String::new();
    let _ = writeln!(
        out,
        "largest stable step: {} ({file}), {nx} × {ny} particles, {duration} s simulated per trial",
        scene.name
    );
    let _ = writeln!(
        out,
        "stable = no NaN, Newton converged, |H − H₀|/E_ref ≤ {tol} at every frame (E_ref = {e_ref:.4e} J)"
    );
    // No positive eigenvalue of M⁻¹K (ω = 0): no linear estimate; the
    // search then starts at its cap.
    let estimate = |h: f64| {
        if h.is_finite() {
            format!("{h:.4e} s")
        } else {
            "n/a (no positive eigenvalue of M⁻¹K)".to_string()
        }
    };
    let _ = writeln!(
        out,
        "linear estimates at the initial state: 2/ω_max = {} (ω_max = {:.1} rad/s), 2/ω_bound = {} (Gershgorin)",
        estimate(h_lin),
        stab.omega_max,
        estimate(h_bound)
    );
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "{:<22} {:>5} {:>4} {:>11} {:>8} {:>8} {:>10} {:>12}  limit above it",
        "method", "kind", "ord", "h stable", "h·ω/2", "steps/fr", "error", "wall s / 1s"
    );
    let mut csv = String::from(
        "method,explicit,symplectic,order,h_stable,h_over_linear,substeps_per_60hz_frame,status,max_relative_error,trials,wall_seconds_per_simulated_second,h_linear,h_bound,tolerance,duration,name,limit\n",
    );
    for f in &found {
        let info = integrator_core::library::info(&f.method);
        let (explicit, symp, order, name) = match (info, cloth::minimise::energy_scheme(&f.method))
        {
            (Some(i), _) => (
                i.explicit,
                i.symplectic || i.symplectic_separable,
                i.order,
                i.name,
            ),
            (None, Some((name, order))) => (false, false, order, name),
            (None, None) => (true, false, 0, ""),
        };
        let kind = format!(
            "{}{}",
            if explicit { "E" } else { "I" },
            if symp { "S" } else { "" }
        );
        let h_text = match (f.h, f.status) {
            (Some(h), "at the cap") => format!("≥{h:.3e}"),
            (Some(h), _) => format!("{h:.3e}"),
            (None, _) => "—".to_string(),
        };
        let ratio =
            f.h.filter(|_| h_lin.is_finite())
                .map_or(String::from("—"), |h| format!("{:.3}", h / h_lin));
        let substeps = f.h.map_or(String::from("—"), |h| {
            format!("{}", (1.0 / 60.0 / h).ceil() as usize)
        });
        let err = if f.max_error.is_finite() {
            format!("{:.2e}", f.max_error)
        } else {
            "—".into()
        };
        let secs = f.seconds.map_or(String::from("—"), |s| format!("{s:.4}"));
        let _ = writeln!(
            out,
            "{:<22} {:>5} {:>4} {:>11} {:>8} {:>8} {:>10} {:>12}  {}",
            f.method, kind, order, h_text, ratio, substeps, err, secs, f.limit
        );
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            csv_field(&f.method),
            explicit,
            symp,
            order,
            f.h.map_or(String::new(), |h| format!("{h:e}")),
            f.h.filter(|_| h_lin.is_finite())
                .map_or(String::new(), |h| format!("{}", h / h_lin)),
            f.h.map_or(String::new(), |h| format!(
                "{}",
                (1.0 / 60.0 / h).ceil() as usize
            )),
            f.status,
            if f.max_error.is_finite() {
                format!("{:e}", f.max_error)
            } else {
                String::new()
            },
            f.trials,
            f.seconds.map_or(String::new(), |s| format!("{s}")),
            // Empty, not "inf", where there is no linear estimate.
            Some(h_lin)
                .filter(|h| h.is_finite())
                .map_or(String::new(), |h| format!("{h:e}")),
            Some(h_bound)
                .filter(|h| h.is_finite())
                .map_or(String::new(), |h| format!("{h:e}")),
            tol,
            duration,
            csv_field(name),
            csv_field(&f.limit),
        );
    }
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "kind: E explicit, I implicit, S symplectic; h·ω/2 = h/(2/ω_max); steps/fr = steps per 60 Hz frame; error = max relative energy error at the step found; wall s / 1s = stepping time per simulated second at that step, one method at a time on one core"
    );
    let path = dir.join("stability.csv");
    fs::write(&path, csv).with_context(|| format!("{}: cannot write", path.display()))?;
    let _ = writeln!(
        out,
        "search: {} trials in {search_seconds:.1} s (methods in parallel); table in {}",
        found.iter().map(|f| f.trials).sum::<usize>(),
        path.display()
    );
    print!("{out}");
    Ok(ExitCode::SUCCESS)
}
