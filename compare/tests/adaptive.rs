//! `adaptive:ID`: symmetric schemes under the reversible controllers,
//! through the comparison library: they land on T exactly and match the
//! reference, and at DOP853's mean step their energy error stays bounded
//! over a long run while DOP853's grows.

use std::f64::consts::PI;

use compare::{Method, Setup, builtin, peer};
use integrator_core::problems::Kepler;

/// The run of `id` from the start to `setup.t_end` with the start-step
/// convention `h`: (steps taken, end state, max energy error over
/// `[0, t_early]`, max over the whole run, last t).
fn run(id: &str, setup: &Setup<Kepler>, h: f64, t_early: f64) -> (u64, Vec<f64>, f64, f64, f64) {
    let Method::Fixed(f) = Method::by_id(id, &setup.sys).unwrap() else {
        panic!("{id} is not a fixed-step method")
    };
    let n = (setup.t_end / h).round() as usize;
    let mut z = setup.z0.clone();
    let (mut early, mut all, mut last_t) = (0.0f64, 0.0f64, 0.0);
    let out = f.stepper.observed(
        &setup.sys,
        &mut z,
        setup.t_end / n as f64,
        n,
        true,
        &mut |_, t, z| {
            let e = setup.energy_error(z);
            all = all.max(e);
            if t <= t_early {
                early = early.max(e);
            }
            last_t = t;
            true
        },
    );
    assert!(out.status.is_ok(), "{id}: {:?}", out.status);
    (out.steps.unwrap(), z, early, all, last_t)
}

#[test]
fn adaptive_runs_land_on_t_end_and_match_the_reference() {
    let setup = builtin::kepler(true, 20.0 * PI, true).unwrap();
    for (id, h, bound) in [
        ("adaptive:leapfrog", 1e-5, 1e-3),
        ("adaptive:kahan-li8", 2e-3, 1e-9),
        ("adaptive-implicit:kahan-li8", 2e-3, 1e-9),
        ("adaptive:gauss2", 2e-4, 1e-5),
    ] {
        let (steps, z, _, energy, last_t) = run(id, &setup, h, 0.0);
        assert!(
            (last_t - setup.t_end).abs() <= 8.0 * f64::EPSILON * setup.t_end,
            "{id}: ends at t = {last_t}"
        );
        let err = setup.error(&z);
        assert!(err < bound, "{id}: error {err:e} after {steps} steps");
        assert!(energy < 1e-2, "{id}: energy error {energy:e}");
    }
}

#[cfg(feature = "peer")]
#[test]
fn at_dop853_s_mean_step_the_energy_error_stays_bounded_while_dop853_s_grows() {
    // Kepler e = 0.9 over 300 orbits; the early window is the first 30.
    let orbits = 300.0;
    let t_early = 30.0 * 2.0 * PI;
    let long = builtin::kepler(true, orbits * 2.0 * PI, false).unwrap();
    let early_setup = builtin::kepler(true, t_early, false).unwrap();
    let tol = 1e-7;
    let d_long = peer::dop853(&long, tol, u32::MAX);
    let d_early = peer::dop853(&early_setup, tol, u32::MAX);
    assert!(d_long.end.is_ok() && d_early.end.is_ok());
    let dop_growth = d_long.energy_error / d_early.energy_error;
    // The same mean step for the reversible method: calibrate ε once (the
    // mean step is proportional to it), then run.
    let mean = long.t_end / d_long.accepted as f64;
    let id = "adaptive:kahan-li8";
    // h is the first step (at pericentre, r = 0.1): start from a tenth of
    // the mean step.
    let mut h = 0.1 * mean;
    for _ in 0..3 {
        let (steps, ..) = run(id, &long, h, t_early);
        h *= steps as f64 / d_long.accepted as f64;
    }
    let (steps, _, early, all, _) = run(id, &long, h, t_early);
    let ratio = steps as f64 / d_long.accepted as f64;
    assert!(
        (0.9..1.1).contains(&ratio),
        "steps {steps} vs {}",
        d_long.accepted
    );
    let growth = all / early;
    eprintln!(
        "dop853 tol {tol:e}: {} steps, energy error {:.3e} → {:.3e} (×{dop_growth:.2}); \
         {id}: {steps} steps, {early:.3e} → {all:.3e} (×{growth:.2})",
        d_long.accepted, d_early.energy_error, d_long.energy_error
    );
    assert!(dop_growth > 4.0, "dop853 growth ×{dop_growth}");
    assert!(growth < 1.5, "{id} growth ×{growth}");
}
