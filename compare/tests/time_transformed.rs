//! `logh:ID`: explicit separable schemes on the logarithmic Hamiltonian,
//! through the comparison library: they land on T exactly, match the
//! reference to their accuracy, and bad ids are clear errors.

use compare::{Method, SweepSettings, builtin, work_precision};
use integrator_core::problems::Kepler;

#[test]
fn time_transformed_runs_land_on_t_end_and_match_the_reference() {
    let setup = builtin::kepler(true, 20.0 * std::f64::consts::PI, true).unwrap();
    for (id, h, bound) in [
        ("logh:leapfrog", 1e-4, 5e-4),
        ("logh:kahan-li8", 1e-2, 1e-10),
    ] {
        let Method::Fixed(f) = Method::by_id(id, &setup.sys).unwrap() else {
            panic!("{id} is a fixed-step method")
        };
        let n = (setup.t_end / h).round() as usize;
        let mut z = setup.z0.clone();
        let mut last_t = 0.0;
        let out = f.stepper.observed(
            &setup.sys,
            &mut z,
            setup.t_end / n as f64,
            n,
            true,
            &mut |_, t, _| {
                last_t = t;
                true
            },
        );
        assert!(out.status.is_ok(), "{id}: {:?}", out.status);
        // Exactly on T, to a few ulps.
        assert!(
            (last_t - setup.t_end).abs() <= 8.0 * f64::EPSILON * setup.t_end,
            "{id}: ends at t = {last_t}, T = {}",
            setup.t_end
        );
        let err = setup.error(&z);
        assert!(err < bound, "{id}: error {err:e} at T");
        // Fewer steps than a fixed step of h, since the step grows away
        // from the pericentre.
        let steps = out.steps.expect("a time-transformed run reports its steps");
        assert!(
            steps > 0 && (steps as usize) < n,
            "{id}: {steps} steps vs {n}"
        );
    }
}

#[test]
fn a_sweep_reports_the_steps_taken_and_the_order() {
    let setup = builtin::kepler(true, 2.0 * std::f64::consts::PI, true).unwrap();
    let methods = vec![Method::by_id("logh:forest-ruth", &setup.sys).unwrap()];
    let settings = SweepSettings {
        h_min: 2e-4,
        h_max: 2e-3,
        points: 4,
        tolerances: vec![],
        repeats: 1,
        target: 1e-8,
    };
    let result = work_precision(&setup, &methods, &settings).unwrap();
    assert!(result.rows.iter().all(|r| r.ok()), "{:?}", result.rows);
    for r in &result.rows {
        assert!((r.h * r.steps as f64 - setup.t_end).abs() < 1e-9, "{r:?}");
    }
    let p = compare::output::fitted_order(&result.rows, "logh:forest-ruth").unwrap();
    assert!((p - 4.0).abs() < 0.3, "fitted order {p}");
}

#[test]
fn bad_logh_ids_are_clear_errors() {
    let kepler = Kepler { e: 0.9 };
    for (id, needle) in [
        ("logh:nope", "unknown base method 'nope'"),
        ("logh:rk4", "'rk4' is an explicit rk scheme"),
        ("logh:gauss2", "an implicit"),
        ("logh:lobatto3a3b-3", "an implicit"),
    ] {
        let e = Method::by_id(id, &kepler).err().unwrap().to_string();
        assert!(e.contains(needle) && e.contains(id), "{id}: {e}");
    }
    let linear = integrator_core::linear::gyroscopic(2, 1, 10.0).unwrap();
    let e = Method::by_id("logh:leapfrog", &linear)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("separable"), "{e}");
    // A problem whose potential is not negative everywhere has no logh:
    // methods (Problem::NEGATIVE_POTENTIAL): the refusal names the problem
    // and the reason. (A start with V ≥ 0 on a problem that declares one is
    // refused at step 0: integrator-core's tests/time_transform.rs.)
    let osc = integrator_core::problems::Oscillator { k: 1.0 };
    let e = Method::by_id("logh:leapfrog", &osc)
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("logh:leapfrog")
            && e.contains("oscillator")
            && e.contains("negative")
            && e.contains("NEGATIVE_POTENTIAL"),
        "{e}"
    );
    assert!(!compare::registry::MethodFamily::LogH.applies(&osc));
    assert!(compare::registry::MethodFamily::LogH.applies(&kepler));
}

#[test]
fn the_timed_run_on_fixed_size_state_gives_the_observed_bits() {
    // Kepler's extended state has 6 entries: `bare` steps a [f64; 6]
    // (integrator_core::fixed), `observed` the slice path on the counting
    // wrapper. Same arithmetic, same bits, landing included.
    let setup = builtin::kepler(true, 4.0 * std::f64::consts::PI, true).unwrap();
    for id in ["logh:leapfrog", "logh:kahan-li8", "logh:stormer-verlet"] {
        let Method::Fixed(f) = Method::by_id(id, &setup.sys).unwrap() else {
            panic!("{id} is a fixed-step method")
        };
        let n = 500;
        let h = setup.t_end / n as f64;
        let mut a = setup.z0.clone();
        let out = f
            .stepper
            .observed(&setup.sys, &mut a, h, n, true, &mut |_, _, _| true);
        assert!(out.status.is_ok(), "{id}: {:?}", out.status);
        let mut b = setup.z0.clone();
        assert!(f.stepper.bare(&setup.sys, &mut b, h, n), "{id}");
        assert_eq!(a, b, "{id}");
        assert_ne!(a, setup.z0, "{id}: the state moved");
    }
}
