//! The state update shared by the minimisation steppers: after a solve has
//! found the step's force `F` (the midpoint rule's `F(x̄)`, the average
//! vector field's `F̄`), both methods advance `z = [q; p]` by
//! `p' = p + τF`, `q' = q + τM⁻¹(p + (τ/2)F)` — the stage solver's form —
//! optionally with compensated (Kahan) summation whose compensation is
//! carried from step to step while the state is the one the last step left.

use super::Mass;

/// The compensation of `z` and the state the last update left.
pub(super) struct Update {
    compensated: bool,
    comp: Vec<f64>,
    z_end: Vec<f64>,
    has_end: bool,
}

impl Update {
    pub(super) fn new(n: usize, compensated: bool) -> Update {
        Update {
            compensated,
            comp: vec![0.0; 2 * n],
            z_end: vec![0.0; 2 * n],
            has_end: false,
        }
    }

    /// Forget the compensation.
    pub(super) fn reset(&mut self) {
        self.has_end = false;
        self.comp.fill(0.0);
    }

    /// Before a step: a state the caller changed does not own the
    /// compensation of the last one.
    pub(super) fn begin(&mut self, z: &[f64]) {
        if self.has_end && z != self.z_end.as_slice() {
            self.comp.fill(0.0);
        }
    }

    /// `p += τF`, `q += τM⁻¹(p + (τ/2)F)` (with the `p` before the kick).
    pub(super) fn apply(&mut self, z: &mut [f64], f: &[f64], tau: f64, mass: Mass<'_>) {
        let n = z.len() / 2;
        let (q, p) = z.split_at_mut(n);
        for k in 0..n {
            let dq = tau * (p[k] + 0.5 * tau * f[k]) / mass.get(k);
            let dp = tau * f[k];
            if self.compensated {
                kahan(&mut q[k], &mut self.comp[k], dq);
                kahan(&mut p[k], &mut self.comp[n + k], dp);
            } else {
                q[k] += dq;
                p[k] += dp;
            }
        }
        if self.compensated {
            self.z_end.copy_from_slice(z);
            self.has_end = true;
        }
    }
}

/// `*s += inc`, compensated: `comp` holds what the last additions lost.
#[inline]
fn kahan(s: &mut f64, comp: &mut f64, inc: f64) {
    let y = inc - *comp;
    let sum = *s + y;
    *comp = (sum - *s) - y;
    *s = sum;
}
