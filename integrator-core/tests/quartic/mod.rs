//! `H = (q² + p²)/2 + εq⁴/4` split as the harmonic oscillator `A` (its flow
//! a rotation) and the quartic kick `B`: a near-integrable system whose
//! `ε²` terms do not vanish (`{{A, B}, B} ∝ q⁶`), shared by the tests that
//! measure generalised orders.

use integrator_core::{FlowError, PartBuffers, Split, StateSpace};

/// `H = (q² + p²)/2 + ε q⁴/4`, split as the oscillator and the quartic kick,
/// with the exact gradient kick: `{V,{T,V}} = −V'² = −ε²q⁶`, so
/// `exp(hB + γ[B,[A,B]])` is `p ← p − hεq³ + 6γε²q⁵`.
pub struct Quartic {
    pub eps: f64,
}

impl StateSpace for Quartic {
    fn state_len(&self) -> usize {
        2
    }
}

impl Split for Quartic {
    fn flow_a(&self, h: f64, z: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
        let (s, c) = h.sin_cos();
        let (q, p) = (z[0], z[1]);
        z[0] = c * q + s * p;
        z[1] = c * p - s * q;
        Ok(())
    }
    fn flow_b(&self, h: f64, z: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
        z[1] -= h * self.eps * z[0].powi(3);
        Ok(())
    }
    fn flow_b_gradient(
        &self,
        h: f64,
        gamma: f64,
        z: &mut [f64],
        _: PartBuffers<'_>,
    ) -> Result<(), FlowError> {
        let q = z[0];
        z[1] += -h * self.eps * q.powi(3) + 6.0 * gamma * self.eps * self.eps * q.powi(5);
        Ok(())
    }
}
