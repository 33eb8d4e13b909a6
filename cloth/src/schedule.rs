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

use crate::method::Method;
use crate::model::ClothModel;
use crate::run::{CallbackError, Frame, RunError, RunOptions, RunReport, RunSettings, Simulation};
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

/// The share of the tension-wave step `ℓ/√(|g|·L)` that `substeps =
/// "auto"` takes. The estimate is the static tension at the top of a
/// hanging sheet; the swinging sheet's tension peaks at about 3.1× it
/// (measured on the 64² sheet released 45°: the largest `h·ω = 4·√(½ΣΛ)`
/// was 1.909 at `h` = 0.55 of this step, docs/results/cloth-inextensible.md),
/// which puts `ω` 1.76× higher: 0.5 keeps such a peak below RATTLE's limit
/// `h·ω < 2`.
pub const TENSION_SAFETY: f64 = 0.5;

/// The share of the linear limits `2/ω` (springs, bending) that `substeps
/// = "auto"` takes: their `ω` are Gershgorin's upper bounds (the bending's
/// `K` is constant, the soft springs barely stretch), so only round-off
/// and the coupling of the modes need the margin.
pub const LINEAR_SAFETY: f64 = 0.9;

/// One bound on the step of `substeps = "auto"`.
#[derive(Clone, Debug, PartialEq)]
pub struct StepLimit {
    /// What sets it: `"tension waves"`, `"springs"`, `"bending"`,
    /// `"colliders"`.
    pub name: &'static str,
    /// The limit itself (s): `ℓ/√(|g|·L)`, `2/ω` or `1/√stiffness`.
    pub limit: f64,
    /// The share taken ([`TENSION_SAFETY`], [`LINEAR_SAFETY`], 1 for a
    /// collider, whose `h·√stiffness ≤ 1` RATTLE requires as it is).
    pub safety: f64,
    /// How the limit was found, in words with the numbers.
    pub how: String,
}

impl StepLimit {
    /// `safety·limit` (s).
    pub fn step(&self) -> f64 {
        self.safety * self.limit
    }
}

/// The step `substeps = "auto"` chose and why.
#[derive(Clone, Debug, PartialEq)]
pub struct AutoStep {
    /// Steps per frame: the fewest whose step is within every limit.
    pub substeps: usize,
    /// `1/(frame_rate·substeps)` (s).
    pub h: f64,
    /// Every limit of the scene; the one with the smallest
    /// [`StepLimit::step`] binds.
    pub limits: Vec<StepLimit>,
}

impl AutoStep {
    /// The limit that binds.
    pub fn binding(&self) -> &StepLimit {
        self.limits
            .iter()
            .min_by(|a, b| a.step().total_cmp(&b.step()))
            .expect("auto_step has a limit")
    }

    /// One line: what was chosen, which limit binds and the others.
    pub fn describe(&self) -> String {
        let b = self.binding();
        let others: Vec<String> = self
            .limits
            .iter()
            .filter(|l| l.name != b.name)
            .map(|l| format!("{} {:.3e} s", l.name, l.step()))
            .collect();
        format!(
            "substeps = \"auto\": {} per frame, h = {:.4e} s, bound by the {}: {} = {:.4e} s, × {} = {:.4e} s{}",
            self.substeps,
            self.h,
            b.name,
            b.how,
            b.limit,
            b.safety,
            b.step(),
            if others.is_empty() {
                String::new()
            } else {
                format!(
                    "; the other limits (with their shares): {}",
                    others.join(", ")
                )
            }
        )
    }
}

/// The step of `substeps = "auto"` for `model` at `frame_rate`: the
/// fewest steps per frame whose step `h` is within every limit the scene
/// has — the tension waves of an inextensible sheet under gravity
/// ([`ClothModel::tension_wave_step`] × [`TENSION_SAFETY`]), the springs'
/// and the bending's linear limits `2/ω` from Gershgorin's bounds
/// ([`ClothModel::spring_rate_bound`], [`ClothModel::bending_rate`]) ×
/// [`LINEAR_SAFETY`], and each collider's `1/√stiffness`. Frames land on
/// `1/frame_rate` because the step is a whole fraction of a frame. An
/// error (the scene's `substeps`) when there is no limit at all (nothing
/// moves the sheet faster than a frame: one step per frame is then
/// chosen, not an error) or the steps exceed [`MAX_STEPS`].
pub fn auto_step(model: &ClothModel, frame_rate: f64) -> AutoStep {
    let mut limits = Vec::new();
    if let Some(wave) = model.tension_wave_step() {
        limits.push(StepLimit {
            name: "tension waves",
            limit: wave,
            safety: TENSION_SAFETY,
            how: "ℓ/√(|g|·L)".to_string(),
        });
    }
    let springs = model.spring_rate_bound();
    if springs > 0.0 && springs.is_finite() {
        limits.push(StepLimit {
            name: "springs",
            limit: 2.0 / springs,
            safety: LINEAR_SAFETY,
            how: format!("2/ω, ω ≤ {springs:.4e} rad/s (Gershgorin, springs and colliders)"),
        });
    }
    if let Some(rate) = model.bending_rate() {
        limits.push(StepLimit {
            name: "bending",
            limit: 2.0 / rate.bound,
            safety: LINEAR_SAFETY,
            how: format!(
                "2/ω, ω ≤ {:.4e} rad/s (Gershgorin; the power iteration's {:.4e})",
                rate.bound, rate.estimate
            ),
        });
    }
    for (k, rate) in model.collider_rates().into_iter().enumerate() {
        if rate > 0.0 {
            limits.push(StepLimit {
                name: "colliders",
                limit: 1.0 / rate,
                safety: 1.0,
                how: format!("1/√stiffness of colliders[{k}]"),
            });
        }
    }
    if limits.is_empty() {
        limits.push(StepLimit {
            name: "frame",
            limit: 1.0 / frame_rate,
            safety: 1.0,
            how: "no limit faster than a frame".to_string(),
        });
    }
    let h_max = limits
        .iter()
        .map(StepLimit::step)
        .fold(f64::INFINITY, f64::min);
    let per_frame = (1.0 / (frame_rate * h_max)).ceil().max(1.0);
    let substeps = if per_frame.is_finite() && per_frame < MAX_STEPS as f64 {
        per_frame as usize
    } else {
        usize::try_from(MAX_STEPS).unwrap_or(usize::MAX)
    };
    AutoStep {
        substeps,
        h: 1.0 / (frame_rate * substeps as f64),
        limits,
    }
}

/// [`schedule`] with `substeps = "auto"` resolved on `model`: where the
/// scene asks for it and the request gives neither `substeps` nor `dt`,
/// the steps per frame are [`auto_step`]'s, and the reason comes back in
/// [`Schedule::note`] and as the [`AutoStep`]. With the variable step
/// (`simulation.step = "variable"`, [`crate::step::variable`]) they are
/// its floor, and the note says so.
pub fn schedule_for(
    scene: &Scene,
    model: &ClothModel,
    request: &RunRequest,
) -> Result<(Schedule, Option<AutoStep>), ScheduleError> {
    if !scene.simulation.auto_substeps || request.substeps.is_some() || request.dt.is_some() {
        return Ok((schedule(scene, request)?, None));
    }
    let auto = auto_step(model, scene.simulation.frame_rate);
    let mut resolved = scene.clone();
    resolved.simulation.substeps = auto.substeps;
    let mut plan = schedule(&resolved, request)?;
    let mut why = auto.describe();
    if scene.simulation.variable.is_some() {
        why.push_str(
            "; with step = \"variable\" the fewest a frame takes, each frame taking more where its h·ω would pass wave_number",
        );
    }
    plan.note = Some(match plan.note {
        Some(n) => format!("{n}; {why}"),
        None => why,
    });
    Ok((plan, Some(auto)))
}

/// Load nothing, build everything: run `scene` with its own method and
/// settings ([`RunSettings::from_scene`]: the default solvers, no guard;
/// `substeps = "auto"` resolved on the model,
/// [`auto_step`]), calling `on_frame` for the initial
/// state and every frame.
pub fn run_scene<F>(scene: &Scene, on_frame: F) -> Result<(Simulation, RunReport), RunError>
where
    F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
{
    let method = Method::parse(&scene.simulation.method)?;
    let mut sim = Simulation::new(scene)?;
    let mut settings = RunSettings::from_scene(scene);
    if scene.simulation.auto_substeps {
        settings.options.substeps = auto_step(&sim.model, scene.simulation.frame_rate).substeps;
    }
    let report = sim.run(&method, &settings, on_frame)?;
    Ok((sim, report))
}
