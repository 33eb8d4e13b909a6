//! Implicit schemes on cloth: the sparse Jacobian of `f(z) = [M⁻¹p; F(q)]`
//! against finite differences, energy behaviour of implicit Euler (decays)
//! and Gauss–Legendre (bounded), steps beyond the explicit stability limit,
//! and the sparse solver's bookkeeping (one symbolic factorisation per run).

use crate::common;
use common::{STAGE_TABLES, run_stage, stage_stats};

use cloth::{Method, RunError, RunOptions, RunSettings, Scene, Simulation};
use integrator_core::OdeSystem;
use integrator_core::implicit::SparseJacobian;
use integrator_core::library::SymplecticEulerA;

/// 5 × 4 particles with all three families, pinned at two corners, gravity,
/// and a sphere collider the cloth starts inside of (so the collider's
/// Jacobian blocks are exercised too).
const SMALL: &str = r#"
gravity = [0.0, -9.81, 0.0]

[cloth]
width = 0.4
height = 0.3
nx = 5
ny = 4
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
center = [0.2, 0.05, 0.15]
radius = 0.12
stiffness = 1.0e3
skin = 0.01

[simulation]
substeps = 1
frames = 1
method = "leapfrog"
"#;

/// 6 × 6 particles, no gravity, no pins, stretched by 10 % and released:
/// the energy is all in the springs at the start.
const STRETCHED: &str = r#"
[cloth]
width = 0.5
height = 0.5
nx = 6
ny = 6
prestretch = 1.1

[material]
density = 0.1
stretch = 40.0
shear = 10.0
bend = 0.5

[simulation]
substeps = 1
frames = 1
method = "leapfrog"
"#;

/// A horizontal sheet pinned along one edge, falling under gravity (the
/// paper's experiment, coarser).
const HANGING: &str = r#"
gravity = [0.0, -9.81, 0.0]

[cloth]
width = 0.5
height = 0.5
nx = 8
ny = 8
plane = "horizontal"

[material]
density = 0.05
stretch = 50.0
shear = 50.0

[pins]
edges = ["top"]

[simulation]
substeps = 1
frames = 1
method = "leapfrog"
"#;

fn perturbed(text: &str, file: &str) -> (Simulation, Vec<f64>) {
    let scene = Scene::from_toml(text, file).unwrap();
    let sim = Simulation::new(&scene).unwrap();
    let mut z = sim.state.clone();
    let n = z.len() / 2;
    let m = sim.model.particle_mass();
    let mut s: u64 = 12345;
    let mut r = move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    };
    for x in &mut z[..n] {
        *x += 0.01 * r();
    }
    for p in &mut z[n..] {
        *p = m * 0.3 * r();
    }
    (sim, z)
}

#[test]
fn sparse_jacobian_matches_finite_differences_of_f() {
    let (sim, z) = perturbed(SMALL, "small.toml");
    let model = &sim.model;
    let d = model.dim();
    assert_eq!(d, z.len());
    let pattern = model.jacobian_pattern();
    let mut values = vec![f64::NAN; pattern.len()];
    model.jacobian_values(0.0, &z, &mut values);
    // Assemble densely (repeated positions are summed).
    let mut jac = vec![0.0; d * d];
    for (&(r, c), v) in pattern.iter().zip(&values) {
        assert!(r < d && c < d);
        jac[r * d + c] += v;
    }
    // Central differences of f, column by column.
    let mut zp = z.clone();
    let (mut fp, mut fm) = (vec![0.0; d], vec![0.0; d]);
    let mut worst: f64 = 0.0;
    let scale = jac.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    for c in 0..d {
        let eps = 1e-6 * z[c].abs().max(1e-3);
        zp[c] = z[c] + eps;
        model.rhs(0.0, &zp, &mut fp);
        zp[c] = z[c] - eps;
        model.rhs(0.0, &zp, &mut fm);
        zp[c] = z[c];
        for r in 0..d {
            let fd = (fp[r] - fm[r]) / (2.0 * eps);
            worst = worst.max((fd - jac[r * d + c]).abs());
        }
    }
    assert!(
        worst <= 1e-6 * scale,
        "worst difference {worst:e} against entries up to {scale:e}"
    );
    // Some particles are inside the sphere, so the test saw collider terms.
    let e = model.energy(&z);
    assert!(e.colliders > 0.0, "{e:?}");
}

#[test]
fn jacobian_has_the_mass_block_and_the_force_block() {
    let (sim, z) = perturbed(HANGING, "hanging.toml");
    let model = &sim.model;
    let n = 3 * model.free_count();
    let pattern = model.jacobian_pattern();
    assert_eq!(pattern.len(), n + model.force_jacobian_nnz());
    let mut values = vec![0.0; pattern.len()];
    model.jacobian_values(0.0, &z, &mut values);
    for (k, &(r, c)) in pattern.iter().enumerate() {
        if r < n {
            assert_eq!(c, r + n);
            assert_eq!(values[k], 1.0 / model.particle_mass());
        } else {
            assert!(c < n, "∂p'/∂p is zero");
        }
    }
}

fn relative_energy_errors(frames: &[cloth::FrameStats], scale: f64) -> Vec<f64> {
    let e0 = frames[0].energy.total();
    frames
        .iter()
        .map(|f| (f.energy.total() - e0) / scale)
        .collect()
}

#[test]
fn implicit_euler_dissipates_while_gauss2_keeps_the_energy() {
    let scene = Scene::from_toml(STRETCHED, "stretched.toml").unwrap();
    let h_max = Simulation::new(&scene).unwrap().model.stability().h_max;
    // Twice the explicit limit, 300 steps in frames of 10.
    let h = 2.0 * h_max;
    let opts = RunOptions {
        frames: 30,
        substeps: 10,
        frame_rate: 1.0 / (10.0 * h),
    };
    let mut sim = Simulation::new(&scene).unwrap();
    let e0 = sim.stats().energy.total();
    assert!(e0 > 0.0);
    let euler = run_stage(&mut sim, "implicit-euler", &opts, None, |_| Ok(())).unwrap();
    let euler_err = relative_energy_errors(&euler.frames, e0);
    // Energy goes down, never up (up to round-off), and ends well below.
    for w in euler.frames.windows(2) {
        assert!(w[1].energy.total() <= w[0].energy.total() + 1e-12 * e0);
    }
    assert!(
        *euler_err.last().unwrap() < -0.3,
        "implicit Euler kept {euler_err:?}"
    );

    let mut sim = Simulation::new(&scene).unwrap();
    let gauss = run_stage(&mut sim, "gauss2", &opts, None, |_| Ok(())).unwrap();
    let gauss_err = relative_energy_errors(&gauss.frames, e0);
    let worst = gauss_err.iter().fold(0.0f64, |a, e| a.max(e.abs()));
    assert!(worst < 1e-2, "gauss2: max relative energy error {worst:e}");
    // The midpoint rule (order 2), symplectic as well, stays bounded too,
    // with a larger error at this step.
    let mut sim = Simulation::new(&scene).unwrap();
    let mid = run_stage(&mut sim, "midpoint", &opts, None, |_| Ok(())).unwrap();
    let worst = relative_energy_errors(&mid.frames, e0)
        .iter()
        .fold(0.0f64, |a, e| a.max(e.abs()));
    assert!(
        worst < 0.25,
        "midpoint: max relative energy error {worst:e}"
    );
}

#[test]
fn gauss2_is_stable_far_above_the_explicit_limit() {
    let scene = Scene::from_toml(HANGING, "hanging.toml").unwrap();
    let stab = Simulation::new(&scene).unwrap().model.stability();
    let h = 10.0 * stab.h_max;
    let opts = RunOptions {
        frames: 20,
        substeps: 10,
        frame_rate: 1.0 / (10.0 * h),
    };
    // Symplectic Euler at this step blows up …
    let mut sim = Simulation::new(&scene).unwrap();
    let err = sim
        .run_scheme(&SymplecticEulerA, &RunSettings::new(opts), |_| Ok(()))
        .unwrap_err();
    assert!(matches!(err, RunError::Diverged { .. }), "{err}");
    // … Gauss–Legendre does not, and keeps its energy within a few per cent
    // of the energy the fall releases (m·g times the sheet's size).
    let mut sim = Simulation::new(&scene).unwrap();
    let run = run_stage(&mut sim, "gauss2", &opts, None, |_| Ok(())).unwrap();
    assert_eq!(run.steps, 200);
    let m_total = sim.model.particle_mass() * sim.model.free_count() as f64;
    let scale = m_total * 9.81 * 0.5;
    let worst = relative_energy_errors(&run.frames, scale)
        .iter()
        .fold(0.0f64, |a, e| a.max(e.abs()));
    assert!(
        worst < 0.05,
        "gauss2 at 10·h_max: relative energy error {worst:e}"
    );
    // The sheet did fall.
    let last = run.frames.last().unwrap();
    assert!(last.energy.kinetic > 0.01 * scale);
    assert!(last.max_strain < 0.5, "strain {}", last.max_strain);
    // One symbolic factorisation for the run, numeric ones only when the
    // Newton iteration asked for a fresh Jacobian (slow contraction, within a
    // step or across steps): far fewer than iterations.
    let s = stage_stats(&run);
    assert_eq!(s.symbolic_factorizations, 1, "{s:?}");
    assert!(
        s.factorizations >= 1 && 4 * s.factorizations < s.newton_iterations,
        "{s:?}"
    );
    assert!(s.newton_iterations >= s.steps, "{s:?}");
    assert_eq!(s.steps, 200);
    assert_eq!(s.failures, 0);
}

#[test]
fn every_implicit_method_steps_cloth_and_names_resolve() {
    let scene = Scene::from_toml(HANGING, "hanging.toml").unwrap();
    let opts = RunOptions {
        frames: 2,
        substeps: 2,
        frame_rate: 100.0,
    };
    for id in STAGE_TABLES {
        let mut sim = Simulation::new(&scene).unwrap();
        let report = run_stage(&mut sim, id, &opts, None, |_| Ok(())).unwrap();
        assert_eq!(report.steps, 4, "{id}");
        assert_eq!(report.method, Method::parse(id).unwrap().name());
        let stats = stage_stats(&report);
        assert_eq!(stats.symbolic_factorizations, 1, "{id}: {stats:?}");
        assert!(sim.state.iter().all(|x| x.is_finite()));
    }
    // Explicit names go through the explicit runner.
    let mut sim = Simulation::new(&scene).unwrap();
    let report = run_stage(&mut sim, "leapfrog", &opts, None, |_| Ok(())).unwrap();
    assert_eq!(report.steps, 4);
    assert_eq!(report.solver, cloth::SolverStats::None);
    // Every method name is known exactly once.
    let all = Method::ids(|_| true);
    let mut sorted = all.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), all.len());
    // Names that are not tables the stage solver steps are refused, not
    // panicked on. (Until every implicit table stepped cloth, lobatto3a-2
    // was the library table refused here; now the energy scheme avf, which
    // has no table, is.)
    let mut sim = Simulation::new(&scene).unwrap();
    for bad in ["avf", "gauss9"] {
        let err = run_stage(&mut sim, bad, &opts, None, |_| Ok(())).unwrap_err();
        assert!(err.to_string().contains(bad), "{err}");
    }
}

/// The runner hands the solver the state moved by a constant and a small
/// drift (see `cloth::step::stage`); Runge–Kutta steps commute with that, so
/// from a state where every component is well away from zero (where the
/// solver converges on the model as it is) both give the same steps.
#[test]
fn the_shifted_run_takes_the_same_steps_as_the_model_itself() {
    use integrator_core::implicit::{SparseWorkspace, step_sparse};
    use integrator_core::library::GaussLegendre2;
    let (mut sim, z) = perturbed(STRETCHED, "stretched.toml");
    let h = 2.0 * sim.model.stability().h_max;
    let steps = 6;
    let mut direct = z.clone();
    let mut ws =
        SparseWorkspace::new(z.len(), 2).with_settings(cloth::step::stage::cloth_settings());
    for k in 0..steps {
        step_sparse(
            &GaussLegendre2::TABLE,
            &sim.model,
            k as f64 * h,
            h,
            &mut direct,
            &mut ws,
        )
        .unwrap();
    }
    sim.state.copy_from_slice(&z);
    let opts = RunOptions {
        frames: 1,
        substeps: steps,
        frame_rate: 1.0 / (steps as f64 * h),
    };
    run_stage(&mut sim, "gauss2", &opts, None, |_| Ok(())).unwrap();
    let n = z.len() / 2;
    let scale_q = z[..n].iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let scale_p = direct[n..].iter().fold(0.0f64, |a, x| a.max(x.abs()));
    for (k, (a, b)) in sim.state.iter().zip(&direct).enumerate() {
        let scale = if k < n { scale_q } else { scale_p };
        assert!((a - b).abs() <= 1e-10 * scale, "component {k}: {a} vs {b}");
    }
}
