//! The spherical pendulum: a point mass on a massless rod of length `L`
//! in ℝ³, under gravity, as a constrained system.

use crate::constrained::Constrained;

/// `H = |p|²/(2m) + m g q₃` on the sphere `|q|² − L² = 0` (one constraint
/// in ℝ³; gravity along −e₃, the pivot at the origin).
///
/// The constraint is written `|q|² − L²` rather than `|q| − L`: it is a
/// polynomial (no square root, smooth everywhere, its gradient `2q` and
/// Hessian `2I` exact in floating point), and it has the same zero set.
///
/// Local coordinates for tests and references: spherical angles `θ` (from
/// the downward vertical) and `φ` (azimuth), with
/// `q = L(sin θ cos φ, sin θ sin φ, −cos θ)` and their conjugate momenta
/// `p_θ = p·∂q/∂θ = mL²θ'`, `p_φ = p·∂q/∂φ = mL² sin²θ φ'`, in which the
/// system is the ODE of `H = p_θ²/(2mL²) + p_φ²/(2mL² sin²θ) − mgL cos θ`
/// ([`local_rhs`](Self::local_rhs)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphericalPendulum {
    pub length: f64,
    pub mass: f64,
    pub gravity: f64,
}

impl SphericalPendulum {
    pub fn new(length: f64, mass: f64, gravity: f64) -> Self {
        SphericalPendulum {
            length,
            mass,
            gravity,
        }
    }

    /// The Cartesian state `[q; p]` at angles `(θ, φ)` with angular
    /// velocities `(θ', φ')`: on the manifold and tangent to it up to the
    /// rounding of the trigonometric functions.
    pub fn state(&self, theta: f64, phi: f64, theta_dot: f64, phi_dot: f64) -> Vec<f64> {
        let ml2 = self.mass * self.length * self.length;
        let s2 = theta.sin().powi(2);
        self.from_local(&[theta, phi, ml2 * theta_dot, ml2 * s2 * phi_dot])
    }

    /// `[θ, φ, p_θ, p_φ]` → `[q; p]`: the position on the sphere and the
    /// momentum in its tangent plane with `p·∂q/∂θ = p_θ`, `p·∂q/∂φ = p_φ`.
    pub fn from_local(&self, y: &[f64]) -> Vec<f64> {
        let [theta, phi, pt, pp] = [y[0], y[1], y[2], y[3]];
        let l = self.length;
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        // Orthonormal tangent vectors: ∂q/∂θ = L e_θ, ∂q/∂φ = L sin θ e_φ.
        let e_t = [ct * cp, ct * sp, st];
        let e_p = [-sp, cp, 0.0];
        let (at, ap) = (pt / l, pp / (l * st));
        vec![
            l * st * cp,
            l * st * sp,
            -l * ct,
            at * e_t[0] + ap * e_p[0],
            at * e_t[1] + ap * e_p[1],
            at * e_t[2] + ap * e_p[2],
        ]
    }

    /// `[q; p]` → `[θ, φ, p_θ, p_φ]` (`φ ∈ (−π, π]`). Defined off the
    /// manifold too (the angles of the direction of `q`), so that finite
    /// differences may leave it.
    pub fn to_local(&self, z: &[f64]) -> Vec<f64> {
        let (x, y, w) = (z[0], z[1], z[2]);
        let l = self.length;
        let rho = x.hypot(y);
        let theta = rho.atan2(-w);
        let phi = y.atan2(x);
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        let dq_dt = [l * ct * cp, l * ct * sp, l * st];
        let dq_dp = [-l * st * sp, l * st * cp, 0.0];
        let p = &z[3..6];
        let dot = |u: &[f64; 3]| u[0] * p[0] + u[1] * p[1] + u[2] * p[2];
        vec![theta, phi, dot(&dq_dt), dot(&dq_dp)]
    }

    /// The right-hand side of the ODE in local coordinates
    /// `y = [θ, φ, p_θ, p_φ]`.
    pub fn local_rhs(&self, y: &[f64], out: &mut [f64]) {
        let ml2 = self.mass * self.length * self.length;
        let (st, ct) = y[0].sin_cos();
        out[0] = y[2] / ml2;
        out[1] = y[3] / (ml2 * st * st);
        out[2] =
            y[3] * y[3] * ct / (ml2 * st * st * st) - self.mass * self.gravity * self.length * st;
        out[3] = 0.0;
    }
}

impl Constrained for SphericalPendulum {
    fn dof(&self) -> usize {
        3
    }
    fn constraints(&self) -> usize {
        1
    }
    fn inverse_mass(&self, out: &mut [f64]) {
        out.fill(1.0 / self.mass);
    }
    fn potential(&self, q: &[f64]) -> f64 {
        self.mass * self.gravity * q[2]
    }
    fn grad_potential(&self, _q: &[f64], out: &mut [f64]) {
        out[0] = 0.0;
        out[1] = 0.0;
        out[2] = self.mass * self.gravity;
    }
    fn constraint(&self, q: &[f64], out: &mut [f64]) {
        out[0] = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] - self.length * self.length;
    }
    fn constraint_jacobian(&self, q: &[f64], out: &mut [f64]) {
        for a in 0..3 {
            out[a] = 2.0 * q[a];
        }
    }
    fn curvature(&self, _q: &[f64], lambda: &[f64], out: &mut [f64]) -> bool {
        out.fill(0.0);
        for a in 0..3 {
            out[a * 3 + a] = 2.0 * lambda[0];
        }
        true
    }
    fn constraint_name(&self, _l: usize) -> String {
        "constraint 0 (|q|² − L², the rod)".to_string()
    }
}
