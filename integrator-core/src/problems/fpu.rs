//! The Fermi–Pasta–Ulam chain with stiff springs (Hairer–Lubich–Wanner,
//! *Geometric Numerical Integration*, I.5.1): `2m` unit masses joined
//! alternately by stiff linear springs (frequency `ω`) and soft cubic-force
//! springs, fixed at both ends,
//!
//! `H = ½ Σ pᵢ² + ω²/4 Σᵢ₌₁ᵐ (q₂ᵢ − q₂ᵢ₋₁)² + Σᵢ₌₀ᵐ (q₂ᵢ₊₁ − q₂ᵢ)⁴`, `q₀ = q₂ₘ₊₁ = 0`.
//!
//! With `ω = 50` the stiff springs oscillate 50 times faster than the soft
//! dynamics: explicit methods need `hω` below their stability limit, and the
//! energy exchange between the stiff springs happens on a time scale of
//! `ω`. The reference is numerical (see [`Fpu::reference`]).

use super::reference_solution;
use crate::system::Separable;

/// The chain with `m` stiff springs (`2m` masses) and stiff frequency `omega`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fpu {
    pub m: usize,
    pub omega: f64,
}

impl Fpu {
    /// HLW's setting: `m = 3`, `ω = 50`.
    pub fn stiff() -> Fpu {
        Fpu { m: 3, omega: 50.0 }
    }

    /// HLW's initial values (I.5.1, in the original coordinates): the first
    /// stiff spring is excited with energy of order one, the first soft
    /// spring is displaced, everything else at rest.
    pub fn start(&self) -> Vec<f64> {
        let n = 2 * self.m;
        let mut z = vec![0.0; 2 * n];
        // x₁ = (q₁ + q₂)/√2 = 1, x_{m+1} = (q₂ − q₁)/√2 = 1/ω,
        // y₁ = (p₁ + p₂)/√2 = 1, y_{m+1} = (p₂ − p₁)/√2 = 1.
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let (x1, xs, y1, ys) = (1.0, 1.0 / self.omega, 1.0, 1.0);
        z[0] = s * (x1 - xs);
        z[1] = s * (x1 + xs);
        z[n] = s * (y1 - ys);
        z[n + 1] = s * (y1 + ys);
        z
    }

    /// The state at time `t` by Sofroniou–Spaletta's order-10 composition
    /// with `40ω` steps per unit time and compensated summation.
    pub fn reference(&self, z0: &[f64], t: f64) -> Vec<f64> {
        reference_solution(self, z0, t, 40.0 * self.omega)
    }

    /// [`Fpu::reference`], or why there is none (a span beyond the budget,
    /// [`super::try_reference_solution`]).
    pub fn try_reference(&self, z0: &[f64], t: f64) -> Result<Vec<f64>, String> {
        super::try_reference_solution(self, z0, t, 40.0 * self.omega)
    }

    /// The energy of each stiff spring, `Iⱼ = ½(ẋ_{m+j}² + ω²x_{m+j}²)` with
    /// `x_{m+j} = (q₂ⱼ − q₂ⱼ₋₁)/√2`: nearly constant in sum (an adiabatic
    /// invariant), exchanged among the springs on the time scale `ω`.
    pub fn stiff_energies(&self, z: &[f64]) -> Vec<f64> {
        let n = 2 * self.m;
        let (q, p) = z.split_at(n);
        let s = std::f64::consts::FRAC_1_SQRT_2;
        (0..self.m)
            .map(|j| {
                let x = s * (q[2 * j + 1] - q[2 * j]);
                let v = s * (p[2 * j + 1] - p[2 * j]);
                0.5 * (v * v + self.omega * self.omega * x * x)
            })
            .collect()
    }
}

impl Separable for Fpu {
    fn dof(&self) -> usize {
        2 * self.m
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        0.5 * p.iter().map(|x| x * x).sum::<f64>()
    }
    fn potential(&self, q: &[f64]) -> f64 {
        let n = 2 * self.m;
        let at = |i: usize| if i == 0 || i > n { 0.0 } else { q[i - 1] };
        let stiff: f64 = (1..=self.m)
            .map(|i| (at(2 * i) - at(2 * i - 1)).powi(2))
            .sum();
        let soft: f64 = (0..=self.m)
            .map(|i| (at(2 * i + 1) - at(2 * i)).powi(4))
            .sum();
        0.25 * self.omega * self.omega * stiff + soft
    }
    fn velocity(&self, p: &[f64], out: &mut [f64]) {
        out.copy_from_slice(p);
    }
    fn force(&self, q: &[f64], out: &mut [f64]) {
        let n = 2 * self.m;
        let at = |i: usize| if i == 0 || i > n { 0.0 } else { q[i - 1] };
        out.fill(0.0);
        let w2 = 0.5 * self.omega * self.omega;
        for i in 1..=self.m {
            // Stiff spring between masses 2i−1 and 2i: V = ω²/4 d², dV/dd = ω²/2 d.
            let d = at(2 * i) - at(2 * i - 1);
            out[2 * i - 1] -= w2 * d;
            out[2 * i - 2] += w2 * d;
        }
        for i in 0..=self.m {
            // Soft spring between masses 2i and 2i+1 (0 and 2m+1 are walls).
            let d = at(2 * i + 1) - at(2 * i);
            let f = 4.0 * d * d * d;
            if 2 * i < n {
                out[2 * i] -= f;
            }
            if i >= 1 {
                out[2 * i - 1] += f;
            }
        }
    }
}
