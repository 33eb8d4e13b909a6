//! The Kepler solver's warm start in a Wisdom–Holman run: [`KeplerHistory`]
//! and the [`WarmJacobi`] split that carries one.

use std::cell::RefCell;

use super::{Jacobi, WhError};
use crate::kepler::WarmStart;
use crate::split::{FlowError, PartBuffers, Split, StateSpace};

/// The warm starts of one run's Kepler drifts
/// ([`KeplerSolver::drift_warm`](crate::kepler::KeplerSolver::drift_warm)):
/// per body, the roots of its last long solves for up to [`SLOTS`]
/// different steps `h` (a composition drifts by several coefficients per
/// step; the merged drifts of a kernel add one more).
///
/// Why the caller owns it: a split system is `&self` (its flows are maps of
/// the state alone), and a history that lived in the split would make one
/// run's bits depend on the runs before it in the same process (repeats of
/// a timing, the rows of a sweep). A run makes a fresh history at its
/// start; a checkpoint of a run in progress saves it
/// ([`to_f64s`](Self::to_f64s), [`from_f64s`](Self::from_f64s)) with the
/// state, so that the resumed run gives the same bits.
///
/// Only long solves (which the lanes never take) read or write it: a
/// short step's drift is the cold drift's bits, so the lanes, the register
/// loop of [`Jacobi::kick_drift_run`] and the scalar path agree on every
/// SIMD level with or without a history. Two are equal where their bits
/// are.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct KeplerHistory {
    /// `slots[body][k]`: `(h, s)` of a remembered solve.
    slots: Vec<[WarmStart; SLOTS]>,
    /// The slot each body fills next with a root for a new `h`.
    next: Vec<usize>,
}

/// The steps remembered per body: more than the distinct drifts of the
/// library's compositions (ABA(10,6,4) has three, merged across steps
/// four), so that none is evicted by the others.
pub const SLOTS: usize = 8;

impl KeplerHistory {
    /// An empty history for `bodies` bodies (body 0, the barycentre or the
    /// central body, has none).
    pub fn new(bodies: usize) -> Self {
        Self {
            slots: vec![[WarmStart::NONE; SLOTS]; bodies],
            next: vec![0; bodies],
        }
    }

    /// The bodies it is for.
    pub fn bodies(&self) -> usize {
        self.slots.len()
    }

    /// Body `body`'s warm start for a solve over `h` (none where no slot
    /// holds this `h`).
    pub fn get(&self, body: usize, h: f64) -> WarmStart {
        self.slots[body]
            .iter()
            .find(|w| w.h().to_bits() == h.to_bits())
            .copied()
            .unwrap_or(WarmStart::NONE)
    }

    /// Keep `warm` (a solve's root for its `h`) for body `body`: in the
    /// slot of the same `h`, else in the next slot in turn.
    pub fn put(&mut self, body: usize, warm: WarmStart) {
        let slots = &mut self.slots[body];
        if let Some(w) = slots
            .iter_mut()
            .find(|w| w.h().to_bits() == warm.h().to_bits())
        {
            *w = warm;
        } else {
            let k = self.next[body];
            slots[k] = warm;
            self.next[body] = (k + 1) % SLOTS;
        }
    }

    /// The history as doubles, for a checkpoint's exact encoding
    /// ([`Encoder::f64s`](crate::checkpoint::Encoder::f64s)): per body its
    /// next slot, then `(h, s)` per slot.
    pub fn to_f64s(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.slots.len() * (1 + 2 * SLOTS));
        for (slots, &next) in self.slots.iter().zip(&self.next) {
            out.push(next as f64);
            for w in slots {
                out.push(w.h());
                out.push(w.s());
            }
        }
        out
    }

    /// The history [`to_f64s`](Self::to_f64s) wrote, or `None` where `a`
    /// is not one (a wrong length or slot index).
    pub fn from_f64s(a: &[f64]) -> Option<Self> {
        let per = 1 + 2 * SLOTS;
        if !a.len().is_multiple_of(per) {
            return None;
        }
        let mut h = Self::new(a.len() / per);
        for (b, chunk) in a.chunks_exact(per).enumerate() {
            let next = chunk[0];
            if !(next >= 0.0 && next < SLOTS as f64 && next.fract() == 0.0) {
                return None;
            }
            h.next[b] = next as usize;
            for k in 0..SLOTS {
                h.slots[b][k] = WarmStart::new(chunk[1 + 2 * k], chunk[2 + 2 * k]);
            }
        }
        Some(h)
    }
}

/// A [`Jacobi`] split with a [`KeplerHistory`] of its own: its Kepler flow
/// is [`Jacobi::kepler_flow_warm`] where the split's
/// [`kepler_warm_start`](Jacobi::kepler_warm_start) is on, else exactly
/// [`Jacobi::kepler_flow`]; every other flow is the split's. Make one per
/// run (see [`KeplerHistory`] for why).
pub struct WarmJacobi<'a> {
    split: &'a Jacobi,
    history: RefCell<KeplerHistory>,
}

impl<'a> WarmJacobi<'a> {
    /// `split` with an empty history.
    pub fn new(split: &'a Jacobi) -> Self {
        Self::with_history(split, KeplerHistory::new(split.bodies()))
    }

    /// `split` with a history (a checkpoint's).
    pub fn with_history(split: &'a Jacobi, history: KeplerHistory) -> Self {
        Self {
            split,
            history: RefCell::new(history),
        }
    }

    /// The split.
    pub fn split(&self) -> &'a Jacobi {
        self.split
    }

    /// The history now (for a checkpoint).
    pub fn history(&self) -> KeplerHistory {
        self.history.borrow().clone()
    }

    /// The Kepler flow over `h` with this run's history.
    pub fn kepler_flow(&self, h: f64, w: &mut [f64]) -> Result<(), WhError> {
        if self.split.kepler_warm_start() {
            self.split
                .kepler_flow_warm(h, w, &mut self.history.borrow_mut())
        } else {
            self.split.kepler_flow(h, w)
        }
    }
}

impl StateSpace for WarmJacobi<'_> {
    fn state_len(&self) -> usize {
        self.split.state_len()
    }
}

impl Split for WarmJacobi<'_> {
    #[inline]
    fn flow_a(&self, h: f64, w: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
        self.kepler_flow(h, w).map_err(FlowError::failed)
    }

    #[inline]
    fn flow_b(
        &self,
        h: f64,
        w: &mut [f64],
        buf: PartBuffers<'_>,
        reuse: bool,
    ) -> Result<(), FlowError> {
        self.split.flow_b(h, w, buf, reuse)
    }

    #[inline]
    fn flow_b_gradient(
        &self,
        h: f64,
        gamma: f64,
        w: &mut [f64],
        buf: PartBuffers<'_>,
    ) -> Result<(), FlowError> {
        self.split.flow_b_gradient(h, gamma, w, buf)
    }

    /// The split's loop in lanes: it takes only steps whose drifts are all
    /// short, which leave the history as it is (see [`KeplerHistory`]).
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
        self.split
            .kick_drift_run(kick, gamma, drift, drift_last, n, w)
    }
}
