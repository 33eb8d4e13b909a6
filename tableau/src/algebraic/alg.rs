//! General real algebraic numbers: polynomials with rational coefficients in
//! finitely many real roots `α₁, …, αₖ` (each a [`RealRoot`] of its own
//! squarefree polynomial `pₖ`).
//!
//! An [`Alg`] is kept reduced modulo every `pₖ(xₖ)`, i.e. as an element of
//! the algebra `A = Q[x₁, …, xₖ]/(p₁(x₁), …, pₖ(xₖ))`, a product of fields
//! (its points are all tuples of conjugates). The number it stands for is its
//! value at the one point `(α₁, …, αₖ)`. Equality in `A` implies equality of
//! the numbers but not conversely, so the zero test does not stop there:
//!
//! * in one root, `e(α) = 0` exactly when `gcd(e, p)` has a root in `α`'s
//!   isolating interval (a Sturm count);
//! * in several roots, scale each root to an algebraic integer
//!   `x̃ₖ = Lₖαₖ` (root of the monic integer polynomial `Lₖ^d pₖ(x/Lₖ)`, every
//!   complex root bounded by `Mₖ`, Cauchy's bound) and `e` to
//!   `γ = Den·e(α) = Σ nₘ x̃ᵐ` with integers `nₘ`. Then `γ` is an algebraic
//!   integer of degree at most `n = ∏ deg pₖ` whose conjugates are bounded by
//!   `M = Σ |nₘ| ∏ Mₖ^{mₖ}`; if `γ ≠ 0` its norm is a nonzero integer, so
//!   `|γ| ≥ M^{−(n−1)}`. A certified enclosure of `γ` inside
//!   `(−M^{−(n−1)}, M^{−(n−1)})` therefore proves `γ = 0`, and one that
//!   excludes 0 proves `γ ≠ 0`; refining the roots (Newton steps certified by
//!   sign changes) makes one of the two happen.
//!
//! This decides zero completely, for any number of roots, within the budget
//! [`MAX_ZERO_TEST_BITS`] on the precision the bound asks for.

use std::collections::BTreeMap;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

use super::poly::{Poly, count_roots};
use super::root::{RealRoot, f64_rational, next_up, sign};
use crate::budget::BeyondBudget;
use crate::number::rational_to_f64;

/// The most bits of precision (`(n − 1)·log₂ M`, see the module docs) a
/// zero test may need; above it the test is refused rather than run long.
pub const MAX_ZERO_TEST_BITS: u64 = 1 << 18;

/// An exponent vector, trailing zeros trimmed.
type Mono = Vec<u32>;

/// A polynomial in the roots of a [`Field`]; see the [module docs](self).
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Alg {
    terms: BTreeMap<Mono, BigRational>,
}

/// The roots the numbers are built from; variable `k` is `roots[k]`.
#[derive(Clone, Debug, Default)]
pub struct Field {
    pub roots: Vec<RealRoot>,
    /// Names for messages, one per root.
    pub names: Vec<String>,
    /// Refined copies of the roots (narrower intervals), kept between tests.
    refined: std::cell::RefCell<BTreeMap<usize, RealRoot>>,
}

fn trim(mut m: Mono) -> Mono {
    while m.last() == Some(&0) {
        m.pop();
    }
    m
}

impl Alg {
    pub fn zero() -> Alg {
        Alg::default()
    }

    pub fn rational(r: BigRational) -> Alg {
        let mut terms = BTreeMap::new();
        if !r.is_zero() {
            terms.insert(Vec::new(), r);
        }
        Alg { terms }
    }

    pub fn int(n: i64) -> Alg {
        Alg::rational(BigRational::from_integer(BigInt::from(n)))
    }

    /// `c · ∏ x_k^e` for `(k, e)` in `exps`.
    pub fn monomial(c: BigRational, exps: &[(usize, u32)]) -> Alg {
        let width = exps.iter().map(|&(k, _)| k + 1).max().unwrap_or(0);
        let mut m = vec![0; width];
        for &(k, e) in exps {
            m[k] += e;
        }
        let mut a = Alg::zero();
        a.add_term(m, c);
        a
    }

    /// Zero in the algebra (sufficient, not necessary, for the value zero).
    pub fn is_zero_poly(&self) -> bool {
        self.terms.is_empty()
    }

    pub fn as_rational(&self) -> Option<BigRational> {
        match self.terms.len() {
            0 => Some(BigRational::zero()),
            1 => self.terms.get(&Vec::new()).cloned(),
            _ => None,
        }
    }

    /// The terms: exponent vectors (trailing zeros trimmed) and coefficients.
    pub fn terms(&self) -> impl Iterator<Item = (&Vec<u32>, &BigRational)> {
        self.terms.iter()
    }

    /// The variables that occur.
    pub fn support(&self) -> Vec<usize> {
        let mut v: Vec<usize> = Vec::new();
        for m in self.terms.keys() {
            for (k, &e) in m.iter().enumerate() {
                if e > 0 && !v.contains(&k) {
                    v.push(k);
                }
            }
        }
        v.sort();
        v
    }

    fn add_term(&mut self, m: Mono, c: BigRational) {
        if c.is_zero() {
            return;
        }
        let m = trim(m);
        let e = self
            .terms
            .entry(m.clone())
            .or_insert_with(BigRational::zero);
        *e += c;
        if e.is_zero() {
            self.terms.remove(&m);
        }
    }

    pub fn add(&self, o: &Alg) -> Alg {
        let mut r = self.clone();
        for (m, c) in &o.terms {
            r.add_term(m.clone(), c.clone());
        }
        r
    }

    pub fn neg(&self) -> Alg {
        Alg {
            terms: self.terms.iter().map(|(m, c)| (m.clone(), -c)).collect(),
        }
    }

    pub fn sub(&self, o: &Alg) -> Alg {
        self.add(&o.neg())
    }

    pub fn scale(&self, r: &BigRational) -> Alg {
        if r.is_zero() {
            return Alg::zero();
        }
        Alg {
            terms: self.terms.iter().map(|(m, c)| (m.clone(), c * r)).collect(),
        }
    }

    /// The univariate polynomial in variable `k`, if only `k` occurs.
    fn univariate(&self, k: usize) -> Option<Poly> {
        let mut v = Vec::new();
        for (m, c) in &self.terms {
            for (j, &e) in m.iter().enumerate() {
                if j != k && e > 0 {
                    return None;
                }
            }
            let e = m.get(k).copied().unwrap_or(0) as usize;
            if v.len() <= e {
                v.resize(e + 1, BigRational::zero());
            }
            v[e] += c;
        }
        Some(Poly(v).trim())
    }

    fn from_univariate(p: &Poly, k: usize) -> Alg {
        let mut r = Alg::zero();
        for (e, c) in p.0.iter().enumerate() {
            let mut m = vec![0; k + 1];
            m[k] = e as u32;
            r.add_term(m, c.clone());
        }
        r
    }
}

impl Field {
    /// Add a root; returns its variable.
    pub fn push(&mut self, root: RealRoot, name: impl Into<String>) -> Alg {
        // The same root given twice is one variable.
        if let Some(k) = self
            .roots
            .iter()
            .position(|r| r.poly == root.poly && r.lo == root.lo && r.hi == root.hi)
        {
            return self.var(k);
        }
        self.roots.push(root);
        self.names.push(name.into());
        self.var(self.roots.len() - 1)
    }

    pub fn var(&self, k: usize) -> Alg {
        let r = &self.roots[k];
        if r.is_rational() {
            return Alg::rational(r.lo.clone());
        }
        let mut m = vec![0; k + 1];
        m[k] = 1;
        let mut a = Alg::zero();
        a.add_term(m, BigRational::one());
        self.reduce(&a)
    }

    /// Reduce modulo every `pₖ(xₖ)`.
    pub fn reduce(&self, a: &Alg) -> Alg {
        let mut cur = a.clone();
        for (k, root) in self.roots.iter().enumerate() {
            // A rational root is its value: reduce modulo x − r.
            let linear;
            let poly = if root.is_rational() {
                linear = Poly(vec![-root.lo.clone(), BigRational::one()]);
                &linear
            } else {
                &root.poly
            };
            let d = poly.degree().unwrap_or(0) as u32;
            if !cur
                .terms
                .keys()
                .any(|m| m.get(k).copied().unwrap_or(0) >= d)
            {
                continue;
            }
            // xₖ^d = −Σ_{j<d} p_j xₖ^j (p monic), applied from the top power down.
            let mut out = Alg::zero();
            let mut pending: Vec<(Mono, BigRational)> = cur.terms.into_iter().collect();
            while let Some((m, c)) = pending.pop() {
                let e = m.get(k).copied().unwrap_or(0);
                if e < d {
                    out.add_term(m, c);
                    continue;
                }
                for (j, pj) in poly.0.iter().enumerate().take(d as usize) {
                    if pj.is_zero() {
                        continue;
                    }
                    let mut m2 = m.clone();
                    m2[k] = e - d + j as u32;
                    pending.push((m2, -(&c * pj)));
                }
            }
            cur = out;
        }
        cur
    }

    pub fn mul(&self, a: &Alg, b: &Alg) -> Alg {
        let mut r = Alg::zero();
        for (ma, ca) in &a.terms {
            for (mb, cb) in &b.terms {
                let n = ma.len().max(mb.len());
                let m: Mono = (0..n)
                    .map(|i| ma.get(i).copied().unwrap_or(0) + mb.get(i).copied().unwrap_or(0))
                    .collect();
                r.add_term(m, ca * cb);
            }
        }
        self.reduce(&r)
    }

    pub fn pow(&self, a: &Alg, k: u32) -> Alg {
        let mut r = Alg::int(1);
        let mut base = a.clone();
        let mut k = k;
        while k > 0 {
            if k & 1 == 1 {
                r = self.mul(&r, &base);
            }
            base = self.mul(&base, &base);
            k >>= 1;
        }
        r
    }

    /// `1/a`. Division by an expression in at most one root is supported:
    /// when `a` vanishes at a conjugate of that root but not at the root
    /// itself, the root's polynomial is replaced by the factor that keeps the
    /// root (dynamic evaluation), which leaves every number's value as it
    /// was. Division by an expression in two or more roots is refused.
    pub fn inverse(&mut self, a: &Alg) -> Result<Alg, String> {
        let a = self.reduce(a);
        if let Some(r) = a.as_rational() {
            if r.is_zero() {
                return Err("division by zero".into());
            }
            return Ok(Alg::rational(r.recip()));
        }
        let sup = a.support();
        if sup.len() > 1 {
            return Err(format!(
                "division by an expression in {} roots ({}) is not supported: write the entry as a polynomial in the roots, or divide by an expression in one root",
                sup.len(),
                sup.iter()
                    .map(|&k| self.names[k].as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        let k = sup[0];
        let p = a.univariate(k).expect("one variable");
        let root = &self.roots[k];
        let g = p.gcd(&root.poly);
        if g.degree().unwrap_or(0) > 0 {
            if count_roots(&g.sturm(), &root.lo, &root.hi) == 1 {
                return Err("division by zero (the divisor vanishes exactly)".into());
            }
            let factor = root.poly.divrem(&g).0.monic();
            let new = RealRoot::new(&factor, root.lo.clone(), root.hi.clone())
                .expect("the root stays in its interval");
            self.roots[k] = new;
            self.refined.borrow_mut().remove(&k);
        }
        let inv = p
            .rem(&self.roots[k].poly)
            .inverse_mod(&self.roots[k].poly)
            .expect("coprime after splitting");
        Ok(Alg::from_univariate(&inv, k))
    }

    /// Root `k` refined to width at most `2^-bits` (cached).
    fn root_at(&self, k: usize, bits: u64) -> RealRoot {
        let mut cache = self.refined.borrow_mut();
        let r = cache.entry(k).or_insert_with(|| self.roots[k].clone());
        let eps = BigRational::new(BigInt::one(), BigInt::one() << bits);
        if r.width() > eps {
            r.refine_to(bits);
        }
        r.clone()
    }

    /// A certified enclosure of the value, with the roots refined to
    /// `2^-bits`. The root intervals are widened outward to dyadic endpoints
    /// and the sum is taken in integers over one common denominator.
    fn enclose(&self, a: &Alg, bits: u64) -> (BigRational, BigRational) {
        let (lo, hi, d) = self.enclose_int(a, bits);
        (BigRational::new(lo, d.clone()), BigRational::new(hi, d))
    }

    /// [`Self::enclose`] as `(lo, hi, den)`: the value lies in
    /// `[lo/den, hi/den]`, `den > 0`, nothing normalised.
    fn enclose_int(&self, a: &Alg, bits: u64) -> (BigInt, BigInt, BigInt) {
        use num_integer::Integer;
        let sup = a.support();
        let prec = bits + 16;
        let scale = BigRational::from_integer(BigInt::one() << prec);
        let ints: BTreeMap<usize, (BigInt, BigInt)> = sup
            .iter()
            .map(|&k| {
                let r = self.root_at(k, bits);
                let lo = (&r.lo * &scale).floor().to_integer();
                let hi = (&r.hi * &scale).ceil().to_integer();
                (k, (lo, hi))
            })
            .collect();
        let mut den = BigInt::one();
        let mut maxdeg = 0u64;
        for (m, c) in &a.terms {
            den = den.lcm(c.denom());
            maxdeg = maxdeg.max(m.iter().map(|&e| e as u64).sum());
        }
        let mut lo = BigInt::zero();
        let mut hi = BigInt::zero();
        for (m, c) in &a.terms {
            let n = c.numer() * (&den / c.denom());
            let (mut tl, mut th) = (BigInt::one(), BigInt::one());
            let mut deg = 0u64;
            for (k, &e) in m.iter().enumerate() {
                for _ in 0..e {
                    let (l, h) = &ints[&k];
                    let ps = [&tl * l, &tl * h, &th * l, &th * h];
                    tl = ps.iter().min().expect("four").clone();
                    th = ps.iter().max().expect("four").clone();
                    deg += 1;
                }
            }
            let shift = (prec * (maxdeg - deg)) as usize;
            let (a1, a2) = (&n * &tl, &n * &th);
            let (l, h) = if a1 <= a2 { (a1, a2) } else { (a2, a1) };
            lo += l << shift;
            hi += h << shift;
        }
        let d = den * (BigInt::one() << (prec * maxdeg) as usize);
        (lo, hi, d)
    }

    /// `(Den, need)`: `γ = Den·e(α)` is an algebraic integer, zero exactly
    /// when `|γ| < 2^-need` (see the [module docs](self)).
    fn zero_bound(&self, a: &Alg) -> (BigRational, u64) {
        use num_integer::Integer;
        let sup = a.support();
        let mut scale: BTreeMap<usize, (BigInt, BigInt)> = BTreeMap::new(); // L, M
        let mut n: u64 = 1;
        for &k in &sup {
            let p = &self.roots[k].poly;
            let d = p.degree().unwrap_or(1);
            n = n.saturating_mul(d as u64);
            let mut l = BigInt::one();
            for c in &p.0 {
                l = l.lcm(c.denom());
            }
            let mut m = BigInt::zero();
            for (j, c) in p.0.iter().enumerate().take(d) {
                let v =
                    (c * BigRational::from_integer(num_traits::pow(l.clone(), d - j))).to_integer();
                let v = if v.is_negative() { -v } else { v };
                if v > m {
                    m = v;
                }
            }
            scale.insert(k, (l, m + BigInt::one()));
        }
        // c'ₘ = cₘ / ∏ Lₖ^{mₖ}; Den = lcm of their denominators.
        let mut coeffs = Vec::new();
        let mut den = BigInt::one();
        for (m, c) in &a.terms {
            let mut lp = BigInt::one();
            let mut mp = BigInt::one();
            for (k, &e) in m.iter().enumerate() {
                if e > 0 {
                    let (l, mk) = &scale[&k];
                    lp *= num_traits::pow(l.clone(), e as usize);
                    mp *= num_traits::pow(mk.clone(), e as usize);
                }
            }
            let cp = c / BigRational::from_integer(lp);
            den = den.lcm(cp.denom());
            coeffs.push((cp, mp));
        }
        let den_q = BigRational::from_integer(den);
        let mut bound = BigRational::zero();
        for (cp, mp) in coeffs {
            bound += (&cp * &den_q).abs() * BigRational::from_integer(mp);
        }
        let bits = bound.ceil().to_integer().bits().max(1);
        (den_q, (n - 1).saturating_mul(bits) + 1)
    }

    /// Decide exactly whether the value of `a` is zero (see the
    /// [module docs](self)).
    pub fn is_zero(&self, a: &Alg) -> Result<bool, BeyondBudget> {
        let a = self.reduce(a);
        if let Some(r) = a.as_rational() {
            return Ok(r.is_zero());
        }
        let sup = a.support();
        if sup.len() == 1 {
            let k = sup[0];
            let p = a.univariate(k).expect("one variable");
            return Ok(self.roots[k].sign_of(&p) == 0);
        }
        for bits in [64, 128, 256] {
            let (lo, hi) = self.enclose(&a, bits);
            if lo.is_positive() || hi.is_negative() {
                return Ok(false);
            }
        }
        let (den, need) = self.zero_bound(&a);
        if need > MAX_ZERO_TEST_BITS {
            return Err(BeyondBudget(format!(
                "deciding whether an expression in {} roots ({}) is zero needs {need} bits of precision, beyond the budget of {MAX_ZERO_TEST_BITS} (tableau::algebraic::alg::MAX_ZERO_TEST_BITS)",
                sup.len(),
                sup.iter()
                    .map(|&k| self.names[k].as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
        // |γ| = |Den·e(α)| < 2^-need, i.e. |x|·Den·2^need < d for x = lo, hi.
        let dscale = den.to_integer() << (need as usize);
        let mut bits = need + 128;
        loop {
            let (lo, hi, d) = self.enclose_int(&a, bits);
            if lo.is_positive() || hi.is_negative() {
                return Ok(false);
            }
            if (lo.abs() * &dscale) < d && (hi.abs() * &dscale) < d {
                return Ok(true);
            }
            bits = bits.saturating_mul(2);
        }
    }

    /// The exact sign of the value.
    pub fn sign(&self, a: &Alg) -> Result<i8, BeyondBudget> {
        let a = self.reduce(a);
        if let Some(r) = a.as_rational() {
            return Ok(sign(&r));
        }
        let mut bits = 64u64;
        let mut tested = false;
        loop {
            let (lo, hi) = self.enclose(&a, bits);
            if lo.is_positive() {
                return Ok(1);
            }
            if hi.is_negative() {
                return Ok(-1);
            }
            if bits >= 256 && !tested {
                if self.is_zero(&a)? {
                    return Ok(0);
                }
                tested = true;
            }
            bits *= 2;
        }
    }

    /// The `f64` nearest to the value (ties to even), decided on certified
    /// enclosures; a value that is zero, or exactly halfway between two
    /// doubles, is detected by an exact zero test.
    pub fn to_f64(&self, a: &Alg) -> Result<f64, BeyondBudget> {
        let a = self.reduce(a);
        if let Some(r) = a.as_rational() {
            return Ok(rational_to_f64(&r));
        }
        let mut bits = 96u64;
        let mut zero_tested = false;
        let mut tested: Option<BigRational> = None;
        loop {
            let (lo, hi) = self.enclose(&a, bits);
            let (fl, fh) = (rational_to_f64(&lo), rational_to_f64(&hi));
            if fl == fh {
                return Ok(fl);
            }
            if bits >= 256 {
                if !zero_tested {
                    if self.is_zero(&a)? {
                        return Ok(0.0);
                    }
                    zero_tested = true;
                }
                if fh == next_up(fl) && fl.is_finite() && fh.is_finite() {
                    let mid =
                        (f64_rational(fl) + f64_rational(fh)) / BigRational::from_integer(2.into());
                    if lo <= mid && mid <= hi && tested.as_ref() != Some(&mid) {
                        if self.is_zero(&a.sub(&Alg::rational(mid.clone())))? {
                            return Ok(rational_to_f64(&mid));
                        }
                        tested = Some(mid);
                    }
                }
            }
            bits *= 2;
        }
    }

    /// The value to about 17 significant digits, for messages; exact zero is
    /// `0`.
    pub fn describe(&self, a: &Alg) -> String {
        match self.reduce(a).as_rational() {
            Some(r) => r.to_string(),
            None => match self.to_f64(a) {
                Ok(x) => format!("≈ {x:e}"),
                Err(_) => "(beyond budget)".into(),
            },
        }
    }
}

/// `sign(x)` for a rational, re-exported for callers.
pub fn rational_sign(x: &BigRational) -> i8 {
    sign(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64, d: i64) -> BigRational {
        BigRational::new(n.into(), d.into())
    }

    #[test]
    fn zero_only_at_the_point() {
        // α = √2, β = −√2 as roots of the same polynomial: α + β = 0 is false
        // in the algebra but true at the point.
        let p = Poly::from_ints(&[-2, 0, 1]);
        let mut f = Field::default();
        let a = f.push(RealRoot::new(&p, q(1, 1), q(2, 1)).unwrap(), "a");
        let b = f.push(RealRoot::new(&p, q(-2, 1), q(-1, 1)).unwrap(), "b");
        let s = a.add(&b);
        assert!(!s.is_zero_poly());
        assert!(f.is_zero(&s).unwrap());
        let d = a.sub(&b);
        assert!(!f.is_zero(&d).unwrap());
        assert_eq!(f.sign(&d).unwrap(), 1);
        assert_eq!(f.to_f64(&d).unwrap(), 2.0 * std::f64::consts::SQRT_2);
    }
}
