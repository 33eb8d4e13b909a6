//! The polish: Newton's method on the square system in exact rational
//! arithmetic, the iterate rounded to a dyadic rational (`2^-BITS`, about 72
//! digits) after every step.
//!
//! **Why rationals, not a multiprecision float crate.** The conditions are
//! polynomials with rational coefficients, so their values and Jacobian at a
//! rational point are exact rationals; the one rounding is the explicit one
//! of the iterate, whose error is known (`≤ 2^-(BITS+1)`), so nothing about
//! the polish depends on a library's rounding modes, and no dependency is
//! added (the workspace already has num-rational). The cost is that the
//! numbers grow within a step (degree `d` multiplies their size by `d`),
//! which is nothing for a handful of unknowns and degree ≤ 9.
//!
//! **Which unknowns.** With more unknowns than conditions, the ones left
//! free are fixed first at their solver values rounded to
//! [`FREE_DIGITS`] decimals (they are then exact as printed, a choice, as
//! McLachlan's `b₁ = −3/73`), and the others (chosen by complete pivoting on
//! the Jacobian, so that their square block is well conditioned) are
//! polished.

use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

use crate::conditions::System;
use crate::linalg::{pivot_columns, solve_rational};
use crate::poly::{Poly, to_f64};
use crate::solve::{Compiled, Solution};

/// The iterate is rounded to a multiple of `2^-BITS`.
pub const BITS: u64 = 240;

/// The digits after the point of a free unknown, fixed before the polish.
pub const FREE_DIGITS: u32 = 20;

/// The digits after the point printed for a determined unknown.
pub const DIGITS: u32 = 50;

/// A solution in high precision.
#[derive(Clone, Debug)]
pub struct Polished {
    /// Every unknown, exactly as it will be printed: determined ones rounded
    /// to [`DIGITS`] decimals, free ones to [`FREE_DIGITS`].
    pub x: Vec<BigRational>,
    /// The unknowns polished (indices into the system's names).
    pub determined: Vec<usize>,
    /// The unknowns fixed at a printed value.
    pub free: Vec<usize>,
    /// Newton steps taken.
    pub steps: usize,
    /// `max |F_i|` at the polished dyadic iterate, before printing (a
    /// rational, exactly).
    pub residual: BigRational,
}

/// Why a polish failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PolishError {
    #[error(
        "the conditions' Jacobian has rank {rank} < {m} at the solution: the conditions are dependent there, so there is no square system to polish"
    )]
    Rank { rank: usize, m: usize },
    #[error("the Jacobian became singular during the polish")]
    Singular,
    #[error("Newton did not converge in high precision (residual {0:.3e} after {1} steps)")]
    NoConvergence(f64, usize),
}

/// `x` rounded to the nearest multiple of `10^-digits` (ties away from 0).
pub fn round_decimal(x: &BigRational, digits: u32) -> BigRational {
    let scale = BigInt::from(10).pow(digits);
    round_to(x, &scale)
}

fn round_to(x: &BigRational, scale: &BigInt) -> BigRational {
    let y = x * BigRational::from_integer(scale.clone());
    let (q, r) = y.numer().div_rem(y.denom());
    // |r| / den ≥ 1/2 → round away from zero.
    let twice = r.abs() * 2;
    let q = if &twice >= y.denom() {
        if y.is_negative() { q - 1 } else { q + 1 }
    } else {
        q
    };
    BigRational::new(q, scale.clone())
}

/// An exact rational from an `f64`.
pub fn from_f64(v: f64) -> BigRational {
    BigRational::from_float(v).unwrap_or_else(BigRational::zero)
}

/// A decimal with `digits` digits after the point, exactly `x` when `x` is a
/// multiple of `10^-digits` (else rounded).
pub fn decimal_text(x: &BigRational, digits: u32) -> String {
    let scale = BigInt::from(10).pow(digits);
    let r = round_to(x, &scale);
    let n = (r * BigRational::from_integer(scale)).to_integer();
    let neg = n.is_negative();
    let s = n.abs().to_string();
    let d = digits as usize;
    let s = if s.len() <= d {
        format!("{}{}", "0".repeat(d + 1 - s.len()), s)
    } else {
        s
    };
    let (int, frac) = s.split_at(s.len() - d);
    let frac = frac.trim_end_matches('0');
    let body = if frac.is_empty() {
        int.to_string()
    } else {
        format!("{int}.{frac}")
    };
    if neg { format!("-{body}") } else { body }
}

fn max_abs(v: &[BigRational]) -> BigRational {
    v.iter()
        .map(Signed::abs)
        .max()
        .unwrap_or_else(BigRational::zero)
}

/// Polish one solution of the solver.
pub fn polish(system: &System, solution: &Solution) -> Result<Polished, PolishError> {
    let c = Compiled::new(system);
    let m = system.conditions.len();
    let n = system.unknowns();
    let determined = pivot_columns(&c.condition_jacobian(&solution.x), 1e-10);
    if determined.len() < m {
        return Err(PolishError::Rank {
            rank: determined.len(),
            m,
        });
    }
    let free: Vec<usize> = (0..n).filter(|i| !determined.contains(i)).collect();
    let mut x: Vec<BigRational> = solution.x.iter().map(|&v| from_f64(v)).collect();
    for &i in &free {
        x[i] = round_decimal(&x[i], FREE_DIGITS);
    }
    let jac: Vec<Vec<Poly>> = system
        .conditions
        .iter()
        .map(|cnd| determined.iter().map(|&j| cnd.poly.derivative(j)).collect())
        .collect();
    let scale = BigInt::one() << BITS;
    let target = BigRational::new(BigInt::one(), BigInt::from(10).pow(70));
    let mut steps = 0;
    let mut residual;
    loop {
        let f: Vec<BigRational> = system
            .conditions
            .iter()
            .map(|cnd| cnd.poly.eval_rational(&x))
            .collect();
        residual = max_abs(&f);
        if residual < target || steps >= 12 {
            break;
        }
        let j: Vec<Vec<BigRational>> = jac
            .iter()
            .map(|row| row.iter().map(|p| p.eval_rational(&x)).collect())
            .collect();
        let neg: Vec<BigRational> = f.iter().map(|v| -v).collect();
        let dx = solve_rational(&j, &neg).ok_or(PolishError::Singular)?;
        for (k, &i) in determined.iter().enumerate() {
            x[i] = round_to(&(&x[i] + &dx[k]), &scale);
        }
        steps += 1;
        // Below the rounding of the iterate there is nothing left to gain.
        if max_abs(&dx) < BigRational::new(BigInt::one(), scale.clone()) {
            let f: Vec<BigRational> = system
                .conditions
                .iter()
                .map(|cnd| cnd.poly.eval_rational(&x))
                .collect();
            residual = max_abs(&f);
            break;
        }
    }
    let converged = residual < BigRational::new(BigInt::one(), BigInt::from(10).pow(60));
    if !converged {
        return Err(PolishError::NoConvergence(to_f64(&residual), steps));
    }
    for &i in &determined {
        x[i] = round_decimal(&x[i], DIGITS);
    }
    Ok(Polished {
        x,
        determined,
        free,
        steps,
        residual,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimals() {
        let q = |n: i64, d: i64| BigRational::new(n.into(), d.into());
        assert_eq!(decimal_text(&q(-1, 3), 5), "-0.33333");
        assert_eq!(decimal_text(&q(2, 3), 5), "0.66667");
        assert_eq!(decimal_text(&q(5, 2), 5), "2.5");
        assert_eq!(decimal_text(&q(-3, 1), 5), "-3");
        assert_eq!(round_decimal(&q(1, 8), 2), q(13, 100));
    }
}
