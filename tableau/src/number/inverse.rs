//! The multiplicative inverse of a sum of radical monomials, by norms down a
//! tower of fields.
//!
//! The monomials of `x` generate a finite group `G` of monomials modulo
//! rationals; the Q-span of `G` is a field of degree `|G|` (the monomials are
//! linearly independent, see [`super::radical`]). [`field_degree`] computes
//! `|G|` without enumerating it: per prime `p`, the exponents (in sixths) of
//! `p` in `x` generate a subgroup of Z/6 of order `6 / gcd(6, e₁, e₂, …)`,
//! and `|G|` is the product of these orders.
//!
//! The inverse removes one prime at a time. Let `K` be the field spanned by
//! the monomials of `x` without the prime `p`, and `β = p^(1/6)`.
//!
//! * If `p` occurs with an odd exponent, `β ↦ −β` is an automorphism `σ` of
//!   `K(β)` over `K(β²)` (since `β ∉ K(β²)`, by linear independence), so
//!   `x · σ(x)` has only even exponents of `p`, and
//!   `x⁻¹ = σ(x) · (x σ(x))⁻¹`. `σ(x)` is `x` with the terms of odd exponent
//!   negated.
//! * If `p` occurs only with exponents 0, 2, 4, then `x = u + vα + wα²` with
//!   `α = p^(1/3)`, `α³ = p` and `u, v, w ∈ K`, and the adjugate of
//!   multiplication by `x`, `adj = (u² − pvw) + (pw² − uv)α + (v² − uw)α²`,
//!   satisfies `x · adj = u³ + pv³ + p²w³ − 3puvw ∈ K`; so
//!   `x⁻¹ = adj · (x · adj)⁻¹`.
//!
//! Each step is a few multiplications of numbers with at most `|G|` terms,
//! so an inverse costs `O(|G|²)` coefficient products (Gaussian elimination
//! on the `|G| × |G|` multiplication matrix, which this replaces, costs
//! `O(|G|³)`). The caller refuses fields beyond [`MAX_INVERSE_DEGREE`].

use std::collections::BTreeMap;

use num_rational::BigRational;
use num_traits::One;

use super::{Number, Radical};

/// The largest degree `|G|` of the field spanned by a divisor that
/// [`Number::recip`](super::Number::recip) inverts; beyond it the inverse is
/// refused ([`super::NumberError::FieldTooLarge`]). 256 is, e.g., a sum of 8
/// square roots of distinct primes, or of 5 cube roots (3⁵ = 243); such an
/// inverse takes well under a second.
pub const MAX_INVERSE_DEGREE: u64 = 256;

/// The degree over Q of the field spanned by the monomials of the given
/// numbers (saturating at `u64::MAX`).
pub fn field_degree<'a>(xs: impl IntoIterator<Item = &'a Number>) -> u64 {
    let mut gcds: BTreeMap<u64, u8> = BTreeMap::new();
    for x in xs {
        for m in x.terms.keys() {
            for &(p, e) in m.factors() {
                let g = gcds.entry(p).or_insert(6);
                *g = gcd6(*g, e);
            }
        }
    }
    gcds.values()
        .map(|&g| u64::from(6 / g))
        .fold(1u64, u64::saturating_mul)
}

fn gcd6(a: u8, b: u8) -> u8 {
    let (mut a, mut b) = (a, b);
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// The primes of the monomials, each with the exponents (in sixths) it
/// occurs with.
fn primes(x: &Number) -> BTreeMap<u64, [bool; 6]> {
    let mut out: BTreeMap<u64, [bool; 6]> = BTreeMap::new();
    for m in x.terms.keys() {
        for &(p, e) in m.factors() {
            out.entry(p).or_insert([false; 6])[e as usize] = true;
        }
    }
    out
}

/// The exponent of `p` in a monomial (0 when absent).
fn exponent(m: &Radical, p: u64) -> u8 {
    m.factors()
        .iter()
        .find(|(q, _)| *q == p)
        .map_or(0, |&(_, e)| e)
}

/// `p^(e/6)` as a number.
fn power(p: u64, e: u8) -> Number {
    Number::from_term(BigRational::one(), Radical(vec![(p, e)]))
}

/// `x⁻¹` for `x ≠ 0`.
pub(super) fn inverse(x: &Number) -> Number {
    if x.terms.len() <= 1 {
        return x.recip().expect("a nonzero monomial is invertible");
    }
    let Some((p, exps)) = primes(x).into_iter().next_back() else {
        return x.recip().expect("a nonzero rational is invertible");
    };
    if exps[1] || exps[3] || exps[5] {
        // σ: β ↦ −β negates the terms with an odd exponent of p.
        let mut conj = x.clone();
        for (m, c) in conj.terms.iter_mut() {
            if exponent(m, p) % 2 == 1 {
                *c = -c.clone();
            }
        }
        let norm = x * &conj;
        return &conj * &inverse(&norm);
    }
    // Only exponents 0, 2, 4: x = u + v·α + w·α² with α = p^(1/3).
    let mut parts = [Number::zero(), Number::zero(), Number::zero()];
    for (m, c) in &x.terms {
        let e = exponent(m, p);
        let rest = Radical(m.0.iter().copied().filter(|&(q, _)| q != p).collect());
        parts[(e / 2) as usize].add_term(&rest, c);
    }
    let [u, v, w] = parts;
    let pn = Number::from_bigint(p.into());
    let a0 = &(&u * &u) - &(&pn * &(&v * &w));
    let a1 = &(&pn * &(&w * &w)) - &(&u * &v);
    let a2 = &(&v * &v) - &(&u * &w);
    let adj = &(&a0 + &(&a1 * &power(p, 2))) + &(&a2 * &power(p, 4));
    let norm = x * &adj;
    debug_assert!(!primes(&norm).contains_key(&p), "the norm is free of p");
    &adj * &inverse(&norm)
}
