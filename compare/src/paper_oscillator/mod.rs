//! The oscillator experiment of Tan et al.'s section 5 (their figures 2–4):
//! `H = ½(p² + k²q²)` integrated by six schemes at several step sizes, every
//! step compared with the closed-form solution; `symlab paper` is its front
//! end.
//!
//! Everything a report can say is computed here, from the runs — the
//! trajectories and their errors ([`Trajectory`], [`Summary`]), the numbers
//! derived from them and the closed-form predictions they are checked
//! against ([`Findings`]) — and the CSV files are written from them
//! ([`errors_csv`], [`series_csv`]). Nothing is hard-coded but the set-up.
//!
//! ```
//! use compare::paper_oscillator::{Config, Method, experiment};
//!
//! let exp = experiment(&Config { step_sizes: vec![0.1], ..Config::default() })?;
//! let heun = exp.run(Method::Heun, 0.1).summary();
//! let midpoint = exp.run(Method::ImplicitMidpoint, 0.1).summary();
//! assert!(midpoint.max_rel_energy_error < 1e-13 && heun.max_rel_energy_error > 1e-6);
//! # Ok::<(), compare::CompareError>(())
//! ```

mod config;
mod csv;
mod findings;
mod method;
mod trajectory;

pub use config::{Config, Invalid, MAX_STEPS, MIN_STEPS, h_name};
pub use csv::{errors_csv, series_csv};
pub use findings::{Findings, relative_difference, value_at};
pub use method::Method;
pub use trajectory::{Summary, Trajectory};

use integrator_core::energy;
use integrator_core::problems::ExactFlow;

use crate::error::{CompareError, Result};

/// Energy errors below this are drawn at this value on the log axis
/// (schemes that conserve the quadratic energy can be exactly 0).
pub const ENERGY_FLOOR: f64 = 1e-17;

/// Energy errors above this are drawn at this value (an unstable run can
/// reach the end of the f64 range, which no axis can span).
pub const ENERGY_CEILING: f64 = 1e100;

/// One method at one step size.
pub fn simulate(config: &Config, method: Method, h: f64) -> Result<Trajectory> {
    config.check()?;
    let osc = config.oscillator();
    let z0 = config.z0();
    let n = config.steps;
    let (states, failure) = method.states(&osc, z0, h, n);
    let energy0 = config.energy0();
    let mut traj = Trajectory {
        method,
        h,
        k: config.k,
        energy0,
        t: Vec::with_capacity(n + 1),
        q: Vec::with_capacity(n + 1),
        p: Vec::with_capacity(n + 1),
        q_exact: Vec::with_capacity(n + 1),
        p_exact: Vec::with_capacity(n + 1),
        energy_error: Vec::with_capacity(n + 1),
        failure,
    };
    for (i, z) in states.iter().enumerate() {
        let t = i as f64 * h;
        let exact = osc.flow(&z0, t).ok_or_else(|| {
            CompareError::problem(
                "oscillator",
                format!("no exact flow from {z0:?} at t = {t}"),
            )
        })?;
        traj.t.push(t);
        traj.q.push(z[0]);
        traj.p.push(z[1]);
        traj.q_exact.push(exact[0]);
        traj.p_exact.push(exact[1]);
        traj.energy_error.push(energy(&osc, z) - energy0);
    }
    Ok(traj)
}

/// Every method at every step size of the set-up.
#[derive(Clone, Debug)]
pub struct Experiment {
    pub config: Config,
    /// By step size (in the set-up's order), then method (in [`Method::ALL`] order).
    pub runs: Vec<Trajectory>,
}

impl Experiment {
    /// The run of `method` at step size `h` (one of the set-up's).
    pub fn get(&self, method: Method, h: f64) -> Option<&Trajectory> {
        self.runs.iter().find(|r| r.method == method && r.h == h)
    }

    /// The run of `method` at step size `h`, which must be one of the
    /// set-up's (the experiment runs every method at each of them).
    ///
    /// # Panics
    /// If `h` is not one of the set-up's step sizes.
    pub fn run(&self, method: Method, h: f64) -> &Trajectory {
        self.get(method, h)
            .unwrap_or_else(|| panic!("h = {h} is not a step size of the set-up"))
    }

    /// `max |H − H₀| / H₀` of `method` at step size `h` (one of the set-up's).
    pub fn max_rel_energy(&self, method: Method, h: f64) -> f64 {
        self.run(method, h).summary().max_rel_energy_error
    }

    /// The runs at step size `h`, in [`Method::ALL`] order.
    pub fn at(&self, h: f64) -> impl Iterator<Item = &Trajectory> {
        self.runs.iter().filter(move |r| r.h == h)
    }
}

/// Run the whole oscillator experiment: every method at every step size.
pub fn experiment(config: &Config) -> Result<Experiment> {
    config.check()?;
    let mut runs = Vec::new();
    for &h in &config.step_sizes {
        for method in Method::ALL {
            runs.push(simulate(config, method, h)?);
        }
    }
    Ok(Experiment {
        config: config.clone(),
        runs,
    })
}

/// The paper's closed form, `q(t) = √(q₀² + p₀²/k²)·cos(kt − arctg(p₀/(kq₀)))`,
/// as printed (section 5).
pub fn paper_closed_form_q(k: f64, q0: f64, p0: f64, t: f64) -> f64 {
    (q0 * q0 + p0 * p0 / (k * k)).sqrt() * (k * t - (p0 / (k * q0)).atan()).cos()
}

/// The largest difference between the paper's closed form and the exact flow
/// used here, over the times of a run.
pub fn paper_closed_form_deviation(traj: &Trajectory, config: &Config) -> f64 {
    traj.t
        .iter()
        .zip(&traj.q_exact)
        .map(|(&t, &q)| (paper_closed_form_q(config.k, config.q0, config.p0, t) - q).abs())
        .fold(0.0, f64::max)
}
