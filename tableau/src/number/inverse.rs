//! The multiplicative inverse of a sum of radical monomials.
//!
//! The monomials of `x` generate a finite group `G` of monomials modulo
//! rationals; the Q-span of `G` is closed under multiplication, hence a field
//! (a finite-dimensional integral domain), of dimension `|G|` by the linear
//! independence of the monomials. Multiplication by `x` is a linear map on
//! that span, invertible because `x ≠ 0`; `x⁻¹` is the solution `y` of
//! `M_x y = 1`, found by exact Gaussian elimination over Q. Tables use few
//! primes (e.g. `sqrt(15)` spans a group of order 2), so `|G|` stays small.

use std::collections::HashMap;

use num_rational::BigRational;
use num_traits::{One, Zero};

use super::{Number, Radical};

pub(super) fn inverse(x: &Number) -> Number {
    let basis = group(x.terms.keys());
    let index: HashMap<&Radical, usize> = basis.iter().enumerate().map(|(i, m)| (m, i)).collect();
    let n = basis.len();
    // Column j of M holds the coordinates of x · basis[j]; stored row-major.
    let mut m = vec![vec![BigRational::zero(); n + 1]; n];
    for (j, g) in basis.iter().enumerate() {
        for (r, c) in &x.terms {
            let (factor, prod) = r.mul(g);
            let i = index[&prod];
            m[i][j] += c * BigRational::from_integer(factor);
        }
    }
    m[index[&Radical::one()]][n] = BigRational::one();
    solve_in_place(&mut m);
    let mut out = Number::zero();
    for (j, g) in basis.iter().enumerate() {
        out.add_term(g, &m[j][n]);
    }
    out
}

/// The closure of the given monomials under multiplication (mod rationals).
fn group<'a>(gens: impl Iterator<Item = &'a Radical>) -> Vec<Radical> {
    let gens: Vec<&Radical> = gens.filter(|g| !g.is_one()).collect();
    let mut elems = vec![Radical::one()];
    let mut seen: std::collections::HashSet<Radical> = elems.iter().cloned().collect();
    let mut k = 0;
    while k < elems.len() {
        let e = elems[k].clone();
        for g in &gens {
            let (_, prod) = e.mul(g);
            if seen.insert(prod.clone()) {
                elems.push(prod);
            }
        }
        k += 1;
    }
    elems
}

/// Gauss–Jordan elimination on an augmented `n × (n+1)` matrix that is known
/// to be invertible; on return the last column holds the solution.
fn solve_in_place(m: &mut [Vec<BigRational>]) {
    let n = m.len();
    for col in 0..n {
        let pivot = (col..n)
            .find(|&r| !m[r][col].is_zero())
            .expect("multiplication by a nonzero field element is invertible");
        m.swap(col, pivot);
        let inv = m[col][col].recip();
        for v in m[col][col..].iter_mut() {
            *v *= &inv;
        }
        let pivot_row = m[col].clone();
        for (r, row) in m.iter_mut().enumerate() {
            if r == col || row[col].is_zero() {
                continue;
            }
            let f = row[col].clone();
            for (v, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                *v -= &f * p;
            }
        }
    }
}
