//! Correct rounding of an exact rational to the nearest `f64` (ties to even).
//!
//! Done in integer arithmetic on the exact numerator and denominator, never by
//! dividing floats, so the constants the macro emits are the doubles nearest
//! to the exact coefficients.

use num_bigint::{BigInt, Sign};
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{ToPrimitive, Zero};

/// The `f64` nearest to `r`, ties to even; overflows to ±∞ and underflows
/// through the subnormals to ±0 exactly as IEEE 754 rounding does.
pub fn rational_to_f64(r: &BigRational) -> f64 {
    if r.is_zero() {
        return 0.0;
    }
    let negative = r.numer().sign() == Sign::Minus;
    let n = r.numer().magnitude().clone();
    let d = r.denom().magnitude().clone();
    // e such that 2^e ≤ n/d < 2^(e+1).
    let mut e = n.bits() as i64 - d.bits() as i64;
    let ge = |e: i64| -> bool {
        // n/d ≥ 2^e ?
        if e >= 0 {
            n >= (&d << e as usize)
        } else {
            (&n << (-e) as usize) >= d
        }
    };
    if !ge(e) {
        e -= 1;
    }
    // Significand has 53 bits: the unit in the last place is 2^(e-52), but no
    // finer than the subnormal step 2^-1074.
    let ulp_exp = (e - 52).max(-1074);
    if e > 1023 {
        return if negative {
            f64::NEG_INFINITY
        } else {
            f64::INFINITY
        };
    }
    // q = floor(n/d / 2^ulp_exp), rem tells the rounding.
    let (num, den) = if ulp_exp >= 0 {
        (BigInt::from(n), BigInt::from(d << ulp_exp as usize))
    } else {
        (BigInt::from(n << (-ulp_exp) as usize), BigInt::from(d))
    };
    let (mut q, rem) = num.div_rem(&den);
    let twice = &rem * 2;
    if twice > den || (twice == den && q.is_odd()) {
        q += 1;
    }
    // q ≤ 2^53; the value is q · 2^ulp_exp, exact in f64 unless it overflows.
    let q = q.to_f64().expect("q has at most 54 bits");
    // Both factors are exact powers of two and q · 2^ulp_exp is representable
    // (or overflows to ∞, as it should), so these products do not round.
    let v = if ulp_exp >= -1022 {
        q * 2f64.powi(ulp_exp as i32)
    } else {
        q * 2f64.powi(-1022) * 2f64.powi((ulp_exp + 1022) as i32)
    };
    if negative { -v } else { v }
}
