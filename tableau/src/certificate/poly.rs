//! Polynomials in several unknowns with rational coefficients (moved here
//! from the `design` crate, which uses them through `design::poly`): the
//! order conditions of a family, or of a certified table file, are built
//! as these, so that their derivatives are
//! exact (differentiate the polynomial) and the same polynomial is evaluated
//! in `f64` by the solver, in exact rationals by the polish, and in rational
//! intervals by the certificate.
//!
//! Sums run over the terms in the order of the `BTreeMap` (exponent vectors
//! lexicographically) and every product is a plain multiplication, with no
//! fused multiply–add, so an `f64` evaluation gives the same bits on every
//! code path.

use std::collections::BTreeMap;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};

use crate::number::order::{qle, qlt};

/// A polynomial in `nvars` unknowns: exponent vector → nonzero coefficient.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Poly {
    nvars: usize,
    terms: BTreeMap<Vec<u8>, BigRational>,
}

impl Poly {
    /// The zero polynomial.
    pub fn zero(nvars: usize) -> Poly {
        Poly {
            nvars,
            terms: BTreeMap::new(),
        }
    }

    /// A constant.
    pub fn constant(nvars: usize, c: BigRational) -> Poly {
        let mut p = Poly::zero(nvars);
        if !c.is_zero() {
            p.terms.insert(vec![0; nvars], c);
        }
        p
    }

    /// The unknown `x_i`.
    pub fn var(nvars: usize, i: usize) -> Poly {
        let mut e = vec![0; nvars];
        e[i] = 1;
        let mut p = Poly::zero(nvars);
        p.terms.insert(e, BigRational::one());
        p
    }

    pub fn nvars(&self) -> usize {
        self.nvars
    }

    pub fn is_zero(&self) -> bool {
        self.terms.is_empty()
    }

    /// The number of (nonzero) terms.
    pub fn len(&self) -> usize {
        self.terms.len()
    }

    /// Whether there are no terms (the zero polynomial).
    pub fn is_empty(&self) -> bool {
        self.terms.is_empty()
    }

    /// The terms, exponent vectors in increasing order.
    pub fn terms(&self) -> impl Iterator<Item = (&Vec<u8>, &BigRational)> {
        self.terms.iter()
    }

    /// The total degree (0 for the zero polynomial).
    pub fn degree(&self) -> usize {
        self.terms
            .keys()
            .map(|e| e.iter().map(|&k| usize::from(k)).sum())
            .max()
            .unwrap_or(0)
    }

    /// The constant when the polynomial is one.
    pub fn as_constant(&self) -> Option<BigRational> {
        match self.terms.len() {
            0 => Some(BigRational::zero()),
            1 => self.terms.get(&vec![0; self.nvars]).cloned(),
            _ => None,
        }
    }

    /// The unknowns that occur.
    pub fn variables(&self) -> Vec<usize> {
        (0..self.nvars)
            .filter(|&i| self.terms.keys().any(|e| e[i] > 0))
            .collect()
    }

    fn add_term(&mut self, e: Vec<u8>, c: BigRational) {
        if c.is_zero() {
            return;
        }
        match self.terms.entry(e) {
            std::collections::btree_map::Entry::Vacant(v) => {
                v.insert(c);
            }
            std::collections::btree_map::Entry::Occupied(mut o) => {
                *o.get_mut() += c;
                if o.get().is_zero() {
                    o.remove();
                }
            }
        }
    }

    pub fn add(&self, o: &Poly) -> Poly {
        let mut out = self.clone();
        for (e, c) in &o.terms {
            out.add_term(e.clone(), c.clone());
        }
        out
    }

    pub fn sub(&self, o: &Poly) -> Poly {
        let mut out = self.clone();
        for (e, c) in &o.terms {
            out.add_term(e.clone(), -c.clone());
        }
        out
    }

    pub fn scale(&self, r: &BigRational) -> Poly {
        if r.is_zero() {
            return Poly::zero(self.nvars);
        }
        Poly {
            nvars: self.nvars,
            terms: self.terms.iter().map(|(e, c)| (e.clone(), c * r)).collect(),
        }
    }

    pub fn mul(&self, o: &Poly) -> Poly {
        let mut out = Poly::zero(self.nvars);
        for (e1, c1) in &self.terms {
            for (e2, c2) in &o.terms {
                let e: Vec<u8> = e1.iter().zip(e2).map(|(a, b)| a + b).collect();
                out.add_term(e, c1 * c2);
            }
        }
        out
    }

    pub fn pow(&self, k: usize) -> Poly {
        let mut out = Poly::constant(self.nvars, BigRational::one());
        for _ in 0..k {
            out = out.mul(self);
        }
        out
    }

    /// `∂/∂x_i`.
    pub fn derivative(&self, i: usize) -> Poly {
        let mut out = Poly::zero(self.nvars);
        for (e, c) in &self.terms {
            if e[i] > 0 {
                let mut d = e.clone();
                d[i] -= 1;
                out.add_term(d, c * BigRational::from_integer(BigInt::from(e[i])));
            }
        }
        out
    }

    /// Substitute `x_i ↦ subs[i]` (polynomials in `m` unknowns).
    pub fn substitute(&self, subs: &[Poly], m: usize) -> Poly {
        let mut out = Poly::zero(m);
        for (e, c) in &self.terms {
            let mut t = Poly::constant(m, c.clone());
            for (i, &k) in e.iter().enumerate() {
                if k > 0 {
                    t = t.mul(&subs[i].pow(usize::from(k)));
                }
            }
            out = out.add(&t);
        }
        out
    }

    /// The value at a rational point, exactly.
    pub fn eval_rational(&self, x: &[BigRational]) -> BigRational {
        let mut out = BigRational::zero();
        for (e, c) in &self.terms {
            let mut t = c.clone();
            for (xi, &k) in x.iter().zip(e) {
                for _ in 0..k {
                    t *= xi;
                }
            }
            out += t;
        }
        out
    }

    /// An enclosure of the values on a box of rational intervals, in exact
    /// rational interval arithmetic (no rounding anywhere).
    pub fn eval_interval(&self, x: &[Interval]) -> Interval {
        let mut out = Interval::point(BigRational::zero());
        for (e, c) in &self.terms {
            let mut t = Interval::point(c.clone());
            for (xi, &k) in x.iter().zip(e) {
                if k > 0 {
                    t = t.mul(&xi.pow(usize::from(k)));
                }
            }
            out = out.add(&t);
        }
        out
    }

    /// The same polynomial compiled for `f64` evaluation.
    pub fn compile(&self) -> FPoly {
        FPoly {
            terms: self
                .terms
                .iter()
                .map(|(e, c)| {
                    let vars = e
                        .iter()
                        .enumerate()
                        .filter(|&(_, &k)| k > 0)
                        .map(|(i, &k)| (i, k))
                        .collect();
                    (to_f64(c), vars)
                })
                .collect(),
        }
    }

    /// Text in the unknowns' names, e.g. `2*g1^3 + g2^3`.
    pub fn to_text(&self, names: &[String]) -> String {
        if self.is_zero() {
            return "0".into();
        }
        let mut s = String::new();
        for (e, c) in self.terms.iter().rev() {
            let neg = c.is_negative();
            let a = c.abs();
            if s.is_empty() {
                if neg {
                    s.push('-');
                }
            } else {
                s.push_str(if neg { " - " } else { " + " });
            }
            let mono: Vec<String> = e
                .iter()
                .enumerate()
                .filter(|&(_, &k)| k > 0)
                .map(|(i, &k)| {
                    if k == 1 {
                        names[i].clone()
                    } else {
                        format!("{}^{k}", names[i])
                    }
                })
                .collect();
            if mono.is_empty() {
                s.push_str(&a.to_string());
            } else if a.is_one() {
                s.push_str(&mono.join("*"));
            } else {
                s.push_str(&format!("{a}*{}", mono.join("*")));
            }
        }
        s
    }
}

/// A rational to the nearest `f64` (to within an ulp; only the solver's
/// starting guesses and Jacobians depend on it, never a decision).
pub fn to_f64(r: &BigRational) -> f64 {
    r.to_f64().unwrap_or(f64::NAN)
}

/// A polynomial compiled for the solver: `(coefficient, [(unknown, power)])`.
#[derive(Clone, Debug)]
pub struct FPoly {
    terms: Vec<(f64, Vec<(usize, u8)>)>,
}

impl FPoly {
    /// The value at `x`, summed in a fixed order with plain products.
    pub fn eval(&self, x: &[f64]) -> f64 {
        let mut sum = 0.0;
        for (c, vars) in &self.terms {
            let mut t = *c;
            for &(i, k) in vars {
                for _ in 0..k {
                    t *= x[i];
                }
            }
            sum += t;
        }
        sum
    }
}

/// A closed interval `[lo, hi]` with rational endpoints.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Interval {
    pub lo: BigRational,
    pub hi: BigRational,
}

impl Interval {
    pub fn point(x: BigRational) -> Interval {
        Interval {
            lo: x.clone(),
            hi: x,
        }
    }

    /// `[c − r, c + r]`.
    pub fn around(c: &BigRational, r: &BigRational) -> Interval {
        Interval {
            lo: c - r,
            hi: c + r,
        }
    }

    pub fn add(&self, o: &Interval) -> Interval {
        Interval {
            lo: &self.lo + &o.lo,
            hi: &self.hi + &o.hi,
        }
    }

    pub fn sub(&self, o: &Interval) -> Interval {
        Interval {
            lo: &self.lo - &o.hi,
            hi: &self.hi - &o.lo,
        }
    }

    pub fn mul(&self, o: &Interval) -> Interval {
        let p = [
            &self.lo * &o.lo,
            &self.lo * &o.hi,
            &self.hi * &o.lo,
            &self.hi * &o.hi,
        ];
        let mut lo = p[0].clone();
        let mut hi = p[0].clone();
        for v in &p[1..] {
            if qlt(v, &lo) {
                lo = v.clone();
            }
            if qlt(&hi, v) {
                hi = v.clone();
            }
        }
        Interval { lo, hi }
    }

    /// `self · r` for a rational `r`.
    pub fn scale(&self, r: &BigRational) -> Interval {
        let a = &self.lo * r;
        let b = &self.hi * r;
        if qle(&a, &b) {
            Interval { lo: a, hi: b }
        } else {
            Interval { lo: b, hi: a }
        }
    }

    /// `self^k`, tight for even powers of an interval containing 0.
    pub fn pow(&self, k: usize) -> Interval {
        if k == 0 {
            return Interval::point(BigRational::one());
        }
        let mut lo_k = BigRational::one();
        let mut hi_k = BigRational::one();
        for _ in 0..k {
            lo_k *= &self.lo;
            hi_k *= &self.hi;
        }
        if k % 2 == 1 {
            Interval { lo: lo_k, hi: hi_k }
        } else if self.lo.is_negative() && self.hi.is_positive() {
            Interval {
                lo: BigRational::zero(),
                hi: if qlt(&lo_k, &hi_k) { hi_k } else { lo_k },
            }
        } else if qle(&lo_k, &hi_k) {
            Interval { lo: lo_k, hi: hi_k }
        } else {
            Interval { lo: hi_k, hi: lo_k }
        }
    }

    /// Whether `0 ∉ [lo, hi]`.
    pub fn excludes_zero(&self) -> bool {
        self.lo.is_positive() || self.hi.is_negative()
    }

    /// `max(|lo|, |hi|)`.
    pub fn magnitude(&self) -> BigRational {
        let (a, b) = (self.lo.abs(), self.hi.abs());
        if qlt(&a, &b) { b } else { a }
    }

    /// Whether `self ⊂ (o.lo, o.hi)`, strictly inside.
    pub fn strictly_inside(&self, o: &Interval) -> bool {
        qlt(&o.lo, &self.lo) && qlt(&self.hi, &o.hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64, d: i64) -> BigRational {
        BigRational::new(n.into(), d.into())
    }

    #[test]
    fn arithmetic_and_derivatives() {
        let x = Poly::var(2, 0);
        let y = Poly::var(2, 1);
        let p = x.pow(3).scale(&q(2, 1)).add(&y.pow(3)); // 2x³ + y³
        assert_eq!(p.derivative(0), x.pow(2).scale(&q(6, 1)));
        assert_eq!(p.eval_rational(&[q(1, 2), q(-1, 1)]), q(-3, 4));
        assert!(p.sub(&p).is_zero());
        let names = vec!["x".to_string(), "y".to_string()];
        assert_eq!(p.to_text(&names), "2*x^3 + y^3");
        assert_eq!(p.compile().eval(&[0.5, -1.0]), -0.75);
    }

    #[test]
    fn intervals_enclose() {
        let x = Interval {
            lo: q(-1, 2),
            hi: q(1, 3),
        };
        assert_eq!(
            x.pow(2),
            Interval {
                lo: q(0, 1),
                hi: q(1, 4)
            }
        );
        let p = Poly::var(1, 0).pow(2).sub(&Poly::constant(1, q(1, 1)));
        let v = p.eval_interval(&[x]);
        assert!(v.lo <= q(-1, 1) && v.hi >= q(-3, 4));
        assert!(v.excludes_zero());
    }
}
