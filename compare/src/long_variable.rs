//! `--long --problem kepler-hard`: the variable-step methods over 10⁴
//! orbits of Kepler e = 0.9 at equal work — the time-transformed
//! `logh:kahan-li8`, the reversible adaptive `adaptive:kahan-li8`, and
//! DOP853 — with the energy error recorded in log-spaced windows of time
//! and its growth exponent fitted as for the fixed-step pairs
//! ([`long`](crate::long)).
//!
//! Equal work: each method is calibrated on 10 orbits to
//! [`VariableSettings::evals_per_orbit`] force evaluations per orbit (ours:
//! the first step `h` rescaled twice, the evaluations being about
//! proportional to `1/h`; DOP853: the tolerance among 1e-4 … 1e-16, one per
//! quarter decade, whose evaluations per orbit are nearest). DOP853 runs
//! the whole interval in chunks of [`CHUNK_ORBITS`] orbits, each a new call
//! from the end state of the last (its stored states are what the energy is
//! measured on, and 10⁴ orbits of them at once would take hundreds of MB);
//! each restart re-estimates the first step, nothing else.

use std::f64::consts::PI;

use integrator_core::problems::Kepler;

use crate::builtin;
use crate::error::{CompareError, Result};
use crate::long::{LongRun, growth_exponent};
use crate::method::Method;
use crate::peer::dop853_observed;
use crate::stepper::Status;

/// The methods of ours in the study.
pub const METHODS: [&str; 2] = ["logh:kahan-li8", "adaptive:kahan-li8"];
/// Orbits per DOP853 call.
pub const CHUNK_ORBITS: f64 = 100.0;
/// The most orbits of the study: 10⁵ (ten times the full study; at most
/// 10¹¹ force evaluations per method).
pub const MAX_ORBITS: f64 = 1e5;
/// Energy-error windows per decade of time.
const PER_DECADE: f64 = 20.0;

/// The study's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VariableSettings {
    pub e: f64,
    pub orbits: f64,
    /// The work of every method: force evaluations per orbit (DOP853: its
    /// right-hand-side evaluations, each one force evaluation).
    pub evals_per_orbit: f64,
}

impl VariableSettings {
    /// e = 0.9, 10⁴ orbits, 4000 evaluations per orbit (DOP853 then runs
    /// near rtol 1e-10, our kahan-li8 at ~235 steps per orbit).
    pub fn full() -> Self {
        VariableSettings {
            e: 0.9,
            orbits: 1e4,
            evals_per_orbit: 4000.0,
        }
    }
    /// 100 orbits.
    pub fn quick() -> Self {
        VariableSettings {
            orbits: 100.0,
            ..Self::full()
        }
    }
}

/// Window ends in time: 20 per decade from 1 orbit to `t_end`.
fn time_windows(t_end: f64) -> Vec<f64> {
    let t0 = 2.0 * PI;
    let decades = (t_end / t0).log10().max(0.0);
    let n = (decades * PER_DECADE).ceil() as usize;
    let mut v: Vec<f64> = (0..n)
        .map(|j| t0 * 10f64.powf(j as f64 / PER_DECADE))
        .collect();
    v.push(t_end);
    v
}

/// Records `max |ΔE/E|` per window of time.
struct Windows<'a> {
    ends: &'a [f64],
    next: usize,
    window: f64,
    samples: Vec<(u64, f64, f64)>,
    step: u64,
}

impl Windows<'_> {
    fn see(&mut self, t: f64, err: f64) {
        self.step += 1;
        self.window = self.window.max(err);
        while self.next < self.ends.len() && t >= self.ends[self.next] * (1.0 - 1e-12) {
            self.samples.push((self.step, t, self.window));
            self.window = 0.0;
            self.next += 1;
        }
    }
}

/// Run the study.
pub fn run(settings: VariableSettings) -> Result<Vec<LongRun>> {
    if !(settings.orbits.is_finite() && (10.0..=MAX_ORBITS).contains(&settings.orbits)) {
        return Err(CompareError::setting(
            "orbits",
            format!(
                "between 10 and {MAX_ORBITS:e} orbits, got {}",
                settings.orbits
            ),
        ));
    }
    if !(settings.e.is_finite() && (0.0..1.0).contains(&settings.e)) {
        return Err(CompareError::setting(
            "e",
            format!("a bound Kepler orbit needs 0 ≤ e < 1, got {}", settings.e),
        ));
    }
    if !(settings.evals_per_orbit.is_finite() && (100.0..=1e6).contains(&settings.evals_per_orbit))
    {
        return Err(CompareError::setting(
            "evals_per_orbit",
            format!(
                "between 100 and 10⁶ force evaluations per orbit, got {}",
                settings.evals_per_orbit
            ),
        ));
    }
    let sys = Kepler { e: settings.e };
    let t_end = settings.orbits * 2.0 * PI;
    let long = builtin::kepler(settings.e == 0.9, t_end, false)?;
    let calib = builtin::kepler(settings.e == 0.9, 20.0 * PI, false)?;
    let ends = time_windows(t_end);
    let mut runs = Vec::new();
    for id in METHODS {
        let Method::Fixed(f) = Method::by_id(id, &sys)? else {
            unreachable!("{id} is a fixed-step method")
        };
        // Calibrate the first step h on 10 orbits.
        let mut h = 0.01;
        for _ in 0..3 {
            let n = (calib.t_end / h).round() as usize;
            let mut z = calib.z0.clone();
            let out = crate::stepper::observed_caught(
                &*f.stepper,
                &sys,
                &mut z,
                calib.t_end / n as f64,
                n,
                true,
                &mut |_, _, _| true,
            );
            if !out.status.is_ok() || out.evals == 0 {
                return Err(CompareError::method(
                    id,
                    format!("calibration run failed: {}", out.status.label()),
                ));
            }
            h *= (out.evals as f64 / 10.0) / settings.evals_per_orbit;
        }
        let n = (t_end / h).round() as usize;
        let mut z = long.z0.clone();
        let mut w = Windows {
            ends: &ends,
            next: 0,
            window: 0.0,
            samples: Vec::new(),
            step: 0,
        };
        let out = crate::stepper::observed_caught(
            &*f.stepper,
            &sys,
            &mut z,
            t_end / n as f64,
            n,
            true,
            &mut |k, t, z| {
                if k > 0 {
                    w.see(t, long.energy_error(z));
                }
                true
            },
        );
        let steps = out.steps.unwrap_or(n as u64);
        runs.push(LongRun {
            problem: long.name.clone(),
            method: id.to_string(),
            order: f.order,
            symplectic: f.symplectic,
            compensated: true,
            h: t_end / steps as f64,
            steps,
            exponent: growth_exponent(&w.samples),
            samples: w.samples,
            status: out.status,
        });
    }
    // DOP853: the tolerance whose work per orbit is nearest.
    let mut best: Option<(f64, f64)> = None;
    for j in 0..=48 {
        let tol = 10f64.powf(-4.0 - j as f64 / 4.0);
        let Ok((_, evals)) =
            dop853_observed(&sys, &calib.z0, calib.t_end, tol, u32::MAX, &mut |_, _| {})
        else {
            continue;
        };
        let miss = ((evals as f64 / 10.0) / settings.evals_per_orbit)
            .ln()
            .abs();
        if best.is_none_or(|(_, m)| miss < m) {
            best = Some((tol, miss));
        }
    }
    let Some((tol, _)) = best else {
        return Err(CompareError::method("dop853", "no DOP853 run succeeded"));
    };
    let mut w = Windows {
        ends: &ends,
        next: 0,
        window: 0.0,
        samples: Vec::new(),
        step: 0,
    };
    let mut z = long.z0.clone();
    let mut t0 = 0.0;
    let mut status = Status::Ok;
    let chunk = CHUNK_ORBITS * 2.0 * PI;
    let mut steps = 0u64;
    while t0 < t_end * (1.0 - 1e-15) {
        let span = chunk.min(t_end - t0);
        let mut last = z.clone();
        let r = dop853_observed(&sys, &z, span, tol, u32::MAX, &mut |t, y| {
            w.see(t0 + t, long.energy_error(y));
            last.copy_from_slice(y);
        });
        match r {
            Ok((accepted, _)) => steps += accepted,
            Err(why) => {
                status = Status::SolverFailed {
                    step: steps as usize,
                    reason: why,
                };
                break;
            }
        }
        z = last;
        t0 += span;
    }
    runs.push(LongRun {
        problem: long.name.clone(),
        method: format!("dop853 (rtol {tol:.1e})"),
        order: 8,
        symplectic: false,
        compensated: false,
        h: t_end / steps.max(1) as f64,
        steps,
        exponent: growth_exponent(&w.samples),
        samples: w.samples,
        status,
    });
    Ok(runs)
}
