//! Checkpoints of cloth runs in the library: a RATTLE run stopped after
//! any frame, its [`RunState`] saved, encoded, decoded and continued in a
//! fresh simulation, ends with the bits, frames and solver counts of the
//! run that was never stopped; checkpointing after every frame does not
//! change a run's bits; a state that does not fit the run is refused.

use cloth::checkpoint::{Action, Decoder, Encoder, NoControl, RunControl, RunState, resumable};
use cloth::{
    CallbackError, FrameStats, Method, RunError, RunReport, RunSettings, Scene, Simulation,
    SolverStats,
};

/// The hammock scene at a small grid, a few frames.
fn hammock(n: usize, frames: usize) -> Scene {
    let mut scene = Scene::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/hammock-inextensible.toml"
    ))
    .unwrap();
    cloth::scene::regrid(&mut scene, n, n);
    scene.simulation.frames = frames;
    scene.validate().unwrap();
    scene
}

/// Saves at the frames in `save_at` and stops at `stop_at`.
struct Saver {
    save_at: Vec<usize>,
    stop_at: Option<usize>,
    saved: Vec<RunState>,
}

impl RunControl for Saver {
    fn after_frame(&mut self, stats: &FrameStats) -> Action {
        if Some(stats.frame) == self.stop_at {
            Action::Stop
        } else if self.save_at.contains(&stats.frame) {
            Action::Checkpoint
        } else {
            Action::Continue
        }
    }
    fn checkpoint(&mut self, state: &RunState) -> Result<(), CallbackError> {
        self.saved.push(state.clone());
        Ok(())
    }
}

fn run(
    scene: &Scene,
    resume: Option<&RunState>,
    control: &mut dyn RunControl,
) -> (Simulation, Result<RunReport, RunError>, Vec<FrameStats>) {
    let method = Method::parse("rattle").unwrap();
    let settings = RunSettings::from_scene(scene);
    let mut sim = Simulation::new(scene).unwrap();
    let mut seen = Vec::new();
    let result = sim.run_controlled(&method, &settings, resume, control, |f| {
        seen.push(f.stats);
        Ok(())
    });
    (sim, result, seen)
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// The solver counts without the timings.
fn counts(s: &SolverStats) -> String {
    match s {
        SolverStats::Constrained(st) => {
            let mut st = *st;
            st.seconds = Default::default();
            format!("{st:?}")
        }
        other => panic!("not a RATTLE run: {other:?}"),
    }
}

/// Through the exact binary encoding, as a checkpoint file holds it.
fn round_trip(state: &RunState) -> RunState {
    let mut e = Encoder::new();
    state.encode(&mut e);
    let bytes = e.finish();
    let path = std::path::Path::new("memory");
    let mut d = Decoder::new(path, &bytes);
    let back = RunState::decode(&mut d).unwrap();
    d.end().unwrap();
    back
}

#[test]
fn a_stopped_rattle_run_continues_to_the_same_bits_from_any_frame() {
    let frames = 24;
    let scene = hammock(8, frames);
    assert!(resumable(&Method::parse("rattle").unwrap()));
    let (whole, report, _) = run(&scene, None, &mut NoControl);
    let report = report.unwrap();
    assert_eq!(report.frames.len(), frames + 1);
    for stop in [0, 1, 5, 6, 11, 23] {
        let mut saver = Saver {
            save_at: vec![],
            stop_at: Some(stop),
            saved: vec![],
        };
        let (_, stopped, seen) = run(&scene, None, &mut saver);
        match stopped {
            Err(RunError::Stopped { frame, .. }) => assert_eq!(frame, stop),
            other => panic!("expected a stop at {stop}, got {other:?}"),
        }
        assert_eq!(seen.len(), stop + 1);
        let state = round_trip(&saver.saved[0]);
        assert_eq!(state, saver.saved[0], "the encoding keeps every bit");
        assert!(state.resumable());
        let (resumed, rest, seen) = run(&scene, Some(&state), &mut NoControl);
        let rest = rest.unwrap();
        assert_eq!(seen.len(), frames - stop, "only the frames after {stop}");
        assert_eq!(
            bits(&resumed.state),
            bits(&whole.state),
            "stopped at {stop}"
        );
        assert_eq!(resumed.time.to_bits(), whole.time.to_bits());
        assert_eq!(resumed.steps, whole.steps);
        assert_eq!(rest.frames, report.frames, "every frame's statistics");
        assert_eq!(rest.steps, report.steps);
        assert_eq!(counts(&rest.solver), counts(&report.solver));
    }
}

#[test]
fn checkpoints_do_not_change_the_bits_of_a_run() {
    let scene = hammock(7, 12);
    let (plain, report, _) = run(&scene, None, &mut NoControl);
    let mut saver = Saver {
        save_at: (0..=12).collect(),
        stop_at: None,
        saved: vec![],
    };
    let (saved, with, _) = run(&scene, None, &mut saver);
    assert_eq!(bits(&saved.state), bits(&plain.state));
    assert_eq!(with.unwrap().frames, report.unwrap().frames);
    assert_eq!(saver.saved.len(), 13);
    // Resuming from a state saved mid-run (not a stop) also agrees.
    let (resumed, _, _) = run(&scene, Some(&saver.saved[7]), &mut NoControl);
    assert_eq!(bits(&resumed.state), bits(&plain.state));
}

#[test]
fn a_state_of_another_run_is_refused() {
    let scene = hammock(6, 6);
    let mut saver = Saver {
        save_at: vec![],
        stop_at: Some(3),
        saved: vec![],
    };
    let _ = run(&scene, None, &mut saver);
    let state = &saver.saved[0];
    // Another grid: the state's length differs.
    let other = hammock(7, 6);
    let (_, r, _) = run(&other, Some(state), &mut NoControl);
    assert!(
        matches!(&r, Err(RunError::Resume(m)) if m.contains("components")),
        "{r:?}"
    );
    // Another step size.
    let mut faster = scene.clone();
    faster.simulation.substeps += 1;
    let (_, r, _) = run(&faster, Some(state), &mut NoControl);
    assert!(
        matches!(&r, Err(RunError::Resume(m)) if m.contains("step")),
        "{r:?}"
    );
    // A damaged stepper payload.
    let mut broken = state.clone();
    broken.stepper.as_mut().unwrap().truncate(10);
    let (_, r, _) = run(&scene, Some(&broken), &mut NoControl);
    assert!(matches!(&r, Err(RunError::Resume(_))), "{r:?}");
    // A run already past its end.
    let mut short = scene.clone();
    short.simulation.frames = 2;
    let (_, r, _) = run(&short, Some(state), &mut NoControl);
    assert!(
        matches!(&r, Err(RunError::Resume(m)) if m.contains("after the last frame")),
        "{r:?}"
    );
}
