//! The mathematical pendulum `H = p²/2 − cos q`.

use super::ExactFlow;
use super::elliptic::{complete_k, incomplete_f, jacobi};
use crate::system::Separable;
use std::f64::consts::PI;

/// `H = p²/2 − cos q`: `q'' = −sin q`.
///
/// In the libration case (`H < 1`) the exact solution is
/// `sin(q/2) = k sn(t + u₀ | k²)`, `p = 2k cn(t + u₀ | k²)` with modulus
/// `k = sin(q_max/2) = √((1 + H)/2)` and phase `u₀ = F(am₀ | k²)`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pendulum;

impl Pendulum {
    /// The state at rest at angle `amplitude` (`= q_max`), a turning point.
    pub fn at_rest(amplitude: f64) -> Vec<f64> {
        vec![amplitude, 0.0]
    }

    /// The parameter `m = k² = (1 + H)/2` of the orbit through `z0`
    /// (`m < 1`: libration).
    pub fn parameter(z0: &[f64]) -> f64 {
        let (q, p) = (z0[0], z0[1]);
        // (1 + H)/2 = p²/4 + sin²(q/2), written without the cancellation of 1 − cos q.
        let s = (0.5 * q).sin();
        0.25 * p * p + s * s
    }

    /// The period `4K(k²)` of the libration through `z0`, `None` if it rotates.
    pub fn period(z0: &[f64]) -> Option<f64> {
        let m = Self::parameter(z0);
        (m < 1.0).then(|| 4.0 * complete_k(m))
    }
}

impl Separable for Pendulum {
    fn dof(&self) -> usize {
        1
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        0.5 * p[0] * p[0]
    }
    fn potential(&self, q: &[f64]) -> f64 {
        -q[0].cos()
    }
    fn velocity(&self, p: &[f64], out: &mut [f64]) {
        out[0] = p[0];
    }
    fn force(&self, q: &[f64], out: &mut [f64]) {
        out[0] = -q[0].sin();
    }
}

impl ExactFlow for Pendulum {
    /// The libration case only (`H < 1`); `None` for rotations and the
    /// separatrix.
    fn flow(&self, z0: &[f64], t: f64) -> Option<Vec<f64>> {
        let [q0, p0] = *z0 else { return None };
        if !(q0.is_finite() && p0.is_finite() && t.is_finite()) {
            return None;
        }
        let m = Self::parameter(z0);
        if m >= 1.0 {
            return None;
        }
        // Shift q into (−π, π]; the shift is added back at the end.
        let turns = (q0 / (2.0 * PI)).round();
        let q0 = q0 - 2.0 * PI * turns;
        if m == 0.0 {
            return Some(z0.to_vec());
        }
        let k = m.sqrt();
        // sn(u₀) = sin(q₀/2)/k, cn(u₀) = p₀/(2k): the amplitude is
        // am(u₀) = atan2(sin(q₀/2), p₀/2), and u₀ = F(am(u₀) | m).
        let u0 = incomplete_f((0.5 * q0).sin().atan2(0.5 * p0), m);
        let (sn, cn, dn) = jacobi(u0 + t, m);
        // sin(q/2) = k sn and cos(q/2) = dn (> 0 in libration).
        let q = 2.0 * (k * sn).atan2(dn) + 2.0 * PI * turns;
        Some(vec![q, 2.0 * k * cn])
    }
}

/// The pendulum with a non-quadratic kinetic energy,
/// `H = p²/2 + α p⁴/4 − cos q`: `q' = p + α p³`, `p' = −sin q`.
///
/// Separable, but with `T` not quadratic, so the order conditions that
/// Runge–Kutta–Nyström methods skip are in play (the catalogue's
/// McLachlan–Atela 4/5 and Calvo–Sanz-Serna 4 drop to order 3 on it). No
/// closed-form solution is provided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuarticPendulum {
    pub alpha: f64,
}

impl Separable for QuarticPendulum {
    fn dof(&self) -> usize {
        1
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        let p2 = p[0] * p[0];
        0.5 * p2 + 0.25 * self.alpha * p2 * p2
    }
    fn potential(&self, q: &[f64]) -> f64 {
        -q[0].cos()
    }
    fn velocity(&self, p: &[f64], out: &mut [f64]) {
        out[0] = p[0] + self.alpha * p[0] * p[0] * p[0];
    }
    fn force(&self, q: &[f64], out: &mut [f64]) {
        out[0] = -q[0].sin();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::library::Rk4;
    use crate::{energy, integrate};

    #[test]
    fn flow_matches_a_tiny_step_integration() {
        // RK4 with h = 1/1024 to t = 8: global error ~1e-13 here.
        let starts: [[f64; 2]; 5] = [
            [1.0, 0.0],
            [0.3, -0.8],
            [-2.5, 0.4],
            [2.9, 0.0],
            [0.2 + 4.0 * PI, 1.2],
        ];
        for z0 in starts {
            let n = 8 * 1024;
            let h = 1.0 / 1024.0;
            let mut z = z0;
            let mut worst: f64 = 0.0;
            integrate(&Rk4, &Pendulum, &mut z, 0.0, h, n, |i, t, z| {
                if i % 256 == 0 {
                    let x = Pendulum.flow(&z0, t).unwrap();
                    worst = worst.max((x[0] - z[0]).abs()).max((x[1] - z[1]).abs());
                }
            })
            .unwrap();
            assert!(
                worst < 1e-10,
                "z0 = {z0:?}: exact vs RK4 differ by {worst:e}"
            );
        }
    }

    #[test]
    fn flow_is_periodic_and_keeps_energy() {
        for z0 in [
            Pendulum::at_rest(2.0),
            vec![-0.5, 1.1],
            Pendulum::at_rest(3.0),
        ] {
            let period = Pendulum::period(&z0).unwrap();
            let e0 = energy(&Pendulum, &z0);
            let back = Pendulum.flow(&z0, period).unwrap();
            assert!(
                (back[0] - z0[0]).abs() < 1e-13 && (back[1] - z0[1]).abs() < 1e-13,
                "{z0:?} → {back:?}"
            );
            for i in 0..30 {
                let z = Pendulum.flow(&z0, 0.77 * i as f64).unwrap();
                assert!((energy(&Pendulum, &z) - e0).abs() < 1e-14);
            }
            let start = Pendulum.flow(&z0, 0.0).unwrap();
            assert!((start[0] - z0[0]).abs() < 1e-15 && (start[1] - z0[1]).abs() < 1e-15);
        }
        // Small amplitude: period → 2π; q_max = 2: 4K(sin²1) = 8.3497529269… (AGM in
        // Python, independently).
        assert!((Pendulum::period(&Pendulum::at_rest(1e-4)).unwrap() - 2.0 * PI).abs() < 1e-8);
        let t2 = Pendulum::period(&Pendulum::at_rest(2.0)).unwrap();
        assert!((t2 - 8.349_752_926_918_493).abs() < 1e-14, "period {t2}");
        assert!(Pendulum.flow(&[0.0, 2.5], 1.0).is_none(), "rotation");
    }

    #[test]
    fn quartic_pendulum_gradients() {
        let sys = QuarticPendulum { alpha: 1.0 };
        let (q, p, d) = (0.7, -1.3, 1e-6);
        let (mut v, mut f) = ([0.0], [0.0]);
        sys.velocity(&[p], &mut v);
        sys.force(&[q], &mut f);
        let dt = (sys.kinetic(&[p + d]) - sys.kinetic(&[p - d])) / (2.0 * d);
        let dv = (sys.potential(&[q + d]) - sys.potential(&[q - d])) / (2.0 * d);
        assert!((dt - v[0]).abs() < 1e-8 && (dv + f[0]).abs() < 1e-8);
    }
}
