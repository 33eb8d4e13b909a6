//! One REBOUND run: the request, the answer as the problem's states, and
//! the sweep's row measured with the project's error and energy measures.

use serde_json::{Value, json};

use super::{Bodies, ENERGY_SAMPLES, Point, ReboundMethod, hex, request, state_of};
use crate::problem::{Family, Problem, Setup};
use crate::row::{Row, median};

/// What one REBOUND run gave.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The problem's state at the end.
    pub end: Vec<f64>,
    /// The problem's state at the sampled points of the observed run.
    pub samples: Vec<Vec<f64>>,
    pub steps: u64,
    /// Wall times of the timed `integrate` calls, seconds.
    pub times: Vec<f64>,
    /// The timed runs ended on the warm-up's bits.
    pub reproducible: bool,
    pub version: String,
}

/// One REBOUND run of `m` on `bodies` over `[0, t_end]` at `point`:
/// observed, warmed up and timed `repeats` times in one process.
pub fn run_bodies(
    bodies: &Bodies,
    m: &ReboundMethod,
    t_end: f64,
    point: Point,
    h_guess: f64,
    repeats: usize,
) -> std::result::Result<Outcome, String> {
    let (steps, tolerance, dt) = match point {
        Point::Steps(n) => (json!(n), Value::Null, t_end / n as f64),
        Point::Tolerance(t) => (Value::Null, json!(hex(t)), h_guess),
    };
    let req = json!({
        "run": bodies.request(),
        "integrator": m.integrator,
        "settings": m.settings.iter().map(|(k, v)| json!([k, v])).collect::<Vec<_>>(),
        "steps": steps,
        "tolerance": tolerance,
        "dt": hex(dt),
        "t_end": hex(t_end),
        "repeats": repeats,
        "samples": ENERGY_SAMPLES,
    });
    let a = request(&m.python, &req).map_err(|f| f.message)?;
    let end = state_of(bodies, &a)?;
    let samples = a["samples"]
        .as_array()
        .map(|s| s.iter().map(|x| state_of(bodies, x)).collect())
        .unwrap_or_else(|| Ok(vec![]))?;
    // One wall time per timed run, each a finite number of seconds ≥ 0: an
    // answer with fewer, or with anything else in their place, has no
    // timing to report (a NaN time beside "ok" would be nonsense).
    let times: Vec<f64> = match a["times"].as_array() {
        Some(t) => t
            .iter()
            .map(|x| x.as_f64().filter(|s| s.is_finite() && *s >= 0.0))
            .collect::<Option<Vec<f64>>>()
            .ok_or_else(|| {
                format!(
                    "the REBOUND script's timings {} are not all finite times in seconds",
                    a["times"]
                )
            })?,
        None => return Err("the REBOUND script's answer has no timings (`times`)".into()),
    };
    if times.is_empty() || times.len() != repeats {
        return Err(format!(
            "the REBOUND script returned {} timings for {repeats} timed runs",
            times.len()
        ));
    }
    Ok(Outcome {
        end,
        samples,
        steps: a["steps"].as_u64().unwrap_or(0),
        times,
        reproducible: a["reproducible"] == json!(true),
        version: a["rebound"].as_str().unwrap_or("unknown").to_string(),
    })
}

/// One row of a sweep: `m` on `setup` at `point`, the error measured here
/// against the setup's reference, the energy error over the sampled states
/// and the end, the median of the timed `integrate` calls. `h_guess` is the
/// first step of an adaptive integrator.
pub fn row<P: Problem>(
    setup: &Setup<P>,
    m: &ReboundMethod,
    point: Point,
    h_guess: f64,
    repeats: usize,
) -> Row {
    let mut row = Row {
        problem: setup.name.clone(),
        method: m.id.clone(),
        family: Family::Rebound,
        order: m.order,
        symplectic: m.symplectic,
        h: f64::NAN,
        tol: f64::NAN,
        steps: 0,
        error: f64::NAN,
        energy_error: f64::NAN,
        time_s: f64::NAN,
        evals: 0,
        newton_iterations: 0,
        fixed_point_iterations: 0,
        factorizations: 0,
        status: String::new(),
        interpreted: false,
    };
    match point {
        Point::Steps(n) => {
            row.steps = n;
            row.h = setup.t_end / n as f64;
        }
        Point::Tolerance(t) => row.tol = t,
    }
    let bodies = match setup.sys.rebound_bodies(&setup.z0) {
        Some(Ok(b)) => b,
        Some(Err(why)) => {
            row.status = format!("not run: {why}");
            return row;
        }
        None => {
            row.status = "not run: the problem has no bodies for REBOUND".into();
            return row;
        }
    };
    let outcome = match run_bodies(&bodies, m, setup.t_end, point, h_guess, repeats) {
        Ok(o) => o,
        Err(why) => {
            row.status = format!("rebound failed: {why}");
            return row;
        }
    };
    row.steps = outcome.steps;
    if outcome.steps > 0 {
        row.h = setup.t_end / outcome.steps as f64;
    }
    row.energy_error = outcome
        .samples
        .iter()
        .chain(std::iter::once(&outcome.end))
        .map(|z| setup.energy_error(z))
        .fold(0.0, f64::max);
    let error = setup.error(&outcome.end);
    if !(error.is_finite() && row.energy_error.is_finite()) {
        row.status = format!(
            "diverged at step {}: the error or the energy is not finite",
            outcome.steps
        );
    } else if !outcome.reproducible {
        row.status = "rebound failed: the timed runs did not end on the warm-up's bits".into();
    } else {
        row.error = error;
        row.time_s = median(outcome.times);
        row.status = "ok".into();
    }
    row
}
