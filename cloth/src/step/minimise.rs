//! The implicit midpoint family on cloth as energy minimisation.
//!
//! The derivation (a midpoint step of size `τ` is `x̄ = argmin (2/τ²)(x −
//! y)ᵀM(x − y) + V(x)` with `y = q + (τ/2)v`, then `q' = 2x̄ − q`), the
//! compositions (`paper-dirk2`, `paper-dirk4`) and the Newton solver live in
//! [`integrator_core::minimise`]: the cloth is one [`SparsePotential`]
//! (its Hessian is [`ClothModel::force_jacobian_values`] negated, tried
//! first, and [`ClothModel::force_jacobian_values_projected`] negated, each
//! spring's block projected onto its PSD part, a sphere collider's
//! tangential term dropped, where that is not definite) and
//! [`Solver::Newton`] steps it with [`MidpointStepper`]. Which tables take
//! this path is a fact `butcher!` proved on the exact table
//! ([`Method::midpoint_weights`]). The cloth is also an
//! [`AveragedPotential`] (the integrals in [`ClothModel::avf_force`]), so the
//! energy-conserving average vector field step ([`AVERAGE_VECTOR_FIELD`](crate::method::AVERAGE_VECTOR_FIELD))
//! is the same Newton minimisation through [`AvfStepper`]. What stays here
//! is cloth-specific:
//!
//! * [`Solver::LocalGlobal`] (Liu, Bargteil, O'Brien and Kavan 2013, "Fast
//!   simulation of mass-spring systems"): each spring's `½(k/L)(ℓ − L)²` is
//!   `min_{|e| = L} ½(k/L)|d − e|²`, so alternating the projection of every
//!   spring (`e = L·d/|d|`, local) with one solve of the quadratic in `x`
//!   (global, the matrix `(4/τ²)M + L`, `L` the spring Laplacian, factorised
//!   once per step size with the layer's [`SparseLlt`]: a scalar `n × n`
//!   Cholesky used for the three coordinates) decreases `Φ` monotonically.
//!   Linear convergence; no colliders (a penalty is not a distance to a set;
//!   refused). Its global step computes `x̄` itself, so its gradient test is
//!   relative to `max(S, c·max(|x̄|, |y|))`, the size of the terms it is
//!   computed from, not to the correction's.
//! * The discrete gradient ([`DISCRETE_GRADIENT`](crate::method::DISCRETE_GRADIENT), Gonzalez 1996, in
//!   [`super::discrete_gradient`]): its
//!   equation is not a minimisation (its Jacobian is not symmetric), so
//!   Newton with faer's sparse LU and a line search on the residual.
//!
//! Every solver stops on the gradient: `‖∇Φ‖_∞ ≤ tol·S`, `S` the force scale
//! ([`ClothModel::force_and_scale`]: the largest tension, weight, collider
//! push, or stiffness times `‖x‖_∞`) or the inertial term's size. The
//! default tolerance, [`DEFAULT_TOLERANCE`] `= 1e-12`, is a few thousand
//! ulps of the force scale: converged steps are the midpoint rule's to
//! round-off, so the run is symplectic in practice. A solve that reaches its
//! iteration cap is an error ([`MinimiseError::NotConverged`]), never
//! accepted.

use std::time::Instant;

use faer::Par;
use integrator_core::minimise::{
    AveragedPotential, AvfStepper, Mass, MidpointSettings, MidpointStepper, NewtonSettings,
    SparseLlt, SparsePotential, UpperPattern, converged,
};
use nalgebra::Vector3;

pub use integrator_core::minimise::{
    DEFAULT_NEWTON_ITERATIONS, DEFAULT_TOLERANCE, MinimiseError, Stats,
};

use super::discrete_gradient::DiscreteGradient;
use super::{ClothStepper, Refused, SolverStats, StepError};
use crate::method::{Mechanism, Method, Minimised};
use crate::model::ClothModel;

/// The default iteration cap of a local/global solve.
pub const DEFAULT_LOCAL_GLOBAL_ITERATIONS: usize = 20_000;

/// The minimisation solver.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solver {
    /// Newton with the exact Hessian where definite, else PSD-projected;
    /// Armijo line search, sparse Cholesky.
    Newton,
    /// Liu et al. 2013 local/global iterations with a prefactored matrix.
    LocalGlobal,
}

impl Solver {
    /// The names `--solver` takes.
    pub const NAMES: &'static [&'static str] = &["newton", "local-global"];

    pub fn name(self) -> &'static str {
        match self {
            Solver::Newton => "newton",
            Solver::LocalGlobal => "local-global",
        }
    }

    pub fn parse(name: &str) -> Option<Solver> {
        match name {
            "newton" => Some(Solver::Newton),
            "local-global" => Some(Solver::LocalGlobal),
            _ => None,
        }
    }
}

/// What a minimisation run is asked to do.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MinimiseSettings {
    pub solver: Solver,
    /// `‖∇Φ‖_∞ ≤ tolerance·S` (see the module documentation).
    pub tolerance: f64,
    /// Iterations per solve before [`MinimiseError::NotConverged`].
    pub max_iterations: usize,
}

impl Default for MinimiseSettings {
    /// Newton, [`DEFAULT_TOLERANCE`], [`DEFAULT_NEWTON_ITERATIONS`].
    fn default() -> Self {
        MinimiseSettings::new(Solver::Newton)
    }
}

impl MinimiseSettings {
    /// The range of the tolerance (‖∇Φ‖_∞ relative to the force scale): the
    /// round-off of the force scale is about 1e-16 of it, and a tolerance of
    /// the whole scale accepts any guess.
    pub const TOLERANCE_RANGE: (f64, f64) = (1e-15, 1.0);

    /// These settings with `tolerance`, if it is in [`TOLERANCE_RANGE`](Self::TOLERANCE_RANGE);
    /// otherwise a sentence saying why not (the caller names the value).
    pub fn with_tolerance(mut self, tolerance: f64) -> Result<MinimiseSettings, String> {
        if !(tolerance > 0.0 && tolerance.is_finite()) {
            return Err(format!(
                "must be a positive finite number (got {tolerance})"
            ));
        }
        let (lo, hi) = Self::TOLERANCE_RANGE;
        if !(lo..=hi).contains(&tolerance) {
            return Err(format!(
                "must be between {lo:e} and {hi} (got {tolerance:e}): below, the residual's round-off alone exceeds it and no solve converges; above, a step is accepted without a solve"
            ));
        }
        self.tolerance = tolerance;
        Ok(self)
    }

    /// The solver with the default tolerance and its default iteration cap.
    pub fn new(solver: Solver) -> MinimiseSettings {
        MinimiseSettings {
            solver,
            tolerance: DEFAULT_TOLERANCE,
            max_iterations: match solver {
                Solver::Newton => DEFAULT_NEWTON_ITERATIONS,
                Solver::LocalGlobal => DEFAULT_LOCAL_GLOBAL_ITERATIONS,
            },
        }
    }

    /// The Newton solver's settings of the midpoint and AVF steppers: this
    /// tolerance and cap, with compensated summation of the updates.
    pub fn newton(&self) -> MidpointSettings {
        MidpointSettings {
            newton: NewtonSettings {
                tolerance: self.tolerance,
                max_iterations: self.max_iterations,
            },
            compensated: true,
        }
    }

    /// Refuse a tolerance that is not a positive finite number and a zero cap.
    pub fn check(&self) -> Result<(), Refused> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(Refused(format!(
                "tolerance: {} is not a positive finite number",
                self.tolerance
            )));
        }
        if self.max_iterations == 0 {
            return Err(Refused("max_iterations: must be at least 1".to_string()));
        }
        Ok(())
    }
}

/// The cloth as a [`SparsePotential`]: `M = m·I`, `V` springs + gravity +
/// colliders, the force with its scale ([`ClothModel::force_and_scale`]),
/// and `∇²V` projected block by block
/// ([`ClothModel::force_jacobian_values_projected`], negated) on
/// [`ClothModel::force_jacobian_pattern`].
impl SparsePotential for ClothModel {
    fn mass(&self) -> Mass<'_> {
        Mass::Scalar(self.particle_mass())
    }

    /// `|V|ₐ`: the springs, the colliders and `Σ|w·xₖ|` (gravity's terms).
    fn potential_and_magnitude(&self, q: &[f64]) -> (f64, f64) {
        let (springs, gravity, colliders) = self.potential_terms(q);
        let w = self.weight();
        let gravity_abs: f64 = q.as_chunks::<3>().0[..self.free_count()]
            .iter()
            .map(|p| w.dot(&Vector3::from(*p)).abs())
            .sum();
        (
            springs + gravity + colliders,
            springs + gravity_abs + colliders,
        )
    }

    fn force_and_scale(&self, q: &[f64], out: &mut [f64]) -> f64 {
        ClothModel::force_and_scale(self, q, out)
    }

    fn hessian_pattern(&self) -> Vec<(usize, usize)> {
        self.force_jacobian_pattern()
    }

    fn hessian_values_projected(&self, q: &[f64], out: &mut [f64]) {
        self.force_jacobian_values_projected(q, out);
        for v in out.iter_mut() {
            *v = -*v;
        }
    }
    fn hessian_values(&self, q: &[f64], out: &mut [f64]) -> bool {
        self.force_jacobian_values(q, out);
        for v in out.iter_mut() {
            *v = -*v;
        }
        true
    }
}

/// The cloth's segment averages for the AVF step (springs and gravity in
/// closed form, [`ClothModel::avf_force`]; colliders are refused by the
/// runner). The Hessian approximation is stored negated like the force
/// Jacobian, hence the sign flip.
impl AveragedPotential for ClothModel {
    fn averaged_value(&self, q: &[f64], q1: &[f64]) -> (f64, f64) {
        self.avf_potential_and_magnitude(q, q1)
    }

    fn averaged_force(&self, q: &[f64], q1: &[f64], out: &mut [f64]) -> f64 {
        self.avf_force(q, q1, out)
    }

    fn averaged_hessian_projected(&self, q: &[f64], q1: &[f64], out: &mut [f64]) {
        self.avf_jacobian_values_projected(q, q1, out);
        for v in out.iter_mut() {
            *v = -*v;
        }
    }
    fn averaged_hessian(&self, q: &[f64], q1: &[f64], out: &mut [f64]) -> bool {
        self.avf_jacobian_values(q, q1, out);
        for v in out.iter_mut() {
            *v = -*v;
        }
        true
    }
}

/// The local/global linear algebra: the scalar matrix `c·I + L` (`L` the
/// spring Laplacian), factorised once per `c` with the layer's
/// [`SparseLlt`].
struct LocalGlobalLinear {
    pattern: UpperPattern,
    /// The Laplacian's entries, in the order of the pattern.
    laplacian: Vec<f64>,
    llt: SparseLlt,
    values: Vec<f64>,
    /// Factorisations by `c` (a composition has up to three step sizes).
    factors: Vec<(f64, Vec<f64>)>,
    /// The right-hand side (particle-major) and its column-major copy.
    rhs: Vec<f64>,
    columns: Vec<f64>,
}

impl LocalGlobalLinear {
    fn new(model: &ClothModel, par: Par) -> LocalGlobalLinear {
        let n = model.free_count();
        let (ff, fp) = model.springs();
        // (column, row, value) of the upper triangle, summed in this order
        // (the order fixes the round-off of the diagonal, and with it how
        // far the Laplacian's rows are from summing to zero: the drift of
        // the momentum).
        let mut lap: Vec<(usize, usize, f64)> = Vec::with_capacity(3 * ff.len() + fp.len() + n);
        for s in ff {
            let (a, b) = (s.a as usize, s.b as usize);
            lap.push((a, a, s.kl));
            lap.push((b, b, s.kl));
            lap.push((a.max(b), a.min(b), -s.kl));
        }
        for s in fp {
            lap.push((s.a as usize, s.a as usize, s.kl));
        }
        lap.extend((0..n).map(|k| (k, k, 0.0)));
        lap.sort_unstable_by_key(|x| (x.0, x.1));
        let mut merged: Vec<(usize, usize, f64)> = Vec::with_capacity(lap.len());
        for e in lap {
            match merged.last_mut() {
                Some(last) if (last.0, last.1) == (e.0, e.1) => last.2 += e.2,
                _ => merged.push(e),
            }
        }
        let pattern: Vec<(usize, usize)> = merged.iter().map(|e| (e.1, e.0)).collect();
        let laplacian: Vec<f64> = merged.iter().map(|e| e.2).collect();
        let pattern = UpperPattern::new(n, &pattern);
        let llt = SparseLlt::new(&pattern, 3, par);
        LocalGlobalLinear {
            values: vec![0.0; pattern.len()],
            pattern,
            laplacian,
            llt,
            factors: Vec::new(),
            rhs: vec![0.0; 3 * n],
            columns: vec![0.0; 3 * n],
        }
    }

    /// The factor of `c·I + L`, computed on first use of `c`.
    fn factor(&mut self, c: f64, stats: &mut Stats) -> Result<usize, MinimiseError> {
        if let Some(k) = self.factors.iter().position(|(fc, _)| *fc == c) {
            return Ok(k);
        }
        let clock = Instant::now();
        self.pattern
            .assemble(&self.laplacian, |_| c, &mut self.values);
        let mut l = vec![0.0; self.llt.factor_len()];
        self.llt.factor(&self.values, &mut l)?;
        stats.factorizations += 1;
        stats.factor_seconds += clock.elapsed().as_secs_f64();
        if self.factors.len() >= 8 {
            self.factors.remove(0);
        }
        self.factors.push((c, l));
        Ok(self.factors.len() - 1)
    }

    /// Solve `(c·I + L) X = R` for the three coordinate columns of `rhs`
    /// (stored particle-major: `rhs[3k + axis]`), in place.
    fn solve(&mut self, k: usize) {
        let n = self.rhs.len() / 3;
        for p in 0..n {
            for a in 0..3 {
                self.columns[a * n + p] = self.rhs[3 * p + a];
            }
        }
        self.llt.solve(&self.factors[k].1, &mut self.columns, 3);
        for p in 0..n {
            for a in 0..3 {
                self.rhs[3 * p + a] = self.columns[a * n + p];
            }
        }
    }
}

/// The midpoint minimisation stepper for one cloth model: Newton through
/// [`MidpointStepper`], or the local/global solver, and the discrete
/// gradient; their linear algebra (analysed once), buffers and counters.
pub struct Minimiser {
    settings: MinimiseSettings,
    mass: f64,
    newton: Option<MidpointStepper>,
    avf: Option<AvfStepper>,
    dg: Option<DiscreteGradient>,
    local_global: Option<LocalGlobalLinear>,
    x: Vec<f64>,
    y: Vec<f64>,
    g: Vec<f64>,
    f: Vec<f64>,
    /// The counters of local/global and discrete-gradient steps (Newton's
    /// are its stepper's).
    stats: Stats,
}

impl Minimiser {
    /// Build the solver's structures for `model` (the symbolic analysis).
    /// The local/global solver refuses a model with colliders.
    pub fn new(model: &ClothModel, settings: MinimiseSettings) -> Result<Minimiser, Refused> {
        settings.check()?;
        super::stage::check_size(model)?;
        let n = 3 * model.free_count();
        let par = Par::Seq;
        let mut stats = Stats::default();
        let (newton, local_global) = match settings.solver {
            Solver::Newton => {
                let stepper = MidpointStepper::with_par(model, settings.newton(), par)
                    .map_err(|e| Refused(e.to_string()))?;
                (Some(stepper), None)
            }
            Solver::LocalGlobal => {
                if model.has_colliders() {
                    return Err(Refused(
                        "solver: local-global handles springs and gravity only; this scene has colliders (use --solver newton)".to_string(),
                    ));
                }
                stats.symbolic_factorizations = 1;
                (None, Some(LocalGlobalLinear::new(model, par)))
            }
        };
        Ok(Minimiser {
            settings,
            mass: model.particle_mass(),
            newton,
            avf: None,
            dg: None,
            local_global,
            x: vec![0.0; n],
            y: vec![0.0; n],
            g: vec![0.0; n],
            f: vec![0.0; n],
            stats,
        })
    }

    /// The run's counters.
    pub fn stats(&self) -> &Stats {
        match (&self.avf, &self.newton) {
            (Some(a), _) => a.stats(),
            (None, Some(s)) => s.stats(),
            (None, None) => &self.stats,
        }
    }

    /// One step of size `h` of the average vector field scheme
    /// ([`AVERAGE_VECTOR_FIELD`](crate::method::AVERAGE_VECTOR_FIELD)), one Newton minimisation through
    /// [`AvfStepper`] with this minimiser's tolerance and cap (the solver
    /// setting must be Newton; [`MinimiseStepper::new`] refuses local/global). The model must
    /// have no colliders. On error `z` is unchanged.
    pub fn avf_step(
        &mut self,
        model: &ClothModel,
        h: f64,
        z: &mut [f64],
    ) -> Result<(), MinimiseError> {
        if self.avf.is_none() {
            self.avf = Some(AvfStepper::new(model, self.settings.newton())?);
        }
        self.avf.as_mut().expect("built above").step(model, h, z)
    }

    pub fn settings(&self) -> &MinimiseSettings {
        &self.settings
    }

    /// One implicit midpoint step of size `tau` on `z = [q; p]`. On error
    /// `z` is unchanged.
    pub fn midpoint_step(
        &mut self,
        model: &ClothModel,
        tau: f64,
        z: &mut [f64],
    ) -> Result<(), MinimiseError> {
        if let Some(stepper) = &mut self.newton {
            return stepper.midpoint_step(model, tau, z);
        }
        let n = z.len() / 2;
        let m = self.mass;
        let (q, p) = z.split_at_mut(n);
        for k in 0..n {
            self.y[k] = q[k] + 0.5 * tau * p[k] / m;
        }
        self.x.copy_from_slice(&self.y);
        let c = 4.0 * m / (tau * tau);
        let iterations = self.local_global_solve(model, c)?;
        self.stats.solves += 1;
        self.stats.iterations += iterations;
        self.stats.max_iterations = self.stats.max_iterations.max(iterations);
        for k in 0..n {
            let xb = self.x[k];
            p[k] = m * (4.0 / tau) * (xb - q[k]) - p[k];
            q[k] = 2.0 * xb - q[k];
        }
        Ok(())
    }

    /// A step of size `h` of the composition with `weights`.
    pub fn step(
        &mut self,
        model: &ClothModel,
        weights: &[f64],
        h: f64,
        z: &mut [f64],
    ) -> Result<(), MinimiseError> {
        if let Some(stepper) = &mut self.newton {
            return stepper.step(model, weights, h, z);
        }
        for &b in weights {
            self.midpoint_step(model, b * h, z)?;
        }
        self.stats.steps += 1;
        Ok(())
    }

    /// One step of size `h` of Gonzalez's discrete gradient
    /// ([`super::discrete_gradient`]; its solver is built on first use).
    /// On error `z` is unchanged.
    pub fn discrete_gradient_step(
        &mut self,
        model: &ClothModel,
        h: f64,
        z: &mut [f64],
    ) -> Result<(), MinimiseError> {
        if self.dg.is_none() {
            self.dg = Some(
                DiscreteGradient::new(model)
                    .map_err(|_| MinimiseError::NotDefinite { pivot: 0 })?,
            );
        }
        let dg = self.dg.as_mut().expect("built above");
        let stats = match &mut self.newton {
            Some(s) => s.stats_mut(),
            None => &mut self.stats,
        };
        let limits = (self.settings.tolerance, self.settings.max_iterations);
        dg.step(model, self.mass, limits, h, z, stats)
    }

    fn local_global_solve(&mut self, model: &ClothModel, c: f64) -> Result<usize, MinimiseError> {
        let tol = self.settings.tolerance;
        let cap = self.settings.max_iterations;
        let lin = self
            .local_global
            .as_mut()
            .expect("a local/global minimiser");
        let k = lin.factor(c, &mut self.stats)?;
        let (ff, fp) = model.springs();
        let w = model.weight();
        let mut it = 0;
        loop {
            let residual = gradient(model, c, &self.x, &self.y, &mut self.f, &mut self.g);
            if converged("local-global", it, residual, tol, cap)? {
                self.stats.max_residual = self.stats.max_residual.max(residual);
                return Ok(it);
            }
            it += 1;
            // Local: each spring's nearest rest-length vector; global: the
            // right-hand side (4/τ²)M·y + weight + Σ (k/L)Aᵀe, one solve.
            let rhs = &mut lin.rhs;
            for (r, yk) in rhs.iter_mut().zip(&self.y) {
                *r = c * yk;
            }
            let x3 = self.x.as_chunks::<3>().0;
            let r3 = rhs.as_chunks_mut::<3>().0;
            for r in r3.iter_mut() {
                for a in 0..3 {
                    r[a] += w[a];
                }
            }
            for s in ff {
                let (a, b) = (s.a as usize, s.b as usize);
                let d = Vector3::from(x3[b]) - Vector3::from(x3[a]);
                let e = d * (s.kl * s.rest / d.norm());
                r3[b] = (Vector3::from(r3[b]) + e).into();
                r3[a] = (Vector3::from(r3[a]) - e).into();
            }
            for s in fp {
                let a = s.a as usize;
                let pin = Vector3::from(s.pin);
                let d = pin - Vector3::from(x3[a]);
                let e = d * (s.rest / d.norm());
                r3[a] = (Vector3::from(r3[a]) + (pin - e) * s.kl).into();
            }
            lin.solve(k);
            self.x.copy_from_slice(&lin.rhs);
        }
    }
}

/// `g = c(x − y) − F(x)` into `g`; returns `‖g‖_∞/S`, `S` the force scale
/// ([`ClothModel::force_and_scale`]) or the inertial term's `c·max(|x|, |y|)`
/// (its terms' size), whichever is larger: the size of the round-off of `g`.
fn gradient(model: &ClothModel, c: f64, x: &[f64], y: &[f64], f: &mut [f64], g: &mut [f64]) -> f64 {
    let mut scale = model.force_and_scale(x, f);
    let mut gmax: f64 = 0.0;
    for (((g, x), y), f) in g.iter_mut().zip(x).zip(y).zip(f.iter()) {
        let inertia = c * (x - y);
        scale = scale.max(c * x.abs().max(y.abs()));
        *g = inertia - f;
        gmax = gmax.max(g.abs());
    }
    if gmax == 0.0 { 0.0 } else { gmax / scale }
}

/// Whether `method` can run on a scene with (`has_colliders`) or without
/// colliders through `solver`: `Err` with the reason — the same reason a
/// run gives ([`Minimiser::new`], [`MinimiseStepper::new`]), so that a
/// caller may refuse a combination before it starts (`symlab cloth
/// --stability` does). The energy schemes (`avf`, `discrete-gradient`)
/// handle springs and gravity only and are solved with Newton only; the
/// local/global solver handles no colliders. Methods that are not
/// minimisations are not affected by `solver`.
pub fn applicable(method: &Method, has_colliders: bool, solver: Solver) -> Result<(), String> {
    let energy = matches!(
        method.mechanism(),
        Mechanism::DiscreteGradient | Mechanism::Minimisation(Minimised::AverageVectorField)
    );
    if energy {
        let name = method.id();
        if has_colliders {
            return Err(format!(
                "method: {name} handles springs and gravity; this scene has colliders"
            ));
        }
        if solver != Solver::Newton {
            return Err(format!("solver: {name} is solved with newton only"));
        }
    } else if method.minimises() && solver == Solver::LocalGlobal && has_colliders {
        return Err(
            "solver: local-global handles springs and gravity only; this scene has colliders (use --solver newton)"
                .to_string(),
        );
    }
    Ok(())
}

/// What a [`MinimiseStepper`] steps.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// Midpoint steps of sizes `bᵢh`.
    Composition(&'static [f64]),
    /// The average vector field step.
    Avf,
    /// Gonzalez's discrete gradient (Newton with sparse LU).
    Gonzalez,
}

/// The minimisation mechanisms as a [`ClothStepper`]: a composition of
/// midpoint steps, the average vector field or the discrete gradient,
/// through one [`Minimiser`].
pub struct MinimiseStepper {
    minimiser: Minimiser,
    kind: Kind,
}

impl MinimiseStepper {
    /// A stepper for `method` on `model` (a minimisation or the discrete
    /// gradient; `Err` naming the method otherwise, or naming what the
    /// settings or the scene refuse).
    pub fn new(
        method: &Method,
        model: &ClothModel,
        settings: MinimiseSettings,
    ) -> Result<MinimiseStepper, Refused> {
        let kind = match method.mechanism() {
            Mechanism::Minimisation(Minimised::Midpoint(w)) => Kind::Composition(w),
            Mechanism::Minimisation(Minimised::AverageVectorField) => Kind::Avf,
            Mechanism::DiscreteGradient => Kind::Gonzalez,
            _ => {
                return Err(Refused(format!(
                    "method: {} is not solved by minimisation",
                    method.id()
                )));
            }
        };
        MinimiseStepper::with_weights_or(kind, method, model, settings)
    }

    /// A stepper for a table that is a composition of midpoint steps with
    /// `weights` (a user's `butcher!` table: `Info::midpoint_weights`).
    pub fn composition(
        weights: &'static [f64],
        model: &ClothModel,
        settings: MinimiseSettings,
    ) -> Result<MinimiseStepper, Refused> {
        settings.check()?;
        Ok(MinimiseStepper {
            minimiser: Minimiser::new(model, settings)?,
            kind: Kind::Composition(weights),
        })
    }

    fn with_weights_or(
        kind: Kind,
        method: &Method,
        model: &ClothModel,
        settings: MinimiseSettings,
    ) -> Result<MinimiseStepper, Refused> {
        settings.check()?;
        if !matches!(kind, Kind::Composition(_)) {
            applicable(method, model.has_colliders(), settings.solver).map_err(Refused)?;
        }
        Ok(MinimiseStepper {
            minimiser: Minimiser::new(model, settings)?,
            kind,
        })
    }

    pub fn minimiser(&self) -> &Minimiser {
        &self.minimiser
    }
}

impl ClothStepper for MinimiseStepper {
    fn step(
        &mut self,
        model: &ClothModel,
        _t: f64,
        h: f64,
        z: &mut [f64],
    ) -> Result<(), StepError> {
        let m = &mut self.minimiser;
        match self.kind {
            Kind::Composition(w) => m.step(model, w, h, z),
            Kind::Avf => m.avf_step(model, h, z),
            Kind::Gonzalez => m.discrete_gradient_step(model, h, z),
        }
        .map_err(StepError::Minimise)
    }

    fn stats(&self) -> SolverStats {
        SolverStats::Minimise(*self.minimiser.stats(), *self.minimiser.settings())
    }
}
