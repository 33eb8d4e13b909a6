//! The banded stepper (`cloth::step::banded`) against the scheme's own
//! step: the same trajectory to the bit for the library's drift–kick
//! sequences, to round-off for the explicit partitioned pairs, the same on
//! one thread or two, on grids down to 3 × 3 and a single free row.

use cloth::step::{Banding, sequence_of};
use cloth::{Method, RunError, RunOptions, RunSettings, Scene, Simulation};

/// An `n × n` sheet hanging from its top edge with all three spring
/// families, gravity, a sphere its middle starts inside and the ground.
fn scene(nx: usize, ny: usize) -> Scene {
    let text = format!(
        r#"
gravity = [0.0, -9.81, 0.0]
[cloth]
width = 1.2
height = 1.2
nx = {nx}
ny = {ny}
origin = [-0.6, 0.4, -0.6]
plane = "horizontal"
[material]
density = 0.1
stretch = 100.0
shear = 25.0
bend = 0.5
[pins]
edges = ["top"]
[[colliders]]
type = "sphere"
center = [0.0, 0.1, 0.0]
radius = 0.32
stiffness = 1.0e6
skin = 0.002
[[colliders]]
type = "plane"
point = [0.0, -0.35, 0.0]
normal = [0.0, 1.0, 0.0]
stiffness = 1.0e6
skin = 0.002
[simulation]
frame_rate = 60.0
substeps = 100
frames = 2
method = "leapfrog"
"#
    );
    Scene::from_toml(&text, "banded.toml").expect("test scene")
}

/// The state after the scene's 200 steps of `id` with `banding`, or the
/// run's error.
fn run(scene: &Scene, id: &str, banding: Banding) -> Result<Vec<f64>, RunError> {
    let mut sim = Simulation::new(scene).unwrap();
    let settings = RunSettings::from_scene(scene).with_banding(banding);
    sim.run(&Method::parse(id).unwrap(), &settings, |_| Ok(()))?;
    assert_eq!(sim.steps, 200);
    Ok(sim.state)
}

/// Every explicit library scheme that is a sequence of plain drifts and
/// kicks.
fn sequences() -> Vec<&'static str> {
    integrator_core::library::REGISTRY
        .iter()
        .map(|(id, _)| *id)
        .filter(|id| sequence_of(id).is_some())
        .collect()
}

#[test]
fn the_library_sequences_and_pairs_band() {
    let ids = sequences();
    for id in [
        "leapfrog",
        "forest-ruth",
        "symplectic-euler-a",
        "symplectic-euler-b",
        "stormer-verlet",
    ] {
        assert!(ids.contains(&id), "{id} not banded: {ids:?}");
    }
    assert!(!ids.contains(&"rk4") && !ids.contains(&"midpoint"));
}

/// Outcomes equal to the bit (a diverging run: the same error, step,
/// component and value).
fn assert_same(a: &Result<Vec<f64>, RunError>, b: &Result<Vec<f64>, RunError>, what: &str) {
    match (a, b) {
        (Ok(a), Ok(b)) => {
            let differ = a
                .iter()
                .zip(b)
                .position(|(x, y)| x.to_bits() != y.to_bits());
            assert_eq!(differ, None, "{what}: first difference at {differ:?}");
        }
        (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "{what}"),
        _ => panic!("{what}: {:?} vs {:?}", a.as_ref().err(), b.as_ref().err()),
    }
}

#[test]
fn drift_kick_sequences_step_to_the_bit_as_their_own_step() {
    let scene = scene(32, 32);
    let pairs = ["symplectic-euler-a", "symplectic-euler-b", "stormer-verlet"];
    let mut finished = 0;
    for id in sequences() {
        let one = run(&scene, id, Banding::Threads(1));
        let two = run(&scene, id, Banding::Threads(2));
        assert_same(&one, &two, &format!("{id}: one thread vs two"));
        if pairs.contains(&id) {
            continue;
        }
        let own = run(&scene, id, Banding::Off);
        assert_same(&own, &two, &format!("{id}: own step vs banded"));
        finished += usize::from(own.is_ok());
    }
    assert!(finished >= 10, "only {finished} sequences ran 200 steps");
}

#[test]
fn the_pairs_step_as_their_own_step_to_round_off() {
    let scene = scene(32, 32);
    let n = 3 * Simulation::new(&scene).unwrap().model.free_count();
    for id in ["symplectic-euler-a", "symplectic-euler-b", "stormer-verlet"] {
        let own = run(&scene, id, Banding::Off).unwrap();
        let banded = run(&scene, id, Banding::Threads(2)).unwrap();
        let gap = |r: std::ops::Range<usize>| {
            let scale = own[r.clone()].iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let d = own[r.clone()]
                .iter()
                .zip(&banded[r])
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            d / scale
        };
        let (dq, dp) = (gap(0..n), gap(n..2 * n));
        // Round-off of 200 compensated steps, grown by the stiff contact
        // (measured: |Δq|/|q| 2e-15 to 6e-13, |Δp|/|p| 1e-12 to 3.5e-11,
        // symplectic Euler (q first) the largest; the same bits on every
        // CPU, so the margin is for the scene, not the platform).
        assert!(
            dq < 1e-11 && dp < 1e-9,
            "{id}: |Δq|/|q| = {dq:e}, |Δp|/|p| = {dp:e}"
        );
        // Not the same bits: the pairs' own steps form their stage values
        // without the carried errors.
        assert_ne!(own, banded, "{id}");
    }
}

#[test]
fn small_grids_and_a_single_free_row() {
    for (nx, ny) in [(3, 3), (16, 2), (5, 4)] {
        let scene = scene(nx, ny);
        for id in ["leapfrog", "forest-ruth", "pefrl"] {
            let own = run(&scene, id, Banding::Off);
            for bands in [1, 2, 3] {
                let banded = run(&scene, id, Banding::Threads(bands));
                assert_same(&own, &banded, &format!("{nx}×{ny} {id} in {bands} bands"));
            }
        }
    }
}

#[test]
fn a_diverging_run_reports_the_same_step_and_component() {
    let scene = scene(16, 16);
    let mut opts = RunOptions::from_scene(&scene);
    opts.substeps = 2; // far beyond the stability limit
    opts.frames = 400;
    for id in ["leapfrog", "stormer-verlet"] {
        let outcome = |banding| {
            let mut sim = Simulation::new(&scene).unwrap();
            let settings = RunSettings::new(opts).with_banding(banding);
            let Err(err) = sim.run(&Method::parse(id).unwrap(), &settings, |_| Ok(())) else {
                panic!("{id}: ran to the end");
            };
            // Left at the last good frame.
            assert_eq!(sim.steps, 2 * sim.frame, "{id}");
            err
        };
        let (own, banded) = (outcome(Banding::Off), outcome(Banding::Threads(2)));
        match (&own, &banded) {
            (RunError::Diverged { step: s0, .. }, RunError::Diverged { step: s1, .. }) => {
                assert_eq!(s0, s1, "{id}")
            }
            _ => panic!("{id}: {own} / {banded}"),
        }
        if id == "leapfrog" {
            assert_eq!(own.to_string(), banded.to_string());
        }
    }
}

#[test]
fn auto_bands_from_banded_from_on_two_cores() {
    use cloth::step::banded::{BANDED_FROM, BANDS};
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let model = |n: usize| cloth::ClothModel::new(&scene(n, n)).unwrap();
    let (small, large) = (model(16), model(32));
    assert!(small.particle_count() < BANDED_FROM && large.particle_count() >= BANDED_FROM);
    assert_eq!(Banding::Auto.bands(&small), None);
    let expected = (cores > 1).then_some(BANDS.min(cores));
    assert_eq!(Banding::Auto.bands(&large), expected);
    assert_eq!(Banding::Off.bands(&large), None);
    assert_eq!(Banding::Threads(0).bands(&small), Some(1));
    assert_eq!(Banding::Threads(99).bands(&small), Some(16));
}

/// The tests of the SIMD levels below set the process's cap
/// (`integrator_core::simd::set_cap`) one after another.
static CAP: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// At `level` and at the portable level, the stencil force at a state off
/// the grid (64² particles) and banded runs (leapfrog on one thread,
/// Forest–Ruth on two, 200 steps of a 32² sheet with colliders) give the
/// same bits.
fn same_bits_as_portable(level: integrator_core::simd::Level) {
    use integrator_core::Separable;
    use integrator_core::simd::{Level, set_cap};
    let _one_at_a_time = CAP.lock().unwrap_or_else(|e| e.into_inner());
    assert!(
        level.available(),
        "the tests were built where this processor had {level}, and run where it has not: rebuild them here"
    );
    println!("cloth simd: {level} here, compared with the portable level");
    let model = cloth::ClothModel::new(&scene(64, 64)).unwrap();
    // The runs on the grid the other tests step stably.
    let scene = scene(32, 32);
    let n = model.dof();
    let q = crate::common::perturbed(&model);
    let mut out = Vec::new();
    for l in [level, Level::Portable] {
        set_cap(Some(l));
        assert_eq!(integrator_core::simd::level(), l);
        let mut f = vec![f64::NAN; n];
        model.force(&q, &mut f);
        let one = run(&scene, "leapfrog", Banding::Threads(1));
        let two = run(&scene, "forest-ruth", Banding::Threads(2));
        out.push((f, one, two));
    }
    set_cap(None);
    let differ = out[0]
        .0
        .iter()
        .zip(&out[1].0)
        .position(|(x, y)| x.to_bits() != y.to_bits());
    assert_eq!(differ, None, "{level}: the stencil force differs");
    assert!(
        out[0].1.is_ok() && out[0].2.is_ok(),
        "{level}: a run failed"
    );
    assert_same(
        &out[0].1,
        &out[1].1,
        &format!("{level}: leapfrog, one band"),
    );
    assert_same(
        &out[0].2,
        &out[1].2,
        &format!("{level}: forest-ruth, two bands"),
    );
}

#[test]
#[cfg_attr(
    not(symlab_avx512),
    ignore = "this machine has no AVX-512F (found when the tests were built)"
)]
fn the_avx512_stencil_and_banded_steps_give_the_portable_bits() {
    same_bits_as_portable(integrator_core::simd::Level::Avx512);
}

#[test]
#[cfg_attr(
    not(symlab_avx2),
    ignore = "this machine has no AVX2 (found when the tests were built)"
)]
fn the_avx2_stencil_and_banded_steps_give_the_portable_bits() {
    same_bits_as_portable(integrator_core::simd::Level::Avx2);
}
