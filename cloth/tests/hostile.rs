//! Hostile, huge and long input: every scene a user can write either
//! loads into a model with a finite initial state or is refused with an
//! error naming the file and the field; runs that could not end (or could
//! not move) are refused before they start; an explicit run never builds
//! the sparse Jacobian; and random mutations of the shipped scenes never
//! panic.

use std::path::PathBuf;

use crate::common;
use common::{run_id, run_stage};

use cloth::step::stage::MAX_FREE_PARTICLES;
use cloth::{
    MAX_FRAMES, MAX_PARTICLES, MAX_STEPS, RunError, RunOptions, Scene, SceneError, Simulation,
};
use proptest::prelude::*;

fn scene_text(name: &str) -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../scenes/{name}.toml"));
    std::fs::read_to_string(path).unwrap()
}

/// The paper scene with `from` replaced by `to` (which must occur).
fn paper_with(edits: &[(&str, &str)]) -> String {
    let mut text = scene_text("paper");
    for (from, to) in edits {
        assert!(text.contains(from), "{from}");
        text = text.replacen(from, to, 1);
    }
    text
}

/// Load the text, build the model: the error, whichever step gave it.
fn build(text: &str) -> Result<Simulation, SceneError> {
    let scene = Scene::from_toml(text, "hostile.toml")?;
    Simulation::new(&scene).map_err(|e| match e {
        // The model names the scene by its name; the tests want the field.
        SceneError::Field { field, message, .. } => SceneError::Field {
            file: "hostile.toml".into(),
            field,
            message,
        },
        other => other,
    })
}

fn refused(text: &str, field: &str) -> String {
    match build(text) {
        Ok(sim) => panic!(
            "accepted, initial energy {:e}; expected an error about {field}",
            sim.stats().energy.total()
        ),
        Err(e) => {
            assert_eq!(e.field(), Some(field), "{e}");
            let message = e.to_string();
            assert!(message.contains("hostile.toml"), "{message}");
            message
        }
    }
}

#[test]
fn extreme_numbers_are_refused_naming_the_field_that_makes_them_extreme() {
    // Each field finite on its own, a derived quantity not: the initial
    // state would be non-finite (these used to panic in `symlab cloth`).
    refused(
        &paper_with(&[("width = 1.0", "width = 1e308")]),
        "cloth.width",
    );
    refused(
        &paper_with(&[("stretch = 50.75", "stretch = 1e308")]),
        "material.stretch",
    );
    let m = refused(
        &paper_with(&[
            ("width = 1.0", "width = 1e-300"),
            ("height = 1.0", "height = 1e-300"),
        ]),
        "cloth.width",
    );
    // The spacing (width over the grid) is what leaves the normal range.
    assert!(m.contains("grid spacing"), "{m}");
    refused(
        &paper_with(&[("density = 0.01378", "density = 1e-320")]),
        "material.density",
    );
    // The weight of the cloth falling by its size overflows: 1e10 kg/m² ×
    // 1 m² × 1e300 m/s² × 1 m.
    refused(
        &paper_with(&[
            (
                "gravity = [0.0, -9.81, 0.0]",
                "gravity = [0.0, -1e300, 0.0]",
            ),
            ("density = 0.01378", "density = 1e10"),
        ]),
        "gravity",
    );
    refused(
        &paper_with(&[(
            "plane = \"horizontal\"",
            "plane = \"horizontal\"\nprestretch = 1e-310",
        )]),
        "cloth.prestretch",
    );
    let m = refused(
        &paper_with(&[("origin = [0.0, 0.0, 0.0]", "origin = [1e20, 0.0, 0.0]")]),
        "cloth.origin",
    );
    assert!(m.contains("rounding"), "{m}");
    // h = 1/(frame_rate·substeps) rounds to 0: refused, not a run that
    // reports success without moving.
    let m = refused(
        &paper_with(&[("frame_rate = 60.0", "frame_rate = 1e308")]),
        "simulation.frame_rate",
    );
    assert!(m.contains("normal"), "{m}");
}

#[test]
fn colliders_too_large_for_the_initial_state_are_refused() {
    // A [[colliders]] table before [simulation] (after it, its keys
    // would belong to the collider).
    let text = |radius: &str, stiffness: &str| {
        paper_with(&[(
            "[simulation]",
            &format!(
                "[[colliders]]\ntype = \"sphere\"\ncenter = [0.5, -1.0, 0.5]\nradius = {radius}\nstiffness = {stiffness}\n\n[simulation]"
            ),
        )])
    };
    refused(&text("1e308", "1e4"), "colliders[0].radius");
    // Finite scales, but the cloth starts 1e150 m deep inside a stiff
    // sphere: the penalty energy overflows, found by building the model.
    let m = refused(&text("1e150", "1e300"), "colliders[0]");
    assert!(m.contains("deep inside"), "{m}");
    // A sane sphere loads and builds.
    build(&text("0.5", "1e4")).unwrap();
}

#[test]
fn a_huge_grid_blames_the_side_that_is_huge() {
    let m = refused(&paper_with(&[("ny = 25", "ny = 100000000000")]), "cloth.ny");
    assert!(m.contains(&MAX_PARTICLES.to_string()), "{m}");
    refused(&paper_with(&[("nx = 25", "nx = 100000000000")]), "cloth.nx");
    refused(
        &paper_with(&[("nx = 25", "nx = 2049"), ("ny = 25", "ny = 2048")]),
        "cloth.nx",
    );
    // At the limit it is accepted (validation only: nothing is built).
    let at = paper_with(&[("nx = 25", "nx = 2048"), ("ny = 25", "ny = 2048")]);
    assert_eq!(2048 * 2048, MAX_PARTICLES);
    Scene::from_toml(&at, "hostile.toml").unwrap();
}

#[test]
fn runs_that_would_not_end_are_refused_before_they_start() {
    let huge = i64::MAX.to_string();
    let m = refused(
        &paper_with(&[("frames = 300", &format!("frames = {huge}"))]),
        "simulation.frames",
    );
    assert!(m.contains(&MAX_FRAMES.to_string()), "{m}");
    let m = refused(
        &paper_with(&[("substeps = 256", &format!("substeps = {huge}"))]),
        "simulation.substeps",
    );
    assert!(m.contains(&MAX_STEPS.to_string()), "{m}");
    // Options given in code are checked by every run, explicit or implicit.
    let scene = Scene::from_toml(&scene_text("paper"), "paper.toml").unwrap();
    for (opts, what) in [
        (
            RunOptions {
                frames: usize::MAX,
                substeps: 1,
                frame_rate: 60.0,
            },
            "frames",
        ),
        (
            RunOptions {
                frames: 10,
                substeps: usize::MAX,
                frame_rate: 60.0,
            },
            "substeps",
        ),
        (
            RunOptions {
                frames: 1,
                substeps: 256,
                frame_rate: 1e308,
            },
            "frame_rate",
        ),
    ] {
        for method in ["leapfrog", "gauss2"] {
            let mut sim = Simulation::new(&scene).unwrap();
            let clock = std::time::Instant::now();
            match run_id(&mut sim, method, &opts, |_| Ok(())) {
                Err(RunError::Options(m)) => assert!(m.starts_with(what), "{m}"),
                other => panic!("{method} {opts:?}: {:?}", other.map(|r| r.steps)),
            }
            assert!(clock.elapsed().as_secs_f64() < 1.0);
            assert_eq!(sim.steps, 0);
        }
    }
}

#[test]
fn a_cloth_at_rest_has_a_finite_start_and_an_elastic_energy_scale() {
    // No gravity, no pins: H₀ is round-off. The model still has an energy
    // scale of its own (the CLI's E_ref floor).
    let text = paper_with(&[
        ("gravity = [0.0, -9.81, 0.0]", ""),
        ("edges = [\"top\"]", ""),
    ]);
    let sim = build(&text).unwrap();
    let h0 = sim.stats().energy.total();
    assert!(h0.abs() < 1e-20, "{h0}");
    let scale = sim.model.elastic_energy_scale(1e-4);
    // ½·Σ k·L·ε²: 1200 stretch springs of 50.75·(1/24), 1152 shear of 50.75·(√2/24).
    let expected = 0.5 * 1e-8 * 50.75 * (1200.0 / 24.0 + 1152.0 * std::f64::consts::SQRT_2 / 24.0);
    assert!(
        (scale - expected).abs() <= 1e-12 * expected,
        "{scale} vs {expected}"
    );
}

#[test]
fn an_explicit_run_never_builds_the_sparse_jacobian() {
    let scene = Scene::from_toml(&scene_text("sphere"), "sphere.toml").unwrap();
    let opts = RunOptions {
        frames: 2,
        substeps: 3,
        frame_rate: 60.0,
    };
    let mut sim = Simulation::new(&scene).unwrap();
    run_id(&mut sim, "leapfrog", &opts, |_| Ok(())).unwrap();
    let st = sim.model.stability();
    assert!(st.omega_max > 0.0 && st.omega_max <= st.omega_bound * (1.0 + 1e-12));
    assert!(
        !sim.model.jacobian_built(),
        "an explicit run built the Jacobian"
    );
    let mut sim = Simulation::new(&scene).unwrap();
    run_stage(
        &mut sim,
        "midpoint",
        &RunOptions { frames: 1, ..opts },
        None,
        |_| Ok(()),
    )
    .unwrap();
    assert!(sim.model.jacobian_built());
}

#[test]
fn the_matrix_free_gershgorin_bound_is_that_of_the_assembled_jacobian() {
    // With the cloth pushed into the sphere, so that collider blocks add
    // to the diagonal.
    let scene = Scene::from_toml(&scene_text("sphere"), "sphere.toml").unwrap();
    let sim = Simulation::new(&scene).unwrap();
    let n = 3 * sim.model.free_count();
    let mut q = sim.state[..n].to_vec();
    let Some(cloth::Collider::Sphere { center, radius, .. }) = scene.colliders.first().cloned()
    else {
        panic!("the sphere scene has a sphere")
    };
    for x in q.chunks_mut(3) {
        // Half of the particles a little inside the sphere's top.
        if x[0] < center[0] {
            x[1] = center[1] + 0.98 * radius;
        }
    }
    let pattern = sim.model.force_jacobian_pattern();
    let mut values = vec![0.0; pattern.len()];
    sim.model.force_jacobian_values(&q, &mut values);
    let mut rows = vec![0.0f64; n];
    for (&(r, _), v) in pattern.iter().zip(&values) {
        rows[r] += (v * sim.model.inverse_mass()).abs();
    }
    let assembled = rows.iter().copied().fold(0.0, f64::max).sqrt();
    let st = sim.model.stability_at(&q, 50);
    assert!(
        (st.omega_bound - assembled).abs() <= 1e-12 * assembled,
        "{} vs {assembled}",
        st.omega_bound
    );
    assert!(st.omega_max <= st.omega_bound * (1.0 + 1e-12));
}

#[test]
fn implicit_methods_refuse_grids_too_large_for_the_sparse_lu() {
    let text = paper_with(&[("nx = 25", "nx = 300"), ("ny = 25", "ny = 300")]);
    let mut sim = build(&text).unwrap();
    let opts = RunOptions {
        frames: 1,
        substeps: 1,
        frame_rate: 60.0,
    };
    match run_id(&mut sim, "gauss2", &opts, |_| Ok(())) {
        Err(RunError::Options(m)) => {
            assert!(m.contains(&MAX_FREE_PARTICLES.to_string()), "{m}")
        }
        other => panic!("{:?}", other.map(|r| r.steps)),
    }
    assert!(!sim.model.jacobian_built());
}

/// Values a hostile user puts in a scene file.
const EXTREME: &[&str] = &[
    "0",
    "-1",
    "1",
    "2",
    "1e308",
    "-1e308",
    "1e-300",
    "5e-324",
    "1e154",
    "nan",
    "inf",
    "-inf",
    "\"NaN\"",
    "\"\"",
    "9223372036854775807",
    "-9223372036854775808",
    "18446744073709551616",
    "100000000000",
    "1.0e15",
    "true",
    "[]",
    "[1e308, 1e308, 1e308]",
    "[0.0, 0.0, 0.0]",
    "[nan, 0.0, 0.0]",
    "[[1, 1], [-1, 0]]",
];

/// A mutation of a scene file: replace the value of the `line`-th
/// `key = value` line (modulo their number) by `EXTREME[value]`, or remove
/// the line.
#[derive(Clone, Debug)]
enum Mutation {
    Replace { line: usize, value: usize },
    Remove { line: usize },
}

fn mutate(text: &str, mutations: &[Mutation]) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for m in mutations {
        let keyed: Vec<usize> = lines
            .iter()
            .enumerate()
            .filter(|(_, l)| {
                let l = l.trim_start();
                !l.starts_with('#') && !l.starts_with('[') && l.contains('=')
            })
            .map(|(k, _)| k)
            .collect();
        if keyed.is_empty() {
            break;
        }
        match *m {
            Mutation::Replace { line, value } => {
                let k = keyed[line % keyed.len()];
                let key = lines[k].split('=').next().unwrap().to_string();
                lines[k] = format!("{key}= {}", EXTREME[value % EXTREME.len()]);
            }
            Mutation::Remove { line } => {
                lines.remove(keyed[line % keyed.len()]);
            }
        }
    }
    lines.join("\n")
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<usize>(), any::<usize>()).prop_map(|(line, value)| Mutation::Replace { line, value }),
        1 => any::<usize>().prop_map(|line| Mutation::Remove { line }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// Loading, validating and building a randomly mutated shipped scene
    /// never panics: it gives a model whose initial state, energy and
    /// forces are finite, and which steps (or stops with an error), or an
    /// error that names the file and, unless the text is not TOML, a field.
    #[test]
    fn mutated_scenes_load_or_fail_naming_a_field(
        which in 0usize..4,
        mutations in prop::collection::vec(mutation(), 1..4),
    ) {
        let name = ["paper", "corners", "sphere", "stiff"][which];
        let text = mutate(&scene_text(name), &mutations);
        match Scene::from_toml(&text, "mutated.toml") {
            Err(SceneError::Field { file, field, message }) => {
                prop_assert_eq!(file, "mutated.toml");
                prop_assert!(!field.is_empty() && !message.is_empty());
            }
            Err(e @ SceneError::Syntax { .. }) => {
                prop_assert!(e.to_string().starts_with("mutated.toml: "), "{}", e);
            }
            Err(e) => prop_assert!(false, "unexpected {}", e),
            Ok(scene) => match Simulation::new(&scene) {
                Err(SceneError::Field { field, message, .. }) => {
                    prop_assert!(!field.is_empty() && !message.is_empty());
                }
                Err(e) => prop_assert!(false, "unexpected {}", e),
                Ok(mut sim) => {
                    prop_assert!(sim.state.iter().all(|x| x.is_finite()));
                    let e = sim.stats().energy;
                    prop_assert!(e.total().is_finite(), "{:?}", e);
                    // A few steps with the scene's method, whatever comes of them.
                    let opts = RunOptions { frames: 1, substeps: 2, ..RunOptions::from_scene(&scene) };
                    if sim.model.free_count() <= 2000 {
                        let _ = run_id(&mut sim, &scene.simulation.method, &opts, |_| Ok(()));
                    }
                }
            },
        }
    }
}
