//! Double-double ("twofold") arithmetic: an unevaluated sum `hi + lo` of
//! two `f64` with `|lo| ≤ ulp(hi)/2`, about 106 significant bits. Used once
//! per table to compute collocation coefficients far below `f64` round-off
//! before they are rounded ([`super::collocation`]), and by the compensated
//! update of a step (the state carried as `z + e`).

use std::ops::{Add, Div, Mul, Neg, Sub};

/// `a + b = s + err` exactly (Knuth's TwoSum, no condition on `a`, `b`).
#[inline]
pub(crate) fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let err = (a - (s - bb)) + (b - bb);
    (s, err)
}

/// `a + b = s + err` exactly when `|a| ≥ |b|` (or `a = 0`) (Dekker).
#[inline]
pub(crate) fn fast_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let err = b - (s - a);
    (s, err)
}

/// `a·b = p + err` exactly (barring over- and underflow), with a fused
/// multiply–add.
#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// `hi + lo`, normalised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Dd {
    pub hi: f64,
    pub lo: f64,
}

impl Dd {
    pub const ZERO: Dd = Dd { hi: 0.0, lo: 0.0 };
    pub const ONE: Dd = Dd { hi: 1.0, lo: 0.0 };

    pub fn from_f64(x: f64) -> Dd {
        Dd { hi: x, lo: 0.0 }
    }

    /// The `f64` nearest to `hi + lo` (`hi`, for a normalised value; a tie
    /// `|lo| = ulp(hi)/2` is broken by the sign of `lo`, which only a value
    /// exactly halfway can make wrong).
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }
}

impl Neg for Dd {
    type Output = Dd;
    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Add for Dd {
    type Output = Dd;
    fn add(self, o: Dd) -> Dd {
        let (s, e) = two_sum(self.hi, o.hi);
        let (t, f) = two_sum(self.lo, o.lo);
        let (s, e) = fast_two_sum(s, e + t);
        let (hi, lo) = fast_two_sum(s, e + f);
        Dd { hi, lo }
    }
}

impl Sub for Dd {
    type Output = Dd;
    fn sub(self, o: Dd) -> Dd {
        self + (-o)
    }
}

impl Mul for Dd {
    type Output = Dd;
    fn mul(self, o: Dd) -> Dd {
        let (p, e) = two_prod(self.hi, o.hi);
        let e = e + (self.hi * o.lo + self.lo * o.hi);
        let (hi, lo) = fast_two_sum(p, e);
        Dd { hi, lo }
    }
}

impl Mul<f64> for Dd {
    type Output = Dd;
    fn mul(self, o: f64) -> Dd {
        self * Dd::from_f64(o)
    }
}

impl Div for Dd {
    type Output = Dd;
    /// Long division: three quotient digits.
    fn div(self, o: Dd) -> Dd {
        let q1 = self.hi / o.hi;
        let r = self - o * q1;
        let q2 = r.hi / o.hi;
        let r = r - o * q2;
        let q3 = r.hi / o.hi;
        let (hi, lo) = fast_two_sum(q1, q2);
        Dd { hi, lo } + Dd::from_f64(q3)
    }
}

impl Div<f64> for Dd {
    type Output = Dd;
    fn div(self, o: f64) -> Dd {
        self / Dd::from_f64(o)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thirds_and_square_roots() {
        // 1/3 to twice the precision: 3·(1/3) − 1 is ~1e-32.
        let third = Dd::ONE / Dd::from_f64(3.0);
        let back = third * 3.0 - Dd::ONE;
        assert!(back.to_f64().abs() < 1e-31, "{back:?}");
        // (1 + 2⁻⁶⁰)² keeps the 2⁻⁵⁹ term that f64 loses.
        let x = Dd {
            hi: 1.0,
            lo: 2f64.powi(-60),
        };
        let sq = x * x;
        assert_eq!(sq.hi, 1.0);
        assert_eq!(sq.lo, 2f64.powi(-59));
        // Sums exact where f64 sums are not.
        let (s, e) = two_sum(1.0, 1e-17);
        assert_eq!((s, e), (1.0, 1e-17));
        let d = (Dd::from_f64(0.1) + Dd::from_f64(0.2)) - Dd::from_f64(0.3);
        // 0.1 + 0.2 − 0.3 of the doubles is 2⁻⁵⁴·(…): exact, tiny, nonzero.
        assert!(d.to_f64() != 0.0 && d.to_f64().abs() < 1e-16);
    }
}
