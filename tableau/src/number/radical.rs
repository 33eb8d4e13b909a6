//! Monomials of real radicals: products `∏ pᵢ^(eᵢ/6)` over distinct primes.
//!
//! Every number the grammar can write lives in the field generated over Q by
//! the sixth roots of primes (`sqrt(p) = p^(3/6)`, `cbrt(p) = p^(2/6)`). By
//! Besicovitch's theorem (A. S. Besicovitch, "On the linear independence of
//! fractional powers of integers", J. London Math. Soc. 15, 1940) the products
//! `∏ pᵢ^(eᵢ/6)` with `0 ≤ eᵢ < 6` over distinct primes are linearly independent
//! over Q. A number is therefore *uniquely* a finite Q-linear combination of
//! such monomials, and it is zero exactly when every coefficient is zero: the
//! zero test is exact and complete.

use num_bigint::BigInt;
use num_traits::{One, ToPrimitive};

/// The denominator of every exponent: sixth roots cover both `sqrt` and `cbrt`.
pub const ROOT: u8 = 6;

/// `∏ pᵢ^(eᵢ/6)`, primes strictly increasing, every `eᵢ` in `1..6`.
/// The empty product is the monomial 1.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Radical(pub(crate) Vec<(u64, u8)>);

impl Radical {
    /// The monomial 1.
    pub fn one() -> Self {
        Radical(Vec::new())
    }

    /// `p^(e/6)` for a prime `p`; `e` is reduced mod 6 and the whole powers are
    /// returned as the integer factor: `p^(e/6) = factor · radical`.
    pub fn prime_power(p: u64, e: u32) -> (BigInt, Self) {
        let whole = e / ROOT as u32;
        let rest = (e % ROOT as u32) as u8;
        let factor = BigInt::from(p).pow(whole);
        if rest == 0 {
            (factor, Radical::one())
        } else {
            (factor, Radical(vec![(p, rest)]))
        }
    }

    pub fn is_one(&self) -> bool {
        self.0.is_empty()
    }

    /// The primes with their exponents (in sixths).
    pub fn factors(&self) -> &[(u64, u8)] {
        &self.0
    }

    /// Product of two monomials: `self · other = factor · radical`, where the
    /// integer `factor` collects whole powers of primes.
    pub fn mul(&self, other: &Radical) -> (BigInt, Radical) {
        let mut factor = BigInt::one();
        let mut out = Vec::with_capacity(self.0.len() + other.0.len());
        let (mut i, mut j) = (0, 0);
        while i < self.0.len() || j < other.0.len() {
            let take = match (self.0.get(i), other.0.get(j)) {
                (Some(a), Some(b)) if a.0 == b.0 => {
                    i += 1;
                    j += 1;
                    let e = a.1 + b.1;
                    if e >= ROOT {
                        factor *= a.0;
                    }
                    (a.0, e % ROOT)
                }
                (Some(a), Some(b)) if a.0 < b.0 => {
                    i += 1;
                    *a
                }
                (Some(_), Some(b)) => {
                    j += 1;
                    *b
                }
                (Some(a), None) => {
                    i += 1;
                    *a
                }
                (None, Some(b)) => {
                    j += 1;
                    *b
                }
                (None, None) => unreachable!(),
            };
            if take.1 != 0 {
                out.push(take);
            }
        }
        (factor, Radical(out))
    }

    /// The inverse monomial: `self⁻¹ = radical / divisor`.
    pub fn recip(&self) -> (BigInt, Radical) {
        let mut divisor = BigInt::one();
        let mut out = Vec::with_capacity(self.0.len());
        for &(p, e) in &self.0 {
            divisor *= p;
            out.push((p, ROOT - e));
        }
        (divisor, Radical(out))
    }

    /// The integer `N = ∏ pᵢ^eᵢ`, so that the monomial is `N^(1/6)`.
    pub fn radicand(&self) -> BigInt {
        let mut n = BigInt::one();
        for &(p, e) in &self.0 {
            n *= BigInt::from(p).pow(e as u32);
        }
        n
    }

    /// Rational bounds `lo ≤ value ≤ lo + 1` on `value · 2^bits`:
    /// returns `floor(N^(1/6) · 2^bits)` and whether it is exact.
    pub fn scaled_floor(&self, bits: u64) -> (BigInt, bool) {
        if self.is_one() {
            return (BigInt::one() << bits, true);
        }
        let n = self.radicand() << (bits as usize * ROOT as usize);
        let r = n.nth_root(ROOT as u32);
        let exact = r.pow(ROOT as u32) == n;
        (r, exact)
    }

    /// A short string in the grammar: `sqrt(A)*cbrt(B)` and the rational
    /// correction that makes it equal to this monomial, `self = text / divisor`.
    ///
    /// `p^(e/6)` is written as `sqrt(p)^a · cbrt(p)^b` with `3a + 2b ≡ e (mod 6)`;
    /// only `e = 1` overshoots by one whole `p` (`p^(7/6)`), which goes into the
    /// divisor.
    pub fn to_grammar(&self) -> (String, BigInt) {
        let mut sq = BigInt::one();
        let mut cb = BigInt::one();
        let mut divisor = BigInt::one();
        for &(p, e) in &self.0 {
            let p_big = BigInt::from(p);
            match e {
                1 => {
                    sq *= &p_big;
                    cb *= &p_big * &p_big;
                    divisor *= &p_big;
                }
                2 => cb *= &p_big,
                3 => sq *= &p_big,
                4 => cb *= &p_big * &p_big,
                5 => {
                    sq *= &p_big;
                    cb *= &p_big;
                }
                _ => unreachable!("exponents are kept in 1..6"),
            }
        }
        let mut parts = Vec::new();
        if !sq.is_one() {
            parts.push(format!("sqrt({sq})"));
        }
        if !cb.is_one() {
            parts.push(format!("cbrt({cb})"));
        }
        (parts.join("*"), divisor)
    }

    /// An f64 approximation (for diagnostics and quick bounds only).
    pub fn approx(&self) -> f64 {
        self.0
            .iter()
            .map(|&(p, e)| (p as f64).powf(e as f64 / ROOT as f64))
            .product::<f64>()
            .to_f64()
            .unwrap_or(f64::NAN)
    }
}

/// Largest trial divisor; a cofactor left below `TRIAL_LIMIT²` is prime.
const TRIAL_LIMIT: u64 = 1 << 20;

/// The prime factorisation of `n > 0`, or `None` when `n` is too large to be
/// factored by trial division with certainty (the caller refuses such input
/// rather than guessing).
pub fn factorize(n: &BigInt) -> Option<Vec<(u64, u32)>> {
    use num_integer::Integer;
    let mut n = n.clone();
    let mut out = Vec::new();
    let mut d: u64 = 2;
    while d < TRIAL_LIMIT {
        let big_d = BigInt::from(d);
        if &big_d * &big_d > n {
            break;
        }
        let mut e = 0;
        loop {
            let (q, r) = n.div_rem(&big_d);
            if r == BigInt::from(0) {
                n = q;
                e += 1;
            } else {
                break;
            }
        }
        if e > 0 {
            out.push((d, e));
        }
        d += if d == 2 { 1 } else { 2 };
    }
    if n.is_one() {
        return Some(out);
    }
    // No factor below min(d, TRIAL_LIMIT): n is prime if n < d².
    let bound = BigInt::from(d) * BigInt::from(d);
    if n < bound {
        let p = n.to_u64()?;
        out.push((p, 1));
        Some(out)
    } else {
        None
    }
}
