//! What a cloth run needs to continue to the same bits, and how the run
//! loop is told to save it or to stop.
//!
//! The frame loop ([`Simulation::run_controlled`](crate::Simulation::run_controlled))
//! asks a [`RunControl`] after every frame whether to go on, to save a
//! [`RunState`] or to save one and stop. The library installs no signal
//! handler and reads no clock for this: the front end decides when (a
//! wall-clock interval, a signal flag it polls) and where the state is
//! written ([`integrator_core::checkpoint`] holds the container). Saving
//! only reads the run, so the bits of a run do not depend on whether or
//! when it was checkpointed.
//!
//! A [`RunState`] holds the simulation (state, time, step and frame
//! counts), the loop's own data (the time origin of its steps, the energy
//! `H₀` its guard measures from, the frames' statistics so far, the
//! stepping time) and the stepper's carried data
//! ([`ClothStepper::save`](crate::step::ClothStepper::save): for RATTLE the
//! unprojected momentum p̃, the warm-start multipliers, the factor of
//! `G·Gᵀ` and its schedule). Steppers that cannot save theirs yet leave
//! [`RunState::stepper`] empty and such a run is not resumable.

pub use integrator_core::checkpoint::{
    CheckpointError, Decoder, Encoder, FILE_NAME, Kind, read, read_any, write,
};
use nalgebra::Vector3;

use crate::frame::{CallbackError, FrameStats};
use crate::method::{Mechanism, Method};
use crate::model::Energy;

/// Whether runs of `method` can save their stepper's data, and so be
/// checkpointed and resumed: RATTLE's, for now (the explicit schemes'
/// workspaces, the stage solver's and the minimisations' warm starts are
/// not saved yet).
pub fn resumable(method: &Method) -> bool {
    matches!(method.mechanism(), Mechanism::Constrained)
}

/// What the loop does after a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Go on.
    Continue,
    /// Hand a [`RunState`] to [`RunControl::checkpoint`], then go on.
    Checkpoint,
    /// Hand a [`RunState`] to [`RunControl::checkpoint`], then stop with
    /// [`RunError::Stopped`](crate::RunError::Stopped).
    Stop,
}

/// The front end's say in a run: polled after every frame (the initial
/// one included), after the frame callback.
pub trait RunControl {
    /// What to do after the frame `stats`.
    fn after_frame(&mut self, stats: &FrameStats) -> Action;
    /// Save `state` (written only when [`after_frame`](Self::after_frame)
    /// asked for it). An error stops the run as a callback's does.
    fn checkpoint(&mut self, state: &RunState) -> Result<(), CallbackError>;
}

/// A control that never saves or stops: a plain run.
pub struct NoControl;

impl RunControl for NoControl {
    fn after_frame(&mut self, _: &FrameStats) -> Action {
        Action::Continue
    }
    fn checkpoint(&mut self, _: &RunState) -> Result<(), CallbackError> {
        Ok(())
    }
}

/// A run between two frames, complete enough to continue it to the same
/// bits.
#[derive(Clone, Debug, PartialEq)]
pub struct RunState {
    /// The scheme's name (as [`RunReport::method`](crate::RunReport::method)).
    pub method: String,
    /// The step size (checked bit for bit when the run continues).
    pub h: f64,
    /// `z = [q; p]` as handed out at the frame.
    pub state: Vec<f64>,
    pub time: f64,
    pub steps: usize,
    pub frame: usize,
    /// The frame the run started at (frames are counted from it).
    pub first_frame: usize,
    /// The time origin of the steps: step `k` starts at `t0 + (k − step0)·h`.
    pub t0: f64,
    pub step0: usize,
    /// The energy at the start of the run, which the guard measures from.
    pub h0: f64,
    /// Every frame so far, the initial one first.
    pub frames: Vec<FrameStats>,
    /// Stepping time so far (s).
    pub stepping_seconds: f64,
    /// The stepper's carried data ([`ClothStepper::save`](crate::step::ClothStepper::save)),
    /// `None` when its method cannot save it.
    pub stepper: Option<Vec<u8>>,
}

impl RunState {
    /// Whether the run can continue from this state.
    pub fn resumable(&self) -> bool {
        self.stepper.is_some()
    }

    /// Append the state to `e`.
    pub fn encode(&self, e: &mut Encoder) {
        e.str(&self.method)
            .f64(self.h)
            .f64s(&self.state)
            .f64(self.time)
            .usize(self.steps)
            .usize(self.frame)
            .usize(self.first_frame)
            .f64(self.t0)
            .usize(self.step0)
            .f64(self.h0)
            .usize(self.frames.len());
        for f in &self.frames {
            encode_frame(e, f);
        }
        e.f64(self.stepping_seconds);
        match &self.stepper {
            Some(b) => e.bool(true).bytes(b),
            None => e.bool(false),
        };
    }

    /// Read a state that [`encode`](Self::encode) wrote.
    pub fn decode(d: &mut Decoder<'_>) -> Result<RunState, CheckpointError> {
        let method = d.str("method")?.to_string();
        let h = d.f64("h")?;
        let state = d.f64s("state")?;
        let time = d.f64("time")?;
        let steps = d.usize("steps")?;
        let frame = d.usize("frame")?;
        let first_frame = d.usize("first_frame")?;
        let t0 = d.f64("t0")?;
        let step0 = d.usize("step0")?;
        let h0 = d.f64("h0")?;
        let n = d.usize("frames")?;
        if n != frame - first_frame.min(frame) + 1 || first_frame > frame {
            return Err(d.error(format!(
                "frames: {n} frames recorded for frames {first_frame} to {frame}"
            )));
        }
        let mut frames = Vec::with_capacity(n);
        for _ in 0..n {
            frames.push(decode_frame(d)?);
        }
        let stepping_seconds = d.f64("stepping_seconds")?;
        let stepper = if d.bool("stepper")? {
            Some(d.bytes("stepper")?.to_vec())
        } else {
            None
        };
        if steps < step0 {
            return Err(d.error(format!("steps {steps} before the origin {step0}")));
        }
        Ok(RunState {
            method,
            h,
            state,
            time,
            steps,
            frame,
            first_frame,
            t0,
            step0,
            h0,
            frames,
            stepping_seconds,
            stepper,
        })
    }
}

/// One frame's statistics into a payload (shared with the figure-5
/// comparison's checkpoints).
pub fn encode_frame(e: &mut Encoder, f: &FrameStats) {
    e.usize(f.frame)
        .usize(f.step)
        .f64(f.time)
        .f64(f.energy.kinetic)
        .f64(f.energy.springs)
        .f64(f.energy.gravity)
        .f64(f.energy.colliders)
        .f64(f.energy.bending)
        .f64(f.momentum.x)
        .f64(f.momentum.y)
        .f64(f.momentum.z)
        .f64(f.max_strain);
}

/// One frame's statistics as [`encode_frame`] wrote them.
pub fn decode_frame(d: &mut Decoder<'_>) -> Result<FrameStats, CheckpointError> {
    Ok(FrameStats {
        frame: d.usize("frame")?,
        step: d.usize("step")?,
        time: d.f64("time")?,
        energy: Energy {
            kinetic: d.f64("kinetic")?,
            springs: d.f64("springs")?,
            gravity: d.f64("gravity")?,
            colliders: d.f64("colliders")?,
            bending: d.f64("bending")?,
        },
        momentum: Vector3::new(d.f64("momentum")?, d.f64("momentum")?, d.f64("momentum")?),
        max_strain: d.f64("max_strain")?,
    })
}
