//! The springs at equal stretch (`cloth::study::equal_stretch`): the study
//! runs on a small sheet and keeps its bound; its stretch is a measurement
//! (a softer spring stretches more, past the bound, a stiffer one less; the
//! measure is the largest warp or weft edge's); it refuses a spring scene
//! and a scene without gravity, naming the field.

use cloth::study::equal_stretch::{
    EqualStretchSettings, MAX_STRETCH, Sampled, WarpWeft, spring_trial, spring_twin, study,
};
use cloth::{Method, RunOptions, RunSettings, Scene, Simulation};
use nalgebra::Vector3;

/// The shipped `scenes/paper64-inextensible.toml` (the paper's sheet,
/// inextensible, released 45° from hanging, with its bending) at `n²` for
/// `frames` frames.
fn sheet(n: usize, frames: usize) -> Scene {
    let mut scene = Scene::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/paper64-inextensible.toml"
    ))
    .unwrap();
    cloth::scene::regrid(&mut scene, n, n);
    scene.simulation.frames = frames;
    scene
}

#[test]
fn the_study_runs_on_a_small_sheet_and_keeps_its_bound() {
    let scene = sheet(8, 60);
    let found = study(&scene, &EqualStretchSettings::new(60)).unwrap();
    assert_eq!(found.grid, (8, 8));
    assert!((found.duration - 1.0).abs() < 1e-12);
    let taken = &found.trials[found.taken];
    assert!(
        taken.max_stretch <= MAX_STRETCH && taken.max_stretch > 0.0,
        "{:?}",
        found.trials
    );
    // Springs on one thread (8² is not banded), RATTLE without and with
    // the scene's bending.
    let models: Vec<&str> = found.rows.iter().map(|r| r.model.as_str()).collect();
    assert_eq!(
        models,
        [
            "springs, 1 thread",
            "RATTLE, no bending",
            "RATTLE, bending 3e-6 N·m"
        ]
    );
    for row in &found.rows {
        assert_eq!(row.run.frames, 60, "{}", row.model);
        assert!((row.run.duration - 1.0).abs() < 1e-9, "{}", row.model);
        assert!(row.run.stepping_seconds > 0.0, "{}", row.model);
        assert!(
            row.run.max_energy_error.is_finite() && row.run.max_energy_error < 1e-2,
            "{}: {}",
            row.model,
            row.run.max_energy_error
        );
        let (lo, mean, hi) = row.run.steps_per_frame;
        assert!(lo >= 1 && lo as f64 <= mean && mean <= hi as f64);
        assert!(
            (row.run.steps as f64 - mean * 60.0).abs() < 1e-9,
            "{}",
            row.model
        );
    }
    let springs = &found.rows[0];
    assert_eq!(springs.stiffness, Some(taken.stiffness));
    assert_eq!(springs.sampled, Sampled::EveryStep);
    assert_eq!(springs.run.steps_per_frame.0, taken.substeps);
    assert!(springs.max_stretch <= MAX_STRETCH);
    // The timed run is the trial's trajectory sampled at the frames only:
    // it cannot see more stretch than every step did.
    assert!(
        springs.run.max_stretch <= taken.max_stretch * (1.0 + 1e-9),
        "frames {} > steps {}",
        springs.run.max_stretch,
        taken.max_stretch
    );
    // RATTLE holds its constraints to round-off.
    for row in &found.rows[1..] {
        assert_eq!(row.sampled, Sampled::EveryFrame);
        assert!(
            row.max_stretch < 1e-12,
            "{}: {}",
            row.model,
            row.max_stretch
        );
    }
}

#[test]
fn a_softer_spring_stretches_more_and_is_reported_past_the_bound() {
    let scene = sheet(8, 60);
    let found = study(&scene, &EqualStretchSettings::new(60)).unwrap();
    let k = found.trials[found.taken].stiffness;
    let soft = spring_trial(&scene, k / 4.0, 60).unwrap();
    let taken = spring_trial(&scene, k, 60).unwrap();
    let stiff = spring_trial(&scene, 4.0 * k, 60).unwrap();
    assert!(soft.failed.is_none() && taken.failed.is_none() && stiff.failed.is_none());
    // The same trial again measures the same (the run is deterministic).
    assert_eq!(taken.max_stretch, found.trials[found.taken].max_stretch);
    assert!(
        soft.max_stretch > MAX_STRETCH,
        "k/4 = {:e} N: {}",
        k / 4.0,
        soft.max_stretch
    );
    assert!(soft.max_stretch > taken.max_stretch && taken.max_stretch > stiff.max_stretch);
    // Under the same tension a spring's stretch goes like 1/k: four times
    // softer, about four times the stretch (the motion changes too).
    let ratio = soft.max_stretch / taken.max_stretch;
    assert!(ratio > 2.0 && ratio < 8.0, "{ratio}");
}

#[test]
fn the_measure_is_the_largest_warp_or_weft_edge() {
    let scene = sheet(3, 1);
    let edges = WarpWeft::of(&scene);
    assert_eq!((edges.nx, edges.ny), (3, 3));
    assert_eq!((edges.dx, edges.dy), (0.5, 0.5));
    let sim = Simulation::new(&scene).unwrap();
    let mut p = sim.model.positions(&sim.state[..sim.state.len() / 2]);
    assert!(edges.max_stretch(&p) < 1e-15);
    // Particle (2, 1) moved 5 % of an edge outwards along the row: its
    // row edge stretches by 5 %, its column edges by √(1 + 0.05²) − 1.
    p[3 + 2].x += 0.05 * 0.5;
    assert!((edges.max_stretch(&p) - 0.05).abs() < 1e-12);
    // Compressed by 7 % counts as 7 %.
    p[3 + 2].x -= 0.05 * 0.5;
    p[3 + 1].x -= 0.07 * 0.5;
    assert!((edges.max_stretch(&p) - 0.07).abs() < 1e-12);
    p[4] = Vector3::new(f64::NAN, 0.0, 0.0);
    assert!(edges.max_stretch(&p).is_nan());
}

#[test]
fn the_twin_is_the_same_sheet_with_springs() {
    let scene = sheet(6, 10);
    let twin = spring_twin(&scene, 0.5).unwrap();
    assert!(!twin.material.inextensible);
    assert_eq!(twin.material.stretch, Some(0.5));
    assert_eq!(twin.material.shear, scene.material.shear);
    assert_eq!(twin.material.bending, 0.0);
    assert_eq!(
        (&twin.cloth, &twin.pins, twin.gravity),
        (&scene.cloth, &scene.pins, scene.gravity)
    );
    assert!(twin.simulation.variable.is_none());
    // It runs as a spring scene.
    let mut sim = Simulation::new(&twin).unwrap();
    let method = Method::parse(&twin.simulation.method).unwrap();
    let options = RunOptions {
        frames: 2,
        substeps: 40,
        frame_rate: 60.0,
    };
    sim.run(&method, &RunSettings::new(options), |_| Ok(()))
        .unwrap();
}

#[test]
fn a_spring_scene_and_a_scene_without_gravity_are_refused_naming_the_field() {
    let springs = Scene::from_toml(
        r#"
        gravity = [0.0, -9.81, 0.0]
        [cloth]
        width = 1.0
        height = 1.0
        nx = 4
        ny = 4
        [material]
        density = 0.1
        stretch = 10.0
        [pins]
        edges = ["top"]
        [simulation]
        substeps = 10
        frames = 3
        method = "stormer-verlet"
    "#,
        "springs.toml",
    )
    .unwrap();
    let err = study(&springs, &EqualStretchSettings::new(3)).unwrap_err();
    assert!(err.to_string().starts_with("material.stretch: "), "{err}");
    let mut still = sheet(4, 3);
    still.gravity = [0.0; 3];
    let err = study(&still, &EqualStretchSettings::new(3)).unwrap_err();
    assert!(err.to_string().starts_with("gravity: "), "{err}");
    let err = study(&sheet(4, 3), &EqualStretchSettings::new(0)).unwrap_err();
    assert!(err.to_string().starts_with("frames: "), "{err}");
}
