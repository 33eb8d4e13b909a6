//! The energy of a run measured against a reference scale: `E_ref`, the
//! relative energy errors, and the guard that stops a run once they pass a
//! limit ([`EnergyGuard`], defined with the run loop that checks it).

use crate::run::{FrameStats, Simulation};
use crate::scene::Scene;

pub use crate::run::{Blowup, EnergyGuard, Located};

/// The strain of the elastic floor of [`reference_energy`]: 0.01 %.
pub const ELASTIC_FLOOR_STRAIN: f64 = 1e-4;

/// Why a scene has no usable energy scale; `field` names the part of the
/// scene that makes it so.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{field}: {message}")]
pub struct ReferenceEnergyError {
    pub field: &'static str,
    pub message: String,
}

/// The energy that relative energy errors are divided by:
/// `E_ref = max(|H₀|, M·|g|·ℓ, E_ε)`, with `H₀` the initial energy, `M` the
/// mass of the free particles, `ℓ` the larger side of the cloth — the
/// energy of the cloth falling by its own size, which is what a hanging
/// sheet trades between kinetic and potential energy (the paper scene
/// starts at `H₀ = 0`) — and `E_ε = ½·Σ k·L·ε²`, `ε` = 0.01 %
/// ([`ELASTIC_FLOOR_STRAIN`]), the elastic energy of every spring with a
/// free end stretched by 0.01 %. The floor `E_ε` is what keeps a scene
/// with nothing to release (no gravity, starting at rest, `H₀` a round-off
/// 1e-31 J) from dividing round-off by round-off and "blowing up" at step
/// 3; on the shipped scenes it is far below the other two terms (3e-5 J on
/// the paper scene against `M·|g|·ℓ` = 0.13 J, still 2.5e-3 J at 2048 ×
/// 2048), so it changes nothing there.
///
/// An error names what makes it unusable: zero (nothing in the scene can
/// exchange energy: no gravity, no spring with a free end, nothing stored
/// at the start) or not finite (the scales overflow).
///
/// ```
/// use cloth::{Scene, Simulation, study::energy::reference_energy};
///
/// let scene = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/paper.toml"))?;
/// let sim = Simulation::new(&scene)?;
/// let e_ref = reference_energy(&scene, &sim)?;
/// assert!(e_ref > 0.1 && e_ref < 0.2); // M·|g|·ℓ of the paper's sheet
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn reference_energy(scene: &Scene, sim: &Simulation) -> Result<f64, ReferenceEnergyError> {
    let h0 = sim.stats().energy.total().abs();
    let m = sim.model.particle_mass() * sim.model.free_count() as f64;
    // |g| without overflowing the squares (gravity = [0, -1e200, 0]).
    let g = sim.model.gravity().iter().fold(0.0f64, |a, x| a.hypot(*x));
    let size = scene.cloth.width.max(scene.cloth.height) * scene.cloth.prestretch;
    let fall = m * g * size;
    let elastic = sim.model.elastic_energy_scale(ELASTIC_FLOOR_STRAIN);
    let e = h0.max(fall).max(elastic);
    if !e.is_finite() || e.is_nan() {
        let field = if !h0.is_finite() {
            "cloth"
        } else if !fall.is_finite() {
            "gravity"
        } else {
            "material"
        };
        return Err(ReferenceEnergyError {
            field,
            message: format!(
                "the reference energy E_ref = max(|H₀|, M·|g|·ℓ, ½·Σk·L·ε²) = max({h0:e}, {fall:e}, {elastic:e}) J is not finite"
            ),
        });
    }
    if e <= 0.0 {
        return Err(ReferenceEnergyError {
            field: "gravity",
            message: "the scene has no energy scale (no gravity, no spring with a free end, no energy at the start): E_ref = 0, so relative energy errors cannot be measured".to_string(),
        });
    }
    Ok(e)
}

/// [`reference_energy`], or 1 J when the scene has no usable energy scale
/// (for reports that read it as a number).
pub fn reference_energy_or_unit(scene: &Scene, sim: &Simulation) -> f64 {
    reference_energy(scene, sim).unwrap_or(1.0)
}

/// `(H − H₀)/E_ref` of each frame, `H₀` the first frame's energy.
pub fn relative_errors(frames: &[FrameStats], e_ref: f64) -> Vec<f64> {
    let h0 = frames.first().map_or(0.0, |f| f.energy.total());
    frames
        .iter()
        .map(|f| (f.energy.total() - h0) / e_ref)
        .collect()
}

/// The largest `|H − H₀|/E_ref` over `frames`, and the time it was reached.
pub fn worst_relative_error(frames: &[FrameStats], e_ref: f64) -> (f64, f64) {
    relative_errors(frames, e_ref)
        .iter()
        .zip(frames)
        .fold((0.0f64, 0.0f64), |(w, t), (e, f)| {
            if e.abs() > w {
                (e.abs(), f.time)
            } else {
                (w, t)
            }
        })
}
