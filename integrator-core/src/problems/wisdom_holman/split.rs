//! The Wisdom–Holman splits as [`Split`] systems, so that every drift–kick
//! sequence and composition of the library and of `butcher!` steps them:
//! part `A` is the Kepler flow (the table's drifts), part `B` the
//! interaction kick (its kicks). A near-integrable table (`SABA₄`,
//! `ABA(8,6,4)`, …) is stepped the way it was designed: `A` integrable and
//! large, `B` of the order of the planetary masses.
//!
//! The state is the split's own `w = [Q; P]`: convert with `from_inertial`
//! before the first step and with `to_inertial` for output.
//!
//! ```
//! use integrator_core::library::Leapfrog;
//! use integrator_core::problems::wisdom_holman::Jacobi;
//! use integrator_core::problems::OuterSolarSystem;
//! use integrator_core::integrate;
//!
//! let split = Jacobi::outer_solar();
//! let z0 = OuterSolarSystem.initial_state();
//! let mut w = vec![0.0; z0.len()];
//! split.from_inertial_checked(&z0, &mut w).unwrap();
//! // Leapfrog's drift–kick–drift on the split is Wisdom–Holman's kernel.
//! integrate(&Leapfrog, &split, &mut w, 0.0, 10.0, 100, |_, _, _| {}).unwrap();
//! let mut z = vec![0.0; z0.len()];
//! split.to_inertial(&w, &mut z).unwrap();
//! let e = |z: &[f64]| split.energy(z);
//! assert!(((e(&z) - e(&z0)) / e(&z0)).abs() < 1e-8);
//! ```

use super::{GradientKick, Jacobi, WhError};
use crate::split::{FlowError, PartBuffers, Split, StateSpace};

impl StateSpace for Jacobi {
    fn state_len(&self) -> usize {
        6 * self.bodies()
    }
}

/// A flow's error as the step reports it: the body and part in the words of
/// [`WhError`]; the step adds the part letter, `integrate` the step.
fn flow_error(e: WhError) -> FlowError {
    FlowError::failed(e)
}

impl Split for Jacobi {
    #[inline]
    fn flow_a(&self, h: f64, w: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
        self.kepler_flow(h, w).map_err(flow_error)
    }

    #[inline]
    fn flow_b(&self, h: f64, w: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
        self.interaction_kick(h, w).map_err(flow_error)
    }

    /// The lazy implementer's modified kick
    /// ([`Jacobi::interaction_kick_gradient`]), or the modified kick itself
    /// ([`Jacobi::interaction_kick_modified`]) as
    /// [`Jacobi::with_gradient_kick`] chose.
    #[inline]
    fn flow_b_gradient(
        &self,
        h: f64,
        gamma: f64,
        w: &mut [f64],
        _: PartBuffers<'_>,
    ) -> Result<(), FlowError> {
        match self.gradient_kick() {
            GradientKick::Lazy => self.interaction_kick_gradient(h, gamma, w),
            GradientKick::Exact => self.interaction_kick_modified(h, gamma, w),
        }
        .map_err(flow_error)
    }

    /// The kicks and drifts in lanes, the state in registers
    /// ([`Jacobi::kick_drift_run`]).
    #[inline]
    fn kick_drift_run(
        &self,
        kick: f64,
        gamma: f64,
        drift: f64,
        drift_last: f64,
        n: usize,
        w: &mut [f64],
    ) -> usize {
        Jacobi::kick_drift_run(self, kick, gamma, drift, drift_last, n, w)
    }
}
