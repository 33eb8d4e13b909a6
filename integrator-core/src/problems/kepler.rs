//! The Kepler problem `H = ½|p|² − 1/|q|` in the plane.

use super::ExactFlow;
use crate::system::Separable;
use std::f64::consts::PI;

/// `H = ½|p|² − 1/|q|` in 2D, `z = [q₁, q₂, p₁, p₂]`.
///
/// `e` selects the standard orbit, [`initial_state`](Kepler::initial_state):
/// at pericentre `q = (1 − e, 0)`, `p = (0, √((1 + e)/(1 − e)))`, semi-major
/// axis 1, energy −½, period 2π. Its exact state at time `t` is
/// [`exact`](Kepler::exact); [`ExactFlow::flow`] solves every bound orbit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kepler {
    pub e: f64,
}

/// Solves `E − e sin E = M` for `0 ≤ e < 1` by Newton's method to round-off
/// (`f' = 1 − e cos E ≥ 1 − e > 0`, and the start `M + e sin M` is within
/// the basin of quadratic convergence for moderate e; safeguarded by a
/// bracket of width 2e around `M` otherwise).
pub fn solve_kepler(e: f64, mean_anomaly: f64) -> f64 {
    let m = mean_anomaly;
    // E lies in [M − e, M + e] since |E − M| = e|sin E| ≤ e.
    let (mut lo, mut hi) = (m - e, m + e);
    let mut x = if e < 0.8 {
        m + e * m.sin()
    } else {
        m + e * m.sin().signum() * 0.85
    };
    x = x.clamp(lo, hi);
    for _ in 0..100 {
        let (s, c) = x.sin_cos();
        let f = x - e * s - m;
        if f == 0.0 {
            return x;
        }
        if f > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        let dx = f / (1.0 - e * c);
        let next = x - dx;
        if !(next >= lo && next <= hi) {
            // Newton left the bracket: bisect instead.
            x = 0.5 * (lo + hi);
            continue;
        }
        if dx.abs() <= f64::EPSILON * x.abs().max(1.0) {
            return next;
        }
        x = next;
    }
    x
}

impl Kepler {
    /// Pericentre of the orbit with eccentricity `e`, semi-major axis 1.
    pub fn initial_state(&self) -> Vec<f64> {
        let e = self.e;
        vec![1.0 - e, 0.0, 0.0, ((1.0 + e) / (1.0 - e)).sqrt()]
    }

    /// The period of the standard orbit: 2π.
    pub const PERIOD: f64 = 2.0 * PI;

    /// The exact state at time `t` on the standard orbit: with the
    /// eccentric anomaly `E − e sin E = t`,
    /// `q = (cos E − e, √(1−e²) sin E)`, `p = (−sin E, √(1−e²) cos E)/(1 − e cos E)`.
    pub fn exact(&self, t: f64) -> Vec<f64> {
        let e = self.e;
        // Reduce t modulo the period so E stays in [−π − e, π + e].
        let m = t - 2.0 * PI * (t / (2.0 * PI)).round();
        let big_e = solve_kepler(e, m);
        let (s, c) = big_e.sin_cos();
        let w = ((1.0 - e) * (1.0 + e)).sqrt();
        let r = 1.0 - e * c;
        vec![c - e, w * s, -s / r, w * c / r]
    }

    /// The angular momentum `L = q₁p₂ − q₂p₁`, an invariant.
    pub fn angular_momentum(z: &[f64]) -> f64 {
        z[0] * z[3] - z[1] * z[2]
    }
}

impl Separable for Kepler {
    fn dof(&self) -> usize {
        2
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        0.5 * (p[0] * p[0] + p[1] * p[1])
    }
    /// `−1/r`, with `r = √(q₁² + q₂²)` as the force computes it (not
    /// `hypot`, a library call several times slower and of no use away
    /// from overflow), so that `force_and_potential` gives the same bits.
    fn potential(&self, q: &[f64]) -> f64 {
        -1.0 / (q[0] * q[0] + q[1] * q[1]).sqrt()
    }
    fn velocity(&self, p: &[f64], out: &mut [f64]) {
        out[0] = p[0];
        out[1] = p[1];
    }
    fn force(&self, q: &[f64], out: &mut [f64]) {
        let r2 = q[0] * q[0] + q[1] * q[1];
        let r3 = r2 * r2.sqrt();
        out[0] = -q[0] / r3;
        out[1] = -q[1] / r3;
    }
    /// One square root for both (the logarithmic Hamiltonian needs `V`
    /// at every kick).
    fn force_and_potential(&self, q: &[f64], out: &mut [f64]) -> f64 {
        let r2 = q[0] * q[0] + q[1] * q[1];
        let r = r2.sqrt();
        let r3 = r2 * r;
        out[0] = -q[0] / r3;
        out[1] = -q[1] / r3;
        -1.0 / r
    }
}

impl ExactFlow for Kepler {
    /// Any bound orbit (`H < 0`, `q ≠ 0`), by the Lagrange coefficients
    /// `q(t) = f q₀ + g p₀`, `p(t) = ḟ q₀ + ġ p₀` in terms of the change of
    /// eccentric anomaly ΔE, from Kepler's equation (Battin, *An
    /// Introduction to the Mathematics and Methods of Astrodynamics*, 4.5).
    fn flow(&self, z0: &[f64], t: f64) -> Option<Vec<f64>> {
        let [x, y, u, v] = *z0 else { return None };
        let r0 = x.hypot(y);
        let energy = 0.5 * (u * u + v * v) - 1.0 / r0;
        if !(energy < 0.0 && r0 > 0.0 && t.is_finite()) {
            return None;
        }
        let a = -0.5 / energy;
        let n = a.powf(-1.5);
        let sigma = x * u + y * v;
        // e cos E₀ = 1 − r₀/a, e sin E₀ = σ₀/√a.
        let (ec, es) = (1.0 - r0 / a, sigma / a.sqrt());
        let e = ec.hypot(es);
        let e0 = es.atan2(ec);
        // Whole periods change nothing; reduce t to keep g accurate.
        let period = 2.0 * PI / n;
        let t = t - period * (t / period).round();
        let big_e = solve_kepler(e, e0 - es + n * t);
        let de = big_e - e0;
        let (s, c) = de.sin_cos();
        let r = a + (r0 - a) * c + sigma * a.sqrt() * s;
        let f = 1.0 - a / r0 * (1.0 - c);
        let g = t - (de - s) / n;
        let fdot = -a.sqrt() * s / (r * r0);
        let gdot = 1.0 - a / r * (1.0 - c);
        Some(vec![
            f * x + g * u,
            f * y + g * v,
            fdot * x + gdot * u,
            fdot * y + gdot * v,
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::library::Rk4;
    use crate::{energy, integrate};

    #[test]
    fn kepler_equation_to_round_off() {
        for e in [0.0, 0.1, 0.6, 0.9, 0.99] {
            for i in 0..=64 {
                let m = -PI + PI * i as f64 / 32.0;
                let x = solve_kepler(e, m);
                assert!(
                    (x - e * x.sin() - m).abs() <= 4.0 * f64::EPSILON * m.abs().max(1.0),
                    "e = {e}, M = {m}: residual {:e}",
                    x - e * x.sin() - m
                );
            }
        }
    }

    #[test]
    fn standard_orbit_invariants_and_period() {
        let k = Kepler { e: 0.6 };
        let z0 = k.initial_state();
        assert_eq!(k.exact(0.0), z0);
        assert_eq!(energy(&k, &z0), -0.5);
        let l0 = Kepler::angular_momentum(&z0);
        assert!((l0 - 0.8).abs() < 1e-15, "L = √(1 − e²)");
        for i in 0..50 {
            let t = 0.31 * i as f64;
            let z = k.exact(t);
            assert!((energy(&k, &z) + 0.5).abs() < 1e-14);
            assert!((Kepler::angular_momentum(&z) - l0).abs() < 1e-14);
            // The general flow agrees with the standard one, also from a
            // point that is not the pericentre.
            let w = k.flow(&z0, t).unwrap();
            let from_mid = k.flow(&k.exact(1.3), t - 1.3).unwrap();
            for j in 0..4 {
                assert!(
                    (w[j] - z[j]).abs() < 1e-13,
                    "t = {t}: flow {w:?} vs exact {z:?}"
                );
                assert!(
                    (from_mid[j] - z[j]).abs() < 1e-13,
                    "t = {t}: {from_mid:?} vs {z:?}"
                );
            }
        }
        let back = k.exact(Kepler::PERIOD);
        assert!(back.iter().zip(&z0).all(|(a, b)| (a - b).abs() < 1e-14));
        assert!(k.flow(&[1.0, 0.0, 0.0, 1.5], 1.0).is_none(), "unbound");
    }

    #[test]
    fn exact_matches_a_tiny_step_integration() {
        // RK4 with h = 2π/2¹⁴ over one period of the e = 0.6 orbit.
        let k = Kepler { e: 0.6 };
        let n = 1 << 14;
        let h = Kepler::PERIOD / n as f64;
        let mut z = k.initial_state();
        let mut worst: f64 = 0.0;
        integrate(&Rk4, &k, &mut z, 0.0, h, n, |i, t, z| {
            if i % 512 == 0 {
                let x = k.exact(t);
                worst = x
                    .iter()
                    .zip(z)
                    .map(|(a, b)| (a - b).abs())
                    .fold(worst, f64::max);
            }
        })
        .unwrap();
        assert!(worst < 1e-9, "exact vs RK4: {worst:e}");
    }
}
