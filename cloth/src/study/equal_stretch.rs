//! The springs at equal stretch (issue 37, item 5): the spring model and
//! the constrained model of one sheet, side by side, with the springs just
//! stiff enough that no warp or weft edge stretches by more than 1 %.
//!
//! The constrained scene (`material.stretch = "inextensible"`) is the
//! reference. Its **spring twin** ([`spring_twin`]) is the same sheet —
//! grid, density, pins, shear, gravity (the same release), frames — with
//! the warp and weft edges stretch springs of stiffness `k` instead of
//! length constraints, no isometric bending (a spring scene cannot have it:
//! the energy assumes isometric motion), stepped by Störmer–Verlet
//! ([`SPRING_METHOD`], the unconstrained method of which RATTLE is the
//! constrained form) at the step `substeps = "auto"` gives a spring scene:
//! 0.9 of the linear limit `2/ω`, `ω` from Gershgorin's bound
//! ([`auto_step`]).
//!
//! **The stiffness** is measured, not assumed: a trial runs the twin over
//! the whole run with a frame after every step and takes the largest
//! `|ℓ − L|/L` over the warp and weft edges at every step
//! ([`WarpWeft::max_stretch`]; the soft shear diagonals are not counted:
//! they are springs in both models). The rule ([`search_stiffness`]):
//! start at three times the static tension at the top of a column over
//! the bound, `k₀ = 3·(ny − 1)·m·|g| / 1 %` (the swinging sheet's tension
//! peaks at about 3.1× the static one, `crate::schedule::TENSION_SAFETY`);
//! a trial with stretch `s` moves to `k·s/(0.95 %)` (a spring's stretch
//! under a given tension goes like `1/k`), or, once a stiffness has passed
//! and a softer one failed and that prediction falls outside them, to their
//! geometric mean (the peak stretch also moves with the motion and the
//! step, so the prediction can overshoot: at 128² it swung between two
//! values); the first trial with `0.9 % ≤ s ≤ 1 %` is taken, and otherwise,
//! after [`EqualStretchSettings::max_trials`] or once the two bracketing
//! stiffnesses are within 1 % of each other, the softest that passed.
//! Every trial is kept and reported.
//!
//! Then each model is run once more with frames at the scene's rate and
//! timed ([`Measured`]): the twin at the stiffness found, on one thread
//! and, where the grid is banded ([`Banding::Auto`]), on the bands'
//! threads; RATTLE with its scene's step (by default the reversible
//! variable step) without bending — the same sheet as the twin — and, if
//! the scene has bending, with it, as the scene is shipped. Each reports
//! its steps per frame, its stepping time per frame, the largest
//! `|H − H₀|/E_ref` over its frames and the largest warp and weft stretch
//! (RATTLE's: its constraint violation, at every frame).
//!
//! ```
//! use cloth::Scene;
//! use cloth::study::equal_stretch::{EqualStretchSettings, MAX_STRETCH, study};
//!
//! let scene = Scene::from_toml(r#"
//!     gravity = [0.0, -6.9367, 6.9367]
//!     [cloth]
//!     width = 1.0
//!     height = 1.0
//!     nx = 6
//!     ny = 6
//!     plane = "vertical"
//!     [material]
//!     density = 0.01378
//!     stretch = "inextensible"
//!     shear = 0.002
//!     [pins]
//!     edges = ["top"]
//!     [simulation]
//!     frames = 30
//!     method = "rattle"
//! "#, "sheet.toml")?;
//! let found = study(&scene, &EqualStretchSettings::new(30))?;
//! let springs = &found.rows[0];
//! assert!(springs.max_stretch <= MAX_STRETCH);
//! assert!(found.rows.iter().any(|r| r.stiffness.is_none() && r.max_stretch < 1e-12));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use nalgebra::Vector3;

use crate::method::{Method, RATTLE};
use crate::run::{RunError, RunOptions, RunSettings, Simulation};
use crate::scene::{Scene, SceneError};
use crate::schedule::auto_step;
use crate::step::Banding;
use crate::study::energy::{ReferenceEnergyError, reference_energy, worst_relative_error};

/// The largest warp or weft stretch `|ℓ − L|/L` the springs may show: 1 %.
pub const MAX_STRETCH: f64 = 0.01;

/// The method of the spring twin: Störmer–Verlet, one force per step.
pub const SPRING_METHOD: &str = "stormer-verlet";

/// The first stiffness is this many times the static tension at the top
/// of a column, over the bound.
pub const PEAK_FACTOR: f64 = 3.0;

/// A trial with stretch `s` moves the stiffness to `k·s/(AIM·bound)`.
pub const AIM: f64 = 0.95;

/// A trial is taken once its stretch is within `[CLOSE·bound, bound]`.
pub const CLOSE: f64 = 0.9;

/// The search stops once the softest stiffness that passed is within this
/// factor of the stiffest that failed.
pub const BRACKET: f64 = 1.01;

/// What the study runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EqualStretchSettings {
    /// Frames after the initial one, at the scene's frame rate (every run
    /// of the study simulates the same span).
    pub frames: usize,
    /// The largest warp and weft stretch the springs may show
    /// ([`MAX_STRETCH`]).
    pub max_stretch: f64,
    /// The most trials of the stiffness search (default 8).
    pub max_trials: usize,
}

impl EqualStretchSettings {
    /// `frames` frames, 1 %, at most 8 trials.
    pub fn new(frames: usize) -> EqualStretchSettings {
        EqualStretchSettings {
            frames,
            max_stretch: MAX_STRETCH,
            max_trials: 8,
        }
    }
}

/// Why the study cannot be made; the message names the field.
#[derive(Debug, thiserror::Error)]
pub enum EqualStretchError {
    /// The scene is a spring scene: there are no constraints to compare.
    #[error(
        "material.stretch: the study compares springs with the length constraints of an inextensible scene (material.stretch = \"inextensible\"); this scene's warp and weft are springs already"
    )]
    NotInextensible,
    /// No gravity: nothing stretches the springs, so no stiffness is
    /// needed and none can be found.
    #[error(
        "gravity: the scene has no gravity, so nothing stretches the springs and the search for a stiffness has nothing to measure"
    )]
    NoGravity,
    /// A setting of the study (`frames`, `max_stretch`, `max_trials`).
    #[error("{field}: {message}")]
    Setting {
        field: &'static str,
        message: String,
    },
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Reference(#[from] ReferenceEnergyError),
    /// A run of the study failed (the message names the model).
    #[error("{model}: {source}")]
    Run {
        model: String,
        #[source]
        source: Box<RunError>,
    },
    /// No trial kept the stretch within the bound.
    #[error(
        "no stiffness found within {trials} trials that keeps the warp and weft within {bound:e} (the last trial: k = {last_k:e} N, stretch {last_stretch:e})"
    )]
    NotFound {
        trials: usize,
        bound: f64,
        last_k: f64,
        last_stretch: f64,
    },
}

/// The larger of `a` and `b`, NaN if either is (`f64::max` drops a NaN).
fn larger(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// The warp and weft edges of a grid: `(i, j)–(i + 1, j)` of rest length
/// `dx` and `(i, j)–(i, j + 1)` of rest length `dy`, pinned ends included
/// (an edge between two pins keeps its length).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WarpWeft {
    pub nx: usize,
    pub ny: usize,
    pub dx: f64,
    pub dy: f64,
}

impl WarpWeft {
    /// The edges of `scene`'s grid (rest lengths `width/(nx − 1)`,
    /// `height/(ny − 1)`, as the springs and the constraints have them).
    pub fn of(scene: &Scene) -> WarpWeft {
        let c = &scene.cloth;
        WarpWeft {
            nx: c.nx,
            ny: c.ny,
            dx: c.width / (c.nx - 1) as f64,
            dy: c.height / (c.ny - 1) as f64,
        }
    }

    /// The largest `|ℓ − L|/L` over the edges, with `positions` indexed by
    /// particle id `j·nx + i` ([`crate::Frame::positions`]). NaN when a
    /// position is not finite.
    pub fn max_stretch(&self, positions: &[Vector3<f64>]) -> f64 {
        let (nx, ny) = (self.nx, self.ny);
        let mut worst = 0.0f64;
        let mut note = |a: usize, b: usize, rest: f64| {
            worst = larger(
                worst,
                ((positions[b] - positions[a]).norm() - rest).abs() / rest,
            );
        };
        for j in 0..ny {
            for i in 0..nx {
                let a = j * nx + i;
                if i + 1 < nx {
                    note(a, a + 1, self.dx);
                }
                if j + 1 < ny {
                    note(a, a + nx, self.dy);
                }
            }
        }
        worst
    }
}

/// The spring twin of an inextensible scene: its warp and weft edges
/// stretch springs of `stretch` N per unit strain, no isometric bending,
/// the fixed step, [`SPRING_METHOD`], `substeps = "auto"`; the rest as it
/// is. Checked as a loaded scene is.
pub fn spring_twin(scene: &Scene, stretch: f64) -> Result<Scene, EqualStretchError> {
    if !scene.material.inextensible {
        return Err(EqualStretchError::NotInextensible);
    }
    let mut twin = scene.clone();
    twin.material.inextensible = false;
    twin.material.stretch = Some(stretch);
    twin.material.bending = 0.0;
    twin.simulation.variable = None;
    twin.simulation.method = SPRING_METHOD.to_string();
    twin.simulation.auto_substeps = true;
    twin.validate()?;
    Ok(twin)
}

/// The first stiffness of the search (N per unit strain):
/// [`PEAK_FACTOR`] times the weight of a column's free particles below
/// its top edge, `(ny − 1)·m·|g|`, over `bound`.
pub fn first_stiffness(scene: &Scene, bound: f64) -> f64 {
    let c = &scene.cloth;
    let m = scene.material.density * c.width * c.height / (c.nx * c.ny) as f64;
    let g = scene.gravity.iter().fold(0.0f64, |a, x| a.hypot(*x));
    PEAK_FACTOR * (c.ny - 1) as f64 * m * g / bound
}

/// One run of a model, measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    /// Frames run (after the initial one) and steps in all.
    pub frames: usize,
    pub steps: usize,
    /// The fewest, the mean and the most steps of a frame.
    pub steps_per_frame: (usize, f64, usize),
    /// Wall-clock time of the stepping alone (s).
    pub stepping_seconds: f64,
    /// `E_ref` (J) and the largest `|H − H₀|/E_ref` over the frames.
    pub e_ref: f64,
    pub max_energy_error: f64,
    /// The largest warp and weft stretch over the frames.
    pub max_stretch: f64,
    /// Simulated seconds.
    pub duration: f64,
}

impl Measured {
    /// Stepping time per frame (s).
    pub fn seconds_per_frame(&self) -> f64 {
        self.stepping_seconds / self.frames.max(1) as f64
    }
}

/// Run `scene` with `method` and `settings`, measuring the energy error
/// and the warp and weft stretch at every frame; a failed run is
/// [`EqualStretchError::Run`] naming `model`.
pub fn measure(
    model: &str,
    scene: &Scene,
    method: &Method,
    settings: &RunSettings,
) -> Result<Measured, EqualStretchError> {
    let failed = |e: RunError| EqualStretchError::Run {
        model: model.to_string(),
        source: Box::new(e),
    };
    let edges = WarpWeft::of(scene);
    let mut sim = Simulation::new(scene)?;
    let e_ref = reference_energy(scene, &sim)?;
    let mut stretch = 0.0f64;
    let mut buffer = Vec::new();
    let report = sim
        .run(method, settings, |frame| {
            frame.model.positions_into(frame.q(), &mut buffer);
            stretch = larger(stretch, edges.max_stretch(&buffer));
            Ok(())
        })
        .map_err(failed)?;
    let frames = report.frames.len().saturating_sub(1);
    let steps_per_frame = match &report.variable {
        Some(v) => v.min_mean_max(),
        None => {
            let n = settings.options.substeps;
            (n, n as f64, n)
        }
    };
    Ok(Measured {
        frames,
        steps: report.steps,
        steps_per_frame,
        stepping_seconds: report.stepping_seconds,
        e_ref,
        max_energy_error: worst_relative_error(&report.frames, e_ref).0,
        max_stretch: stretch,
        duration: sim.time,
    })
}

/// One trial of the stiffness search.
#[derive(Clone, Debug, PartialEq)]
pub struct Trial {
    /// The stiffness tried (N per unit strain).
    pub stiffness: f64,
    /// Steps per frame (`substeps = "auto"` of the twin).
    pub substeps: usize,
    /// The largest warp and weft stretch at any step (∞ when the run
    /// failed).
    pub max_stretch: f64,
    /// The largest `|H − H₀|/E_ref` at any step.
    pub max_energy_error: f64,
    /// Why the run failed, if it did.
    pub failed: Option<String>,
}

/// Run the spring twin at `stiffness` over `frames` frames of `scene`'s
/// rate with a frame after every step, and measure its largest warp and
/// weft stretch and energy error at every step. A run that fails is a
/// trial with stretch ∞ and the reason.
pub fn spring_trial(
    scene: &Scene,
    stiffness: f64,
    frames: usize,
) -> Result<Trial, EqualStretchError> {
    let twin = spring_twin(scene, stiffness)?;
    let rate = twin.simulation.frame_rate;
    let sim = Simulation::new(&twin)?;
    let substeps = auto_step(&sim.model, rate).substeps;
    let options = RunOptions {
        frames: frames.saturating_mul(substeps),
        substeps: 1,
        frame_rate: rate * substeps as f64,
    };
    let settings = RunSettings::new(options).with_banding(Banding::Off);
    let model = format!("springs, k = {stiffness:e} N (a trial)");
    let method = spring_method()?;
    match measure(&model, &twin, &method, &settings) {
        Ok(m) => Ok(Trial {
            stiffness,
            substeps,
            max_stretch: m.max_stretch,
            max_energy_error: m.max_energy_error,
            failed: None,
        }),
        Err(EqualStretchError::Run { source, .. }) if source.is_blowup() => Ok(Trial {
            stiffness,
            substeps,
            max_stretch: f64::INFINITY,
            max_energy_error: f64::INFINITY,
            failed: Some(source.to_string()),
        }),
        Err(e) => Err(e),
    }
}

/// [`SPRING_METHOD`], parsed.
fn spring_method() -> Result<Method, EqualStretchError> {
    Method::parse(SPRING_METHOD).map_err(|e| EqualStretchError::Run {
        model: "springs".into(),
        source: Box::new(e.into()),
    })
}

/// The stiffness search ([`first_stiffness`], then `k·s/(AIM·bound)`,
/// or the geometric mean of the softest stiffness that passed and the
/// stiffest that failed where that prediction is not between them, until a
/// trial's stretch is within `[CLOSE·bound, bound]`); every trial, and the
/// index of the one taken: that one, or after `max_trials` (or once the
/// bracket is within [`BRACKET`]) the softest whose stretch is within the
/// bound.
pub fn search_stiffness(
    scene: &Scene,
    settings: &EqualStretchSettings,
) -> Result<(Vec<Trial>, usize), EqualStretchError> {
    let bound = settings.max_stretch;
    let mut k = first_stiffness(scene, bound);
    let mut trials: Vec<Trial> = Vec::new();
    while trials.len() < settings.max_trials {
        let trial = spring_trial(scene, k, settings.frames)?;
        let s = trial.max_stretch;
        trials.push(trial);
        if s <= bound && s >= CLOSE * bound {
            let taken = trials.len() - 1;
            return Ok((trials, taken));
        }
        let predicted = if s.is_finite() && s > 0.0 {
            k * s / (AIM * bound)
        } else if s == 0.0 {
            k / 4.0
        } else {
            k * 4.0
        };
        // The softest that passed and the stiffest that failed.
        let passed = trials
            .iter()
            .filter(|t| t.max_stretch <= bound)
            .map(|t| t.stiffness)
            .fold(f64::INFINITY, f64::min);
        let failed = trials
            .iter()
            .filter(|t| t.max_stretch > bound || t.max_stretch.is_nan())
            .map(|t| t.stiffness)
            .fold(0.0f64, f64::max);
        k = if passed.is_finite() && failed > 0.0 {
            if passed / failed <= BRACKET {
                break;
            }
            if predicted > failed && predicted < passed {
                predicted
            } else {
                (passed * failed).sqrt()
            }
        } else {
            predicted
        };
    }
    let softest = trials
        .iter()
        .enumerate()
        .filter(|(_, t)| t.max_stretch <= bound)
        .min_by(|a, b| a.1.stiffness.total_cmp(&b.1.stiffness))
        .map(|(i, _)| i);
    match (softest, trials.last()) {
        (Some(i), _) => Ok((trials, i)),
        (None, Some(last)) => Err(EqualStretchError::NotFound {
            trials: trials.len(),
            bound,
            last_k: last.stiffness,
            last_stretch: last.max_stretch,
        }),
        (None, None) => Err(EqualStretchError::Setting {
            field: "max_trials",
            message: "must be at least 1".into(),
        }),
    }
}

/// How a row's stretch was sampled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sampled {
    /// At every step (the springs: the search's trial at the stiffness
    /// taken).
    EveryStep,
    /// At every frame (RATTLE, which solves its constraints to round-off at
    /// every step).
    EveryFrame,
}

/// One model of the comparison, run and timed.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// What was run, in words (`springs, 1 thread`, `RATTLE, no bending`).
    pub model: String,
    /// The method's id.
    pub method: &'static str,
    /// The springs' stiffness (N per unit strain); `None` for RATTLE.
    pub stiffness: Option<f64>,
    /// The isometric bending rigidity `B` (N·m; 0: none).
    pub bending: f64,
    /// Threads of the stepping.
    pub threads: usize,
    /// The timed run (its `max_stretch` sampled at the frames).
    pub run: Measured,
    /// The largest warp and weft stretch, sampled as [`Row::sampled`]
    /// says.
    pub max_stretch: f64,
    pub sampled: Sampled,
}

/// The study: the trials of the search, the one taken, and the rows.
#[derive(Clone, Debug, PartialEq)]
pub struct EqualStretch {
    /// The grid and the span simulated (s).
    pub grid: (usize, usize),
    pub frames: usize,
    pub duration: f64,
    pub max_stretch: f64,
    pub trials: Vec<Trial>,
    /// Index into `trials` of the stiffness taken.
    pub taken: usize,
    /// Springs on one thread, springs banded (where the grid is), RATTLE
    /// without bending, RATTLE with the scene's bending (where it has
    /// some).
    pub rows: Vec<Row>,
    /// The warp and weft rest lengths `(dx, dy)` (m): the springs'
    /// constant as a linear spring is `k/dx`, `k/dy` (N/m).
    pub rest: (f64, f64),
}

/// Whether the study can be made of `scene` with `settings`, before
/// anything runs: an inextensible scene with gravity, at least one frame,
/// a bound in (0, 1), at least one trial.
pub fn check(scene: &Scene, settings: &EqualStretchSettings) -> Result<(), EqualStretchError> {
    if !scene.material.inextensible {
        return Err(EqualStretchError::NotInextensible);
    }
    if scene.gravity.iter().all(|g| *g == 0.0) {
        return Err(EqualStretchError::NoGravity);
    }
    if settings.frames == 0 {
        return Err(EqualStretchError::Setting {
            field: "frames",
            message: "must be at least 1: the study measures a run".into(),
        });
    }
    if !(settings.max_stretch > 0.0 && settings.max_stretch < 1.0) {
        return Err(EqualStretchError::Setting {
            field: "max_stretch",
            message: format!("must be in (0, 1) (got {})", settings.max_stretch),
        });
    }
    if settings.max_trials == 0 {
        return Err(EqualStretchError::Setting {
            field: "max_trials",
            message: "must be at least 1".into(),
        });
    }
    Ok(())
}

/// The whole study of `scene` (inextensible, with gravity; [`check`]).
pub fn study(
    scene: &Scene,
    settings: &EqualStretchSettings,
) -> Result<EqualStretch, EqualStretchError> {
    check(scene, settings)?;
    let (trials, taken) = search_stiffness(scene, settings)?;
    let chosen = &trials[taken];
    let k = chosen.stiffness;
    let rate = scene.simulation.frame_rate;
    let mut rows = Vec::new();

    // The springs, timed at 60 Hz frames: one thread, then banded.
    let twin = spring_twin(scene, k)?;
    let springs = spring_method()?;
    let twin_model = Simulation::new(&twin)?.model;
    let options = RunOptions {
        frames: settings.frames,
        substeps: chosen.substeps,
        frame_rate: rate,
    };
    let mut bandings = vec![(Banding::Off, 1)];
    if let Some(bands) = Banding::Auto.bands(&twin_model) {
        bandings.push((Banding::Auto, bands));
    }
    for (banding, threads) in bandings {
        let model = if threads == 1 {
            "springs, 1 thread".to_string()
        } else {
            format!("springs, {threads} threads (banded)")
        };
        let run = measure(
            &model,
            &twin,
            &springs,
            &RunSettings::new(options).with_banding(banding),
        )?;
        rows.push(Row {
            model,
            method: springs.id(),
            stiffness: Some(k),
            bending: 0.0,
            threads,
            max_stretch: chosen.max_stretch,
            sampled: Sampled::EveryStep,
            run,
        });
    }

    // RATTLE: the same sheet without bending, then as the scene has it.
    let rattle = Method::parse(RATTLE).map_err(|e| EqualStretchError::Run {
        model: "RATTLE".into(),
        source: Box::new(e.into()),
    })?;
    let mut bendings = vec![0.0];
    if scene.material.bending > 0.0 {
        bendings.push(scene.material.bending);
    }
    for bending in bendings {
        let mut constrained = scene.clone();
        constrained.material.bending = bending;
        constrained.simulation.method = RATTLE.to_string();
        let model_name = if bending == 0.0 {
            "RATTLE, no bending".to_string()
        } else {
            format!("RATTLE, bending {bending:e} N·m")
        };
        let sim = Simulation::new(&constrained)?;
        let substeps = if constrained.simulation.auto_substeps {
            auto_step(&sim.model, rate).substeps
        } else {
            constrained.simulation.substeps
        };
        let options = RunOptions {
            frames: settings.frames,
            substeps,
            frame_rate: rate,
        };
        let run_settings = RunSettings::new(options).with_variable(constrained.simulation.variable);
        let run = measure(&model_name, &constrained, &rattle, &run_settings)?;
        rows.push(Row {
            model: model_name,
            method: rattle.id(),
            stiffness: None,
            bending,
            threads: 1,
            max_stretch: run.max_stretch,
            sampled: Sampled::EveryFrame,
            run,
        });
    }
    let edges = WarpWeft::of(scene);
    Ok(EqualStretch {
        grid: (scene.cloth.nx, scene.cloth.ny),
        frames: settings.frames,
        duration: settings.frames as f64 / rate,
        max_stretch: settings.max_stretch,
        trials,
        taken,
        rows,
        rest: (edges.dx, edges.dy),
    })
}
