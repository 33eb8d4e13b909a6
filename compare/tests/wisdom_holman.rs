//! `wh:ID`: the library's splittings on the Wisdom–Holman split of the outer
//! solar system, through the comparison library: measured with the same
//! error as every other method, converging with the splitting's order,
//! counting one force evaluation per kick, and refusing what is not a
//! splitting by name.

use compare::builtin;
use compare::{Method, Setup};
use integrator_core::problems::OuterSolarSystem;

/// The error at `t_end` and the evaluations of `n` steps of `id`.
fn run(setup: &Setup<OuterSolarSystem>, id: &str, n: usize) -> (f64, u64) {
    let Method::Fixed(f) = Method::by_id(id, &setup.sys).unwrap() else {
        panic!("{id} is a fixed-step method")
    };
    let mut z = setup.z0.clone();
    let mut last = 0;
    let out = f.stepper.observed(
        &setup.sys,
        &mut z,
        setup.t_end / n as f64,
        n,
        true,
        &mut |k, _, _| {
            last = k;
            true
        },
    );
    assert!(out.status.is_ok(), "{id}: {:?}", out.status);
    assert_eq!(last, n, "{id}: every step observed");
    // The timed path ends in the same state.
    let mut bare = setup.z0.clone();
    assert!(
        f.stepper
            .bare(&setup.sys, &mut bare, setup.t_end / n as f64, n)
    );
    assert_eq!(
        bare, z,
        "{id}: the timed run's end differs from the observed run's"
    );
    (setup.error(&z), out.evals)
}

#[test]
fn wisdom_holman_converges_with_the_order_of_the_splitting() {
    let setup = builtin::outer_solar(2.0e4, true).unwrap();
    // The classical map: order 2, one kick per step.
    let (e1, evals) = run(&setup, "wh:leapfrog", 200);
    let (e2, _) = run(&setup, "wh:leapfrog", 400);
    assert_eq!(evals, 200);
    let p = (e1 / e2).log2();
    assert!(
        (p - 2.0).abs() < 0.2,
        "wh:leapfrog: order {p} ({e1:e}, {e2:e})"
    );
    // A fourth-order composition: three kicks per step, order 4.
    let (e1, evals) = run(&setup, "wh:forest-ruth", 100);
    let (e2, _) = run(&setup, "wh:forest-ruth", 200);
    assert_eq!(evals, 300);
    let p = (e1 / e2).log2();
    assert!(
        (p - 4.0).abs() < 0.4,
        "wh:forest-ruth: order {p} ({e1:e}, {e2:e})"
    );
}

#[test]
fn the_kepler_flow_beats_the_drift_on_the_same_splitting() {
    // The same table at the same step: drifts as exact Kepler flows (the
    // Sun's pull integrated exactly) against drifts of T(p) — the point of
    // Wisdom–Holman: the error shrinks by orders of magnitude.
    let setup = builtin::outer_solar(2.0e4, true).unwrap();
    let (wh, _) = run(&setup, "wh:leapfrog", 200);
    let (plain, _) = run(&setup, "leapfrog", 200);
    assert!(wh * 100.0 < plain, "wh {wh:e} vs leapfrog {plain:e}");
}

#[test]
fn what_is_not_a_splitting_is_refused_by_name() {
    let sys = OuterSolarSystem;
    for (id, needle) in [
        ("wh:rk4", "'rk4' is not a splitting"),
        ("wh:stormer-verlet", "'stormer-verlet' is not a splitting"),
        ("wh:nope", "'nope' is not a splitting"),
    ] {
        let Err(e) = Method::by_id(id, &sys) else {
            panic!("{id} accepted")
        };
        let msg = e.to_string();
        assert!(
            msg.contains(needle) && msg.contains("leapfrog"),
            "{id}: {msg}"
        );
    }
    assert!(Method::ids(&sys).contains(&"wh:kahan-li8".to_string()));
}
