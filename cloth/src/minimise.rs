//! The implicit midpoint family on cloth as energy minimisation.
//!
//! # The midpoint step is a minimisation
//!
//! For `M q̈ = F(q) = −∇V(q)` (here `M = m·I`), one implicit midpoint step of
//! size `τ` from `(q, v)` is
//!
//! ```text
//! q' = q + τ·(v + v')/2,   v' = v + τ·M⁻¹F(x̄),   x̄ = (q + q')/2.
//! ```
//!
//! Then `x̄ = q + (τ/2)(v + v')/2 = q + (τ/2)v + (τ²/4)M⁻¹F(x̄)`, i.e. with
//! `y = q + (τ/2)v`, `(4/τ²)M(x̄ − y) − F(x̄) = 0`: `x̄` is a stationary
//! point of
//!
//! ```text
//! Φ(x) = (2/τ²)(x − y)ᵀM(x − y) + V(x),   ∇Φ = (4/τ²)M(x − y) − F(x),
//! ```
//!
//! and afterwards `q' = 2x̄ − q`, `v' = 2(v + v')/2 − v = (2/τ)(q' − q) − v
//! = (4/τ)(x̄ − q) − v` (with momenta `p = M v`). This is a backward-Euler
//! half step (`x̄` is the backward-Euler position after `τ/2`) followed by
//! an explicit half step (the reflection `q' = 2x̄ − q`). The tests check the
//! steps against the generic stage solver's implicit midpoint rule.
//!
//! A symplectic diagonally implicit RK method whose table has
//! `aᵢᵢ = bᵢ/2` and `aᵢⱼ = bⱼ` (`j < i`) is the composition of midpoint steps
//! of sizes `b₁h, …, b_sh` (Hairer–Lubich–Wanner VI.4): [`composition`]
//! reads the weights off a table, and the paper's `paper-dirk2` (`b = (½,
//! ½)`) and `paper-dirk4` (the triple jump, with a negative middle weight)
//! step as successive minimisations. A negative `τ` changes nothing: the
//! mass term `(2/τ²)M` is still positive.
//!
//! # Solvers
//!
//! * [`Solver::Newton`]: Newton's method on `Φ` with the Hessian
//!   `(4/τ²)M + K⁺`, `K⁺` the PSD projection of `∇²V` block by block
//!   ([`ClothModel::force_jacobian_values_projected`]), so the Hessian is
//!   positive definite at any step size, every direction descends, and a
//!   backtracking (Armijo) line search on `Φ` makes each iteration decrease
//!   `Φ`. faer's sparse Cholesky (`LLᵀ`): symbolic analysis (AMD ordering)
//!   once per run, a numeric factorisation per iteration.
//! * [`Solver::LocalGlobal`] (Liu, Bargteil, O'Brien and Kavan 2013, "Fast
//!   simulation of mass-spring systems"): each spring's `½(k/L)(ℓ − L)²` is
//!   `min_{|e| = L} ½(k/L)|d − e|²`, so alternating the projection of every
//!   spring (`e = L·d/|d|`, local) with one solve of the quadratic in `x`
//!   (global, the matrix `(4/τ²)M + L`, `L` the spring Laplacian, factorised
//!   once per step size: a scalar `n × n` Cholesky used for the three
//!   coordinates) decreases `Φ` monotonically. Linear convergence; no
//!   colliders (a penalty is not a distance to a set; refused).
//!
//! Both stop on the gradient: `‖∇Φ‖_∞ ≤ tol·S`, `S` the force scale at the
//! iterate (the largest tension, weight, collider push or inertial term
//! `(4/τ²)m|x − y|`, see [`ClothModel::force_and_scale`]). The default
//! tolerance, [`DEFAULT_TOLERANCE`] `= 1e-12`, is a few thousand ulps of the
//! force scale: converged steps are the midpoint rule's to round-off, so the run
//! is symplectic in practice. A solve that reaches its iteration cap is an
//! error ([`MinimiseError::NotConverged`]), never accepted.

use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};
use integrator_core::implicit::ImplicitTable;
use nalgebra::Vector3;

use crate::implicit::{self as cloth_implicit, TableVisitor};
use crate::methods::MethodError;
use crate::model::ClothModel;
use crate::sim::{CallbackError, Frame, FrameStats, RunError, RunOptions, RunReport, Simulation};

/// The default convergence tolerance on `‖∇Φ‖_∞` relative to the force scale.
pub const DEFAULT_TOLERANCE: f64 = 1e-12;

/// Default iteration caps per solve.
pub const DEFAULT_NEWTON_ITERATIONS: usize = 100;
pub const DEFAULT_LOCAL_GLOBAL_ITERATIONS: usize = 20_000;

/// Halvings of the Newton step before the line search gives up.
const MAX_HALVINGS: usize = 60;

/// Armijo's sufficient-decrease constant.
const ARMIJO: f64 = 1e-4;

/// The minimisation solver.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solver {
    /// Newton with PSD-projected Hessian, Armijo line search, sparse Cholesky.
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

/// Counters of a minimisation run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Steps of the method.
    pub steps: usize,
    /// Midpoint solves (one per step and composition weight).
    pub solves: usize,
    /// Iterations over all solves (Newton steps or local/global rounds).
    pub iterations: usize,
    /// The most iterations one solve took.
    pub max_iterations: usize,
    /// Numeric factorisations (Newton: one per iteration; local/global: one
    /// per distinct step size).
    pub factorizations: usize,
    /// Symbolic analyses (once per run).
    pub symbolic_factorizations: usize,
    /// Solves started from the previous solve's correction (it lowered `Φ`).
    pub predicted: usize,
    /// Halvings of the line search over the run.
    pub backtracks: usize,
    /// Newton steps taken in full without the Armijo test because the
    /// predicted decrease of `Φ` was below its round-off.
    pub roundoff_steps: usize,
    /// Solves accepted at their round-off floor above the tolerance: three
    /// Newton steps in a row (each with a fresh factorisation) whose
    /// predicted decrease of `Φ` was below its round-off or that moved no
    /// coordinate by more than 4 ulps of the largest, and that no longer
    /// halved the gradient. Counted and reported, with their residual in
    /// `max_residual`.
    pub floor_accepts: usize,
    /// The largest final residual `‖∇Φ‖_∞/S` over all solves.
    pub max_residual: f64,
    /// Wall time in factorisations (s).
    pub factor_seconds: f64,
}

impl Stats {
    /// Iterations per step.
    pub fn iterations_per_step(&self) -> f64 {
        self.iterations as f64 / self.steps.max(1) as f64
    }
    /// Factorisations per step.
    pub fn factorizations_per_step(&self) -> f64 {
        self.factorizations as f64 / self.steps.max(1) as f64
    }
}

/// Why a midpoint solve failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MinimiseError {
    #[error(
        "the {solver} minimisation did not converge in {iterations} iterations (‖∇Φ‖ = {residual:e} of the force scale; tolerance {tolerance:e})"
    )]
    NotConverged {
        solver: &'static str,
        iterations: usize,
        residual: f64,
        tolerance: f64,
    },
    #[error(
        "the Newton line search found no decrease of the objective in {halvings} halvings at iteration {iteration} (‖∇Φ‖ = {residual:e} of the force scale)"
    )]
    LineSearch {
        iteration: usize,
        halvings: usize,
        residual: f64,
    },
    #[error("the Hessian is not numerically positive definite (pivot {pivot})")]
    NotDefinite { pivot: usize },
    #[error("a non-finite value appeared in the {solver} iteration {iteration}")]
    NonFinite {
        solver: &'static str,
        iteration: usize,
    },
}

/// The composition weights of a table that is a composition of implicit
/// midpoint steps: lower triangular with `aᵢᵢ = bᵢ/2`, `aᵢⱼ = bⱼ` (`j < i`),
/// every `bᵢ ≠ 0` and `cᵢ` the row sums. Decided on the `f64` table by exact
/// comparison (`bᵢ/2` is exact in binary, so a correctly rounded table of
/// this shape passes and no other does), `None` otherwise.
pub fn composition<const S: usize>(table: &ImplicitTable<S>) -> Option<Vec<f64>> {
    if table.a_hat.is_some() {
        return None;
    }
    for i in 0..S {
        if table.b[i] == 0.0 || !table.b[i].is_finite() || table.a[i][i] != table.b[i] / 2.0 {
            return None;
        }
        for j in 0..S {
            let want = if j < i {
                table.b[j]
            } else if j > i {
                0.0
            } else {
                continue;
            };
            if table.a[i][j] != want {
                return None;
            }
        }
    }
    Some(table.b.to_vec())
}

/// The composition weights of a named implicit scheme, if it is one of the
/// midpoint family ([`composition`]).
pub fn weights_of(id: &str) -> Option<Vec<f64>> {
    struct W;
    impl TableVisitor for W {
        type Output = Option<Vec<f64>>;
        fn visit<const S: usize>(
            self,
            table: &ImplicitTable<S>,
            _: &'static integrator_core::Info,
        ) -> Self::Output {
            composition(table)
        }
    }
    cloth_implicit::with_table(id, W).ok().flatten()
}

/// Whether `id` steps through the minimisation solvers: a scheme of
/// [`IMPLICIT`](crate::implicit::IMPLICIT) whose table is a composition of
/// midpoint steps (today `midpoint`, `paper-dirk2`, `paper-dirk4`), or the
/// discrete gradient ([`DISCRETE_GRADIENT`]).
pub fn is_minimisation(id: &str) -> bool {
    id == DISCRETE_GRADIENT || weights_of(id).is_some()
}

/// The name of the energy–momentum conserving comparison scheme.
pub const DISCRETE_GRADIENT: &str = "discrete-gradient";

/// The Newton linear algebra: the upper triangle of `(4/τ²)M + K⁺` in CSC.
struct NewtonLinear {
    /// Force-Jacobian values (full pattern).
    full: Vec<f64>,
    /// For each upper entry: its position in `full`, or `usize::MAX`.
    source: Vec<usize>,
    /// Positions of the diagonal entries in the upper values.
    diag: Vec<usize>,
    symbolic: SymbolicSparseColMat<usize>,
    cholesky: SymbolicCholesky<usize>,
    values: Vec<f64>,
    l_values: Vec<f64>,
    mem: MemBuffer,
    par: Par,
    /// The `c` of the factor in `l_values`, if any.
    factored: Option<f64>,
}

fn upper_structure(
    n: usize,
    entries: &mut Vec<(usize, usize, usize)>,
) -> (SymbolicSparseColMat<usize>, Vec<usize>, Vec<usize>) {
    entries.extend((0..n).map(|k| (k, k, usize::MAX)));
    entries.sort_unstable();
    entries.dedup_by_key(|e| (e.0, e.1));
    let mut col_ptr = vec![0usize; n + 1];
    for &(c, _, _) in entries.iter() {
        col_ptr[c + 1] += 1;
    }
    for c in 0..n {
        col_ptr[c + 1] += col_ptr[c];
    }
    let row_idx: Vec<usize> = entries.iter().map(|e| e.1).collect();
    let source: Vec<usize> = entries.iter().map(|e| e.2).collect();
    let diag: Vec<usize> = entries
        .iter()
        .enumerate()
        .filter(|(_, e)| e.0 == e.1)
        .map(|(k, _)| k)
        .collect();
    (
        SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx),
        source,
        diag,
    )
}

fn analyse(
    symbolic: &SymbolicSparseColMat<usize>,
    par: Par,
) -> (SymbolicCholesky<usize>, MemBuffer) {
    let cholesky = factorize_symbolic_cholesky(
        symbolic.as_ref(),
        Side::Upper,
        SymmetricOrdering::Amd,
        CholeskySymbolicParams::default(),
    )
    .expect("the symbolic Cholesky of a valid pattern");
    let mem = MemBuffer::new(StackReq::any_of(&[
        cholesky.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
        cholesky.solve_in_place_scratch::<f64>(3, par),
    ]));
    (cholesky, mem)
}

impl NewtonLinear {
    fn new(model: &ClothModel, par: Par) -> NewtonLinear {
        let n = 3 * model.free_count();
        let pattern = model.force_jacobian_pattern();
        let mut entries: Vec<(usize, usize, usize)> = pattern
            .iter()
            .enumerate()
            .filter(|(_, (r, c))| r <= c)
            .map(|(k, &(r, c))| (c, r, k))
            .collect();
        let (symbolic, source, diag) = upper_structure(n, &mut entries);
        let (cholesky, mem) = analyse(&symbolic, par);
        NewtonLinear {
            full: vec![0.0; pattern.len()],
            values: vec![0.0; source.len()],
            l_values: vec![0.0; cholesky.len_val()],
            source,
            diag,
            symbolic,
            cholesky,
            mem,
            par,
            factored: None,
        }
    }

    /// Factorise `c·I + K⁺(x)` (or, with `old = Some(q)`, the discrete
    /// gradient's projected Jacobian between `q` and `x` as midpoint).
    fn factor(
        &mut self,
        model: &ClothModel,
        x: &[f64],
        old: Option<&[f64]>,
        c: f64,
    ) -> Result<(), MinimiseError> {
        match old {
            None => model.force_jacobian_values_projected(x, &mut self.full),
            Some(q) => model.discrete_gradient_jacobian_projected(q, x, &mut self.full),
        }
        for (v, &s) in self.values.iter_mut().zip(&self.source) {
            *v = if s == usize::MAX { 0.0 } else { -self.full[s] };
        }
        for &d in &self.diag {
            self.values[d] += c;
        }
        let matrix = SparseColMatRef::new(self.symbolic.as_ref(), &self.values);
        self.factored = None;
        self.cholesky
            .factorize_numeric_llt(
                &mut self.l_values,
                matrix,
                Side::Upper,
                LltRegularization::default(),
                self.par,
                MemStack::new(&mut self.mem),
                Default::default(),
            )
            .map(|_| ())
            .map_err(|e| match e {
                faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } => {
                    MinimiseError::NotDefinite { pivot: index }
                }
            })?;
        if old.is_none() {
            self.factored = Some(c);
        }
        Ok(())
    }

    fn solve(&mut self, rhs: &mut [f64]) {
        let n = rhs.len();
        faer::sparse::linalg::cholesky::LltRef::new(&self.cholesky, &self.l_values)
            .solve_in_place_with_conj(
                Conj::No,
                MatMut::from_column_major_slice_mut(rhs, n, 1),
                self.par,
                MemStack::new(&mut self.mem),
            );
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

/// The local/global linear algebra: the scalar matrix `c·I + L` (upper),
/// factorised once per `c`.
struct LocalGlobalLinear {
    /// For each upper entry: the Laplacian value.
    laplacian: Vec<f64>,
    diag: Vec<usize>,
    symbolic: SymbolicSparseColMat<usize>,
    cholesky: SymbolicCholesky<usize>,
    values: Vec<f64>,
    /// Factorisations by `c` (a composition has up to three step sizes).
    factors: Vec<(f64, Vec<f64>)>,
    mem: MemBuffer,
    par: Par,
    /// `e` per spring and the right-hand side (three columns).
    rhs: Vec<f64>,
}

impl LocalGlobalLinear {
    fn new(model: &ClothModel, par: Par) -> LocalGlobalLinear {
        let n = model.free_count();
        let (ff, fp) = model.springs();
        // (column, row, value) of the upper triangle, summed.
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
        let mut entries: Vec<(usize, usize, usize)> = merged
            .iter()
            .enumerate()
            .map(|(k, e)| (e.0, e.1, k))
            .collect();
        let (symbolic, source, diag) = upper_structure(n, &mut entries);
        let laplacian = source.iter().map(|&s| merged[s].2).collect();
        let (cholesky, mem) = analyse(&symbolic, par);
        LocalGlobalLinear {
            laplacian,
            values: vec![0.0; source.len()],
            diag,
            symbolic,
            cholesky,
            factors: Vec::new(),
            mem,
            par,
            rhs: vec![0.0; 3 * n],
        }
    }

    /// The factor of `c·I + L`, computed on first use of `c`.
    fn factor(&mut self, c: f64, stats: &mut Stats) -> Result<usize, MinimiseError> {
        if let Some(k) = self.factors.iter().position(|(fc, _)| *fc == c) {
            return Ok(k);
        }
        let clock = Instant::now();
        self.values.copy_from_slice(&self.laplacian);
        for &d in &self.diag {
            self.values[d] += c;
        }
        let mut l = vec![0.0; self.cholesky.len_val()];
        let matrix = SparseColMatRef::new(self.symbolic.as_ref(), &self.values);
        self.cholesky
            .factorize_numeric_llt(
                &mut l,
                matrix,
                Side::Upper,
                LltRegularization::default(),
                self.par,
                MemStack::new(&mut self.mem),
                Default::default(),
            )
            .map_err(|e| match e {
                faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } => {
                    MinimiseError::NotDefinite { pivot: index }
                }
            })?;
        stats.factorizations += 1;
        stats.factor_seconds += clock.elapsed().as_secs_f64();
        if self.factors.len() >= 8 {
            self.factors.remove(0);
        }
        self.factors.push((c, l));
        Ok(self.factors.len() - 1)
    }

    /// Solve `(c·I + L) X = R` for the three coordinate columns of `rhs`
    /// (stored particle-major: `rhs[3k + axis]`).
    fn solve(&mut self, k: usize) {
        let n = self.rhs.len() / 3;
        // Reorder to column-major n × 3, solve, and back.
        let mut cols = std::mem::take(&mut self.rhs);
        let mut tmp = vec![0.0; 3 * n];
        for p in 0..n {
            for a in 0..3 {
                tmp[a * n + p] = cols[3 * p + a];
            }
        }
        faer::sparse::linalg::cholesky::LltRef::new(&self.cholesky, &self.factors[k].1)
            .solve_in_place_with_conj(
                Conj::No,
                MatMut::from_column_major_slice_mut(&mut tmp, n, 3),
                self.par,
                MemStack::new(&mut self.mem),
            );
        for p in 0..n {
            for a in 0..3 {
                cols[3 * p + a] = tmp[a * n + p];
            }
        }
        self.rhs = cols;
    }
}

/// The midpoint minimisation stepper for one cloth model: its linear
/// algebra (analysed once), buffers and counters.
pub struct Minimiser {
    settings: Settings,
    mass: f64,
    newton: Option<NewtonLinear>,
    dg: Option<DgLinear>,
    local_global: Option<LocalGlobalLinear>,
    x: Vec<f64>,
    y: Vec<f64>,
    /// `x̄ − y` of the last solve and its `c`.
    last_correction: Vec<f64>,
    last_c: Option<f64>,
    g: Vec<f64>,
    dx: Vec<f64>,
    /// Scratch for a gradient at a trial point.
    dx_scratch: Vec<f64>,
    trial: Vec<f64>,
    f: Vec<f64>,
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
            Solver::Newton => (Some(NewtonLinear::new(model, par)), None),
            Solver::LocalGlobal => {
                if model.has_colliders() {
                    return Err(RunError::Options(
                        "solver: local-global handles springs and gravity only; this scene has colliders (use --solver newton)".to_string(),
                    ));
                }
                (None, Some(LocalGlobalLinear::new(model, par)))
            }
        };
        stats.symbolic_factorizations = 1;
        Ok(Minimiser {
            settings,
            mass: model.particle_mass(),
            newton,
            dg: None,
            local_global,
            x: vec![0.0; n],
            y: vec![0.0; n],
            last_correction: vec![0.0; n],
            last_c: None,
            g: vec![0.0; n],
            dx: vec![0.0; n],
            dx_scratch: vec![0.0; n],
            trial: vec![0.0; n],
            f: vec![0.0; n],
            stats,
        })
    }

    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// One implicit midpoint step of size `tau` on `z = [q; p]`.
    pub fn midpoint_step(
        &mut self,
        model: &ClothModel,
        tau: f64,
        z: &mut [f64],
    ) -> Result<(), MinimiseError> {
        let n = z.len() / 2;
        let m = self.mass;
        let (q, p) = z.split_at_mut(n);
        for k in 0..n {
            self.y[k] = q[k] + 0.5 * tau * p[k] / m;
        }
        self.x.copy_from_slice(&self.y);
        let c = 4.0 * m / (tau * tau);
        let iterations = match self.settings.solver {
            Solver::Newton => self.newton_solve(model, c)?,
            Solver::LocalGlobal => self.local_global_solve(model, c)?,
        };
        for ((d, x), y) in self.last_correction.iter_mut().zip(&self.x).zip(&self.y) {
            *d = x - y;
        }
        self.last_c = Some(c);
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
                self.stats.max_residual = self.stats.max_residual.max(residual);
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
            self.stats.factor_seconds += clock.elapsed().as_secs_f64();
            self.stats.factorizations += 1;
            for (d, g) in self.dx.iter_mut().zip(&self.g) {
                *d = -g;
            }
            lin.solve(&mut self.dx);
            let mut alpha = 1.0;
            let mut halvings = 0;
            let mut trial_g = std::mem::take(&mut self.dx.clone());
            loop {
                for ((t, x), d) in self.trial.iter_mut().zip(&self.x).zip(&self.dx) {
                    *t = x + alpha * d;
                }
                let (r, nn) = dg_gradient(&self.trial, &mut self.f, &mut trial_g, &self.y);
                if nn < (1.0 - ARMIJO * alpha) * norm || r <= tol {
                    residual = r;
                    norm = nn;
                    break;
                }
                halvings += 1;
                self.stats.backtracks += 1;
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
            self.g.copy_from_slice(&trial_g);
        }
        self.stats.solves += 1;
        self.stats.iterations += it;
        self.stats.max_iterations = self.stats.max_iterations.max(it);
        self.stats.steps += 1;
        for k in 0..n {
            let xb = self.x[k];
            p[k] = m * (4.0 / h) * (xb - q[k]) - p[k];
            q[k] = 2.0 * xb - q[k];
        }
        Ok(())
    }

    fn newton_solve(&mut self, model: &ClothModel, c: f64) -> Result<usize, MinimiseError> {
        let tol = self.settings.tolerance;
        let cap = self.settings.max_iterations;
        let lin = self.newton.as_mut().expect("a Newton minimiser");
        // Start from y plus the previous solve's correction x̄ − y, scaled
        // by c_prev/c (it is about M⁻¹F·τ²/4), when that lowers Φ.
        let mut phi = objective(model, c, &self.x, &self.y);
        if let Some(c_prev) = self.last_c {
            let r = c_prev / c;
            for ((t, y), d) in self
                .trial
                .iter_mut()
                .zip(&self.y)
                .zip(&self.last_correction)
            {
                *t = y + r * d;
            }
            let guess = objective(model, c, &self.trial, &self.y);
            if guess.0 < phi.0 {
                std::mem::swap(&mut self.x, &mut self.trial);
                phi = guess;
                self.stats.predicted += 1;
            }
        }
        let mut residual = gradient(model, c, &self.x, &self.y, &mut self.f, &mut self.g);
        let mut it = 0;
        let mut stalled = 0;
        // Keep the last factor (of this c) while it contracts the gradient
        // by REUSE_CONTRACTION per iteration; refactorise otherwise.
        let mut refactor = lin.factored != Some(c);
        loop {
            if !residual.is_finite() || !phi.0.is_finite() {
                return Err(MinimiseError::NonFinite {
                    solver: "newton",
                    iteration: it,
                });
            }
            if residual <= tol {
                self.stats.max_residual = self.stats.max_residual.max(residual);
                return Ok(it);
            }
            if it == cap {
                return Err(MinimiseError::NotConverged {
                    solver: "newton",
                    iterations: it,
                    residual,
                    tolerance: tol,
                });
            }
            it += 1;
            let fresh = refactor || lin.factored != Some(c);
            if fresh {
                let clock = Instant::now();
                lin.factor(model, &self.x, None, c)?;
                self.stats.factor_seconds += clock.elapsed().as_secs_f64();
                self.stats.factorizations += 1;
            }
            for (d, g) in self.dx.iter_mut().zip(&self.g) {
                *d = -g;
            }
            lin.solve(&mut self.dx);
            let slope: f64 = self.dx.iter().zip(&self.g).map(|(d, g)| d * g).sum();
            if !slope.is_finite() {
                return Err(MinimiseError::NonFinite {
                    solver: "newton",
                    iteration: it,
                });
            }
            let mut alpha = 1.0;
            let mut halvings = 0;
            let new_phi = loop {
                for ((t, x), d) in self.trial.iter_mut().zip(&self.x).zip(&self.dx) {
                    *t = x + alpha * d;
                }
                let trial = objective(model, c, &self.trial, &self.y);
                // A decrease predicted below the round-off of Φ cannot be
                // tested on Φ: take the full Newton step (the gradient test
                // decides convergence, the cap stops a run that would not).
                if halvings == 0 && -slope <= ROUNDOFF * phi.1 {
                    self.stats.roundoff_steps += 1;
                    break trial;
                }
                if trial.0 <= phi.0 + ARMIJO * alpha * slope {
                    break trial;
                }
                // Where the decrease Armijo asks for is within a few
                // thousand ulps of Φ, Φ's own round-off decides the test:
                // there the full step is judged by the gradient instead
                // (taken when it shrinks ‖∇Φ‖).
                if halvings == 0 && -slope <= NOISY * phi.1 {
                    let mut g_trial = std::mem::take(&mut self.dx_scratch);
                    let r = gradient(model, c, &self.trial, &self.y, &mut self.f, &mut g_trial);
                    self.dx_scratch = g_trial;
                    if r < residual {
                        self.stats.roundoff_steps += 1;
                        break trial;
                    }
                }
                halvings += 1;
                self.stats.backtracks += 1;
                if halvings > MAX_HALVINGS || slope >= 0.0 {
                    return Err(MinimiseError::LineSearch {
                        iteration: it,
                        halvings,
                        residual,
                    });
                }
                alpha *= 0.5;
            };
            std::mem::swap(&mut self.x, &mut self.trial);
            phi = new_phi;
            let before = residual;
            residual = gradient(model, c, &self.x, &self.y, &mut self.f, &mut self.g);
            refactor = !fresh && (halvings > 0 || residual > REUSE_CONTRACTION * before);
            // At round-off: a predicted decrease below the round-off of Φ,
            // or a step that moved no coordinate by more than a few ulps of
            // the largest. Counted only for steps with a fresh factor.
            let moved = self.dx.iter().fold(0.0f64, |m, d| m.max((alpha * d).abs()));
            let x_max = self.x.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let at_roundoff = -slope <= ROUNDOFF * phi.1 || moved <= 4.0 * f64::EPSILON * x_max;
            if at_roundoff && !fresh && residual > 0.5 * before {
                refactor = true;
            } else if at_roundoff && residual > 0.5 * before {
                stalled += 1;
                if stalled >= 3 && residual > tol {
                    self.stats.floor_accepts += 1;
                    self.stats.max_residual = self.stats.max_residual.max(residual);
                    return Ok(it);
                }
            } else {
                stalled = 0;
            }
        }
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

/// Below this many ulps of `Φ`'s magnitude, Armijo's test is unreliable.
const NOISY: f64 = 4096.0 * f64::EPSILON;

/// A reused factorisation is kept while each iteration shrinks the
/// gradient by at least this factor.
const REUSE_CONTRACTION: f64 = 0.25;

/// Below this many ulps of `Φ`'s magnitude a predicted decrease is round-off.
const ROUNDOFF: f64 = 64.0 * f64::EPSILON;

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

/// `(Φ(x), |Φ|ₐ)`: the objective and the sum of the magnitudes of its
/// terms (what its round-off is relative to).
fn objective(model: &ClothModel, c: f64, x: &[f64], y: &[f64]) -> (f64, f64) {
    let inertia: f64 = 0.5 * c * x.iter().zip(y).map(|(x, y)| (x - y) * (x - y)).sum::<f64>();
    let (springs, gravity, colliders) = model.potential_terms(x);
    let w = model.weight();
    let gravity_abs: f64 = x
        .as_chunks::<3>()
        .0
        .iter()
        .map(|p| w.dot(&Vector3::from(*p)).abs())
        .sum();
    (
        inertia + springs + gravity + colliders,
        inertia + springs + gravity_abs + colliders,
    )
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
    mut on_frame: F,
) -> Result<MinimiseRun, RunError>
where
    F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
{
    let (method, weights): (&'static str, Option<Vec<f64>>) = if id == DISCRETE_GRADIENT {
        ("Discrete gradient (Gonzalez 1996), energy-momentum", None)
    } else {
        let weights = weights_of(id).ok_or_else(|| {
            if cloth_implicit::is_implicit(id) {
                MethodError::NotSteppable(id.to_string())
            } else {
                MethodError::Unknown(id.to_string())
            }
        })?;
        let info = cloth_implicit::info(id).expect("an implicit scheme");
        (info.name, Some(weights))
    };
    let h = opts.step_size();
    opts.check()?;
    settings.check()?;
    if weights.is_none() {
        if sim.model.has_colliders() {
            return Err(RunError::Options(format!(
                "method: {DISCRETE_GRADIENT} handles springs and gravity; this scene has colliders"
            )));
        }
        if settings.solver != Solver::Newton {
            return Err(RunError::Options(format!(
                "solver: {DISCRETE_GRADIENT} is solved with newton only (its equation is not a minimisation)"
            )));
        }
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
            let result = match &weights {
                Some(w) => solver.step(&sim.model, w, h, &mut sim.state),
                None => solver.discrete_gradient_step(&sim.model, h, &mut sim.state),
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
