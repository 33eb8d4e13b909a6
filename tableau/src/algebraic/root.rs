//! Real roots of rational polynomials, each picked out by an isolating
//! interval, refined by exact bisection with Sturm counts; the correctly
//! rounded `f64` of a root is decided on certified enclosures, never by
//! evaluating in floating point.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

use super::poly::{Poly, count_roots, qeq, qle, qlt};
use crate::number::rational_to_f64;

/// One real root of a squarefree polynomial: `poly` has exactly one root in
/// the half-open interval `(lo, hi]`, or the root is the rational `lo = hi`.
#[derive(Clone, Debug)]
pub struct RealRoot {
    /// Monic and squarefree.
    pub poly: Poly,
    pub lo: BigRational,
    pub hi: BigRational,
    sturm: Vec<Poly>,
}

/// The same polynomial and the same interval (compared with
/// [`super::poly::qeq`]).
impl PartialEq for RealRoot {
    fn eq(&self, o: &RealRoot) -> bool {
        self.poly == o.poly && qeq(&self.lo, &o.lo) && qeq(&self.hi, &o.hi)
    }
}

impl Eq for RealRoot {}

/// `n / 2ᵏ`, reduced by stripping the common powers of two (no gcd: the
/// binary gcd of `num-bigint` is quadratic with a large constant, and the
/// refinement builds such numbers of hundreds of thousands of bits).
pub fn dyadic(n: BigInt, k: u64) -> BigRational {
    if n.is_zero() {
        return BigRational::zero();
    }
    let t = n.trailing_zeros().unwrap_or(0).min(k);
    BigRational::new_raw(n >> t as usize, BigInt::one() << (k - t) as usize)
}

/// `floor(x · 2ᵏ)` in integers, without normalising a rational.
pub fn floor_scaled(x: &BigRational, k: u64) -> BigInt {
    use num_integer::Integer;
    (x.numer() << k as usize).div_floor(x.denom())
}

/// `ceil(x · 2ᵏ)` in integers.
pub fn ceil_scaled(x: &BigRational, k: u64) -> BigInt {
    -floor_scaled(&-x, k)
}

fn two() -> BigRational {
    BigRational::from_integer(BigInt::from(2))
}

impl RealRoot {
    /// The root of `poly` in `(lo, hi]`, if there is exactly one there
    /// (`poly` is made squarefree and monic first). `Err` says how many there
    /// are.
    pub fn new(poly: &Poly, lo: BigRational, hi: BigRational) -> Result<RealRoot, usize> {
        if poly.degree().unwrap_or(0) == 0 || qlt(&hi, &lo) {
            return Err(0);
        }
        let p = poly.squarefree();
        let sturm = p.sturm();
        if qeq(&lo, &hi) {
            return if p.eval(&lo).is_zero() {
                Ok(RealRoot {
                    poly: p,
                    lo: lo.clone(),
                    hi: lo,
                    sturm,
                })
            } else {
                Err(0)
            };
        }
        // Every root has |x| < 1 + max|cₖ| (Cauchy, p monic) ≤ 2^k: clip the
        // interval there, so that huge bounds cost no bisections.
        let cauchy =
            p.0.iter()
                .map(|c| c.abs().ceil().to_integer().bits())
                .max()
                .unwrap_or(0)
                + 1;
        let big = BigRational::from_integer(BigInt::one() << cauchy);
        let (lo, hi) = (
            if qlt(&lo, &-big.clone()) {
                -big.clone()
            } else {
                lo
            },
            if qlt(&big, &hi) { big } else { hi },
        );
        if qle(&hi, &lo) {
            return Err(0);
        }
        let n = count_roots(&sturm, &lo, &hi);
        if n != 1 {
            return Err(n);
        }
        let mut r = RealRoot {
            poly: p,
            lo,
            hi,
            sturm,
        };
        if r.poly.eval(&r.hi).is_zero() {
            r.lo = r.hi.clone();
        }
        Ok(r)
    }

    /// A rational number as a root of `x − r`.
    pub fn rational(r: BigRational) -> RealRoot {
        let poly = Poly(vec![-r.clone(), BigRational::one()]);
        RealRoot {
            sturm: poly.sturm(),
            poly,
            lo: r.clone(),
            hi: r,
        }
    }

    /// Every real root of `poly` in `(a, b]`, in increasing order.
    pub fn isolate(poly: &Poly, a: &BigRational, b: &BigRational) -> Vec<RealRoot> {
        let p = poly.squarefree();
        let sturm = p.sturm();
        let mut out = Vec::new();
        let mut stack = vec![(a.clone(), b.clone())];
        while let Some((lo, hi)) = stack.pop() {
            let n = count_roots(&sturm, &lo, &hi);
            if n == 0 {
                continue;
            }
            if n == 1 {
                if p.degree() == Some(1) {
                    // The root of a linear polynomial is rational.
                    let r = -p.coeff(0) / p.coeff(1);
                    out.push(RealRoot {
                        poly: p.clone(),
                        lo: r.clone(),
                        hi: r,
                        sturm: sturm.clone(),
                    });
                    continue;
                }
                let exact = p.eval(&hi).is_zero();
                out.push(RealRoot {
                    poly: p.clone(),
                    lo: if exact { hi.clone() } else { lo },
                    hi,
                    sturm: sturm.clone(),
                });
                continue;
            }
            let mid = (&lo + &hi) / two();
            // Upper half first on the stack so the lower half pops first.
            stack.push((mid.clone(), hi));
            stack.push((lo, mid));
        }
        out
    }

    /// Whether `o` is the same number: the same polynomial, and the root
    /// in both intervals (a Sturm count on their intersection; two roots of
    /// one polynomial in intervals that share no root are distinct).
    pub fn same_root(&self, o: &RealRoot) -> bool {
        if self.poly != o.poly {
            return false;
        }
        match (self.is_rational(), o.is_rational()) {
            (true, true) => qeq(&self.lo, &o.lo),
            (false, false) => {
                let lo = if qlt(&self.lo, &o.lo) {
                    &o.lo
                } else {
                    &self.lo
                };
                let hi = if qlt(&self.hi, &o.hi) {
                    &self.hi
                } else {
                    &o.hi
                };
                qlt(lo, hi) && count_roots(&self.sturm, lo, hi) == 1
            }
            // A rational root r of the polynomial is the other's root when
            // it lies in the other's interval (which holds one root).
            (true, false) => qlt(&o.lo, &self.lo) && qle(&self.lo, &o.hi),
            (false, true) => qlt(&self.lo, &o.lo) && qle(&o.lo, &self.hi),
        }
    }

    pub fn is_rational(&self) -> bool {
        qeq(&self.lo, &self.hi)
    }

    pub fn width(&self) -> BigRational {
        &self.hi - &self.lo
    }

    /// Whether the interval is wider than `2^-bits`, in integers (no
    /// normalised rational).
    pub fn wider_than(&self, bits: u64) -> bool {
        let (l, h) = (&self.lo, &self.hi);
        let wn = h.numer() * l.denom() - l.numer() * h.denom();
        (wn << bits as usize) > l.denom() * h.denom()
    }

    /// About `log₂(1/width)` (at most it, never more), in integers.
    fn width_bits(&self) -> u64 {
        let (l, h) = (&self.lo, &self.hi);
        let wn = h.numer() * l.denom() - l.numer() * h.denom();
        let wd = l.denom() * h.denom();
        (wd.bits() as i64 - wn.bits() as i64 - 1).max(0) as u64
    }

    /// Split the interval at `m` (strictly inside), keeping the half that
    /// holds the root; an exact hit makes the root rational.
    pub fn split_at(&mut self, m: BigRational) {
        if self.is_rational() {
            return;
        }
        if self.poly.eval(&m).is_zero() {
            self.lo = m.clone();
            self.hi = m;
            return;
        }
        if count_roots(&self.sturm, &self.lo, &m) == 1 {
            self.hi = m;
        } else {
            self.lo = m;
        }
    }

    /// Halve the interval.
    pub fn bisect(&mut self) {
        if !self.is_rational() {
            let m = (&self.lo + &self.hi) / two();
            self.split_at(m);
        }
    }

    /// Refine until the width is at most `2^-bits`: bisection to a narrow
    /// interval, then Newton steps in integer arithmetic on dyadic points
    /// `X/2^k`, each accepted only when an exact sign change of the
    /// polynomial certifies the root in the new, smaller interval (a failed
    /// step falls back to bisection).
    pub fn refine_to(&mut self, bits: u64) {
        self.refine_within(bits, u64::MAX);
    }

    /// [`Self::refine_to`] with at most `bisections` bisections (each a
    /// Sturm count; certified Newton steps are not limited, they halve the
    /// number of unknown bits). Returns whether the width was reached; when
    /// not, the interval is narrower than before and still holds the root.
    pub fn refine_within(&mut self, bits: u64, bisections: u64) -> bool {
        use num_integer::Integer;
        if self.is_rational() || !self.wider_than(bits) {
            return true;
        }
        let mut left = bisections;
        // Integer coefficients: D·p.
        let mut den = BigInt::one();
        for c in &self.poly.0 {
            den = den.lcm(c.denom());
        }
        let ip: Vec<BigInt> = self
            .poly
            .0
            .iter()
            .map(|c| c.numer() * (&den / c.denom()))
            .collect();
        let d = ip.len() - 1;
        // 2^{k·d}·D·p(X/2^k) and 2^{k(d−1)}·D·p'(X/2^k).
        let eval = |x: &BigInt, k: u64| -> (BigInt, BigInt) {
            let mut v = BigInt::zero();
            let mut dv = BigInt::zero();
            for (j, c) in ip.iter().enumerate().rev() {
                // Horner with the scale folded in: v = v·X + c·2^{k(d−j)}
                // computed as Σ c X^j 2^{k(d−j)}.
                v = &v * x + (c << (k as usize * (d - j)));
                if j > 0 {
                    dv = &dv * x + ((c * BigInt::from(j)) << (k as usize * (d - j)));
                }
            }
            // v has been built as Σ c_j X^j 2^{k(d−j)}; dv as
            // Σ j c_j X^{j−1} 2^{k(d−j)}.
            (v, dv)
        };
        let sgn = |v: &BigInt| -> i8 {
            if v.is_positive() {
                1
            } else if v.is_negative() {
                -1
            } else {
                0
            }
        };
        let mut failures: u32 = 0;
        while self.wider_than(bits) {
            if self.is_rational() {
                return true;
            }
            let cur = self.width_bits();
            if cur < 40 || failures > 3 {
                if left == 0 {
                    return false;
                }
                left -= 1;
                self.bisect();
                failures = failures.saturating_sub(1);
                continue;
            }
            let k = bits.min(2 * cur - 8).max(cur + 1) + 2;
            // floor((lo + hi)/2 · 2^k) in integers.
            let (l, h) = (&self.lo, &self.hi);
            let x = ((l.numer() * h.denom() + h.numer() * l.denom()) << k as usize)
                .div_floor(&((l.denom() * h.denom()) << 1usize));
            let (v, dv) = eval(&x, k);
            if dv.is_zero() {
                if left == 0 {
                    return false;
                }
                left -= 1;
                self.bisect();
                continue;
            }
            // p/p' in units of 2^-k is v/dv.
            let xn = &x - v.div_floor(&dv);
            let (a, b) = (&xn - BigInt::from(2), &xn + BigInt::from(2));
            let (ra, rb) = (dyadic(a.clone(), k), dyadic(b.clone(), k));
            let ok = qle(&self.lo, &ra)
                && qle(&rb, &self.hi)
                && sgn(&eval(&a, k).0) * sgn(&eval(&b, k).0) < 0;
            if ok {
                self.lo = ra;
                self.hi = rb;
            } else {
                failures += 1;
                if left == 0 {
                    return false;
                }
                left -= 1;
                self.bisect();
            }
        }
        true
    }

    /// The `f64` nearest to the root (ties to even), decided on the exact
    /// interval: refined until both ends round alike; a root exactly halfway
    /// between two doubles is rational and is found exactly.
    pub fn to_f64(&self) -> f64 {
        let mut r = self.clone();
        loop {
            if r.is_rational() {
                return rational_to_f64(&r.lo);
            }
            let (fl, fh) = (rational_to_f64(&r.lo), rational_to_f64(&r.hi));
            if fl == fh {
                return fl;
            }
            // Split at the rounding boundary between neighbouring doubles when
            // there is one, else halve.
            let next = next_up(fl);
            if fh == next && fl.is_finite() && fh.is_finite() {
                let mid = (f64_rational(fl) + f64_rational(fh)) / two();
                if qlt(&r.lo, &mid) && qlt(&mid, &r.hi) {
                    r.split_at(mid);
                    continue;
                }
            }
            r.bisect();
        }
    }

    /// The exact sign of `q(root)` for a rational polynomial `q`: zero is
    /// decided by `gcd(q, poly)` having the root (a Sturm count on the
    /// isolating interval), the sign of a nonzero value on a refined
    /// enclosure.
    pub fn sign_of(&self, q: &Poly) -> i8 {
        if self.is_rational() {
            let v = q.eval(&self.lo);
            return sign(&v);
        }
        let g = q.gcd(&self.poly);
        if g.degree().unwrap_or(0) > 0 && count_roots(&g.sturm(), &self.lo, &self.hi) == 1 {
            return 0;
        }
        let mut r = self.clone();
        loop {
            let (lo, hi) = q.eval_interval(&r.lo, &r.hi);
            if lo.is_positive() {
                return 1;
            }
            if hi.is_negative() {
                return -1;
            }
            r.bisect();
            if r.is_rational() {
                return sign(&q.eval(&r.lo));
            }
        }
    }
}

pub fn sign(v: &BigRational) -> i8 {
    if v.is_positive() {
        1
    } else if v.is_negative() {
        -1
    } else {
        0
    }
}

/// The exact rational value of a finite double.
pub fn f64_rational(x: f64) -> BigRational {
    crate::rounding::f64_to_rational(x).expect("finite")
}

/// The next double above `x` (for finite `x`).
pub fn next_up(x: f64) -> f64 {
    if x.is_nan() || x == f64::INFINITY {
        return x;
    }
    if x == 0.0 {
        return f64::from_bits(1);
    }
    let b = x.to_bits();
    if x > 0.0 {
        f64::from_bits(b + 1)
    } else {
        f64::from_bits(b - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64, d: i64) -> BigRational {
        BigRational::new(n.into(), d.into())
    }

    #[test]
    fn sqrt2_rounds_correctly() {
        let r = RealRoot::new(&Poly::from_ints(&[-2, 0, 1]), q(1, 1), q(2, 1)).unwrap();
        assert_eq!(r.to_f64(), std::f64::consts::SQRT_2);
        let all = RealRoot::isolate(&Poly::from_ints(&[-2, 0, 1]), &q(-2, 1), &q(2, 1));
        assert_eq!(all.len(), 2);
        assert_eq!(all[0].to_f64(), -std::f64::consts::SQRT_2);
    }

    #[test]
    fn rational_roots_and_ties_are_exact() {
        // 2x − 1 − 2^-53: the root 1/2 + 2^-54 is a tie between 1/2 and
        // 1/2 + 2^-53; ties to even gives 1/2.
        let t = BigRational::new(BigInt::one(), BigInt::one() << 54u32);
        let root = q(1, 2) + t;
        let p = Poly(vec![-root.clone(), BigRational::one()]).mul(&Poly::from_ints(&[-3, 0, 1]));
        let r = RealRoot::new(&p, q(0, 1), q(1, 1)).unwrap();
        assert_eq!(r.to_f64(), 0.5);
        assert_eq!(r.sign_of(&Poly(vec![-root, BigRational::one()])), 0);
    }

    #[test]
    fn signs_are_exact() {
        let r = RealRoot::new(&Poly::from_ints(&[-2, 0, 1]), q(1, 1), q(2, 1)).unwrap();
        assert_eq!(r.sign_of(&Poly::from_ints(&[-2, 0, 1])), 0);
        assert_eq!(r.sign_of(&Poly::from_ints(&[-4, 0, 0, 0, 1])), 0);
        // √2 − 1.41421356 > 0
        assert_eq!(r.sign_of(&Poly(vec![-q(141421356, 100000000), q(1, 1)])), 1);
    }
}
