//! The paper's figure 5 as data: the undamped cloth of its section 5 (a
//! horizontal rectangle pinned along one edge, 13.78 g/m², stiffness 50.75)
//! at 60 Hz frames, explicit Euler against symplectic Euler, with
//! Störmer–Verlet, implicit Euler and Gauss–Legendre 2 for contrast, and the
//! midpoint family and the average vector field solved as energy
//! minimisation at one step per frame; plus `2/ω_max` of the same cloth over
//! grid resolutions; and RATTLE on the same sheet made inextensible
//! ([`paper_scene_inextensible`]). Each run stops at the first frame whose relative energy
//! error passes the [`EnergyGuard`]'s default limit, or at a failed solve,
//! and records where. `symlab paper` formats and plots what [`experiment`]
//! returns.

use crate::checkpoint::{CheckpointError, Decoder, Encoder, decode_frame, encode_frame};
use crate::study::energy::{reference_energy_or_unit, relative_errors};
use crate::{
    AVERAGE_VECTOR_FIELD, EnergyGuard, FrameStats, Method, RunError, RunOptions, RunSettings,
    Scene, SceneError, Simulation, SolverStats, Vec3,
};

/// A run has blown up once `|H − H₀|/E_ref` passes this: the energy
/// guard's default limit.
pub const BLOWUP: f64 = EnergyGuard::DEFAULT_LIMIT;

/// The paper scene, as shipped (compiled in, so `symlab paper` does not
/// depend on the working directory).
pub const SCENE_TOML: &str = include_str!("../../../scenes/paper.toml");

/// Frames simulated by default: 5 s at 60 Hz.
pub const DEFAULT_FRAMES: usize = 300;

/// Steps per frame of the implicit methods in the substepped setting: the
/// fewest (a power of two) at which both stage solves converged over the
/// first second when this was measured (at 4 and 8 Newton diverged within
/// half a second; the report shows what this run met).
pub const IMPLICIT_SUBSTEPS: usize = 16;

/// Frames of the substepped implicit runs (at most): one second. Each
/// Gauss–Legendre step is a sparse Newton solve of 7 200 unknowns, about
/// 20 ms here, so a second at 16 steps per frame costs about 20 s.
pub const IMPLICIT_FRAMES: usize = 60;

/// Steps per frame of RATTLE on the inextensible sheet: its largest stable
/// step on the 25² sheet is about 1.2e-2 s, two per frame (docs/results/paper.md,
/// "Inextensible cloth"); four leave a margin.
pub const INEXTENSIBLE_SUBSTEPS: usize = 4;

/// The shear stiffness (N per unit strain) of the inextensible sheet: soft,
/// as in `scenes/paper64-inextensible.toml`. RATTLE steps the shear springs
/// explicitly, and the paper's 50.75 would set its step as the stretch
/// springs set the explicit methods'.
pub const INEXTENSIBLE_SHEAR: f64 = 0.002;

/// The paper scene with its warp and weft springs made length constraints
/// (`material.stretch = "inextensible"`), its shear softened to
/// [`INEXTENSIBLE_SHEAR`], stepped by `rattle`; released flat, as the
/// paper's sheet is.
pub fn paper_scene_inextensible() -> Result<Scene, SceneError> {
    let mut scene = paper_scene()?;
    scene.material.stretch = None;
    scene.material.inextensible = true;
    scene.material.shear = Some(INEXTENSIBLE_SHEAR);
    scene.simulation.method = "rattle".to_string();
    scene.simulation.substeps = INEXTENSIBLE_SUBSTEPS;
    Ok(scene)
}

/// One run of the comparison.
#[derive(Clone, Debug)]
pub struct ClothRun {
    /// Method id (as in `symlab list`).
    pub id: &'static str,
    /// The scheme's name.
    pub name: String,
    pub substeps: usize,
    /// Step size (s).
    pub h: f64,
    /// `h·ω_max` at rest.
    pub h_omega: f64,
    /// Frames recorded (the initial one first), up to the last good one.
    pub frames: Vec<FrameStats>,
    /// `None` when the run completed; otherwise why and where it stopped.
    pub stopped: Option<Stopped>,
    /// Seconds spent stepping.
    pub stepping_seconds: f64,
    /// Newton iterations per step (implicit methods).
    pub newton_per_step: Option<f64>,
    /// Positions of the last good frame, by particle id.
    pub last_positions: Vec<Vec3>,
    /// For an explicit run that blew up: the blow-up under way, replayed
    /// step by step — the last step whose strain is at most [`SHOW_STRAIN`]
    /// (step, time, `|H − H₀|/E_ref`, positions).
    pub blowing_up: Option<(usize, f64, f64, Vec<Vec3>)>,
}

/// The largest strain `|ℓ − L|/L` of the state shown for a run that blew
/// up. The unstable modes are stiff and in-plane: the cloth still looks
/// intact at 50 times E_ref, and a few steps later its coordinates are
/// astronomical; the last state whose springs are at most doubled shows
/// the blow-up and still fits a picture.
pub const SHOW_STRAIN: f64 = 1.0;

/// Replay an explicit run one step per frame up to `until` steps and keep
/// the last state with finite energy and strain at most [`SHOW_STRAIN`].
fn replay_blowup(
    scene: &Scene,
    method: &Method,
    opts: &RunOptions,
    until: usize,
    e_ref: f64,
) -> Option<(usize, f64, f64, Vec<Vec3>)> {
    let mut sim = Simulation::new(scene).ok()?;
    let h0 = sim.stats().energy.total();
    let replay = RunOptions {
        frames: until,
        substeps: 1,
        frame_rate: opts.frame_rate * opts.substeps as f64,
    };
    let mut shown = None;
    let _ = sim.run(method, &RunSettings::new(replay), |frame| {
        let rel = ((frame.stats.energy.total() - h0) / e_ref).abs();
        let strain = frame.stats.max_strain;
        if !rel.is_finite() || strain.is_nan() || strain > SHOW_STRAIN {
            return Err("past the threshold".into());
        }
        shown = Some((frame.stats.step, frame.stats.time, rel, frame.positions()));
        Ok(())
    });
    shown
}

impl ClothRun {
    /// The largest `|H − H₀|/E_ref` over the recorded frames.
    pub fn max_error(&self, e_ref: f64) -> f64 {
        relative_errors(&self.frames, e_ref)
            .into_iter()
            .fold(0.0, |m, e| m.max(e.abs()))
    }
    /// `(H − H₀)/E_ref` at the last recorded frame.
    pub fn final_error(&self, e_ref: f64) -> f64 {
        relative_errors(&self.frames, e_ref)
            .last()
            .copied()
            .unwrap_or(0.0)
    }
    /// Simulated time of the last good frame (s).
    pub fn end_time(&self) -> f64 {
        self.frames.last().map_or(0.0, |f| f.time)
    }
}

/// `2/ω_max` of the paper's cloth at one resolution.
#[derive(Clone, Copy, Debug)]
pub struct GridLimit {
    pub n: usize,
    pub particle_mass: f64,
    pub omega_max: f64,
    pub h_max: f64,
}

/// The whole comparison.
#[derive(Clone, Debug)]
pub struct ClothExperiment {
    pub scene: Scene,
    pub frames: usize,
    pub e_ref: f64,
    pub omega_max: f64,
    pub h_max: f64,
    pub runs: Vec<ClothRun>,
    pub grids: Vec<GridLimit>,
}

/// The paper scene, parsed.
pub fn paper_scene() -> Result<Scene, SceneError> {
    Scene::from_toml(SCENE_TOML, "scenes/paper.toml")
}

/// Run one method at `substeps` steps per frame for `frames` frames.
fn run_one(
    scene: &Scene,
    id: &'static str,
    substeps: usize,
    frames: usize,
    e_ref: f64,
    omega_max: f64,
) -> Result<ClothRun, RunError> {
    let mut sim = Simulation::new(scene)?;
    let opts = RunOptions {
        frames,
        substeps,
        frame_rate: scene.simulation.frame_rate,
    };
    let method = Method::parse(id)?;
    let mut recorded: Vec<FrameStats> = Vec::new();
    let mut last_positions = sim.model.positions(&sim.state[..sim.state.len() / 2]);
    // The guard places a blow-up at its frame: the report says between
    // which steps (at one step per frame, the step itself).
    let settings = RunSettings::new(opts).with_guard(EnergyGuard::new(e_ref).without_replay());
    let result = sim.run(&method, &settings, |frame| {
        recorded.push(frame.stats);
        last_positions = frame.positions();
        Ok(())
    });
    let name = method.name().to_string();
    let mut blown_at = None;
    let (stopped, stepping_seconds, newton_per_step) = match result {
        Ok(report) => (
            None,
            report.stepping_seconds,
            match report.solver {
                SolverStats::Stage(s) => Some(s.newton_iterations as f64 / s.steps.max(1) as f64),
                SolverStats::Minimise(s, _) => Some(s.iterations_per_step()),
                SolverStats::Constrained(s) => Some(s.iterations_per_step()),
                SolverStats::None => None,
            },
        ),
        Err(RunError::Blowup(b)) => {
            blown_at = Some(b.step);
            let stop = Stop::Blowup {
                step: b.step,
                last_good_step: recorded.last().map_or(0, |f| f.step),
                frame: b.frame,
                time: b.time,
                relative_error: b.relative_error,
                substeps,
            };
            (Some(Stopped(stop)), f64::NAN, None)
        }
        Err(RunError::Diverged { step, time, .. }) => (
            Some(Stopped(Stop::NonFinite { step, time })),
            f64::NAN,
            None,
        ),
        Err(RunError::Solve {
            step, time, source, ..
        }) => {
            let why = source.to_string();
            (
                Some(Stopped(Stop::Stage { step, time, why })),
                f64::NAN,
                None,
            )
        }
        Err(RunError::Minimise {
            step, time, source, ..
        }) => {
            let why = source.to_string();
            (
                Some(Stopped(Stop::Minimise { step, time, why })),
                f64::NAN,
                None,
            )
        }
        Err(RunError::Constraint {
            step, time, source, ..
        }) => {
            let why = source.to_string();
            (
                Some(Stopped(Stop::Constraint { step, time, why })),
                f64::NAN,
                None,
            )
        }
        Err(other) => return Err(other),
    };
    let h = opts.step_size();
    let blowing_up = match (&stopped, blown_at) {
        (Some(_), Some(step)) if method.explicit() => {
            replay_blowup(scene, &method, &opts, step, e_ref)
        }
        _ => None,
    };
    Ok(ClothRun {
        id,
        name,
        substeps,
        h,
        h_omega: h * omega_max,
        frames: recorded,
        stopped,
        stepping_seconds,
        newton_per_step,
        last_positions,
        blowing_up,
    })
}

/// `2/ω_max` of the paper's cloth, pinned along its top edge, at `n × n`.
fn grid_limit(scene: &Scene, n: usize) -> Result<GridLimit, SceneError> {
    let mut s = scene.clone();
    s.cloth.nx = n;
    s.cloth.ny = n;
    s.pins = (0..n).map(|i| (i, 0)).collect();
    let sim = Simulation::new(&s)?;
    let st = sim.model.stability();
    Ok(GridLimit {
        n,
        particle_mass: sim.model.particle_mass(),
        omega_max: st.omega_max,
        h_max: st.h_max,
    })
}

/// The runs of the comparison in order, `(method id, steps per frame)`,
/// for the paper scene whose explicit runs take `explicit_substeps` steps
/// per frame in the substepped setting; RATTLE on the inextensible sheet
/// ([`INEXTENSIBLE_SUBSTEPS`]) is the last.
fn plan(explicit_substeps: usize) -> [(&'static str, usize); 15] {
    [
        ("euler", 1),
        ("symplectic-euler-a", 1),
        ("stormer-verlet", 1),
        ("implicit-euler", 1),
        ("gauss2", 1),
        // The midpoint family as energy minimisation (cloth::step::minimise).
        ("midpoint", 1),
        ("paper-dirk2", 1),
        ("paper-dirk4", 1),
        // Energy-conserving (not symplectic), the same minimisation machinery.
        (AVERAGE_VECTOR_FIELD, 1),
        ("euler", explicit_substeps),
        ("symplectic-euler-a", explicit_substeps),
        ("stormer-verlet", explicit_substeps),
        ("implicit-euler", IMPLICIT_SUBSTEPS),
        ("gauss2", IMPLICIT_SUBSTEPS),
        ("rattle", INEXTENSIBLE_SUBSTEPS),
    ]
}

/// The number of runs of the comparison ([`experiment_from`] stops between
/// them).
pub const RUNS: usize = 15;

/// Run the comparison: `frames` frames of each setting.
pub fn experiment(frames: usize) -> Result<ClothExperiment, RunError> {
    let done = experiment_from(frames, Vec::new(), |_| true)?;
    Ok(done.expect("a comparison that is never stopped completes"))
}

/// The comparison continued from the runs already `done` (a prefix of the
/// plan, as a checkpoint kept them: [`encode_run`]), asking `go_on` after
/// each new run with every run so far whether to go on. `None` when it
/// said no before the last run; each run is the same computation whether
/// or not the comparison was stopped before it, so a resumed comparison
/// has the same runs (apart from their wall times).
pub fn experiment_from(
    frames: usize,
    done: Vec<ClothRun>,
    mut go_on: impl FnMut(&[ClothRun]) -> bool,
) -> Result<Option<ClothExperiment>, RunError> {
    let scene = paper_scene()?;
    let sim = Simulation::new(&scene)?;
    let e_ref = reference_energy_or_unit(&scene, &sim);
    let stab = sim.model.stability();
    // The same sheet inextensible, stepped by RATTLE; its h·ω_max is that
    // of its own soft springs, and E_ref the paper scene's (the same mass,
    // gravity and size).
    let inextensible = paper_scene_inextensible()?;
    let omega_inextensible = Simulation::new(&inextensible)?.model.stability().omega_max;
    let plan = plan(scene.simulation.substeps);
    let mut runs = done;
    runs.truncate(plan.len());
    for &(id, k) in &plan[runs.len()..] {
        let run = if id == "rattle" {
            run_one(&inextensible, id, k, frames, e_ref, omega_inextensible)?
        } else {
            let n = if !Method::parse(id)?.explicit() && k > 1 {
                frames.min(IMPLICIT_FRAMES)
            } else {
                frames
            };
            run_one(&scene, id, k, n, e_ref, stab.omega_max)?
        };
        runs.push(run);
        if runs.len() < plan.len() && !go_on(&runs) {
            return Ok(None);
        }
    }
    let mut grids = Vec::new();
    for n in [2, 3, 5, 9, 17, 25] {
        grids.push(grid_limit(&scene, n)?);
    }
    Ok(Some(ClothExperiment {
        scene,
        frames,
        e_ref,
        omega_max: stab.omega_max,
        h_max: stab.h_max,
        runs,
        grids,
    }))
}

/// A finished run into a checkpoint's payload (every field, the doubles'
/// bits exactly).
pub fn encode_run(e: &mut Encoder, r: &ClothRun) {
    e.str(r.id)
        .str(&r.name)
        .usize(r.substeps)
        .f64(r.h)
        .f64(r.h_omega)
        .usize(r.frames.len());
    for f in &r.frames {
        encode_frame(e, f);
    }
    match r.stopped.as_ref().map(|s| &s.0) {
        None => e.u64(0),
        Some(Stop::Blowup {
            step,
            last_good_step,
            frame,
            time,
            relative_error,
            substeps,
        }) => e
            .u64(1)
            .usize(*step)
            .usize(*last_good_step)
            .usize(*frame)
            .f64(*time)
            .f64(*relative_error)
            .usize(*substeps),
        Some(Stop::NonFinite { step, time }) => e.u64(2).usize(*step).f64(*time),
        Some(Stop::Stage { step, time, why }) => e.u64(3).usize(*step).f64(*time).str(why),
        Some(Stop::Minimise { step, time, why }) => e.u64(4).usize(*step).f64(*time).str(why),
        Some(Stop::Constraint { step, time, why }) => e.u64(5).usize(*step).f64(*time).str(why),
    };
    e.f64(r.stepping_seconds).bool(r.newton_per_step.is_some());
    if let Some(x) = r.newton_per_step {
        e.f64(x);
    }
    encode_positions(e, &r.last_positions);
    e.bool(r.blowing_up.is_some());
    if let Some((step, time, rel, positions)) = &r.blowing_up {
        e.usize(*step).f64(*time).f64(*rel);
        encode_positions(e, positions);
    }
}

/// A run as [`encode_run`] wrote it; its method must be one of the plan's
/// (a checkpoint of another comparison is refused, naming the id).
pub fn decode_run(d: &mut Decoder<'_>) -> Result<ClothRun, CheckpointError> {
    let id_text = d.str("method id")?;
    let Some(id) = plan(1).iter().map(|(id, _)| *id).find(|id| *id == id_text) else {
        return Err(d.error(format!(
            "method id '{id_text}' is not a run of the figure-5 comparison"
        )));
    };
    let name = d.str("method name")?.to_string();
    let substeps = d.usize("substeps")?;
    let h = d.f64("h")?;
    let h_omega = d.f64("h_omega")?;
    let n = d.usize("frames")?;
    // Each frame takes 12 fields: a count beyond the bytes left is refused
    // by the reads, and the vector grows only as frames are read.
    let mut frames = Vec::new();
    for _ in 0..n {
        frames.push(decode_frame(d)?);
    }
    let stopped = match d.u64("stop")? {
        0 => None,
        1 => Some(Stop::Blowup {
            step: d.usize("step")?,
            last_good_step: d.usize("last_good_step")?,
            frame: d.usize("frame")?,
            time: d.f64("time")?,
            relative_error: d.f64("relative_error")?,
            substeps: d.usize("substeps")?,
        }),
        2 => Some(Stop::NonFinite {
            step: d.usize("step")?,
            time: d.f64("time")?,
        }),
        k @ 3..=5 => {
            let (step, time, why) = (d.usize("step")?, d.f64("time")?, d.str("why")?.to_string());
            Some(match k {
                3 => Stop::Stage { step, time, why },
                4 => Stop::Minimise { step, time, why },
                _ => Stop::Constraint { step, time, why },
            })
        }
        k => return Err(d.error(format!("unknown stop kind {k}"))),
    }
    .map(Stopped);
    let stepping_seconds = d.f64("stepping_seconds")?;
    let newton_per_step = if d.bool("newton_per_step")? {
        Some(d.f64("newton_per_step")?)
    } else {
        None
    };
    let last_positions = decode_positions(d)?;
    let blowing_up = if d.bool("blowing_up")? {
        Some((
            d.usize("step")?,
            d.f64("time")?,
            d.f64("relative_error")?,
            decode_positions(d)?,
        ))
    } else {
        None
    };
    Ok(ClothRun {
        id,
        name,
        substeps,
        h,
        h_omega,
        frames,
        stopped,
        stepping_seconds,
        newton_per_step,
        last_positions,
        blowing_up,
    })
}

fn encode_positions(e: &mut Encoder, xs: &[Vec3]) {
    let flat: Vec<f64> = xs.iter().flat_map(|x| [x.x, x.y, x.z]).collect();
    e.f64s(&flat);
}

fn decode_positions(d: &mut Decoder<'_>) -> Result<Vec<Vec3>, CheckpointError> {
    let flat = d.f64s("positions")?;
    if flat.len() % 3 != 0 {
        return Err(d.error(format!(
            "positions: {} numbers, not a multiple of 3",
            flat.len()
        )));
    }
    Ok(flat
        .chunks_exact(3)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect())
}

/// Why a run of the experiment stopped before its end, as data; its
/// `Display` is the sentence the report prints.
#[derive(Clone, Debug, PartialEq)]
pub struct Stopped(pub Stop);

/// The ways a run of the experiment stops early.
#[derive(Clone, Debug, PartialEq)]
pub enum Stop {
    /// The energy guard fired (or the energy stopped being finite) at
    /// `step`; `last_good_step` is the step of the last recorded frame.
    Blowup {
        step: usize,
        last_good_step: usize,
        frame: usize,
        time: f64,
        relative_error: f64,
        substeps: usize,
    },
    /// The state stopped being finite at `step`.
    NonFinite { step: usize, time: f64 },
    /// The stage solver failed at `step`.
    Stage { step: usize, time: f64, why: String },
    /// The minimisation failed at `step`.
    Minimise { step: usize, time: f64, why: String },
    /// RATTLE's constraint solve failed at `step`.
    Constraint { step: usize, time: f64, why: String },
}

impl std::fmt::Display for Stopped {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.0 {
            Stop::Blowup {
                step,
                last_good_step,
                frame,
                time,
                relative_error,
                substeps,
            } => {
                if *substeps == 1 {
                    write!(f, "blew up at step {step} (t = {time:.4} s): ")?;
                } else {
                    write!(
                        f,
                        "blew up between steps {last_good_step} and {step} (frame {frame}, t = {time:.4} s): "
                    )?;
                }
                if relative_error.is_finite() {
                    write!(f, "|H − H₀|/E_ref = {relative_error:.2e} > {BLOWUP}")
                } else {
                    write!(f, "the energy is no longer finite")
                }
            }
            Stop::NonFinite { step, time } => write!(
                f,
                "blew up at step {step} (t = {time:.4} s): a non-finite state"
            ),
            Stop::Stage { step, time, why } => write!(
                f,
                "stage solver failed at step {step} (t = {time:.4} s): {why}"
            ),
            Stop::Minimise { step, time, why } => write!(
                f,
                "minimisation failed at step {step} (t = {time:.4} s): {why}"
            ),
            Stop::Constraint { step, time, why } => write!(
                f,
                "constraint solve failed at step {step} (t = {time:.4} s): {why}"
            ),
        }
    }
}
