//! Gonzalez's discrete gradient (1996) on cloth: `x̄ = (q + q')/2` solves
//! `(4/h²)M(x̄ − y) = F̄(q, x̄)` with the cloth's discrete-gradient force
//! ([`ClothModel::discrete_gradient_force`]). Its equation is not a
//! minimisation (its Jacobian is not symmetric), so Newton with faer's
//! sparse LU and a line search on the residual; it stops on the
//! minimisations' gradient test, and [`Minimiser`](super::Minimiser) runs it.

use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par};
use integrator_core::minimise::{MinimiseError, Stats, converged};

use super::Refused;
use crate::method::DISCRETE_GRADIENT;
use crate::model::ClothModel;

/// Halvings of the discrete gradient's Newton step before its line search
/// gives up.
const MAX_HALVINGS: usize = 60;

/// The sufficient-decrease constant of the discrete gradient's line search.
const ARMIJO: f64 = 1e-4;

/// The discrete gradient's linear algebra: `c·I − ∂F̄/∂x̄` (not symmetric)
/// with faer's sparse LU, symbolic analysis once.
pub(super) struct DgLinear {
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
    pub(super) fn new(model: &ClothModel, par: Par) -> Result<DgLinear, Refused> {
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
            return Err(Refused(format!(
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
                    Refused(format!(
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

/// The discrete gradient's solver: its linear algebra (analysed once) and
/// buffers.
pub(super) struct DiscreteGradient {
    lin: DgLinear,
    x: Vec<f64>,
    y: Vec<f64>,
    g: Vec<f64>,
    dx: Vec<f64>,
    /// Scratch for a gradient at a trial point.
    g_trial: Vec<f64>,
    trial: Vec<f64>,
    f: Vec<f64>,
}

impl DiscreteGradient {
    /// The symbolic LU of the springs' pattern, and buffers for `model`.
    pub(super) fn new(model: &ClothModel) -> Result<DiscreteGradient, Refused> {
        let n = 3 * model.free_count();
        Ok(DiscreteGradient {
            lin: DgLinear::new(model, Par::Seq)?,
            x: vec![0.0; n],
            y: vec![0.0; n],
            g: vec![0.0; n],
            dx: vec![0.0; n],
            g_trial: vec![0.0; n],
            trial: vec![0.0; n],
            f: vec![0.0; n],
        })
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
    #[allow(clippy::too_many_arguments)]
    pub(super) fn step(
        &mut self,
        model: &ClothModel,
        mass: f64,
        (tol, cap): (f64, usize),
        h: f64,
        z: &mut [f64],
        stats: &mut Stats,
    ) -> Result<(), MinimiseError> {
        let n = z.len() / 2;
        let m = mass;
        let c = 4.0 * m / (h * h);
        let (q, p) = z.split_at_mut(n);
        for k in 0..n {
            self.y[k] = q[k] + 0.5 * h * p[k] / m;
        }
        self.x.copy_from_slice(&self.y);
        let lin = &mut self.lin;
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
            if converged("discrete-gradient", it, residual, tol, cap)? {
                stats.max_residual = stats.max_residual.max(residual);
                break;
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
}
