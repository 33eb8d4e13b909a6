//! RATTLE on the inextensible cloth: Störmer–Verlet (the Lobatto IIIA–IIIB
//! pair with two stages) applied to the constrained Hamiltonian system
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
//! **The position solve.** With `q̂ = q + h·M⁻¹(p − h/2·∇V(q))` and the
//! scaled multipliers `Λ = h²λ/(2m)`, `q'(Λ) = q̂ − G(q)ᵀΛ`, and
//! `g(q'(Λ)) = 0` is solved by simplified Newton: `Λ ← Λ + A⁻¹·g(q'(Λ))`
//! with `A = G(q)·G(q)ᵀ` (the true Jacobian is `G(q')·G(q)ᵀ`). `A` is SPD
//! while the constraints are independent; its factor is renewed at the end
//! of every few steps (at that step's `q'`, this step's `q`) and otherwise
//! an older one serves, so the position solve costs no factorisation of
//! its own. While the
//! iteration contracts (each residual at most [`RattleSettings::contraction`]
//! of the one before) the factor is kept; when it does not, the iteration
//! goes on with a sparse LU of the true Jacobian `G(q')·G(q)ᵀ` at the
//! current iterate, refreshed again whenever it stops contracting. (A
//! symmetric refresh, `½(G(q')G(q)ᵀ + G(q)G(q')ᵀ)` by Cholesky, was tried
//! first and does not help: the slow modes come from the skew part of the
//! difference, which it leaves out; on the falling 64² sheet at 8 steps per
//! frame the iteration then crawled at 0.6 per iteration.) The multipliers
//! start from the previous step's (warm start). The iteration stops when
//! every edge holds to round-off,
//! `|g_c| ≤ 32·ε·L_c²·(1 + ‖q‖_∞/L_c)` ([`CONSTRAINT_TOLERANCE`]); after
//! [`RattleSettings::max_iterations`] it is an error that the run reports
//! with the step and time, never a step accepted off the manifold.
//!
//! **The velocity projection** `G(q')·G(q')ᵀ·μ = G(q')·p̃` is made only
//! where a state is handed out, at the end of a frame ([`ClothStepper::leave`]).
//! Between frames the steps carry the unprojected `p̃` on (SHAKE's form of
//! RATTLE): the next step's constraint impulse acts along the same
//! `G(q')ᵀ` as the projection's, so its multipliers take the projection's
//! up and the positions are the same as with a projection after every
//! step; the momentum handed out at a frame is RATTLE's. At the next frame
//! the steps go on from the carried `p̃`. This halves the solves of a step
//! (a projection took as many as a position solve). Every
//! [`RattleSettings::refactor_every`] steps (default 6) the factor of
//! `G(q')·G(q')ᵀ` is renewed for the next position solves; the projection
//! solves directly where the factor is of its `q'`, and otherwise runs
//! conjugate gradients preconditioned with the last factor, to the
//! round-off of the right-hand side (its residual is `G(q')·p'` itself),
//! falling back to a factorisation if they do not get there in
//! [`RattleSettings::max_pcg`] iterations.
//!
//! The symbolic analysis of `G·Gᵀ` (its pattern never changes) is made once
//! with the model.
//!
//! [`CONSTRAINT_TOLERANCE`]: crate::model::CONSTRAINT_TOLERANCE

use std::sync::Arc;
use std::time::Instant;

use integrator_core::Separable;

use integrator_core::checkpoint::{CheckpointError, Decoder, Encoder};

use super::{ClothStepper, Refused, SolverStats, StepError};
use crate::model::constraints::{EdgeConstraints, Gram, Jacobian, q_max};
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
    /// (default false: measured on the 64² sheet, the per-edge loops took
    /// 6.1 ms per frame on two threads against 2.2 ms on one, and faer's
    /// factorisation and solves gained nothing; see docs/results/cloth-inextensible.md).
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
}

impl Default for RattleSettings {
    fn default() -> Self {
        RattleSettings {
            max_iterations: 50,
            contraction: 0.5,
            parallel: false,
            refactor_every: 6,
            max_pcg: 12,
        }
    }
}

/// Where the stepping time went (s).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timing {
    /// The soft forces `−∇V` (springs, gravity, colliders).
    pub forces: f64,
    /// Edge vectors, residuals, `G·v`, `Gᵀ·λ` and the vector updates.
    pub constraints: f64,
    /// Assembling `G·Gᵀ` and its numeric Cholesky factorisation.
    pub factorize: f64,
    /// Triangular solves with the factor.
    pub solve: f64,
}

/// What the constraint solver did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    pub steps: usize,
    /// Simplified Newton iterations of the position solves, in all.
    pub iterations: usize,
    /// The most iterations one position solve took.
    pub max_iterations: usize,
    /// Numeric Cholesky factorisations of `G·Gᵀ` (one at the start, one
    /// every [`RattleSettings::refactor_every`] steps, and one where a
    /// frame's projection fell back to it).
    pub factorizations: usize,
    /// Numeric LU factorisations of the true Jacobian `G(q')·G(q)ᵀ` (the
    /// position solve's refreshes), and their symbolic analyses (0 or 1).
    pub lu_factorizations: usize,
    pub symbolic_lu: usize,
    /// Preconditioned conjugate-gradient iterations of the velocity
    /// projections that reused an earlier factor, and the projections that
    /// fell back to a factorisation.
    pub pcg_iterations: usize,
    pub pcg_failures: usize,
    /// The largest scaled residual `max_c |g_c|/(L_c(L_c + ‖q‖_∞))` a step
    /// ended with (at most [`CONSTRAINT_TOLERANCE`]).
    pub max_residual: f64,
    /// The largest transverse-wave number `h·ω = 4·√(½·Σ_c Λ_c)` a step
    /// ended with (its tensions; RATTLE is stable only below 2, so this is
    /// how close the run came to its step's limit).
    pub max_wave_number: f64,
    pub seconds: Timing,
}

impl Stats {
    /// Position iterations per step.
    pub fn iterations_per_step(&self) -> f64 {
        self.iterations as f64 / self.steps.max(1) as f64
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

/// RATTLE as a [`ClothStepper`].
pub struct RattleStepper {
    constraints: Arc<EdgeConstraints>,
    gram: Gram,
    jacobian: Jacobian,
    settings: RattleSettings,
    n3: usize,
    /// Edge vectors at the step's start `q`, and at the iterate `q'`.
    d: Vec<[f64; 3]>,
    d1: Vec<[f64; 3]>,
    /// Scaled multipliers `Λ = h²λ/(2m)` (warm start), with the `h` they
    /// were made for.
    lambda: Vec<f64>,
    /// The previous step's multipliers, and how many steps in a row were
    /// solved since the last restart (two are needed to extrapolate).
    lambda_prev: Vec<f64>,
    solved: usize,
    lambda_h: f64,
    g: Vec<f64>,
    delta: Vec<f64>,
    /// The velocity projection's right-hand side and the conjugate
    /// gradients' vectors.
    b: Vec<f64>,
    r: Vec<f64>,
    z: Vec<f64>,
    pdir: Vec<f64>,
    ap: Vec<f64>,
    /// Steps since the last factorisation.
    since_factor: usize,
    /// Whether the last position solve refreshed the true Jacobian's LU.
    stale: bool,
    /// The largest `h·ω` of the last step solved.
    last_wave_number: f64,
    /// The force at `cached_q`; `valid`: `cached_q`, `force`, `d` and the
    /// factor of `G(q)G(q)ᵀ` belong to the state the last step ended with.
    force: Vec<f64>,
    cached_q: Vec<f64>,
    valid: bool,
    qhat: Vec<f64>,
    q1: Vec<f64>,
    w: Vec<f64>,
    phalf: Vec<f64>,
    /// At the end of a frame: the unprojected momentum the steps carry on
    /// with, and the projected one handed out (`resume`: both belong to
    /// the state the last frame ended with).
    p_carried: Vec<f64>,
    p_out: Vec<f64>,
    resume: bool,
    /// Whether the step being taken started from an unprojected momentum,
    /// so that its multipliers carry the skipped projection's too.
    carried: bool,
    stats: Stats,
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
        let n3 = 3 * model.free_count();
        let nc = constraints.len();
        Ok(RattleStepper {
            gram: Gram::new(constraints.clone(), settings.parallel),
            jacobian: Jacobian::new(constraints.clone(), settings.parallel),
            constraints: constraints.clone(),
            settings,
            n3,
            d: vec![[0.0; 3]; nc],
            d1: vec![[0.0; 3]; nc],
            lambda: vec![0.0; nc],
            lambda_prev: vec![0.0; nc],
            solved: 0,
            lambda_h: h,
            g: vec![0.0; nc],
            delta: vec![0.0; nc],
            b: vec![0.0; nc],
            r: vec![0.0; nc],
            z: vec![0.0; nc],
            pdir: vec![0.0; nc],
            ap: vec![0.0; nc],
            since_factor: 0,
            stale: false,
            last_wave_number: 0.0,
            force: vec![0.0; n3],
            cached_q: vec![0.0; n3],
            valid: false,
            qhat: vec![0.0; n3],
            q1: vec![0.0; n3],
            w: vec![0.0; n3],
            phalf: vec![0.0; n3],
            p_carried: vec![0.0; n3],
            p_out: vec![0.0; n3],
            resume: false,
            carried: false,
            stats: Stats::default(),
        })
    }

    /// The force, edge vectors and factor at `q` (the start of a run, or
    /// after the loop restored a state).
    fn prepare(&mut self, model: &ClothModel, q: &[f64]) -> Result<(), RattleError> {
        let par = self.settings.parallel;
        let t0 = Instant::now();
        model.force(q, &mut self.force);
        let t1 = Instant::now();
        self.constraints.edge_vectors(q, &mut self.d, par);
        let t2 = Instant::now();
        let factored = self.gram.factorize(&self.d);
        let t3 = Instant::now();
        let s = &mut self.stats.seconds;
        s.forces += (t1 - t0).as_secs_f64();
        s.constraints += (t2 - t1).as_secs_f64();
        s.factorize += (t3 - t2).as_secs_f64();
        self.stats.factorizations += 1;
        factored.map_err(|_| RattleError::NotPositive {
            phase: "position solve",
        })?;
        self.cached_q.copy_from_slice(q);
        self.valid = true;
        Ok(())
    }

    /// The position solve: `q1 = q̂ − G(q)ᵀΛ` with `g(q1) = 0`; leaves
    /// `w = G(q)ᵀΛ` and the edge vectors at `q1` in `d1`.
    fn position_solve(&mut self, q_scale: f64) -> Result<(), RattleError> {
        let par = self.settings.parallel;
        let c = &*self.constraints;
        let mut previous = f64::INFINITY;
        let mut iterations = 0;
        // Whether the iteration runs on the LU of the true Jacobian.
        let mut exact = false;
        loop {
            let t0 = Instant::now();
            c.apply_gt(&self.d, &self.lambda, &mut self.w, par);
            for ((x, qh), w) in self.q1.iter_mut().zip(&self.qhat).zip(&self.w) {
                *x = qh - w;
            }
            c.edge_vectors(&self.q1, &mut self.d1, par);
            let residual = c.residuals(&self.d1, q_scale, &mut self.g, par);
            self.stats.seconds.constraints += t0.elapsed().as_secs_f64();
            if residual <= CONSTRAINT_TOLERANCE {
                self.stats.iterations += iterations;
                self.stats.max_iterations = self.stats.max_iterations.max(iterations);
                self.stats.max_residual = self.stats.max_residual.max(residual);
                return Ok(());
            }
            if !residual.is_finite() {
                return Err(RattleError::Diverged { residual });
            }
            if iterations == self.settings.max_iterations {
                return Err(RattleError::NotConverged {
                    iterations,
                    residual,
                    tolerance: CONSTRAINT_TOLERANCE,
                    wave_number: self.last_wave_number,
                });
            }
            if residual > self.settings.contraction * previous {
                let t = Instant::now();
                let refreshed = self.jacobian.factorize(&self.d, &self.d1);
                self.stats.seconds.factorize += t.elapsed().as_secs_f64();
                self.stats.lu_factorizations += 1;
                self.stats.symbolic_lu += usize::from(matches!(refreshed, Ok(true)));
                refreshed.map_err(|_| RattleError::Singular)?;
                exact = true;
                self.stale = true;
            }
            previous = residual;
            let t = Instant::now();
            self.delta.copy_from_slice(&self.g);
            if exact {
                self.jacobian.solve(&mut self.delta);
            } else {
                self.gram.solve(&mut self.delta);
            }
            self.stats.seconds.solve += t.elapsed().as_secs_f64();
            for (l, dl) in self.lambda.iter_mut().zip(&self.delta) {
                *l += dl;
            }
            iterations += 1;
        }
    }

    /// The velocity projection's `G(q')·G(q')ᵀ·μ = b` (`b` in `self.b`,
    /// `μ` left in `self.delta`) by conjugate gradients preconditioned with
    /// the factor of an earlier step's `G·Gᵀ`, instead of a new
    /// factorisation. Converged when the residual, which is `G(q')·p'`
    /// itself, is at the round-off of computing `b`:
    /// `‖r‖∞ ≤ 64·ε·2·L_max·‖p̃‖∞`. `false` (and nothing kept) when it is not
    /// within [`RattleSettings::max_pcg`] iterations: the caller factorises.
    fn pcg(&mut self) -> bool {
        let par = self.settings.parallel;
        let c = &*self.constraints;
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let tol = 64.0 * f64::EPSILON * 2.0 * c.max_rest() * q_max(&self.phalf);
        if q_max(&self.b) <= tol {
            self.delta.fill(0.0);
            return true;
        }
        self.delta.fill(0.0);
        self.r.copy_from_slice(&self.b);
        self.z.copy_from_slice(&self.r);
        self.gram.solve(&mut self.z);
        self.pdir.copy_from_slice(&self.z);
        let mut rz = dot(&self.r, &self.z);
        for it in 1..=self.settings.max_pcg {
            c.apply_gt(&self.d, &self.pdir, &mut self.w, par);
            c.apply_g(&self.d, &self.w, &mut self.ap, par);
            let alpha = rz / dot(&self.pdir, &self.ap);
            for ((x, r), (pd, ap)) in self
                .delta
                .iter_mut()
                .zip(self.r.iter_mut())
                .zip(self.pdir.iter().zip(&self.ap))
            {
                *x += alpha * pd;
                *r -= alpha * ap;
            }
            if q_max(&self.r) <= tol {
                self.stats.pcg_iterations += it;
                return true;
            }
            self.z.copy_from_slice(&self.r);
            self.gram.solve(&mut self.z);
            let rz_new = dot(&self.r, &self.z);
            let beta = rz_new / rz;
            rz = rz_new;
            for (pd, z) in self.pdir.iter_mut().zip(&self.z) {
                *pd = z + beta * *pd;
            }
        }
        self.stats.pcg_failures += 1;
        false
    }

    fn step_inner(&mut self, model: &ClothModel, h: f64, z: &mut [f64]) -> Result<(), RattleError> {
        let n3 = self.n3;
        let (m, inv_m) = (model.particle_mass(), model.inverse_mass());
        let (q, p) = z.split_at_mut(n3);
        if !self.valid || self.cached_q != *q {
            self.solved = 0;
            self.carried = false;
            self.prepare(model, q)?;
        }
        self.valid = false;
        // Multipliers that also take up the skipped projection's are two
        // half-steps' impulses: the tension is measured by half of them.
        let impulses: f64 = if self.carried { 2.0 } else { 1.0 };
        // Warm start: Λ = h²λ/(2m) scales with h².
        if self.lambda_h != h {
            let s = (h / self.lambda_h).powi(2);
            self.lambda.iter_mut().for_each(|l| *l *= s);
            self.lambda_prev.iter_mut().for_each(|l| *l *= s);
            self.lambda_h = h;
        }
        // The multipliers are smooth in time: start from the linear
        // extrapolation of the last two steps' (the last one's after a
        // restart), an error of O(h²) instead of O(h).
        if self.solved >= 2 {
            for (l, lp) in self.lambda.iter_mut().zip(self.lambda_prev.iter_mut()) {
                let last = *l;
                *l = 2.0 * last - *lp;
                *lp = last;
            }
        } else {
            self.lambda_prev.copy_from_slice(&self.lambda);
        }
        let t0 = Instant::now();
        let half = 0.5 * h;
        for (((ph, qh), (&pk, &fk)), &qk) in self
            .phalf
            .iter_mut()
            .zip(self.qhat.iter_mut())
            .zip(p.iter().zip(&self.force))
            .zip(q.iter())
        {
            *ph = pk + half * fk;
            *qh = qk + h * inv_m * *ph;
        }
        self.stats.seconds.constraints += t0.elapsed().as_secs_f64();
        let q_scale = q_max(q).max(q_max(&self.qhat));
        self.position_solve(q_scale)?;
        let t_wave = Instant::now();
        self.last_wave_number = self.constraints.wave_number(&self.lambda) / impulses.sqrt();
        self.stats.max_wave_number = self.stats.max_wave_number.max(self.last_wave_number);
        self.stats.seconds.constraints += t_wave.elapsed().as_secs_f64();
        // p½ = p + h/2·F(q) − (m/h)·G(q)ᵀΛ; then the force at q'.
        let t1 = Instant::now();
        let scale = m / h;
        for (ph, w) in self.phalf.iter_mut().zip(&self.w) {
            *ph -= scale * w;
        }
        let t2 = Instant::now();
        model.force(&self.q1, &mut self.force);
        let t3 = Instant::now();
        for (ph, f) in self.phalf.iter_mut().zip(&self.force) {
            *ph += half * f;
        }
        // No velocity projection between the frames (SHAKE's form of the
        // same steps): p̃ goes on to the next step, whose multipliers take
        // up the projection's. Every `refactor_every` steps the factor of
        // G(q')·G(q')ᵀ is renewed for the next position solves.
        std::mem::swap(&mut self.d, &mut self.d1);
        p.copy_from_slice(&self.phalf);
        q.copy_from_slice(&self.q1);
        self.cached_q.copy_from_slice(&self.q1);
        let t4 = Instant::now();
        // Renewed early when this step's solve had to leave the factor for
        // the LU of the true Jacobian: the sheet turns too fast for it.
        let due = (self.settings.refactor_every != 0
            && self.since_factor + 1 >= self.settings.refactor_every)
            || std::mem::take(&mut self.stale);
        if due {
            let factored = self.gram.factorize(&self.d);
            self.stats.factorizations += 1;
            self.since_factor = 0;
            factored.map_err(|_| RattleError::NotPositive {
                phase: "position solve",
            })?;
        } else {
            self.since_factor += 1;
        }
        let t5 = Instant::now();
        let s = &mut self.stats.seconds;
        s.constraints += (t2 - t1).as_secs_f64() + (t4 - t3).as_secs_f64();
        s.forces += (t3 - t2).as_secs_f64();
        s.factorize += (t5 - t4).as_secs_f64();
        self.stats.steps += 1;
        self.solved += 1;
        self.carried = true;
        self.valid = true;
        Ok(())
    }

    /// The velocity projection of the state the steps left in `z`:
    /// `p' = p̃ − G(q')ᵀμ` with `G(q')·G(q')ᵀ·μ = G(q')·p̃`, directly where
    /// the factor is of this `q'`, else by conjugate gradients preconditioned
    /// with the older factor, falling back to a new factorisation (which
    /// then serves the next position solves too).
    fn project(&mut self, z: &mut [f64]) -> Result<(), RattleError> {
        let par = self.settings.parallel;
        let (_, p) = z.split_at_mut(self.n3);
        self.phalf.copy_from_slice(p);
        let t4 = Instant::now();
        self.constraints
            .apply_g(&self.d, &self.phalf, &mut self.b, par);
        let t5 = Instant::now();
        let mut factorizing = 0.0;
        if self.since_factor == 0 {
            self.delta.copy_from_slice(&self.b);
            self.gram.solve(&mut self.delta);
        } else if !self.pcg() {
            let t6 = Instant::now();
            let factored = self.gram.factorize(&self.d);
            factorizing = t6.elapsed().as_secs_f64();
            self.stats.factorizations += 1;
            self.since_factor = 0;
            factored.map_err(|_| RattleError::NotPositive {
                phase: "velocity projection",
            })?;
            self.delta.copy_from_slice(&self.b);
            self.gram.solve(&mut self.delta);
        }
        let t7 = Instant::now();
        self.constraints
            .apply_gt(&self.d, &self.delta, &mut self.w, par);
        for ((pk, ph), w) in p.iter_mut().zip(&self.phalf).zip(&self.w) {
            *pk = ph - w;
        }
        let t8 = Instant::now();
        let s = &mut self.stats.seconds;
        s.constraints += (t5 - t4).as_secs_f64() + (t8 - t7).as_secs_f64();
        // Conjugate gradients count as solves; a factorisation as
        // factorisation, its solve as a solve.
        s.factorize += factorizing;
        s.solve += (t7 - t5).as_secs_f64() - factorizing;
        Ok(())
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
        self.step_inner(model, h, z).map_err(StepError::Constraint)
    }

    /// Carry on from the unprojected momentum the last frame ended with,
    /// where `z` is still the state handed out then.
    fn enter(&mut self, _model: &ClothModel, _t: f64, z: &mut [f64]) {
        let (q, p) = z.split_at_mut(self.n3);
        if self.resume && self.valid && self.cached_q == *q && self.p_out == *p {
            p.copy_from_slice(&self.p_carried);
        } else {
            self.carried = false;
        }
        self.resume = false;
    }

    /// Hand out `[q; p]` with `p` projected onto the tangent space
    /// (`G(q)·M⁻¹·p = 0`), as RATTLE's own step ends. The positions do not
    /// depend on it: the next step's multipliers would take it up.
    fn leave(&mut self, _model: &ClothModel, _t: f64, z: &mut [f64]) {
        if !(self.valid && self.carried) {
            return;
        }
        self.p_carried.copy_from_slice(&z[self.n3..]);
        match self.project(z) {
            Ok(()) => {
                self.p_out.copy_from_slice(&z[self.n3..]);
                self.resume = true;
            }
            Err(_) => {
                // Not positive definite at the end of a step that solved:
                // leave p̃ as it is; the next step will fail on the same
                // matrix and report it with its step and time.
                z[self.n3..].copy_from_slice(&self.p_carried);
                self.valid = false;
            }
        }
    }

    fn stats(&self) -> SolverStats {
        SolverStats::Constrained(self.stats)
    }

    /// Everything the next steps read before writing: the carried p̃ and
    /// the momentum handed out (to recognise the frame's state in
    /// `enter`), the warm-start multipliers and their extrapolation count,
    /// the factor of `G·Gᵀ` (of the configuration of its last renewal,
    /// not of the current one) and the steps since it, the force and edge
    /// vectors at `q`, the flags, and the statistics.
    fn save(&self, e: &mut Encoder) -> bool {
        let d: Vec<f64> = self.d.iter().flatten().copied().collect();
        e.f64s(&self.lambda)
            .f64s(&self.lambda_prev)
            .usize(self.solved)
            .f64(self.lambda_h)
            .usize(self.since_factor)
            .bool(self.stale)
            .f64(self.last_wave_number)
            .f64s(&self.force)
            .f64s(&self.cached_q)
            .bool(self.valid)
            .f64s(&d)
            .f64s(self.gram.factor())
            .f64s(&self.p_carried)
            .f64s(&self.p_out)
            .bool(self.resume)
            .bool(self.carried);
        let st = &self.stats;
        e.usize(st.steps)
            .usize(st.iterations)
            .usize(st.max_iterations)
            .usize(st.factorizations)
            .usize(st.lu_factorizations)
            .usize(st.symbolic_lu)
            .usize(st.pcg_iterations)
            .usize(st.pcg_failures)
            .f64(st.max_residual)
            .f64(st.max_wave_number)
            .f64(st.seconds.forces)
            .f64(st.seconds.constraints)
            .f64(st.seconds.factorize)
            .f64(st.seconds.solve);
        true
    }

    fn restore(&mut self, _model: &ClothModel, r: &mut Decoder<'_>) -> Result<(), CheckpointError> {
        r.f64s_into(&mut self.lambda, "rattle.lambda")?;
        r.f64s_into(&mut self.lambda_prev, "rattle.lambda_prev")?;
        self.solved = r.usize("rattle.solved")?;
        self.lambda_h = r.f64("rattle.lambda_h")?;
        self.since_factor = r.usize("rattle.since_factor")?;
        self.stale = r.bool("rattle.stale")?;
        self.last_wave_number = r.f64("rattle.last_wave_number")?;
        r.f64s_into(&mut self.force, "rattle.force")?;
        r.f64s_into(&mut self.cached_q, "rattle.cached_q")?;
        self.valid = r.bool("rattle.valid")?;
        let mut d = vec![0.0; 3 * self.d.len()];
        r.f64s_into(&mut d, "rattle.edge_vectors")?;
        for (x, c) in self.d.iter_mut().zip(d.chunks_exact(3)) {
            *x = [c[0], c[1], c[2]];
        }
        r.f64s_into(self.gram.factor_mut(), "rattle.factor")?;
        r.f64s_into(&mut self.p_carried, "rattle.p_carried")?;
        r.f64s_into(&mut self.p_out, "rattle.p_out")?;
        self.resume = r.bool("rattle.resume")?;
        self.carried = r.bool("rattle.carried")?;
        let st = &mut self.stats;
        st.steps = r.usize("rattle.stats")?;
        st.iterations = r.usize("rattle.stats")?;
        st.max_iterations = r.usize("rattle.stats")?;
        st.factorizations = r.usize("rattle.stats")?;
        st.lu_factorizations = r.usize("rattle.stats")?;
        st.symbolic_lu = r.usize("rattle.stats")?;
        st.pcg_iterations = r.usize("rattle.stats")?;
        st.pcg_failures = r.usize("rattle.stats")?;
        st.max_residual = r.f64("rattle.stats")?;
        st.max_wave_number = r.f64("rattle.stats")?;
        st.seconds.forces = r.f64("rattle.stats")?;
        st.seconds.constraints = r.f64("rattle.stats")?;
        st.seconds.factorize = r.f64("rattle.stats")?;
        st.seconds.solve = r.f64("rattle.stats")?;
        Ok(())
    }
}
