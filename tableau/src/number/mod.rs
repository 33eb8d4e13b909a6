//! Exact real numbers: rationals extended by real radicals of rationals.
//!
//! A [`Number`] is a finite sum `Σ cₖ · mₖ` of rational coefficients `cₖ`
//! ([`BigRational`]) times [`Radical`] monomials `∏ pᵢ^(eᵢ/6)`. Because these
//! monomials are linearly independent over Q (see [`radical`]), the
//! representation is canonical: two numbers are equal exactly when their term
//! maps are equal, and a number is zero exactly when it has no terms. The set
//! is closed under `+ − × ÷`, integer powers, and `sqrt`/`cbrt` of rationals.
//!
//! ```
//! use tableau::Number;
//! let two = Number::from(2);
//! let sqrt2 = two.sqrt().unwrap();
//! let lhs = Number::from(8).sqrt().unwrap() - &(&two * &sqrt2);
//! assert!(lhs.is_zero());
//! let inv = (Number::from(1) + &sqrt2).recip().unwrap();
//! assert_eq!(inv, &sqrt2 - &Number::from(1));
//! ```

mod inverse;
pub mod order;
pub mod radical;
mod round;

use std::cmp::Ordering;
use std::collections::BTreeMap;
use std::fmt;
use std::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

pub use inverse::{MAX_INVERSE_DEGREE, field_degree};
pub use radical::Radical;
pub use round::rational_to_f64;

/// What can go wrong in exact arithmetic. Every variant is a property of the
/// input, never an internal failure.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum NumberError {
    #[error("division by zero")]
    DivisionByZero,
    #[error("square root of a negative number ({0})")]
    NegativeSqrt(String),
    #[error(
        "{func} of an irrational number ({arg}) is a nested radical, which the exact arithmetic does not support"
    )]
    NestedRadical { func: &'static str, arg: String },
    #[error("radicand {0} is too large to factor exactly; refusing rather than guessing")]
    TooLargeToFactor(String),
    #[error("exponent {0} is too large")]
    ExponentTooLarge(i64),
    /// A divisor whose radicals span a field beyond the exact arithmetic's
    /// budget ([`MAX_INVERSE_DEGREE`]).
    #[error(
        "dividing by {divisor}: its radicals span a field of degree {degree} over Q, and exact division is limited to degree {MAX_INVERSE_DEGREE} (e.g. 8 square roots or 5 cube roots of distinct primes); refusing rather than running without bound"
    )]
    FieldTooLarge { divisor: String, degree: u64 },
}

/// The bits of the least common denominator of the numbers' coefficients
/// (stopping once it passes 2¹⁶ bits).
pub fn common_denominator_bits<'a>(xs: impl IntoIterator<Item = &'a Number>) -> u64 {
    use num_integer::Integer;
    let mut d = BigInt::one();
    for x in xs {
        for c in x.terms.values() {
            if !c.denom().is_one() {
                d = d.lcm(c.denom());
                if d.bits() > 1 << 16 {
                    return d.bits();
                }
            }
        }
    }
    d.bits()
}

/// An exact real number in Q(p^(1/6) : p prime). See the [module docs](self).
#[derive(Clone, PartialEq, Eq, Hash, Default)]
pub struct Number {
    /// Nonzero coefficients only; the empty map is zero.
    terms: BTreeMap<Radical, BigRational>,
}

impl Number {
    pub fn zero() -> Self {
        Number::default()
    }

    pub fn one() -> Self {
        Number::from(1)
    }

    /// The rational `num/den`; `den = 0` is an error.
    pub fn ratio(num: i64, den: i64) -> Result<Self, NumberError> {
        if den == 0 {
            return Err(NumberError::DivisionByZero);
        }
        Ok(Number::from_rational(BigRational::new(
            num.into(),
            den.into(),
        )))
    }

    pub fn from_rational(r: BigRational) -> Self {
        let mut terms = BTreeMap::new();
        if !r.is_zero() {
            terms.insert(Radical::one(), r);
        }
        Number { terms }
    }

    pub fn from_bigint(n: BigInt) -> Self {
        Number::from_rational(BigRational::from_integer(n))
    }

    /// `coeff · radical`, for building numbers term by term.
    fn from_term(coeff: BigRational, radical: Radical) -> Self {
        let mut terms = BTreeMap::new();
        if !coeff.is_zero() {
            terms.insert(radical, coeff);
        }
        Number { terms }
    }

    pub fn is_zero(&self) -> bool {
        self.terms.is_empty()
    }

    pub fn is_one(&self) -> bool {
        self.as_rational().is_some_and(|r| r.is_one())
    }

    /// The rational value, if the number has no radical part.
    pub fn as_rational(&self) -> Option<BigRational> {
        match self.terms.len() {
            0 => Some(BigRational::zero()),
            1 => self.terms.get(&Radical::one()).cloned(),
            _ => None,
        }
    }

    pub fn is_rational(&self) -> bool {
        self.as_rational().is_some()
    }

    /// The terms `(monomial, coefficient)` in canonical order.
    pub fn terms(&self) -> impl Iterator<Item = (&Radical, &BigRational)> {
        self.terms.iter()
    }

    fn add_term(&mut self, radical: &Radical, coeff: &BigRational) {
        if coeff.is_zero() {
            return;
        }
        match self.terms.get_mut(radical) {
            Some(c) => {
                *c += coeff;
                if c.is_zero() {
                    self.terms.remove(radical);
                }
            }
            None => {
                self.terms.insert(radical.clone(), coeff.clone());
            }
        }
    }

    /// The coefficients as integers over one common denominator `d > 0`:
    /// `self = Σ nₖ mₖ / d`.
    fn integer_coefficients(&self) -> (Vec<(&Radical, BigInt)>, BigInt) {
        use num_integer::Integer;
        let mut d = BigInt::one();
        for c in self.terms.values() {
            if !c.denom().is_one() {
                d = d.lcm(c.denom());
            }
        }
        let n = self
            .terms
            .iter()
            .map(|(m, c)| {
                let n = if c.denom() == &d {
                    c.numer().clone()
                } else {
                    c.numer() * (&d / c.denom())
                };
                (m, n)
            })
            .collect();
        (n, d)
    }

    /// Multiply every coefficient by a rational.
    pub fn scale(&self, r: &BigRational) -> Number {
        if r.is_zero() {
            return Number::zero();
        }
        Number {
            terms: self.terms.iter().map(|(m, c)| (m.clone(), c * r)).collect(),
        }
    }

    /// `1/self`; an exact zero is an error.
    pub fn recip(&self) -> Result<Number, NumberError> {
        if self.is_zero() {
            return Err(NumberError::DivisionByZero);
        }
        if self.terms.len() == 1 {
            let (m, c) = self.terms.iter().next().unwrap();
            let (divisor, inv) = m.recip();
            let coeff = c.recip() / BigRational::from_integer(divisor);
            return Ok(Number::from_term(coeff, inv));
        }
        let degree = field_degree([self]);
        if degree > MAX_INVERSE_DEGREE {
            return Err(NumberError::FieldTooLarge {
                divisor: self.short_text(),
                degree,
            });
        }
        Ok(inverse::inverse(self))
    }

    /// The number as text, cut to about 80 characters for messages.
    pub fn short_text(&self) -> String {
        let mut t = String::new();
        for (k, (m, c)) in self.terms.iter().enumerate() {
            if t.len() > 80 {
                t.push_str(&format!(" + … ({} terms)", self.terms.len()));
                return t;
            }
            if k > 0 {
                t.push_str(" + ");
            }
            let bits = c.numer().bits() + c.denom().bits();
            if bits > 256 {
                let (text, _) = m.to_grammar();
                let text = if text.is_empty() {
                    String::new()
                } else {
                    format!("·{text}")
                };
                t.push_str(&format!("(a {bits}-bit rational){text}"));
            } else {
                t.push_str(&Number::from_term(c.clone(), m.clone()).to_string());
            }
        }
        t
    }

    /// A size measure: the bits of all numerators, denominators and
    /// radicands.
    pub fn size_bits(&self) -> u64 {
        self.terms
            .iter()
            .map(|(m, c)| c.numer().bits() + c.denom().bits() + m.radicand().bits())
            .fold(0u64, u64::saturating_add)
    }

    /// The number of terms `cₖ · mₖ`.
    pub fn term_count(&self) -> usize {
        self.terms.len()
    }

    /// `self / rhs`; division by an exact zero is an error.
    pub fn checked_div(&self, rhs: &Number) -> Result<Number, NumberError> {
        Ok(self * &rhs.recip()?)
    }

    /// `self^n` for any integer `n` (negative powers of zero are an error).
    pub fn powi(&self, n: i64) -> Result<Number, NumberError> {
        if n.unsigned_abs() > 1 << 16 {
            return Err(NumberError::ExponentTooLarge(n));
        }
        let base = if n < 0 { self.recip()? } else { self.clone() };
        let mut e = n.unsigned_abs();
        let mut acc = Number::one();
        let mut sq = base;
        while e > 0 {
            if e & 1 == 1 {
                acc = &acc * &sq;
            }
            e >>= 1;
            if e > 0 {
                sq = &sq * &sq;
            }
        }
        Ok(acc)
    }

    /// The non-negative square root of a non-negative rational.
    pub fn sqrt(&self) -> Result<Number, NumberError> {
        let r = self
            .as_rational()
            .ok_or_else(|| NumberError::NestedRadical {
                func: "sqrt",
                arg: self.to_string(),
            })?;
        if r.is_negative() {
            return Err(NumberError::NegativeSqrt(self.to_string()));
        }
        Self::rational_root(&r, 3)
    }

    /// The real cube root of a rational (negative for a negative argument).
    pub fn cbrt(&self) -> Result<Number, NumberError> {
        let r = self
            .as_rational()
            .ok_or_else(|| NumberError::NestedRadical {
                func: "cbrt",
                arg: self.to_string(),
            })?;
        let root = Self::rational_root(&r.abs(), 2)?;
        Ok(if r.is_negative() { -root } else { root })
    }

    /// `r^(e/6)` for `r ≥ 0` and `e ∈ {2, 3}` (cube and square roots), via
    /// `(n/d)^(e/6) = (n · d^(k−1))^(e/6) / d` with `k = 6/e`, so that only an
    /// integer radicand is factored.
    fn rational_root(r: &BigRational, e: u32) -> Result<Number, NumberError> {
        if r.is_zero() {
            return Ok(Number::zero());
        }
        let k = 6 / e;
        let d = r.denom().clone();
        let n = r.numer() * d.pow(k - 1);
        let factors =
            radical::factorize(&n).ok_or_else(|| NumberError::TooLargeToFactor(n.to_string()))?;
        let mut coeff = BigRational::new(BigInt::one(), d);
        let mut rad = Radical::one();
        for (p, mult) in factors {
            let (whole, part) = Radical::prime_power(p, mult * e);
            coeff *= BigRational::from_integer(whole);
            let (extra, prod) = rad.mul(&part);
            coeff *= BigRational::from_integer(extra);
            rad = prod;
        }
        Ok(Number::from_term(coeff, rad))
    }

    /// Exact sign: refines rational enclosures until they exclude zero, which
    /// always happens for a nonzero number.
    pub fn signum(&self) -> Ordering {
        if let Some(r) = self.as_rational() {
            return r.cmp(&BigRational::zero());
        }
        let mut bits = 64;
        loop {
            let (lo, hi) = self.enclosure(bits);
            if lo.is_positive() {
                return Ordering::Greater;
            }
            if hi.is_negative() {
                return Ordering::Less;
            }
            bits *= 2;
        }
    }

    /// `|self|`.
    pub fn abs(&self) -> Number {
        if self.signum() == Ordering::Less {
            -self.clone()
        } else {
            self.clone()
        }
    }

    /// Rational bounds `lo ≤ self ≤ hi` with `hi − lo ≤ (number of terms) ·
    /// max|coeff| · 2^-bits`.
    pub fn enclosure(&self, bits: u64) -> (BigRational, BigRational) {
        let scale = BigRational::from_integer(BigInt::one() << bits);
        let mut lo = BigRational::zero();
        let mut hi = BigRational::zero();
        for (m, c) in &self.terms {
            let (floor, exact) = m.scaled_floor(bits);
            let m_lo = BigRational::from_integer(floor.clone()) / &scale;
            let m_hi = if exact {
                m_lo.clone()
            } else {
                BigRational::from_integer(floor + 1) / &scale
            };
            if c.is_positive() {
                lo += c * &m_lo;
                hi += c * &m_hi;
            } else {
                lo += c * &m_hi;
                hi += c * &m_lo;
            }
        }
        (lo, hi)
    }

    /// The nearest `f64` (ties to even), decided exactly: an irrational number
    /// is never on a rounding boundary, so enclosures are refined until both
    /// ends round to the same double.
    pub fn to_f64(&self) -> f64 {
        if let Some(r) = self.as_rational() {
            return rational_to_f64(&r);
        }
        let mut bits = 80;
        loop {
            let (lo, hi) = self.enclosure(bits);
            let (a, b) = (rational_to_f64(&lo), rational_to_f64(&hi));
            if a == b {
                return a;
            }
            bits *= 2;
        }
    }

    /// A short decimal approximation, `1.235e-7`, with four significant
    /// digits and the exact decimal exponent even where the number is far
    /// outside `f64`'s range (`10^5000` reads `1.000e5000`, never `inf`).
    pub fn approx_text(&self) -> String {
        let x = self.to_f64();
        if x == 0.0 && self.is_zero() {
            return "0".into();
        }
        if x.is_finite() && x.abs() >= f64::MIN_POSITIVE {
            return format!("{x:.3e}");
        }
        // A rational close enough for four digits (the number is not zero:
        // an irrational's enclosures tighten around it), then scaled by an
        // exact power of ten into f64's range.
        let r = match self.as_rational() {
            Some(r) => r,
            None => {
                let mut bits = 64;
                loop {
                    let (lo, hi) = self.enclosure(bits);
                    let width = &hi - &lo;
                    if width * BigRational::from_integer(BigInt::from(1u32 << 16)) < lo.abs() {
                        break lo;
                    }
                    bits *= 2;
                }
            }
        };
        let bits = r.numer().bits() as i64 - r.denom().bits() as i64;
        let e10 = (bits as f64 * std::f64::consts::LOG10_2).floor() as i64;
        let ten = BigInt::from(10u32);
        let scale = BigRational::from_integer(num_traits::pow(ten, e10.unsigned_abs() as usize));
        let scaled = if e10 >= 0 { &r / &scale } else { &r * &scale };
        let m = round::rational_to_f64(&scaled);
        // m is within a factor of ten of 1: renormalise its printed form.
        let text = format!("{m:.3e}");
        let (mant, exp) = text.split_once('e').expect("{:e} has an exponent");
        let exp: i64 = exp.parse().expect("{:e}'s exponent is an integer");
        format!("{mant}e{}", exp + e10)
    }

    /// Compare two numbers exactly.
    pub fn cmp_exact(&self, other: &Number) -> Ordering {
        (self - other).signum()
    }
}

impl From<i64> for Number {
    fn from(n: i64) -> Self {
        Number::from_bigint(BigInt::from(n))
    }
}

impl From<i32> for Number {
    fn from(n: i32) -> Self {
        Number::from(n as i64)
    }
}

impl From<BigRational> for Number {
    fn from(r: BigRational) -> Self {
        Number::from_rational(r)
    }
}

impl<'a> Add<&'a Number> for &'a Number {
    type Output = Number;
    fn add(self, rhs: &Number) -> Number {
        let mut out = self.clone();
        out += rhs;
        out
    }
}

impl<'a> Sub<&'a Number> for &'a Number {
    type Output = Number;
    fn sub(self, rhs: &Number) -> Number {
        let mut out = self.clone();
        out -= rhs;
        out
    }
}

impl<'a> Mul<&'a Number> for &'a Number {
    type Output = Number;
    fn mul(self, rhs: &Number) -> Number {
        // Rational fast path: the common case in Butcher tables.
        if let Some(r) = rhs.as_rational() {
            return self.scale(&r);
        }
        if let Some(r) = self.as_rational() {
            return rhs.scale(&r);
        }
        // Fraction-free: scale both to integer coefficients over their
        // common denominators, accumulate integer products, and divide once
        // per resulting term (no gcd in the inner loop).
        let (na, da) = self.integer_coefficients();
        let (nb, db) = rhs.integer_coefficients();
        let mut acc: std::collections::HashMap<Radical, BigInt> =
            std::collections::HashMap::with_capacity(self.terms.len() * rhs.terms.len());
        for (ma, ca) in &na {
            for (mb, cb) in &nb {
                let (factor, m) = ma.mul(mb);
                let mut c = ca * cb;
                if !factor.is_one() {
                    c *= factor;
                }
                *acc.entry(m).or_default() += c;
            }
        }
        let den = da * db;
        let terms = acc
            .into_iter()
            .filter(|(_, c)| !c.is_zero())
            .map(|(m, c)| (m, BigRational::new(c, den.clone())))
            .collect();
        Number { terms }
    }
}

impl AddAssign<&Number> for Number {
    fn add_assign(&mut self, rhs: &Number) {
        for (m, c) in &rhs.terms {
            self.add_term(m, c);
        }
    }
}

impl SubAssign<&Number> for Number {
    fn sub_assign(&mut self, rhs: &Number) {
        for (m, c) in &rhs.terms {
            self.add_term(m, &-c);
        }
    }
}

impl Neg for Number {
    type Output = Number;
    fn neg(mut self) -> Number {
        for c in self.terms.values_mut() {
            *c = -c.clone();
        }
        self
    }
}

impl Neg for &Number {
    type Output = Number;
    fn neg(self) -> Number {
        -self.clone()
    }
}

macro_rules! forward_owned {
    ($($tr:ident $f:ident),*) => {$(
        impl $tr<Number> for Number {
            type Output = Number;
            fn $f(self, rhs: Number) -> Number { (&self).$f(&rhs) }
        }
        impl<'a> $tr<&'a Number> for Number {
            type Output = Number;
            fn $f(self, rhs: &'a Number) -> Number { (&self).$f(rhs) }
        }
        impl<'a> $tr<Number> for &'a Number {
            type Output = Number;
            fn $f(self, rhs: Number) -> Number { self.$f(&rhs) }
        }
    )*};
}
forward_owned!(Add add, Sub sub, Mul mul);

impl fmt::Display for Number {
    /// Canonical text in the grammar, e.g. `1/4 - 1/6*sqrt(3)`; parsing it
    /// back gives the same number.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_zero() {
            return f.write_str("0");
        }
        for (k, (m, c)) in self.terms.iter().enumerate() {
            let (text, divisor) = m.to_grammar();
            let c = c / BigRational::from_integer(divisor);
            let neg = c.is_negative();
            let c = c.abs();
            match (k, neg) {
                (0, true) => f.write_str("-")?,
                (0, false) => {}
                (_, true) => f.write_str(" - ")?,
                (_, false) => f.write_str(" + ")?,
            }
            if text.is_empty() {
                write!(f, "{c}")?;
            } else if c.is_one() {
                f.write_str(&text)?;
            } else if c.numer().is_one() {
                write!(f, "{text}/{}", c.denom())?;
            } else {
                write!(f, "{c}*{text}")?;
            }
        }
        Ok(())
    }
}

impl fmt::Debug for Number {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Number({self})")
    }
}

impl PartialOrd for Number {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Number {
    /// The exact numeric order.
    fn cmp(&self, other: &Self) -> Ordering {
        self.cmp_exact(other)
    }
}
