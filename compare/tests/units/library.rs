//! Tests of `compare::library` (from its `#[cfg(test)]` module: `compare`
//! has no unit-test harness, which would compile the whole crate a second
//! time; see `compare/tests/units/mod.rs`).

use compare::library::*;
use integrator_core::library::REGISTRY;
use integrator_core::problems::Kepler;

#[test]
fn library_lists_cover_the_registry() {
    let mut all: Vec<&str> = RK_IDS.iter().chain(SEPARABLE_IDS).copied().collect();
    let mut registry: Vec<&str> = REGISTRY.iter().map(|(id, _)| *id).collect();
    all.sort_unstable();
    registry.sort_unstable();
    assert_eq!(all, registry);
    for (id, info) in REGISTRY {
        assert_eq!(
            RK_IDS.contains(id),
            info.form == "rk",
            "{id}: form {}",
            info.form
        );
    }
}

#[test]
fn observed_and_bare_runs_agree() {
    let sys = Kepler { e: 0.3 };
    let z0 = sys.initial_state();
    for id in ["leapfrog", "rk4", "gauss2"] {
        let s = separable_stepper::<Kepler>(id).unwrap();
        let mut a = z0.clone();
        let out = s.observed(&sys, &mut a, 0.01, 100, true, &mut |_, _, _| true);
        assert!(out.status.is_ok(), "{id}");
        assert!(out.evals > 0);
        let mut b = z0.clone();
        assert!(s.bare(&sys, &mut b, 0.01, 100));
        assert_eq!(a, b, "{id}");
    }
}
