//! RATTLE on the inextensible cloth (`material.stretch = "inextensible"`):
//! the constraints hold to round-off after every step and the velocity is
//! tangent to them; momentum is conserved without gravity and pins; the
//! energy error is bounded and of order 2; bad input and failed solves are
//! errors naming the field, or the step and time.

use cloth::{
    CONSTRAINT_TOLERANCE, Method, RattleSettings, RunError, RunOptions, RunSettings, Scene,
    Simulation, SolverStats,
};
use nalgebra::Vector3;

/// A small inextensible sheet hanging from its top edge, released 45° from
/// hanging (gravity tilted out of its plane), with soft shear springs and
/// no bending (`bending = 0`): these tests measure RATTLE itself, some of
/// them against the figures of the sheet without bending (its columns
/// swing alike, so its shear springs keep their length to round-off;
/// with bending the columns next to the free side edges, which carry no
/// bending term of their own, swing differently and shear the cells by
/// 0.3 % in 1 s at 10², `bending::` and `auto_step::` test the sheet with
/// bending). They step RATTLE at a fixed step (`step = "fixed"`; the
/// variable step, the default of an inextensible scene, has its tests in
/// `variable_step::`).
fn hanging(n: usize, substeps: usize, frames: usize) -> Scene {
    Scene::from_toml(
        &format!(
            r#"
            gravity = [0.0, -6.9367, 6.9367]
            [cloth]
            width = 1.0
            height = 1.0
            nx = {n}
            ny = {n}
            plane = "vertical"
            [material]
            density = 0.01378
            stretch = "inextensible"
            shear = 0.002
            bending = 0.0
            [pins]
            edges = ["top"]
            [simulation]
            substeps = {substeps}
            step = "fixed"
            frames = {frames}
            method = "rattle"
        "#
        ),
        "hanging.toml",
    )
    .unwrap()
}

fn rattle() -> Method {
    Method::parse("rattle").unwrap()
}

#[test]
fn rattle_is_a_method_with_its_facts() {
    let m = rattle();
    assert_eq!(m.kind(), "implicit");
    assert_eq!(m.order(), 2);
    assert!(m.symplectic() && m.symmetric());
    assert_eq!(m.mechanism(), cloth::Mechanism::Constrained);
    assert!(Method::listing().contains("rattle"));
}

#[test]
fn constraints_hold_to_round_off_after_every_step_and_the_velocity_is_tangent() {
    // One step per frame: the callback sees every step.
    let scene = hanging(10, 1, 240);
    let mut sim = Simulation::new(&scene).unwrap();
    assert!(sim.model.is_inextensible());
    assert_eq!(sim.model.constraint_count(), 9 * 10 + 10 * 9 - 9);
    let n = 3 * sim.model.free_count();
    let (mut worst_g, mut worst_v, mut moved) = (0.0f64, 0.0f64, 0.0f64);
    let opts = RunOptions {
        frames: 240,
        substeps: 1,
        frame_rate: 240.0,
    };
    let start = sim.state.clone();
    let report = sim
        .run(&rattle(), &RunSettings::new(opts), |f| {
            worst_g = worst_g.max(f.model.constraint_residual(f.q()).unwrap());
            worst_v = worst_v.max(f.model.constraint_velocity_residual(f.state).unwrap());
            let dq = f.q().iter().zip(&start[..n]).map(|(a, b)| (a - b).abs());
            moved = moved.max(dq.fold(0.0, f64::max));
            Ok(())
        })
        .unwrap();
    assert_eq!(report.steps, 240);
    // The sheet swings (tens of centimetres), its edges keep their lengths
    // to the round-off tolerance, and its velocity is tangent to round-off.
    assert!(moved > 0.2, "moved {moved}");
    assert!(worst_g <= CONSTRAINT_TOLERANCE, "residual {worst_g:e}");
    assert!(worst_v <= 1e-13, "G·v residual {worst_v:e}");
    let SolverStats::Constrained(stats) = report.solver else {
        panic!("{:?}", report.solver)
    };
    assert!(stats.max_residual <= CONSTRAINT_TOLERANCE);
    // By default a Cholesky every third step (the velocity projections in
    // between by preconditioned conjugate gradients, checked above by the
    // tangent velocity after every step).
    assert!(stats.factorizations <= 241 / 3 + 2, "{stats:?}");
    assert!(stats.pcg_iterations > 0, "{stats:?}");
    assert!(stats.iterations_per_step() < 10.0, "{stats:?}");
    // The edges keep their length, measured directly too.
    let strain = report
        .frames
        .iter()
        .map(|f| f.max_strain)
        .fold(0.0, f64::max);
    assert!(strain < 1e-12, "max strain {strain:e}");
}

#[test]
fn factorising_every_step_reuses_the_projection_factor_for_the_position_solve() {
    let mut scene = hanging(10, 1, 60);
    scene.simulation.frame_rate = 240.0;
    let mut sim = Simulation::new(&scene).unwrap();
    let every = RunSettings::from_scene(&scene).with_rattle(RattleSettings {
        refactor_every: 1,
        ..RattleSettings::default()
    });
    let n = 3 * sim.model.free_count();
    let mut worst_v = 0.0f64;
    let report = sim
        .run(&rattle(), &every, |f| {
            worst_v = worst_v.max(f.model.constraint_velocity_residual(f.state).unwrap());
            assert!(f.model.constraint_residual(&f.state[..n]).unwrap() <= CONSTRAINT_TOLERANCE);
            Ok(())
        })
        .unwrap();
    let SolverStats::Constrained(stats) = report.solver else {
        panic!("{:?}", report.solver)
    };
    // One Cholesky per step and one at the start, no conjugate gradients.
    assert_eq!(stats.factorizations, 61);
    assert_eq!(stats.pcg_iterations, 0);
    assert!(worst_v <= 1e-13, "G·v residual {worst_v:e}");
}

/// Over pairs `(x, y)` of states `[q; p]`: the largest position and
/// momentum differences, the largest momentum of `x`, and how far `x`'s
/// positions moved from `start`'s.
fn apart<'a>(
    pairs: impl Iterator<Item = (&'a [f64], &'a [f64])>,
    start: &[f64],
) -> (f64, f64, f64, f64) {
    let n = start.len() / 2;
    let (mut dq, mut dp, mut pmax, mut moved) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (x, y) in pairs {
        for i in 0..n {
            dq = dq.max((x[i] - y[i]).abs());
            dp = dp.max((x[n + i] - y[n + i]).abs());
            pmax = pmax.max(x[n + i].abs());
            moved = moved.max((x[i] - start[i]).abs());
        }
    }
    (dq, dp, pmax, moved)
}

/// The states at every frame of the 12 × 12 sheet at `h = 1/480 s`, with
/// `substeps` steps per frame, and the run's solver statistics.
fn states(substeps: usize, steps: usize) -> (Vec<Vec<f64>>, cloth::step::rattle::Stats) {
    let mut scene = hanging(12, substeps, steps / substeps);
    scene.simulation.frame_rate = 480.0 / substeps as f64;
    frames_and_stats(&scene, RattleSettings::default())
}

#[test]
fn projecting_only_at_frames_gives_rattles_positions_and_momenta() {
    // One step per frame projects the momentum after every step (RATTLE
    // as written); eight per frame carry the unprojected momentum between
    // frames (SHAKE's form) and project at the frames only. The positions
    // do not depend on the projection and the frames' momenta are its
    // result, so the two agree at every eighth step to round-off (the
    // sheet moves by about 0.3 m over the 0.5 s).
    let (every, every_stats) = states(1, 240);
    let (frames, frame_stats) = states(8, 240);
    assert_eq!(frames.len(), 31);
    let (dq, dp, pmax, moved) = apart(
        frames
            .iter()
            .enumerate()
            .map(|(k, f)| (every[8 * k].as_slice(), f.as_slice())),
        &every[0],
    );
    assert!(moved > 0.1, "moved {moved}");
    assert!(dq < 1e-12, "positions differ by {dq:e} m");
    assert!(
        dp < 1e-10 * pmax,
        "momenta differ by {dp:e} (largest {pmax:e})"
    );
    // Skipping seven projections in eight skips their solves; the tension
    // measured from the multipliers that carry them stays the same.
    assert!(
        4 * frame_stats.pcg_iterations < every_stats.pcg_iterations,
        "{} conjugate-gradient iterations at the frames only, {} at every step",
        frame_stats.pcg_iterations,
        every_stats.pcg_iterations
    );
    let (a, b) = (every_stats.max_wave_number, frame_stats.max_wave_number);
    assert!((a - b).abs() < 0.05 * a, "h·ω {a} against {b}");
}

#[test]
fn a_released_sheet_conserves_linear_and_angular_momentum() {
    // No gravity, no pins: spin the sheet in its plane, drift it, and let a
    // transverse wave run over it (tangent to the constraints: flat sheet,
    // velocity along its normal).
    let mut scene = hanging(9, 4, 30);
    scene.gravity = [0.0; 3];
    scene.pins.clear();
    let mut sim = Simulation::new(&scene).unwrap();
    let n = 3 * sim.model.free_count();
    let m = sim.model.particle_mass();
    let omega = Vector3::new(0.0, 0.0, 2.0);
    let centre = Vector3::new(0.5, -0.5, 0.0);
    for k in 0..sim.model.free_count() {
        let x = Vector3::new(sim.state[3 * k], sim.state[3 * k + 1], sim.state[3 * k + 2]);
        let wave = (std::f64::consts::PI * x.x).sin() * (std::f64::consts::PI * x.y).cos();
        let v = omega.cross(&(x - centre)) + Vector3::new(0.1, 0.05, 0.8 * wave);
        for a in 0..3 {
            sim.state[n + 3 * k + a] = m * v[a];
        }
    }
    let totals = |z: &[f64]| {
        let (q, p) = z.split_at(n);
        let (mut lin, mut ang, mut scale_p, mut scale_l) =
            (Vector3::zeros(), Vector3::zeros(), 0.0, 0.0);
        for k in 0..n / 3 {
            let x = Vector3::new(q[3 * k], q[3 * k + 1], q[3 * k + 2]);
            let pk = Vector3::new(p[3 * k], p[3 * k + 1], p[3 * k + 2]);
            lin += pk;
            ang += x.cross(&pk);
            scale_p += pk.norm();
            scale_l += x.norm() * pk.norm();
        }
        (lin, ang, scale_p, scale_l)
    };
    let (p0, l0, sp, sl) = totals(&sim.state);
    let (mut dp, mut dl, mut bent) = (0.0f64, 0.0f64, 0.0f64);
    sim.run(&rattle(), &RunSettings::from_scene(&scene), |f| {
        let (p, l, _, _) = totals(f.state);
        dp = dp.max((p - p0).norm() / sp);
        dl = dl.max((l - l0).norm() / sl);
        bent = bent.max(f.stats.energy.springs);
        Ok(())
    })
    .unwrap();
    // The wave bends the sheet (the shear springs take energy) …
    assert!(bent > 0.0);
    // … and the constraint forces are central pairs, as are the springs':
    // both totals stay to round-off.
    assert!(dp <= 1e-14, "linear momentum drifted by {dp:e}");
    assert!(dl <= 1e-13, "angular momentum drifted by {dl:e}");
}

#[test]
fn the_energy_error_is_bounded_and_of_order_two() {
    let worst = |substeps: usize| {
        let scene = hanging(8, substeps, 300);
        let mut sim = Simulation::new(&scene).unwrap();
        let report = sim
            .run(&rattle(), &RunSettings::from_scene(&scene), |_| Ok(()))
            .unwrap();
        let e0 = report.frames[0].energy.total();
        let errs: Vec<f64> = report
            .frames
            .iter()
            .map(|f| (f.energy.total() - e0).abs())
            .collect();
        let third = errs.len() / 3;
        let first = errs[..third].iter().cloned().fold(0.0, f64::max);
        let last = errs[2 * third..].iter().cloned().fold(0.0, f64::max);
        (errs.iter().cloned().fold(0.0, f64::max), first, last)
    };
    // Energy scale: the sheet's weight times its size, 0.135 J.
    let (coarse, first, last) = worst(2);
    assert!(coarse < 1e-4, "max |H − H₀| = {coarse:e} J");
    // Bounded: the last third of five seconds shows no more error than
    // the first third, within a factor (no drift, no growth).
    assert!(last < 3.0 * first, "first {first:e}, last {last:e}");
    let (fine, _, _) = worst(4);
    let ratio = coarse / fine;
    assert!(
        (3.0..5.5).contains(&ratio),
        "h → h/2 divides the error by {ratio}"
    );
}

fn scene_error(toml: &str) -> String {
    Scene::from_toml(toml, "bad.toml")
        .and_then(|s| Simulation::new(&s).map(|_| ()))
        .unwrap_err()
        .to_string()
}

const BASE: &str = r#"
    gravity = [0.0, -9.81, 0.0]
    [cloth]
    width = WIDTH
    height = 1.0
    nx = 6
    ny = 6
    prestretch = PRESTRETCH
    [material]
    density = 0.1
    stretch = "inextensible"
    [pins]
    PINS
    [simulation]
    substeps = 4
    frames = 3
    method = "rattle"
"#;

fn base(width: &str, prestretch: &str, pins: &str) -> String {
    BASE.replace("WIDTH", width)
        .replace("PRESTRETCH", prestretch)
        .replace("PINS", pins)
}

#[test]
fn bad_scenes_name_the_field() {
    let ok = base("1.0", "1.0", r#"edges = ["top"]"#);
    assert!(Simulation::new(&Scene::from_toml(&ok, "ok.toml").unwrap()).is_ok());
    // A degenerate edge: L² is not a normal number.
    let e = scene_error(&base("1e-200", "1.0", r#"edges = ["top"]"#));
    assert!(e.contains("cloth.width"), "{e}");
    // Two pins of one edge pulled apart beyond its length by the
    // prestretch: the prestretch is the field to change (issue 35: it was
    // blamed on the pins alone), and the message says both.
    let e = scene_error(&base("1.0", "1.1", r#"edges = ["top"]"#));
    assert!(
        e.starts_with("bad: cloth.prestretch")
            && e.contains("both pinned")
            && e.contains("cannot hold")
            && e.contains("unpin"),
        "{e}"
    );
    // Without pins, a prestretched start is off the constraints.
    let e = scene_error(&base("1.0", "1.1", ""));
    assert!(e.contains("cloth.prestretch"), "{e}");
    // A straight line of edges taut between two pins: dependent
    // constraints, infinite tension.
    let e = scene_error(&base(
        "1.0",
        "1.0",
        r#"corners = ["top-left", "top-right"]"#,
    ));
    assert!(e.contains("pins") && e.contains("dependent"), "{e}");
    // Not a stiffness nor "inextensible".
    let e = scene_error(&ok.replace(r#""inextensible""#, r#""rubber""#));
    assert!(
        e.contains("material.stretch") && e.contains("rubber"),
        "{e}"
    );
    // The wrong method for the model, either way.
    let e = scene_error(&ok.replace(r#"method = "rattle""#, r#"method = "stormer-verlet""#));
    assert!(
        e.contains("simulation.method") && e.contains("rattle"),
        "{e}"
    );
    let springs = ok.replace(r#""inextensible""#, "100.0");
    let e = scene_error(&springs);
    assert!(e.contains("simulation.method"), "{e}");
}

#[test]
fn runs_refuse_the_wrong_method_and_a_collider_too_stiff_for_the_step() {
    let ok = base("1.0", "1.0", r#"edges = ["top"]"#);
    let scene = Scene::from_toml(&ok, "ok.toml").unwrap();
    let mut sim = Simulation::new(&scene).unwrap();
    let settings = RunSettings::from_scene(&scene);
    let e = sim
        .run(&Method::parse("leapfrog").unwrap(), &settings, |_| Ok(()))
        .unwrap_err();
    assert!(e.to_string().contains("rattle"), "{e}");
    let stiff = format!(
        "{ok}\n[[colliders]]\ntype = \"sphere\"\ncenter = [0.5, -2.0, 0.0]\nradius = 0.5\nstiffness = 1e9\n"
    );
    let scene = Scene::from_toml(&stiff, "stiff.toml").unwrap();
    let mut sim = Simulation::new(&scene).unwrap();
    let e = sim.run(&rattle(), &settings, |_| Ok(())).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("colliders[0].stiffness") && msg.contains("1/h²"),
        "{msg}"
    );
    // A soft one is stepped.
    let soft = stiff.replace("1e9", "1e3");
    let scene = Scene::from_toml(&soft, "soft.toml").unwrap();
    let mut sim = Simulation::new(&scene).unwrap();
    sim.run(&rattle(), &settings, |_| Ok(())).unwrap();
}

#[test]
fn a_solve_that_cannot_converge_is_an_error_naming_the_step_and_time() {
    // The whole sheet released flat: by half a second its free edge moves
    // at metres per second, and at two steps per frame the position solve
    // has no solution near its start (the edges turn too far in a step).
    let mut scene = hanging(25, 2, 60);
    scene.cloth.plane = cloth::Plane::Horizontal;
    scene.gravity = [0.0, -9.81, 0.0];
    let mut sim = Simulation::new(&scene).unwrap();
    let err = sim
        .run(&rattle(), &RunSettings::from_scene(&scene), |_| Ok(()))
        .unwrap_err();
    let msg = err.to_string();
    match &err {
        RunError::Constraint { step, time, .. } => {
            assert!(
                msg.contains(&format!("step {step} (t = {time} s)")),
                "{msg}"
            );
            assert!(*step > 1);
        }
        other => panic!("expected a constraint failure, got {other}"),
    }
    assert!(err.is_blowup());
    assert!(msg.contains("rattle") || msg.contains("RATTLE"), "{msg}");
    // The simulation is left at the last good frame, on the constraints.
    let n = 3 * sim.model.free_count();
    assert!(sim.model.constraint_residual(&sim.state[..n]).unwrap() <= CONSTRAINT_TOLERANCE);
    // A cap of one iteration on a moving sheet fails at once.
    let scene = hanging(8, 1, 10);
    let mut sim = Simulation::new(&scene).unwrap();
    let capped = RunSettings::from_scene(&scene).with_rattle(RattleSettings {
        max_iterations: 1,
        ..RattleSettings::default()
    });
    let err = sim.run(&rattle(), &capped, |_| Ok(())).unwrap_err();
    assert!(
        err.to_string().contains("did not converge in 1 iterations"),
        "{err}"
    );
}

#[test]
fn the_parallel_loops_agree_to_round_off() {
    // Large enough for the per-edge loops to be split (more than 2048 edges).
    let scene = hanging(40, 6, 2);
    let run = |parallel: bool| {
        let mut sim = Simulation::new(&scene).unwrap();
        let settings = RunSettings::from_scene(&scene).with_rattle(RattleSettings {
            parallel,
            ..RattleSettings::default()
        });
        sim.run(&rattle(), &settings, |_| Ok(())).unwrap();
        sim.state
    };
    let (a, b) = (run(false), run(true));
    let same = a
        .iter()
        .zip(&b)
        .filter(|(x, y)| x.to_bits() == y.to_bits())
        .count();
    // The per-edge loops write each entry from one task; the factorisation
    // on two threads may sum in another order, so allow round-off there.
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(worst <= 1e-12, "{worst:e} ({same} of {} equal)", a.len());
}

/// The run of `scene` with `settings`: its frames' states and solver
/// statistics.
fn frames_and_stats(
    scene: &Scene,
    settings: RattleSettings,
) -> (Vec<Vec<f64>>, cloth::step::rattle::Stats) {
    let mut sim = Simulation::new(scene).unwrap();
    let run = RunSettings::from_scene(scene).with_rattle(settings);
    let mut out = Vec::new();
    let report = sim
        .run(&rattle(), &run, |f| {
            out.push(f.state.to_vec());
            Ok(())
        })
        .unwrap();
    let SolverStats::Constrained(stats) = report.solver else {
        panic!("{:?}", report.solver)
    };
    (out, stats)
}

#[test]
fn anderson_mixing_takes_the_same_steps_to_round_off_in_fewer_iterations() {
    // Released 45°, the 16² sheet swings by tens of centimetres in a
    // second; the plain simplified Newton iteration and the one mixed with
    // its last 4 corrections both stop at the constraints' round-off, so
    // they reach the same states to round-off, the mixed one in fewer
    // iterations.
    let scene = hanging(16, 4, 60);
    let plain = RattleSettings {
        anderson: 0,
        ..RattleSettings::default()
    };
    assert_eq!(RattleSettings::default().anderson, 4);
    let (a, sa) = frames_and_stats(&scene, plain);
    let (b, sb) = frames_and_stats(&scene, RattleSettings::default());
    assert_eq!(a.len(), b.len());
    let (dq, dp, pmax, moved) = apart(
        a.iter().zip(&b).map(|(x, y)| (x.as_slice(), y.as_slice())),
        &a[0],
    );
    assert!(moved > 0.1, "moved {moved}");
    assert!(dq < 1e-12, "positions differ by {dq:e} m");
    assert!(
        dp < 1e-10 * pmax,
        "momenta differ by {dp:e} (largest {pmax:e})"
    );
    assert!(sa.max_residual <= CONSTRAINT_TOLERANCE && sb.max_residual <= CONSTRAINT_TOLERANCE);
    assert!(
        sb.iterations < sa.iterations,
        "{} iterations mixed, {} plain",
        sb.iterations,
        sa.iterations
    );
}

#[test]
fn a_factor_that_stops_contracting_is_renewed_before_the_true_jacobian_is() {
    // Never refactorised on a schedule (refactor_every = 0), the factor of
    // the start grows old as the sheet swings: the position solves renew
    // it at their step's q (a Cholesky) when it stops contracting, and
    // need the LU of the true Jacobian only where even that does not
    // contract, which on this sheet is never.
    let scene = hanging(16, 4, 60);
    let settings = RattleSettings {
        refactor_every: 0,
        ..RattleSettings::default()
    };
    let (frames, stats) = frames_and_stats(&scene, settings);
    assert_eq!(frames.len(), 61);
    // One at the start, the rest renewals (and projections that fell back).
    assert!(stats.factorizations > 1 + stats.pcg_failures, "{stats:?}");
    assert_eq!(stats.lu_factorizations, 0, "{stats:?}");
    assert!(stats.max_residual <= CONSTRAINT_TOLERANCE, "{stats:?}");
}

#[test]
fn the_wave_number_of_a_sheet_hanging_at_rest_is_its_static_tension() {
    // Gravity in the sheet's plane: it hangs at rest, and every vertical
    // edge carries the weight of the particles below it. The particle in
    // row 1 of an n-row sheet hangs by an edge holding n − 1 particles and
    // holds one holding n − 2, so the largest wave number is
    // h·ω = 4·√(½(Λ_up + Λ_down)) with Λ = T·h²/(4·m·L) and T = k·m·|g|:
    // h·ω = 2·h·√((n − 3/2)·|g|/L), which is 2·h/(the model's tension-wave
    // step) up to √((n − 3/2)/(n − 1)).
    let n = 12;
    let mut scene = hanging(n, 1, 20);
    scene.gravity = [0.0, -9.81, 0.0];
    scene.simulation.frame_rate = 240.0;
    let mut sim = Simulation::new(&scene).unwrap();
    let h = 1.0 / 240.0;
    let report = sim
        .run(&rattle(), &RunSettings::from_scene(&scene), |_| Ok(()))
        .unwrap();
    let SolverStats::Constrained(stats) = report.solver else {
        panic!("{:?}", report.solver)
    };
    let l = 1.0 / (n - 1) as f64;
    let expected = 2.0 * h * ((n as f64 - 1.5) * 9.81 / l).sqrt();
    let rel = (stats.max_wave_number - expected).abs() / expected;
    assert!(
        rel < 1e-6,
        "wave number {} against the static {expected}",
        stats.max_wave_number
    );
    let estimate = 2.0 * h / sim.model.tension_wave_step().unwrap();
    let ratio = expected / estimate;
    assert!((ratio - ((n as f64 - 1.5) / (n as f64 - 1.0)).sqrt()).abs() < 1e-12);
    // The summary's figure is below RATTLE's limit of 2 at this step.
    assert!(stats.max_wave_number < 2.0);
}
