//! Tests of `compare::adaptive` (from its `#[cfg(test)]` module: `compare`
//! has no unit-test harness, which would compile the whole crate a second
//! time; see `compare/tests/units/mod.rs`).

use compare::adaptive::*;
use compare::*;
use integrator_core::adaptive::Controller;
use integrator_core::library::REGISTRY;
use integrator_core::problems::Kepler;

#[test]
fn symmetric_ids_are_the_registry_s() {
    let mut mine: Vec<&str> = symmetric_ids();
    let mut registry: Vec<&str> = REGISTRY
        .iter()
        .filter(|(_, i)| i.symmetric)
        .map(|(id, _)| *id)
        .collect();
    mine.sort_unstable();
    registry.sort_unstable();
    assert_eq!(
        mine, registry,
        "a symmetric library scheme is missing from compare/src/adaptive.rs (or one listed there is not symmetric)"
    );
    // The dispatch generated from the scheme list covers exactly them.
    for (id, info) in REGISTRY {
        let got = stepper::<Kepler>(id, Controller::Integrating).is_some();
        assert_eq!(got, info.symmetric, "{id}");
    }
}

#[test]
fn non_symmetric_and_unknown_bases_are_refused() {
    let sys = Kepler { e: 0.9 };
    for (id, want) in [
        ("adaptive:rk4", "not symmetric"),
        ("adaptive-implicit:symplectic-euler-a", "not symmetric"),
        ("adaptive:nope", "unknown base method 'nope'"),
    ] {
        let err = match Method::by_id(id, &sys) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("{id} accepted"),
        };
        assert!(
            err.contains(want) && err.contains("leapfrog"),
            "{id}: {err}"
        );
    }
    assert!(Method::by_id("adaptive:gauss2", &sys).is_ok());
    assert!(Method::by_id("adaptive-implicit:kahan-li8", &sys).is_ok());
}
