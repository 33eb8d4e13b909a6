//! What one frame of a run measured, and what a frame callback may fail
//! with: the vocabulary the run loop ([`crate::run`]) and its checkpoints
//! ([`crate::checkpoint`]) share (both re-exported by `run`).

use nalgebra::Vector3;

use crate::model::Energy;

/// What a frame callback may fail with; it stops the run.
pub type CallbackError = Box<dyn std::error::Error + Send + Sync>;

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
