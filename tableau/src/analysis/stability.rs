//! The stability function `R(z) = 1 + z bᵀ(I − zA)⁻¹𝟙 = P(z)/Q(z)` with
//! `P(z) = det(I − zA + z𝟙bᵀ)` and `Q(z) = det(I − zA)` (Hairer–Wanner II,
//! IV.3), as an exact rational function in lowest terms.
//!
//! Both determinants have degree at most `s`, so they are found exactly by
//! evaluating at `z = 0, 1, …, s` and interpolating. `|R(iy)| = 1` for every
//! real `y` exactly when `P(z)P(−z) = Q(z)Q(−z)` as polynomials (the two
//! sides are polynomials in `y` after `z = iy`, equal on all of ℝ).

use crate::{Number, Rk};

/// A polynomial with exact coefficients, constant term first, no trailing
/// zeros (the zero polynomial is empty).
#[derive(Clone, Debug, PartialEq)]
pub struct Poly(pub Vec<Number>);

impl Poly {
    fn trim(mut self) -> Self {
        while self.0.last().is_some_and(Number::is_zero) {
            self.0.pop();
        }
        self
    }

    pub fn degree(&self) -> Option<usize> {
        self.0.len().checked_sub(1)
    }

    fn mul(&self, other: &Poly) -> Poly {
        if self.0.is_empty() || other.0.is_empty() {
            return Poly(Vec::new());
        }
        let mut out = vec![Number::zero(); self.0.len() + other.0.len() - 1];
        for (i, x) in self.0.iter().enumerate() {
            for (j, y) in other.0.iter().enumerate() {
                out[i + j] += &(x * y);
            }
        }
        Poly(out).trim()
    }

    /// `p(−z)`.
    fn reflect(&self) -> Poly {
        Poly(
            self.0
                .iter()
                .enumerate()
                .map(|(k, c)| if k % 2 == 1 { -c } else { c.clone() })
                .collect(),
        )
    }

    fn scale(&self, x: &Number) -> Poly {
        Poly(self.0.iter().map(|c| c * x).collect()).trim()
    }

    /// Quotient and remainder of exact polynomial division.
    fn div_rem(&self, d: &Poly) -> (Poly, Poly) {
        let dd = d.degree().expect("division by the zero polynomial");
        let lead_inv = d.0[dd].recip().expect("leading coefficient is nonzero");
        let mut rem = self.0.clone();
        let mut quot = vec![Number::zero(); self.0.len().saturating_sub(dd).max(1)];
        while rem.len() > dd && !rem.is_empty() {
            let k = rem.len() - 1 - dd;
            let f = &rem[rem.len() - 1] * &lead_inv;
            for (j, dc) in d.0.iter().enumerate() {
                rem[k + j] -= &(&f * dc);
            }
            quot[k] = f;
            rem.pop();
            while rem.last().is_some_and(Number::is_zero) {
                rem.pop();
            }
        }
        (Poly(quot).trim(), Poly(rem).trim())
    }

    fn gcd(a: &Poly, b: &Poly) -> Poly {
        let (mut a, mut b) = (a.clone(), b.clone());
        while !b.0.is_empty() {
            let (_, r) = a.div_rem(&b);
            a = b;
            b = r;
        }
        a
    }

    /// The polynomial in `z` as text in the grammar (`1 + z/2 + z^2/12`).
    pub fn to_text(&self) -> String {
        if self.0.is_empty() {
            return "0".into();
        }
        let mut out = String::new();
        for (k, c) in self.0.iter().enumerate() {
            if c.is_zero() {
                continue;
            }
            let z = match k {
                0 => String::new(),
                1 => "z".into(),
                _ => format!("z^{k}"),
            };
            let neg = c.signum() == std::cmp::Ordering::Less;
            let mag = c.abs();
            let coef = if mag.is_rational() {
                mag.to_string()
            } else {
                format!("({mag})")
            };
            let term = match (k, mag.is_one(), mag.as_rational()) {
                (0, _, _) => coef,
                (_, true, _) => z,
                (_, false, Some(r)) if r.numer() == &1.into() => format!("{z}/{}", r.denom()),
                _ => format!("{coef}*{z}"),
            };
            if out.is_empty() {
                if neg {
                    out.push('-');
                }
            } else {
                out.push_str(if neg { " - " } else { " + " });
            }
            out.push_str(&term);
        }
        out
    }
}

/// `R(z) = P(z)/Q(z)` in lowest terms with `Q(0) = 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct StabilityFunction {
    pub numerator: Poly,
    pub denominator: Poly,
}

impl StabilityFunction {
    pub fn of(rk: &Rk) -> StabilityFunction {
        let s = rk.b.len();
        let ones_b = |z: &Number, i: usize, j: usize| &(z * &rk.b[j]) - &(z * &rk.a[i][j]);
        let points: Vec<Number> = (0..=s as i64).map(Number::from).collect();
        let p_vals: Vec<Number> = points
            .iter()
            .map(|z| {
                det((0..s)
                    .map(|i| (0..s).map(|j| ident(i, j) + ones_b(z, i, j)).collect())
                    .collect())
            })
            .collect();
        let q_vals: Vec<Number> = points
            .iter()
            .map(|z| {
                det((0..s)
                    .map(|i| (0..s).map(|j| ident(i, j) - z * &rk.a[i][j]).collect())
                    .collect())
            })
            .collect();
        let p = interpolate(&points, &p_vals);
        let q = interpolate(&points, &q_vals);
        let g = Poly::gcd(&p, &q);
        let (mut p, _) = p.div_rem(&g);
        let (mut q, _) = q.div_rem(&g);
        // Normalise Q(0) = 1 (Q(0) ≠ 0 since Q(0) = det I = 1 before reduction).
        let q0 = q.0[0].recip().expect("Q(0) is nonzero");
        p = p.scale(&q0);
        q = q.scale(&q0);
        StabilityFunction {
            numerator: p,
            denominator: q,
        }
    }

    /// `|R(iy)| = 1` for all real `y`.
    pub fn unimodular_on_imaginary_axis(&self) -> bool {
        let lhs = self.numerator.mul(&self.numerator.reflect());
        let rhs = self.denominator.mul(&self.denominator.reflect());
        lhs == rhs
    }

    pub fn to_text(&self) -> String {
        if self.denominator.degree() == Some(0) {
            self.numerator.to_text()
        } else {
            format!(
                "({})/({})",
                self.numerator.to_text(),
                self.denominator.to_text()
            )
        }
    }
}

fn ident(i: usize, j: usize) -> Number {
    if i == j {
        Number::one()
    } else {
        Number::zero()
    }
}

/// Exact determinant by Gaussian elimination over the field.
fn det(mut m: Vec<Vec<Number>>) -> Number {
    let n = m.len();
    let mut d = Number::one();
    for col in 0..n {
        let Some(p) = (col..n).find(|&r| !m[r][col].is_zero()) else {
            return Number::zero();
        };
        if p != col {
            m.swap(p, col);
            d = -d;
        }
        let pivot = m[col][col].clone();
        d = &d * &pivot;
        let inv = pivot.recip().expect("pivot is nonzero");
        for r in col + 1..n {
            if m[r][col].is_zero() {
                continue;
            }
            let f = &m[r][col] * &inv;
            let (top, bottom) = m.split_at_mut(r);
            for (x, y) in bottom[0][col..n].iter_mut().zip(&top[col][col..n]) {
                *x -= &(&f * y);
            }
        }
    }
    d
}

/// The polynomial of degree < n through `(xₖ, yₖ)` (Newton's divided
/// differences, exact).
fn interpolate(x: &[Number], y: &[Number]) -> Poly {
    let n = x.len();
    let mut coef = y.to_vec();
    for k in 1..n {
        for i in (k..n).rev() {
            let num = &coef[i] - &coef[i - 1];
            let den = &x[i] - &x[i - k];
            coef[i] = num.checked_div(&den).expect("distinct nodes");
        }
    }
    // Expand the Newton form into monomials (Horner from the top).
    let mut p = Poly(vec![coef[n - 1].clone()]);
    for i in (0..n - 1).rev() {
        p = p.mul(&Poly(vec![-&x[i], Number::one()]));
        let mut v = p.0;
        if v.is_empty() {
            v.push(Number::zero());
        }
        v[0] += &coef[i];
        p = Poly(v).trim();
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn implicit_midpoint_is_the_11_pade() {
        let rk = Rk {
            a: vec![vec![Number::ratio(1, 2).unwrap()]],
            b: vec![Number::one()],
            c: None,
        };
        let r = StabilityFunction::of(&rk);
        assert_eq!(r.to_text(), "(1 + z/2)/(1 - z/2)");
        assert!(r.unimodular_on_imaginary_axis());
    }

    #[test]
    fn explicit_euler() {
        let rk = Rk {
            a: vec![vec![Number::zero()]],
            b: vec![Number::one()],
            c: None,
        };
        let r = StabilityFunction::of(&rk);
        assert_eq!(r.to_text(), "1 + z");
        assert!(!r.unimodular_on_imaginary_axis());
    }
}
