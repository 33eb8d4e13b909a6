//! Symmetry: the method equals its adjoint `Φ*_h = Φ_{−h}⁻¹`.
//!
//! The adjoint of `(A, b, c)` is `a*ᵢⱼ = b_{s+1−j} − a_{s+1−i, s+1−j}`,
//! `b*ᵢ = b_{s+1−i}`, `c*ᵢ = 1 − c_{s+1−i}` (HLW V.2, Theorem 2.3). Two
//! irreducible tables define the same method exactly when one is a
//! permutation of the other's stages, so on the irreducible form the test
//! "the adjoint is a stage permutation of the table" is exact both ways.
//! For a drift–kick sequence the adjoint is the reversed sequence, and
//! sequences in normal form (zeros dropped, neighbours merged) define the same
//! map for every separable Hamiltonian exactly when they are equal.

use crate::table::Splitting;
use crate::{Number, Rk};

pub fn adjoint(rk: &Rk) -> Rk {
    let s = rk.b.len();
    let r = |i: usize| s - 1 - i;
    Rk {
        a: (0..s)
            .map(|i| (0..s).map(|j| &rk.b[r(j)] - &rk.a[r(i)][r(j)]).collect())
            .collect(),
        b: (0..s).map(|i| rk.b[r(i)].clone()).collect(),
        c: rk
            .c
            .as_ref()
            .map(|c| (0..s).map(|i| Number::one() - &c[r(i)]).collect()),
    }
}

/// Whether the tables (sharing stages) are a stage permutation of `other`.
pub fn equal_up_to_permutation(tables: &[Rk], other: &[Rk]) -> bool {
    let s = tables[0].b.len();
    if other[0].b.len() != s {
        return false;
    }
    let mut perm = vec![usize::MAX; s];
    let mut used = vec![false; s];
    search(tables, other, 0, &mut perm, &mut used)
}

/// Backtracking over the image of stage `i`, checking every entry between
/// already-assigned stages as soon as both ends are known.
fn search(t: &[Rk], o: &[Rk], i: usize, perm: &mut [usize], used: &mut [bool]) -> bool {
    let s = perm.len();
    if i == s {
        return true;
    }
    for k in 0..s {
        if used[k] {
            continue;
        }
        perm[i] = k;
        let fits = t.iter().zip(o).all(|(x, y)| {
            x.b[i] == y.b[k]
                && match (&x.c, &y.c) {
                    (Some(cx), Some(cy)) => cx[i] == cy[k],
                    _ => true,
                }
                && (0..=i).all(|j| x.a[i][j] == y.a[k][perm[j]] && x.a[j][i] == y.a[perm[j]][k])
        });
        if fits {
            used[k] = true;
            if search(t, o, i + 1, perm, used) {
                return true;
            }
            used[k] = false;
        }
    }
    perm[i] = usize::MAX;
    false
}

/// A drift–kick sequence is symmetric when its normal form is a palindrome
/// ([`Splitting::flows`]: with gradient kicks, each flow's coefficient and
/// gradient; the adjoint `Φ₋ₕ⁻¹` of `exp(kh B + gh³ C)` is itself, since
/// `(−h)³ = −h³`, so the adjoint of a sequence is the sequence reversed).
pub fn splitting_is_symmetric(s: &Splitting) -> bool {
    let nf = s.flows();
    nf.iter().eq(nf.iter().rev())
}
