//! RATTLE on the inextensible cloth: the one constrained integrator of
//! `integrator_core::constrained::rattle` (Störmer–Verlet, the Lobatto
//! IIIA–IIIB pair with two stages, in its multiplier form) applied to
//! `H = ½pᵀM⁻¹p + V(q)`, `g(q) = 0`, with `M = m·I`, `V` the soft springs
//! (shear, bend), gravity and the colliders, and `g` the warp and weft
//! length constraints (`crate::model` `constraints.rs`). One step:
//!
//! ```text
//! p½ = p − h/2·(∇V(q) + G(q)ᵀλ)
//! q' = q + h·M⁻¹·p½                    with g(q') = 0      (solve for λ)
//! p' = p½ − h/2·(∇V(q') + G(q')ᵀμ)     with G(q')·M⁻¹·p' = 0 (solve for μ)
//! ```
//!
//! It is symplectic on the constraint manifold, symmetric and of order 2
//! (Leimkuhler & Skeel 1994), and needs no stretch stiffness: its step is
//! limited by the soft forces and by the tension waves of the sheet.
//!
//! The algorithm (the simplified Newton position solve with a kept factor,
//! its refresh by the true Jacobian, the warm start, the stop at round-off
//! and the cap, the velocity projection only where a frame is handed out
//! and its conjugate gradients) lives in `integrator_core`; what is the
//! cloth's is here and in `constraints.rs`:
//!
//! - the system (`ClothSystem`): one edge vector `d_c = x_a − x_b` per
//!   constraint as the geometry of `G` (row `2d_cᵀ`), the scaled
//!   multipliers `Λ = h²λ/(2m)` (so that the displacement is `G(q)ᵀΛ` and
//!   the matrix `G·Gᵀ`: `M⁻¹ = I/m` absorbed), the stop rule
//!   `|g_c| ≤ 32·ε·L_c²·(1 + ‖q‖_∞/L_c)` ([`CONSTRAINT_TOLERANCE`]) and the
//!   transverse-wave number `h·ω = 4·√(½·Σ_c Λ_c)` as the measure of the
//!   step's limit;
//! - the linear algebra (`SparseGram` in `constraints.rs`): a sparse
//!   Cholesky of `G·Gᵀ` whose symbolic analysis (the pattern never
//!   changes) is made once with the model, renewed at a step's `q` when the
//!   kept one stops contracting (measured on the 64² sheet released 45°
//!   over 600 frames: 769 LU refreshes became 0 and 2428 Cholesky 2792,
//!   at 1.8 ms against 5.9 ms for an LU; 49.8 → 39.7 ms per frame, under
//!   load), and a sparse LU of the true
//!   Jacobian `G(q')·G(q)ᵀ` for the refreshes that still do not contract
//!   (a symmetric refresh,
//!   `½(G(q')G(q)ᵀ + G(q)G(q')ᵀ)` by Cholesky, was tried first and does
//!   not help: the slow modes come from the skew part of the difference,
//!   which it leaves out; on the falling 64² sheet at 8 steps per frame the
//!   iteration then crawled at 0.6 per iteration). It is the cloth's
//!   because it assembles `G·Gᵀ` from the edge vectors on the grid's
//!   pattern (`±4·d_c·d_e` where two edges share a particle);
//! - the stepper ([`RattleStepper`]): the colliders' step limit, the
//!   projection at the end of a frame ([`ClothStepper::leave`]), the
//!   checkpoint, and the error messages in the cloth's terms.
//!
//! [`CONSTRAINT_TOLERANCE`]: crate::model::CONSTRAINT_TOLERANCE

use std::sync::Arc;

use integrator_core::Separable;
use integrator_core::checkpoint::{CheckpointError, Decoder, Encoder};
use integrator_core::constrained::rattle::{self, Mark, Projection, Rattle, RattleSystem};

pub use integrator_core::constrained::rattle::{Stats, Timing};

use super::{ClothStepper, Refused, SolverStats, StepError};
use crate::model::constraints::{EdgeConstraints, SparseGram, q_max};
use crate::model::{CONSTRAINT_TOLERANCE, ClothModel};

/// The constraint solver's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RattleSettings {
    /// Simplified Newton iterations of one position solve before the step
    /// fails (default 50).
    pub max_iterations: usize,
    /// Refresh the factor when an iteration shrinks the residual by less
    /// than this factor (default 0.5).
    pub contraction: f64,
    /// Assemble, factorise and run the per-edge loops on both cores
    /// (default false: two cores do not pay anywhere in a RATTLE step on
    /// these grids). Measured on the paper's sheet released 45° (Zen 5,
    /// 2026-11-30, quiet, one run at a time): at 64² over 100 frames
    /// 15.7–15.9 ms per frame on one core against 22.3–25.7 on two, the
    /// per-edge loops and the mixing 2.5 against 8.5 ms per frame (8001
    /// edges are too few for rayon's hand-over) and the factorisations,
    /// with the assembly on two threads, 5.0 against 5.2; at 128² over 30
    /// frames 115–117 against 127–133 ms. faer chooses its simplicial
    /// Cholesky for `G·Gᵀ` (at 64², 8001 rows, 146 324 entries in the
    /// factor), which has no parallel path; forced to its supernodal one
    /// (2080 supernodes of 3.8 columns on average, too small for its
    /// parallel dense kernels) a factorisation took 1.64 ms on two threads
    /// against 1.49 on one, and a pair of triangular solves 0.33 ms on
    /// either (with the other core busy: upper bounds), twice the
    /// simplicial solves, which the ~9 solves of every step make the
    /// larger cost.
    pub parallel: bool,
    /// Factorise `G·Gᵀ` afresh every this many steps (default 6; 1: every
    /// step; 0: only when the conjugate gradients of a frame's velocity
    /// projection fail), and after every step whose position solve had to
    /// refresh the LU of the true Jacobian (the factor was too old for the
    /// sheet's motion: without that, the hammock scene refreshed an LU at
    /// 0.59 of its steps and ran 1.65× slower). The factor serves the position solves of the
    /// steps after it (an older one costs them a few more iterations) and
    /// the projections at the frames. The default was measured on the
    /// paper's sheet released 45° (docs/results/cloth-inextensible.md): at 64²
    /// with 6 steps per frame 3 and 6 gave 15.1 and 14.1 ms per frame, at
    /// 128² with 12 per frame 3, 4, 6 and 12 gave 168, 144, 124 and 120 ms.
    pub refactor_every: usize,
    /// Conjugate-gradient iterations of one velocity projection before it
    /// falls back to a factorisation (default 12).
    pub max_pcg: usize,
    /// Anderson acceleration of the position solve with this many of its
    /// last corrections (default 4; 0: the plain simplified Newton
    /// iteration; see `integrator_core`'s `rattle::Settings::anderson`).
    /// Measured on the paper's sheet released 45° at 64² over 600 frames
    /// (Zen 5, quiet, one run at a time, 2026-11-30): depth 0, 2, 3, 4 and
    /// 6 took 11.31, 9.29, 9.07, 8.88 and 8.75 iterations per step and
    /// 33.6, 31.0, 30.9, 30.5 and 30.9 ms per frame (beyond 4 the history
    /// costs what the iterations save), with the same steps per frame and
    /// energy error to the printed digits. `refactor_every` 4, 6, 9 and 12
    /// gave 30.7, 30.5, 31.8 and 31.0 ms there: 6 stays.
    pub anderson: usize,
    /// Let the variable step go back to a frame's start with the carried
    /// data its first try started from ([`ClothStepper::mark`]: the kept
    /// factor, the warm start, the carried momentum) for every further
    /// try of the frame (default true). False: a further try starts
    /// afresh (a factorisation at the frame's start, multipliers from
    /// zero, the projected momentum), as before the marks; kept to measure
    /// the difference in one build (docs/results/cloth-inextensible.md).
    pub rewind: bool,
}

impl Default for RattleSettings {
    fn default() -> Self {
        RattleSettings {
            max_iterations: 50,
            contraction: 0.5,
            parallel: false,
            refactor_every: 6,
            max_pcg: 12,
            anderson: 4,
            rewind: true,
        }
    }
}

/// Why a constrained step failed (the run adds the step and time).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RattleError {
    #[error(
        "the RATTLE position solve did not converge in {iterations} iterations: the constraint residual max|g_c|/(L_c(L_c + ‖q‖∞)) is {residual:e}, the tolerance {tolerance:e} (32·ε); the step is too large for the sheet's motion (the step before ended with a transverse-wave number h·ω = 4·√(½ΣΛ) of {wave_number:.3}, where RATTLE is stable only below 2: a peak of tension needs a shorter step)"
    )]
    NotConverged {
        iterations: usize,
        residual: f64,
        tolerance: f64,
        /// The largest `h·ω` of the last step solved (0 before the first).
        wave_number: f64,
    },
    #[error(
        "the constraints' Gram matrix G·Gᵀ is not positive definite in the {phase}: the length constraints became dependent (a line of edges pulled straight between pins, or a sheet folded onto itself)"
    )]
    NotPositive { phase: &'static str },
    #[error(
        "the position solve's Jacobian G(q')·G(q)ᵀ is singular: the length constraints became dependent"
    )]
    Singular,
    #[error("the RATTLE position solve diverged: the constraint residual is {residual:e}")]
    Diverged { residual: f64 },
}

impl RattleSettings {
    /// The integrator's settings: the projection only where a frame is
    /// handed out (SHAKE's form; see the module documentation).
    fn core(&self) -> rattle::Settings {
        rattle::Settings {
            max_iterations: self.max_iterations,
            contraction: self.contraction,
            refactor_every: self.refactor_every,
            anderson: self.anderson,
            max_pcg: self.max_pcg,
            projection: Projection::AtLeave,
        }
    }
}

/// The inextensible cloth as a [`RattleSystem`]: the model (masses,
/// forces) and its edge constraints, made for each call from the model the
/// run loop hands the stepper.
pub(crate) struct ClothSystem<'a> {
    model: &'a ClothModel,
    constraints: &'a EdgeConstraints,
    parallel: bool,
}

impl RattleSystem for ClothSystem<'_> {
    /// The edge vectors `d_c = x_a − x_b`.
    type Geometry = Vec<[f64; 3]>;

    fn coordinates(&self) -> usize {
        3 * self.model.free_count()
    }
    fn constraint_count(&self) -> usize {
        self.constraints.len()
    }
    fn mass(&self, out: &mut [f64]) {
        out.fill(self.model.particle_mass());
    }
    fn inverse_mass(&self, out: &mut [f64]) {
        out.fill(self.model.inverse_mass());
    }
    fn force(&self, q: &[f64], out: &mut [f64]) {
        self.model.force(q, out);
    }
    fn new_geometry(&self) -> Vec<[f64; 3]> {
        vec![[0.0; 3]; self.constraints.len()]
    }
    fn geometry(&self, q: &[f64], geo: &mut Vec<[f64; 3]>) {
        self.constraints.edge_vectors(q, geo, self.parallel);
    }
    /// `G(q)ᵀΛ`: with `Λ = h²λ/(2m)` this is the displacement
    /// `h²/2·M⁻¹G(q)ᵀλ`.
    fn displace(&self, geo: &Vec<[f64; 3]>, kappa: &[f64], out: &mut [f64]) {
        self.constraints.apply_gt(geo, kappa, out, self.parallel);
    }
    fn impulse(&self, geo: &Vec<[f64; 3]>, mu: &[f64], out: &mut [f64]) {
        self.constraints.apply_gt(geo, mu, out, self.parallel);
    }
    /// `G·p` (`G·M⁻¹·p` times `m`, the scaling of `G·Gᵀ`).
    fn tangent(&self, geo: &Vec<[f64; 3]>, p: &[f64], out: &mut [f64]) {
        self.constraints.apply_g(geo, p, out, self.parallel);
    }
    fn residuals(&self, _q: &[f64], geo: &Vec<[f64; 3]>, q_scale: f64, out: &mut [f64]) -> f64 {
        self.constraints.residuals(geo, q_scale, out, self.parallel)
    }
    fn tolerance(&self) -> f64 {
        CONSTRAINT_TOLERANCE
    }
    /// `64·ε·2·L_max·‖p‖∞`: `G·p` sums `2·d_c·(p_a − p_b)`.
    fn projection_tolerance(&self, _geo: &Vec<[f64; 3]>, p: &[f64]) -> f64 {
        64.0 * f64::EPSILON * 2.0 * self.constraints.max_rest() * q_max(p)
    }
    /// The transverse-wave number `h·ω = 4·√(½·Σ_c Λ_c)`.
    fn wave_number(&self, kappa: &[f64]) -> f64 {
        self.constraints.wave_number(kappa)
    }
}

/// RATTLE as a [`ClothStepper`]: the one integrator with the cloth's
/// sparse linear algebra.
pub struct RattleStepper {
    constraints: Arc<EdgeConstraints>,
    parallel: bool,
    rattle: Rattle<Vec<[f64; 3]>, SparseGram>,
    /// The variable step's marks ([`ClothStepper::mark`]): a frame's
    /// start and the end of the try it keeps.
    marks: [Mark; 2],
    rewind: bool,
}

impl RattleStepper {
    /// A stepper for `model` at step `h`: refused when the model is not
    /// inextensible, or when a collider's penalty is too stiff for the step
    /// (its rate `√stiffness` must satisfy `h·√stiffness ≤ 1`: the penalty
    /// is stepped explicitly, as Störmer–Verlet, whose linear limit is 2).
    pub fn new(
        model: &ClothModel,
        h: f64,
        settings: RattleSettings,
    ) -> Result<RattleStepper, Refused> {
        let Some(constraints) = model.constraints() else {
            return Err(Refused(
                "method: rattle steps an inextensible material (material.stretch = \"inextensible\"); this scene's warp and weft are springs".to_string(),
            ));
        };
        for (k, rate) in model.collider_rates().into_iter().enumerate() {
            if h * rate > 1.0 {
                return Err(Refused(format!(
                    "colliders[{k}].stiffness: {:e} s⁻² makes a particle in contact oscillate at {rate:e} rad/s; RATTLE steps the penalty explicitly and needs h·√stiffness ≤ 1, so at h = {h:e} s the stiffness may be at most 1/h² = {:e} s⁻² (or take more substeps)",
                    rate * rate,
                    1.0 / (h * h)
                )));
            }
        }
        let sys = ClothSystem {
            model,
            constraints,
            parallel: settings.parallel,
        };
        let lin = SparseGram::new(constraints.clone(), settings.parallel);
        Ok(RattleStepper {
            marks: Default::default(),
            rewind: settings.rewind,
            rattle: Rattle::new(&sys, lin, h, settings.core()),
            constraints: constraints.clone(),
            parallel: settings.parallel,
        })
    }

    /// The integrator's error in the cloth's terms (the wave number of the
    /// step before, for a position solve that did not converge).
    fn error(&self, e: rattle::RattleError) -> RattleError {
        match e {
            rattle::RattleError::NotConverged {
                iterations,
                residual,
                tolerance,
            } => RattleError::NotConverged {
                iterations,
                residual,
                tolerance,
                wave_number: self.rattle.last_wave_number(),
            },
            rattle::RattleError::NotPositive { phase } => RattleError::NotPositive { phase },
            rattle::RattleError::Singular => RattleError::Singular,
            rattle::RattleError::Diverged { residual } => RattleError::Diverged { residual },
        }
    }
}

impl ClothStepper for RattleStepper {
    fn step(
        &mut self,
        model: &ClothModel,
        _t: f64,
        h: f64,
        z: &mut [f64],
    ) -> Result<(), StepError> {
        let sys = ClothSystem {
            model,
            constraints: &self.constraints,
            parallel: self.parallel,
        };
        self.rattle
            .step(&sys, h, z)
            .map_err(|e| StepError::Constraint(self.error(e)))
    }

    /// Carry on from the unprojected momentum the last frame ended with,
    /// where `z` is still the state handed out then.
    fn enter(&mut self, _model: &ClothModel, _t: f64, z: &mut [f64]) {
        self.rattle.enter(z);
    }

    /// Hand out `[q; p]` with `p` projected onto the tangent space
    /// (`G(q)·M⁻¹·p = 0`), as RATTLE's own step ends.
    fn leave(&mut self, model: &ClothModel, _t: f64, z: &mut [f64]) {
        let sys = ClothSystem {
            model,
            constraints: &self.constraints,
            parallel: self.parallel,
        };
        self.rattle.leave(&sys, z);
    }

    fn mark(&mut self, slot: usize) {
        if let (true, Some(m)) = (self.rewind, self.marks.get_mut(slot)) {
            self.rattle.mark(m);
        }
    }

    fn rewind(&mut self, slot: usize) -> bool {
        self.rewind && self.marks.get(slot).is_some_and(|m| self.rattle.rewind(m))
    }

    fn stats(&self) -> SolverStats {
        SolverStats::Constrained(self.rattle.stats())
    }

    /// `h·ω = 4·√(½ΣΛ)` of the last step solved (of the whole impulse at
    /// the step's start when it started from a carried momentum).
    fn wave_number(&self) -> Option<f64> {
        Some(self.rattle.last_wave_number())
    }

    /// Start the next position solve from zero multipliers (the failed
    /// solve's iterate is no guess).
    fn restart(&mut self) {
        self.rattle.forget_warm_start();
    }

    /// The integrator's carried data ([`Rattle::save`]): the carried p̃,
    /// the warm start, the kept factor of `G·Gᵀ` and its age, the force and
    /// edge vectors at `q`, the flags and the statistics.
    fn save(&self, e: &mut Encoder) -> bool {
        self.rattle.save(e);
        true
    }

    fn restore(&mut self, _model: &ClothModel, r: &mut Decoder<'_>) -> Result<(), CheckpointError> {
        self.rattle.restore(r)
    }
}
