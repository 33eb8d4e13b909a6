//! Reduction to an irreducible table (Hairer–Wanner, *Solving ODEs II*,
//! IV.12; Butcher, *Numerical Methods for ODEs*, 381).
//!
//! Two tables define the same map when one is a reduced form of the other:
//! stages that never reach the output can be dropped (DJ-reduction), and
//! stages that always take the same value can be merged (S-reduction).
//! Symplecticity and symmetry are decided exactly on the irreducible form,
//! where the algebraic conditions are both sufficient and necessary. The
//! tables of a partitioned pair share their stages and are reduced together.

use crate::{Number, Rk};

/// The irreducible form of tables sharing their stages, and whether anything
/// was removed.
pub fn reduce(tables: &[&Rk]) -> (Vec<Rk>, bool) {
    let mut cur: Vec<Rk> = tables.iter().map(|t| (*t).clone()).collect();
    let mut changed = false;
    loop {
        let (next, dj) = dj_reduce(&cur);
        let (next, s) = s_reduce(&next);
        if !dj && !s {
            return (cur, changed);
        }
        changed = true;
        cur = next;
    }
}

/// Drop the stages on which the output does not depend.
fn dj_reduce(tables: &[Rk]) -> (Vec<Rk>, bool) {
    let s = tables[0].b.len();
    let mut needed: Vec<bool> = (0..s)
        .map(|j| tables.iter().any(|t| !t.b[j].is_zero()))
        .collect();
    loop {
        let mut grew = false;
        for i in 0..s {
            if !needed[i] {
                continue;
            }
            for (j, need) in needed.iter_mut().enumerate() {
                if !*need && tables.iter().any(|t| !t.a[i][j].is_zero()) {
                    *need = true;
                    grew = true;
                }
            }
        }
        if !grew {
            break;
        }
    }
    let keep: Vec<usize> = (0..s).filter(|&j| needed[j]).collect();
    if keep.len() == s || keep.is_empty() {
        return (tables.to_vec(), false);
    }
    let out = tables
        .iter()
        .map(|t| Rk {
            a: keep
                .iter()
                .map(|&i| keep.iter().map(|&j| t.a[i][j].clone()).collect())
                .collect(),
            b: keep.iter().map(|&j| t.b[j].clone()).collect(),
            c: t.c
                .as_ref()
                .map(|c| keep.iter().map(|&j| c[j].clone()).collect()),
        })
        .collect();
    (out, true)
}

/// Merge stages that take equal values for every problem: the coarsest
/// partition of the stages such that, for every table, the sums of `aᵢⱼ` over
/// each class `J` agree for all `i` in a class (and so do the given `cᵢ`).
fn s_reduce(tables: &[Rk]) -> (Vec<Rk>, bool) {
    let s = tables[0].b.len();
    let mut class: Vec<usize> = vec![0; s];
    // Start from the given abscissae: stages at different times differ.
    if tables.iter().any(|t| t.c.is_some()) {
        class = refine(&class, |i| {
            tables
                .iter()
                .filter_map(|t| t.c.as_ref().map(|c| c[i].clone()))
                .collect()
        });
    }
    loop {
        let n_classes = class.iter().max().map_or(0, |m| m + 1);
        let next = refine(&class, |i| {
            let mut key = Vec::new();
            for t in tables {
                for k in 0..n_classes {
                    let mut sum = Number::zero();
                    for j in (0..s).filter(|&j| class[j] == k) {
                        sum += &t.a[i][j];
                    }
                    key.push(sum);
                }
            }
            key
        });
        if next == class {
            break;
        }
        class = next;
    }
    let n_classes = class.iter().max().map_or(0, |m| m + 1);
    if n_classes == s {
        return (tables.to_vec(), false);
    }
    let rep: Vec<usize> = (0..n_classes)
        .map(|k| class.iter().position(|&c| c == k).unwrap())
        .collect();
    let out = tables
        .iter()
        .map(|t| {
            let sum_over = |row: &[Number], k: usize| {
                (0..s)
                    .filter(|&j| class[j] == k)
                    .fold(Number::zero(), |acc, j| acc + &row[j])
            };
            Rk {
                a: rep
                    .iter()
                    .map(|&i| (0..n_classes).map(|k| sum_over(&t.a[i], k)).collect())
                    .collect(),
                b: (0..n_classes).map(|k| sum_over(&t.b, k)).collect(),
                c: t.c
                    .as_ref()
                    .map(|c| rep.iter().map(|&i| c[i].clone()).collect()),
            }
        })
        .collect();
    (out, true)
}

/// Split each class by the key of its members; classes are renumbered in
/// order of first appearance so that equal partitions compare equal.
fn refine(class: &[usize], key: impl Fn(usize) -> Vec<Number>) -> Vec<usize> {
    let mut seen: Vec<(usize, Vec<Number>)> = Vec::new();
    class
        .iter()
        .enumerate()
        .map(|(i, &c)| {
            let k = (c, key(i));
            match seen.iter().position(|x| *x == k) {
                Some(p) => p,
                None => {
                    seen.push(k);
                    seen.len() - 1
                }
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn n(x: i64) -> Number {
        Number::from(x)
    }
    fn half() -> Number {
        Number::ratio(1, 2).unwrap()
    }

    #[test]
    fn irreducible_tables_are_unchanged() {
        let midpoint = Rk {
            a: vec![vec![half()]],
            b: vec![n(1)],
            c: None,
        };
        let (out, changed) = reduce(&[&midpoint]);
        assert!(!changed);
        assert_eq!(out[0], midpoint);
    }

    #[test]
    fn duplicate_stages_merge_and_dead_stages_drop() {
        // Implicit midpoint written with two identical stages and weights 1/2,
        // plus a third stage that never reaches the output.
        let q = Number::ratio(1, 4).unwrap();
        let rk = Rk {
            a: vec![
                vec![q.clone(), q.clone(), n(0)],
                vec![q.clone(), q, n(0)],
                vec![n(1), n(0), n(7)],
            ],
            b: vec![half(), half(), n(0)],
            c: None,
        };
        let (out, changed) = reduce(&[&rk]);
        assert!(changed);
        assert_eq!(
            out[0],
            Rk {
                a: vec![vec![half()]],
                b: vec![n(1)],
                c: None
            }
        );
    }
}
