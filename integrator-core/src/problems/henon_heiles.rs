//! The Hénon–Heiles system, `H = ½|p|² + ½|q|² + q₁²q₂ − q₂³/3`, in its
//! chaotic regime (energy 1/8; Hairer–Lubich–Wanner I.3.2 show the
//! Poincaré section). No closed-form flow exists and trajectories separate
//! exponentially, so the reference is a high-accuracy numerical solution
//! (see [`reference`]) valid only over short times; long runs are judged by
//! their energy error.

use super::reference_solution;
use crate::system::Separable;

/// `H = ½(p₁² + p₂²) + ½(q₁² + q₂²) + q₁²q₂ − q₂³/3`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HenonHeiles;

impl HenonHeiles {
    /// A chaotic initial state at energy 1/8: `q = (0, 0)`, `p = (1/2, 0)`.
    pub fn chaotic_start() -> [f64; 4] {
        [0.0, 0.0, 0.5, 0.0]
    }

    /// The state at time `t` from `z0`, by Sofroniou–Spaletta's order-10
    /// composition with 2000 steps per unit time and compensated summation:
    /// its error is below 1e-13 up to `t = 10` (checked against a run with
    /// half the step in the tests).
    pub fn reference(&self, z0: &[f64], t: f64) -> Vec<f64> {
        reference_solution(self, z0, t, Self::REFERENCE_STEPS_PER_UNIT)
    }

    /// [`HenonHeiles::reference`], or why there is none (a span beyond the
    /// budget, [`super::try_reference_solution`]).
    pub fn try_reference(&self, z0: &[f64], t: f64) -> Result<Vec<f64>, String> {
        super::try_reference_solution(self, z0, t, Self::REFERENCE_STEPS_PER_UNIT)
    }

    const REFERENCE_STEPS_PER_UNIT: f64 = 2000.0;
}

impl Separable for HenonHeiles {
    fn dof(&self) -> usize {
        2
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        0.5 * (p[0] * p[0] + p[1] * p[1])
    }
    fn potential(&self, q: &[f64]) -> f64 {
        let (x, y) = (q[0], q[1]);
        0.5 * (x * x + y * y) + x * x * y - y * y * y / 3.0
    }
    fn velocity(&self, p: &[f64], out: &mut [f64]) {
        out[0] = p[0];
        out[1] = p[1];
    }
    fn force(&self, q: &[f64], out: &mut [f64]) {
        let (x, y) = (q[0], q[1]);
        out[0] = -x - 2.0 * x * y;
        out[1] = -y - x * x + y * y;
    }
}
