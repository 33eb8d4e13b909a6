//! A non-separable Hamiltonian, for what must not (or need not) treat a
//! Hamiltonian as separable.

use crate::system::Hamiltonian;

/// `H = ½(p₁² + p₂²)(1 + ε q₁²) + ½(q₁² + q₂²)`: a position-dependent mass.
/// Implements [`Hamiltonian`] only, not [`Separable`](crate::Separable).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NonSeparable {
    pub eps: f64,
}

impl Hamiltonian for NonSeparable {
    fn dof(&self) -> usize {
        2
    }
    fn energy(&self, q: &[f64], p: &[f64]) -> f64 {
        let pp = p[0] * p[0] + p[1] * p[1];
        0.5 * pp * (1.0 + self.eps * q[0] * q[0]) + 0.5 * (q[0] * q[0] + q[1] * q[1])
    }
    fn grad_q(&self, q: &[f64], p: &[f64], out: &mut [f64]) {
        let pp = p[0] * p[0] + p[1] * p[1];
        out[0] = pp * self.eps * q[0] + q[0];
        out[1] = q[1];
    }
    fn grad_p(&self, q: &[f64], p: &[f64], out: &mut [f64]) {
        let m = 1.0 + self.eps * q[0] * q[0];
        out[0] = m * p[0];
        out[1] = m * p[1];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradients_match_finite_differences() {
        let h = NonSeparable { eps: 0.7 };
        let (q, p) = ([0.4, -0.9], [1.3, 0.2]);
        let (mut gq, mut gp) = ([0.0; 2], [0.0; 2]);
        h.grad_q(&q, &p, &mut gq);
        h.grad_p(&q, &p, &mut gp);
        let d = 1e-6;
        for i in 0..2 {
            let (mut qp, mut qm, mut pp, mut pm) = (q, q, p, p);
            qp[i] += d;
            qm[i] -= d;
            pp[i] += d;
            pm[i] -= d;
            let dq = (h.energy(&qp, &p) - h.energy(&qm, &p)) / (2.0 * d);
            let dp = (h.energy(&q, &pp) - h.energy(&q, &pm)) / (2.0 * d);
            assert!((dq - gq[i]).abs() < 1e-8, "∂H/∂q{i}: {dq} vs {}", gq[i]);
            assert!((dp - gp[i]).abs() < 1e-8, "∂H/∂p{i}: {dp} vs {}", gp[i]);
        }
    }
}
