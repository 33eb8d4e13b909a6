//! The structure of `A`: explicit, diagonally implicit, fully implicit.

use serde::Serialize;

use crate::{Number, Rk};

/// How implicit a table is, from least to most (the derived order is used to
/// pick the more implicit table of a pair).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Class {
    /// `aᵢⱼ = 0` for `j ≥ i`: every stage follows from the earlier ones.
    Explicit,
    /// Lower triangular with one nonzero diagonal entry repeated on the whole
    /// diagonal: one factorisation serves every stage.
    Sdirk,
    /// Lower triangular with some nonzero diagonal entry: stage-by-stage
    /// solves of the system's size.
    Dirk,
    /// Anything else: all stages are solved together.
    Implicit,
}

impl Class {
    pub fn name(self) -> &'static str {
        match self {
            Class::Explicit => "explicit",
            Class::Sdirk => "sdirk",
            Class::Dirk => "dirk",
            Class::Implicit => "implicit",
        }
    }
}

pub fn classify(rk: &Rk) -> Class {
    let a = &rk.a;
    let s = a.len();
    let upper_zero = (0..s).all(|i| (i + 1..s).all(|j| a[i][j].is_zero()));
    if !upper_zero {
        return Class::Implicit;
    }
    let diag: Vec<&Number> = (0..s).map(|i| &a[i][i]).collect();
    if diag.iter().all(|d| d.is_zero()) {
        Class::Explicit
    } else if diag.iter().all(|d| *d == diag[0]) {
        Class::Sdirk
    } else {
        Class::Dirk
    }
}

/// Whether a partitioned pair is explicit on separable systems
/// `q' = f(p)`, `p' = g(q)`: stage `i` of `q` may use `P_j` for `j ≤ i` when
/// stage `i` of `p` uses only `Q_j` for `j < i`, or the other way round.
pub fn explicit_on_separable(q: &Rk, p: &Rk) -> bool {
    let s = q.a.len();
    let lower = |rk: &Rk, strict: bool| {
        (0..s).all(|i| ((if strict { i } else { i + 1 })..s).all(|j| rk.a[i][j].is_zero()))
    };
    (lower(q, false) && lower(p, true)) || (lower(q, true) && lower(p, false))
}
