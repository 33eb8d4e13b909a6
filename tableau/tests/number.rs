//! The exact number field: identities, field axioms, exact zero tests and
//! correct rounding to f64.

use std::cmp::Ordering;

use num_bigint::BigInt;
use num_rational::BigRational;
use proptest::prelude::*;
use tableau::number::rational_to_f64;
use tableau::{Number, NumberError};

fn int(n: i64) -> Number {
    Number::from(n)
}
fn sqrt(n: i64) -> Number {
    int(n).sqrt().unwrap()
}
fn cbrt(n: i64) -> Number {
    int(n).cbrt().unwrap()
}
fn q(n: i64, d: i64) -> Number {
    Number::ratio(n, d).unwrap()
}

#[test]
fn radical_identities_are_exact() {
    assert!((sqrt(8) - int(2) * sqrt(2)).is_zero());
    assert!((sqrt(6) - sqrt(2) * sqrt(3)).is_zero());
    assert!((cbrt(16) - int(2) * cbrt(2)).is_zero());
    assert_eq!((int(1) + sqrt(2)).recip().unwrap(), sqrt(2) - int(1));
    assert_eq!(sqrt(2) * sqrt(2), int(2));
    assert_eq!(cbrt(2) * cbrt(2) * cbrt(2), int(2));
    // sqrt and cbrt of the same prime meet in sixth roots: 2^(1/2)·2^(1/3) = 2^(5/6).
    assert_eq!((sqrt(2) * cbrt(2)).powi(6).unwrap(), int(32));
    // Rational radicands: sqrt(1/2) = sqrt(2)/2, cbrt(-27/8) = -3/2.
    assert_eq!(q(1, 2).sqrt().unwrap(), sqrt(2) * q(1, 2));
    assert_eq!(q(-27, 8).cbrt().unwrap(), q(-3, 2));
    assert_eq!(sqrt(0), int(0));
    // Perfect powers collapse to rationals.
    assert!(sqrt(144).is_rational());
    assert_eq!(cbrt(1000), int(10));
    // sqrt(15) is not a rational combination of sqrt(3) and sqrt(5).
    assert!((sqrt(15) - sqrt(3) * sqrt(5)).is_zero());
    assert!(!(sqrt(15) - sqrt(3) - sqrt(5)).is_zero());
}

#[test]
fn gauss_legendre_coefficients_are_consistent() {
    // The Gauss–Legendre s = 2 nodes are roots of the shifted Legendre
    // polynomial x² − x + 1/6.
    let c1 = q(1, 2) - sqrt(3) * q(1, 6);
    let p = &c1 * &c1 - &c1 + q(1, 6);
    assert!(p.is_zero());
}

#[test]
fn inverse_in_multi_radical_fields() {
    let xs = [
        int(1) + sqrt(2) + sqrt(3),
        sqrt(2) + sqrt(3) + sqrt(5) + sqrt(7),
        int(1) + cbrt(2) + cbrt(4),
        int(2) - cbrt(2),
        sqrt(2) + cbrt(3),
        q(1, 4) - sqrt(3) * q(1, 6),
    ];
    for x in &xs {
        let inv = x.recip().unwrap();
        assert_eq!(x * &inv, int(1), "x = {x}, 1/x = {inv}");
    }
}

#[test]
fn errors_not_panics() {
    assert_eq!(int(0).recip(), Err(NumberError::DivisionByZero));
    assert_eq!(
        int(1).checked_div(&(sqrt(2) - sqrt(2))),
        Err(NumberError::DivisionByZero)
    );
    assert!(matches!(int(-2).sqrt(), Err(NumberError::NegativeSqrt(_))));
    assert!(matches!(
        (int(1) + sqrt(2)).sqrt(),
        Err(NumberError::NestedRadical { .. })
    ));
    assert!(matches!(int(0).powi(-1), Err(NumberError::DivisionByZero)));
    // The product of two primes above 2^40 cannot be factored by trial
    // division: refused, not guessed.
    let big = Number::from_bigint(
        BigInt::from(1_099_511_628_211u64) * BigInt::from(1_099_511_628_401u64),
    );
    assert!(matches!(big.sqrt(), Err(NumberError::TooLargeToFactor(_))));
    // A large but smooth radicand is fine.
    let smooth = Number::from_bigint(BigInt::from(2).pow(200) * BigInt::from(3));
    assert_eq!(
        smooth.sqrt().unwrap(),
        Number::from_bigint(BigInt::from(2).pow(100)) * sqrt(3)
    );
}

#[test]
fn exact_sign_of_nearly_cancelling_numbers() {
    // 1 + sqrt(2)... (sqrt(2) - 1)^20 is tiny but positive; 99/70 − sqrt(2) > 0
    // by 7e-5 and 577/408 − sqrt(2) > 0 by 2e-6.
    let tiny = (sqrt(2) - int(1)).powi(40).unwrap();
    assert_eq!(tiny.signum(), Ordering::Greater);
    assert_eq!((q(577, 408) - sqrt(2)).signum(), Ordering::Greater);
    assert_eq!((sqrt(2) - q(577, 408)).signum(), Ordering::Less);
    assert!(sqrt(2) < sqrt(3));
    assert!(cbrt(3) < sqrt(3));
}

#[test]
fn correct_rounding_of_radicals() {
    assert_eq!(sqrt(2).to_f64(), std::f64::consts::SQRT_2);
    assert_eq!(sqrt(3).to_f64(), 3f64.sqrt()); // IEEE sqrt is correctly rounded
    assert_eq!(q(1, 3).to_f64(), 1.0 / 3.0);
    assert_eq!(q(1, 10).to_f64(), 0.1);
    // Forest–Ruth's x = 1/(2 − cbrt(2)) = 1.35120719195965763404…; the nearest
    // doubles are …6575 (0.84e-16 below) and …6578 (1.38e-16 above).
    let x = (int(2) - cbrt(2)).recip().unwrap();
    assert_eq!(x.to_f64(), 1.351_207_191_959_657_5);
    // A tiny positive number rounds to a tiny positive double, not to 0.
    let tiny = (sqrt(2) - int(1)).powi(40).unwrap();
    let t = tiny.to_f64();
    assert!(t > 0.0 && (t - (2f64.sqrt() - 1.0).powi(40)).abs() < 1e-10 * t);
}

#[test]
fn rational_rounding_edge_cases() {
    let r = |n: BigInt, d: BigInt| BigRational::new(n, d);
    let two = BigInt::from(2);
    // Exact powers of two across the whole range, subnormals included.
    for e in -1074..=1023i32 {
        let v = if e >= 0 {
            r(two.pow(e as u32), 1.into())
        } else {
            r(1.into(), two.pow((-e) as u32))
        };
        let expected = if e >= -1022 {
            2f64.powi(e)
        } else {
            f64::from_bits(1u64 << (e + 1074))
        };
        assert_eq!(rational_to_f64(&v), expected, "2^{e}");
    }
    // Halfway between the two smallest subnormals' neighbours: 2^-1075 ties to 0,
    // 3·2^-1075 ties to even (2·2^-1074).
    assert_eq!(rational_to_f64(&r(1.into(), two.pow(1075))), 0.0);
    assert_eq!(rational_to_f64(&r(3.into(), two.pow(1075))), 2.0 * 5e-324);
    // Overflow to infinity, and the largest finite double.
    assert_eq!(rational_to_f64(&r(two.pow(1024), 1.into())), f64::INFINITY);
    let max = r((two.pow(53) - 1) * two.pow(971), 1.into());
    assert_eq!(rational_to_f64(&max), f64::MAX);
    // 1 + 2^-53 is a tie between 1 and 1 + 2^-52: ties to even gives 1.
    let tie = r(two.pow(53) + 1, two.pow(53));
    assert_eq!(rational_to_f64(&tie), 1.0);
    let above = r(two.pow(54) + 3, two.pow(54));
    assert_eq!(rational_to_f64(&above), 1.0 + f64::EPSILON);
    assert_eq!(rational_to_f64(&r((-7).into(), 3.into())), -7.0 / 3.0);
}

proptest! {
    /// IEEE division of two integers below 2^53 is correctly rounded, so it is
    /// an independent oracle for the integer-arithmetic rounding.
    #[test]
    fn rounding_matches_ieee_division(n in -(1i64 << 53)..(1i64 << 53), d in 1i64..(1i64 << 53)) {
        let v = BigRational::new(n.into(), d.into());
        prop_assert_eq!(rational_to_f64(&v), n as f64 / d as f64);
    }
}

/// A random element of Q(sqrt(2), sqrt(3), cbrt(2), sqrt(5)): a small
/// combination of products of radicals with rational coefficients.
fn arb_number() -> impl Strategy<Value = Number> {
    let term = (-20i64..=20, 1i64..=12, 0usize..6, 0usize..3).prop_map(|(n, d, r1, r2)| {
        let rads = [int(1), sqrt(2), sqrt(3), cbrt(2), sqrt(5), cbrt(4)];
        let rads2 = [int(1), sqrt(3), cbrt(3)];
        q(n, d) * rads[r1].clone() * rads2[r2].clone()
    });
    prop::collection::vec(term, 1..4)
        .prop_map(|ts| ts.into_iter().fold(Number::zero(), |a, t| a + t))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn field_axioms(x in arb_number(), y in arb_number(), z in arb_number()) {
        prop_assert_eq!(&(&x + &y) + &z, &x + &(&y + &z));
        prop_assert_eq!(&(&x * &y) * &z, &x * &(&y * &z));
        prop_assert_eq!(&x * &(&y + &z), &(&x * &y) + &(&x * &z));
        prop_assert_eq!(&x * &y, &y * &x);
        prop_assert!((&x - &x).is_zero());
        if !x.is_zero() {
            let inv = x.recip().unwrap();
            prop_assert!((&x * &inv).is_one(), "x = {}, 1/x = {}", x, inv);
            prop_assert_eq!((&y * &x).checked_div(&x).unwrap(), y.clone());
        } else {
            prop_assert_eq!(x.recip(), Err(NumberError::DivisionByZero));
        }
    }

    #[test]
    fn order_and_rounding_agree_with_floats(x in arb_number(), y in arb_number()) {
        let (fx, fy) = (x.to_f64(), y.to_f64());
        // Correct rounding is monotone.
        match x.cmp_exact(&y) {
            Ordering::Less => prop_assert!(fx <= fy),
            Ordering::Greater => prop_assert!(fx >= fy),
            Ordering::Equal => prop_assert_eq!(fx, fy),
        }
        // And close to a float evaluation of the terms.
        let approx: f64 = x.terms().map(|(m, c)| rational_to_f64(c) * m.approx()).sum();
        prop_assert!((fx - approx).abs() <= 1e-12 * (1.0 + approx.abs()));
    }

    #[test]
    fn powers(x in arb_number(), a in 0i64..4, b in 0i64..4) {
        prop_assert_eq!(x.powi(a).unwrap() * x.powi(b).unwrap(), x.powi(a + b).unwrap());
        if !x.is_zero() {
            prop_assert!((x.powi(-a).unwrap() * x.powi(a).unwrap()).is_one());
        }
    }
}
