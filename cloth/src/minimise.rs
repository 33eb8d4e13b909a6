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
//! ([`weights_of`]). The cloth is also an
//! [`AveragedPotential`] (the integrals in [`ClothModel::avf_force`]), so the
//! energy-conserving average vector field step ([`AVERAGE_VECTOR_FIELD`])
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
//! * The discrete gradient ([`DISCRETE_GRADIENT`], Gonzalez 1996): its
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

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par};
use integrator_core::minimise::{
    AveragedPotential, AvfStepper, Mass, MidpointSettings, MidpointStepper, NewtonSettings,
    SparseLlt, SparsePotential, UpperPattern,
};
use nalgebra::Vector3;

pub use integrator_core::minimise::{
    DEFAULT_NEWTON_ITERATIONS, DEFAULT_TOLERANCE, MinimiseError, Stats,
};

use crate::implicit as cloth_implicit;
use crate::methods::MethodError;
use crate::model::ClothModel;
use crate::sim::{CallbackError, Frame, FrameStats, RunError, RunOptions, RunReport, Simulation};

/// The default iteration cap of a local/global solve.
pub const DEFAULT_LOCAL_GLOBAL_ITERATIONS: usize = 20_000;

/// Halvings of the discrete gradient's Newton step before its line search
/// gives up.
const MAX_HALVINGS: usize = 60;

/// The sufficient-decrease constant of the discrete gradient's line search.
const ARMIJO: f64 = 1e-4;

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
pub struct Settings {
    pub solver: Solver,
    /// `‖∇Φ‖_∞ ≤ tolerance·S` (see the module documentation).
    pub tolerance: f64,
    /// Iterations per solve before [`MinimiseError::NotConverged`].
    pub max_iterations: usize,
}

impl Default for Settings {
    /// Newton, [`DEFAULT_TOLERANCE`], [`DEFAULT_NEWTON_ITERATIONS`].
    fn default() -> Self {
        Settings::new(Solver::Newton)
    }
}

impl Settings {
    /// The solver with the default tolerance and its default iteration cap.
    pub fn new(solver: Solver) -> Settings {
        Settings {
            solver,
            tolerance: DEFAULT_TOLERANCE,
            max_iterations: match solver {
                Solver::Newton => DEFAULT_NEWTON_ITERATIONS,
                Solver::LocalGlobal => DEFAULT_LOCAL_GLOBAL_ITERATIONS,
            },
        }
    }

    /// Refuse a tolerance that is not a positive finite number and a zero cap.
    pub fn check(&self) -> Result<(), RunError> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(RunError::Options(format!(
                "tolerance: {} is not a positive finite number",
                self.tolerance
            )));
        }
        if self.max_iterations == 0 {
            return Err(RunError::Options(
                "max_iterations: must be at least 1".to_string(),
            ));
        }
        Ok(())
    }
}

/// The composition weights of a named implicit scheme, if it is one of the
/// midpoint family: a table with `aᵢᵢ = bᵢ/2`, `aᵢⱼ = bⱼ` (`j < i`), as
/// `butcher!` decided on its exact entries
/// ([`Info::midpoint_weights`](integrator_core::Info::midpoint_weights)),
/// never on the doubles.
pub fn weights_of(id: &str) -> Option<Vec<f64>> {
    cloth_implicit::info(id).and_then(|info| info.midpoint_weights.map(<[f64]>::to_vec))
}

/// Whether `id` steps through the minimisation solvers: a scheme of
/// [`IMPLICIT`](crate::implicit::IMPLICIT) whose table is a composition of
/// midpoint steps (today `midpoint`, `paper-dirk2`, `paper-dirk4`), the
/// average vector field ([`AVERAGE_VECTOR_FIELD`]) or the discrete gradient
/// ([`DISCRETE_GRADIENT`]).
pub fn is_minimisation(id: &str) -> bool {
    id == DISCRETE_GRADIENT || id == AVERAGE_VECTOR_FIELD || weights_of(id).is_some()
}

/// The name and order of the two energy-conserving comparison schemes
/// ([`AVERAGE_VECTOR_FIELD`], [`DISCRETE_GRADIENT`]), which have no table
/// and so no `Info`: both are implicit, symmetric, second order and not
/// symplectic. `None` for any other id.
pub fn energy_scheme(id: &str) -> Option<(&'static str, usize)> {
    match id {
        AVERAGE_VECTOR_FIELD => Some((
            "Average vector field (discrete gradient as minimisation), energy-conserving",
            2,
        )),
        DISCRETE_GRADIENT => Some(("Discrete gradient (Gonzalez 1996), energy-momentum", 2)),
        _ => None,
    }
}

/// The name of the energy-conserving scheme solved as a minimisation: the
/// average vector field discrete gradient
/// ([`integrator_core::minimise::AvfStepper`], the cloth's integrals in
/// [`ClothModel::avf_force`]). Conserves energy and linear momentum; not
/// symplectic.
pub const AVERAGE_VECTOR_FIELD: &str = "avf";

/// The name of the energy–momentum conserving comparison scheme.
pub const DISCRETE_GRADIENT: &str = "discrete-gradient";

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

/// The discrete gradient's linear algebra: `c·I − ∂F̄/∂x̄` (not symmetric)
/// with faer's sparse LU, symbolic analysis once.
struct DgLinear {
    full: Vec<f64>,
    diag: Vec<usize>,
    symbolic: SymbolicSparseColMat<usize>,
    lu: faer::sparse::linalg::lu::SymbolicLu<usize>,
    numeric: faer::sparse::linalg::lu::NumericLu<usize, f64>,
    values: Vec<f64>,
    mem: MemBuffer,
    par: Par,
}

impl DgLinear {
    fn new(model: &ClothModel, par: Par) -> Result<DgLinear, RunError> {
        let n = 3 * model.free_count();
        let pattern = model.force_jacobian_pattern();
        let has_diag = {
            let mut seen = vec![false; n];
            for &(r, c) in &pattern {
                if r == c {
                    seen[r] = true;
                }
            }
            seen.iter().all(|&s| s)
        };
        if !has_diag {
            return Err(RunError::Options(format!(
                "method: {DISCRETE_GRADIENT} needs every free particle on a spring"
            )));
        }
        let mut col_ptr = vec![0usize; n + 1];
        for &(_, c) in &pattern {
            col_ptr[c + 1] += 1;
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let row_idx: Vec<usize> = pattern.iter().map(|&(r, _)| r).collect();
        let diag = pattern
            .iter()
            .enumerate()
            .filter(|(_, (r, c))| r == c)
            .map(|(k, _)| k)
            .collect();
        let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let lu =
            faer::sparse::linalg::lu::factorize_symbolic_lu(symbolic.as_ref(), Default::default())
                .map_err(|e| {
                    RunError::Options(format!(
                        "method: {DISCRETE_GRADIENT}: symbolic LU failed: {e:?}"
                    ))
                })?;
        let mem = MemBuffer::new(StackReq::any_of(&[
            lu.factorize_numeric_lu_scratch::<f64>(par, Default::default()),
            lu.solve_in_place_scratch::<f64>(1, par),
        ]));
        Ok(DgLinear {
            full: vec![0.0; pattern.len()],
            values: vec![0.0; pattern.len()],
            diag,
            symbolic,
            lu,
            numeric: faer::sparse::linalg::lu::NumericLu::new(),
            mem,
            par,
        })
    }

    fn factor(
        &mut self,
        model: &ClothModel,
        q: &[f64],
        x: &[f64],
        c: f64,
    ) -> Result<(), MinimiseError> {
        model.discrete_gradient_jacobian(q, x, &mut self.full);
        for (v, f) in self.values.iter_mut().zip(&self.full) {
            *v = -f;
        }
        for &d in &self.diag {
            self.values[d] += c;
        }
        let matrix = SparseColMatRef::new(self.symbolic.as_ref(), &self.values);
        self.lu
            .factorize_numeric_lu(
                &mut self.numeric,
                matrix,
                self.par,
                MemStack::new(&mut self.mem),
                Default::default(),
            )
            .map(|_| ())
            .map_err(|_| MinimiseError::NotDefinite { pivot: 0 })
    }

    fn solve(&mut self, rhs: &mut [f64]) {
        let n = rhs.len();
        faer::sparse::linalg::lu::LuRef::new_unchecked(&self.lu, &self.numeric)
            .solve_in_place_with_conj(
                Conj::No,
                MatMut::from_column_major_slice_mut(rhs, n, 1),
                self.par,
                MemStack::new(&mut self.mem),
            );
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
    settings: Settings,
    mass: f64,
    newton: Option<MidpointStepper>,
    avf: Option<AvfStepper>,
    dg: Option<DgLinear>,
    local_global: Option<LocalGlobalLinear>,
    x: Vec<f64>,
    y: Vec<f64>,
    g: Vec<f64>,
    dx: Vec<f64>,
    /// Scratch for a gradient at a trial point.
    g_trial: Vec<f64>,
    trial: Vec<f64>,
    f: Vec<f64>,
    /// The counters of local/global and discrete-gradient steps (Newton's
    /// are its stepper's).
    stats: Stats,
}

impl Minimiser {
    /// Build the solver's structures for `model` (the symbolic analysis).
    /// The local/global solver refuses a model with colliders.
    pub fn new(model: &ClothModel, settings: Settings) -> Result<Minimiser, RunError> {
        settings.check()?;
        cloth_implicit::check_size(model)?;
        let n = 3 * model.free_count();
        let par = Par::Seq;
        let mut stats = Stats::default();
        let (newton, local_global) = match settings.solver {
            Solver::Newton => {
                let stepper = MidpointStepper::with_par(
                    model,
                    MidpointSettings {
                        newton: NewtonSettings {
                            tolerance: settings.tolerance,
                            max_iterations: settings.max_iterations,
                        },
                        compensated: true,
                    },
                    par,
                )
                .map_err(|e| RunError::Options(e.to_string()))?;
                (Some(stepper), None)
            }
            Solver::LocalGlobal => {
                if model.has_colliders() {
                    return Err(RunError::Options(
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
            dx: vec![0.0; n],
            g_trial: vec![0.0; n],
            trial: vec![0.0; n],
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
    /// ([`AVERAGE_VECTOR_FIELD`]), one Newton minimisation through
    /// [`AvfStepper`] with this minimiser's tolerance and cap (the solver
    /// setting must be Newton; [`run`] refuses local/global). The model must
    /// have no colliders. On error `z` is unchanged.
    pub fn avf_step(
        &mut self,
        model: &ClothModel,
        h: f64,
        z: &mut [f64],
    ) -> Result<(), MinimiseError> {
        if self.avf.is_none() {
            self.avf = Some(AvfStepper::new(
                model,
                MidpointSettings {
                    newton: NewtonSettings {
                        tolerance: self.settings.tolerance,
                        max_iterations: self.settings.max_iterations,
                    },
                    compensated: true,
                },
            )?);
        }
        self.avf.as_mut().expect("built above").step(model, h, z)
    }

    pub fn settings(&self) -> &Settings {
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

    /// One step of size `h` of the discrete-gradient scheme
    /// ([`ClothModel::discrete_gradient_force`]): `x̄ = (q + q')/2` solves
    /// `(4/h²)M(x̄ − y) = F̄(q, x̄)`, `y = q + (h/2)v`, then `q' = 2x̄ − q`,
    /// `v' = (4/h)(x̄ − q) − v`, as for the midpoint rule. `F̄` is not a
    /// gradient in `x̄` and its Jacobian `(4/h²)M − ∂F̄/∂x̄` is not symmetric:
    /// Newton's method with the exact Jacobian
    /// ([`ClothModel::discrete_gradient_jacobian`]) and faer's sparse LU
    /// (symbolic analysis once per run; the pattern of the springs), and a
    /// backtracking line search on the residual `‖g‖₂` (the Newton
    /// direction always descends it); it stops on the same gradient test.
    pub fn discrete_gradient_step(
        &mut self,
        model: &ClothModel,
        h: f64,
        z: &mut [f64],
    ) -> Result<(), MinimiseError> {
        let n = z.len() / 2;
        let m = self.mass;
        let c = 4.0 * m / (h * h);
        let (q, p) = z.split_at_mut(n);
        for k in 0..n {
            self.y[k] = q[k] + 0.5 * h * p[k] / m;
        }
        self.x.copy_from_slice(&self.y);
        let tol = self.settings.tolerance;
        let cap = self.settings.max_iterations;
        if self.dg.is_none() {
            self.dg = Some(
                DgLinear::new(model, Par::Seq)
                    .map_err(|_| MinimiseError::NotDefinite { pivot: 0 })?,
            );
        }
        let lin = self.dg.as_mut().expect("built above");
        let stats = stats_of(&mut self.newton, &mut self.stats);
        let dg_gradient = |x: &[f64], f: &mut [f64], g: &mut [f64], y: &[f64]| -> (f64, f64) {
            let mut scale = model.discrete_gradient_force(q, x, f);
            let mut gmax: f64 = 0.0;
            let mut g2 = 0.0;
            for (((g, x), y), f) in g.iter_mut().zip(x).zip(y).zip(f.iter()) {
                scale = scale.max(c * x.abs().max(y.abs()));
                *g = c * (x - y) - f;
                gmax = gmax.max(g.abs());
                g2 += *g * *g;
            }
            (if gmax == 0.0 { 0.0 } else { gmax / scale }, g2.sqrt())
        };
        let (mut residual, mut norm) = dg_gradient(&self.x, &mut self.f, &mut self.g, &self.y);
        let mut it = 0;
        loop {
            if !residual.is_finite() {
                return Err(MinimiseError::NonFinite {
                    solver: "discrete-gradient",
                    iteration: it,
                });
            }
            if residual <= tol {
                stats.max_residual = stats.max_residual.max(residual);
                break;
            }
            if it == cap {
                return Err(MinimiseError::NotConverged {
                    solver: "discrete-gradient",
                    iterations: it,
                    residual,
                    tolerance: tol,
                });
            }
            it += 1;
            let clock = Instant::now();
            lin.factor(model, q, &self.x, c)?;
            stats.factor_seconds += clock.elapsed().as_secs_f64();
            stats.factorizations += 1;
            for (d, g) in self.dx.iter_mut().zip(&self.g) {
                *d = -g;
            }
            lin.solve(&mut self.dx);
            let mut alpha = 1.0;
            let mut halvings = 0;
            loop {
                for ((t, x), d) in self.trial.iter_mut().zip(&self.x).zip(&self.dx) {
                    *t = x + alpha * d;
                }
                let (r, nn) = dg_gradient(&self.trial, &mut self.f, &mut self.g_trial, &self.y);
                if nn < (1.0 - ARMIJO * alpha) * norm || r <= tol {
                    residual = r;
                    norm = nn;
                    break;
                }
                halvings += 1;
                stats.backtracks += 1;
                if halvings > MAX_HALVINGS {
                    return Err(MinimiseError::LineSearch {
                        iteration: it,
                        halvings,
                        residual,
                    });
                }
                alpha *= 0.5;
            }
            std::mem::swap(&mut self.x, &mut self.trial);
            std::mem::swap(&mut self.g, &mut self.g_trial);
        }
        stats.solves += 1;
        stats.iterations += it;
        stats.max_iterations = stats.max_iterations.max(it);
        stats.steps += 1;
        for k in 0..n {
            let xb = self.x[k];
            p[k] = m * (4.0 / h) * (xb - q[k]) - p[k];
            q[k] = 2.0 * xb - q[k];
        }
        Ok(())
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
            if !residual.is_finite() {
                return Err(MinimiseError::NonFinite {
                    solver: "local-global",
                    iteration: it,
                });
            }
            if residual <= tol {
                self.stats.max_residual = self.stats.max_residual.max(residual);
                return Ok(it);
            }
            if it == cap {
                return Err(MinimiseError::NotConverged {
                    solver: "local-global",
                    iterations: it,
                    residual,
                    tolerance: tol,
                });
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

/// The counters a step adds to: the Newton stepper's, or `own`.
fn stats_of<'a>(newton: &'a mut Option<MidpointStepper>, own: &'a mut Stats) -> &'a mut Stats {
    match newton {
        Some(s) => s.stats_mut(),
        None => own,
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

/// A finished minimisation run.
#[derive(Clone, Debug, PartialEq)]
pub struct MinimiseRun {
    pub report: RunReport,
    pub solver: Stats,
    pub settings: Settings,
}

/// Run `opts.frames` frames of `opts.substeps` steps of the midpoint-family
/// scheme `id` ([`is_minimisation`]) through the minimisation solver, as
/// [`Simulation::run`] does for explicit schemes: `on_frame` is called with
/// the current frame first and after every frame; a solve that fails stops
/// the run with [`RunError::Minimise`] naming the step and time, a
/// non-finite state with [`RunError::Diverged`]; the state is then left as
/// it was at the end of the last good frame.
pub fn run<F>(
    sim: &mut Simulation,
    id: &str,
    opts: &RunOptions,
    settings: Settings,
    on_frame: F,
) -> Result<MinimiseRun, RunError>
where
    F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
{
    let kind = if id == DISCRETE_GRADIENT {
        Kind::Gonzalez
    } else if id == AVERAGE_VECTOR_FIELD {
        Kind::Avf
    } else {
        let weights = weights_of(id).ok_or_else(|| {
            if cloth_implicit::is_implicit(id) {
                MethodError::NotSteppable(id.to_string())
            } else {
                MethodError::Unknown(id.to_string())
            }
        })?;
        Kind::Composition(weights)
    };
    let method = match &kind {
        Kind::Gonzalez | Kind::Avf => energy_scheme(id).expect("an energy scheme").0,
        Kind::Composition(_) => cloth_implicit::info(id).expect("an implicit scheme").name,
    };
    run_kind(sim, method, kind, opts, settings, on_frame)
}

/// [`run`] for a `butcher!` scheme type whose table is a composition of
/// midpoint steps ([`Info::midpoint_weights`](integrator_core::Info::midpoint_weights),
/// decided exactly at compile time): a user's table of that shape steps
/// through the minimisation solver like the library's. Refuses (naming the
/// method) a scheme of another shape.
pub fn run_scheme<S, F>(
    sim: &mut Simulation,
    opts: &RunOptions,
    settings: Settings,
    on_frame: F,
) -> Result<MinimiseRun, RunError>
where
    S: integrator_core::Scheme,
    F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
{
    let weights = S::INFO
        .midpoint_weights
        .ok_or_else(|| MethodError::NotSteppable(S::INFO.name.to_string()))?;
    run_kind(
        sim,
        S::INFO.name,
        Kind::Composition(weights.to_vec()),
        opts,
        settings,
        on_frame,
    )
}

/// What a minimisation run steps.
enum Kind {
    /// Midpoint steps of sizes `bᵢh`.
    Composition(Vec<f64>),
    /// The average vector field step.
    Avf,
    /// Gonzalez's discrete gradient (Newton with sparse LU).
    Gonzalez,
}

/// Whether method `id` can run on a scene with (`has_colliders`) or
/// without colliders through `solver`: `Err` with the reason — the same
/// reason a run gives ([`run`], [`Minimiser::new`]), so that a caller may
/// refuse a combination before it starts (`symlab cloth --stability` does).
/// The energy schemes (`avf`, `discrete-gradient`) handle springs and
/// gravity only and are solved with Newton only; the local/global solver
/// handles no colliders. Methods that are not minimisations are not
/// affected by `solver`.
pub fn applicable(id: &str, has_colliders: bool, solver: Solver) -> Result<(), String> {
    let energy = match id {
        DISCRETE_GRADIENT => Some(DISCRETE_GRADIENT),
        AVERAGE_VECTOR_FIELD => Some(AVERAGE_VECTOR_FIELD),
        _ => None,
    };
    if let Some(name) = energy {
        if has_colliders {
            return Err(format!(
                "method: {name} handles springs and gravity; this scene has colliders"
            ));
        }
        if solver != Solver::Newton {
            return Err(format!("solver: {name} is solved with newton only"));
        }
    } else if is_minimisation(id) && solver == Solver::LocalGlobal && has_colliders {
        return Err(
            "solver: local-global handles springs and gravity only; this scene has colliders (use --solver newton)"
                .to_string(),
        );
    }
    Ok(())
}

fn run_kind<F>(
    sim: &mut Simulation,
    method: &'static str,
    kind: Kind,
    opts: &RunOptions,
    settings: Settings,
    mut on_frame: F,
) -> Result<MinimiseRun, RunError>
where
    F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
{
    let h = opts.step_size();
    opts.check()?;
    settings.check()?;
    let name = match kind {
        Kind::Gonzalez => Some(DISCRETE_GRADIENT),
        Kind::Avf => Some(AVERAGE_VECTOR_FIELD),
        Kind::Composition(_) => None,
    };
    if let Some(name) = name {
        applicable(name, sim.model.has_colliders(), settings.solver).map_err(RunError::Options)?;
    }
    let mut solver = Minimiser::new(&sim.model, settings)?;
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
    emit(sim, &mut frames)?;
    let mut saved = sim.state.clone();
    let t0 = sim.time;
    let step0 = sim.steps;
    let mut stepping = 0.0;
    for _ in 0..opts.frames {
        saved.copy_from_slice(&sim.state);
        let frame_start = sim.steps;
        let clock = Instant::now();
        for _ in 0..opts.substeps {
            let t = t0 + (sim.steps - step0) as f64 * h;
            let result = match &kind {
                Kind::Composition(w) => solver.step(&sim.model, w, h, &mut sim.state),
                Kind::Avf => solver.avf_step(&sim.model, h, &mut sim.state),
                Kind::Gonzalez => solver.discrete_gradient_step(&sim.model, h, &mut sim.state),
            };
            if let Err(source) = result {
                let step = sim.steps + 1;
                sim.state.copy_from_slice(&saved);
                sim.steps = frame_start;
                return Err(RunError::Minimise {
                    method,
                    step,
                    time: t,
                    source,
                });
            }
            sim.steps += 1;
            if let Some(index) = sim.state.iter().position(|x| !x.is_finite()) {
                let value = sim.state[index];
                sim.state.copy_from_slice(&saved);
                let steps = sim.steps;
                sim.steps = frame_start;
                return Err(RunError::Diverged {
                    method,
                    step: steps,
                    time: t0 + (steps - step0) as f64 * h,
                    frame: sim.frame + 1,
                    index,
                    value,
                    particle: sim.model.particle_of_component(index),
                });
            }
        }
        stepping += clock.elapsed().as_secs_f64();
        sim.frame += 1;
        sim.time = t0 + (sim.steps - step0) as f64 * h;
        emit(sim, &mut frames)?;
    }
    Ok(MinimiseRun {
        report: RunReport {
            method,
            h,
            steps: sim.steps - step0,
            frames,
            stepping_seconds: stepping,
        },
        solver: *solver.stats(),
        settings,
    })
}

/// What the solver of a run did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SolverStats {
    /// An explicit run.
    None,
    /// The generic sparse stage solver ([`crate::implicit`]).
    Stage(integrator_core::implicit::Stats),
    /// A minimisation run.
    Minimise(Stats, Settings),
}

/// Run any method that steps cloth: the midpoint family
/// ([`is_minimisation`]) and the discrete gradient through [`run`] with
/// `settings`, other implicit ones through the sparse stage solver, explicit
/// ones with [`Simulation::run_named`].
pub fn run_any<F>(
    sim: &mut Simulation,
    id: &str,
    opts: &RunOptions,
    settings: Settings,
    on_frame: F,
) -> Result<(RunReport, SolverStats), RunError>
where
    F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
{
    if is_minimisation(id) {
        let r = run(sim, id, opts, settings, on_frame)?;
        Ok((r.report, SolverStats::Minimise(r.solver, r.settings)))
    } else {
        let (report, stats) = cloth_implicit::run_method(sim, id, opts, on_frame)?;
        Ok((report, stats.map_or(SolverStats::None, SolverStats::Stage)))
    }
}
