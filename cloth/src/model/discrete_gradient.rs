//! Gonzalez's discrete gradient of the springs: the force between two
//! configurations and its Jacobian (`crate::step::discrete_gradient` steps
//! with them).

use nalgebra::{Matrix3, Vector3};

use super::ClothModel;

impl ClothModel {
    /// The discrete gradient force of the springs and gravity between the
    /// positions `q` and `q' = 2x̄ − q`, given the midpoint `x̄` (Gonzalez
    /// 1996, in the spirit of Simo and Tarnow 1992): a spring with ends
    /// `d = q_b − q_a`, `d' = q'_b − q'_a` and `D = (d + d')/2 = x̄_b − x̄_a`
    /// pulls `b` by `−s·D` and `a` by `s·D` with
    /// `s = (k/L)(1 − 2L/(ℓ + ℓ'))`, `ℓ = |d|`, `ℓ' = |d'|`, so that
    /// `s·D·(d' − d) = ½(k/L)[(ℓ' − L)² − (ℓ − L)²]` exactly: the work of
    /// the force over the step is the change of the spring energy, and the
    /// forces are equal, opposite and along `D` (momentum and angular
    /// momentum kept). Gravity is linear and needs nothing. Colliders are
    /// not included (callers refuse scenes with colliders). Returns the
    /// force scale as [`force_and_scale`](Self::force_and_scale) does.
    pub fn discrete_gradient_force(&self, q: &[f64], xbar: &[f64], out: &mut [f64]) -> f64 {
        // With `dm = x̄_b − x̄_a`: `d' = 2·dm − d`.
        let (scale, kappa) = self.two_configuration_force(q, xbar, out, |d, dm, kl, rest| {
            let (l0, l1) = (d.norm(), (2.0 * dm - d).norm());
            dm * (kl - 2.0 * kl * rest / (l0 + l1))
        });
        let q_max = xbar.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        scale.max(kappa * q_max)
    }

    /// A positive semidefinite approximation of `−∂F̄/∂x̄` for
    /// [`discrete_gradient_force`](Self::discrete_gradient_force), in the
    /// layout of [`force_jacobian_pattern`](Self::force_jacobian_pattern)
    /// (as values of `∂F̄/∂x̄`, i.e. negated): a spring's exact block is
    /// `s·I + β·D·d'ᵀ`, `β = 4(k/L)L/((ℓ + ℓ')²ℓ')`; it is replaced by its
    /// symmetric part with `s` clamped at 0 and the rank-two term
    /// `½β(D·d'ᵀ + d'·Dᵀ)` projected onto its positive eigenvalue
    /// `½β(D·d' + |D||d'|)` along `D̂ + d̂'`. Allocates nothing.
    pub fn discrete_gradient_jacobian_projected(
        &self,
        q: &[f64],
        xbar: &[f64],
        values: &mut [f64],
    ) {
        self.discrete_gradient_jacobian_into(q, xbar, values, true);
    }

    /// The exact `∂F̄/∂x̄` of
    /// [`discrete_gradient_force`](Self::discrete_gradient_force) (not
    /// symmetric: a spring's block is `s·I + β·D·d'ᵀ`), in the layout of
    /// [`force_jacobian_pattern`](Self::force_jacobian_pattern), negated
    /// blocks as there. Allocates nothing.
    pub fn discrete_gradient_jacobian(&self, q: &[f64], xbar: &[f64], values: &mut [f64]) {
        self.discrete_gradient_jacobian_into(q, xbar, values, false);
    }

    fn discrete_gradient_jacobian_into(
        &self,
        q: &[f64],
        xbar: &[f64],
        values: &mut [f64],
        project: bool,
    ) {
        let block = |d: Vector3<f64>, dm: Vector3<f64>, kl: f64, rest: f64| -> Matrix3<f64> {
            let d1 = 2.0 * dm - d;
            let (l0, l1) = (d.norm(), d1.norm());
            let s = kl - 2.0 * kl * rest / (l0 + l1);
            let beta = 4.0 * kl * rest / ((l0 + l1) * (l0 + l1) * l1);
            if !project {
                // ∂(s·D)/∂D = s·I + β·D·d'ᵀ (d' = 2D − d).
                return Matrix3::from_diagonal_element(s) + (dm * d1.transpose()) * beta;
            }
            let s = s.max(0.0);
            let (na, nb) = (dm.norm(), l1);
            let mut k = Matrix3::from_diagonal_element(s);
            if na > 0.0 && nb > 0.0 {
                let u = dm / na + d1 / nb;
                let un = u.norm();
                let lam = 0.5 * beta * (dm.dot(&d1) + na * nb);
                if un > 0.0 && lam > 0.0 {
                    let u = u / un;
                    k += (u * u.transpose()) * lam;
                }
            }
            k
        };
        self.add_spring_blocks(q, xbar, values, block);
    }
}
