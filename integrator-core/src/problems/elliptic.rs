//! Jacobi elliptic functions and elliptic integrals of the first kind, for
//! the pendulum's exact solution. All take the parameter `m = k²` with
//! `0 ≤ m < 1`.
//!
//! * [`jacobi`]: `sn`, `cn`, `dn` by the descending Landen transformation
//!   (the AGM scale, Abramowitz–Stegun 16.4).
//! * [`complete_k`]: `K(m) = π / (2 AGM(1, √(1 − m)))` (A–S 17.6).
//! * [`incomplete_f`]: `F(φ | m)`, the inverse of the amplitude, by
//!   Carlson's symmetric integral `R_F` (DLMF 19.25.5, 19.36.1).

use std::f64::consts::PI;

/// The AGM scale of A–S 16.4: `a₀ = 1, b₀ = √(1 − m), c₀ = √m`, and
/// `aₙ₊₁ = (aₙ + bₙ)/2, bₙ₊₁ = √(aₙ bₙ), cₙ₊₁ = (aₙ − bₙ)/2` until `c_N`
/// is negligible. Returns `(a, c)` for `n = 0..=N`.
fn agm_scale(m: f64) -> (Vec<f64>, Vec<f64>) {
    let mut a = vec![1.0];
    let mut c = vec![m.sqrt()];
    let mut b = (1.0 - m).sqrt();
    // c shrinks quadratically; 40 rounds are far more than m < 1 − 1e-300 needs.
    for _ in 0..40 {
        let (an, cn) = (*a.last().unwrap(), *c.last().unwrap());
        if cn <= f64::EPSILON * an * 0.25 {
            break;
        }
        a.push(0.5 * (an + b));
        c.push(0.5 * (an - b));
        b = (an * b).sqrt();
    }
    (a, c)
}

/// The complete elliptic integral of the first kind `K(m)`, `0 ≤ m < 1`.
pub fn complete_k(m: f64) -> f64 {
    let (a, _) = agm_scale(m);
    PI / (2.0 * a.last().unwrap())
}

/// `(sn, cn, dn)(u | m)` for `0 ≤ m < 1`.
///
/// The argument is first reduced modulo the period `4K`, so the accuracy
/// does not degrade with `|u|` beyond the rounding of `u` itself.
pub fn jacobi(u: f64, m: f64) -> (f64, f64, f64) {
    let (a, c) = agm_scale(m);
    let n = a.len() - 1;
    let k4 = 4.0 * PI / (2.0 * a[n]);
    let u = u - k4 * (u / k4).round();
    // φ_N = 2^N a_N u, then φₙ₋₁ = (φₙ + asin((cₙ/aₙ) sin φₙ)) / 2.
    let mut phi = a[n] * u * f64::powi(2.0, n as i32);
    for i in (1..=n).rev() {
        phi = 0.5 * (phi + (c[i] / a[i] * phi.sin()).asin());
    }
    let (sn, cn) = phi.sin_cos();
    // dn² = 1 − m sn² = (1 − m) + m cn²: a sum of non-negative terms, so no
    // cancellation near sn = ±1 (where A–S's cn/cos(φ₁ − φ₀) is 0/0).
    let dn = ((1.0 - m) + m * cn * cn).sqrt();
    (sn, cn, dn)
}

/// Carlson's symmetric elliptic integral `R_F(x, y, z)` for non-negative
/// arguments, at most one of them zero (duplication to `|1 − x/A| < 1e-3`,
/// then the fifth-order series; truncation error below 1e-17).
pub fn carlson_rf(x: f64, y: f64, z: f64) -> f64 {
    let (mut x, mut y, mut z) = (x, y, z);
    for _ in 0..100 {
        let a = (x + y + z) / 3.0;
        let (dx, dy, dz) = (1.0 - x / a, 1.0 - y / a, 1.0 - z / a);
        if dx.abs().max(dy.abs()).max(dz.abs()) < 1e-3 {
            let e2 = dx * dy - dz * dz;
            let e3 = dx * dy * dz;
            return (1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0)
                / a.sqrt();
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * sy + sx * sz + sy * sz;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
    }
    f64::NAN
}

/// The incomplete elliptic integral of the first kind
/// `F(φ | m) = ∫₀^φ dθ / √(1 − m sin²θ)` for any real `φ`: the `u` with
/// `am(u | m) = φ`.
pub fn incomplete_f(phi: f64, m: f64) -> f64 {
    // F(φ + jπ) = F(φ) + 2jK; reduce to |φ| ≤ π/2 where
    // F(φ) = sin φ · R_F(cos²φ, 1 − m sin²φ, 1).
    let j = (phi / PI).round();
    let phi = phi - j * PI;
    let (s, c) = phi.sin_cos();
    let f = s * carlson_rf(c * c, 1.0 - m * s * s, 1.0);
    if j == 0.0 {
        f
    } else {
        f + 2.0 * j * complete_k(m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn complete_integral_known_values() {
        // K(0) = π/2; K(1/2) = Γ(1/4)² / (4√π) = 1.8540746773013719…;
        // K(0.9) = 2.5780921133481733 (A–S Table 17.1, DLMF).
        assert_eq!(complete_k(0.0), PI / 2.0);
        assert!((complete_k(0.5) - 1.854_074_677_301_371_9).abs() < 4e-16);
        assert!((complete_k(0.9) - 2.578_092_113_348_173_3).abs() < 1e-15);
        // F(π/2 | m) = K(m) by Carlson, independently of the AGM.
        for m in [0.1, 0.5, 0.9, 0.99] {
            let (f, k) = (incomplete_f(PI / 2.0, m), complete_k(m));
            assert!((f - k).abs() < 4e-15 * k, "m = {m}: F(π/2) = {f}, K = {k}");
        }
    }

    #[test]
    fn jacobi_identities_and_special_values() {
        for m in [0.0, 0.1, 0.5, 0.8, 0.95] {
            let k = complete_k(m);
            let (sn, cn, dn) = jacobi(k, m);
            assert!(
                (sn - 1.0).abs() < 1e-15 && cn.abs() < 1e-15,
                "m = {m}: sn(K) = {sn}, cn(K) = {cn}"
            );
            assert!((dn - (1.0 - m).sqrt()).abs() < 1e-15);
            let (sn, cn, _) = jacobi(2.0 * k, m);
            assert!(sn.abs() < 1e-15 && (cn + 1.0).abs() < 1e-15);
            for i in 0..50 {
                let u = -7.0 + 0.3 * i as f64;
                let (sn, cn, dn) = jacobi(u, m);
                assert!((sn * sn + cn * cn - 1.0).abs() < 4e-16);
                assert!((dn * dn + m * sn * sn - 1.0).abs() < 4e-16);
                // Derivatives: sn' = cn dn, cn' = −sn dn (central differences).
                let d = 1e-5;
                let (sp, cp, _) = jacobi(u + d, m);
                let (sm, cm, _) = jacobi(u - d, m);
                assert!(
                    ((sp - sm) / (2.0 * d) - cn * dn).abs() < 1e-9,
                    "m = {m}, u = {u}"
                );
                assert!(
                    ((cp - cm) / (2.0 * d) + sn * dn).abs() < 1e-9,
                    "m = {m}, u = {u}"
                );
            }
        }
        // m = 0: the circular functions exactly.
        let (sn, cn, dn) = jacobi(1.0, 0.0);
        assert_eq!((sn, cn, dn), (1f64.sin(), 1f64.cos(), 1.0));
    }

    #[test]
    fn f_inverts_the_amplitude() {
        for m in [0.0, 0.3, 0.7, 0.9] {
            for i in 0..41 {
                let phi = -6.0 + 0.3 * i as f64;
                let u = incomplete_f(phi, m);
                let (sn, cn, _) = jacobi(u, m);
                assert!(
                    (sn - phi.sin()).abs() < 2e-15,
                    "m = {m}, φ = {phi}: sn = {sn}"
                );
                assert!(
                    (cn - phi.cos()).abs() < 2e-15,
                    "m = {m}, φ = {phi}: cn = {cn}"
                );
            }
        }
        // Monotone in φ (dF/dφ > 0).
        assert!(incomplete_f(3.0, 0.9) > incomplete_f(1.0, 0.9));
    }
}
