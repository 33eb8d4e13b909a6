//! Running a scene: the one frame loop. Every method steps through it —
//! an explicit scheme, the stage solver, a minimisation, the discrete
//! gradient ([`crate::step`]) — with the same substeps per frame, the same
//! callback per frame, the same statistics, one non-finite check after
//! every step, and one optional energy guard after every frame that, when
//! the energy error passes its limit, replays the frame one step at a time
//! to find the step ([`Blowup`]).
//!
//! ```
//! use cloth::{EnergyGuard, Method, RunError, RunOptions, RunSettings, Scene, Simulation};
//!
//! let scene = Scene::from_toml(r#"
//!     gravity = [0.0, -9.81, 0.0]
//!     [cloth]
//!     width = 1.0
//!     height = 1.0
//!     nx = 5
//!     ny = 5
//!     [material]
//!     density = 0.1
//!     stretch = 50.0
//!     [pins]
//!     edges = ["top"]
//!     [simulation]
//!     substeps = 1
//!     frames = 40
//!     method = "euler"
//! "#, "inline.toml")?;
//! let mut sim = Simulation::new(&scene)?;
//! // Explicit Euler far beyond its stability limit, guarded: the run stops
//! // once |H − H₀|/E_ref passes 100, and the replay names the step.
//! let settings = RunSettings::from_scene(&scene).with_guard(EnergyGuard::new(1.0));
//! match sim.run(&Method::parse("euler")?, &settings, |_| Ok(())) {
//!     Err(RunError::Blowup(b)) => {
//!         assert!(b.relative_error > 100.0 || b.relative_error.is_nan());
//!         assert_eq!(sim.frame, b.last_good.frame); // left at the last good frame
//!     }
//!     other => panic!("expected a blow-up, got {other:?}"),
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::time::Instant;

use integrator_core::{Scheme, SolveError, Step};
use nalgebra::Vector3;

use crate::checkpoint::{Action, Decoder, Encoder, NoControl, RunControl, RunState};
pub use crate::frame::{CallbackError, FrameStats};
use crate::method::{Mechanism, Method, MethodError};
use crate::model::ClothModel;
use crate::scene::{Scene, SceneError};
use crate::step::dispatch::{SchemeVisitor, TableVisitor, with_scheme, with_table};
use crate::step::minimise::MinimiseError;
use crate::step::rattle::RattleError;
use crate::step::variable::{Attempt, Controller, Next};
use crate::step::{
    BandedStepper, Banding, ClothStepper, Halt, Halted, MARK_KEPT, MARK_START, MinimiseSettings,
    MinimiseStepper, RattleSettings, RattleStepper, Refused, SchemeStepper, SolverStats,
    StageSettings, StageStepper, StepError, VariableStats, VariableStep, sequence_of,
};

/// Frames, substeps and frame rate of a run (from the scene, or overridden).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunOptions {
    /// Frames after the initial one.
    pub frames: usize,
    /// Steps per frame.
    pub substeps: usize,
    /// Frames per second (Hz).
    pub frame_rate: f64,
}

impl RunOptions {
    pub fn from_scene(scene: &Scene) -> RunOptions {
        RunOptions {
            frames: scene.simulation.frames,
            substeps: scene.simulation.substeps,
            frame_rate: scene.simulation.frame_rate,
        }
    }
    /// The step size `1/(frame_rate·substeps)` (s).
    pub fn step_size(&self) -> f64 {
        1.0 / (self.frame_rate * self.substeps as f64)
    }

    /// Whether these options make a run that can mean something and ends:
    /// at least one step per frame, at most [`MAX_FRAMES`](crate::MAX_FRAMES)
    /// frames and [`MAX_STEPS`](crate::MAX_STEPS) steps in all, and a step
    /// that is a positive normal number (see
    /// [`run_length_problem`](crate::scene::run_length_problem)). Every run
    /// checks this before it builds anything.
    pub fn check(&self) -> Result<(), RunError> {
        match crate::scene::run_length_problem(self.frames, self.substeps, self.frame_rate) {
            None => Ok(()),
            Some((what, message)) => Err(RunError::Options(format!("{what}: {message}"))),
        }
    }
}

/// A frame as the callback sees it.
pub struct Frame<'a> {
    pub stats: FrameStats,
    pub model: &'a ClothModel,
    /// The state `z = [q; p]` of the free particles.
    pub state: &'a [f64],
}

impl Frame<'_> {
    /// Positions of the free particles (the first half of the state).
    pub fn q(&self) -> &[f64] {
        &self.state[..self.state.len() / 2]
    }
    /// Momenta of the free particles.
    pub fn p(&self) -> &[f64] {
        &self.state[self.state.len() / 2..]
    }
    /// Positions of all particles, by particle id `j·nx + i` (pinned included).
    pub fn positions(&self) -> Vec<Vector3<f64>> {
        self.model.positions(self.q())
    }
}

/// The solvers' settings of a run, with the defaults a scene gets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverSettings {
    /// The minimisation solver's (the midpoint family, `avf`,
    /// `discrete-gradient`): Newton at `1e-12` by default.
    pub minimise: MinimiseSettings,
    /// The sparse stage solver's: [`crate::step::stage::cloth_settings`] by
    /// default.
    pub stage: StageSettings,
    /// RATTLE's constraint solver (`rattle`, inextensible scenes).
    pub rattle: RattleSettings,
    /// Which explicit drift–kick runs step in bands of rows on two threads
    /// ([`crate::step::banded`]; by default those on large enough grids).
    pub banding: Banding,
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            minimise: MinimiseSettings::default(),
            stage: crate::step::stage::cloth_settings(),
            rattle: RattleSettings::default(),
            banding: Banding::default(),
        }
    }
}

/// Everything a run is asked to do besides the method: its length, the
/// solvers' settings, the variable step and an optional energy guard.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSettings {
    pub options: RunOptions,
    pub solvers: SolverSettings,
    /// Stop once `|H − H₀|/E_ref` passes a limit (none by default).
    pub guard: Option<EnergyGuard>,
    /// RATTLE's reversible variable step ([`crate::step::variable`]): each
    /// frame takes the fewest steps, at least
    /// [`options.substeps`](RunOptions::substeps) (and 2), whose interior
    /// transverse-wave numbers stay at or below the target, as `h·ω ∝ 1/N`
    /// from the counts integrated. `None` (the
    /// default of [`RunSettings::new`]): `options.substeps` steps every
    /// frame. [`RunSettings::from_scene`] takes the scene's
    /// `simulation.step`. Only a RATTLE run can take it.
    pub variable: Option<VariableStep>,
}

impl RunSettings {
    /// `options` with the default solvers and no guard.
    pub fn new(options: RunOptions) -> RunSettings {
        RunSettings {
            options,
            solvers: SolverSettings::default(),
            guard: None,
            variable: None,
        }
    }
    /// The scene's frames, substeps, frame rate and step
    /// (`simulation.step`: the variable step by default on an
    /// inextensible scene), with the default solvers.
    pub fn from_scene(scene: &Scene) -> RunSettings {
        RunSettings::new(RunOptions::from_scene(scene)).with_variable(scene.simulation.variable)
    }
    /// The variable step, or `None` for the fixed one.
    pub fn with_variable(mut self, variable: Option<VariableStep>) -> RunSettings {
        self.variable = variable;
        self
    }
    pub fn with_guard(mut self, guard: EnergyGuard) -> RunSettings {
        self.guard = Some(guard);
        self
    }
    pub fn with_minimise(mut self, minimise: MinimiseSettings) -> RunSettings {
        self.solvers.minimise = minimise;
        self
    }
    pub fn with_stage(mut self, stage: StageSettings) -> RunSettings {
        self.solvers.stage = stage;
        self
    }
    pub fn with_rattle(mut self, rattle: RattleSettings) -> RunSettings {
        self.solvers.rattle = rattle;
        self
    }
    pub fn with_banding(mut self, banding: Banding) -> RunSettings {
        self.solvers.banding = banding;
        self
    }
}

impl From<RunOptions> for RunSettings {
    fn from(options: RunOptions) -> RunSettings {
        RunSettings::new(options)
    }
}

/// A run has blown up once `|H − H₀|/E_ref` exceeds the limit or is not a
/// number (`H₀` the energy at the start of the run). The default limit,
/// [`EnergyGuard::DEFAULT_LIMIT`] = 100: the cloth holds a hundred times
/// the energy of its own fall (with `E_ref` from
/// [`study::energy::reference_energy`](crate::study::energy::reference_energy)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyGuard {
    /// The energy scale `E_ref` (J).
    pub e_ref: f64,
    /// The largest `|H − H₀|/E_ref` a good frame may show.
    pub limit: f64,
    /// Replay the frame that passed the limit one step at a time to find
    /// the step ([`Located::Step`]); off, the blow-up is placed at the
    /// frame ([`Located::Frame`]), which costs nothing more.
    pub locate: bool,
}

impl EnergyGuard {
    /// The default limit of `|H − H₀|/E_ref`.
    pub const DEFAULT_LIMIT: f64 = 100.0;

    /// The default limit, replaying to find the step.
    pub fn new(e_ref: f64) -> EnergyGuard {
        EnergyGuard {
            e_ref,
            limit: EnergyGuard::DEFAULT_LIMIT,
            locate: true,
        }
    }
    pub fn with_limit(self, limit: f64) -> EnergyGuard {
        EnergyGuard { limit, ..self }
    }
    pub fn without_replay(self) -> EnergyGuard {
        EnergyGuard {
            locate: false,
            ..self
        }
    }
    /// `|H − H₀|/E_ref`.
    pub fn relative_error(&self, energy: f64, h0: f64) -> f64 {
        ((energy - h0) / self.e_ref).abs()
    }
    /// Past the limit, or not a number (the energy is ∞ − ∞).
    pub fn exceeded(&self, relative_error: f64) -> bool {
        relative_error.is_nan() || relative_error > self.limit
    }
}

/// How the step of a [`Blowup`] was found.
#[derive(Debug)]
pub enum Located {
    /// Replaying the frame one step at a time: `step` is the first step
    /// past the limit.
    Step,
    /// Not replayed ([`EnergyGuard::locate`] off), or the replay stayed
    /// within the limit: `step` is the end of the frame that passed it.
    Frame,
    /// The replay stopped first, with this error (a non-finite state or a
    /// failed solve): it says where.
    Stopped(Box<RunError>),
}

/// Where and how a guarded run passed its energy limit. The simulation is
/// left at `last_good`.
#[derive(Debug)]
pub struct Blowup {
    /// The scheme's name.
    pub method: &'static str,
    /// The step found ([`Located`] says how) and its time (s).
    pub step: usize,
    pub time: f64,
    /// The frame that passed the limit.
    pub frame: usize,
    /// `|H − H₀|/E_ref` at `step` (NaN once the energy is not finite).
    pub relative_error: f64,
    pub limit: f64,
    /// The last frame within the limit.
    pub last_good: FrameStats,
    pub located: Located,
}

/// A relative energy error for a message: NaN (the energy is ∞ − ∞) said
/// in words.
fn show_relative(rel: f64) -> String {
    if rel.is_nan() {
        "not a number (the energy is no longer finite)".to_string()
    } else {
        format!("{rel:.3e}")
    }
}

impl std::fmt::Display for Blowup {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (method, rel, limit) = (self.method, show_relative(self.relative_error), self.limit);
        match &self.located {
            Located::Step => write!(
                f,
                "{method}: the cloth blew up at step {} (t = {} s, frame {}): |H − H₀|/E_ref = {rel} (limit {limit})",
                self.step, self.time, self.frame
            ),
            Located::Frame => write!(
                f,
                "{method}: the cloth blew up between step {} and step {} (t = {} s to {} s): |H − H₀|/E_ref = {rel} at frame {} (limit {limit})",
                self.last_good.step, self.step, self.last_good.time, self.time, self.frame
            ),
            Located::Stopped(err) => write!(f, "{err}"),
        }
    }
}

/// The outcome of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct RunReport {
    /// The scheme's name.
    pub method: &'static str,
    /// Step size (s); of a variable-step run, the largest (its floor's).
    pub h: f64,
    pub steps: usize,
    /// One entry per frame, the initial state first.
    pub frames: Vec<FrameStats>,
    /// Wall-clock time of the stepping alone, callbacks excluded (s).
    pub stepping_seconds: f64,
    /// What the solver did ([`SolverStats::None`] for an explicit run).
    pub solver: SolverStats,
    /// What the variable step did (`None` for a fixed step); boxed, so
    /// that a report stays small where it is moved about.
    pub variable: Option<Box<VariableStats>>,
}

/// Why a run stopped.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Method(#[from] MethodError),
    #[error("invalid run options: {0}")]
    Options(String),
    #[error(
        "{method}: the cloth blew up at step {step} (t = {time} s, frame {frame}): state component {index} = {value}{particle}",
        particle = particle.map(|(i, j)| format!(" (particle ({i}, {j}))")).unwrap_or_default()
    )]
    Diverged {
        method: &'static str,
        step: usize,
        time: f64,
        frame: usize,
        index: usize,
        value: f64,
        particle: Option<(usize, usize)>,
    },
    #[error("{method}: step {step} (t = {time} s) failed: {source}")]
    Solve {
        method: &'static str,
        step: usize,
        time: f64,
        #[source]
        source: SolveError,
    },
    #[error("{method}: step {step} (t = {time} s) failed: {source}")]
    Minimise {
        method: &'static str,
        step: usize,
        time: f64,
        #[source]
        source: MinimiseError,
    },
    #[error("{method}: step {step} (t = {time} s) failed: {source}")]
    Constraint {
        method: &'static str,
        step: usize,
        time: f64,
        #[source]
        source: RattleError,
    },
    /// The variable step found no count of steps per frame up to its cap
    /// that the frame accepts; the message names the scene's fields.
    #[error("{method}: frame {frame} (t = {time} s): {message}")]
    StepControl {
        method: &'static str,
        frame: usize,
        time: f64,
        message: String,
    },
    /// The energy guard stopped the run ([`RunSettings::guard`]).
    #[error("{0}")]
    Blowup(Box<Blowup>),
    /// The [`RunControl`] stopped the run after `frame` (with a checkpoint
    /// if it asked for one); the simulation is at that frame.
    #[error("stopped after frame {frame} (t = {time} s)")]
    Stopped { frame: usize, time: f64 },
    /// A saved [`RunState`] does not fit this run or its stepper.
    #[error("cannot continue the run: {0}")]
    Resume(String),
    #[error("frame {frame} (t = {time} s): {source}")]
    Callback {
        frame: usize,
        time: f64,
        #[source]
        source: CallbackError,
    },
}

impl From<Refused> for RunError {
    fn from(r: Refused) -> RunError {
        RunError::Options(r.0)
    }
}

impl RunError {
    /// Whether the cloth itself failed (a non-finite state, a failed
    /// solve, the energy guard), as opposed to bad input or a callback.
    pub fn is_blowup(&self) -> bool {
        matches!(
            self,
            RunError::Diverged { .. }
                | RunError::Solve { .. }
                | RunError::Minimise { .. }
                | RunError::Constraint { .. }
                | RunError::StepControl { .. }
                | RunError::Blowup(_)
        )
    }
}

/// The frame callback as the loop holds it: one dynamic call per frame.
type OnFrame<'f> = dyn FnMut(&Frame<'_>) -> Result<(), CallbackError> + 'f;

/// A cloth model with its current state.
#[derive(Clone, Debug)]
pub struct Simulation {
    pub model: ClothModel,
    /// `z = [q; p]` of the free particles.
    pub state: Vec<f64>,
    pub time: f64,
    /// Steps taken so far.
    pub steps: usize,
    /// Frames completed so far (the initial state is frame 0).
    pub frame: usize,
}

impl Simulation {
    /// The scene's model at its initial state.
    pub fn new(scene: &Scene) -> Result<Simulation, SceneError> {
        let model = ClothModel::new(scene)?;
        let state = model.initial_state();
        Ok(Simulation {
            model,
            state,
            time: 0.0,
            steps: 0,
            frame: 0,
        })
    }

    /// The statistics of the current state.
    pub fn stats(&self) -> FrameStats {
        let n = self.model.free_count() * 3;
        FrameStats {
            frame: self.frame,
            step: self.steps,
            time: self.time,
            energy: self.model.energy(&self.state),
            momentum: self.model.momentum(&self.state[n..]),
            max_strain: self.model.max_strain(&self.state[..n]),
        }
    }

    /// Run `settings.options.frames` frames of `substeps` steps of
    /// `method`, each through its mechanism, calling `on_frame` with the
    /// current frame first (when the simulation is fresh, the initial
    /// state) and after every frame. Checks for non-finite values after
    /// every step and stops at the first with [`RunError::Diverged`]; a
    /// failed solve stops with [`RunError::Solve`] or
    /// [`RunError::Minimise`]; the guard, if any, with
    /// [`RunError::Blowup`]. Each names the step, time and method, and the
    /// state is then left as it was at the end of the last good frame.
    pub fn run<F>(
        &mut self,
        method: &Method,
        settings: &RunSettings,
        on_frame: F,
    ) -> Result<RunReport, RunError>
    where
        F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
    {
        self.run_controlled(method, settings, None, &mut NoControl, on_frame)
    }

    /// [`run`](Self::run), asking `control` after every frame whether to
    /// save a [`RunState`] or to stop ([`RunError::Stopped`]), and, with
    /// `resume`, continuing the run that state was saved from instead of
    /// starting one: the simulation, the stepper's carried data, the
    /// frames so far and the energy origin are restored, the frames
    /// already done are not emitted again, and the run ends with the bits,
    /// frames and solver statistics of the run that was never stopped.
    /// `settings` must be that run's (the step size is checked).
    pub fn run_controlled<F>(
        &mut self,
        method: &Method,
        settings: &RunSettings,
        resume: Option<&RunState>,
        control: &mut dyn RunControl,
        mut on_frame: F,
    ) -> Result<RunReport, RunError>
    where
        F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
    {
        settings.options.check()?;
        if let Some(why) = crate::scene::method_mismatch(method, self.model.is_inextensible()) {
            return Err(RunError::Options(format!("method: {why}")));
        }
        if settings.variable.is_some() && method.mechanism() != Mechanism::Constrained {
            return Err(RunError::Options(format!(
                "simulation.step: the variable step is RATTLE's (an inextensible scene); {} takes a fixed step (step = \"fixed\")",
                method.id()
            )));
        }
        let on_frame: &mut OnFrame<'_> = &mut on_frame;
        let name = method.name();
        /// The run with the method's scheme or table, once the dispatch
        /// ([`with_scheme`], [`with_table`]) has found its type.
        struct Drive<'a, 'f> {
            /// The method's id.
            id: &'a str,
            sim: &'a mut Simulation,
            settings: &'a RunSettings,
            on_frame: &'a mut OnFrame<'f>,
            resume: Option<&'a RunState>,
            control: &'a mut dyn RunControl,
        }
        match method.mechanism() {
            Mechanism::Explicit => {
                impl SchemeVisitor for Drive<'_, '_> {
                    type Output = Result<RunReport, RunError>;
                    fn visit<S: Step<ClothModel> + Scheme>(self, scheme: S) -> Self::Output {
                        // Only explicit schemes come here; the branch keeps
                        // the implicit tables' own steps out of the binary.
                        let banded = self.settings.solvers.banding.bands(&self.sim.model);
                        let sequence = banded.and_then(|_| sequence_of(self.id));
                        if let (Some(bands), Some(seq)) = (banded, sequence) {
                            self.sim.drive(
                                S::INFO.name,
                                &|sim: &Simulation| {
                                    Ok(BandedStepper::new(seq.clone(), &sim.model, bands))
                                },
                                self.settings,
                                self.on_frame,
                                self.resume,
                                self.control,
                            )
                        } else if S::INFO.explicit {
                            self.sim.drive(
                                S::INFO.name,
                                &|sim: &Simulation| Ok(SchemeStepper::new(scheme, &sim.model)),
                                self.settings,
                                self.on_frame,
                                self.resume,
                                self.control,
                            )
                        } else {
                            Err(MethodError::Implicit(S::INFO.name.to_string()).into())
                        }
                    }
                }
                let drive = Drive {
                    id: method.id(),
                    sim: self,
                    settings,
                    on_frame,
                    resume,
                    control,
                };
                with_scheme(method, drive).expect("every explicit method is a library scheme")
            }
            Mechanism::StageSolver => {
                impl TableVisitor for Drive<'_, '_> {
                    type Output = Result<RunReport, RunError>;
                    fn visit<const S: usize>(
                        self,
                        table: &integrator_core::implicit::ImplicitTable<S>,
                        info: &'static integrator_core::Info,
                    ) -> Self::Output {
                        let stage = self.settings.solvers.stage;
                        self.sim.drive(
                            info.name,
                            &|sim: &Simulation| {
                                Ok(StageStepper::new(
                                    table, &sim.model, &sim.state, sim.time, stage,
                                )?)
                            },
                            self.settings,
                            self.on_frame,
                            self.resume,
                            self.control,
                        )
                    }
                }
                let drive = Drive {
                    id: method.id(),
                    sim: self,
                    settings,
                    on_frame,
                    resume,
                    control,
                };
                with_table(method, drive)
                    .ok_or_else(|| MethodError::NotSteppable(method.id().to_string()))?
            }
            Mechanism::Constrained => {
                let (rattle, h) = (settings.solvers.rattle, settings.options.step_size());
                self.drive(
                    name,
                    &|sim: &Simulation| Ok(RattleStepper::new(&sim.model, h, rattle)?),
                    settings,
                    on_frame,
                    resume,
                    control,
                )
            }
            Mechanism::Minimisation(_) | Mechanism::DiscreteGradient => {
                let minimise = settings.solvers.minimise;
                self.drive(
                    name,
                    &|sim: &Simulation| Ok(MinimiseStepper::new(method, &sim.model, minimise)?),
                    settings,
                    on_frame,
                    resume,
                    control,
                )
            }
        }
    }

    /// [`run`](Self::run) with any scheme type that steps cloth: a user's
    /// `butcher!` scheme, stepped with its own code; a table that
    /// `butcher!` proved to be a composition of midpoint steps
    /// ([`Info::midpoint_weights`](integrator_core::Info::midpoint_weights))
    /// steps as successive minimisations instead, which descend at any step
    /// size, in the same loop.
    pub fn run_scheme<S, F>(
        &mut self,
        scheme: &S,
        settings: &RunSettings,
        mut on_frame: F,
    ) -> Result<RunReport, RunError>
    where
        S: Step<ClothModel> + Scheme,
        F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
    {
        settings.options.check()?;
        if self.model.is_inextensible() {
            return Err(RunError::Options(format!(
                "method: {} steps the spring model; an inextensible material is stepped by {}",
                S::INFO.name,
                crate::method::RATTLE
            )));
        }
        let on_frame: &mut OnFrame<'_> = &mut on_frame;
        if let Some(weights) = S::INFO.midpoint_weights {
            let minimise = settings.solvers.minimise;
            return self.drive(
                S::INFO.name,
                &|sim: &Simulation| {
                    Ok(MinimiseStepper::composition(weights, &sim.model, minimise)?)
                },
                settings,
                on_frame,
                None,
                &mut NoControl,
            );
        }
        let scheme = *scheme;
        self.drive(
            S::INFO.name,
            &|sim: &Simulation| Ok(SchemeStepper::new(scheme, &sim.model)),
            settings,
            on_frame,
            None,
            &mut NoControl,
        )
    }

    /// The one frame loop. `make` builds the stepper at the current state
    /// (again for a replay).
    fn drive<St: ClothStepper>(
        &mut self,
        method: &'static str,
        make: &dyn Fn(&Simulation) -> Result<St, RunError>,
        settings: &RunSettings,
        on_frame: &mut OnFrame<'_>,
        resume: Option<&RunState>,
        control: &mut dyn RunControl,
    ) -> Result<RunReport, RunError> {
        let opts = settings.options;
        let h = opts.step_size();
        let mut controller = settings.variable.map(|v| Controller::new(v, opts.substeps));
        let (mut stepper, mut frames, h0, clock, first_frame, mut stepping) = match resume {
            None => {
                let stepper = make(self)?;
                let mut frames = Vec::with_capacity(opts.frames.min(1 << 16) + 1);
                let first = self.stats();
                let h0 = first.energy.total();
                self.emit(first, &mut frames, on_frame)?;
                let clock = Clock {
                    t0: self.time,
                    step0: self.steps,
                    h,
                };
                (stepper, frames, h0, clock, self.frame, 0.0)
            }
            Some(rs) => {
                self.restore(method, h, rs)?;
                let mut stepper = make(self)?;
                let Some(bytes) = &rs.stepper else {
                    return Err(RunError::Resume(format!(
                        "{method}: the saved run holds no stepper state (this method cannot be resumed)"
                    )));
                };
                let path = std::path::Path::new("stepper");
                let mut d = Decoder::new(path, bytes);
                stepper
                    .restore(&self.model, &mut d)
                    .and_then(|()| match controller.as_mut() {
                        Some(c) => c.restore(&mut d),
                        None => Ok(()),
                    })
                    .and_then(|()| d.end())
                    .map_err(|e| RunError::Resume(format!("{method}: {e}")))?;
                let clock = Clock {
                    t0: rs.t0,
                    step0: rs.step0,
                    h,
                };
                let mut frames = Vec::with_capacity(opts.frames.min(1 << 16) + 1);
                frames.extend_from_slice(&rs.frames);
                (
                    stepper,
                    frames,
                    rs.h0,
                    clock,
                    rs.first_frame,
                    rs.stepping_seconds,
                )
            }
        };
        let mut saved = self.state.clone();
        // The variable step's kept end state while it tries a count below.
        let mut kept = if controller.is_some() {
            self.state.clone()
        } else {
            Vec::new()
        };
        let state_of = |sim: &Simulation,
                        stepper: &St,
                        controller: Option<&Controller>,
                        frames: &[FrameStats],
                        stepping: f64| {
            let mut e = Encoder::new();
            let carried = stepper.save(&mut e).then(|| {
                if let Some(c) = controller {
                    c.save(&mut e);
                }
                e.finish()
            });
            RunState {
                method: method.to_string(),
                h,
                state: sim.state.clone(),
                time: sim.time,
                steps: sim.steps,
                frame: sim.frame,
                first_frame,
                t0: clock.t0,
                step0: clock.step0,
                h0,
                frames: frames.to_vec(),
                stepping_seconds: stepping,
                stepper: carried,
            }
        };
        // After the initial frame of a fresh run (a resumed one was asked
        // at the frame it was saved at).
        if resume.is_none() {
            let last = *frames.last().expect("the initial frame");
            self.control(control, &last, &|sim| {
                state_of(sim, &stepper, controller.as_ref(), &frames, 0.0)
            })?;
        }
        let done = self.frame - first_frame;
        if done > opts.frames {
            return Err(RunError::Resume(format!(
                "the saved run is at frame {}, after the last frame ({}) of this one",
                self.frame,
                first_frame + opts.frames
            )));
        }
        for _ in done..opts.frames {
            saved.copy_from_slice(&self.state);
            let started = Instant::now();
            match controller.as_mut() {
                None => {
                    let done = self.advance(&mut stepper, opts.substeps, clock, method, &saved);
                    stepping += started.elapsed().as_secs_f64();
                    done?;
                    self.time = clock.time(self.steps);
                }
                Some(c) => {
                    // Frames on the grid: frame k at t0 + k/frame_rate.
                    let frame_time =
                        |k: usize| clock.t0 + (k - first_frame) as f64 / opts.frame_rate;
                    let t = frame_time(self.frame);
                    let done = self.advance_variable(
                        &mut stepper,
                        c,
                        &mut kept,
                        t,
                        opts.frame_rate,
                        method,
                        &saved,
                    );
                    stepping += started.elapsed().as_secs_f64();
                    done?;
                    self.time = frame_time(self.frame + 1);
                }
            }
            self.frame += 1;
            let stats = self.stats();
            if let Some(guard) = &settings.guard {
                let rel = guard.relative_error(stats.energy.total(), h0);
                if guard.exceeded(rel) {
                    let last_good = *frames.last().expect("the initial frame");
                    // A variable-step frame is not replayed step by step
                    // (its count of steps was the search's).
                    let guard = if controller.is_some() {
                        &guard.without_replay()
                    } else {
                        guard
                    };
                    return Err(self.blowup(
                        method,
                        make,
                        guard,
                        clock,
                        &saved,
                        last_good,
                        stats,
                        rel,
                        h0,
                        opts.substeps,
                    ));
                }
            }
            self.emit(stats, &mut frames, on_frame)?;
            self.control(control, &stats, &|sim| {
                state_of(sim, &stepper, controller.as_ref(), &frames, stepping)
            })?;
        }
        Ok(RunReport {
            method,
            h: match &controller {
                Some(c) => 1.0 / (opts.frame_rate * c.floor as f64),
                None => h,
            },
            steps: self.steps - clock.step0,
            frames,
            stepping_seconds: stepping,
            solver: stepper.stats(),
            variable: controller.map(|c| Box::new(c.stats)),
        })
    }

    /// One frame of the variable step ([`crate::step::variable`]) from
    /// `saved`, its start at time `t`: integrate it with the count the
    /// search asks for until the search is done, each time from `saved`,
    /// keeping in `kept` the end state of the fewest steps found within the
    /// target while another count is tried. On an error the state and steps
    /// go back to `saved`.
    #[allow(clippy::too_many_arguments)]
    fn advance_variable<St: ClothStepper>(
        &mut self,
        stepper: &mut St,
        ctl: &mut Controller,
        kept: &mut [f64],
        t: f64,
        frame_rate: f64,
        method: &'static str,
        saved: &[f64],
    ) -> Result<(), RunError> {
        let mut search = ctl.search();
        let mut n = search.first(ctl.guess());
        let mut tried = 0usize;
        let target = ctl.settings.wave_number;
        // Every try starts from the frame's start as the first did: the
        // state and the stepper's carried data (RATTLE's factor and warm
        // start), so that the count taken ends on the same bits whichever
        // counts were tried before it, and a try costs no fresh start.
        stepper.mark(MARK_START);
        let mut failed_last = false;
        loop {
            self.state.copy_from_slice(saved);
            if search.attempts() > 0 && !stepper.rewind(MARK_START) && failed_last {
                // No marks: drop the failed try's multipliers as a guess.
                stepper.restart();
            }
            // h as the fixed step computes it, so that a frame at the
            // floor is the fixed step's frame to the bit.
            let h = 1.0 / (frame_rate * n as f64);
            // An integration stops at its first interior node past the
            // target: that node alone rejects the count.
            let (attempt, done, why) = self.attempt(stepper, n, t, h, target);
            tried += done;
            if matches!(attempt, Attempt::Ran(w) if w <= target) {
                let end = t + n as f64 * h;
                stepper.leave(&self.model, end, &mut self.state);
            } else {
                ctl.rejected(attempt);
            }
            failed_last = attempt == Attempt::Failed;
            match search.record(n, attempt) {
                Next::Try(next) => {
                    if search.keep() {
                        kept.copy_from_slice(&self.state);
                        stepper.mark(MARK_KEPT);
                    }
                    n = next;
                }
                Next::Done { steps, latest } => {
                    if !latest {
                        self.state.copy_from_slice(kept);
                        stepper.rewind(MARK_KEPT);
                    }
                    let w = search.taken().unwrap_or(0.0);
                    ctl.finish(steps, &search, tried, w);
                    self.steps += steps;
                    return Ok(());
                }
                Next::Exhausted { tried: last } => {
                    self.state.copy_from_slice(saved);
                    stepper.rewind(MARK_START);
                    let what = match (attempt, why) {
                        (_, Some(why)) => why,
                        (Attempt::Ran(w), None) => format!("the largest was {w:.3}"),
                        (Attempt::Failed, None) => "it failed".to_string(),
                    };
                    return Err(RunError::StepControl {
                        method,
                        frame: self.frame + 1,
                        time: t,
                        message: format!(
                            "the variable step (simulation.step = \"variable\") found no count of steps per frame up to simulation.max_substeps = {} whose interior transverse-wave numbers h·ω stay at or below simulation.wave_number = {}: at {last} steps per frame {what}",
                            ctl.settings.max_substeps.max(ctl.floor),
                            ctl.settings.wave_number
                        ),
                    });
                }
            }
        }
    }

    /// Integrate the frame in `self.state` with `n` steps of `h` from time
    /// `t`: the largest wave number at its interior nodes (after steps 2 to
    /// `n`), or a failure with the steps done and why. The integration ends
    /// at the first interior node whose wave number passes `stop` (that
    /// value, and the steps done).
    fn attempt<St: ClothStepper>(
        &mut self,
        stepper: &mut St,
        n: usize,
        t: f64,
        h: f64,
        stop: f64,
    ) -> (Attempt, usize, Option<String>) {
        stepper.enter(&self.model, t, &mut self.state);
        let mut w = 0.0f64;
        for k in 0..n {
            if let Err(e) = stepper.step(&self.model, t + k as f64 * h, h, &mut self.state) {
                return (
                    Attempt::Failed,
                    k + 1,
                    Some(format!("step {} failed: {e}", k + 1)),
                );
            }
            if let Some(index) = self.state.iter().position(|x| !x.is_finite()) {
                return (
                    Attempt::Failed,
                    k + 1,
                    Some(format!(
                        "step {} left state component {index} = {}",
                        k + 1,
                        self.state[index]
                    )),
                );
            }
            if k >= 1 {
                w = w.max(stepper.wave_number().unwrap_or(f64::INFINITY));
                if k + 1 < n && w > stop {
                    return (Attempt::Ran(w), k + 1, None);
                }
            }
        }
        (Attempt::Ran(w), n, None)
    }

    /// Ask `control` what to do after the frame `stats`; `state` makes the
    /// state it may ask to save.
    fn control(
        &self,
        control: &mut dyn RunControl,
        stats: &FrameStats,
        state: &dyn Fn(&Simulation) -> RunState,
    ) -> Result<(), RunError> {
        let action = control.after_frame(stats);
        if action == Action::Continue {
            return Ok(());
        }
        control
            .checkpoint(&state(self))
            .map_err(|source| RunError::Callback {
                frame: stats.frame,
                time: stats.time,
                source,
            })?;
        if action == Action::Stop {
            return Err(RunError::Stopped {
                frame: stats.frame,
                time: stats.time,
            });
        }
        Ok(())
    }

    /// Put the simulation where `rs` was saved, checking that it is a
    /// state of this run: the method, the step size to the bit, the
    /// state's length.
    fn restore(&mut self, method: &str, h: f64, rs: &RunState) -> Result<(), RunError> {
        if rs.method != method {
            return Err(RunError::Resume(format!(
                "the saved run steps with {}, this one with {method}",
                rs.method
            )));
        }
        if rs.h.to_bits() != h.to_bits() {
            return Err(RunError::Resume(format!(
                "the saved run's step is {:e} s, this one's {h:e} s",
                rs.h
            )));
        }
        if rs.state.len() != self.state.len() {
            return Err(RunError::Resume(format!(
                "the saved state has {} components, this model {}",
                rs.state.len(),
                self.state.len()
            )));
        }
        self.state.copy_from_slice(&rs.state);
        self.time = rs.time;
        self.steps = rs.steps;
        self.frame = rs.frame;
        Ok(())
    }

    /// Record a frame and hand it to the callback.
    fn emit(
        &self,
        stats: FrameStats,
        frames: &mut Vec<FrameStats>,
        on_frame: &mut OnFrame<'_>,
    ) -> Result<(), RunError> {
        frames.push(stats);
        on_frame(&Frame {
            stats,
            model: &self.model,
            state: &self.state,
        })
        .map_err(|source| RunError::Callback {
            frame: stats.frame,
            time: stats.time,
            source,
        })
    }

    /// `n` steps (a frame, or one step of a replay) with the non-finite
    /// check after each; on an error the state, steps and time go back to
    /// `saved`, the state at the start.
    fn advance<St: ClothStepper>(
        &mut self,
        stepper: &mut St,
        n: usize,
        clock: Clock,
        method: &'static str,
        saved: &[f64],
    ) -> Result<(), RunError> {
        let start = self.steps;
        stepper.enter(&self.model, clock.time(start), &mut self.state);
        let time = |k: usize| clock.time(start + k);
        if let Err(Halt { done, why }) =
            stepper.steps(&self.model, &time, clock.h, n, &mut self.state)
        {
            // The failed step's number (from 1) and start time.
            let (step, t) = (start + done + 1, clock.time(start + done));
            let err = match why {
                Halted::Failed(StepError::Solve(source)) => RunError::Solve {
                    method,
                    step,
                    time: t,
                    source,
                },
                Halted::Failed(StepError::Minimise(source)) => RunError::Minimise {
                    method,
                    step,
                    time: t,
                    source,
                },
                Halted::Failed(StepError::Constraint(source)) => RunError::Constraint {
                    method,
                    step,
                    time: t,
                    source,
                },
                Halted::NonFinite { index, value } => RunError::Diverged {
                    method,
                    step,
                    time: clock.time(step),
                    frame: self.frame + 1,
                    index,
                    value,
                    particle: self.model.particle_of_component(index),
                },
            };
            self.state.copy_from_slice(saved);
            self.steps = start;
            return Err(err);
        }
        self.steps = start + n;
        stepper.leave(&self.model, clock.time(self.steps), &mut self.state);
        Ok(())
    }

    /// The guard passed its limit at `bad`: find the step (replaying the
    /// frame from `saved` one step at a time if the guard says so), and
    /// leave the simulation at the last good frame.
    #[allow(clippy::too_many_arguments)]
    fn blowup<St: ClothStepper>(
        &mut self,
        method: &'static str,
        make: &dyn Fn(&Simulation) -> Result<St, RunError>,
        guard: &EnergyGuard,
        clock: Clock,
        saved: &[f64],
        last_good: FrameStats,
        bad: FrameStats,
        rel: f64,
        h0: f64,
        substeps: usize,
    ) -> RunError {
        self.state.copy_from_slice(saved);
        self.steps = last_good.step;
        self.time = last_good.time;
        self.frame = last_good.frame;
        let mut blowup = Blowup {
            method,
            step: bad.step,
            time: bad.time,
            frame: bad.frame,
            relative_error: rel,
            limit: guard.limit,
            last_good,
            located: Located::Frame,
        };
        if guard.locate {
            match make(self) {
                Err(err) => blowup.located = Located::Stopped(Box::new(err)),
                Ok(mut stepper) => {
                    let mut before = saved.to_vec();
                    for _ in 0..substeps {
                        before.copy_from_slice(&self.state);
                        if let Err(err) = self.advance(&mut stepper, 1, clock, method, &before) {
                            blowup.located = Located::Stopped(Box::new(err));
                            break;
                        }
                        let energy = self.model.energy(&self.state).total();
                        let rel = guard.relative_error(energy, h0);
                        if guard.exceeded(rel) {
                            blowup.step = self.steps;
                            blowup.time = clock.time(self.steps);
                            blowup.relative_error = rel;
                            blowup.located = Located::Step;
                            break;
                        }
                    }
                }
            }
            self.state.copy_from_slice(saved);
            self.steps = last_good.step;
        }
        RunError::Blowup(Box::new(blowup))
    }
}

/// The times of a run's steps: step `k` starts at `t0 + (k − step0)·h`.
#[derive(Clone, Copy, Debug)]
struct Clock {
    t0: f64,
    step0: usize,
    h: f64,
}

impl Clock {
    fn time(&self, step: usize) -> f64 {
        self.t0 + (step - self.step0) as f64 * self.h
    }
}
