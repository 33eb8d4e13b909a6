//! Running a scene: substeps per frame, a callback per frame, energy and
//! momentum recorded per frame, and a clear error when the state blows up.

use std::time::Instant;

use integrator_core::{Scheme, SolveError, Step};
use nalgebra::Vector3;

use crate::methods::{self, MethodError, SchemeVisitor};
use crate::model::{ClothModel, Energy};
use crate::scene::{Scene, SceneError};

/// What a frame callback may fail with; it stops the run.
pub type CallbackError = Box<dyn std::error::Error + Send + Sync>;

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

/// What is known about the state at a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameStats {
    /// 0 for the initial state.
    pub frame: usize,
    /// Steps taken so far.
    pub step: usize,
    /// Simulated time (s).
    pub time: f64,
    pub energy: Energy,
    /// Total momentum of the free particles (kg·m/s).
    pub momentum: Vector3<f64>,
    /// The largest `|ℓ − L|/L` over all springs.
    pub max_strain: f64,
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

/// The outcome of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct RunReport {
    /// The scheme's name.
    pub method: &'static str,
    /// Step size (s).
    pub h: f64,
    pub steps: usize,
    /// One entry per frame, the initial state first.
    pub frames: Vec<FrameStats>,
    /// Wall-clock time of the stepping alone, callbacks excluded (s).
    pub stepping_seconds: f64,
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
        source: crate::minimise::MinimiseError,
    },
    #[error("frame {frame} (t = {time} s): {source}")]
    Callback {
        frame: usize,
        time: f64,
        #[source]
        source: CallbackError,
    },
}

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

    /// Run `opts.frames` frames of `opts.substeps` steps with `scheme`,
    /// calling `on_frame` with the current frame first (when the simulation
    /// is fresh, the initial state) and after every frame. Checks for
    /// non-finite values after every step, and stops at the first with
    /// [`RunError::Diverged`] naming the step, time and method; the state is
    /// then left as it was at the end of the last good frame.
    pub fn run<S, F>(
        &mut self,
        scheme: &S,
        opts: &RunOptions,
        mut on_frame: F,
    ) -> Result<RunReport, RunError>
    where
        S: Step<ClothModel> + Scheme,
        F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
    {
        // A table that is exactly a composition of midpoint steps (a user's
        // as well as the library's) steps as successive minimisations,
        // which descend at any step size, not through the stage equations.
        if S::INFO.midpoint_weights.is_some() {
            return crate::minimise::run_scheme::<S, F>(
                self,
                opts,
                crate::minimise::Settings::default(),
                on_frame,
            )
            .map(|r| r.report);
        }
        let method = S::INFO.name;
        let h = opts.step_size();
        opts.check()?;
        let mut frames = Vec::with_capacity(opts.frames.min(1 << 16) + 1);
        let mut emit = |sim: &Simulation, frames: &mut Vec<FrameStats>| -> Result<(), RunError> {
            let stats = sim.stats();
            frames.push(stats);
            on_frame(&Frame {
                stats,
                model: &sim.model,
                state: &sim.state,
            })
            .map_err(|source| RunError::Callback {
                frame: stats.frame,
                time: stats.time,
                source,
            })
        };
        emit(self, &mut frames)?;
        let mut ws = scheme.workspace(&self.model);
        let mut saved = self.state.clone();
        let t0 = self.time;
        let step0 = self.steps;
        let mut stepping = 0.0;
        for _ in 0..opts.frames {
            saved.copy_from_slice(&self.state);
            let frame_start = self.steps;
            let clock = Instant::now();
            for _ in 0..opts.substeps {
                let t = t0 + (self.steps - step0) as f64 * h;
                let reuse = self.steps > step0;
                if let Err(source) =
                    scheme.step_reusing(&self.model, t, h, &mut self.state, &mut ws, reuse)
                {
                    let step = self.steps + 1;
                    self.state.copy_from_slice(&saved);
                    self.steps = frame_start;
                    return Err(RunError::Solve {
                        method,
                        step,
                        time: t,
                        source,
                    });
                }
                self.steps += 1;
                if let Some(index) = self.state.iter().position(|x| !x.is_finite()) {
                    let value = self.state[index];
                    self.state.copy_from_slice(&saved);
                    let steps = self.steps;
                    self.steps = frame_start;
                    return Err(RunError::Diverged {
                        method,
                        step: steps,
                        time: t0 + (steps - step0) as f64 * h,
                        frame: self.frame + 1,
                        index,
                        value,
                        particle: self.model.particle_of_component(index),
                    });
                }
            }
            stepping += clock.elapsed().as_secs_f64();
            self.frame += 1;
            self.time = t0 + (self.steps - step0) as f64 * h;
            emit(self, &mut frames)?;
        }
        Ok(RunReport {
            method,
            h,
            steps: self.steps - step0,
            frames,
            stepping_seconds: stepping,
        })
    }

    /// [`run`](Self::run) with a library scheme named by its id (see
    /// [`methods::STEPPABLE`]).
    pub fn run_named<F>(
        &mut self,
        method: &str,
        opts: &RunOptions,
        on_frame: F,
    ) -> Result<RunReport, RunError>
    where
        F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
    {
        struct Visit<'s, F> {
            sim: &'s mut Simulation,
            opts: &'s RunOptions,
            on_frame: F,
        }
        impl<F: FnMut(&Frame<'_>) -> Result<(), CallbackError>> SchemeVisitor for Visit<'_, F> {
            type Output = Result<RunReport, RunError>;
            fn visit<S: Step<ClothModel> + Scheme>(self, scheme: S) -> Self::Output {
                self.sim.run(&scheme, self.opts, self.on_frame)
            }
        }
        methods::with_scheme(
            method,
            Visit {
                sim: self,
                opts,
                on_frame,
            },
        )?
    }
}

/// Load nothing, build everything: run `scene` with its own method and
/// settings through [`crate::minimise::run_any`] (the midpoint family and the
/// energy-conserving schemes as minimisations with the default Newton
/// settings, other implicit schemes through the sparse stage solver,
/// explicit ones directly),
/// calling `on_frame` for the initial state and every frame.
pub fn run_scene<F>(scene: &Scene, on_frame: F) -> Result<(Simulation, RunReport), RunError>
where
    F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
{
    let mut sim = Simulation::new(scene)?;
    let (report, _) = crate::minimise::run_any(
        &mut sim,
        &scene.simulation.method,
        &RunOptions::from_scene(scene),
        crate::minimise::Settings::default(),
        on_frame,
    )?;
    Ok((sim, report))
}
