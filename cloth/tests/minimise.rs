//! The midpoint family as energy minimisation (`cloth::step::minimise`): the
//! steps equal the generic stage solver's to round-off, momentum is kept by
//! every solver, an iteration cap is an error naming the step and time, bad
//! settings are refused, the discrete gradient and the average vector field
//! keep energy, and a user's table of midpoint shape takes this path.

use crate::common;
use common::{minimise_stats, run_minimise, run_stage};

use cloth::step::minimise::{MinimiseError, MinimiseStepper, Minimiser};
use cloth::{
    AVERAGE_VECTOR_FIELD, DISCRETE_GRADIENT, Method, MinimiseSettings as Settings, RunError,
    RunOptions, RunSettings, Scene, Simulation, Solver,
};

/// The composition weights of a method of the midpoint family.
fn weights_of(id: &str) -> Option<Vec<f64>> {
    Method::parse(id)
        .ok()
        .and_then(|m| m.midpoint_weights())
        .map(<[f64]>::to_vec)
}

/// Whether `id` is solved by minimisation (or the discrete gradient).
fn is_minimisation(id: &str) -> bool {
    Method::parse(id).is_ok_and(|m| m.minimises())
}

/// 6 × 5 particles, all three families, pinned at two corners, gravity,
/// starting stretched by 5 %, and a sphere collider it falls onto.
const SMALL: &str = r#"
gravity = [0.0, -9.81, 0.0]

[cloth]
width = 0.4
height = 0.3
nx = 6
ny = 5
prestretch = 1.05

[material]
density = 0.2
stretch = 30.0
shear = 8.0
bend = 0.5

[pins]
corners = ["top-left", "top-right"]

[[colliders]]
type = "sphere"
center = [0.2, -0.1, 0.15]
radius = 0.12
stiffness = 1.0e3
skin = 0.01

[simulation]
substeps = 1
frames = 1
method = "midpoint"
"#;

/// 6 × 6 particles, no gravity, no pins, stretched by 20 % and released.
const STRETCHED: &str = r#"
[cloth]
width = 0.5
height = 0.5
nx = 6
ny = 6
prestretch = 1.05
origin = [0.3, -0.2, 0.1]

[material]
density = 0.1
stretch = 40.0
shear = 10.0
bend = 1.0

[simulation]
substeps = 1
frames = 1
method = "midpoint"
"#;

fn scene(text: &str) -> Scene {
    Scene::from_toml(text, "inline.toml").unwrap()
}

fn opts(frames: usize, substeps: usize) -> RunOptions {
    RunOptions {
        frames,
        substeps,
        frame_rate: 60.0,
    }
}

/// The largest difference between two states, relative to the largest
/// component of either half (positions, momenta).
fn state_difference(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() / 2;
    let mut worst: f64 = 0.0;
    for (x, y) in [(&a[..n], &b[..n]), (&a[n..], &b[n..])] {
        let scale = x.iter().chain(y.iter()).fold(0.0f64, |m, v| m.max(v.abs()));
        let diff = x
            .iter()
            .zip(y)
            .fold(0.0f64, |m, (u, v)| m.max((u - v).abs()));
        worst = worst.max(diff / scale);
    }
    worst
}

#[test]
fn composition_is_read_off_the_table() {
    assert_eq!(weights_of("midpoint"), Some(vec![1.0]));
    assert_eq!(weights_of("paper-dirk2"), Some(vec![0.5, 0.5]));
    let w = weights_of("paper-dirk4").unwrap();
    let x = 1.0 / (2.0 - 2f64.cbrt());
    assert_eq!(w.len(), 3);
    assert!((w[0] - x).abs() < 1e-15 && (w[1] - (1.0 - 2.0 * x)).abs() < 1e-14);
    // Not compositions of midpoint steps.
    for id in ["gauss2", "gauss3", "implicit-euler", "radau2a-3"] {
        assert_eq!(weights_of(id), None, "{id}");
        assert!(!is_minimisation(id));
    }
    assert!(is_minimisation(DISCRETE_GRADIENT));
}

/// At a small step where both converge, the minimisation step is the
/// generic stage solver's implicit midpoint (and paper-dirk2) step, with
/// and without colliders, to round-off after 120 steps. The stage solver
/// is iterated to round-off here (stagnation limit 1e-13, no plateau
/// rule): with the cloth's defaults ([`cloth::step::stage::cloth_settings`], which
/// accept a stagnation at 1e-9 of the stage values) it stops short on the
/// collider scene, 8.3e-10 from both (measured).
///
/// Round-off here: every force evaluation carries about `ε·S`, `S` the
/// force scale ([`cloth::ClothModel::force_and_scale`], dominated by the
/// stiffness times `‖q‖_∞`: ~170–330 N here, against momenta of ~3e-3), a
/// kick adds `h` times it to the momenta, and over the run that adds up to
/// `R = ε·steps·h·S/‖p‖_∞` ≈ 1e-12 relative to the momenta. Measured
/// (tolerance 1e-14): 0.8–6.4 R (1.3e-12 to 5.8e-12); positions agree far
/// closer.
#[test]
fn equals_the_stage_solver_to_roundoff() {
    for text in [SMALL, STRETCHED] {
        for id in ["midpoint", "paper-dirk2"] {
            let sc = scene(text);
            let o = opts(6, 20); // h = 1/1200 s, 120 steps
            let mut a = Simulation::new(&sc).unwrap();
            let mut b = Simulation::new(&sc).unwrap();
            let tight = Settings {
                tolerance: 1e-14,
                ..Settings::default()
            };
            let n = a.state.len() / 2;
            let model = a.model.clone();
            let mut f = vec![0.0; n];
            let mut s_max: f64 = 0.0;
            let run = run_minimise(&mut a, id, &o, tight, |frame| {
                s_max = s_max.max(model.force_and_scale(&frame.state[..n], &mut f));
                Ok(())
            })
            .unwrap();
            let stage = integrator_core::implicit::Settings {
                stagnation_limit: 1e-13,
                plateau_limit: 0.0,
                ..cloth::step::stage::cloth_settings()
            };
            run_stage(&mut b, id, &o, Some(stage), |_| Ok(())).unwrap();
            let d = state_difference(&a.state, &b.state);
            let p_max = a.state[n..].iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let r = f64::EPSILON * 120.0 * o.step_size() * s_max / p_max;
            println!(
                "{id}: states differ by {d:e} = {:.2} R (R = {r:e}) after 120 steps",
                d / r
            );
            assert!(r < 3e-12, "{id}: R = {r:e}");
            assert!(
                d < 16.0 * r,
                "{id}: states differ by {d:e} = {} R after 120 steps",
                d / r
            );
            assert_eq!(minimise_stats(&run).steps, 120);
            assert_eq!(minimise_stats(&run).floor_accepts, 0);
            assert_eq!(minimise_stats(&run).symbolic_factorizations, 1);
            assert_eq!(run.method, Method::parse(id).unwrap().name());
        }
    }
}

/// The local/global solver converges to the same steps as Newton.
#[test]
fn local_global_agrees_with_newton() {
    let sc = scene(STRETCHED);
    let o = opts(3, 4); // h = 1/240 s
    let mut a = Simulation::new(&sc).unwrap();
    let mut b = Simulation::new(&sc).unwrap();
    let n = run_minimise(&mut a, "midpoint", &o, Settings::default(), |_| Ok(())).unwrap();
    let l = run_minimise(
        &mut b,
        "midpoint",
        &o,
        Settings::new(Solver::LocalGlobal),
        |_| Ok(()),
    )
    .unwrap();
    let d = state_difference(&a.state, &b.state);
    // Measured 1.1e-9: both stop at ‖∇Φ‖ ≤ 1e-12 of the force scale, and the
    // momenta (small beside the positions) show that as ~1e-9 relative.
    assert!(d < 1e-8, "newton and local-global differ by {d:e}");
    // One factorisation per step size for local/global; Newton at most one
    // per iteration (it keeps a factor while it contracts).
    assert_eq!(minimise_stats(&l).factorizations, 1);
    assert!(minimise_stats(&n).factorizations <= minimise_stats(&n).iterations);
}

/// With gravity off, a released stretched sheet keeps its total momentum
/// (zero) to round-off, with every solver and scheme, at h = 1/60 s. Each
/// Newton or local/global iteration keeps `Σ(x − y) = 0` exactly in exact
/// arithmetic (the springs' Hessian and Laplacian annihilate translations),
/// so what is left is round-off, amplified by the condition of the step's
/// matrix (~1e3 here): measured up to 1.5e-13 of the momentum scale.
#[test]
fn momentum_is_conserved_by_every_solver() {
    let sc = scene(STRETCHED);
    let o = opts(30, 1); // h = 1/60 s
    let m_total = Simulation::new(&sc).unwrap().model.particle_mass() * 36.0;
    // The discrete gradient at h = 1/240 s: at 1/60 s its Newton iteration
    // fails on this sheet at step 21 (README). The average vector field,
    // a minimisation, at 1/60 s.
    for (id, solver, o) in [
        ("midpoint", Solver::Newton, o),
        ("midpoint", Solver::LocalGlobal, o),
        ("paper-dirk2", Solver::Newton, o),
        ("paper-dirk4", Solver::Newton, o),
        (DISCRETE_GRADIENT, Solver::Newton, opts(30, 4)),
        (AVERAGE_VECTOR_FIELD, Solver::Newton, o),
    ] {
        let mut sim = Simulation::new(&sc).unwrap();
        let run = run_minimise(&mut sim, id, &o, Settings::new(solver), |_| Ok(())).unwrap();
        // Momentum scale: the sheet's mass times the speed its spring energy would give.
        let e = run.frames[0].energy.total();
        let p_scale = (2.0 * e * m_total).sqrt();
        for f in &run.frames {
            let p = f.momentum.norm();
            assert!(
                p < 1e-11 * p_scale,
                "{id} ({}): |P| = {p:e} at frame {} (scale {p_scale:e})",
                solver.name(),
                f.frame
            );
        }
    }
}

/// The discrete gradient keeps the energy to the solver's tolerance.
#[test]
fn discrete_gradient_keeps_energy() {
    let sc = scene(STRETCHED);
    let o = opts(60, 4); // h = 1/240 s (at 1/60 s its Newton iteration fails: README)
    let mut sim = Simulation::new(&sc).unwrap();
    let run = run_minimise(&mut sim, DISCRETE_GRADIENT, &o, Settings::default(), |_| {
        Ok(())
    })
    .unwrap();
    let e0 = run.frames[0].energy.total();
    let worst = run
        .frames
        .iter()
        .map(|f| ((f.energy.total() - e0) / e0).abs())
        .fold(0.0, f64::max);
    assert!(
        worst < 1e-8,
        "discrete gradient: relative energy error {worst:e}"
    );
}

/// A solve that reaches its iteration cap is an error naming the step and
/// time; nothing is accepted.
#[test]
fn iteration_cap_is_an_error() {
    let sc = scene(SMALL);
    let mut sim = Simulation::new(&sc).unwrap();
    let before = sim.state.clone();
    let settings = Settings {
        max_iterations: 1,
        ..Settings::default()
    };
    let err = run_minimise(&mut sim, "midpoint", &opts(3, 1), settings, |_| Ok(())).unwrap_err();
    match &err {
        RunError::Minimise {
            step, time, source, ..
        } => {
            assert_eq!(*step, 1);
            assert_eq!(*time, 0.0);
            assert!(matches!(
                source,
                MinimiseError::NotConverged { iterations: 1, .. }
            ));
        }
        other => panic!("expected RunError::Minimise, got {other:?}"),
    }
    let msg = err.to_string();
    assert!(msg.contains("step 1") && msg.contains("t = 0 s"), "{msg}");
    assert_eq!(
        sim.state, before,
        "the state is left at the last good frame"
    );
    assert_eq!(sim.steps, 0);
}

#[test]
fn bad_settings_are_refused() {
    let sc = scene(SMALL);
    for t in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let mut sim = Simulation::new(&sc).unwrap();
        let s = Settings {
            tolerance: t,
            ..Settings::default()
        };
        let err = run_minimise(&mut sim, "midpoint", &opts(1, 1), s, |_| Ok(())).unwrap_err();
        assert!(err.to_string().contains("tolerance"), "{err}");
    }
    // Local/global has no colliders; the discrete gradient neither.
    let mut sim = Simulation::new(&sc).unwrap();
    let err = run_minimise(
        &mut sim,
        "midpoint",
        &opts(1, 1),
        Settings::new(Solver::LocalGlobal),
        |_| Ok(()),
    )
    .unwrap_err();
    assert!(err.to_string().contains("colliders"), "{err}");
    // The minimisation stepper refuses a method that is not a minimisation.
    let err = MinimiseStepper::new(
        &Method::parse("gauss2").unwrap(),
        &sim.model,
        Settings::default(),
    )
    .err()
    .unwrap();
    assert!(err.to_string().contains("gauss2"), "{err}");
    assert_eq!(Solver::parse("bogus"), None);
}

/// The average vector field step, a minimisation, keeps the energy at one
/// step per frame to the solver's tolerance on the released sheet (where
/// Gonzalez's discrete gradient, solved on its residual, fails at step 21).
#[test]
fn average_vector_field_keeps_energy_at_one_step_per_frame() {
    let sc = scene(STRETCHED);
    let mut sim = Simulation::new(&sc).unwrap();
    let run = run_minimise(
        &mut sim,
        AVERAGE_VECTOR_FIELD,
        &opts(60, 1),
        Settings::default(),
        |_| Ok(()),
    )
    .unwrap();
    let e0 = run.frames[0].energy.total();
    let worst = run
        .frames
        .iter()
        .map(|f| ((f.energy.total() - e0) / e0).abs())
        .fold(0.0, f64::max);
    println!(
        "avf at 1/60 s: relative energy error {worst:e}, {:.1} iterations per step",
        minimise_stats(&run).iterations_per_step()
    );
    // Measured 6.2e-9 (11 Newton iterations per step). The energy is exact
    // up to the solves' residual, ‖∇Ψ‖ ≤ 1e-12 of the force scale, which is
    // the stiffness times ‖q‖_∞, far above the tensions of this sheet; the
    // bound leaves room for a machine whose faer kernels round differently.
    assert!(worst < 1e-7, "avf: relative energy error {worst:e}");
    // The midpoint rule at the same step does not keep it.
    let mut sim = Simulation::new(&sc).unwrap();
    let mid = run_minimise(
        &mut sim,
        "midpoint",
        &opts(60, 1),
        Settings::default(),
        |_| Ok(()),
    );
    if let Ok(mid) = mid {
        let moved = mid
            .frames
            .iter()
            .map(|f| ((f.energy.total() - e0) / e0).abs())
            .fold(0.0, f64::max);
        assert!(moved > 1e3 * worst, "midpoint {moved:e} vs avf {worst:e}");
    }
}

/// The AVF refuses colliders and the local/global solver, naming the field.
#[test]
fn average_vector_field_refuses_what_it_cannot_solve() {
    let mut sim = Simulation::new(&scene(SMALL)).unwrap();
    let err = run_minimise(
        &mut sim,
        AVERAGE_VECTOR_FIELD,
        &opts(1, 1),
        Settings::default(),
        |_| Ok(()),
    )
    .unwrap_err();
    assert!(err.to_string().contains("colliders"), "{err}");
    let mut sim = Simulation::new(&scene(STRETCHED)).unwrap();
    let err = run_minimise(
        &mut sim,
        AVERAGE_VECTOR_FIELD,
        &opts(1, 1),
        Settings::new(Solver::LocalGlobal),
        |_| Ok(()),
    )
    .unwrap_err();
    assert!(err.to_string().contains("solver"), "{err}");
}

integrator_core::butcher! {
    /// A user's composition of three midpoint steps (1/4, 1/2, 1/4).
    pub QuarterHalfQuarter {
        claims: [symplectic, symmetric, order = 2],
        a: [[1/8, 0, 0], [1/4, 1/4, 0], [1/4, 1/2, 1/8]],
        b: [1/4, 1/2, 1/4],
    }
}

/// A user's `butcher!` table of midpoint shape, run with
/// [`Simulation::run`] like any scheme, steps as successive minimisations
/// (decided exactly at compile time): its run equals three midpoint
/// minimisations per step bit for bit, and it runs at one step per frame,
/// where the sparse stage solver fails at step 1 or 2 (README).
#[test]
fn a_users_midpoint_shaped_table_takes_the_minimisation_path() {
    let sc = scene(STRETCHED);
    let o = opts(10, 1);
    let mut a = Simulation::new(&sc).unwrap();
    let report = a
        .run_scheme(&QuarterHalfQuarter, &RunSettings::new(o), |_| Ok(()))
        .unwrap();
    assert_eq!(report.steps, 10);
    let mut b = Simulation::new(&sc).unwrap();
    let mut m = Minimiser::new(&b.model, Settings::default()).unwrap();
    let h = o.step_size();
    for _ in 0..10 {
        m.step(&b.model, &[0.25, 0.5, 0.25], h, &mut b.state)
            .unwrap();
    }
    assert_eq!(a.state, b.state);
    assert_eq!(m.stats().solves, 30);
}

/// A scene file naming a scheme of the midpoint family or an
/// energy-conserving one runs it through the minimisation solver
/// (`run_scene` goes through `Simulation::run`): the same bits as a run
/// with the default minimisation settings.
#[test]
fn scene_files_run_the_minimisation_schemes() {
    for method in ["midpoint", "paper-dirk2", AVERAGE_VECTOR_FIELD] {
        let text = STRETCHED.replace(
            "method = \"midpoint\"",
            &format!("method = \"{method}\"\nframes = 5"),
        );
        let text = text.replacen("frames = 1\n", "", 1);
        let sc = scene(&text);
        let (sim, report) = cloth::run_scene(&sc, |_| Ok(())).unwrap();
        assert_eq!(report.steps, 5, "{method}");
        let mut direct = Simulation::new(&sc).unwrap();
        run_minimise(
            &mut direct,
            method,
            &opts(5, 1),
            Settings::default(),
            |_| Ok(()),
        )
        .unwrap();
        assert_eq!(sim.state, direct.state, "{method}");
    }
}
