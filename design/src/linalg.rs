//! Small dense linear algebra: Gaussian elimination with partial pivoting in
//! `f64` (the solver's steps, the certificate's approximate inverse) and in
//! exact rationals (the polish's Newton steps). The systems have at most a
//! few dozen unknowns, so nothing here needs to be clever; the `f64` loops
//! sum in a fixed order with plain products (no fused multiply–add).

// Dense elimination reads as the textbook writes it, with indices into
// several rows at once; iterators would hide which row is which.
#![allow(clippy::needless_range_loop)]

use num_rational::BigRational;
use num_traits::Zero;

/// Solve `a·x = b` for square `a` (row-major `n × n`); `None` when a pivot
/// is below `1e-300` or not finite.
pub fn solve_f64(a: &[Vec<f64>], b: &[f64]) -> Option<Vec<f64>> {
    let n = b.len();
    let mut m: Vec<Vec<f64>> = a.to_vec();
    let mut r = b.to_vec();
    for col in 0..n {
        let mut piv = col;
        for row in col + 1..n {
            if m[row][col].abs() > m[piv][col].abs() {
                piv = row;
            }
        }
        let p = m[piv][col];
        if p.is_nan() || p.abs() <= 1e-300 || !p.is_finite() {
            return None;
        }
        m.swap(col, piv);
        r.swap(col, piv);
        for row in col + 1..n {
            let f = m[row][col] / m[col][col];
            if f == 0.0 {
                continue;
            }
            for k in col..n {
                let t = f * m[col][k];
                m[row][k] -= t;
            }
            let t = f * r[col];
            r[row] -= t;
        }
    }
    let mut x = vec![0.0; n];
    for row in (0..n).rev() {
        let mut s = r[row];
        for k in row + 1..n {
            let t = m[row][k] * x[k];
            s -= t;
        }
        x[row] = s / m[row][row];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// Solve `a·x = b` exactly; `None` when `a` is singular.
pub fn solve_rational(a: &[Vec<BigRational>], b: &[BigRational]) -> Option<Vec<BigRational>> {
    let n = b.len();
    let mut m: Vec<Vec<BigRational>> = a.to_vec();
    let mut r = b.to_vec();
    for col in 0..n {
        let piv = (col..n).find(|&row| !m[row][col].is_zero())?;
        m.swap(col, piv);
        r.swap(col, piv);
        for row in col + 1..n {
            if m[row][col].is_zero() {
                continue;
            }
            let f = &m[row][col] / &m[col][col];
            for k in col..n {
                let t = &f * &m[col][k];
                m[row][k] -= t;
            }
            let t = &f * &r[col];
            r[row] -= t;
        }
    }
    let mut x = vec![BigRational::zero(); n];
    for row in (0..n).rev() {
        let mut s = r[row].clone();
        for k in row + 1..n {
            s -= &m[row][k] * &x[k];
        }
        x[row] = s / &m[row][row];
    }
    Some(x)
}

/// The columns of a `m × n` matrix (`m ≤ n`) that Gaussian elimination with
/// complete pivoting picks first: `m` columns whose square submatrix is well
/// conditioned, or fewer when the rank is smaller (pivots below `tol` times
/// the largest entry are not taken).
pub fn pivot_columns(a: &[Vec<f64>], tol: f64) -> Vec<usize> {
    let mut m: Vec<Vec<f64>> = a.to_vec();
    let rows = m.len();
    let cols = m.first().map_or(0, Vec::len);
    let scale = m.iter().flatten().fold(0.0_f64, |acc, v| acc.max(v.abs()));
    let mut chosen = Vec::new();
    let mut free_rows: Vec<usize> = (0..rows).collect();
    let mut free_cols: Vec<usize> = (0..cols).collect();
    while !free_rows.is_empty() && !free_cols.is_empty() {
        let mut best = (0, 0, 0.0_f64);
        for (ri, &r) in free_rows.iter().enumerate() {
            for (ci, &c) in free_cols.iter().enumerate() {
                if m[r][c].abs() > best.2 {
                    best = (ri, ci, m[r][c].abs());
                }
            }
        }
        if !scale.is_finite() || best.2 <= tol * scale {
            break;
        }
        let r = free_rows.remove(best.0);
        let c = free_cols.remove(best.1);
        chosen.push(c);
        for &r2 in &free_rows {
            let f = m[r2][c] / m[r][c];
            for k in 0..cols {
                let t = f * m[r][k];
                m[r2][k] -= t;
            }
        }
    }
    chosen.sort_unstable();
    chosen
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves() {
        let a = vec![vec![2.0, 1.0], vec![1.0, 3.0]];
        let x = solve_f64(&a, &[3.0, 5.0]).unwrap();
        assert!((x[0] - 0.8).abs() < 1e-15 && (x[1] - 1.4).abs() < 1e-15);
        let q = |n: i64| BigRational::from_integer(n.into());
        let ar = vec![vec![q(2), q(1)], vec![q(1), q(3)]];
        let xr = solve_rational(&ar, &[q(3), q(5)]).unwrap();
        assert_eq!(xr[0], BigRational::new(4.into(), 5.into()));
        assert_eq!(pivot_columns(&[vec![0.0, 1.0, 1e-20]], 1e-12), vec![1]);
    }
}
