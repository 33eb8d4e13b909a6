//! Fraction-free arithmetic for the order analyses.
//!
//! Every elementary weight of order `n` is a sum of products of exactly `n`
//! table entries (and every word coefficient of weight `n` a sum of products
//! of powers of the `γ`s of total degree `n`). Scaling every entry by a common
//! denominator `D` therefore makes all intermediate values integers (or
//! integer combinations of radical monomials), the value of order `n` being
//! the integer divided by `Dⁿ`. This avoids the gcd of every rational
//! operation, which dominates for tables published with long decimals. The
//! arithmetic stays exact; values are turned back into [`Number`]s only for
//! reports.

use std::cell::RefCell;
use std::collections::HashMap;

use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{One, Zero};

use crate::Number;
use crate::number::Radical;

/// The monomials `∏ p^(e/6)` as [`Number`]s, built once each.
#[derive(Default)]
pub(crate) struct Monomials(RefCell<HashMap<Radical, Number>>);

impl Monomials {
    fn get(&self, m: &Radical) -> Number {
        if let Some(x) = self.0.borrow().get(m) {
            return x.clone();
        }
        let x = monomial(m);
        self.0.borrow_mut().insert(m.clone(), x.clone());
        x
    }
}

/// `∏ p^(e/6)` through the public roots: `p^(1/6) = √p / ∛p`,
/// `p^(2/6) = ∛p`, `p^(3/6) = √p`, `p^(4/6) = (∛p)²`, `p^(5/6) = √p·∛p`.
fn monomial(m: &Radical) -> Number {
    let mut out = Number::one();
    for &(p, e) in m.factors() {
        let p = Number::from_bigint(BigInt::from(p));
        let sq = || p.sqrt().expect("a prime is positive");
        let cb = || p.cbrt().expect("a rational has a cube root");
        let factor = match e {
            1 => sq().checked_div(&cb()).expect("∛p ≠ 0"),
            2 => cb(),
            3 => sq(),
            4 => &cb() * &cb(),
            5 => &sq() * &cb(),
            _ => unreachable!("radical exponents are in 1..6"),
        };
        out = &out * &factor;
    }
    out
}

/// The ring the analyses compute in.
pub(crate) trait Scalar: Clone {
    fn zero() -> Self;
    fn one() -> Self;
    fn is_zero(&self) -> bool;
    fn mul(&self, other: &Self) -> Self;
    fn add_assign(&mut self, other: &Self);
    fn scale(&self, k: &BigInt) -> Self;
    /// Whether the value is the integer `k`.
    fn is_integer(&self, k: &BigInt) -> bool;
    /// `x · den`, which must be integral: `den` is a multiple of the
    /// denominators of `x`'s coefficients.
    fn from_number(x: &Number, den: &BigInt) -> Self;
    /// `self / den` as a [`Number`].
    fn to_number(&self, den: &BigInt, monomials: &Monomials) -> Number;

    /// `self += a·b`, skipping zeros.
    fn add_product(&mut self, a: &Self, b: &Self) {
        if !a.is_zero() && !b.is_zero() {
            self.add_assign(&a.mul(b));
        }
    }
}

/// The least common multiple of the denominators of the coefficients of
/// `numbers`.
pub(crate) fn common_denominator<'a>(numbers: impl IntoIterator<Item = &'a Number>) -> BigInt {
    let mut den: BigInt = One::one();
    for x in numbers {
        for (_, c) in x.terms() {
            den = den.lcm(c.denom());
        }
    }
    den
}

fn scaled_integer(c: &BigRational, den: &BigInt) -> BigInt {
    let (q, r) = den.div_rem(c.denom());
    debug_assert!(Zero::is_zero(&r), "den is a common denominator");
    c.numer() * q
}

impl Scalar for BigInt {
    fn zero() -> Self {
        Zero::zero()
    }

    fn one() -> Self {
        One::one()
    }

    fn is_zero(&self) -> bool {
        Zero::is_zero(self)
    }

    fn mul(&self, other: &Self) -> Self {
        self * other
    }

    fn add_assign(&mut self, other: &Self) {
        *self += other;
    }

    fn scale(&self, k: &BigInt) -> Self {
        self * k
    }

    fn is_integer(&self, k: &BigInt) -> bool {
        self == k
    }

    fn from_number(x: &Number, den: &BigInt) -> Self {
        let r = x
            .as_rational()
            .expect("the rational engine gets rational entries");
        scaled_integer(&r, den)
    }

    fn to_number(&self, den: &BigInt, _: &Monomials) -> Number {
        Number::from_rational(BigRational::new(self.clone(), den.clone()))
    }
}

/// `Σ cₖ mₖ` with integer coefficients and radical monomials, sorted by
/// monomial, no zero coefficients.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct RadicalPoly(Vec<(Radical, BigInt)>);

impl RadicalPoly {
    fn add_term(&mut self, m: &Radical, c: BigInt) {
        if Zero::is_zero(&c) {
            return;
        }
        match self.0.binary_search_by(|(r, _)| r.cmp(m)) {
            Ok(i) => {
                self.0[i].1 += c;
                if Zero::is_zero(&self.0[i].1) {
                    self.0.remove(i);
                }
            }
            Err(i) => self.0.insert(i, (m.clone(), c)),
        }
    }
}

impl Scalar for RadicalPoly {
    fn zero() -> Self {
        RadicalPoly(Vec::new())
    }

    fn one() -> Self {
        RadicalPoly(vec![(Radical::one(), One::one())])
    }

    fn is_zero(&self) -> bool {
        self.0.is_empty()
    }

    fn mul(&self, other: &Self) -> Self {
        let mut out = RadicalPoly(Vec::with_capacity(self.0.len() * other.0.len()));
        for (ma, ca) in &self.0 {
            for (mb, cb) in &other.0 {
                if ma.is_one() {
                    out.add_term(mb, ca * cb);
                } else if mb.is_one() {
                    out.add_term(ma, ca * cb);
                } else {
                    let (factor, m) = ma.mul(mb);
                    out.add_term(&m, ca * cb * factor);
                }
            }
        }
        out
    }

    fn add_assign(&mut self, other: &Self) {
        for (m, c) in &other.0 {
            self.add_term(m, c.clone());
        }
    }

    fn scale(&self, k: &BigInt) -> Self {
        if Zero::is_zero(k) {
            return Self::zero();
        }
        RadicalPoly(self.0.iter().map(|(m, c)| (m.clone(), c * k)).collect())
    }

    fn is_integer(&self, k: &BigInt) -> bool {
        match self.0.as_slice() {
            [] => Zero::is_zero(k),
            [(m, c)] => m.is_one() && c == k,
            _ => false,
        }
    }

    fn from_number(x: &Number, den: &BigInt) -> Self {
        let mut out = Self::zero();
        for (m, c) in x.terms() {
            out.add_term(m, scaled_integer(c, den));
        }
        out
    }

    fn to_number(&self, den: &BigInt, monomials: &Monomials) -> Number {
        let mut out = Number::zero();
        for (m, c) in &self.0 {
            let coeff = Number::from_rational(BigRational::new(c.clone(), den.clone()));
            out += &if m.is_one() {
                coeff
            } else {
                &coeff * &monomials.get(m)
            };
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn monomials_round_trip() {
        let x = Number::from(15).sqrt().unwrap() + Number::from(2).cbrt().unwrap();
        let y = (&x * &x) * &x;
        let z = y.recip().unwrap();
        let monos = Monomials::default();
        for v in [x, y, z, Number::ratio(-3, 7).unwrap(), Number::zero()] {
            let den = common_denominator([&v]);
            let p = RadicalPoly::from_number(&v, &den);
            assert_eq!(p.to_number(&den, &monos), v);
            let sq = p.mul(&p);
            assert_eq!(sq.to_number(&(&den * &den), &monos), &v * &v);
        }
        for e in 1..6u8 {
            let m = Radical(vec![(7, e)]);
            let n = monomial(&m);
            let terms: Vec<_> = n.terms().collect();
            assert_eq!(terms.len(), 1);
            assert_eq!(terms[0].0, &m);
            assert!(num_traits::One::is_one(terms[0].1));
        }
    }
}
