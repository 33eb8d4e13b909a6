//! Exact integer linear algebra by computing modulo many primes: the
//! characteristic polynomial of an integer matrix (Hessenberg reduction over
//! each prime field, then the Chinese remainder theorem), and a coprimality
//! test for integer polynomials.
//!
//! Nothing here is approximate. The characteristic polynomial's coefficients
//! are bounded a priori (Hadamard's inequality for every principal minor),
//! and enough primes are used that their product exceeds twice the bound, so
//! the symmetric residue *is* the coefficient. The primes are below 2⁶² and
//! proven prime by a Miller–Rabin test with the first twelve prime bases,
//! which is deterministic below 3.3·10²⁴.

use num_bigint::{BigInt, Sign};
use num_integer::Integer;
use num_traits::{One, ToPrimitive, Zero};

/// `a · b mod p`.
fn mul_mod(a: u64, b: u64, p: u64) -> u64 {
    ((a as u128 * b as u128) % p as u128) as u64
}

fn pow_mod(mut a: u64, mut e: u64, p: u64) -> u64 {
    let mut r = 1u64;
    while e > 0 {
        if e & 1 == 1 {
            r = mul_mod(r, a, p);
        }
        a = mul_mod(a, a, p);
        e >>= 1;
    }
    r
}

/// `a⁻¹ mod p` for `a ≠ 0` and `p` prime (Fermat).
fn inv_mod(a: u64, p: u64) -> u64 {
    pow_mod(a, p - 2, p)
}

/// Deterministic for every `n < 3.3·10²⁴`, so for every `u64`.
fn is_prime(n: u64) -> bool {
    const BASES: [u64; 12] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37];
    if n < 2 {
        return false;
    }
    for &b in &BASES {
        if n.is_multiple_of(b) {
            return n == b;
        }
    }
    let (mut d, mut r) = (n - 1, 0);
    while d.is_multiple_of(2) {
        d /= 2;
        r += 1;
    }
    'bases: for &a in &BASES {
        let mut x = pow_mod(a, d, n);
        if x == 1 || x == n - 1 {
            continue;
        }
        for _ in 1..r {
            x = mul_mod(x, x, n);
            if x == n - 1 {
                continue 'bases;
            }
        }
        return false;
    }
    true
}

/// The primes below 2⁶², largest first.
pub(crate) struct Primes {
    next: u64,
}

impl Primes {
    pub(crate) fn new() -> Self {
        Primes {
            next: (1u64 << 62) - 1,
        }
    }
}

impl Iterator for Primes {
    type Item = u64;
    fn next(&mut self) -> Option<u64> {
        while self.next > 3 {
            let n = self.next;
            self.next -= 2;
            if is_prime(n) {
                return Some(n);
            }
        }
        None
    }
}

/// Bits of information one prime contributes (each is above 2⁶¹).
pub(crate) const BITS_PER_PRIME: u64 = 61;

fn residue(x: &BigInt, p: u64) -> u64 {
    let r = x.mod_floor(&BigInt::from(p));
    r.to_u64().expect("a residue is below p")
}

/// `det(λI − M) = Σₖ cₖ λ^(s−k)` modulo `p`: the coefficients `c₀ = 1, c₁, …,
/// c_s` (Hessenberg reduction, then the recurrence of its leading minors;
/// Cohen, *A Course in Computational Algebraic Number Theory*, 2.2.9).
fn charpoly_mod(m: &[Vec<u64>], p: u64) -> Vec<u64> {
    let n = m.len();
    let mut h: Vec<Vec<u64>> = m.to_vec();
    let sub = |a: u64, b: u64| if a >= b { a - b } else { a + p - b };
    let add = |a: u64, b: u64| {
        let s = a + b;
        if s >= p { s - p } else { s }
    };
    for col in 0..n.saturating_sub(2) {
        let m1 = col + 1;
        let Some(i) = (m1..n).find(|&i| h[i][col] != 0) else {
            continue;
        };
        if i != m1 {
            h.swap(i, m1);
            for row in h.iter_mut() {
                row.swap(i, m1);
            }
        }
        let t_inv = inv_mod(h[m1][col], p);
        for j in m1 + 1..n {
            let u = mul_mod(h[j][col], t_inv, p);
            if u == 0 {
                continue;
            }
            // row_j −= u · row_m1
            let (top, bottom) = h.split_at_mut(j);
            let (rm, rj) = (&top[m1], &mut bottom[0]);
            for (x, y) in rj.iter_mut().zip(rm) {
                *x = sub(*x, mul_mod(u, *y, p));
            }
            // col_m1 += u · col_j
            for row in h.iter_mut() {
                row[m1] = add(row[m1], mul_mod(u, row[j], p));
            }
        }
    }
    // polys[k] = det(λI − H[..k, ..k]), coefficients highest power first
    // trimmed to the form (c₀ = 1, c₁, …, c_k).
    let mut polys: Vec<Vec<u64>> = vec![vec![1]];
    for k in 1..=n {
        // (λ − h_{k−1,k−1}) · polys[k−1]
        let prev = &polys[k - 1];
        let mut cur = vec![0u64; k + 1];
        for (i, &c) in prev.iter().enumerate() {
            cur[i] = add(cur[i], c);
            cur[i + 1] = sub(cur[i + 1], mul_mod(h[k - 1][k - 1], c, p));
        }
        let mut t = 1u64;
        for i in 1..k {
            t = mul_mod(t, h[k - i][k - i - 1], p);
            if t == 0 {
                break;
            }
            let f = mul_mod(t, h[k - i - 1][k - 1], p);
            if f == 0 {
                continue;
            }
            // cur −= f · polys[k−i−1] (degree k−i−1: aligned to the low end)
            let q = &polys[k - i - 1];
            let shift = k + 1 - q.len();
            for (j, &c) in q.iter().enumerate() {
                cur[shift + j] = sub(cur[shift + j], mul_mod(f, c, p));
            }
        }
        polys.push(cur);
    }
    polys.pop().expect("n + 1 polynomials")
}

/// An upper bound on `|cₖ|` for every coefficient of `det(λI − M)`: the
/// `k`-th elementary symmetric function of the row norms (rounded up), which
/// bounds the sum of the principal `k × k` minors by Hadamard's inequality.
pub(crate) fn charpoly_bound(m: &[Vec<BigInt>]) -> BigInt {
    let norms: Vec<BigInt> = m
        .iter()
        .map(|row| {
            let sq: BigInt = row.iter().map(|x| x * x).sum();
            let r = sq.sqrt();
            if &r * &r == sq { r } else { r + 1 }
        })
        .collect();
    // e[k] = elementary symmetric functions of the norms seen so far.
    let mut e = vec![BigInt::one()];
    for r in &norms {
        e.push(BigInt::zero());
        for k in (1..e.len()).rev() {
            let add = &e[k - 1] * r;
            e[k] += add;
        }
    }
    e.into_iter().max().unwrap_or_else(BigInt::one)
}

/// The number of primes [`charpoly`] needs for a matrix with this bound.
pub(crate) fn primes_needed(bound: &BigInt) -> u64 {
    (bound.bits() + 2).div_ceil(BITS_PER_PRIME)
}

/// `det(λI − M) = Σₖ cₖ λ^(s−k)` for an integer matrix: `[c₀ = 1, c₁, …, c_s]`.
pub(crate) fn charpoly(m: &[Vec<BigInt>]) -> Vec<BigInt> {
    let n = m.len();
    let bound = charpoly_bound(m);
    let needed = primes_needed(&bound);
    let mut modulus = BigInt::one();
    let mut value = vec![BigInt::zero(); n + 1];
    for p in Primes::new().take(needed as usize) {
        let mp: Vec<Vec<u64>> = m
            .iter()
            .map(|row| row.iter().map(|x| residue(x, p)).collect())
            .collect();
        let r = charpoly_mod(&mp, p);
        // Garner: value ← value + modulus · ((r − value) · modulus⁻¹ mod p).
        let m_inv = inv_mod(residue(&modulus, p), p);
        for (v, &rk) in value.iter_mut().zip(&r) {
            let diff = (rk + p - residue(v, p)) % p;
            let k = mul_mod(diff, m_inv, p);
            if k != 0 {
                *v += &modulus * BigInt::from(k);
            }
        }
        modulus *= BigInt::from(p);
    }
    let half = &modulus >> 1;
    for v in value.iter_mut() {
        if *v > half {
            *v -= &modulus;
        }
    }
    value
}

/// Whether two integer polynomials (constant term first, no trailing
/// zeros) are coprime over Q, decided modulo primes: when a prime divides
/// neither leading coefficient, the degree of the gcd modulo that prime is at
/// least the degree of the gcd over Q, so a gcd of degree 0 modulo one such
/// prime proves coprimality. `None` when the primes tried do not decide.
pub(crate) fn coprime_mod(a: &[BigInt], b: &[BigInt], tries: usize) -> Option<bool> {
    let (Some(la), Some(lb)) = (a.last(), b.last()) else {
        return None;
    };
    if a.len() == 1 || b.len() == 1 {
        return Some(true);
    }
    for p in Primes::new().take(tries) {
        if residue(la, p) == 0 || residue(lb, p) == 0 {
            continue;
        }
        let ap: Vec<u64> = a.iter().map(|x| residue(x, p)).collect();
        let bp: Vec<u64> = b.iter().map(|x| residue(x, p)).collect();
        if gcd_degree_mod(ap, bp, p) == 0 {
            return Some(true);
        }
    }
    None
}

/// A ring homomorphism from the numbers whose denominators are prime to `ℓ`
/// onto the prime field F_ℓ, sending each `p^(1/6)` to a sixth root `r_p` of
/// `p` modulo `ℓ`. It is well defined because the field of the radicals is
/// `Q[x_p]/(x_p⁶ − p)` (the monomials are linearly independent, so the degrees
/// agree), and any choice of roots of `x_p⁶ − p` in F_ℓ is a homomorphism of
/// that ring. For `ℓ ∤ 6∏p` its kernel is a prime above `ℓ` of a local ring
/// that is a discrete valuation ring, so a gcd of degree 0 modulo `ℓ` (with
/// leading coefficients that survive) proves two polynomials coprime, as for
/// integers ([`coprime_mod`]).
pub(crate) struct RadicalHom {
    l: u64,
    roots: std::collections::BTreeMap<u64, u64>,
}

impl RadicalHom {
    /// The `skip`-th homomorphism for these primes: `ℓ ≡ 11 (mod 12)` below
    /// 2⁶², so that square roots are `x^((ℓ+1)/4)` and cube roots are unique,
    /// `x^((2ℓ−1)/3)`; every `p` must be a square modulo `ℓ`. `None` beyond
    /// twelve primes (a field too large to bother).
    pub(crate) fn find(primes: &[u64], skip: usize) -> Option<RadicalHom> {
        if primes.len() > 12 {
            return None;
        }
        let mut found = 0;
        let mut n = (1u64 << 62) - 1;
        n -= (n + 1) % 12; // n ≡ 11 (mod 12)
        while n > 1 << 40 {
            let l = n;
            n -= 12;
            let squares = primes
                .iter()
                .all(|&p| p % l != 0 && pow_mod(p % l, (l - 1) / 2, l) == 1);
            if !squares || !is_prime(l) {
                continue;
            }
            if found < skip {
                found += 1;
                continue;
            }
            let roots = primes
                .iter()
                .map(|&p| {
                    let sq = pow_mod(p % l, (l + 1) / 4, l);
                    (p, pow_mod(sq, (2 * l - 1) / 3, l))
                })
                .collect();
            let hom = RadicalHom { l, roots };
            debug_assert!(hom.roots.iter().all(|(&p, &r)| pow_mod(r, 6, l) == p % l));
            return Some(hom);
        }
        None
    }

    /// The image of `x`, or `None` when a denominator is divisible by `ℓ`.
    pub(crate) fn map(&self, x: &crate::Number) -> Option<u64> {
        let l = self.l;
        let mut acc = 0u64;
        for (m, c) in x.terms() {
            let d = residue(c.denom(), l);
            if d == 0 {
                return None;
            }
            let mut v = mul_mod(residue(c.numer(), l), inv_mod(d, l), l);
            for &(p, e) in m.factors() {
                v = mul_mod(v, pow_mod(self.roots[&p], u64::from(e), l), l);
            }
            acc = (acc + v) % l;
        }
        Some(acc)
    }

    /// Whether `a` and `b` (constant term first, no trailing zeros) are
    /// proven coprime by this homomorphism; `false` means undecided.
    pub(crate) fn proves_coprime(&self, a: &[crate::Number], b: &[crate::Number]) -> bool {
        let map = |v: &[crate::Number]| v.iter().map(|x| self.map(x)).collect::<Option<Vec<u64>>>();
        let (Some(am), Some(bm)) = (map(a), map(b)) else {
            return false;
        };
        if am.last() == Some(&0) || bm.last() == Some(&0) || am.is_empty() || bm.is_empty() {
            return false;
        }
        gcd_degree_mod(am, bm, self.l) == 0
    }
}

fn trim_mod(v: &mut Vec<u64>) {
    while v.last() == Some(&0) {
        v.pop();
    }
}

fn gcd_degree_mod(mut a: Vec<u64>, mut b: Vec<u64>, p: u64) -> usize {
    trim_mod(&mut a);
    trim_mod(&mut b);
    while !b.is_empty() {
        // a ← a mod b
        let inv = inv_mod(*b.last().expect("nonempty"), p);
        while a.len() >= b.len() {
            let f = mul_mod(*a.last().expect("nonempty"), inv, p);
            let shift = a.len() - b.len();
            for (j, &c) in b.iter().enumerate() {
                let t = mul_mod(f, c, p);
                a[shift + j] = if a[shift + j] >= t {
                    a[shift + j] - t
                } else {
                    a[shift + j] + p - t
                };
            }
            trim_mod(&mut a);
            if a.is_empty() {
                break;
            }
        }
        std::mem::swap(&mut a, &mut b);
    }
    a.len().saturating_sub(1)
}

/// The content (gcd of the coefficients) of an integer polynomial.
fn content(a: &[BigInt]) -> BigInt {
    a.iter().fold(BigInt::zero(), |g, x| g.gcd(x))
}

fn primitive(a: Vec<BigInt>) -> Vec<BigInt> {
    let c = content(&a);
    if c.is_zero() || c.is_one() {
        return a;
    }
    a.into_iter().map(|x| x / &c).collect()
}

fn trim(mut a: Vec<BigInt>) -> Vec<BigInt> {
    while a.last().is_some_and(Zero::is_zero) {
        a.pop();
    }
    a
}

/// The gcd over Z of two integer polynomials (constant term first), by the
/// primitive remainder sequence; primitive, with a positive leading
/// coefficient.
pub(crate) fn gcd_z(a: &[BigInt], b: &[BigInt]) -> Vec<BigInt> {
    let (mut a, mut b) = (primitive(trim(a.to_vec())), primitive(trim(b.to_vec())));
    if a.len() < b.len() {
        std::mem::swap(&mut a, &mut b);
    }
    while !b.is_empty() {
        // Pseudo-remainder of a by b.
        let lb = b.last().expect("nonempty").clone();
        let mut r = a;
        while r.len() >= b.len() {
            let lr = r.last().expect("nonempty").clone();
            let shift = r.len() - b.len();
            for x in r.iter_mut() {
                *x *= &lb;
            }
            for (j, c) in b.iter().enumerate() {
                r[shift + j] -= &lr * c;
            }
            r = trim(r);
        }
        a = b;
        b = primitive(r);
    }
    if a.last().is_some_and(|x| x.sign() == Sign::Minus) {
        a = a.into_iter().map(|x| -x).collect();
    }
    a
}

/// Exact division of integer polynomials over Q: `a / b` when `b` divides
/// `a`, as rational coefficients (numerators over a common power of the
/// leading coefficient are avoided by dividing exactly where possible).
pub(crate) fn div_exact(a: &[BigInt], b: &[BigInt]) -> Vec<num_rational::BigRational> {
    use num_rational::BigRational;
    let lb = BigRational::from_integer(b.last().expect("nonzero divisor").clone());
    let mut rem: Vec<BigRational> = a.iter().cloned().map(BigRational::from_integer).collect();
    let mut quot = vec![BigRational::zero(); a.len().saturating_sub(b.len()) + 1];
    while rem.len() >= b.len() && !rem.is_empty() {
        let shift = rem.len() - b.len();
        let f = rem.last().expect("nonempty") / &lb;
        for (j, c) in b.iter().enumerate() {
            rem[shift + j] -= &f * BigRational::from_integer(c.clone());
        }
        quot[shift] = f;
        rem.pop();
        while rem.last().is_some_and(Zero::is_zero) {
            rem.pop();
        }
    }
    debug_assert!(rem.iter().all(Zero::is_zero), "b divides a");
    quot
}

#[cfg(test)]
mod tests {
    use super::*;

    fn big(v: &[i64]) -> Vec<BigInt> {
        v.iter().map(|&x| BigInt::from(x)).collect()
    }

    #[test]
    fn primes_are_prime() {
        assert!(is_prime(2) && is_prime(3) && is_prime(97) && !is_prime(91));
        assert!(!is_prime(3_215_031_751)); // a strong pseudoprime to bases 2, 3, 5, 7
        let ps: Vec<u64> = Primes::new().take(3).collect();
        assert_eq!(ps[0], 4_611_686_018_427_387_847);
        assert!(ps.windows(2).all(|w| w[0] > w[1]));
    }

    #[test]
    fn charpoly_of_small_matrices() {
        // [[1, 2], [3, 4]]: λ² − 5λ − 2.
        let m = vec![big(&[1, 2]), big(&[3, 4])];
        assert_eq!(charpoly(&m), big(&[1, -5, -2]));
        // A 3×3 with a zero subdiagonal entry.
        let m = vec![big(&[2, 0, 1]), big(&[0, 3, 0]), big(&[1, 0, 2])];
        // (λ − 3)((λ − 2)² − 1) = λ³ − 7λ² + 15λ − 9
        assert_eq!(charpoly(&m), big(&[1, -7, 15, -9]));
    }

    #[test]
    fn gcd_and_coprimality() {
        // (1 + z)(2 + z) and (1 + z)(3 − z)
        let a = big(&[2, 3, 1]);
        let b = big(&[3, 2, -1]);
        assert_eq!(gcd_z(&a, &b), big(&[1, 1]));
        assert_eq!(coprime_mod(&a, &b, 4), None);
        assert_eq!(coprime_mod(&big(&[1, 1]), &big(&[1, 2]), 4), Some(true));
    }
}
