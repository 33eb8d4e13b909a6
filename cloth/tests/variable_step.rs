//! RATTLE's reversible variable step (`simulation.step = "variable"`,
//! `cloth::step::variable`): frames land on `k/frame_rate`; at a tension
//! peak the steps per frame rise and the run goes on where the fixed step
//! at the floor fails; forwards, momenta flipped, and back returns to the
//! start to round-off; a checkpoint resumes to the same bits; while the
//! floor is accepted the run is the fixed step's to the bit; the scene's
//! fields are checked, naming them.

use cloth::checkpoint::{Action, RunControl, RunState};
use cloth::{
    CallbackError, FrameStats, Method, RunError, RunReport, RunSettings, Scene, Simulation,
    SolverStats, VariableStep,
};

/// A small inextensible sheet with the paper's cloth, pinned along its top
/// edge and released flat (`plane = "horizontal"`), with bending: it falls
/// and whips through the vertical at t ≈ 1.4 s. At 12² with 2 steps per
/// frame the fixed step fails there (frame 86); the variable step with
/// that floor takes 3 or 5 steps in 4 of its first 100 frames (28, 85, 88,
/// 96).
fn flat(n: usize, substeps: usize, frames: usize, step: &str) -> Scene {
    Scene::from_toml(
        &format!(
            r#"
            gravity = [0.0, -9.81, 0.0]
            [cloth]
            width = 1.0
            height = 1.0
            nx = {n}
            ny = {n}
            plane = "horizontal"
            [material]
            density = 0.01378
            stretch = "inextensible"
            shear = 0.002
            bending = 3.0e-6
            [pins]
            edges = ["top"]
            [simulation]
            substeps = {substeps}
            frames = {frames}
            step = "{step}"
            method = "rattle"
        "#
        ),
        "flat.toml",
    )
    .unwrap()
}

fn rattle() -> Method {
    Method::parse("rattle").unwrap()
}

fn run(scene: &Scene) -> (Simulation, Result<RunReport, RunError>) {
    let mut sim = Simulation::new(scene).unwrap();
    let result = sim.run(&rattle(), &RunSettings::from_scene(scene), |_| Ok(()));
    (sim, result)
}

#[test]
fn the_step_is_variable_by_default_on_an_inextensible_scene_and_fixed_when_asked() {
    let mut text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/paper64-inextensible.toml"
    ))
    .unwrap();
    let scene = Scene::from_toml(&text, "p.toml").unwrap();
    assert_eq!(scene.simulation.variable, Some(VariableStep::default()));
    // The scene writes its step out; without the line it is the default.
    let line = "step = \"variable\"";
    assert!(text.contains(line));
    let without = text.replace(line, "");
    let scene = Scene::from_toml(&without, "p.toml").unwrap();
    assert_eq!(scene.simulation.variable, Some(VariableStep::default()));
    text = text.replace(line, "step = \"fixed\"");
    let scene = Scene::from_toml(&text, "p.toml").unwrap();
    assert_eq!(scene.simulation.variable, None);
    let settings = RunSettings::from_scene(&flat(4, 2, 1, "variable"));
    assert_eq!(settings.variable, Some(VariableStep::default()));
}

#[test]
fn frames_land_on_the_grid_and_the_steps_rise_at_the_whip() {
    // 100 frames: through the whip at about 1.4 s.
    let scene = flat(12, 2, 100, "variable");
    let (sim, result) = run(&scene);
    let report = result.unwrap();
    for f in &report.frames {
        assert_eq!(
            f.time.to_bits(),
            (f.frame as f64 / 60.0).to_bits(),
            "frame {} at t = {}",
            f.frame,
            f.time
        );
    }
    let v = report.variable.as_ref().expect("a variable-step run");
    let (min, _, max) = v.min_mean_max();
    assert_eq!(min, 2, "the floor is taken where it suffices: {v:?}");
    assert!(max > 2, "the steps rise at the whip: {v:?}");
    assert!(v.redone > 0, "{v:?}");
    assert!(v.max_accepted <= 1.0, "{v:?}");
    assert_eq!(v.steps(), report.steps);
    assert_eq!(sim.steps, report.steps);
    assert_eq!(v.frames, 100);
}

#[test]
fn the_variable_step_runs_where_the_fixed_step_at_its_floor_fails() {
    let (_, fixed) = run(&flat(12, 2, 100, "fixed"));
    let err = fixed.expect_err("the fixed step at 2 per frame fails at the whip");
    assert!(matches!(err, RunError::Constraint { .. }), "{err}");
    let (sim, variable) = run(&flat(12, 2, 100, "variable"));
    variable.unwrap();
    assert_eq!(sim.frame, 100);
}

/// Flip the momenta of `z = [q; p]`.
fn flipped(z: &[f64]) -> Vec<f64> {
    let n = z.len() / 2;
    z.iter()
        .enumerate()
        .map(|(k, x)| if k < n { *x } else { -x })
        .collect()
}

/// The largest difference of positions and of momenta.
fn miss(a: &[f64], b: &[f64]) -> (f64, f64) {
    let n = a.len() / 2;
    let d = |r: std::ops::Range<usize>| r.map(|k| (a[k] - b[k]).abs()).fold(0.0f64, f64::max);
    (d(0..n), d(n..2 * n))
}

/// Forward `frames` frames from `scene`'s start, then backward from the
/// flipped end with `back` (the same settings, or another run's), and the
/// miss against the start.
fn there_and_back(scene: &Scene, frames: usize, back: RunSettings) -> ((f64, f64), RunReport) {
    let mut forward = RunSettings::from_scene(scene);
    forward.options.frames = frames;
    let mut sim = Simulation::new(scene).unwrap();
    let start = sim.state.clone();
    let report = sim.run(&rattle(), &forward, |_| Ok(())).unwrap();
    let mut back_sim = Simulation::new(scene).unwrap();
    back_sim.state = flipped(&sim.state);
    let mut back = back;
    back.options.frames = frames;
    back_sim.run(&rattle(), &back, |_| Ok(())).unwrap();
    (miss(&flipped(&back_sim.state), &start), report)
}

#[test]
fn forwards_flipped_and_back_returns_to_the_start_to_round_off() {
    // 100 frames from the flat start through the whip (frames 85 and 88
    // take 3 and 5 steps, one of the tries at frame 88 fails its solve),
    // then back through it with the momenta flipped: the backward run
    // chooses its own counts from its own states, and returns to the start.
    // Tolerance: each step solves the constraints to 32·ε relative (about
    // 7e-15 m on this 1 m sheet), and the backward run starts from the
    // forward's rounded end, so the miss is that round-off carried through
    // 2 × 213 steps of the sheet's motion; measured 8.3e-13 m and
    // 4.2e-16 kg·m/s (the momenta are of order 1e-2 kg·m/s), the bounds
    // 1e-11 m and 1e-14 kg·m/s leave a factor 12 and 24. A different
    // choice of steps misses by far more (checked below).
    let scene = flat(12, 2, 100, "variable");
    let ((dq, dp), report) = there_and_back(&scene, 100, RunSettings::from_scene(&scene));
    let v = report.variable.unwrap();
    assert!(
        v.min_mean_max().2 > 2,
        "the frames at the whip took more steps: {v:?}"
    );
    assert!(v.failed > 0, "a try failed and was redone: {v:?}");
    assert!(
        dq <= 1e-11 && dp <= 1e-14,
        "missed the start by {dq:e} m, {dp:e} kg·m/s"
    );
    // The test can fail: back with a fixed count (the largest forward count
    // every frame, so that it runs) instead of the variable step's misses the
    // start by far more.
    let mut fixed = RunSettings::from_scene(&scene).with_variable(None);
    fixed.options.substeps = v.min_mean_max().2;
    let ((dq, _), _) = there_and_back(&scene, 100, fixed);
    assert!(dq > 1e-6, "the fixed step back missed by only {dq:e} m");
}

/// Stops (saving) at `stop_at`.
struct Saver {
    stop_at: usize,
    saved: Vec<RunState>,
}

impl RunControl for Saver {
    fn after_frame(&mut self, stats: &FrameStats) -> Action {
        if stats.frame == self.stop_at {
            Action::Stop
        } else {
            Action::Continue
        }
    }
    fn checkpoint(&mut self, state: &RunState) -> Result<(), CallbackError> {
        self.saved.push(state.clone());
        Ok(())
    }
}

#[test]
fn a_checkpoint_in_the_whip_resumes_to_the_same_bits() {
    let scene = flat(12, 2, 100, "variable");
    let settings = RunSettings::from_scene(&scene);
    let (whole_sim, whole) = run(&scene);
    let whole = whole.unwrap();
    // Stop at frame 86, between the frames 85 and 88 that take more than
    // the floor (a try of frame 88 fails its solve after the resume).
    let mut saver = Saver {
        stop_at: 86,
        saved: Vec::new(),
    };
    let mut sim = Simulation::new(&scene).unwrap();
    let stopped = sim.run_controlled(&rattle(), &settings, None, &mut saver, |_| Ok(()));
    assert!(matches!(stopped, Err(RunError::Stopped { frame: 86, .. })));
    let state = saver.saved.pop().unwrap();
    let at_stop = state.stepper.as_ref().map(Vec::len).unwrap();
    assert!(at_stop > 0);
    let mut resumed = Simulation::new(&scene).unwrap();
    let report = resumed
        .run_controlled(
            &rattle(),
            &settings,
            Some(&state),
            &mut cloth::checkpoint::NoControl,
            |_| Ok(()),
        )
        .unwrap();
    let bits = |z: &[f64]| z.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&resumed.state), bits(&whole_sim.state));
    assert_eq!(report.frames, whole.frames);
    assert_eq!(report.variable, whole.variable);
    // The solver's counts, but for its timings (they differ from run to
    // run) and its symbolic LU analyses: the resumed run's LU makes its
    // own symbolic analysis at its first refresh (a checkpoint does not
    // hold it; it is of the pattern, the same for every refresh, and changes
    // no bit).
    let counts = |s: &SolverStats| match *s {
        SolverStats::Constrained(mut st) => {
            st.seconds = Default::default();
            st.symbolic_lu = 0;
            st
        }
        _ => panic!("a RATTLE run"),
    };
    assert_eq!(counts(&report.solver), counts(&whole.solver));
    let v = whole.variable.unwrap();
    assert!(v.redone > 0 && v.min_mean_max().2 > 2, "{v:?}");
    // The stopped run's counts differ from the whole run's: the frames after
    // the stop took more than the floor too.
    let before: usize = state.frames.last().unwrap().step;
    assert!(
        whole.steps - before > 2 * (100 - 86),
        "{} steps after the stop",
        whole.steps - before
    );
}

#[test]
fn while_the_floor_is_accepted_the_run_is_the_fixed_steps_to_the_bit() {
    // The first 30 frames of the fall: 4 per frame keep h·ω below 1.
    let variable = flat(12, 4, 30, "variable");
    let fixed = flat(12, 4, 30, "fixed");
    let (a, ra) = run(&variable);
    let (b, rb) = run(&fixed);
    let ra = ra.unwrap();
    rb.unwrap();
    let v = ra.variable.unwrap();
    assert_eq!(v.histogram.len(), 1, "{v:?}");
    assert_eq!(v.attempts, 30);
    let bits = |z: &[f64]| z.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.state), bits(&b.state));
}

#[test]
fn the_scene_fields_are_checked_naming_them() {
    let text = |sim: &str, stretch: &str| {
        format!(
            r#"
            [cloth]
            width = 1.0
            height = 1.0
            nx = 4
            ny = 4
            [material]
            density = 0.01378
            stretch = {stretch}
            shear = 0.002
            [pins]
            edges = ["top"]
            [simulation]
            frames = 1
            {sim}
        "#
        )
    };
    let err = |sim: &str, stretch: &str| {
        Scene::from_toml(&text(sim, stretch), "s.toml")
            .unwrap_err()
            .to_string()
    };
    let e = err(
        "substeps = 2\nstep = \"variable\"\nmethod = \"stormer-verlet\"",
        "10.0",
    );
    assert!(
        e.contains("simulation.step") && e.contains("inextensible"),
        "{e}"
    );
    let e = err(
        "step = \"adaptive\"\nmethod = \"rattle\"",
        "\"inextensible\"",
    );
    assert!(
        e.contains("simulation.step") && e.contains("\"fixed\""),
        "{e}"
    );
    let e = err("wave_number = 2.5\nmethod = \"rattle\"", "\"inextensible\"");
    assert!(e.contains("simulation.wave_number"), "{e}");
    let e = err(
        "step = \"fixed\"\nwave_number = 1.2\nmethod = \"rattle\"",
        "\"inextensible\"",
    );
    assert!(
        e.contains("simulation.wave_number") && e.contains("fixed"),
        "{e}"
    );
    let e = err("max_substeps = 1\nmethod = \"rattle\"", "\"inextensible\"");
    assert!(e.contains("simulation.max_substeps"), "{e}");
    let ok = Scene::from_toml(
        &text(
            "wave_number = 1.5\nmax_substeps = 64\nmethod = \"rattle\"",
            "\"inextensible\"",
        ),
        "s.toml",
    )
    .unwrap();
    assert_eq!(
        ok.simulation.variable,
        Some(VariableStep {
            wave_number: 1.5,
            max_substeps: 64
        })
    );
}

#[test]
fn a_cap_too_low_for_the_whip_stops_the_run_naming_the_fields() {
    let mut scene = flat(12, 2, 100, "variable");
    scene.simulation.variable = Some(VariableStep {
        wave_number: 1.0,
        max_substeps: 2,
    });
    let (sim, result) = run(&scene);
    let e = result.unwrap_err();
    assert!(matches!(e, RunError::StepControl { .. }), "{e}");
    let text = e.to_string();
    assert!(
        text.contains("simulation.max_substeps = 2") && text.contains("simulation.wave_number"),
        "{text}"
    );
    assert!(sim.frame < 100);
}

/// A frame tried again starts from the marks of the frame's start (the
/// kept factor, the warm start, the carried momentum), not afresh: the
/// count taken ends on the bits of a first try with that count whatever
/// was tried in between, and the try from the marks makes the
/// factorisations the first try made, no more. With `rewind = false` the
/// stepper keeps no marks.
#[test]
fn a_frame_tried_again_ends_on_the_bits_of_its_first_try() {
    use cloth::step::{ClothStepper, MARK_START, RattleStepper};
    use cloth::{ClothModel, RattleSettings};

    let scene = flat(12, 4, 40, "fixed");
    let model = ClothModel::new(&scene).unwrap();
    let h = |n: usize| 1.0 / (60.0 * n as f64);
    let integrate = |stepper: &mut RattleStepper, z: &mut Vec<f64>, t: f64, n: usize| {
        stepper.enter(&model, t, z);
        for k in 0..n {
            stepper.step(&model, t + k as f64 * h(n), h(n), z).unwrap();
        }
        stepper.leave(&model, t + 1.0 / 60.0, z);
    };
    let mut stepper = RattleStepper::new(&model, h(4), RattleSettings::default()).unwrap();
    let mut z = model.initial_state();
    // 30 frames of 4 steps: the sheet is falling, its factor aged.
    for k in 0..30 {
        integrate(&mut stepper, &mut z, k as f64 / 60.0, 4);
    }
    let t = 0.5;
    let factorizations = |s: &RattleStepper| match s.stats() {
        SolverStats::Constrained(st) => st.factorizations,
        other => panic!("RATTLE reported {other:?}"),
    };
    let bits = |z: &[f64]| z.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let start = z.clone();
    stepper.mark(MARK_START);
    let f0 = factorizations(&stepper);
    let mut first = start.clone();
    integrate(&mut stepper, &mut first, t, 5);
    let first_cost = factorizations(&stepper) - f0;
    // A try with another count, then the first count again from the marks.
    assert!(stepper.rewind(MARK_START));
    let mut other = start.clone();
    integrate(&mut stepper, &mut other, t, 3);
    assert_ne!(bits(&other), bits(&first), "3 and 5 steps should end apart");
    assert!(stepper.rewind(MARK_START));
    let f1 = factorizations(&stepper);
    let mut again = start.clone();
    integrate(&mut stepper, &mut again, t, 5);
    assert_eq!(
        bits(&again),
        bits(&first),
        "the second try of 5 steps differs from the first"
    );
    assert_eq!(factorizations(&stepper) - f1, first_cost);

    let fresh = RattleSettings {
        rewind: false,
        ..Default::default()
    };
    let mut plain = RattleStepper::new(&model, h(4), fresh).unwrap();
    plain.mark(MARK_START);
    assert!(!plain.rewind(MARK_START));
}
