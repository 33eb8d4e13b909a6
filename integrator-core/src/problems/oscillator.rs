//! The harmonic oscillator of the paper, `H = ½(p² + k²q²)`.

use super::ExactFlow;
use crate::system::Separable;

/// `H = ½(p² + k²q²)`: `q'' = −k²q`, angular frequency `k`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Oscillator {
    pub k: f64,
}

impl Separable for Oscillator {
    fn dof(&self) -> usize {
        1
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        0.5 * p[0] * p[0]
    }
    fn potential(&self, q: &[f64]) -> f64 {
        0.5 * self.k * self.k * q[0] * q[0]
    }
    fn velocity(&self, p: &[f64], out: &mut [f64]) {
        out[0] = p[0];
    }
    fn force(&self, q: &[f64], out: &mut [f64]) {
        out[0] = -self.k * self.k * q[0];
    }
}

impl ExactFlow for Oscillator {
    /// `q(t) = q₀ cos kt + (p₀/k) sin kt`, `p(t) = p₀ cos kt − k q₀ sin kt`.
    fn flow(&self, z0: &[f64], t: f64) -> Option<Vec<f64>> {
        let [q0, p0] = *z0 else { return None };
        let k = self.k;
        if k == 0.0 {
            return Some(vec![q0 + p0 * t, p0]);
        }
        let (s, c) = (k * t).sin_cos();
        Some(vec![q0 * c + p0 / k * s, p0 * c - k * q0 * s])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy;

    #[test]
    fn flow_solves_the_equations_and_keeps_energy() {
        let osc = Oscillator { k: 2.5 };
        let z0 = [0.3, -1.1];
        let e0 = energy(&osc, &z0);
        for i in 0..20 {
            let t = 0.37 * i as f64;
            let z = osc.flow(&z0, t).unwrap();
            assert!((energy(&osc, &z) - e0).abs() < 1e-14);
            // q' = p and p' = −k²q by central differences.
            let d = 1e-6;
            let (zp, zm) = (osc.flow(&z0, t + d).unwrap(), osc.flow(&z0, t - d).unwrap());
            assert!(((zp[0] - zm[0]) / (2.0 * d) - z[1]).abs() < 1e-8);
            assert!(((zp[1] - zm[1]) / (2.0 * d) + 6.25 * z[0]).abs() < 1e-8);
        }
        assert_eq!(osc.flow(&z0, 0.0).unwrap(), z0.to_vec());
        assert!(osc.flow(&[1.0], 1.0).is_none());
    }
}
