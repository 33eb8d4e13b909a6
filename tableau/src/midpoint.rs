//! Whether a Runge–Kutta table is a composition of implicit midpoint steps,
//! decided exactly.
//!
//! The implicit midpoint rule of step `τ` is the one-stage table
//! `A = (1/2)`, `b = (1)`. Composing midpoint steps of sizes `b₁h, …, b_sh`
//! gives the diagonally implicit table with `aᵢᵢ = bᵢ/2`, `aᵢⱼ = bⱼ`
//! (`j < i`), `aᵢⱼ = 0` (`j > i`) and `cᵢ` the row sums; conversely every
//! such table is that composition (Hairer–Lubich–Wanner, *Geometric
//! Numerical Integration*, VI.4: every symplectic DIRK is of this form).
//! A solver can then step such a table as `s` successive midpoint steps —
//! for `M q̈ = −∇V(q)` each one an energy minimisation (the cloth crate's
//! `minimise` module).
//!
//! The entries are exact [`Number`]s, whose representation is canonical,
//! so the test is exact equality: no floating point decides it.
//!
//! ```
//! use tableau::{catalogue, midpoint, Table};
//!
//! let Table::Rk(rk) = catalogue::load("paper-dirk2")?.table else { unreachable!() };
//! let w = midpoint::composition_weights(&rk).expect("two half steps");
//! assert_eq!(w, vec![tableau::Number::ratio(1, 2)?, tableau::Number::ratio(1, 2)?]);
//! let Table::Rk(gauss) = catalogue::load("gauss2")?.table else { unreachable!() };
//! assert!(midpoint::composition_weights(&gauss).is_none());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::Number;
use crate::table::Rk;

/// The weights `b` when `rk` is a composition of implicit midpoint steps
/// (`aᵢᵢ = bᵢ/2`, `aᵢⱼ = bⱼ` for `j < i`, `aᵢⱼ = 0` for `j > i`, every
/// `bᵢ ≠ 0`, and `c`, when given, the row sums of `A`); `None` otherwise,
/// and for a table whose rows do not match `b` in length.
pub fn composition_weights(rk: &Rk) -> Option<Vec<Number>> {
    let s = rk.b.len();
    if s == 0 || rk.a.len() != s || rk.a.iter().any(|row| row.len() != s) {
        return None;
    }
    let half = Number::ratio(1, 2).ok()?;
    for (i, row) in rk.a.iter().enumerate() {
        if rk.b[i].is_zero() {
            return None;
        }
        for (j, a) in row.iter().enumerate() {
            let ok = match j.cmp(&i) {
                std::cmp::Ordering::Less => *a == rk.b[j],
                std::cmp::Ordering::Equal => *a == &rk.b[i] * &half,
                std::cmp::Ordering::Greater => a.is_zero(),
            };
            if !ok {
                return None;
            }
        }
    }
    if let Some(c) = &rk.c {
        if c.len() != s {
            return None;
        }
        for (ci, row) in c.iter().zip(&rk.a) {
            let mut sum = Number::zero();
            for a in row {
                sum += a;
            }
            if *ci != sum {
                return None;
            }
        }
    }
    Some(rk.b.clone())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Table, catalogue};

    fn rk(id: &str) -> Rk {
        match catalogue::load(id).unwrap().table {
            Table::Rk(rk) => rk,
            other => panic!("{id}: not an RK table: {other:?}"),
        }
    }

    #[test]
    fn the_midpoint_family_is_recognised_and_others_are_not() {
        assert_eq!(
            composition_weights(&rk("midpoint")),
            Some(vec![Number::one()])
        );
        let w = composition_weights(&rk("paper-dirk4")).expect("the triple jump");
        assert_eq!(w.len(), 3);
        assert_eq!(w[0], w[2]);
        // b₁ + b₂ + b₃ = 1 exactly, with b₂ = 1 − 2x irrational.
        assert_eq!(&(&w[0] + &w[1]) + &w[2], Number::one());
        assert!(w[1].as_rational().is_none());
        for id in [
            "gauss2",
            "gauss3",
            "implicit-euler",
            "radau2a-3",
            "lobatto3c-2",
        ] {
            assert!(composition_weights(&rk(id)).is_none(), "{id}");
        }
    }

    #[test]
    fn one_entry_off_is_refused() {
        let mut t = rk("paper-dirk2");
        assert!(composition_weights(&t).is_some());
        t.a[1][0] = Number::ratio(1, 3).unwrap();
        assert!(composition_weights(&t).is_none());
        let mut t = rk("paper-dirk2");
        t.c = Some(vec![
            Number::ratio(1, 4).unwrap(),
            Number::ratio(1, 2).unwrap(),
        ]);
        assert!(composition_weights(&t).is_none(), "c is not the row sums");
        let mut t = rk("paper-dirk2");
        t.a[0][1] = Number::ratio(1, 100).unwrap();
        assert!(composition_weights(&t).is_none(), "not lower triangular");
    }
}
