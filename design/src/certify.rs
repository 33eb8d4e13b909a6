//! The certificate: a Krawczyk test, in exact rational interval arithmetic,
//! that an exact solution of the imposed conditions lies within a radius `r`
//! of the printed coefficients, and a proof that the next order's error
//! terms are bounded away from zero there (so the order is exactly `p`).
//!
//! For the square system `F(x_D; x_free) = 0` in the determined unknowns
//! `x_D` (the free ones fixed at their printed rationals), the box
//! `X = x̃ ± r` and any nonsingular `Y`, the Krawczyk operator
//! `K(X) = x̃ − Y·F(x̃) + (I − Y·J(X))·(X − x̃)` contains every zero of `F`
//! in `X`, and `K(X) ⊂ int X` proves that `X` holds exactly one
//! (Krawczyk 1969; Moore 1977; Rump 1983). Here `x̃` and `r` are rationals,
//! `F(x̃)` is exact, `J(X)` is an enclosure of the Jacobian over `X` from
//! exact rational interval arithmetic on the derivative polynomials (no
//! rounding mode is involved anywhere), and `Y` is any rational matrix (an
//! `f64` inverse of `J(x̃)`, converted exactly): the test is a proof for
//! whatever `Y` is, and a poor `Y` only makes it fail. Componentwise,
//! `K(X) ⊂ int X` reads `|(Y·F(x̃))_i| + r·Σ_j |I − Y·J(X)|_{ij} < r`, with
//! `|·|` the magnitude of an interval, decided exactly.

// The Krawczyk sums index Y, J(X) and F(x̃) together, as the formula does.
#![allow(clippy::needless_range_loop)]

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

use crate::conditions::System;
use crate::linalg::inverse_f64;
use crate::polish::from_f64;
use crate::poly::{Interval, to_f64};

/// A proof about one printed solution.
#[derive(Clone, Debug)]
pub struct Certificate {
    /// An exact solution lies in the box of this radius (max norm) around
    /// the printed determined unknowns; it is the only one there.
    pub radius: BigRational,
    /// `max_i Σ_j |I − Y·J(X)|_{ij}`: how strongly the Krawczyk map
    /// contracts (must be < 1).
    pub contraction: f64,
    /// `max_i |(Y·F(x̃))_i| / r`.
    pub offset: f64,
    /// An error term of degree `p + 1` whose enclosure over the box excludes
    /// zero, with the enclosure: the order is exactly `p` at every point of
    /// the box.
    pub next_order: Option<(String, f64, f64)>,
}

/// Why a certificate was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Refusal {
    #[error("the Jacobian at the printed point is singular in f64")]
    Singular,
    #[error(
        "Krawczyk's test fails for radius {radius:.3e}: |Y·F(x̃)| = {offset:.3e}·r and the contraction is {contraction:.3e} (their sum must be < 1)"
    )]
    NotContained {
        radius: f64,
        offset: f64,
        contraction: f64,
    },
    #[error(
        "no error term of degree {degree} is bounded away from zero on the box, so the order is not proven to be exactly {order}"
    )]
    NextOrder { degree: usize, order: usize },
}

/// `10^-k`.
pub fn ten_to_minus(k: u32) -> BigRational {
    BigRational::new(BigInt::one(), BigInt::from(10).pow(k))
}

/// Run the Krawczyk test on the box `x ± radius` in the unknowns
/// `determined` (the others fixed at their values in `x`), and bound the
/// next order's error terms on it.
pub fn krawczyk(
    system: &System,
    x: &[BigRational],
    determined: &[usize],
    radius: &BigRational,
) -> Result<Certificate, Refusal> {
    let m = determined.len();
    let fx: Vec<BigRational> = system
        .conditions
        .iter()
        .map(|c| c.poly.eval_rational(x))
        .collect();
    let jac_polys: Vec<Vec<crate::poly::Poly>> = system
        .conditions
        .iter()
        .map(|c| determined.iter().map(|&j| c.poly.derivative(j)).collect())
        .collect();
    // Y ≈ J(x̃)⁻¹ in f64, then exact.
    let j_point: Vec<Vec<f64>> = jac_polys
        .iter()
        .map(|row| row.iter().map(|p| to_f64(&p.eval_rational(x))).collect())
        .collect();
    let y_f = inverse_f64(&j_point).ok_or(Refusal::Singular)?;
    let y: Vec<Vec<BigRational>> = y_f
        .iter()
        .map(|row| row.iter().map(|&v| from_f64(v)).collect())
        .collect();
    let boxed: Vec<Interval> = x
        .iter()
        .enumerate()
        .map(|(i, v)| {
            if determined.contains(&i) {
                Interval::around(v, radius)
            } else {
                Interval::point(v.clone())
            }
        })
        .collect();
    let j_box: Vec<Vec<Interval>> = jac_polys
        .iter()
        .map(|row| row.iter().map(|p| p.eval_interval(&boxed)).collect())
        .collect();
    let mut worst_offset = BigRational::zero();
    let mut worst_contraction = BigRational::zero();
    let mut contained = true;
    for i in 0..m {
        let mut yf = BigRational::zero();
        for k in 0..m {
            yf += &y[i][k] * &fx[k];
        }
        let mut row_sum = BigRational::zero();
        for j in 0..m {
            let mut mij = Interval::point(if i == j {
                BigRational::one()
            } else {
                BigRational::zero()
            });
            for k in 0..m {
                mij = mij.sub(&j_box[k][j].scale(&y[i][k]));
            }
            row_sum += mij.magnitude();
        }
        // |Y F|_i + r Σ_j |M_ij| < r
        if yf.abs() + radius * &row_sum >= *radius {
            contained = false;
        }
        let off = yf.abs() / radius;
        if off > worst_offset {
            worst_offset = off;
        }
        if row_sum > worst_contraction {
            worst_contraction = row_sum;
        }
    }
    let offset = to_f64(&worst_offset);
    let contraction = to_f64(&worst_contraction);
    if !contained {
        return Err(Refusal::NotContained {
            radius: to_f64(radius),
            offset,
            contraction,
        });
    }
    let next_order = system.error_terms.iter().find_map(|e| {
        let v = e.poly.eval_interval(&boxed);
        v.excludes_zero()
            .then(|| (e.word.clone(), to_f64(&v.lo), to_f64(&v.hi)))
    });
    if next_order.is_none() {
        return Err(Refusal::NextOrder {
            degree: system.order + 1,
            order: system.order,
        });
    }
    Ok(Certificate {
        radius: radius.clone(),
        contraction,
        offset,
        next_order,
    })
}

/// The smallest radius `10^-k` (k from `max_k` down to 10) for which the
/// test succeeds.
pub fn certify(
    system: &System,
    x: &[BigRational],
    determined: &[usize],
    max_k: u32,
) -> Result<Certificate, Refusal> {
    let mut last = Refusal::Singular;
    let mut k = max_k;
    while k >= 10 {
        match krawczyk(system, x, determined, &ten_to_minus(k)) {
            Ok(c) => return Ok(c),
            Err(e @ Refusal::Singular) => return Err(e),
            Err(e) => last = e,
        }
        k -= 2;
    }
    Err(last)
}
