//! The library's public functions with adversarial values — NaN, inf, 0,
//! negative steps, huge step counts — return errors that name the setting;
//! none panics, hangs or runs for hours.

use compare::hard::{self, Case};
use compare::long::{self, LongSettings};
use compare::long_variable::{self, VariableSettings};
use compare::{CompareError, Method, Setup, SweepSettings, work_precision};
use integrator_core::problems::Kepler;

/// The error of a call that must fail.
fn fails<T>(r: compare::Result<T>) -> CompareError {
    match r {
        Ok(_) => panic!("expected an error"),
        Err(e) => e,
    }
}

fn setting(e: CompareError) -> (&'static str, String) {
    match e {
        CompareError::Setting { name, why } => (name, why),
        other => panic!("not a setting error: {other}"),
    }
}

fn fixed(id: &str, sys: &Kepler) -> compare::Fixed<Kepler> {
    match Method::by_id(id, sys).unwrap() {
        Method::Fixed(f) => f,
        Method::Dop853 | Method::Rebound(_) => unreachable!(),
    }
}

#[test]
fn the_stability_search_refuses_unbounded_settings() {
    let sys = Kepler { e: 0.6 };
    let setup = Setup::new(sys, 1.0).unwrap();
    let methods = vec![fixed("leapfrog", &sys)];
    let case = |h0: f64| Case {
        name: "kepler",
        setup: setup.clone(),
        h0,
        omega_max: None,
        note: String::new(),
    };
    for h0 in [0.0, -1.0, f64::NAN, f64::INFINITY, 5e-324, 1e-12, 2.0] {
        let (name, why) = setting(fails(hard::run_case(&case(h0), &methods, 0.01, 1e-4)));
        assert_eq!(name, "h0", "{h0}: {why}");
    }
    for floor in [0.0, -1.0, f64::NAN, 1e-300, 2.0] {
        let (name, why) = setting(fails(hard::run_case(&case(0.1), &methods, 0.01, floor)));
        assert_eq!(name, "floor", "{floor}: {why}");
    }
    for tol in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let (name, why) = setting(fails(hard::run_case(&case(0.1), &methods, tol, 1e-4)));
        assert_eq!(name, "tolerance", "{tol}: {why}");
        let e = fails(hard::search(&case(0.1), &methods[0], tol, 1e-4));
        assert_eq!(setting(e).0, "tolerance");
    }
    // Sensible settings still search.
    let rows = hard::run_case(&case(0.1), &methods, 0.05, 1e-3).unwrap();
    assert_eq!(rows.len(), 1);
    assert!(rows[0].h_stable.is_some_and(|h| h > 0.0 && h.is_finite()));
}

#[test]
fn the_long_studies_refuse_absurd_settings() {
    for s in [
        VariableSettings {
            orbits: 1e300,
            ..VariableSettings::quick()
        },
        VariableSettings {
            orbits: f64::NAN,
            ..VariableSettings::quick()
        },
        VariableSettings {
            e: 1.5,
            ..VariableSettings::quick()
        },
        VariableSettings {
            e: f64::NAN,
            ..VariableSettings::quick()
        },
        VariableSettings {
            evals_per_orbit: 0.0,
            ..VariableSettings::quick()
        },
        VariableSettings {
            evals_per_orbit: f64::INFINITY,
            ..VariableSettings::quick()
        },
    ] {
        let e = fails(long_variable::run(s));
        let (name, _) = setting(e);
        assert!(["orbits", "e", "evals_per_orbit"].contains(&name), "{s:?}");
    }
    let sys = Kepler { e: 0.6 };
    let setup = Setup::energy_only(sys, 1.0).unwrap();
    let methods = vec![fixed("leapfrog", &sys)];
    for (h, steps) in [
        (f64::NAN, 100),
        (-0.01, 100),
        (0.0, 100),
        (0.01, 0),
        (0.01, u64::MAX),
    ] {
        let e = fails(long::run(&setup, &methods, LongSettings { h, steps }));
        assert!(["h", "steps"].contains(&setting(e).0));
    }
}

#[test]
fn a_sweep_of_hours_is_refused_with_its_limit() {
    let sys = Kepler { e: 0.6 };
    let setup = Setup::new(sys, 100.0).unwrap();
    let methods: Vec<_> = ["leapfrog", "rk4", "forest-ruth", "gauss2"]
        .iter()
        .map(|id| Method::by_id(id, &sys).unwrap())
        .collect();
    // 10⁸ steps per run at 200 step sizes, 100 timed runs each.
    let settings = SweepSettings {
        h_min: 1e-6,
        h_max: 1.0,
        points: 200,
        tolerances: vec![],
        repeats: 100,
        target: 1e-8,
    };
    let (name, why) = setting(fails(work_precision(&setup, &methods, &settings)));
    assert_eq!(name, "h_min");
    assert!(why.contains("at most 1e10"), "{why}");
    // NaN, inf, zero and negative settings: errors naming the field.
    for (edit, field) in [
        (
            SweepSettings {
                h_min: f64::NAN,
                ..settings.clone()
            },
            "h_min",
        ),
        (
            SweepSettings {
                h_max: f64::INFINITY,
                ..settings.clone()
            },
            "h_max",
        ),
        (
            SweepSettings {
                h_min: -1e-3,
                ..settings.clone()
            },
            "h_min",
        ),
        (
            SweepSettings {
                target: 0.0,
                ..settings.clone()
            },
            "target",
        ),
        (
            SweepSettings {
                points: 0,
                ..settings.clone()
            },
            "points",
        ),
        (
            SweepSettings {
                repeats: 0,
                ..settings.clone()
            },
            "repeats",
        ),
        (
            SweepSettings {
                tolerances: vec![f64::NAN],
                ..settings.clone()
            },
            "tolerances",
        ),
    ] {
        let (name, why) = setting(fails(work_precision(&setup, &methods, &edit)));
        assert_eq!(name, field, "{why}");
    }
    for t in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let (name, _) = setting(Setup::new(sys, t).unwrap_err());
        assert_eq!(name, "t_end");
    }
}
