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
        ("interp:gauss2", MethodFamily::Interpreted),
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

/// `interp:ID` is the catalogue's table through the interpreter: the same
/// steps as the generated scheme (its evaluations exactly, its state to
/// the last bits the order of operations leaves), marked interpreted so
/// that no one reads its time against generated code; an id the catalogue
/// lacks is refused by its name.
#[test]
fn interp_ids_step_the_catalogue_table_by_the_interpreter() {
    let kepler = Kepler { e: 0.6 };
    let run = |id: &str| {
        let Method::Fixed(f) = Method::by_id(id, &kepler).unwrap() else {
            panic!("{id} takes fixed steps")
        };
        let mut z = vec![0.4, 0.0, 0.0, 2.0];
        let r = observed_caught(
            &*f.stepper,
            &kepler,
            &mut z,
            0.01,
            500,
            true,
            &mut |_, _, _| true,
        );
        assert!(r.status.is_ok(), "{id}: {}", r.status.label());
        (f.id.clone(), f.interpreted, f.order, z, r.evals)
    };
    for base in ["blanes-moan-prk10", "kahan-li8", "rk4"] {
        let (gid, g_interp, g_order, zg, eg) = run(base);
        let (iid, i_interp, i_order, zi, ei) = run(&format!("interp:{base}"));
        assert_eq!((gid.as_str(), g_interp), (base, false));
        assert_eq!(iid, format!("interp:{base}"));
        assert!(i_interp, "{iid} is marked interpreted");
        assert_eq!(g_order, i_order, "{base}");
        assert!(eg > 0, "{base}: evaluations counted");
        assert_eq!(eg, ei, "{base}: evaluations");
        for (a, b) in zg.iter().zip(&zi) {
            assert!(
                (a - b).abs() <= 1e-12 * a.abs().max(1.0),
                "{base}: {a} vs {b}"
            );
        }
    }
    let err = match Method::by_id("interp:kahan-li9", &kepler) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("kahan-li9 is not in the catalogue"),
    };
    assert!(
        err.contains("interp:kahan-li9") && err.contains("kahan-li8"),
        "{err}"
    );
}
