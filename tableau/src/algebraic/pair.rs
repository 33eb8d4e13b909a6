//! The product-of-fields algebras of a collocation table.
//!
//! Let `P` be monic and squarefree of degree `s` with roots `c₁, …, c_s` (the
//! nodes). Then
//!
//! * `K = Q[x]/(P)` is isomorphic to `Qˢ` through `f ↦ (f(c₁), …, f(c_s))`
//!   (Chinese remainder theorem over the real closure): one element stands
//!   for a quantity of every stage, e.g. all weights `bᵢ = B(cᵢ)` at once;
//! * `L = Q[x, y]/(P(x), Q(x, y))`, with `Q = (P(x) − P(y))/(x − y)`, is
//!   isomorphic to `Q^{s(s−1)}` through the ordered pairs `(cᵢ, cⱼ)`, `i ≠ j`
//!   (for fixed `x = cᵢ`, `Q(cᵢ, y) = ∏_{j≠i}(y − cⱼ)` is squarefree), so one
//!   element stands for every off-diagonal entry `aᵢⱼ = A(cᵢ, cⱼ)` at once.
//!
//! Both are products of fields, and an element is zero exactly when it is
//! zero at every stage (pair): an identity over all stages is decided exactly
//! and completely by reducing to the normal form (`deg_x < s`,
//! `deg_y < s − 1`) and comparing with zero. Sums over stages are traces:
//! `Σᵢ f(cᵢ) = Σₘ fₘ pₘ` with the power sums `pₘ = Σᵢ cᵢᵐ` (Newton's
//! identities), and `Σ_{j≠i} g(cᵢ, cⱼ)` is the relative trace of `L` over
//! `K`, where `y` runs over the roots of `Q(x, y)`, whose power sums are
//! `pₘ − xᵐ`.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Zero};

use super::poly::Poly;

fn q(n: i64) -> BigRational {
    BigRational::from_integer(BigInt::from(n))
}

/// An element of `L`: `Σₖ yᵏ coeffs[k](x)`, reduced (`k < s − 1`, each
/// coefficient reduced mod `P`), trailing zeros trimmed.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Pair(pub Vec<Poly>);

/// `K` and `L` for one node polynomial.
#[derive(Clone, Debug)]
pub struct Ring {
    pub s: usize,
    /// Monic, squarefree, degree `s`.
    pub p: Poly,
    /// `Q(x, y)` as coefficients of `yᵏ`, `k = 0 … s − 1` (the last is 1).
    qy: Vec<Poly>,
    /// `pₘ = Σᵢ cᵢᵐ`, `m = 0 … 2s + 4`.
    power_sums: Vec<BigRational>,
}

impl Pair {
    pub fn is_zero(&self) -> bool {
        self.0.iter().all(Poly::is_zero)
    }

    fn trim(mut self) -> Pair {
        while self.0.last().is_some_and(Poly::is_zero) {
            self.0.pop();
        }
        self
    }
}

impl Ring {
    /// `p` must be squarefree of degree ≥ 1; it is made monic.
    pub fn new(p: &Poly) -> Ring {
        let p = p.monic();
        let s = p.degree().expect("nonzero");
        assert!(
            s >= 1 && p.is_squarefree(),
            "node polynomial must be squarefree"
        );
        // Q(x, y) = Σ_m c_m Σ_{k<m} x^{m−1−k} yᵏ: coefficient of yᵏ is
        // Σ_{m>k} c_m x^{m−1−k}.
        let qy = (0..s)
            .map(|k| Poly((k + 1..=s).map(|m| p.coeff(m)).collect()).trim())
            .collect();
        let mut ps = vec![q(s as i64)];
        for k in 1..=2 * s + 4 {
            // p_k + Σ_{i=1}^{min(k−1,s)} c_{s−i} p_{k−i} + [k ≤ s] k c_{s−k} = 0
            let mut acc = BigRational::zero();
            for i in 1..=(k - 1).min(s) {
                acc += p.coeff(s - i) * &ps[k - i];
            }
            if k <= s {
                acc += p.coeff(s - k) * q(k as i64);
            }
            ps.push(-acc);
        }
        Ring {
            s,
            p,
            qy,
            power_sums: ps,
        }
    }

    /// Reduce in `K`.
    pub fn r1(&self, f: &Poly) -> Poly {
        f.rem(&self.p)
    }

    pub fn mul1(&self, f: &Poly, g: &Poly) -> Poly {
        self.r1(&f.mul(g))
    }

    /// `Σᵢ f(cᵢ)`, exactly.
    pub fn trace(&self, f: &Poly) -> BigRational {
        let f = self.r1(f);
        f.0.iter()
            .enumerate()
            .map(|(m, c)| c * &self.power_sums[m])
            .fold(BigRational::zero(), |a, b| a + b)
    }

    /// Reduce any bivariate `Σ yᵏ coeffs[k](x)` to normal form in `L`.
    pub fn reduce(&self, mut coeffs: Vec<Poly>) -> Pair {
        let d = self.s - 1;
        for k in (d..coeffs.len()).rev() {
            let c = std::mem::take(&mut coeffs[k]);
            if c.is_zero() {
                continue;
            }
            // y^d = −Σ_{j<d} qy[j](x) yʲ (Q monic in y)
            for j in 0..d {
                if !self.qy[j].is_zero() {
                    let t = c.mul(&self.qy[j]);
                    coeffs[k - d + j] = coeffs[k - d + j].sub(&t);
                }
            }
        }
        coeffs.truncate(d);
        Pair(coeffs.into_iter().map(|c| self.r1(&c)).collect()).trim()
    }

    pub fn from_x(&self, f: &Poly) -> Pair {
        self.reduce(vec![f.clone()])
    }

    pub fn from_y(&self, g: &Poly) -> Pair {
        self.reduce(g.0.iter().map(|c| Poly::constant(c.clone())).collect())
    }

    pub fn add(&self, a: &Pair, b: &Pair) -> Pair {
        let n = a.0.len().max(b.0.len());
        let z = Poly::zero();
        Pair(
            (0..n)
                .map(|k| a.0.get(k).unwrap_or(&z).add(b.0.get(k).unwrap_or(&z)))
                .collect(),
        )
        .trim()
    }

    pub fn sub(&self, a: &Pair, b: &Pair) -> Pair {
        let n = a.0.len().max(b.0.len());
        let z = Poly::zero();
        Pair(
            (0..n)
                .map(|k| a.0.get(k).unwrap_or(&z).sub(b.0.get(k).unwrap_or(&z)))
                .collect(),
        )
        .trim()
    }

    pub fn mul(&self, a: &Pair, b: &Pair) -> Pair {
        if a.0.is_empty() || b.0.is_empty() {
            return Pair::default();
        }
        let mut out = vec![Poly::zero(); a.0.len() + b.0.len() - 1];
        for (i, x) in a.0.iter().enumerate() {
            for (j, y) in b.0.iter().enumerate() {
                out[i + j] = out[i + j].add(&x.mul(y));
            }
        }
        self.reduce(out)
    }

    /// `g(x, y) ↦ g(y, x)` (an automorphism of `L`: `Q` is symmetric).
    pub fn swap(&self, a: &Pair) -> Pair {
        let mut out: Vec<Poly> = vec![Poly::zero(); self.s];
        for (k, c) in a.0.iter().enumerate() {
            for (m, v) in c.0.iter().enumerate() {
                out[m] = out[m].add(&Poly::monomial(v.clone(), k));
            }
        }
        self.reduce(out)
    }

    /// `g(x, y) ↦ g(1 − x, 1 − y)`, an automorphism of `L` when
    /// `P(1 − x) = ±P(x)`.
    pub fn reflect(&self, a: &Pair) -> Pair {
        let one_minus = Poly::from_ints(&[1, -1]);
        let mut out: Vec<Poly> = Vec::new();
        for (k, c) in a.0.iter().enumerate() {
            let cx = c.compose(&one_minus);
            // (1 − y)^k = Σ_j C(k, j) (−1)^j y^j
            let yk = one_minus.pow(k);
            for (j, coef) in yk.0.iter().enumerate() {
                if out.len() <= j {
                    out.resize(j + 1, Poly::zero());
                }
                out[j] = out[j].add(&cx.scale(coef));
            }
        }
        self.reduce(out)
    }

    /// `Σ_{j≠i} g(cᵢ, cⱼ)` as an element of `K` (the relative trace).
    pub fn trace_y(&self, a: &Pair) -> Poly {
        let mut acc = Poly::zero();
        for (k, c) in a.0.iter().enumerate() {
            // p_k − x^k
            let t = Poly::constant(self.power_sums[k].clone())
                .sub(&Poly::monomial(BigRational::one(), k));
            acc = acc.add(&c.mul(&t));
        }
        self.r1(&acc)
    }

    /// `F(x, y)·u(y)` where `F = ∫₀ˣ P(t)/(t − y) dt` — the building block of
    /// `aᵢⱼ = ∫₀^{cᵢ} ℓⱼ`; returns the bivariate polynomial `F` (unreduced)
    /// as coefficients of `yʲ`.
    pub fn lagrange_integral(&self) -> Vec<Poly> {
        // P(t)/(t − y) = Σ_k t^k q_k(y), q_k(y) = Σ_{m>k} c_m y^{m−1−k};
        // F = Σ_k x^{k+1}/(k+1) q_k(y): coefficient of yʲ is
        // Σ_k x^{k+1}/(k+1) c_{k+1+j}.
        let s = self.s;
        (0..s)
            .map(|j| {
                let mut v = vec![BigRational::zero(); s + 1];
                for k in 0..s {
                    let m = k + 1 + j;
                    if m <= s {
                        v[k + 1] = self.p.coeff(m) / q(k as i64 + 1);
                    }
                }
                Poly(v).trim()
            })
            .collect()
    }

    /// The reduced normal form's value bounds need the coefficients; this
    /// gives the bivariate normal form as `(i, j, coeff)` of `xⁱ yʲ`.
    pub fn terms(a: &Pair) -> Vec<(usize, usize, BigRational)> {
        let mut out = Vec::new();
        for (j, c) in a.0.iter().enumerate() {
            for (i, v) in c.0.iter().enumerate() {
                if !v.is_zero() {
                    out.push((i, j, v.clone()));
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebraic::poly::shifted_legendre;

    #[test]
    fn traces_are_power_sums() {
        let r = Ring::new(&shifted_legendre(3));
        // Σ cᵢ = 3/2 for nodes symmetric about 1/2.
        assert_eq!(r.trace(&Poly::x()), BigRational::new(3.into(), 2.into()));
        assert_eq!(r.trace(&Poly::one()), q(3));
        // Σ_{j≠i} 1 = s − 1
        assert_eq!(r.trace_y(&r.from_x(&Poly::one())), Poly::constant(q(2)));
        // Σ_{j≠i} cⱼ = Σ c − cᵢ
        let t = r.trace_y(&r.from_y(&Poly::x()));
        assert_eq!(t, Poly(vec![BigRational::new(3.into(), 2.into()), q(-1)]));
    }

    #[test]
    fn q_vanishes_and_swap_is_an_involution() {
        let r = Ring::new(&shifted_legendre(4));
        let g = r.mul(
            &r.from_x(&Poly::from_ints(&[1, 2, 3])),
            &r.from_y(&Poly::from_ints(&[0, 5, 0, 7])),
        );
        assert_eq!(r.swap(&r.swap(&g)), g);
        assert_eq!(r.reflect(&r.reflect(&g)), g);
        // x + y + … : Q(x, y) itself reduces to zero
        let qq = r.reduce(r.qy.clone());
        assert!(qq.is_zero());
    }
}
