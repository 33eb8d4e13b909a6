//! Tests of `compare::registry` (from its `#[cfg(test)]` module: `compare`
//! has no unit-test harness, which would compile the whole crate a second
//! time; see `compare/tests/units/mod.rs`).

use compare::registry::*;
use compare::*;
use integrator_core::linear;
use integrator_core::problems::Kepler;

#[test]
fn separable_methods_on_the_linear_problem_say_why_not() {
    let sys = linear::gyroscopic(3, 1, 10.0).unwrap();
    let err = match Method::by_id("leapfrog", &sys) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("leapfrog cannot step the linear system"),
    };
    assert!(err.contains("separable"), "{err}");
    assert!(Method::by_id("gauss2-propagator", &sys).is_ok());
    let kepler = Kepler { e: 0.6 };
    assert!(Method::by_id("gauss2-propagator", &kepler).is_err());
    let err = match Method::by_id("nope", &kepler) {
        Err(e) => e.to_string(),
        Ok(_) => panic!(),
    };
    assert!(err.contains("leapfrog") && err.contains("unknown"), "{err}");
}

#[test]
fn every_listed_id_resolves_to_its_family() {
    let kepler = Kepler { e: 0.6 };
    for id in ids(&kepler) {
        assert!(Method::by_id(&id, &kepler).is_ok(), "{id}");
        assert!(MethodFamily::of(&id).is_some(), "{id}");
    }
    let solar = integrator_core::problems::OuterSolarSystem;
    let listed = ids(&solar);
    assert!(listed.iter().any(|id| id == "wh:leapfrog"));
    for (id, family) in [
        ("wh:leapfrog", MethodFamily::WisdomHolman),
        ("logh:kahan-li8", MethodFamily::LogH),
        ("adaptive:gauss2", MethodFamily::Adaptive),
        ("adaptive-implicit:gauss2", MethodFamily::AdaptiveImplicit),
        ("rebound:whfast", MethodFamily::Rebound),
        ("dop853", MethodFamily::Dop853),
        ("gauss2-propagator", MethodFamily::Propagator),
        ("gauss2", MethodFamily::Library),
    ] {
        assert_eq!(MethodFamily::of(id), Some(family), "{id}");
        assert!(!family.about().is_empty() && !family.pattern().is_empty());
    }
    assert!(MethodFamily::WisdomHolman.applies(&solar));
    assert!(!MethodFamily::WisdomHolman.applies(&kepler));
    assert!(MethodFamily::Rebound.applies(&kepler));
    let gyro = linear::gyroscopic(3, 1, 10.0).unwrap();
    assert!(MethodFamily::Propagator.applies(&gyro));
    assert!(!MethodFamily::LogH.applies(&gyro));
}
