//! One step of a Lobatto IIIA–IIIB pair on a constrained system with dense
//! linear algebra. RATTLE (`s = 2`) is the one RATTLE of
//! [`rattle`](super::rattle) with dense LU factors; the pairs with `s ≥ 3`
//! take the stage Newton here: the position step (stages and their
//! multipliers, by Newton's method with a dense LU) and the velocity step
//! (the last multiplier, a projection onto the tangent space).

// The Newton matrix is assembled by block indices.
#![allow(clippy::needless_range_loop)]

use super::dense_lu::DenseLu;
use super::dense_rattle::{DenseGram, DenseSystem};
use super::error::{ConstrainedError, Where};
use super::rattle::{Projection, Rattle, RattleError, Settings};
use super::system::{Constrained, inf_norm};
use super::table::{LobattoPair, lobatto3a3b3, rattle};

/// When the Newton iteration stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonSettings {
    /// The iteration cap; reaching it is an error
    /// ([`ConstrainedError::NotConverged`]), never a silent acceptance.
    pub max_iterations: usize,
    /// RATTLE: stop when every `|gₗ(q₁)|` is within `tolerance` units of
    /// its round-off `ε·‖∇gₗ‖₁·‖q‖∞` (the residual of the
    /// [`rattle`](super::rattle) position solve, in the scale of
    /// [`Residual`](super::Residual)). `s ≥ 3`: stop when the last correction of every stage position is below
    /// `tolerance·ε·‖q‖∞` and that of every stage momentum below
    /// `tolerance·ε·max(‖p‖∞, ‖Δp‖∞, m‖q‖∞/h)` (`Δp` the step's change of
    /// momentum; `m‖q‖/h` because the multipliers are fixed through the
    /// positions): the round-off of the state, hence of the constraints. A
    /// correction that stops shrinking while below `4·tolerance` has reached
    /// the floor of rounding and is accepted too, and so is one whose
    /// contraction `θ` predicts less than one unit of round-off for the rest
    /// of the iteration (`θ/(1 − θ)·correction ≤ 1`).
    pub tolerance: f64,
    /// How far the initial state may be off the manifold, in units of
    /// `ε·scale` of each residual (see
    /// [`Residual::scale`](super::Residual::scale)).
    pub start_tolerance: f64,
    /// Use the system's [`curvature`](super::Constrained::curvature), where
    /// it provides one, for Newton's method proper on the full system of
    /// stages and multipliers (size `(s−1)(d + m)`). Off, or without it, the
    /// `O(h²)` curvature blocks are dropped and the stages eliminated: a
    /// simplified Newton iteration on the multipliers alone (size
    /// `(s−1)m`), more iterations of a smaller solve, the same result to
    /// round-off. RATTLE (s = 2) has no such term: its position solve is on
    /// the multipliers alone.
    pub curvature: bool,
}

impl Default for NewtonSettings {
    fn default() -> Self {
        NewtonSettings {
            max_iterations: 50,
            tolerance: 16.0,
            start_tolerance: 64.0,
            curvature: true,
        }
    }
}

/// A Lobatto IIIA–IIIB pair applied to a [`Constrained`] system: RATTLE
/// for `S = 2`, order 4 for `S = 3`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstrainedPair<const S: usize> {
    pub pair: LobattoPair<S>,
    pub settings: NewtonSettings,
}

impl ConstrainedPair<2> {
    /// RATTLE (Andersen 1983), the s = 2 pair: with `λ = Λ₁` and `μ = Λ₂`,
    ///
    /// ```text
    /// p½ = p₀ − h/2 (∇V(q₀) + G(q₀)ᵀλ)
    /// q₁ = q₀ + h M⁻¹ p½,                 g(q₁) = 0          (position step: λ)
    /// p₁ = p½ − h/2 (∇V(q₁) + G(q₁)ᵀμ),   G(q₁) M⁻¹ p₁ = 0   (velocity step: μ)
    /// ```
    ///
    /// stepped by the one RATTLE ([`Rattle`]) with dense LU factors: a
    /// simplified Newton iteration on `λ` with the factor of
    /// `G(q₀)M⁻¹G(q₀)ᵀ` (the true Jacobian `G(q₁)M⁻¹G(q₀)ᵀ` when it stops
    /// contracting), warm-started by extrapolating the last two steps'
    /// multipliers, and the projection solved directly after every step.
    pub fn rattle() -> Self {
        ConstrainedPair {
            pair: rattle(),
            settings: NewtonSettings::default(),
        }
    }
}

impl ConstrainedPair<3> {
    /// The s = 3 pair, order 4.
    pub fn lobatto3a3b3() -> Self {
        ConstrainedPair {
            pair: lobatto3a3b3(),
            settings: NewtonSettings::default(),
        }
    }
}

/// What one step needs besides the state, made once per run. It carries
/// the multipliers of the last step (the warm start of the next) and counts
/// the steps, so that errors name the step.
pub struct ConstrainedWorkspace {
    d: usize,
    m: usize,
    s: usize,
    minv: Vec<f64>,
    max_minv: f64,
    q0: Vec<f64>,
    p0: Vec<f64>,
    /// Stage positions `Q_k`, `s × d` (`Q₀ = q₀`).
    qs: Vec<f64>,
    /// Scaled multipliers `ν_k = h²Λ_k`, `s × m` (the last is set by the
    /// velocity step).
    nu: Vec<f64>,
    /// `∇V(Q_k)`, `s × d`.
    grad: Vec<f64>,
    /// `G(Q_k)`, `s × m × d`.
    gq: Vec<f64>,
    /// The columns where each row of `G(Q_k)` is nonzero (`s × m` lists),
    /// so that products with `G` cost its nonzeros, not `m·d`.
    nz: Vec<Vec<usize>>,
    /// `Fₖ = h²∇V(Qₖ) + G(Qₖ)ᵀνₖ`, `s × d`.
    force: Vec<f64>,
    /// Stage momenta `P_k`, `s × d`.
    ps: Vec<f64>,
    gval: Vec<f64>,
    lam: Vec<f64>,
    curv: Vec<f64>,
    pt: Vec<f64>,
    mu: Vec<f64>,
    /// Newton residual, correction.
    r: Vec<f64>,
    /// `curvature` was provided at the last stage (`None`: not asked yet).
    curvature: Option<bool>,
    lu: DenseLu,
    lu_m: DenseLu,
    rhs_m: Vec<f64>,
    lu_red: DenseLu,
    rhs_red: Vec<f64>,
    /// Physical multipliers `Λ_k` of the last step (`s × m`), if any.
    last_lambda: Option<Vec<f64>>,
    /// RATTLE (`s = 2`): the one RATTLE with dense factors, made at the
    /// first step (it needs `h`), and the state before a step, restored
    /// when the step fails.
    rattle: Option<Rattle<Vec<f64>, DenseGram>>,
    z_keep: Vec<f64>,
    /// Steps taken with this workspace.
    pub steps: usize,
    /// Newton iterations of the last step.
    pub iterations: usize,
    /// Newton iterations of all steps.
    pub total_iterations: usize,
}

impl ConstrainedWorkspace {
    /// The multipliers `Λ₁ … Λ_s` of the last step, `s × m` row-major.
    pub fn multipliers(&self) -> Option<&[f64]> {
        self.last_lambda.as_deref()
    }

    /// Forget the last step's multipliers (the next step starts cold).
    pub fn reset(&mut self) {
        self.last_lambda = None;
        self.rattle = None;
        self.steps = 0;
    }
}

impl<const S: usize> ConstrainedPair<S> {
    /// The pair with other Newton settings.
    pub fn with_settings(mut self, settings: NewtonSettings) -> Self {
        self.settings = settings;
        self
    }

    /// A workspace for `sys`.
    pub fn workspace<Sys: Constrained + ?Sized>(&self, sys: &Sys) -> ConstrainedWorkspace {
        let (d, m) = (sys.dof(), sys.constraints());
        let n = (S - 1) * (d + m);
        let mut minv = vec![0.0; d];
        sys.inverse_mass(&mut minv);
        ConstrainedWorkspace {
            d,
            m,
            s: S,
            max_minv: minv.iter().fold(0.0, |a: f64, &b| a.max(b)),
            minv,
            q0: vec![0.0; d],
            p0: vec![0.0; d],
            qs: vec![0.0; S * d],
            nu: vec![0.0; S * m],
            grad: vec![0.0; S * d],
            gq: vec![0.0; S * m * d],
            nz: vec![Vec::new(); S * m],
            force: vec![0.0; S * d],
            ps: vec![0.0; S * d],
            gval: vec![0.0; m],
            lam: vec![0.0; m],
            curv: vec![0.0; d * d],
            pt: vec![0.0; d],
            mu: vec![0.0; m],
            r: vec![0.0; n],
            curvature: None,
            lu: DenseLu::new(n),
            lu_m: DenseLu::new(m),
            rhs_m: vec![0.0; m],
            lu_red: DenseLu::new((S - 1) * m),
            rhs_red: vec![0.0; (S - 1) * m],
            last_lambda: None,
            rattle: None,
            z_keep: vec![0.0; 2 * d],
            steps: 0,
            iterations: 0,
            total_iterations: 0,
        }
    }

    /// One step of size `h` from `z = [q₀; p₀]` at time `t` (used only in
    /// messages), in place. `z` must be on the manifold (see
    /// [`check_start`](super::check_start)). Errors name the step (counted
    /// by `ws`) and `t`; `z` is unchanged when the step fails.
    ///
    /// RATTLE steps as [`ConstrainedPair::rattle`] says. For `s ≥ 3` the
    /// unknowns of the position step are the stage positions
    /// `Q₂ … Q_s` and the scaled multipliers `νₖ = h²Λₖ`, `k = 1 … s−1`
    /// (scaled so that the Newton matrix stays `O(1)` as `h → 0`); with
    /// `α = AÂ` and `cᵢ = Σⱼ aᵢⱼ` the equations are
    ///
    /// ```text
    /// Qᵢ − q₀ − h cᵢ M⁻¹p₀ + Σₖ αᵢₖ M⁻¹ (h²∇V(Qₖ) + G(Qₖ)ᵀνₖ) = 0,   g(Qᵢ) = 0,   i = 2 … s,
    /// ```
    ///
    /// (the stage momenta `Pⱼ = p₀ − Σₖ âⱼₖ (h∇V(Qₖ) + G(Qₖ)ᵀνₖ/h)`
    /// eliminated). The velocity step then fixes `Λ_s` by
    /// `G(q₁)M⁻¹p₁ = 0`: one solve with `G M⁻¹ Gᵀ`, plus one refinement.
    pub fn step<Sys: Constrained + ?Sized>(
        &self,
        sys: &Sys,
        t: f64,
        h: f64,
        z: &mut [f64],
        ws: &mut ConstrainedWorkspace,
    ) -> Result<(), ConstrainedError> {
        let place = Where::Step {
            step: ws.steps + 1,
            t,
        };
        let (d, m) = (ws.d, ws.m);
        if ws.s != S || sys.dof() != d || sys.constraints() != m {
            return Err(ConstrainedError::Workspace {
                detail: format!(
                    "made for {} stages, {d} coordinates and {m} constraints; asked for {S}, {} and {}",
                    ws.s,
                    sys.dof(),
                    sys.constraints()
                ),
            });
        }
        if z.len() != 2 * d {
            return Err(ConstrainedError::Dimension {
                expected: 2 * d,
                got: z.len(),
            });
        }
        if h == 0.0 || !h.is_finite() {
            return Err(ConstrainedError::StepSize(h));
        }
        if S == 2 {
            return self.rattle_step(sys, h, z, ws, place);
        }
        self.position_step(sys, h, z, ws).map_err(|e| e.at(place))?;
        self.velocity_step(sys, h, ws).map_err(|e| e.at(place))?;
        let q1 = &ws.qs[(S - 1) * d..S * d];
        if let Some(i) = q1.iter().chain(&ws.p0).position(|x| !x.is_finite()) {
            return Err(ConstrainedError::Diverged {
                where_: place,
                detail: format!("z[{i}] is not finite after the step"),
            });
        }
        // The new state; `ws.p0` holds p₁ after the velocity step.
        z[..d].copy_from_slice(q1);
        z[d..].copy_from_slice(&ws.p0);
        // Physical multipliers for the warm start of the next step.
        let mut lam = ws.last_lambda.take().unwrap_or_else(|| vec![0.0; S * m]);
        let h2 = h * h;
        for (l, nu) in lam.iter_mut().zip(&ws.nu) {
            *l = nu / h2;
        }
        ws.last_lambda = Some(lam);
        ws.steps += 1;
        ws.total_iterations += ws.iterations;
        Ok(())
    }

    /// RATTLE: one step of the one RATTLE ([`Rattle`]) with dense LU
    /// factors and a projection after every step, the position solve
    /// stopping at `settings.tolerance` units of round-off of each
    /// `gₗ(q₁)`. The multipliers kept are `Λ₁ = 2κ/h²` and `Λ₂ = 2μ/h`.
    fn rattle_step<Sys: Constrained + ?Sized>(
        &self,
        sys: &Sys,
        h: f64,
        z: &mut [f64],
        ws: &mut ConstrainedWorkspace,
        place: Where,
    ) -> Result<(), ConstrainedError> {
        let (d, m) = (ws.d, ws.m);
        let dsys = DenseSystem {
            sys,
            minv: &ws.minv,
            tolerance: self.settings.tolerance,
        };
        let settings = Settings {
            max_iterations: self.settings.max_iterations,
            contraction: 0.5,
            // A factor at every step's end: the next position solve and
            // this step's projection (a direct solve) use it.
            refactor_every: 1,
            // The plain simplified Newton iteration: with a factor at every
            // step there is little to accelerate.
            anderson: 0,
            max_pcg: 12,
            projection: Projection::EveryStep,
        };
        let rattle = ws
            .rattle
            .get_or_insert_with(|| Rattle::new(&dsys, DenseGram::new(m), h, settings));
        ws.z_keep.copy_from_slice(z);
        let before = rattle.stats().iterations;
        if let Err(e) = rattle.step(&dsys, h, z) {
            z.copy_from_slice(&ws.z_keep);
            // The next step starts afresh from the restored state.
            return Err(match e {
                RattleError::NotConverged {
                    iterations,
                    residual,
                    ..
                } => ConstrainedError::NotConverged {
                    where_: place,
                    iterations,
                    correction: residual,
                },
                RattleError::NotPositive { phase } => ConstrainedError::Degenerate {
                    where_: place,
                    detail: format!(
                        "G M⁻¹ Gᵀ is singular in the {phase}: the constraint gradients became dependent"
                    ),
                },
                RattleError::Singular => ConstrainedError::Degenerate {
                    where_: place,
                    detail: "the position solve's Jacobian G(q₁) M⁻¹ G(q₀)ᵀ is singular (the step may be too large for the constraints to turn)".into(),
                },
                RattleError::Diverged { residual } => ConstrainedError::Diverged {
                    where_: place,
                    detail: format!("the constraint residual is {residual:e} units of round-off"),
                },
            });
        }
        if let Some(i) = z.iter().position(|x| !x.is_finite()) {
            z.copy_from_slice(&ws.z_keep);
            return Err(ConstrainedError::Diverged {
                where_: place,
                detail: format!("z[{i}] is not finite after the step"),
            });
        }
        ws.iterations = rattle.stats().iterations - before;
        let mut lam = ws.last_lambda.take().unwrap_or_else(|| vec![0.0; 2 * m]);
        let h2 = h * h;
        for (l, k) in lam[..m].iter_mut().zip(rattle.multipliers()) {
            *l = 2.0 * k / h2;
        }
        for (l, mu) in lam[m..].iter_mut().zip(rattle.projection_multipliers()) {
            *l = 2.0 * mu / h;
        }
        ws.last_lambda = Some(lam);
        debug_assert_eq!(z.len(), 2 * d);
        ws.steps += 1;
        ws.total_iterations += ws.iterations;
        Ok(())
    }

    /// Evaluate `∇V` and `G` at stage `k`.
    fn evaluate_stage<Sys: Constrained + ?Sized>(
        sys: &Sys,
        ws: &mut ConstrainedWorkspace,
        k: usize,
    ) {
        let (d, m) = (ws.d, ws.m);
        let q = &ws.qs[k * d..(k + 1) * d];
        sys.grad_potential(q, &mut ws.grad[k * d..(k + 1) * d]);
        sys.constraint_jacobian(q, &mut ws.gq[k * m * d..(k + 1) * m * d]);
        for l in 0..m {
            let row = &ws.gq[k * m * d + l * d..k * m * d + (l + 1) * d];
            let nz = &mut ws.nz[k * m + l];
            nz.clear();
            nz.extend((0..d).filter(|&a| row[a] != 0.0));
        }
    }

    /// `Fₖ = h²∇V(Qₖ) + G(Qₖ)ᵀνₖ` for `k < s` into `ws.force`.
    fn forces(ws: &mut ConstrainedWorkspace, h2: f64) {
        let (d, m) = (ws.d, ws.m);
        for k in 0..S - 1 {
            let f = &mut ws.force[k * d..(k + 1) * d];
            for (fa, ga) in f.iter_mut().zip(&ws.grad[k * d..(k + 1) * d]) {
                *fa = h2 * ga;
            }
            for l in 0..m {
                let nu = ws.nu[k * m + l];
                let row = &ws.gq[k * m * d + l * d..k * m * d + (l + 1) * d];
                for &a in &ws.nz[k * m + l] {
                    f[a] += row[a] * nu;
                }
            }
        }
    }

    fn position_step<Sys: Constrained + ?Sized>(
        &self,
        sys: &Sys,
        h: f64,
        z: &[f64],
        ws: &mut ConstrainedWorkspace,
    ) -> Result<(), ConstrainedError> {
        let (d, m) = (ws.d, ws.m);
        let h2 = h * h;
        let alpha = self.pair.a_a_hat();
        let c = self.pair.c();
        let a_hat = self.pair.a_hat;
        let nq = (S - 1) * d;
        let start = Where::Start;
        ws.q0.copy_from_slice(&z[..d]);
        ws.p0.copy_from_slice(&z[d..]);
        for k in 0..S {
            ws.qs[k * d..(k + 1) * d].copy_from_slice(&z[..d]);
        }
        Self::evaluate_stage(sys, ws, 0);

        // Warm start: the last step's multipliers moved on by one step
        // (Λₖ + Λ_s − Λ₁, a linear extrapolation in time); cold: zero.
        match &ws.last_lambda {
            Some(lam) => {
                for k in 0..S - 1 {
                    for l in 0..m {
                        let shift = lam[(S - 1) * m + l] - lam[l];
                        ws.nu[k * m + l] = h2 * (lam[k * m + l] + shift);
                    }
                }
            }
            None => ws.nu.fill(0.0),
        }
        // Predicted stages: the equations with ∇V and G frozen at q₀.
        for i in 1..S {
            for a in 0..d {
                let mut f = 0.0;
                for k in 0..S - 1 {
                    let mut fk = h2 * ws.grad[a];
                    for l in 0..m {
                        fk += ws.gq[l * d + a] * ws.nu[k * m + l];
                    }
                    f += alpha[i][k] * fk;
                }
                ws.qs[i * d + a] = ws.q0[a] + h * c[i] * ws.minv[a] * ws.p0[a] - ws.minv[a] * f;
            }
        }

        // The curvature enters the Newton matrix only for s ≥ 3; without it
        // the stage corrections are eliminated and Newton runs on the
        // multipliers alone.
        if S >= 3 && self.settings.curvature && ws.curvature.is_none() {
            ws.lam.fill(0.0);
            let has = sys.curvature(&ws.q0, &ws.lam, &mut ws.curv);
            ws.curvature = Some(has);
        }
        let reduced = !self.settings.curvature || ws.curvature == Some(false);
        let tol = self.settings.tolerance;
        let mut correction = f64::INFINITY;
        ws.iterations = 0;
        let mut converged = false;
        while ws.iterations < self.settings.max_iterations {
            ws.iterations += 1;
            for k in 1..S {
                Self::evaluate_stage(sys, ws, k);
            }
            // Residual: R rows, then the constraint rows.
            Self::forces(ws, h2);
            for i in 1..S {
                for a in 0..d {
                    let mut f = 0.0;
                    for k in 0..S - 1 {
                        f += alpha[i][k] * ws.force[k * d + a];
                    }
                    ws.r[(i - 1) * d + a] =
                        ws.qs[i * d + a] - ws.q0[a] - h * c[i] * ws.minv[a] * ws.p0[a]
                            + ws.minv[a] * f;
                }
                sys.constraint(&ws.qs[i * d..(i + 1) * d], &mut ws.gval);
                ws.r[nq + (i - 1) * m..nq + i * m].copy_from_slice(&ws.gval);
            }
            if let Some(i) = ws.r.iter().position(|x| !x.is_finite()) {
                return Err(ConstrainedError::Diverged {
                    where_: start,
                    detail: format!(
                        "Newton iteration {}: residual {i} is not finite",
                        ws.iterations
                    ),
                });
            }
            // The Newton correction, into `ws.r`.
            if reduced {
                self.reduced_correction(ws, &alpha)?;
            } else {
                self.full_correction(sys, ws, h2, &alpha)?;
            }
            if let Some(i) = ws.r.iter().position(|x| !x.is_finite()) {
                return Err(ConstrainedError::Diverged {
                    where_: start,
                    detail: format!(
                        "Newton iteration {}: correction {i} is not finite",
                        ws.iterations
                    ),
                });
            }
            // Apply the correction and measure it in units of round-off.
            let mut dq: f64 = 0.0;
            for i in 1..S {
                for a in 0..d {
                    let dx = ws.r[(i - 1) * d + a];
                    ws.qs[i * d + a] += dx;
                    dq = dq.max(dx.abs());
                }
            }
            let mut dp: f64 = 0.0;
            for j in 0..S {
                for a in 0..d {
                    let mut x = 0.0;
                    for k in 0..S - 1 {
                        for l in 0..m {
                            x += a_hat[j][k] * ws.gq[k * m * d + l * d + a] * ws.r[nq + k * m + l];
                        }
                    }
                    dp = dp.max((x / h).abs());
                }
            }
            for k in 0..S - 1 {
                for l in 0..m {
                    ws.nu[k * m + l] += ws.r[nq + k * m + l];
                }
            }
            self.stage_momenta(ws, h);
            // The scales of round-off. Momenta are resolved only to the
            // rounding of the positions divided by the step (the
            // multipliers of an index-3 problem are fixed through positions,
            // `O(ε/h²)`), so a momentum correction is at round-off when it is
            // below `ε` times the larger of `‖p‖` (with the step's change of
            // momentum) and `m‖q‖/h`.
            let qscale = inf_norm(&ws.qs);
            let mut pscale = inf_norm(&ws.p0);
            for j in 0..S {
                for a in 0..d {
                    pscale = pscale.max((ws.ps[j * d + a] - ws.p0[a]).abs());
                }
            }
            pscale = pscale.max(qscale / (h.abs() * ws.max_minv));
            let eps = f64::EPSILON;
            let previous = correction;
            correction = (dq / (eps * qscale)).max(dp / (eps * pscale));
            if dq == 0.0 && dp == 0.0 {
                correction = 0.0;
            }
            // Converged: the correction is below the tolerance, or it stopped
            // shrinking while within four times the tolerance (the floor of
            // rounding in evaluating the residual: more iterations only
            // stir the last bits).
            //
            // Or: the contraction θ = correction/previous predicts that the
            // rest of the iteration would move the state by less than one
            // unit of round-off, θ/(1 − θ)·correction ≤ 1 (the stopping rule
            // of Hairer & Wanner, Solving ODEs II, IV.8, with the tolerance
            // at round-off); it saves the confirming iteration of a
            // quadratically converging Newton.
            let theta = correction / previous;
            let predicted = theta / (1.0 - theta) * correction;
            if correction <= tol
                || (correction <= 4.0 * tol && correction > 0.5 * previous)
                || (previous.is_finite() && theta < 1.0 && predicted <= 1.0)
            {
                converged = true;
                break;
            }
        }
        if !converged {
            return Err(ConstrainedError::NotConverged {
                where_: start,
                iterations: ws.iterations,
                correction,
            });
        }
        // ∇V and G at the converged stages, for the momenta.
        for k in 1..S {
            Self::evaluate_stage(sys, ws, k);
        }
        Ok(())
    }

    /// The full Newton matrix (size `(s−1)(d + m)`, with the curvature
    /// blocks) factorised by faer's dense LU; the correction replaces the
    /// residual in `ws.r`.
    fn full_correction<Sys: Constrained + ?Sized>(
        &self,
        sys: &Sys,
        ws: &mut ConstrainedWorkspace,
        h2: f64,
        alpha: &[[f64; S]; S],
    ) -> Result<(), ConstrainedError> {
        let (d, m) = (ws.d, ws.m);
        let nq = (S - 1) * d;
        let n = nq + (S - 1) * m;
        let start = Where::Start;
        // Newton matrix.
        ws.lu.clear();
        for i in 1..S {
            for a in 0..d {
                ws.lu.set((i - 1) * d + a, (i - 1) * d + a, 1.0);
            }
            for k in 0..S - 1 {
                let al = alpha[i][k];
                if al == 0.0 {
                    continue;
                }
                // ∂/∂νₖ: αᵢₖ M⁻¹ G(Qₖ)ᵀ.
                for a in 0..d {
                    for l in 0..m {
                        let g = ws.gq[k * m * d + l * d + a];
                        ws.lu
                            .set((i - 1) * d + a, nq + k * m + l, al * ws.minv[a] * g);
                    }
                }
                // ∂/∂Qₖ (k ≥ 1): αᵢₖ M⁻¹ (h²∇²V + Σ νₗ∇²gₗ), when provided.
                if k >= 1 && ws.curvature != Some(false) {
                    for l in 0..m {
                        ws.lam[l] = ws.nu[k * m + l] / h2;
                    }
                    let has = sys.curvature(&ws.qs[k * d..(k + 1) * d], &ws.lam, &mut ws.curv);
                    ws.curvature = Some(has);
                    if has {
                        for a in 0..d {
                            for e in 0..d {
                                let v = al * ws.minv[a] * h2 * ws.curv[a * d + e];
                                let (row, col) = ((i - 1) * d + a, (k - 1) * d + e);
                                let old = if row == col { 1.0 } else { 0.0 };
                                ws.lu.set(row, col, old + v);
                            }
                        }
                    }
                }
            }
            // ∂g(Qᵢ)/∂Qᵢ = G(Qᵢ).
            for l in 0..m {
                for a in 0..d {
                    ws.lu.set(
                        nq + (i - 1) * m + l,
                        (i - 1) * d + a,
                        ws.gq[i * m * d + l * d + a],
                    );
                }
            }
        }
        if let Some(k) = ws.lu.factor(4.0 * n as f64 * f64::EPSILON) {
            return Err(ConstrainedError::Degenerate {
                where_: start,
                detail: format!(
                    "the Newton matrix of the stage equations is singular at pivot {k} of {n} \
                     in iteration {} (G(Qᵢ) M⁻¹ G(Qₖ)ᵀ has lost rank)",
                    ws.iterations
                ),
            });
        }
        for x in ws.r.iter_mut() {
            *x = -*x;
        }
        ws.lu.solve(&mut ws.r);
        Ok(())
    }

    /// The Newton correction when `∂Rᵢ/∂Qₖ = δᵢₖI` (a system without
    /// curvature, or the curvature switched off): the stage
    /// corrections are eliminated,
    /// `ΔQᵢ = −Rᵢ − Σₖ αᵢₖ M⁻¹G(Qₖ)ᵀΔνₖ`, leaving the multiplier system
    /// `Σₖ αᵢₖ G(Qᵢ)M⁻¹G(Qₖ)ᵀ Δνₖ = g(Qᵢ) − G(Qᵢ)Rᵢ` of size `(s−1)m`.
    fn reduced_correction(
        &self,
        ws: &mut ConstrainedWorkspace,
        alpha: &[[f64; S]; S],
    ) -> Result<(), ConstrainedError> {
        let (d, m) = (ws.d, ws.m);
        let nq = (S - 1) * d;
        let nr = (S - 1) * m;
        ws.lu_red.clear();
        for i in 1..S {
            for k in 0..S - 1 {
                let al = alpha[i][k];
                if al == 0.0 {
                    continue;
                }
                for l in 0..m {
                    let gi = &ws.gq[i * m * d + l * d..i * m * d + (l + 1) * d];
                    for e in 0..m {
                        let gk = &ws.gq[k * m * d + e * d..k * m * d + (e + 1) * d];
                        let x: f64 = ws.nz[i * m + l]
                            .iter()
                            .map(|&a| gi[a] * ws.minv[a] * gk[a])
                            .sum();
                        ws.lu_red.set((i - 1) * m + l, k * m + e, al * x);
                    }
                }
            }
        }
        if let Some(k) = ws.lu_red.factor(4.0 * nr as f64 * f64::EPSILON) {
            return Err(ConstrainedError::Degenerate {
                where_: Where::Start,
                detail: format!(
                    "the multiplier matrix αᵢₖ G(Qᵢ) M⁻¹ G(Qₖ)ᵀ is singular at pivot {k} of {nr} \
                     in iteration {} (the step may be too large for the constraints to turn)",
                    ws.iterations
                ),
            });
        }
        for i in 1..S {
            for l in 0..m {
                let gi = &ws.gq[i * m * d + l * d..i * m * d + (l + 1) * d];
                let gr: f64 = ws.nz[i * m + l]
                    .iter()
                    .map(|&a| gi[a] * ws.r[(i - 1) * d + a])
                    .sum();
                ws.rhs_red[(i - 1) * m + l] = ws.r[nq + (i - 1) * m + l] - gr;
            }
        }
        ws.lu_red.solve(&mut ws.rhs_red);
        // ΔQᵢ = −Rᵢ − M⁻¹ Σₖ αᵢₖ G(Qₖ)ᵀΔνₖ, accumulated in ws.pt.
        for i in 1..S {
            ws.pt.fill(0.0);
            for k in 0..S - 1 {
                let al = alpha[i][k];
                if al == 0.0 {
                    continue;
                }
                for e in 0..m {
                    let x = al * ws.rhs_red[k * m + e];
                    let row = &ws.gq[k * m * d + e * d..k * m * d + (e + 1) * d];
                    for &a in &ws.nz[k * m + e] {
                        ws.pt[a] += row[a] * x;
                    }
                }
            }
            for a in 0..d {
                ws.r[(i - 1) * d + a] = -ws.r[(i - 1) * d + a] - ws.minv[a] * ws.pt[a];
            }
        }
        ws.r[nq..].copy_from_slice(&ws.rhs_red);
        Ok(())
    }

    /// `Pⱼ = p₀ − Σₖ âⱼₖ (h∇V(Qₖ) + G(Qₖ)ᵀνₖ/h)` (k < s: the last column
    /// of `Â` vanishes).
    fn stage_momenta(&self, ws: &mut ConstrainedWorkspace, h: f64) {
        let d = ws.d;
        Self::forces(ws, h * h);
        for j in 0..S {
            for a in 0..d {
                let mut f = 0.0;
                for k in 0..S - 1 {
                    f += self.pair.a_hat[j][k] * ws.force[k * d + a];
                }
                ws.ps[j * d + a] = ws.p0[a] - f / h;
            }
        }
    }

    /// `p̃ = p₀ − Σₖ<s bₖ(h∇V(Qₖ) + G(Qₖ)ᵀνₖ/h) − b_s h∇V(Q_s)`, then
    /// `p₁ = p̃ − G(q₁)ᵀμ` with `μ = h b_s Λ_s` from
    /// `(G M⁻¹ Gᵀ) μ = G M⁻¹ p̃` (the projection onto the tangent space in
    /// the metric `M⁻¹`), refined once. Leaves `p₁` in `ws.p0` and `ν_s`.
    fn velocity_step<Sys: Constrained + ?Sized>(
        &self,
        _sys: &Sys,
        h: f64,
        ws: &mut ConstrainedWorkspace,
    ) -> Result<(), ConstrainedError> {
        let (d, m) = (ws.d, ws.m);
        let h2 = h * h;
        let b = self.pair.b;
        Self::forces(ws, h2);
        for a in 0..d {
            let mut f = 0.0;
            for k in 0..S - 1 {
                f += b[k] * ws.force[k * d + a];
            }
            f += b[S - 1] * h2 * ws.grad[(S - 1) * d + a];
            ws.pt[a] = ws.p0[a] - f / h;
        }
        let g1 = &ws.gq[(S - 1) * m * d..S * m * d];
        let nz1 = &ws.nz[(S - 1) * m..S * m];
        ws.lu_m.clear();
        for l in 0..m {
            for k in 0..m {
                let x: f64 = nz1[l]
                    .iter()
                    .map(|&a| g1[l * d + a] * ws.minv[a] * g1[k * d + a])
                    .sum();
                ws.lu_m.set(l, k, x);
            }
        }
        if let Some(k) = ws.lu_m.factor(4.0 * m as f64 * f64::EPSILON) {
            return Err(ConstrainedError::Degenerate {
                where_: Where::Start,
                detail: format!(
                    "G(q₁) M⁻¹ G(q₁)ᵀ is singular at pivot {k} of {m} in the velocity step"
                ),
            });
        }
        ws.mu.fill(0.0);
        // The projection, then once more on its own rounding residual.
        for _round in 0..2 {
            for l in 0..m {
                ws.rhs_m[l] = nz1[l]
                    .iter()
                    .map(|&a| g1[l * d + a] * ws.minv[a] * ws.pt[a])
                    .sum();
            }
            ws.lu_m.solve(&mut ws.rhs_m);
            for l in 0..m {
                let x = ws.rhs_m[l];
                for &a in &nz1[l] {
                    ws.pt[a] -= g1[l * d + a] * x;
                }
            }
            for l in 0..m {
                ws.mu[l] += ws.rhs_m[l];
            }
        }
        // μ = h b_s Λ_s, stored as ν_s = h²Λ_s = h μ / b_s.
        for l in 0..m {
            ws.nu[(S - 1) * m + l] = h * ws.mu[l] / b[S - 1];
        }
        ws.p0.copy_from_slice(&ws.pt);
        Ok(())
    }
}
