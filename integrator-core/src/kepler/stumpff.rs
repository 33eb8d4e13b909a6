//! Stumpff's functions: [`stumpff`].

/// Below this `|z|` the series is used (a change of eccentric anomaly of up
/// to two radians, a third of a turn).
pub(super) const SERIES_LIMIT: f64 = 4.0;
/// Below this `|z|` ten terms of the series reach the last bit (twelve up
/// to [`SERIES_LIMIT`]).
pub(super) const SERIES_LONG: f64 = 1.0;
/// Below this `|z|` five terms of the series reach the last bit.
pub(super) const SERIES_SHORT: f64 = 1e-2;
/// Below this `|z|` seven terms do (ten up to [`SERIES_LONG`]).
pub(super) const SERIES_MID: f64 = 0.1;

/// `1/24 − C2[1]`, `1/6 − C3[0]` and `1/120 − C3[1]`: what rounding the
/// first coefficients to f64 left out (computed exactly with rational
/// arithmetic, then rounded; checked by a test). Each rounding is the same
/// at every call — `C3[0]` is 0.25 ulp below 1/6 — so left out, it is a
/// bias of `G₃` (and, through `z·c`, of the other `Gₖ`) of the same sign
/// at every step, which made the energy of a long run of drifts drift
/// linearly (measured: 0.004 ulp per step at h = P/16, growing with the
/// eccentricity); added back below the leading term, it is rounded away
/// with the sum, like any other rounding.
pub(super) const C2_1_LO: f64 = 2.3129646346357427e-18;
pub(super) const C3_0_LO: f64 = 9.25185853854297e-18;
pub(super) const C3_1_LO: f64 = 1.1564823173178714e-19;

/// `1/(2k+2)!` for `k = 0 … 11`: the coefficients of `c₂(z) = Σ (−z)ᵏ/(2k+2)!`.
pub(super) const C2: [f64; 12] = [
    1.0 / 2.0,
    1.0 / 24.0,
    1.0 / 720.0,
    1.0 / 40320.0,
    1.0 / 3628800.0,
    1.0 / 479001600.0,
    1.0 / 87178291200.0,
    1.0 / 20922789888000.0,
    1.0 / 6402373705728000.0,
    1.0 / 2432902008176640000.0,
    1.0 / 1124000727777607680000.0,
    1.0 / 620448401733239439360000.0,
];

/// `1/(2k+3)!` for `k = 0 … 11`: the coefficients of `c₃(z) = Σ (−z)ᵏ/(2k+3)!`.
pub(super) const C3: [f64; 12] = [
    1.0 / 6.0,
    1.0 / 120.0,
    1.0 / 5040.0,
    1.0 / 362880.0,
    1.0 / 39916800.0,
    1.0 / 6227020800.0,
    1.0 / 1307674368000.0,
    1.0 / 355687428096000.0,
    1.0 / 121645100408832000.0,
    1.0 / 51090942171709440000.0,
    1.0 / 25852016738884976640000.0,
    1.0 / 15511210043330985984000000.0,
];

/// `[c₀(z), c₁(z), c₂(z), c₃(z)]`: Stumpff's functions `c₀ … c₃`, which turn the universal-variable form of
/// the two-body problem into one formula for every conic:
///
/// ```text
/// c₀(z) = cos √z,  c₁(z) = sin √z / √z,  c₂(z) = (1 − cos √z)/z,
/// c₃(z) = (√z − sin √z)/z^{3/2}            (z > 0; cosh/sinh for z < 0),
/// ```
///
/// all entire in `z` with `cₖ(0) = 1/k!` and `c_k(z) = 1/k! − z·c_{k+2}(z)`.
///
/// For `|z| < 4` (the whole Wisdom–Holman regime: a change of eccentric
/// anomaly of up to two radians, a third of a turn) `c₂` and `c₃` come from
/// their Taylor series, five to twelve terms as `|z|` grows, which reach
/// the last bit there: no transcendental call, and no cancellation beyond
/// the sum's leading terms (`c₂(4) = 0.354` from `½ − ⅙ + …`); the rounding errors of the first coefficients (1/6, 1/24, 1/120)
/// are added back, so that they do not bias every call the same way. Only `c₀` and `c₁` are then formed from `cₖ = 1/k! − z·c_{k+2}`,
/// where `|z·c_{k+2}|` below ½ (`|z| < 1`) keeps the subtraction benign
/// and up to `1.42` (`c₀(4) = cos 2`) costs at most the absolute rounding
/// of `cos` itself. For `|z| ≥ 4` the closed forms are used, with `1 − cos x = 2 sin²(x/2)` (and
/// `cosh x − 1 = 2 sinh²(x/2)`) so that no difference of nearly equal
/// numbers is formed; `x − sin x` loses at most a factor
/// `1/(1 − sin 2/2) ≈ 1.8` of relative accuracy at `x = 2` and less
/// beyond (the series covers the range where it lost up to 6).
///
/// Non-finite for a `z` so negative that `cosh √−z` overflows (`z < −5·10⁵`).
#[inline]
pub fn stumpff(z: f64) -> [f64; 4] {
    let a = z.abs();
    if a < SERIES_LIMIT {
        // As few terms as reach the last bit: the first one left out is
        // below 1e-18 of the sum (|z|⁵/12! at |z| = 0.01, |z|⁷/16! at 0.1,
        // 1/22! at 1, 4¹²/26! at 4). Short Wisdom–Holman steps (|z| ~
        // 1e-4) take the first branch.
        let m = -z;
        let (c2, c3) = if a < SERIES_SHORT {
            series::<5>(m)
        } else if a < SERIES_MID {
            series::<7>(m)
        } else if a < SERIES_LONG {
            series::<10>(m)
        } else {
            series::<12>(m)
        };
        [1.0 - z * c2, 1.0 - z * c3, c2, c3]
    } else {
        closed_forms(z)
    }
}

/// Stumpff's functions by their closed forms (`z ≠ 0`; see [`stumpff`]).
#[inline]
fn closed_forms(z: f64) -> [f64; 4] {
    if z > 0.0 {
        let x = z.sqrt();
        let (s, c) = x.sin_cos();
        let half = (0.5 * x).sin();
        [c, s / x, 2.0 * half * half / z, (x - s) / (z * x)]
    } else {
        let y = -z;
        let x = y.sqrt();
        let (s, c) = (x.sinh(), x.cosh());
        let half = (0.5 * x).sinh();
        [c, s / x, 2.0 * half * half / y, (s - x) / (y * x)]
    }
}

/// `(c₂, c₃)` from the first `N` terms of their series in `m = −z`.
#[inline(always)]
fn series<const N: usize>(m: f64) -> (f64, f64) {
    let mut c2 = C2[N - 1];
    let mut c3 = C3[N - 1];
    for k in (2..N - 1).rev() {
        c2 = c2 * m + C2[k];
        c3 = c3 * m + C3[k];
    }
    series_head(m, c2, c3)
}

/// The last two Horner steps of [`series`] from the tails
/// `Σ_{k≥2} C[k] m^{k−2}`, with the rounding errors of the first
/// coefficients added back ([`C3_0_LO`]); `C2[0] = ½` is exact.
#[inline(always)]
pub(super) fn series_head(m: f64, t2: f64, t3: f64) -> (f64, f64) {
    let c2 = C2[0] + m * (C2[1] + (C2_1_LO + t2 * m));
    let c3 = C3[0] + (C3_0_LO + m * (C3[1] + (C3_1_LO + t3 * m)));
    (c2, c3)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_branches_meet_at_the_switches() {
        // Just inside and just outside |z| = 1 (ten terms, twelve) and
        // |z| = 4 (twelve terms, the closed forms) the branches agree to a
        // few ulps; c₀ = 1 − z·c₂ is compared in absolute terms, where it
        // passes near cos 2 ≈ −0.42 after a cancellation of 1.4.
        for z in [1.0f64, -1.0, 4.0, -4.0] {
            let inside = stumpff(z * (1.0 - 1e-15));
            let outside = stumpff(z);
            for k in 0..4 {
                let rel = (inside[k] - outside[k]).abs() / outside[k].abs().max(1.0);
                assert!(rel < 3e-15, "c{k}({z}): {} vs {}", inside[k], outside[k]);
            }
        }
    }

    #[test]
    fn the_long_series_agrees_with_the_closed_forms() {
        // 1 ≤ |z| < 4, where the closed forms lose at most a factor 6
        // (x − sin x at x = 1).
        for i in 0..=300 {
            let z = 1.0 + 3.0 * f64::from(i) / 300.0 * (1.0 - 1e-12);
            for z in [z, -z] {
                let (a, b) = (stumpff(z), closed_forms(z));
                for k in 0..4 {
                    let rel = (a[k] - b[k]).abs() / b[k].abs().max(1.0);
                    assert!(rel < 8e-15, "c{k}({z}): {} vs {}", a[k], b[k]);
                }
            }
        }
    }

    #[test]
    fn the_low_parts_are_what_rounding_the_coefficients_left_out() {
        // 1 − k·C is exact in one fused operation (a small, representable
        // difference), so (1 − k·C)/k is the low part to one rounding.
        for (k, hi, lo) in [
            (24.0, C2[1], C2_1_LO),
            (6.0, C3[0], C3_0_LO),
            (120.0, C3[1], C3_1_LO),
        ] {
            let exact = f64::mul_add(-k, hi, 1.0) / k;
            assert!(
                (exact - lo).abs() <= lo.abs() * f64::EPSILON,
                "1/{k}: {exact:e} vs {lo:e}"
            );
        }
    }

    #[test]
    fn the_recurrence_and_the_values_at_zero_hold() {
        assert_eq!(stumpff(0.0), [1.0, 1.0, 0.5, 1.0 / 6.0]);
        for z in [-30.0, -2.0, -0.7, -1e-3, 1e-3, 0.4, 0.99, 3.0, 39.0] {
            let [c0, c1, c2, c3] = stumpff(z);
            assert!(
                (c0 - (1.0 - z * c2)).abs() < 1e-14 * c0.abs().max(1.0),
                "z = {z}"
            );
            assert!(
                (c1 - (1.0 - z * c3)).abs() < 1e-14 * c1.abs().max(1.0),
                "z = {z}"
            );
        }
    }
}
