//! The cloth studies as a library user calls them: the largest stable step
//! and the growth fit of the energy error.

use cloth::study::energy::relative_errors;
use cloth::study::growth::{self, Trend};
use cloth::study::stability::{
    Outcome, Scales, StabilityError, StabilitySettings, Status, largest_stable_step, search,
    seconds_per_simulated_second, trial,
};
use cloth::{Method, RunSettings, Scene, Simulation};

/// A 4 × 4 sheet pinned along its top edge, stiff enough that the stable
/// step (about a millisecond) is far from the search's cap.
fn small(gravity: bool) -> Scene {
    let g = if gravity {
        "gravity = [0.0, -9.81, 0.0]\n"
    } else {
        ""
    };
    Scene::from_toml(
        &format!(
            r#"{g}
            [cloth]
            width = 1.0
            height = 1.0
            nx = 4
            ny = 4
            [material]
            density = 0.1
            stretch = 1000.0
            [pins]
            edges = ["top"]
            [simulation]
            substeps = 10
            frames = 3
            method = "stormer-verlet"
            "#
        ),
        "small.toml",
    )
    .unwrap()
}

fn method(id: &str) -> Method {
    Method::parse(id).unwrap()
}

fn quick() -> StabilitySettings {
    StabilitySettings {
        duration: 0.2,
        ..StabilitySettings::default()
    }
}

#[test]
fn stormer_verlet_is_bracketed_near_its_linear_limit() {
    let scene = small(true);
    let settings = quick();
    let found = largest_stable_step(&scene, &method("stormer-verlet"), &settings).unwrap();
    assert_eq!(found.status, Status::Bracketed);
    let h = found.h.unwrap();
    assert!(found.max_error <= settings.tolerance);
    // The step above h failed, within the resolution.
    let beyond = found.beyond.as_ref().unwrap();
    assert!(!beyond.stable(), "{beyond:?}");
    // Close to 2/ω_max: the springs are nearly linear at this amplitude.
    let ratio = h / found.h_linear;
    assert!(ratio > 0.5 && ratio < 1.5, "h/h_lin = {ratio}");
    // A trial just above the bracket fails, one at h passes.
    let scales = Scales::of(&scene).unwrap();
    let at = trial(&scene, &found.method, h, scales.e_ref, &settings);
    assert!(at.outcome.stable(), "{at:?}");
    assert!(
        seconds_per_simulated_second(&scene, &found.method, h, scales.e_ref, &settings).is_some()
    );
}

#[test]
fn the_search_is_the_same_called_once_or_per_method() {
    let scene = small(true);
    let settings = quick();
    let scales = Scales::of(&scene).unwrap();
    let m = method("symplectic-euler-a");
    let a = largest_stable_step(&scene, &m, &settings).unwrap();
    let b = search(&scene, &m, &scales, &settings);
    assert_eq!(a.h, b.h);
    assert_eq!(a.trials, b.trials);
}

#[test]
fn explicit_euler_is_unstable_down_to_the_floor() {
    // Explicit Euler grows every undamped mode: with a floor close to the
    // linear limit, every step tried fails.
    let scene = small(true);
    let settings = StabilitySettings {
        max_steps_explicit: 400.0,
        ..quick()
    };
    let found = largest_stable_step(&scene, &method("euler"), &settings).unwrap();
    assert_eq!(found.status, Status::BelowFloor, "{found:?}");
    assert_eq!(found.h, None);
    assert!(found.max_error.is_nan());
    assert!(
        matches!(
            found.beyond,
            Some(Outcome::Energy { .. } | Outcome::Blowup { .. })
        ),
        "{found:?}"
    );
}

#[test]
fn a_soft_cloth_is_stable_up_to_the_cap() {
    let scene = small(true);
    let settings = StabilitySettings {
        // Eight steps of 10 µs: far below 2/ω_max.
        duration: 8e-5,
        ..StabilitySettings::default()
    };
    let found = largest_stable_step(&scene, &method("stormer-verlet"), &settings).unwrap();
    assert_eq!(found.status, Status::AtCap, "{found:?}");
    assert_eq!(found.h, Some(settings.cap()));
    assert_eq!(found.beyond, None);
}

#[test]
fn settings_and_scenes_without_a_scale_are_refused_by_name() {
    let bad = StabilitySettings {
        resolution: 1.0,
        ..StabilitySettings::default()
    };
    let err = largest_stable_step(&small(true), &method("stormer-verlet"), &bad).unwrap_err();
    assert!(
        matches!(
            err,
            StabilityError::Setting {
                field: "resolution",
                ..
            }
        ),
        "{err}"
    );
    // No gravity, at rest: nothing to measure the energy error against but
    // the elastic floor, which is positive: the search runs.
    assert!(largest_stable_step(&small(false), &method("stormer-verlet"), &quick()).is_ok());
}

#[test]
fn the_growth_of_a_stable_run_is_not_exponential() {
    let scene = small(true);
    let mut sim = Simulation::new(&scene).unwrap();
    let mut settings = RunSettings::from_scene(&scene);
    settings.options.frames = 40;
    let report = sim
        .run(&method("stormer-verlet"), &settings, |_| Ok(()))
        .unwrap();
    let e_ref = Scales::of(&scene).unwrap().e_ref;
    let times: Vec<f64> = report.frames.iter().map(|f| f.time).collect();
    let g = growth::fit(&times, &relative_errors(&report.frames, e_ref));
    assert!(!g.exponential(), "{g:?}");
    assert!(matches!(g.trend(), Some(Trend::Bounded | Trend::Power)));
}
