//! Wisdom–Holman methods in a comparison: any splitting of the library (a
//! drift–kick sequence or composition, `symlab list`'s `splittings`) stepped
//! on the Jacobi split `H = H_Kepler + H_interaction` of an N-body problem,
//! drifts as exact Kepler flows and kicks as the interaction
//! ([`integrator_core::problems::wisdom_holman`]). `wh:leapfrog` is the
//! classical Wisdom–Holman map; `wh:ID` for a near-integrable table (SABA,
//! ABA(8,6,4), …) is the method its authors designed.
//!
//! The problem's state stays the inertial `z = [x; p]`: a run converts it to
//! Jacobi coordinates before the first step and back for every observation
//! and at the end, so errors are measured as for every other method. The
//! timed run converts twice (start and end), as REBOUND's WHFast does with
//! its safe mode off.
//!
//! A user's N-body problem (inertial state `[x; p]`, body 0 the central
//! mass) gets these methods through one constructor:
//!
//! ```
//! use compare::Method;
//! use integrator_core::problems::OuterSolarSystem;
//! use integrator_core::problems::wisdom_holman::Jacobi;
//!
//! let split = Jacobi::outer_solar(); // or Jacobi::new(G, &masses, names)
//! let m: Method<OuterSolarSystem> = Method::wisdom_holman("wh:kahan-li8", &split).unwrap();
//! assert_eq!(m.id(), "wh:kahan-li8");
//! assert!(Method::<OuterSolarSystem>::wisdom_holman("wh:rk4", &split).is_err());
//! ```

use std::cell::Cell;

use integrator_core::problems::wisdom_holman::Jacobi;
use integrator_core::scheme::SplitWorkspace;
use integrator_core::split::{FlowError, PartBuffers, Split, StateSpace};
use integrator_core::{Scheme, Step};

use crate::error::{CompareError, Result};
use crate::method::{Fixed, Method};
use crate::problem::{Family, Problem};
use crate::stepper::{Outcome, Status, Stepper, Workspace};

/// The prefix of the Wisdom–Holman method ids.
pub const PREFIX: &str = "wh:";

/// A splitting `M` on the Jacobi split of an N-body problem, as a
/// [`Stepper`] of the problem's inertial state.
pub struct WhStepper<M> {
    scheme: M,
    split: Jacobi,
}

impl<M> WhStepper<M> {
    pub fn new(scheme: M, split: Jacobi) -> Self {
        WhStepper { scheme, split }
    }
}

/// The split with its interaction kicks counted: one kick is one N-body
/// force evaluation, the `evals` of a Wisdom–Holman row.
pub struct Counting<'a> {
    split: &'a Jacobi,
    kicks: Cell<u64>,
}

impl StateSpace for Counting<'_> {
    fn state_len(&self) -> usize {
        self.split.state_len()
    }
}

impl Split for Counting<'_> {
    fn flow_a(
        &self,
        h: f64,
        w: &mut [f64],
        buf: PartBuffers<'_>,
        reuse: bool,
    ) -> std::result::Result<(), FlowError> {
        self.split.flow_a(h, w, buf, reuse)
    }
    fn flow_b(
        &self,
        h: f64,
        w: &mut [f64],
        buf: PartBuffers<'_>,
        reuse: bool,
    ) -> std::result::Result<(), FlowError> {
        self.kicks.set(self.kicks.get() + 1);
        self.split.flow_b(h, w, buf, reuse)
    }
}

fn failed(step: usize, reason: impl ToString) -> Status {
    Status::SolverFailed {
        step,
        reason: reason.to_string(),
    }
}

impl<M> WhStepper<M>
where
    M: for<'a> Step<Counting<'a>, Workspace = SplitWorkspace>,
{
    fn run_observed(
        &self,
        counting: &Counting<'_>,
        z: &mut [f64],
        h: f64,
        n: usize,
        compensated: bool,
        observe: &mut dyn FnMut(usize, f64, &[f64]) -> bool,
    ) -> Status {
        if !(h.is_finite() && h != 0.0) {
            return failed(0, format!("step size h = {h} must be finite and nonzero"));
        }
        let mut w = vec![0.0; z.len()];
        if let Err(e) = self.split.from_inertial_checked(z, &mut w) {
            return failed(0, e);
        }
        if !observe(0, 0.0, z) {
            return Status::Stopped { step: 0 };
        }
        let mut ws = self.scheme.workspace(counting);
        ws.set_compensated(compensated);
        for k in 0..n {
            let t = k as f64 * h;
            if let Err(e) = self
                .scheme
                .step_reusing(counting, t, h, &mut w, &mut ws, k > 0)
            {
                return failed(k + 1, e);
            }
            if let Err(e) = self.split.to_inertial(&w, z) {
                return failed(k + 1, e);
            }
            if z.iter().any(|x| !x.is_finite()) {
                return Status::Diverged { step: k + 1 };
            }
            if !observe(k + 1, (k + 1) as f64 * h, z) {
                return Status::Stopped { step: k + 1 };
            }
        }
        Status::Ok
    }
}

impl<P, M> Stepper<P> for WhStepper<M>
where
    P: Problem,
    M: Step<Jacobi, Workspace = SplitWorkspace>
        + for<'a> Step<Counting<'a>, Workspace = SplitWorkspace>
        + Send
        + Sync,
{
    fn observed(
        &self,
        _sys: &P,
        z: &mut [f64],
        h: f64,
        n: usize,
        compensated: bool,
        observe: &mut dyn FnMut(usize, f64, &[f64]) -> bool,
    ) -> Outcome {
        let counting = Counting {
            split: &self.split,
            kicks: Cell::new(0),
        };
        let status = self.run_observed(&counting, z, h, n, compensated, observe);
        Outcome {
            status,
            evals: counting.kicks.get(),
            newton_iterations: 0,
            fixed_point_iterations: 0,
            factorizations: 0,
            steps: None,
        }
    }

    fn bare(&self, _sys: &P, z: &mut [f64], h: f64, n: usize) -> bool {
        let mut w = vec![0.0; z.len()];
        if self.split.from_inertial(z, &mut w).is_err() {
            return false;
        }
        let mut ws = Step::<Jacobi>::workspace(&self.scheme, &self.split);
        for k in 0..n {
            let t = k as f64 * h;
            if self
                .scheme
                .step_reusing(&self.split, t, h, &mut w, &mut ws, k > 0)
                .is_err()
            {
                return false;
            }
        }
        self.split.to_inertial(&w, z).is_ok() && z.iter().all(|x| x.is_finite())
    }
}

/// The facts of a `wh:ID` row: the splitting's verified order (for general
/// parts `A`, `B`: see [`integrator_core::split`]) and symplecticity.
pub(crate) fn fixed<P, M>(id: &str, scheme: M, split: &Jacobi) -> Method<P>
where
    P: Problem,
    M: Scheme
        + Step<Jacobi, Workspace = SplitWorkspace>
        + for<'a> Step<Counting<'a>, Workspace = SplitWorkspace>
        + Send
        + Sync,
{
    Method::Fixed(Fixed {
        id: id.to_string(),
        order: M::INFO.order,
        symplectic: M::INFO.symplectic_separable,
        family: Family::Splitting,
        interpreted: false,
        stepper: Box::new(WhStepper::new(scheme, split.clone())),
    })
}

/// `wh:ID` on `split`, or an error naming the id: `ID` must be a splitting
/// of the library (`symlab list`: a drift–kick sequence or composition).
pub fn method<P: Problem>(id: &str, split: &Jacobi) -> Result<Method<P>> {
    let Some(base) = id.strip_prefix(PREFIX) else {
        return Err(CompareError::method(
            id,
            format!("method '{id}' is not a Wisdom–Holman id ({PREFIX}ID)"),
        ));
    };
    crate::library::wh_method(id, base, split).ok_or_else(|| {
        CompareError::method(
            id,
            format!(
                "method '{id}': '{base}' is not a splitting of the library; Wisdom–Holman steps a drift–kick sequence or composition: {}",
                crate::library::SPLITTING_IDS.join(", ")
            ),
        )
    })
}

/// Every `wh:ID`.
pub fn ids() -> Vec<String> {
    crate::library::SPLITTING_IDS
        .iter()
        .map(|id| format!("{PREFIX}{id}"))
        .collect()
}
