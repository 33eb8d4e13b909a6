//! The stability study of a scene (`symlab cloth SCENE --stability`): the
//! largest stable step of each method ([`cloth::study::stability`]
//! searches), beside the linear estimates `2/ω_max` and `2/ω_bound`, as a
//! table to print and `stability.csv`.
//!
//! Methods are searched in parallel (rayon), one per thread; the time to
//! simulate the duration at the step found is then measured again alone,
//! one method after the other.

use std::fmt::Write as _;
use std::fs;
use std::path::PathBuf;
use std::time::Instant;

use cloth::study::energy::reference_energy;
use cloth::study::stability::{
    Found, Outcome, Scales, StabilityError, StabilitySettings, Status, search,
    seconds_per_simulated_second,
};
use cloth::{Method, MinimiseSettings, Simulation};
use compare::format::{self, MISSING};
use compare::output::csv_field;
use rayon::prelude::*;

use super::plan::{Source, applicable, output_dir, rename, solver, solver_applies};
use super::request::{Field, InputError, JobError, Origin, Request, SceneSource};

pub use cloth::study::stability::default_methods;

/// The stability study as asked: the scene (at `grid`), the methods
/// (default [`default_methods`]), the simulated seconds per trial, the
/// largest relative energy error a stable run may show, and the
/// minimisation solver of the methods that need one.
#[derive(Clone, Debug)]
pub struct StabilityRequest {
    pub scene: SceneSource,
    pub grid: Option<String>,
    pub out: Option<PathBuf>,
    pub methods: Option<Vec<String>>,
    pub duration: f64,
    pub tolerance: Option<f64>,
    pub solver: Option<String>,
}

/// How a trial ended, in words.
fn describe(outcome: &Outcome) -> String {
    match outcome {
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

/// Why the next larger step failed (or why none was found).
fn limit(f: &Found) -> String {
    let beyond = f.beyond.as_ref().map_or(String::new(), describe);
    match f.status {
        Status::Bracketed => beyond,
        Status::AtCap => format!("stable up to the cap {:.3e} s", f.cap),
        Status::BelowFloor => format!("unstable down to the floor {:.3e} s: {beyond}", f.floor),
    }
}

/// The status as `stability.csv` writes it.
fn status(s: Status) -> &'static str {
    match s {
        Status::Bracketed => "bracketed",
        Status::AtCap => "at the cap",
        Status::BelowFloor => "below the floor",
    }
}

/// Search the largest stable step of each method (in parallel), time
/// each at its step (alone), write `stability.csv`; the table to print.
pub fn run(asked: &StabilityRequest) -> Result<String, JobError> {
    let request = Request {
        grid: asked.grid.clone(),
        out: asked.out.clone(),
        solver: asked.solver.clone(),
        ..Request::new(asked.scene.clone())
    };
    let file = asked.scene.file_name();
    let scene = super::plan::load(&request)?.0;
    let study = StabilitySettings {
        duration: asked.duration,
        tolerance: asked
            .tolerance
            .unwrap_or(StabilitySettings::default().tolerance),
        minimise: MinimiseSettings::new(solver(asked.solver.as_deref())?),
        ..StabilitySettings::default()
    };
    study.check().map_err(|e| match e {
        StabilityError::Setting { field, message } => InputError {
            origin: Origin::Field(
                match field {
                    "duration" => Field::Duration,
                    "tolerance" => Field::Tolerance,
                    _ => Field::Stability,
                },
                None,
            ),
            message,
        },
        other => InputError::field(Field::Stability, other.to_string()),
    })?;
    let methods = match &asked.methods {
        Some(names) => {
            if names.is_empty() {
                return Err(InputError::field(Field::Methods, "no method given").into());
            }
            names
                .iter()
                .map(|m| {
                    Method::parse(m).map_err(|e| InputError::field(Field::Methods, e.to_string()))
                })
                .collect::<Result<Vec<_>, _>>()?
        }
        None => default_methods(),
    };
    for m in &methods {
        applicable(
            m,
            &Source::Field(Field::Methods, m.id().to_string()),
            &scene,
            &file,
            study.minimise.solver,
        )?;
    }
    solver_applies(asked.solver.as_deref(), &methods)?;
    let dir = output_dir(&request, &scene)?;
    let scene = &scene;
    let sim = Simulation::new(scene).map_err(|e| JobError::Scene(rename(&e, &file)))?;
    let e_ref =
        reference_energy(scene, &sim).map_err(|e| InputError::scene(&file, None, e.to_string()))?;
    let stab = sim.model.stability();
    let h_lin = stab.h_max;
    let h_bound = 2.0 / stab.omega_bound;
    let scales = Scales {
        e_ref,
        h_linear: h_lin,
    };
    let clock = Instant::now();
    let found: Vec<Found> = methods
        .par_iter()
        .map(|m| search(scene, m, &scales, &study))
        .collect();
    let search_seconds = clock.elapsed().as_secs_f64();
    // Time each method alone at its step.
    let seconds: Vec<Option<f64>> = found
        .iter()
        .map(|f| {
            f.h.and_then(|h| seconds_per_simulated_second(scene, &f.method, h, e_ref, &study))
        })
        .collect();
    let (nx, ny) = sim.model.grid();
    let (tol, duration) = (study.tolerance, study.duration);
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
    for (f, secs) in found.iter().zip(&seconds) {
        let m = &f.method;
        let kind = format!(
            "{}{}",
            if m.explicit() { "E" } else { "I" },
            if m.symplectic() { "S" } else { "" }
        );
        let h_text = match (f.h, f.status) {
            (Some(h), Status::AtCap) => format!("≥{h:.3e}"),
            (Some(h), _) => format!("{h:.3e}"),
            (None, _) => MISSING.to_string(),
        };
        let over_linear = f.h.filter(|_| h_lin.is_finite()).map(|h| h / h_lin);
        let substeps = f.h.map(|h| (1.0 / 60.0 / h).ceil() as usize);
        let limit = limit(f);
        let _ = writeln!(
            out,
            "{:<22} {:>5} {:>4} {:>11} {:>8} {:>8} {:>10} {:>12}  {}",
            m.id(),
            kind,
            m.order(),
            h_text,
            format::opt(over_linear, |r| format::fixed(r, 3)),
            substeps.map_or(MISSING.to_string(), |n| n.to_string()),
            format::sci(f.max_error, 2),
            format::opt(*secs, |s| format::fixed(s, 4)),
            limit
        );
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            csv_field(m.id()),
            m.explicit(),
            m.symplectic(),
            m.order(),
            f.h.map_or(String::new(), |h| format!("{h:e}")),
            over_linear.map_or(String::new(), |r| format!("{r}")),
            substeps.map_or(String::new(), |n| format!("{n}")),
            status(f.status),
            if f.max_error.is_finite() {
                format!("{:e}", f.max_error)
            } else {
                String::new()
            },
            f.trials,
            secs.map_or(String::new(), |s| format!("{s}")),
            // Empty, not "inf", where there is no linear estimate.
            Some(h_lin)
                .filter(|h| h.is_finite())
                .map_or(String::new(), |h| format!("{h:e}")),
            Some(h_bound)
                .filter(|h| h.is_finite())
                .map_or(String::new(), |h| format!("{h:e}")),
            tol,
            duration,
            csv_field(m.name()),
            csv_field(&limit),
        );
    }
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "kind: E explicit, I implicit, S symplectic; h·ω/2 = h/(2/ω_max); steps/fr = steps per 60 Hz frame; error = max relative energy error at the step found; wall s / 1s = stepping time per simulated second at that step, one method at a time on one core"
    );
    let path = dir.join("stability.csv");
    fs::write(&path, csv).map_err(|e| JobError::io(&path, "cannot write", e))?;
    let _ = writeln!(
        out,
        "search: {} trials in {search_seconds:.1} s (methods in parallel); table in {}",
        found.iter().map(|f| f.trials).sum::<usize>(),
        path.display()
    );
    Ok(out)
}
