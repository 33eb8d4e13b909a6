//! Symplecticity: `W = BA + AᵀB − bbᵀ = 0` for a Runge–Kutta table and
//! `bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ = 0` for a partitioned pair (Hairer–Lubich–Wanner,
//! *Geometric Numerical Integration*, Theorems VI.4.3, VI.4.6 and VI.4.7).
//!
//! The conditions are sufficient for every table and necessary for
//! irreducible ones, so the verdict is taken on the irreducible form (see
//! [`super::reduce`]); the nonzero entries are reported for the table as
//! written.

use serde::Serialize;

use crate::{Number, Rk};

/// One entry of `W` (or of the partitioned condition) that does not vanish.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WEntry {
    pub i: usize,
    pub j: usize,
    #[serde(serialize_with = "crate::analysis::serialize_display")]
    pub value: Number,
}

/// `Wᵢⱼ = bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ` for the tables `(A, b)` and `(Â, b̂)`; with
/// `Â = A` this is the Runge–Kutta matrix `BA + AᵀB − bbᵀ`.
pub fn w_matrix(q: &Rk, p: &Rk) -> Vec<Vec<Number>> {
    let s = q.b.len();
    (0..s)
        .map(|i| {
            (0..s)
                .map(|j| &q.b[i] * &p.a[i][j] + &p.b[j] * &q.a[j][i] - &q.b[i] * &p.b[j])
                .collect()
        })
        .collect()
}

pub fn nonzero_entries(w: &[Vec<Number>]) -> Vec<WEntry> {
    let mut out = Vec::new();
    for (i, row) in w.iter().enumerate() {
        for (j, v) in row.iter().enumerate() {
            if !v.is_zero() {
                out.push(WEntry {
                    i,
                    j,
                    value: v.clone(),
                });
            }
        }
    }
    out
}

pub fn vanishes(w: &[Vec<Number>]) -> bool {
    w.iter().all(|row| row.iter().all(Number::is_zero))
}
