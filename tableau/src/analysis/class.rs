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
/// `q' = f(p)`, `p' = g(q)`: stage value `Qᵢ` needs `f(Pⱼ)` wherever
/// `aᵢⱼ ≠ 0` and `Pᵢ` needs `g(Qⱼ)` wherever `âᵢⱼ ≠ 0`. The stages can be
/// computed one after another without solving anything exactly when this
/// dependency graph has no cycle (Störmer–Verlet as the Lobatto IIIA–IIIB
/// pair is explicit although neither table is strictly lower triangular).
pub fn explicit_on_separable(q: &Rk, p: &Rk) -> bool {
    separable_stage_order(q, p).is_some()
}

/// An order in which the stages of a pair can be computed explicitly on
/// separable systems: node `i < s` is `Qᵢ`, node `s + i` is `Pᵢ`. `None` when
/// the dependency graph has a cycle (the pair is implicit there). Among the
/// ready nodes the smallest comes first, so the order is deterministic.
pub fn separable_stage_order(q: &Rk, p: &Rk) -> Option<Vec<usize>> {
    let s = q.a.len();
    // Nodes 0..s are the Qᵢ, s..2s the Pᵢ; edges point to what a node needs.
    let needs = |node: usize| -> Vec<usize> {
        if node < s {
            (0..s)
                .filter(|&j| !q.a[node][j].is_zero())
                .map(|j| s + j)
                .collect()
        } else {
            (0..s).filter(|&j| !p.a[node - s][j].is_zero()).collect()
        }
    };
    let edges: Vec<Vec<usize>> = (0..2 * s).map(needs).collect();
    let mut pending: Vec<usize> = edges.iter().map(Vec::len).collect();
    let mut done = vec![false; 2 * s];
    let mut order = Vec::with_capacity(2 * s);
    while let Some(n) = (0..2 * s).find(|&n| !done[n] && pending[n] == 0) {
        done[n] = true;
        order.push(n);
        for (m, e) in edges.iter().enumerate() {
            pending[m] -= e.iter().filter(|&&k| k == n).count();
        }
    }
    (order.len() == 2 * s).then_some(order)
}
