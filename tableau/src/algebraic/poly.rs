//! Dense univariate polynomials over Q, with the exact real-root tools the
//! algebraic numbers need: Euclidean division and gcd, squarefree parts,
//! Sturm sequences (exact root counts in an interval), and evaluation on a
//! rational interval (a certified enclosure, never a float).

use std::fmt;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

/// `Σ coeffs[k] xᵏ`, constant term first, no trailing zeros (zero is empty).
#[derive(Clone, Default)]
pub struct Poly(pub Vec<BigRational>);

/// Equality coefficient by coefficient with [`qeq`] (never the recursive
/// comparison of `num-rational`).
impl PartialEq for Poly {
    fn eq(&self, o: &Poly) -> bool {
        self.0.len() == o.0.len() && self.0.iter().zip(&o.0).all(|(a, b)| qeq(a, b))
    }
}

impl Eq for Poly {}

pub use crate::number::order::{qcmp, qeq, qle, qlt};

fn q(n: i64) -> BigRational {
    BigRational::from_integer(BigInt::from(n))
}

impl Poly {
    pub fn zero() -> Poly {
        Poly(Vec::new())
    }

    pub fn one() -> Poly {
        Poly::constant(BigRational::one())
    }

    pub fn constant(c: BigRational) -> Poly {
        Poly(vec![c]).trim()
    }

    /// `x`.
    pub fn x() -> Poly {
        Poly(vec![q(0), q(1)])
    }

    /// `c·xᵏ`.
    pub fn monomial(c: BigRational, k: usize) -> Poly {
        let mut v = vec![BigRational::zero(); k + 1];
        v[k] = c;
        Poly(v).trim()
    }

    pub fn from_ints(c: &[i64]) -> Poly {
        Poly(c.iter().map(|&n| q(n)).collect()).trim()
    }

    pub fn trim(mut self) -> Poly {
        while self.0.last().is_some_and(Zero::is_zero) {
            self.0.pop();
        }
        self
    }

    pub fn is_zero(&self) -> bool {
        self.0.is_empty()
    }

    /// Degree; `None` for the zero polynomial.
    pub fn degree(&self) -> Option<usize> {
        self.0.len().checked_sub(1)
    }

    pub fn lead(&self) -> BigRational {
        self.0.last().cloned().unwrap_or_else(BigRational::zero)
    }

    pub fn coeff(&self, k: usize) -> BigRational {
        self.0.get(k).cloned().unwrap_or_else(BigRational::zero)
    }

    pub fn add(&self, o: &Poly) -> Poly {
        let n = self.0.len().max(o.0.len());
        Poly((0..n).map(|k| self.coeff(k) + o.coeff(k)).collect()).trim()
    }

    pub fn sub(&self, o: &Poly) -> Poly {
        let n = self.0.len().max(o.0.len());
        Poly((0..n).map(|k| self.coeff(k) - o.coeff(k)).collect()).trim()
    }

    pub fn neg(&self) -> Poly {
        Poly(self.0.iter().map(|c| -c).collect())
    }

    pub fn scale(&self, r: &BigRational) -> Poly {
        if r.is_zero() {
            return Poly::zero();
        }
        Poly(self.0.iter().map(|c| c * r).collect())
    }

    pub fn mul(&self, o: &Poly) -> Poly {
        if self.is_zero() || o.is_zero() {
            return Poly::zero();
        }
        let mut out = vec![BigRational::zero(); self.0.len() + o.0.len() - 1];
        for (i, a) in self.0.iter().enumerate() {
            if a.is_zero() {
                continue;
            }
            for (j, b) in o.0.iter().enumerate() {
                if !b.is_zero() {
                    out[i + j] += a * b;
                }
            }
        }
        Poly(out).trim()
    }

    pub fn pow(&self, k: usize) -> Poly {
        let mut r = Poly::one();
        for _ in 0..k {
            r = r.mul(self);
        }
        r
    }

    /// Quotient and remainder; `d` must be nonzero.
    pub fn divrem(&self, d: &Poly) -> (Poly, Poly) {
        let dd = d.degree().expect("division by the zero polynomial");
        let lead_inv = d.lead().recip();
        let mut r = self.0.clone();
        if r.len() <= dd {
            return (Poly::zero(), self.clone());
        }
        let mut quot = vec![BigRational::zero(); r.len() - dd];
        for k in (dd..r.len()).rev() {
            if r[k].is_zero() {
                continue;
            }
            let f = &r[k] * &lead_inv;
            for (j, dc) in d.0.iter().enumerate() {
                if !dc.is_zero() {
                    let t = &f * dc;
                    r[k - dd + j] -= t;
                }
            }
            quot[k - dd] = f;
        }
        r.truncate(dd);
        (Poly(quot).trim(), Poly(r).trim())
    }

    pub fn rem(&self, d: &Poly) -> Poly {
        self.divrem(d).1
    }

    /// Monic (leading coefficient 1); zero stays zero.
    pub fn monic(&self) -> Poly {
        if self.is_zero() {
            return Poly::zero();
        }
        self.scale(&self.lead().recip())
    }

    /// The monic gcd.
    pub fn gcd(&self, o: &Poly) -> Poly {
        let (mut a, mut b) = (self.clone(), o.clone());
        while !b.is_zero() {
            let r = a.rem(&b);
            a = b;
            b = r.monic();
        }
        a.monic()
    }

    /// `(g, u)` with `g = gcd(self, m)` monic and `u·self ≡ g (mod m)`.
    pub fn gcd_ext(&self, m: &Poly) -> (Poly, Poly) {
        let (mut r0, mut r1) = (m.clone(), self.rem(m));
        let (mut s0, mut s1) = (Poly::zero(), Poly::one());
        while !r1.is_zero() {
            let (qt, r) = r0.divrem(&r1);
            let s = s0.sub(&qt.mul(&s1));
            r0 = r1;
            r1 = r;
            s0 = s1;
            s1 = s;
        }
        let l = r0.lead().recip();
        (r0.scale(&l), s0.scale(&l))
    }

    /// The inverse of `self` modulo `m`, if `gcd(self, m) = 1`.
    pub fn inverse_mod(&self, m: &Poly) -> Option<Poly> {
        let (g, u) = self.gcd_ext(m);
        (g.degree() == Some(0)).then(|| u.rem(m))
    }

    pub fn derivative(&self) -> Poly {
        Poly(
            self.0
                .iter()
                .enumerate()
                .skip(1)
                .map(|(k, c)| c * q(k as i64))
                .collect(),
        )
        .trim()
    }

    /// `∫₀ˣ self`.
    pub fn integral(&self) -> Poly {
        let mut v = vec![BigRational::zero()];
        v.extend(self.0.iter().enumerate().map(|(k, c)| c / q(k as i64 + 1)));
        Poly(v).trim()
    }

    pub fn eval(&self, x: &BigRational) -> BigRational {
        let mut acc = BigRational::zero();
        for c in self.0.iter().rev() {
            acc = acc * x + c;
        }
        acc
    }

    /// `self(p(x))`.
    pub fn compose(&self, p: &Poly) -> Poly {
        let mut acc = Poly::zero();
        for c in self.0.iter().rev() {
            acc = acc.mul(p).add(&Poly::constant(c.clone()));
        }
        acc
    }

    /// `self / gcd(self, self')`: the same roots, each simple.
    pub fn squarefree(&self) -> Poly {
        let g = self.gcd(&self.derivative());
        self.divrem(&g).0.monic()
    }

    pub fn is_squarefree(&self) -> bool {
        self.gcd(&self.derivative()).degree() == Some(0)
    }

    /// The Sturm sequence `p, p', −rem(p, p'), …`.
    pub fn sturm(&self) -> Vec<Poly> {
        let mut seq = vec![self.clone(), self.derivative()];
        loop {
            let n = seq.len();
            if seq[n - 1].is_zero() {
                seq.pop();
                break;
            }
            let r = seq[n - 2].rem(&seq[n - 1]).neg();
            if r.is_zero() {
                break;
            }
            seq.push(r);
        }
        seq
    }

    /// Exact enclosure `[lo, hi]` of `{self(x) : x ∈ [a, b]}` (Horner in
    /// interval arithmetic).
    pub fn eval_interval(&self, a: &BigRational, b: &BigRational) -> (BigRational, BigRational) {
        let mut lo = BigRational::zero();
        let mut hi = BigRational::zero();
        for c in self.0.iter().rev() {
            let (l, h) = imul(&lo, &hi, a, b);
            lo = l + c;
            hi = h + c;
        }
        (lo, hi)
    }

    /// Text with variable `var`, highest power first, e.g. `x^2 - 1/3`.
    pub fn to_text(&self, var: &str) -> String {
        if self.is_zero() {
            return "0".into();
        }
        let mut s = String::new();
        for (k, c) in self.0.iter().enumerate().rev() {
            if c.is_zero() {
                continue;
            }
            let neg = c.is_negative();
            let a = c.abs();
            if s.is_empty() {
                if neg {
                    s.push('-');
                }
            } else {
                s.push_str(if neg { " - " } else { " + " });
            }
            let mono = match k {
                0 => String::new(),
                1 => var.to_string(),
                _ => format!("{var}^{k}"),
            };
            if mono.is_empty() {
                s.push_str(&a.to_string());
            } else if a.is_one() {
                s.push_str(&mono);
            } else {
                s.push_str(&format!("{a}*{mono}"));
            }
        }
        s
    }
}

/// `[a, b]·[c, d]`.
pub fn imul(
    a: &BigRational,
    b: &BigRational,
    c: &BigRational,
    d: &BigRational,
) -> (BigRational, BigRational) {
    let ps = [a * c, a * d, b * c, b * d];
    let mut lo = ps[0].clone();
    let mut hi = ps[0].clone();
    for p in &ps[1..] {
        if qlt(p, &lo) {
            lo = p.clone();
        }
        if qlt(&hi, p) {
            hi = p.clone();
        }
    }
    (lo, hi)
}

/// Sign changes of a Sturm sequence at `x`.
fn variations(seq: &[Poly], x: &BigRational) -> usize {
    let mut last = 0i8;
    let mut n = 0;
    for p in seq {
        let v = p.eval(x);
        let s = if v.is_positive() {
            1
        } else if v.is_negative() {
            -1
        } else {
            0
        };
        if s != 0 {
            if last != 0 && s != last {
                n += 1;
            }
            last = s;
        }
    }
    n
}

/// The number of distinct real roots of `p` in the half-open interval
/// `(a, b]` (Sturm's theorem), for a nonzero `p`.
pub fn count_roots(seq: &[Poly], a: &BigRational, b: &BigRational) -> usize {
    variations(seq, a).saturating_sub(variations(seq, b))
}

/// `P_n(u)`, the Legendre polynomial, by the three-term recurrence.
pub fn legendre(n: usize) -> Poly {
    let mut p0 = Poly::one();
    if n == 0 {
        return p0;
    }
    let mut p1 = Poly::x();
    for k in 1..n {
        // (k+1) P_{k+1} = (2k+1) u P_k − k P_{k−1}
        let t = Poly::x()
            .mul(&p1)
            .scale(&q(2 * k as i64 + 1))
            .sub(&p0.scale(&q(k as i64)));
        p0 = p1;
        p1 = t.scale(&q(k as i64 + 1).recip());
    }
    p1
}

/// `P_n(2x − 1)`, the shifted Legendre polynomial on `[0, 1]`.
pub fn shifted_legendre(n: usize) -> Poly {
    legendre(n).compose(&Poly::from_ints(&[-1, 2]))
}

impl fmt::Debug for Poly {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.to_text("x"))
    }
}

impl fmt::Display for Poly {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.to_text("x"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn division_and_gcd() {
        let a = Poly::from_ints(&[-1, 0, 1]); // x² − 1
        let b = Poly::from_ints(&[1, 1]); // x + 1
        let (qt, r) = a.divrem(&b);
        assert_eq!(qt, Poly::from_ints(&[-1, 1]));
        assert!(r.is_zero());
        assert_eq!(
            a.gcd(&Poly::from_ints(&[-1, 0, 0, 1])),
            Poly::from_ints(&[-1, 1])
        );
        let inv = Poly::from_ints(&[1, 1])
            .inverse_mod(&Poly::from_ints(&[-2, 0, 1]))
            .unwrap();
        // (1 + x)(−1 + x) = x² − 1 ≡ 1 mod x² − 2
        assert_eq!(inv, Poly::from_ints(&[-1, 1]));
    }

    #[test]
    fn sturm_counts_roots() {
        let p = shifted_legendre(5);
        let seq = p.sturm();
        assert_eq!(count_roots(&seq, &q(0), &q(1)), 5);
        assert_eq!(
            count_roots(&seq, &q(0), &BigRational::new(1.into(), 2.into())),
            3
        );
        assert_eq!(
            legendre(3),
            Poly(vec![
                q(0),
                BigRational::new((-3).into(), 2.into()),
                q(0),
                BigRational::new(5.into(), 2.into())
            ])
        );
    }
}
