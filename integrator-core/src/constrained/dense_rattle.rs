//! A [`Constrained`] system on the one RATTLE ([`Rattle`]) with dense LU
//! factors: the small systems' choice of linear algebra (a spherical
//! pendulum, a pendulum chain), where a dense solve is cheapest.

use super::dense_lu::DenseLu;
use super::rattle::{ConstraintSolver, RattleSystem, Singular};
use super::system::Constrained;

/// A [`Constrained`] system seen by [`Rattle`](super::rattle::Rattle): the
/// geometry is `G(q)` itself (row-major `m × d`), the multipliers are
/// `κ = h²λ/2` (so that the displacement is `M⁻¹G(q)ᵀκ`), and the
/// position solve stops when every `|gₗ(q')|` is within `tolerance` units
/// of its round-off `ε·‖∇gₗ‖₁·‖q‖∞` (the scale of
/// [`Residual`](super::Residual)).
pub(crate) struct DenseSystem<'a, S: ?Sized> {
    pub sys: &'a S,
    pub minv: &'a [f64],
    pub tolerance: f64,
}

impl<S: Constrained + ?Sized> DenseSystem<'_, S> {
    fn m(&self) -> usize {
        self.sys.constraints()
    }
}

impl<S: Constrained + ?Sized> RattleSystem for DenseSystem<'_, S> {
    type Geometry = Vec<f64>;

    fn coordinates(&self) -> usize {
        self.minv.len()
    }
    fn constraint_count(&self) -> usize {
        self.m()
    }
    fn mass(&self, out: &mut [f64]) {
        for (o, w) in out.iter_mut().zip(self.minv) {
            *o = 1.0 / w;
        }
    }
    fn inverse_mass(&self, out: &mut [f64]) {
        out.copy_from_slice(self.minv);
    }
    fn force(&self, q: &[f64], out: &mut [f64]) {
        self.sys.grad_potential(q, out);
        for f in out.iter_mut() {
            *f = -*f;
        }
    }
    fn new_geometry(&self) -> Vec<f64> {
        vec![0.0; self.m() * self.minv.len()]
    }
    fn geometry(&self, q: &[f64], geo: &mut Vec<f64>) {
        self.sys.constraint_jacobian(q, geo);
    }
    fn displace(&self, geo: &Vec<f64>, kappa: &[f64], out: &mut [f64]) {
        self.impulse(geo, kappa, out);
        for (o, w) in out.iter_mut().zip(self.minv) {
            *o *= w;
        }
    }
    fn impulse(&self, geo: &Vec<f64>, mu: &[f64], out: &mut [f64]) {
        let d = self.minv.len();
        out.fill(0.0);
        for (row, &x) in geo.chunks_exact(d).zip(mu) {
            for (o, g) in out.iter_mut().zip(row) {
                *o += g * x;
            }
        }
    }
    fn tangent(&self, geo: &Vec<f64>, p: &[f64], out: &mut [f64]) {
        let d = self.minv.len();
        for (o, row) in out.iter_mut().zip(geo.chunks_exact(d)) {
            *o = row
                .iter()
                .zip(self.minv)
                .zip(p)
                .map(|((g, w), p)| g * w * p)
                .sum();
        }
    }
    /// In the scale of [`Residual`](super::Residual), `ε·‖∇gₗ‖₁·‖q‖∞`
    /// of `q` itself (the step's `q_scale` also counts `q̂`, which would
    /// stop the iteration above the round-off a caller measures).
    fn residuals(&self, q: &[f64], geo: &Vec<f64>, _q_scale: f64, out: &mut [f64]) -> f64 {
        let d = self.minv.len();
        let q_scale = q.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        self.sys.constraint(q, out);
        let mut worst = 0.0f64;
        for (g, row) in out.iter().zip(geo.chunks_exact(d)) {
            if *g == 0.0 {
                continue;
            }
            let scale: f64 = row.iter().map(|x| x.abs()).sum();
            worst = worst.max(g.abs() / (f64::EPSILON * scale * q_scale));
        }
        worst
    }
    fn tolerance(&self) -> f64 {
        self.tolerance
    }
    /// `tolerance·ε·max‖∇gₗ‖₁·‖M⁻¹p‖∞`, the round-off of `G M⁻¹ p`.
    fn projection_tolerance(&self, geo: &Vec<f64>, p: &[f64]) -> f64 {
        let d = self.minv.len();
        let gn = geo
            .chunks_exact(d)
            .map(|row| row.iter().map(|x| x.abs()).sum::<f64>())
            .fold(0.0f64, f64::max);
        let vn = p
            .iter()
            .zip(self.minv)
            .fold(0.0f64, |a, (p, w)| a.max((p * w).abs()));
        self.tolerance * f64::EPSILON * gn * vn
    }
}

/// Dense LU factors of `A = G(q)M⁻¹G(q)ᵀ` and of the true Jacobian
/// `G(q')M⁻¹G(q)ᵀ`, in storage made once.
pub(crate) struct DenseGram {
    a: DenseLu,
    j: DenseLu,
    m: usize,
}

impl DenseGram {
    pub fn new(m: usize) -> Self {
        DenseGram {
            a: DenseLu::new(m),
            j: DenseLu::new(m),
            m,
        }
    }
}

/// `lu ← G₁ M⁻¹ G₀ᵀ` factorised; `Err` at a pivot below `4mε·max|Aᵢⱼ|`.
fn factor_product(lu: &mut DenseLu, m: usize, minv: &[f64], g1: &[f64], g0: &[f64]) -> bool {
    let d = minv.len();
    for l in 0..m {
        let r1 = &g1[l * d..(l + 1) * d];
        for k in 0..m {
            let r0 = &g0[k * d..(k + 1) * d];
            let x: f64 = r1
                .iter()
                .zip(minv)
                .zip(r0)
                .map(|((a, w), b)| a * w * b)
                .sum();
            lu.set(l, k, x);
        }
    }
    lu.factor(4.0 * m as f64 * f64::EPSILON).is_none()
}

impl<S: Constrained + ?Sized> ConstraintSolver<DenseSystem<'_, S>> for DenseGram {
    fn factorize(&mut self, sys: &DenseSystem<'_, S>, geo: &Vec<f64>) -> Result<(), Singular> {
        if factor_product(&mut self.a, self.m, sys.minv, geo, geo) {
            Ok(())
        } else {
            Err(Singular)
        }
    }
    fn solve(&mut self, rhs: &mut [f64]) {
        self.a.solve(rhs);
    }
    fn factorize_jacobian(
        &mut self,
        sys: &DenseSystem<'_, S>,
        geo: &Vec<f64>,
        geo1: &Vec<f64>,
    ) -> Result<bool, Singular> {
        if factor_product(&mut self.j, self.m, sys.minv, geo1, geo) {
            Ok(false)
        } else {
            Err(Singular)
        }
    }
    fn solve_jacobian(&mut self, rhs: &mut [f64]) {
        self.j.solve(rhs);
    }
}
