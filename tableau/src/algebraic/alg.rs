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
//! [`MAX_ZERO_TEST_BITS`] on the precision the bound asks for and
//! [`MAX_ZERO_TEST_WORK`] on the work (estimated before it is done).
//!
//! Two exact shortcuts come first. Where the roots include every root of
//! one polynomial (a *complete family of conjugates*, e.g. the nodes of a
//! collocation table), sums over the family are replaced by their values
//! through the power sums ([`Field::collapse`]): `Σᵢ bᵢcᵢᵏ` becomes a
//! rational and a row sum `Σⱼ aᵢⱼ` a polynomial in `cᵢ`. Two distinct
//! roots of one polynomial are reduced modulo its divided difference, which
//! vanishes there, and an element zero on every pair of distinct roots
//! reduces to the zero polynomial.
//!
//! Rationals are compared by cross multiplication ([`super::poly::qcmp`]),
//! never by `num-rational`'s `Ord`, which recurses once per shared partial
//! quotient of the continued fractions and overflowed the stack on numbers
//! agreeing to 100 000 bits; long dyadic numbers are built without a gcd.

use std::collections::BTreeMap;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

use super::poly::{Poly, count_roots, qeq, qle};
use super::root::{RealRoot, ceil_scaled, f64_rational, floor_scaled, next_up, sign};
use crate::budget::BeyondBudget;
use crate::number::rational_to_f64;

pub use crate::budget::{MAX_ALG_TERMS, MAX_ANALYSIS_WORK, MAX_ZERO_TEST_BITS, MAX_ZERO_TEST_WORK};

/// An exponent vector, trailing zeros trimmed.
type Mono = Vec<u32>;

/// A polynomial in the roots of a [`Field`]; see the [module docs](self).
#[derive(Clone, Debug, Default)]
pub struct Alg {
    terms: BTreeMap<Mono, BigRational>,
}

/// Equal as polynomials (coefficients compared with [`qeq`]).
impl PartialEq for Alg {
    fn eq(&self, o: &Alg) -> bool {
        self.terms.len() == o.terms.len()
            && self
                .terms
                .iter()
                .zip(&o.terms)
                .all(|((ma, ca), (mb, cb))| ma == mb && qeq(ca, cb))
    }
}

impl Eq for Alg {}

/// The roots the numbers are built from; variable `k` is `roots[k]`.
#[derive(Clone, Debug, Default)]
pub struct Field {
    pub roots: Vec<RealRoot>,
    /// Names for messages, one per root.
    pub names: Vec<String>,
    /// Refined copies of the roots (narrower intervals), kept between tests.
    refined: std::cell::RefCell<BTreeMap<usize, RealRoot>>,
    /// Work spent on enclosures and refinements (see [`work_of_enclosure`]),
    /// and the limit on it for the whole field (`None`: only the per-test
    /// limit [`MAX_ZERO_TEST_WORK`] applies).
    spent: std::cell::Cell<u64>,
    work_limit: Option<u64>,
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

/// Words (64 bits) of a number of `bits` bits.
fn words(bits: u64) -> u64 {
    bits / 64 + 1
}

/// The estimated word products of multiplying an `x`-word by a `y`-word
/// number: schoolbook below 32 words, Karatsuba's `n^1.585` above (what
/// `num-bigint` does, within a small factor).
pub fn mul_work(x: u64, y: u64) -> u64 {
    let (lo, hi) = if x <= y { (x, y) } else { (y, x) };
    if lo <= 32 {
        return lo.saturating_mul(hi);
    }
    let k = (lo as f64).powf(1.585);
    ((hi as f64 / lo as f64) * k).min(u64::MAX as f64 / 4.0) as u64
}

/// The bits of a rational (numerator and denominator).
fn qbits(c: &BigRational) -> u64 {
    c.numer().bits() + c.denom().bits()
}

/// The estimated work of [`Field`]'s certified enclosure of an element with
/// `terms` terms of total degree at most `deg` and coefficients of at most
/// `cbits` bits, in roots of degrees `root_degrees`, at precision `bits`:
/// refining every root there (certified Newton steps: four evaluations of a
/// degree-`d` polynomial at `bits`-bit points per step, the last step
/// dominating a doubling sequence) and multiplying out every term in
/// integers of up to `bits · deg` bits.
pub fn work_of_enclosure(terms: u64, deg: u64, cbits: u64, root_degrees: &[u64], bits: u64) -> u64 {
    let w = words(bits);
    let mut work: u64 = 0;
    for &d in root_degrees {
        let eval = d.saturating_mul(mul_work(w.saturating_mul(d), w));
        work = work.saturating_add(eval.saturating_mul(8));
    }
    let mut per_term: u64 = 0;
    for t in 1..=deg.max(1) {
        per_term = per_term.saturating_add(mul_work(w.saturating_mul(t), w).saturating_mul(4));
    }
    per_term = per_term.saturating_add(mul_work(w.saturating_mul(deg.max(1)), words(cbits)) * 2);
    // Calibrated against measured times: the refinement's bisections and
    // Sturm counts, and the allocation of the long products, cost about three
    // times the products counted above.
    work.saturating_add(per_term.saturating_mul(terms))
        .saturating_mul(3)
}

/// The estimated work of isolating a root of `p`: its squarefree part and
/// Sturm sequence, two remainder sequences (see [`Field`]'s gcd budget).
pub fn root_work(p: &Poly) -> u64 {
    let d = p.0.len() as u64;
    let b = p.0.iter().map(qbits).max().unwrap_or(0);
    Field::gcd_work(d, b).saturating_mul(2)
}

/// The estimated work of isolating the root of `p` in `(lo, hi]` and
/// refining it to width `2^-64` by bisection ([`root_work`] plus one Sturm
/// count per halving: the interval is first clipped to Cauchy's bound
/// `2^cauchy`, and each count evaluates about `deg²` coefficients of up to
/// `2·deg·bits` bits at points of up to `cauchy + 64` bits).
pub fn isolation_work(p: &Poly, lo: &BigRational, hi: &BigRational) -> u64 {
    let d = p.0.len() as u64;
    let b = p.0.iter().map(qbits).max().unwrap_or(0);
    let cauchy =
        p.0.iter()
            .map(|c| c.numer().bits() + c.denom().bits())
            .max()
            .unwrap_or(0)
            + 2;
    let point = words(cauchy + 64 + qbits(lo) + qbits(hi));
    let coef = words(2u64.saturating_mul(d).saturating_mul(b + 64));
    let halvings = cauchy + 64;
    let count = d.saturating_mul(d).saturating_mul(mul_work(coef, point));
    root_work(p).saturating_add(halvings.saturating_mul(count))
}

fn names(f: &Field, sup: &[usize]) -> String {
    sup.iter()
        .map(|&k| f.names.get(k).map_or("?", String::as_str))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The largest degree of the root a nested radical's radicand may live in.
pub const MAX_NESTED_DEGREE: usize = 16;

/// The most bits of a coefficient of a nested radical's radicand (the
/// characteristic polynomial's coefficients grow to about
/// `MAX_NESTED_DEGREE` times as many).
pub const MAX_NESTED_BITS: u64 = 4096;

/// The characteristic polynomial of multiplication by `e(x)` in
/// `Q[x]/(p)` (`p` monic of degree `d`), by Faddeev–LeVerrier in exact
/// rationals: `d³` products per step, `d` steps.
#[allow(clippy::needless_range_loop)] // matrix code indexes as the formula does
fn charpoly_of_multiplication(e: &Poly, p: &Poly) -> Poly {
    let d = p.degree().unwrap_or(0);
    // Column j: x^j·e mod p.
    let mut m = vec![vec![BigRational::zero(); d]; d];
    let mut col = e.rem(p);
    for j in 0..d {
        for i in 0..d {
            m[i][j] = col.coeff(i);
        }
        col = col.mul(&Poly::x()).rem(p);
    }
    let mul = |a: &Vec<Vec<BigRational>>, b: &Vec<Vec<BigRational>>| {
        let mut c = vec![vec![BigRational::zero(); d]; d];
        for i in 0..d {
            for k in 0..d {
                if a[i][k].is_zero() {
                    continue;
                }
                for j in 0..d {
                    c[i][j] += &a[i][k] * &b[k][j];
                }
            }
        }
        c
    };
    // c[d] = 1; M_k = A·M_{k−1} + c_{d−k+1} I; c_{d−k} = −tr(A·M_k)/k.
    let mut c = vec![BigRational::zero(); d + 1];
    c[d] = BigRational::one();
    let mut mk = vec![vec![BigRational::zero(); d]; d];
    for k in 1..=d {
        let mut next = mul(&m, &mk);
        for (i, row) in next.iter_mut().enumerate() {
            row[i] += &c[d - k + 1];
        }
        mk = next;
        let am = mul(&m, &mk);
        let tr = (0..d).fold(BigRational::zero(), |acc, i| acc + &am[i][i]);
        c[d - k] = -tr / BigRational::from_integer(BigInt::from(k));
    }
    Poly(c).trim()
}

impl Field {
    /// A field whose enclosures together may cost at most `limit` (in the
    /// units of [`MAX_ZERO_TEST_WORK`]); past it every test is refused.
    pub fn with_work_limit(mut self, limit: u64) -> Field {
        self.work_limit = Some(limit);
        self.spent.set(0);
        self
    }

    /// The field with a work limit: its own if it has one, else `limit`.
    pub fn with_default_work_limit(mut self, limit: u64) -> Field {
        if self.work_limit.is_none() {
            self.work_limit = Some(limit);
        }
        self
    }

    /// The work spent so far on enclosures (see [`work_of_enclosure`]).
    pub fn work_spent(&self) -> u64 {
        self.spent.get()
    }

    /// Add a root; returns its variable. A root equal to one already there
    /// (the same polynomial, and the two intervals share it: decided exactly
    /// by a Sturm count on their intersection) is that variable.
    pub fn push(&mut self, root: RealRoot, name: impl Into<String>) -> Alg {
        if let Some(k) = self.roots.iter().position(|r| r.same_root(&root)) {
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

    /// Reduce modulo every `pₖ(xₖ)`: each power `xₖᵉ`, `e ≥ deg pₖ`, is
    /// replaced by its remainder (computed once per exponent and variable).
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
            let top = cur
                .terms
                .keys()
                .map(|m| m.get(k).copied().unwrap_or(0))
                .max()
                .unwrap_or(0);
            if top < d || d == 0 {
                continue;
            }
            // pw[e − d] = xᵉ mod p as d coefficients (p monic).
            let du = d as usize;
            let mut pw: Vec<Vec<BigRational>> = Vec::with_capacity((top - d + 1) as usize);
            let first: Vec<BigRational> = poly.0.iter().take(du).map(|c| -c).collect();
            pw.push(first);
            for _ in d..top {
                let prev = pw.last().expect("nonempty");
                let t = prev[du - 1].clone();
                let mut next = Vec::with_capacity(du);
                for j in 0..du {
                    let lower = if j == 0 {
                        BigRational::zero()
                    } else {
                        prev[j - 1].clone()
                    };
                    next.push(lower - &t * &poly.0[j]);
                }
                pw.push(next);
            }
            let mut out = Alg::zero();
            for (m, c) in std::mem::take(&mut cur.terms) {
                let e = m.get(k).copied().unwrap_or(0);
                if e < d {
                    out.add_term(m, c);
                    continue;
                }
                for (j, r) in pw[(e - d) as usize].iter().enumerate() {
                    if r.is_zero() {
                        continue;
                    }
                    let mut m2 = m.clone();
                    m2[k] = j as u32;
                    out.add_term(m2, &c * r);
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

    /// The estimated work of `a · b`: term products × word products of the
    /// coefficients, plus the reduction (each product term expands into at
    /// most `deg pₖ` terms per variable).
    fn product_work(&self, a: &Alg, b: &Alg) -> u64 {
        let ba = a.terms.values().map(qbits).max().unwrap_or(0);
        let bb = b.terms.values().map(qbits).max().unwrap_or(0);
        let vars = a.support().len().max(b.support().len()) as u64;
        let dmax = self
            .roots
            .iter()
            .map(|r| r.poly.degree().unwrap_or(1) as u64)
            .max()
            .unwrap_or(1);
        let pairs = (a.terms.len() as u64).saturating_mul(b.terms.len() as u64);
        // Each term product also normalises a rational and inserts an
        // exponent vector into a map: measured, about 2000 word products'
        // worth of time.
        pairs
            .saturating_mul(mul_work(words(ba), words(bb)).saturating_add(2000))
            .saturating_mul(1 + vars.min(4) * dmax / 4)
    }

    /// `a · b` within the budgets [`crate::budget::MAX_ALG_PRODUCT_WORK`] (estimated before
    /// it is done) and [`MAX_ALG_TERMS`] (of the result).
    pub fn try_mul(&self, a: &Alg, b: &Alg) -> Result<Alg, BeyondBudget> {
        let work = self.product_work(a, b);
        if work > crate::budget::MAX_ALG_PRODUCT_WORK {
            return Err(BeyondBudget(format!(
                "a product of numbers with {} and {} terms needs about {work} word products, beyond the budget of {} (tableau::budget::MAX_ALG_PRODUCT_WORK)",
                a.terms.len(),
                b.terms.len(),
                crate::budget::MAX_ALG_PRODUCT_WORK
            )));
        }
        self.charge(work)?;
        let r = self.mul(a, b);
        self.check_size(&r)?;
        Ok(r)
    }

    /// Refuse an element with more than [`MAX_ALG_TERMS`] terms or a
    /// coefficient over [`crate::budget::MAX_ENTRY_BITS`] bits.
    pub fn check_size(&self, r: &Alg) -> Result<(), BeyondBudget> {
        if r.terms.len() > MAX_ALG_TERMS {
            return Err(BeyondBudget(format!(
                "a number with {} terms in the roots, beyond the budget of {MAX_ALG_TERMS} (tableau::budget::MAX_ALG_TERMS)",
                r.terms.len()
            )));
        }
        if let Some(b) = r.terms.values().map(qbits).max()
            && b > crate::budget::MAX_ENTRY_BITS
        {
            return Err(BeyondBudget(format!(
                "a coefficient of {b} bits, beyond the budget of {} bits (tableau::budget::MAX_ENTRY_BITS)",
                crate::budget::MAX_ENTRY_BITS
            )));
        }
        Ok(())
    }

    pub fn pow(&self, a: &Alg, k: u32) -> Alg {
        let mut r = Alg::int(1);
        let mut base = a.clone();
        let mut k = k;
        while k > 0 {
            if k & 1 == 1 {
                r = self.mul(&r, &base);
            }
            k >>= 1;
            if k > 0 {
                base = self.mul(&base, &base);
            }
        }
        r
    }

    /// `aᵏ` by repeated squaring, each product within the budgets of
    /// [`Self::try_mul`].
    pub fn try_pow(&self, a: &Alg, k: u32) -> Result<Alg, BeyondBudget> {
        let mut r = Alg::int(1);
        let mut base = a.clone();
        let mut k = k;
        while k > 0 {
            if k & 1 == 1 {
                r = self.try_mul(&r, &base)?;
            }
            k >>= 1;
            if k > 0 {
                base = self.try_mul(&base, &base)?;
            }
        }
        Ok(r)
    }

    /// The estimated work of a gcd of univariate polynomials of degree at
    /// most `d` with coefficients of at most `b` bits over Q (Euclid's
    /// algorithm: about d² operations on numbers of up to 2·d·b bits).
    pub(crate) fn gcd_work(d: u64, b: u64) -> u64 {
        let w = words(2u64.saturating_mul(d + 1).saturating_mul(b + 64));
        // ×4: measured against enclosures, rational remainder sequences
        // (with their gcd normalisations) cost about four times the
        // products counted.
        (d + 1)
            .saturating_mul(d + 1)
            .saturating_mul(mul_work(w, w))
            .saturating_mul(4)
    }

    fn check_gcd(&self, p: &Poly, k: usize) -> Result<(), BeyondBudget> {
        let q = &self.roots[k].poly;
        let d = p.0.len().max(q.0.len()) as u64;
        let b = p.0.iter().chain(&q.0).map(qbits).max().unwrap_or(0);
        let work = Self::gcd_work(d, b);
        if work > MAX_ZERO_TEST_WORK {
            return Err(BeyondBudget(format!(
                "a gcd of polynomials of degree {d} with {b}-bit coefficients (in the root {}) needs about {work} word products, beyond the budget of {MAX_ZERO_TEST_WORK} (tableau::budget::MAX_ZERO_TEST_WORK)",
                names(self, &[k])
            )));
        }
        self.charge(work)
    }

    /// Count `work` against the field's limit (if it has one).
    pub(crate) fn charge(&self, work: u64) -> Result<(), BeyondBudget> {
        let spent = self.spent.get().saturating_add(work);
        if let Some(limit) = self.work_limit
            && spent > limit
        {
            return Err(BeyondBudget(format!(
                "the exact tests of this table together need more than the budget of {limit} word products (tableau::budget::MAX_ANALYSIS_WORK)"
            )));
        }
        self.spent.set(spent);
        Ok(())
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
        if sup.len() != 1 {
            return Err(format!(
                "division by an expression in {} roots ({}) is not supported: write the entry as a polynomial in the roots, or divide by an expression in one root",
                sup.len(),
                names(self, &sup)
            ));
        }
        let k = sup[0];
        let p = a.univariate(k).ok_or("division: not univariate")?;
        self.check_gcd(&p, k).map_err(|e| e.0)?;
        let root = &self.roots[k];
        let g = p.gcd(&root.poly);
        if g.degree().unwrap_or(0) > 0 {
            if count_roots(&g.sturm(), &root.lo, &root.hi) == 1 {
                return Err("division by zero (the divisor vanishes exactly)".into());
            }
            let factor = root.poly.divrem(&g).0.monic();
            let new = RealRoot::new(&factor, root.lo.clone(), root.hi.clone())
                .map_err(|_| "division: the root left its interval".to_string())?;
            self.roots[k] = new;
            self.refined.borrow_mut().remove(&k);
        }
        let inv = p
            .rem(&self.roots[k].poly)
            .inverse_mod(&self.roots[k].poly)
            .ok_or("division: the divisor is not invertible")?;
        Ok(Alg::from_univariate(&inv, k))
    }

    /// Root `k` refined to width at most `2^-bits` (cached).
    ///
    /// Certified Newton steps do nearly all of it; the bisections a
    /// refinement may fall back on (Sturm counts, e.g. for roots closer
    /// together than the interval) are limited to an eighth of
    /// [`MAX_ZERO_TEST_WORK`] (at least 16, at most 256): past them the
    /// interval stays wider and the test that needed it is refused.
    fn root_at(&self, k: usize, bits: u64) -> RealRoot {
        let mut cache = self.refined.borrow_mut();
        let r = cache.entry(k).or_insert_with(|| self.roots[k].clone());
        if r.wider_than(bits) {
            let d = r.poly.0.len() as u64;
            let b = r.poly.0.iter().map(qbits).max().unwrap_or(0);
            // ×64: a Sturm count evaluates in normalised rationals, a gcd
            // per operation (measured: ~2 ms per count for a cubic with
            // 1000-bit coefficients).
            let count = d
                .saturating_mul(d)
                .saturating_mul(mul_work(
                    words(2u64.saturating_mul(d).saturating_mul(b + 64)),
                    words(bits + 64),
                ))
                .saturating_mul(64);
            let allowance = (MAX_ZERO_TEST_WORK / 8 / count.max(1)).clamp(16, 256);
            r.refine_within(bits, allowance);
        }
        r.clone()
    }

    /// A certified enclosure of the value, with the roots refined to
    /// `2^-bits`. The root intervals are widened outward to dyadic endpoints
    /// and the sum is taken in integers over one common denominator.
    fn enclose(&self, a: &Alg, bits: u64) -> Result<(BigRational, BigRational), BeyondBudget> {
        let (lo, hi, d) = self.enclose_int(a, bits)?;
        // Not normalised (a gcd of such long numbers costs more than the
        // enclosure): used only for comparisons by cross multiplication and
        // for rounding, which take any positive denominator.
        Ok((
            BigRational::new_raw(lo, d.clone()),
            BigRational::new_raw(hi, d),
        ))
    }

    /// The estimated work of [`Self::enclose_int`], refused past
    /// [`MAX_ZERO_TEST_WORK`] (and the field's own limit).
    fn check_enclosure(&self, a: &Alg, bits: u64) -> Result<(), BeyondBudget> {
        use num_integer::Integer;
        let sup = a.support();
        let mut den = BigInt::one();
        let mut nbits = 0;
        let mut deg = 0u64;
        for (m, c) in &a.terms {
            den = den.lcm(c.denom());
            nbits = nbits.max(c.numer().bits());
            deg = deg.max(m.iter().map(|&e| e as u64).sum());
        }
        // Roots already refined to this precision (cached) cost nothing.
        let cache = self.refined.borrow();
        let degs: Vec<u64> = sup
            .iter()
            .filter(|&&k| cache.get(&k).is_none_or(|r| r.wider_than(bits)))
            .map(|&k| self.roots[k].poly.degree().unwrap_or(1) as u64)
            .collect();
        drop(cache);
        let work = work_of_enclosure(a.terms.len() as u64, deg, nbits + den.bits(), &degs, bits);
        if work > MAX_ZERO_TEST_WORK {
            return Err(BeyondBudget(format!(
                "an enclosure of an expression with {} terms in {} roots ({}) to {bits} bits needs about {work} word products, beyond the budget of {MAX_ZERO_TEST_WORK} (tableau::budget::MAX_ZERO_TEST_WORK)",
                a.terms.len(),
                sup.len(),
                names(self, &sup)
            )));
        }
        self.charge(work)
    }

    /// [`Self::enclose`] as `(lo, hi, den)`: the value lies in
    /// `[lo/den, hi/den]`, `den > 0`, nothing normalised.
    fn enclose_int(&self, a: &Alg, bits: u64) -> Result<(BigInt, BigInt, BigInt), BeyondBudget> {
        use num_integer::Integer;
        self.check_enclosure(a, bits)?;
        let sup = a.support();
        let prec = bits + 16;
        let ints: BTreeMap<usize, (BigInt, BigInt)> = sup
            .iter()
            .map(|&k| {
                let r = self.root_at(k, bits);
                (k, (floor_scaled(&r.lo, prec), ceil_scaled(&r.hi, prec)))
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
                let Some((l, h)) = ints.get(&k) else {
                    continue;
                };
                for _ in 0..e {
                    let ps = [&tl * l, &tl * h, &th * l, &th * h];
                    let mut mn = &ps[0];
                    let mut mx = &ps[0];
                    for p in &ps[1..] {
                        if p < mn {
                            mn = p;
                        }
                        if p > mx {
                            mx = p;
                        }
                    }
                    (tl, th) = (mn.clone(), mx.clone());
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
        Ok((lo, hi, d))
    }

    /// `(Den, need, bits of M)`: `γ = Den·e(α)` is an algebraic integer,
    /// zero exactly when `|γ| < 2^-need` (see the [module docs](self)).
    fn zero_bound(&self, a: &Alg) -> (BigInt, u64, u64) {
        use num_integer::Integer;
        let sup = a.support();
        let mut scale: BTreeMap<usize, (BigInt, BigInt)> = BTreeMap::new(); // L, M
        let mut n: u64 = 1;
        for &k in &sup {
            let p = &self.roots[k].poly;
            let d = p.degree().unwrap_or(1).max(1);
            n = n.saturating_mul(d as u64);
            let mut l = BigInt::one();
            for c in &p.0 {
                l = l.lcm(c.denom());
            }
            let mut m = BigInt::zero();
            for (j, c) in p.0.iter().enumerate().take(d) {
                let v = (c.numer() * num_traits::pow(l.clone(), d - j)) / c.denom();
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
                if e > 0
                    && let Some((l, mk)) = scale.get(&k)
                {
                    lp *= num_traits::pow(l.clone(), e as usize);
                    mp *= num_traits::pow(mk.clone(), e as usize);
                }
            }
            let cp = c / BigRational::from_integer(lp);
            den = den.lcm(cp.denom());
            coeffs.push((cp, mp));
        }
        let mut bound = BigInt::zero();
        for (cp, mp) in coeffs {
            // |cp·Den| is an integer.
            let v = (cp.numer() * (&den / cp.denom())).abs();
            bound += v * mp;
        }
        let bits = bound.bits().max(1);
        (den, (n - 1).saturating_mul(bits).saturating_add(1), bits)
    }

    /// The real `n`-th root (`n` = 2 or 3) of the value of `a`, an element
    /// in at most one root `α` of a polynomial `p` of degree at most
    /// [`MAX_NESTED_DEGREE`], as a new root: `a(α)` is a root of the
    /// characteristic polynomial `χ` of multiplication by `a` in `Q[x]/(p)`
    /// (Faddeev–LeVerrier, exact), so `y = a(α)^{1/n}` is a root of
    /// `χ(yⁿ)`, picked out by a certified enclosure of `a(α)` (refined until
    /// its `n`-th roots isolate exactly one root of the squarefree part).
    /// This is how nested radicals such as `sqrt(525 + 70*sqrt(30))` are
    /// read. Refused (with the reason) for an element in two or more roots,
    /// a negative radicand of a square root, or beyond the budgets.
    pub fn nth_root(&mut self, a: &Alg, n: u32, name: &str) -> Result<Alg, String> {
        let a = self.collapse(&self.reduce(a));
        if let Some(r) = a.as_rational() {
            // Rational: the caller's rational path.
            return Err(format!(
                "internal: a rational radicand {r} reached nth_root"
            ));
        }
        let sup = a.support();
        if sup.len() != 1 {
            return Err(format!(
                "a nested radical of an expression in {} roots ({}): only radicands in one root are supported; write the number as root(...) in `let`",
                sup.len(),
                names(self, &sup)
            ));
        }
        let k = sup[0];
        let p = self.roots[k].poly.clone();
        let d = p.degree().unwrap_or(0);
        if d > MAX_NESTED_DEGREE {
            return Err(format!(
                "a nested radical over a root of degree {d}, above {MAX_NESTED_DEGREE} (tableau::algebraic::alg::MAX_NESTED_DEGREE)"
            ));
        }
        let e = a.univariate(k).expect("one variable");
        let ebits = e.0.iter().map(qbits).max().unwrap_or(0);
        if ebits > MAX_NESTED_BITS {
            return Err(format!(
                "a nested radical whose radicand has coefficients of {ebits} bits, beyond {MAX_NESTED_BITS} (tableau::algebraic::alg::MAX_NESTED_BITS)"
            ));
        }
        let chi = charpoly_of_multiplication(&e, &p);
        let mut xn = vec![BigRational::zero(); n as usize + 1];
        xn[n as usize] = BigRational::one();
        let r = chi.compose(&Poly(xn)).squarefree();
        if r.degree().unwrap_or(0) > crate::budget::MAX_ROOT_DEGREE {
            return Err(format!(
                "the nested radical's polynomial has degree above {} (tableau::budget::MAX_ROOT_DEGREE)",
                crate::budget::MAX_ROOT_DEGREE
            ));
        }
        let size: u64 = r.0.iter().map(qbits).sum();
        if size > crate::budget::MAX_ROOT_BITS {
            return Err(format!(
                "the nested radical's polynomial has {size} bits of coefficients, beyond {} (tableau::budget::MAX_ROOT_BITS)",
                crate::budget::MAX_ROOT_BITS
            ));
        }
        // Isolation is charged as for the widest interval (as `root(...)`'s).
        let wide = BigRational::one();
        let work = isolation_work(&r, &wide, &wide);
        if work > MAX_ZERO_TEST_WORK {
            return Err(format!(
                "isolating the nested radical's root needs about {work} word products, beyond {MAX_ZERO_TEST_WORK} (tableau::budget::MAX_ZERO_TEST_WORK)"
            ));
        }
        self.charge(work).map_err(|e| e.0)?;
        let sign = self.sign(&a).map_err(|e| e.0)?;
        if n == 2 && sign < 0 {
            return Err(format!("{name}: the square root of a negative number"));
        }
        for bits in [64u64, 128, 256, 512, 1024, 2048, 4096] {
            let (lo, hi) = self.enclose(&a, bits).map_err(|e| e.0)?;
            // Bounds of the n-th roots of |a| at scale 2^bits (floor of the
            // lower, one past the ceiling of the upper).
            let (alo, ahi) = if sign > 0 { (lo, hi) } else { (-hi, -lo) };
            let alo = if alo.is_negative() {
                BigRational::zero()
            } else {
                alo
            };
            let scale = BigInt::one() << (bits as usize * n as usize);
            let lo_i = (alo * BigRational::from_integer(scale.clone()))
                .floor()
                .to_integer();
            let hi_i = (ahi * BigRational::from_integer(scale)).ceil().to_integer();
            let den = BigInt::one() << (bits as usize);
            let l = BigRational::new(lo_i.nth_root(n), den.clone());
            let u = BigRational::new(hi_i.nth_root(n) + BigInt::one() + BigInt::one(), den);
            let (l, u) = if sign > 0 { (l, u) } else { (-u, -l) };
            // (l − 2^-bits, u]: the root lies in [l, u].
            let eps = BigRational::new(BigInt::one(), BigInt::one() << (bits as usize + 1));
            if let Ok(root) = RealRoot::new(&r, &l - &eps, u) {
                return Ok(self.push(root, name));
            }
        }
        Err(format!(
            "{name}: the nested radical's root was not isolated at 4096 bits"
        ))
    }

    /// Zero test of a univariate `a` in root `k`: `gcd(a, pₖ)` has the root.
    fn univariate_zero(&self, a: &Alg, k: usize) -> Result<bool, BeyondBudget> {
        let p = a
            .univariate(k)
            .ok_or_else(|| BeyondBudget("internal: not univariate".into()))?;
        let root = &self.roots[k];
        if root.is_rational() {
            return Ok(p.eval(&root.lo).is_zero());
        }
        self.check_gcd(&p, k)?;
        let g = p.gcd(&root.poly);
        Ok(g.degree().unwrap_or(0) > 0 && count_roots(&g.sturm(), &root.lo, &root.hi) == 1)
    }

    /// Decide exactly whether the value of `a` is zero (see the
    /// [module docs](self)), within [`MAX_ZERO_TEST_BITS`] and
    /// [`MAX_ZERO_TEST_WORK`].
    pub fn is_zero(&self, a: &Alg) -> Result<bool, BeyondBudget> {
        let a = self.collapse(&self.reduce(a));
        if let Some(r) = a.as_rational() {
            return Ok(r.is_zero());
        }
        let sup = a.support();
        if sup.len() == 1 {
            return self.univariate_zero(&a, sup[0]);
        }
        let a = match sup[..] {
            [x, y]
                if !self.roots[x].is_rational()
                    && !self.roots[y].is_rational()
                    && self.roots[x].poly == self.roots[y].poly
                    && !self.roots[x].same_root(&self.roots[y]) =>
            {
                let r = self.reduce_conjugate_pair(&a, x, y);
                if r.is_zero_poly() {
                    return Ok(true);
                }
                r
            }
            _ => a,
        };
        for bits in [64, 128, 256] {
            let (lo, hi, _) = self.enclose_int(&a, bits)?;
            if lo.is_positive() || hi.is_negative() {
                return Ok(false);
            }
        }
        let (den, need, mbits) = self.zero_bound(&a);
        if need > MAX_ZERO_TEST_BITS {
            return Err(BeyondBudget(format!(
                "deciding whether an expression in {} roots ({}) is zero needs {need} bits of precision, beyond the budget of {MAX_ZERO_TEST_BITS} (tableau::budget::MAX_ZERO_TEST_BITS)",
                sup.len(),
                names(self, &sup)
            )));
        }
        // |γ| = |Den·e(α)| < 2^-need, i.e. |x|·Den·2^need < d for x = lo, hi.
        let dscale = den << (need as usize);
        let mut bits = need + mbits + 64;
        for _ in 0..3 {
            let (lo, hi, d) = self.enclose_int(&a, bits)?;
            if lo.is_positive() || hi.is_negative() {
                return Ok(false);
            }
            if (lo.abs() * &dscale) < d && (hi.abs() * &dscale) < d {
                return Ok(true);
            }
            bits = bits.saturating_mul(2);
        }
        Err(BeyondBudget(format!(
            "the enclosure of an expression in {} roots ({}) did not reach 2^-{need} at {bits} bits (tableau::budget::MAX_ZERO_TEST_WORK)",
            sup.len(),
            names(self, &sup)
        )))
    }

    /// The precision at which an enclosure of the nonzero `a` must exclude
    /// 0 (its zero bound plus the size of its conjugates and a margin).
    fn separating_bits(&self, a: &Alg) -> Result<u64, BeyondBudget> {
        let (_, need, mbits) = self.zero_bound(a);
        if need > MAX_ZERO_TEST_BITS {
            return Err(BeyondBudget(format!(
                "separating a number in {} roots from zero needs {need} bits of precision, beyond the budget of {MAX_ZERO_TEST_BITS} (tableau::budget::MAX_ZERO_TEST_BITS)",
                a.support().len()
            )));
        }
        Ok((need + mbits + 64).max(512))
    }

    /// The exact sign of the value.
    pub fn sign(&self, a: &Alg) -> Result<i8, BeyondBudget> {
        let a = self.collapse(&self.reduce(a));
        if let Some(r) = a.as_rational() {
            return Ok(sign(&r));
        }
        for bits in [64u64, 128, 256] {
            let (lo, hi, _) = self.enclose_int(&a, bits)?;
            if lo.is_positive() {
                return Ok(1);
            }
            if hi.is_negative() {
                return Ok(-1);
            }
        }
        if self.is_zero(&a)? {
            return Ok(0);
        }
        let mut bits = self.separating_bits(&a)?;
        for _ in 0..3 {
            let (lo, hi, _) = self.enclose_int(&a, bits)?;
            if lo.is_positive() {
                return Ok(1);
            }
            if hi.is_negative() {
                return Ok(-1);
            }
            bits = bits.saturating_mul(2);
        }
        Err(BeyondBudget(format!(
            "the sign of a nonzero number was not separated at {bits} bits (tableau::budget::MAX_ZERO_TEST_WORK)"
        )))
    }

    /// The `f64` nearest to the value (ties to even), decided on certified
    /// enclosures; a value that is zero, or exactly halfway between two
    /// doubles, is detected by an exact zero test. The precision is bounded:
    /// once the value is known to differ from 0 and from the halfway point
    /// in question, their zero bounds say at which precision the enclosure
    /// must decide.
    pub fn to_f64(&self, a: &Alg) -> Result<f64, BeyondBudget> {
        let a = self.collapse(&self.reduce(a));
        if let Some(r) = a.as_rational() {
            return Ok(rational_to_f64(&r));
        }
        let mut bits = 96u64;
        let mut zero_tested = false;
        let mut tested: Vec<BigRational> = Vec::new();
        let mut cap: u64 = 0;
        loop {
            let (lo, hi) = self.enclose(&a, bits)?;
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
                    cap = cap.max(self.separating_bits(&a)?);
                }
                if fh == next_up(fl) && fl.is_finite() && fh.is_finite() {
                    let mid =
                        (f64_rational(fl) + f64_rational(fh)) / BigRational::from_integer(2.into());
                    if qle(&lo, &mid) && qle(&mid, &hi) && !tested.iter().any(|t| qeq(t, &mid)) {
                        let diff = a.sub(&Alg::rational(mid.clone()));
                        if self.is_zero(&diff)? {
                            return Ok(rational_to_f64(&mid));
                        }
                        cap = cap.max(self.separating_bits(&diff)?);
                        tested.push(mid);
                    }
                }
                if cap > 0 && bits > cap.saturating_mul(4) || tested.len() > 4 {
                    return Err(BeyondBudget(format!(
                        "rounding a number in {} roots to f64 was not decided at {bits} bits (tableau::budget::MAX_ZERO_TEST_WORK)",
                        a.support().len()
                    )));
                }
            }
            bits = bits.saturating_mul(2);
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

    /// `a` reduced modulo the divided difference `Q(x, y) = (P(x) − P(y))/(x − y)`
    /// in `y` (monic of degree `deg P − 1`), for two distinct roots `x`, `y`
    /// of one polynomial `P`: `Q` vanishes there, so the value is unchanged,
    /// and `{P(x), Q(x, y)}` is a Gröbner basis of the algebra of ordered
    /// pairs of distinct roots (see [`super::pair`]), so an element that is
    /// zero there reduces to the zero polynomial.
    fn reduce_conjugate_pair(&self, a: &Alg, x: usize, y: usize) -> Alg {
        let p = &self.roots[x].poly;
        let d = p.degree().unwrap_or(0) as u32;
        if d < 2 {
            return a.clone();
        }
        // y^{d−1} ≡ −Σ_{k<d−1} q_k(x) y^k, q_k(x) = Σ_{m>k} p_m x^{m−1−k}.
        let mut cur = a.clone();
        for _ in 0..4 {
            if !cur
                .terms
                .keys()
                .any(|m| m.get(y).copied().unwrap_or(0) >= d - 1)
            {
                break;
            }
            let mut out = Alg::zero();
            for (m, c) in std::mem::take(&mut cur.terms) {
                let e = m.get(y).copied().unwrap_or(0);
                if e < d - 1 {
                    out.add_term(m, c);
                    continue;
                }
                for k in 0..(d - 1) {
                    for mm in (k + 1)..=d {
                        let pm = p.coeff(mm as usize);
                        if pm.is_zero() {
                            continue;
                        }
                        let mut m2 = m.clone();
                        let w = m2.len().max(x + 1).max(y + 1);
                        m2.resize(w, 0);
                        m2[y] = e - (d - 1) + k;
                        m2[x] += mm - 1 - k;
                        out.add_term(m2, -(&c * &pm));
                    }
                }
            }
            cur = self.reduce(&out);
        }
        cur
    }

    /// The complete families of conjugates: groups of variables that are
    /// all the distinct real roots of one polynomial, as many as its degree
    /// (every root real), with the power sums `pₘ = Σ xᵐ`, `m < degree`.
    fn complete_groups(&self) -> Vec<(Vec<usize>, Vec<BigRational>)> {
        let mut seen = vec![false; self.roots.len()];
        let mut out = Vec::new();
        for k in 0..self.roots.len() {
            if seen[k] || self.roots[k].is_rational() {
                continue;
            }
            let p = &self.roots[k].poly;
            let group: Vec<usize> = (k..self.roots.len())
                .filter(|&j| !self.roots[j].is_rational() && self.roots[j].poly == *p)
                .collect();
            for &j in &group {
                seen[j] = true;
            }
            let d = p.degree().unwrap_or(0);
            if d < 2 || group.len() != d {
                continue;
            }
            let distinct = group.iter().enumerate().all(|(x, &i)| {
                group[x + 1..]
                    .iter()
                    .all(|&j| !self.roots[i].same_root(&self.roots[j]))
            });
            if !distinct {
                continue;
            }
            // Newton: p_m + Σ_{i=1}^{m−1} c_{d−i} p_{m−i} + m c_{d−m} = 0 (monic).
            let mut ps: Vec<BigRational> = vec![BigRational::from_integer(BigInt::from(d))];
            for m in 1..d {
                let mut acc = BigRational::from_integer(BigInt::from(m)) * p.coeff(d - m);
                for i in 1..m {
                    acc += p.coeff(d - i) * &ps[m - i];
                }
                ps.push(-acc);
            }
            out.push((group, ps));
        }
        out
    }

    /// An element with the same value and, where it can, fewer roots: for a
    /// complete family of conjugates `G` (all roots of one polynomial) and a
    /// pivot `S` (no variable, or one variable of `G`), the terms that involve
    /// exactly one variable `xⱼ` of `G \ S` are sums `Σⱼ Fⱼ(xⱼ)`; with `F`
    /// the most frequent `Fⱼ`, `Σ_{j ∈ G∖S} F(xⱼ)` is replaced by its value
    /// through the power sums, `Σₘ fₘ·(pₘ − Σ_{k∈S} xₖᵐ)`, and only the
    /// `Fⱼ − F ≠ 0` stay. The result is kept when it involves fewer
    /// variables of `G`. This turns `Σᵢ bᵢcᵢᵏ` over the nodes into a
    /// rational and the row sums `Σⱼ aᵢⱼ` into a polynomial in `cᵢ`.
    pub fn collapse(&self, a: &Alg) -> Alg {
        let groups = self.complete_groups();
        if groups.is_empty() {
            return a.clone();
        }
        let mut cur = a.clone();
        // Each accepted step removes a variable of some group: bounded.
        let mut steps = self.roots.len() + 1;
        'outer: while steps > 0 {
            steps -= 1;
            let sup = cur.support();
            for (g, ps) in &groups {
                let before = g.iter().filter(|k| sup.contains(k)).count();
                if before == 0 {
                    continue;
                }
                let pivots: Vec<Option<usize>> = std::iter::once(None)
                    .chain(g.iter().filter(|k| sup.contains(k)).map(|&k| Some(k)))
                    .collect();
                for s in pivots {
                    if let Some(next) = self.collapse_step(&cur, g, s, ps) {
                        let ns = next.support();
                        let after = g.iter().filter(|k| ns.contains(k)).count();
                        if after < before {
                            cur = next;
                            continue 'outer;
                        }
                    }
                }
            }
            break;
        }
        cur
    }

    fn collapse_step(
        &self,
        a: &Alg,
        g: &[usize],
        s: Option<usize>,
        ps: &[BigRational],
    ) -> Option<Alg> {
        type F = BTreeMap<(u32, Mono), BigRational>;
        let free: Vec<usize> = g.iter().copied().filter(|&k| Some(k) != s).collect();
        let mut rest = Alg::zero();
        let mut parts: BTreeMap<usize, F> = free.iter().map(|&j| (j, F::new())).collect();
        for (m, c) in &a.terms {
            let js: Vec<usize> = free
                .iter()
                .copied()
                .filter(|&j| m.get(j).copied().unwrap_or(0) > 0)
                .collect();
            if js.len() != 1 {
                rest.add_term(m.clone(), c.clone());
                continue;
            }
            let j = js[0];
            let mut mr = m.clone();
            let e = mr[j];
            mr[j] = 0;
            let mr = trim(mr);
            parts.get_mut(&j)?.insert((e, mr), c.clone());
        }
        let same = |x: &F, y: &F| {
            x.len() == y.len()
                && x.iter()
                    .zip(y)
                    .all(|((k1, v1), (k2, v2))| k1 == k2 && qeq(v1, v2))
        };
        // The most frequent part.
        let mut best: Option<(&F, usize)> = None;
        for (_, f) in parts.iter() {
            let n = parts.values().filter(|o| same(o, f)).count();
            if best.is_none_or(|(_, bn)| n > bn) {
                best = Some((f, n));
            }
        }
        let (f, _) = best?;
        if f.is_empty() {
            return None;
        }
        let f = f.clone();
        let mut out = rest;
        for ((e, mr), c) in &f {
            let pe = ps.get(*e as usize)?;
            out.add_term(mr.clone(), c * pe);
            if let Some(k) = s {
                let mut m2 = mr.clone();
                if m2.len() <= k {
                    m2.resize(k + 1, 0);
                }
                m2[k] += e;
                out.add_term(m2, -c.clone());
            }
        }
        for (&j, fj) in &parts {
            if same(fj, &f) {
                continue;
            }
            for ((e, mr), c) in fj {
                let mut m2 = mr.clone();
                if m2.len() <= j {
                    m2.resize(j + 1, 0);
                }
                m2[j] += e;
                out.add_term(m2, c.clone());
            }
            for ((e, mr), c) in &f {
                let mut m2 = mr.clone();
                if m2.len() <= j {
                    m2.resize(j + 1, 0);
                }
                m2[j] += e;
                out.add_term(m2, -c.clone());
            }
        }
        Some(self.reduce(&out))
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
