//! General real algebraic numbers: polynomials with rational coefficients in
//! finitely many real roots `α₁, …, αₖ` (each a [`RealRoot`] of its own
//! squarefree polynomial `pₖ`).
//!
//! An [`Alg`] is kept reduced modulo every `pₖ(xₖ)`, i.e. as an element of
//! the algebra `A = Q[x₁, …, xₖ]/(p₁(x₁), …, pₖ(xₖ))`, a product of fields
//! (its points are all tuples of conjugates). The number it stands for is its
//! value at the one point `(α₁, …, αₖ)`. Equality in `A` implies equality of
//! the numbers but not conversely, so the zero test does not stop there: the
//! value `γ = e(α)` is a root of the characteristic polynomial `χ(t)` of
//! multiplication by `e` on the part of `A` that `e` involves; `γ = 0` exactly
//! when `χ(0) = 0` and a certified enclosure of `γ` holds no other root of
//! the squarefree part of `χ` (Sturm counts). This decides zero completely,
//! for any number of roots, within the budget [`MAX_ZERO_TEST_DIMENSION`].

use std::collections::BTreeMap;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

use super::poly::{Poly, count_roots, imul};
use super::root::{RealRoot, f64_rational, next_up, sign};
use crate::budget::BeyondBudget;
use crate::number::rational_to_f64;

/// The largest algebra (product of the degrees of the roots an expression
/// involves) on which a zero test runs; above it the test is refused.
pub const MAX_ZERO_TEST_DIMENSION: usize = 512;

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
        let e = self.terms.entry(m.clone()).or_insert_with(BigRational::zero);
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
            let d = root.poly.degree().unwrap_or(0) as u32;
            if !cur.terms.keys().any(|m| m.get(k).copied().unwrap_or(0) >= d) {
                continue;
            }
            // xₖ^d = −Σ_{j<d} p_j xₖ^j (p monic), applied from the top power down.
            let mut out = Alg::zero();
            let mut pending: Vec<(Mono, BigRational)> =
                cur.terms.into_iter().collect();
            while let Some((m, c)) = pending.pop() {
                let e = m.get(k).copied().unwrap_or(0);
                if e < d {
                    out.add_term(m, c);
                    continue;
                }
                for (j, pj) in root.poly.0.iter().enumerate().take(d as usize) {
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
                sup.iter().map(|&k| self.names[k].as_str()).collect::<Vec<_>>().join(", ")
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
        }
        let inv = p
            .rem(&self.roots[k].poly)
            .inverse_mod(&self.roots[k].poly)
            .expect("coprime after splitting");
        Ok(Alg::from_univariate(&inv, k))
    }

    /// A certified enclosure of the value.
    fn enclose(&self, a: &Alg, roots: &[RealRoot]) -> (BigRational, BigRational) {
        let mut lo = BigRational::zero();
        let mut hi = BigRational::zero();
        for (m, c) in &a.terms {
            let (mut tl, mut th) = (c.clone(), c.clone());
            for (k, &e) in m.iter().enumerate() {
                for _ in 0..e {
                    let (l, h) = imul(&tl, &th, &roots[k].lo, &roots[k].hi);
                    tl = l;
                    th = h;
                }
            }
            lo += tl;
            hi += th;
        }
        (lo, hi)
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
        let dims: Vec<usize> = sup
            .iter()
            .map(|&k| self.roots[k].poly.degree().unwrap_or(1))
            .collect();
        let n: usize = dims.iter().product();
        if n > MAX_ZERO_TEST_DIMENSION {
            return Err(BeyondBudget(format!(
                "deciding whether an expression in {} roots ({}) is zero needs an algebra of dimension {n}, beyond the budget of {MAX_ZERO_TEST_DIMENSION} (tableau::algebraic::alg::MAX_ZERO_TEST_DIMENSION)",
                sup.len(),
                sup.iter().map(|&k| self.names[k].as_str()).collect::<Vec<_>>().join(", ")
            )));
        }
        // The basis: monomials with exponent < dims[i] in variable sup[i].
        let width = sup.iter().max().map_or(0, |&k| k + 1);
        let mut basis: Vec<Mono> = vec![vec![0; width]];
        for (i, &k) in sup.iter().enumerate() {
            let mut next = Vec::new();
            for m in &basis {
                for e in 0..dims[i] as u32 {
                    let mut m2 = m.clone();
                    m2[k] = e;
                    next.push(m2);
                }
            }
            basis = next;
        }
        let basis: Vec<Mono> = basis.into_iter().map(trim).collect();
        let index: BTreeMap<&Mono, usize> = basis.iter().enumerate().map(|(i, m)| (m, i)).collect();
        let mut mat = vec![vec![BigRational::zero(); n]; n];
        for (col, m) in basis.iter().enumerate() {
            let mut e = Alg::zero();
            e.add_term(m.clone(), BigRational::one());
            let prod = self.mul(&a, &e);
            for (m2, c) in &prod.terms {
                mat[index[m2]][col] = c.clone();
            }
        }
        let chi = charpoly(mat);
        if !chi.coeff(0).is_zero() {
            return Ok(false);
        }
        let chi = chi.squarefree();
        let seq = chi.sturm();
        let mut roots: Vec<RealRoot> = self.roots.clone();
        loop {
            let (lo, hi) = self.enclose(&a, &roots);
            if lo.is_positive() || hi.is_negative() {
                return Ok(false);
            }
            let inside =
                count_roots(&seq, &lo, &hi) + usize::from(chi.eval(&lo).is_zero());
            if inside == 1 {
                return Ok(true);
            }
            for &k in &sup {
                roots[k].bisect();
            }
        }
    }

    /// The exact sign of the value.
    pub fn sign(&self, a: &Alg) -> Result<i8, BeyondBudget> {
        let a = self.reduce(a);
        if self.is_zero(&a)? {
            return Ok(0);
        }
        let sup = a.support();
        let mut roots = self.roots.clone();
        loop {
            let (lo, hi) = self.enclose(&a, &roots);
            if lo.is_positive() {
                return Ok(1);
            }
            if hi.is_negative() {
                return Ok(-1);
            }
            for &k in &sup {
                roots[k].bisect();
            }
        }
    }

    /// The `f64` nearest to the value (ties to even), decided on certified
    /// enclosures; a value exactly halfway between two doubles is detected
    /// by an exact zero test.
    pub fn to_f64(&self, a: &Alg) -> Result<f64, BeyondBudget> {
        let a = self.reduce(a);
        if let Some(r) = a.as_rational() {
            return Ok(rational_to_f64(&r));
        }
        if self.is_zero(&a)? {
            return Ok(0.0);
        }
        let sup = a.support();
        let mut roots = self.roots.clone();
        let mut tested: Option<BigRational> = None;
        loop {
            let (lo, hi) = self.enclose(&a, &roots);
            let (fl, fh) = (rational_to_f64(&lo), rational_to_f64(&hi));
            if fl == fh {
                return Ok(fl);
            }
            if fh == next_up(fl) && fl.is_finite() && fh.is_finite() {
                let mid = (f64_rational(fl) + f64_rational(fh)) / BigRational::from_integer(2.into());
                if lo <= mid && mid <= hi && tested.as_ref() != Some(&mid) {
                    if self.is_zero(&a.sub(&Alg::rational(mid.clone())))? {
                        return Ok(rational_to_f64(&mid));
                    }
                    tested = Some(mid);
                }
            }
            for &k in &sup {
                roots[k].bisect();
            }
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

/// The characteristic polynomial `det(t·I − M)` (Hessenberg reduction over
/// Q, then the recurrence on the Hessenberg form).
pub fn charpoly(mut h: Vec<Vec<BigRational>>) -> Poly {
    let n = h.len();
    for c in 0..n.saturating_sub(2) {
        let Some(i) = (c + 1..n).find(|&i| !h[i][c].is_zero()) else {
            continue;
        };
        if i != c + 1 {
            h.swap(i, c + 1);
            for row in h.iter_mut() {
                row.swap(i, c + 1);
            }
        }
        let t = h[c + 1][c].clone();
        for j in c + 2..n {
            if h[j][c].is_zero() {
                continue;
            }
            let u = &h[j][c] / &t;
            for k in 0..n {
                if !h[c + 1][k].is_zero() {
                    let d = &u * &h[c + 1][k];
                    h[j][k] -= d;
                }
            }
            for k in 0..n {
                if !h[k][j].is_zero() {
                    let d = &u * &h[k][j];
                    h[k][c + 1] += d;
                }
            }
        }
    }
    let mut p: Vec<Poly> = vec![Poly::one()];
    for m in 1..=n {
        let mut pm = Poly(vec![-h[m - 1][m - 1].clone(), BigRational::one()])
            .trim()
            .mul(&p[m - 1]);
        let mut t = BigRational::one();
        for i in (1..m).rev() {
            t *= &h[i][i - 1];
            if t.is_zero() {
                break;
            }
            let f = &t * &h[i - 1][m - 1];
            if !f.is_zero() {
                pm = pm.sub(&p[i - 1].scale(&f));
            }
        }
        p.push(pm);
    }
    p.pop().expect("n + 1 polynomials")
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
    fn charpoly_of_a_small_matrix() {
        // [[2, 1], [1, 2]]: t² − 4t + 3
        let m = vec![vec![q(2, 1), q(1, 1)], vec![q(1, 1), q(2, 1)]];
        assert_eq!(charpoly(m), Poly::from_ints(&[3, -4, 1]));
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
