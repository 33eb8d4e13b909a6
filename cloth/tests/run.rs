//! Method dispatch and runs: names map to the library's explicit schemes,
//! frames and callbacks come in order, and a run that blows up stops with
//! an error naming the method, step and time.

use std::collections::BTreeSet;

use crate::common;
use common::run_id;

use cloth::MethodError;
use cloth::step::dispatch::{SchemeVisitor, with_explicit_scheme};
use cloth::{ClothModel, Method, RunError, RunOptions, Scene, Simulation};
use integrator_core::library::REGISTRY;
use integrator_core::{Scheme, Step};

#[test]
fn steppable_methods_are_exactly_the_explicit_library_schemes() {
    let explicit: BTreeSet<&str> = REGISTRY
        .iter()
        .filter(|(_, i)| i.explicit)
        .map(|(id, _)| *id)
        .collect();
    let explicit_ids = Method::ids(|m| m.explicit());
    let steppable: BTreeSet<&str> = explicit_ids.iter().copied().collect();
    assert_eq!(steppable, explicit);
    struct Name;
    impl SchemeVisitor for Name {
        type Output = &'static str;
        fn visit<S: Step<ClothModel> + Scheme>(self, _: S) -> &'static str {
            S::INFO.name
        }
    }
    for id in &explicit_ids {
        let name = with_explicit_scheme(id, Name).unwrap();
        assert_eq!(
            name,
            integrator_core::library::info(id).unwrap().name,
            "{id}"
        );
    }
    for (id, info) in REGISTRY.iter().filter(|(_, i)| !i.explicit) {
        let err = with_explicit_scheme(id, Name).unwrap_err();
        let expected = if Method::parse(id).is_ok() {
            MethodError::Implicit(id.to_string())
        } else {
            MethodError::NotSteppable(id.to_string())
        };
        assert_eq!(err, expected, "{}", info.name);
    }
    let err = with_explicit_scheme("verlet", Name).unwrap_err();
    assert_eq!(err, MethodError::Unknown("verlet".into()));
    let msg = err.to_string();
    assert!(
        msg.contains("unknown method \"verlet\"") && msg.contains("stormer-verlet, leapfrog"),
        "{msg}"
    );
}

const HANGING: &str = r#"
gravity = [0.0, -9.81, 0.0]

[cloth]
width = 0.5
height = 0.5
nx = 5
ny = 5
plane = "horizontal"

[material]
density = 0.1
stretch = 20.0
shear = 5.0

[pins]
edges = ["top"]

[simulation]
substeps = 50
frames = 4
method = "symplectic-euler-a"
"#;

#[test]
fn frames_come_in_order_with_their_statistics() {
    let scene = Scene::from_toml(HANGING, "hanging.toml").unwrap();
    let mut seen = Vec::new();
    let (sim, report) = cloth::run_scene(&scene, |frame| {
        let x = frame.positions();
        assert_eq!(x.len(), 25);
        assert_eq!(frame.q().len(), 3 * 20);
        seen.push((frame.stats.frame, frame.stats.step, x[12].y));
        Ok(())
    })
    .unwrap();
    assert_eq!(report.method, "Symplectic Euler (p first)");
    assert_eq!(report.steps, 200);
    assert_eq!(sim.steps, 200);
    assert_eq!(
        seen.iter().map(|s| s.0).collect::<Vec<_>>(),
        [0, 1, 2, 3, 4]
    );
    assert_eq!(
        seen.iter().map(|s| s.1).collect::<Vec<_>>(),
        [0, 50, 100, 150, 200]
    );
    // The cloth falls.
    assert!(seen[4].2 < seen[0].2 - 0.01);
    assert_eq!(report.frames.len(), 5);
    assert!((report.frames[4].time - 4.0 / 60.0).abs() < 1e-12);
    assert!((report.h - 1.0 / 3000.0).abs() < 1e-18);
    // Energy is recorded and roughly conserved at this step size.
    let e0 = report.frames[0].energy.total();
    let scale = report
        .frames
        .iter()
        .map(|f| f.energy.kinetic)
        .fold(0.0, f64::max);
    assert!(
        report
            .frames
            .iter()
            .all(|f| (f.energy.total() - e0).abs() < 0.05 * scale)
    );
    let mut csv = Vec::new();
    cloth::write_energy_csv_to(&mut csv, &report.frames, 1.0).unwrap();
    let csv = String::from_utf8(csv).unwrap();
    assert_eq!(csv.lines().count(), 6);
    assert!(csv.starts_with(cloth::ENERGY_CSV_HEADER));
}

#[test]
fn a_run_continues_where_it_stopped() {
    let scene = Scene::from_toml(HANGING, "hanging.toml").unwrap();
    let opts = RunOptions::from_scene(&scene);
    let mut once = Simulation::new(&scene).unwrap();
    run_id(
        &mut once,
        "leapfrog",
        &RunOptions { frames: 4, ..opts },
        |_| Ok(()),
    )
    .unwrap();
    let mut twice = Simulation::new(&scene).unwrap();
    run_id(
        &mut twice,
        "leapfrog",
        &RunOptions { frames: 2, ..opts },
        |_| Ok(()),
    )
    .unwrap();
    let r = run_id(
        &mut twice,
        "leapfrog",
        &RunOptions { frames: 2, ..opts },
        |_| Ok(()),
    )
    .unwrap();
    assert_eq!(r.frames[0].frame, 2);
    assert_eq!(r.frames[2].frame, 4);
    assert_eq!(twice.steps, once.steps);
    assert!((twice.time - once.time).abs() < 1e-15);
    // The same up to round-off: a new run starts a new workspace, and with it
    // the compensated summation starts afresh.
    let diff = twice
        .state
        .iter()
        .zip(&once.state)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(diff < 1e-14, "{diff:e}");
}

#[test]
fn a_blow_up_names_method_step_and_time() {
    let scene = Scene::from_toml(HANGING, "hanging.toml").unwrap();
    let mut sim = Simulation::new(&scene).unwrap();
    let before = sim.state.clone();
    // Far beyond the stability limit: one step per frame.
    let opts = RunOptions {
        frames: 10_000,
        substeps: 1,
        frame_rate: 60.0,
    };
    let err = run_id(&mut sim, "stormer-verlet", &opts, |_| Ok(())).unwrap_err();
    let RunError::Diverged {
        method,
        step,
        time,
        frame,
        ..
    } = &err
    else {
        panic!("expected divergence, got {err}");
    };
    assert_eq!(*method, "Störmer–Verlet (Lobatto IIIA–IIIB pair, 2 stages)");
    assert_eq!(*step, *frame);
    assert!((*time - *step as f64 / 60.0).abs() < 1e-9);
    let msg = err.to_string();
    assert!(
        msg.contains("Störmer–Verlet")
            && msg.contains(&format!("step {step}"))
            && msg.contains("t = "),
        "{msg}"
    );
    // The state is left at the last good frame.
    assert_eq!(sim.steps, step - 1);
    assert!(sim.state.iter().all(|x| x.is_finite()));
    assert_ne!(sim.state, before);
}

#[test]
fn a_failing_callback_stops_the_run() {
    let scene = Scene::from_toml(HANGING, "hanging.toml").unwrap();
    let mut sim = Simulation::new(&scene).unwrap();
    let err = run_id(&mut sim, "rk4", &RunOptions::from_scene(&scene), |f| {
        if f.stats.frame == 2 {
            Err("disk full".into())
        } else {
            Ok(())
        }
    })
    .unwrap_err();
    assert!(matches!(err, RunError::Callback { frame: 2, .. }));
    assert!(err.to_string().starts_with("frame 2 (t = "), "{err}");
    assert_eq!(sim.frame, 2);
}

#[test]
fn bad_options_and_methods_are_errors() {
    let scene = Scene::from_toml(HANGING, "hanging.toml").unwrap();
    let mut sim = Simulation::new(&scene).unwrap();
    let opts = RunOptions {
        substeps: 0,
        ..RunOptions::from_scene(&scene)
    };
    assert!(matches!(
        run_id(&mut sim, "rk4", &opts, |_| Ok(())),
        Err(RunError::Options(_))
    ));
    // The explicit dispatch refuses an implicit method (it runs through
    // its own solver: `Simulation::run`).
    struct Name;
    impl SchemeVisitor for Name {
        type Output = ();
        fn visit<S: integrator_core::Step<ClothModel> + integrator_core::Scheme>(self, _: S) {}
    }
    let err = with_explicit_scheme("gauss2", Name).unwrap_err();
    assert!(err.to_string().contains("implicit"), "{err}");
}
