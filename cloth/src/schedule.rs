//! The run a caller asks of a scene: its frames, steps per frame and frame
//! rate, with the scene's values for what is not given, and a step size
//! `dt` turned into whole steps per frame. Checked against the run limits
//! ([`MAX_FRAMES`], [`MAX_STEPS`], a normal step size) before anything is
//! built; an error says which value broke them, so `symlab cloth` names the
//! flag and a Rust caller its own field.
//!
//! ```
//! use cloth::schedule::{Asked, RunRequest, schedule};
//! let scene = cloth::Scene::from_toml(include_str!("../../scenes/paper32.toml"), "paper32.toml").unwrap();
//! let plan = schedule(&scene, &RunRequest { frames: Some(3), dt: Some(1e-3), ..Default::default() }).unwrap();
//! assert_eq!(plan.options.frames, 3);
//! assert!((plan.options.step_size() - 1e-3).abs() < 1e-15);
//!
//! let err = schedule(&scene, &RunRequest { substeps: Some(0), ..Default::default() }).unwrap_err();
//! assert_eq!(err.asked, Asked::Substeps);
//! ```

use crate::run::RunOptions;
use crate::scene::{MAX_FRAMES, MAX_STEPS, Scene, run_length_problem};

/// What a caller asks for; `None` keeps the scene's value. `dt` sets the
/// steps per frame to the nearest whole number of steps of `dt`, and moves
/// the frame rate so that they make a frame exactly.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RunRequest {
    pub frames: Option<usize>,
    pub substeps: Option<usize>,
    pub dt: Option<f64>,
}

/// Which value a schedule error is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Asked {
    Frames,
    Substeps,
    Dt,
    /// A field of the scene's `[simulation]` table (`frames`, `substeps`,
    /// `frame_rate`) that the request left as it was.
    Scene(&'static str),
}

/// Why the asked run cannot be made: [`Asked`] names the value, `message`
/// says what is wrong with it (without naming it).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct ScheduleError {
    pub asked: Asked,
    pub message: String,
}

/// The checked run, and a note when the frame rate moved for `dt`.
#[derive(Clone, Debug, PartialEq)]
pub struct Schedule {
    pub options: RunOptions,
    pub note: Option<String>,
}

fn fail(asked: Asked, message: String) -> ScheduleError {
    ScheduleError { asked, message }
}

/// The run of `scene` that `request` asks for, checked.
pub fn schedule(scene: &Scene, request: &RunRequest) -> Result<Schedule, ScheduleError> {
    let mut opts = RunOptions::from_scene(scene);
    let duration = scene.simulation.frames as f64 / scene.simulation.frame_rate;
    let mut note = None;
    if let Some(k) = request.substeps {
        if k == 0 {
            return Err(fail(Asked::Substeps, "must be at least 1".into()));
        }
        opts.substeps = k;
    }
    if let Some(h) = request.dt {
        if !(h > 0.0 && h.is_finite()) {
            return Err(fail(
                Asked::Dt,
                format!("must be a positive step size in seconds (got {h})"),
            ));
        }
        let rate = opts.frame_rate;
        let per_frame = (1.0 / (rate * h)).round().max(1.0);
        if per_frame.is_nan() || per_frame > MAX_STEPS as f64 {
            return Err(fail(
                Asked::Dt,
                format!(
                    "{per_frame:e} steps per {rate} Hz frame is more than the limit of {MAX_STEPS} steps in a run"
                ),
            ));
        }
        let k = per_frame as usize;
        opts.substeps = k;
        let exact = 1.0 / (k as f64 * h);
        if (exact - rate).abs() > 1e-9 * rate {
            opts.frame_rate = exact;
            note = Some(format!(
                "frame rate {exact:.4} Hz instead of {rate} Hz so that {k} step{} of h = {h:e} s make a frame",
                if k == 1 { "" } else { "s" }
            ));
            if request.frames.is_none() {
                let frames = (duration * exact).round().max(1.0);
                if frames.is_nan() || frames > MAX_FRAMES as f64 {
                    return Err(fail(
                        Asked::Dt,
                        format!(
                            "the scene's {duration} s would be {frames:e} frames of one step, more than the limit of {MAX_FRAMES} frames (give the number of frames)"
                        ),
                    ));
                }
                opts.frames = frames as usize;
            }
        }
    }
    if let Some(n) = request.frames {
        opts.frames = n;
    }
    if let Some((what, message)) = run_length_problem(opts.frames, opts.substeps, opts.frame_rate) {
        let asked = match what {
            "frames" if request.frames.is_some() => Asked::Frames,
            "frames" | "substeps" | "frame_rate" if request.dt.is_some() => Asked::Dt,
            "substeps" if request.substeps.is_some() => Asked::Substeps,
            "frames" => Asked::Scene("frames"),
            "substeps" => Asked::Scene("substeps"),
            _ => Asked::Scene("frame_rate"),
        };
        return Err(fail(asked, message));
    }
    Ok(Schedule {
        options: opts,
        note,
    })
}
