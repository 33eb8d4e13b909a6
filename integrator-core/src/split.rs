//! Split systems: `H = A + B`, where the exact flows of the parts `A` and
//! `B` are known (Kepler motion and an interaction kick; a linear part
//! solved exactly and a nonlinear one), and a drift–kick sequence or
//! composition is a product of those flows.
//!
//! A drift–kick sequence never needed `T` and `V` as such: a drift is the
//! exact flow of `T(p)` for a time `cᵢh`, a kick the exact flow of `V(q)`.
//! So every drift–kick sequence and composition of the library and of
//! `butcher!` steps any [`Split`] system, with the code `butcher!` emits for
//! the table (drift ↦ [`flow_a`](Split::flow_a), kick ↦
//! [`flow_b`](Split::flow_b)), and a [`Separable`] system is the special
//! case `A = T`, `B = V` through a blanket impl that keeps what the
//! separable step always did: compensated summation of every drift and
//! kick, and first same as last (the velocity or force of the previous
//! step's last operation reused).
//!
//! # Order
//!
//! The order of a splitting for general `A` and `B` is the order the
//! verifier decides for the drift–kick sequence on separable `H` with a
//! general `T(p)` (`ORDER`, `INFO.order`), and no more. The reason is the
//! free Lie algebra: the error of a composition of the flows of `A` and `B`
//! is a series of nested Poisson brackets (Lie brackets of the vector
//! fields) of `A` and `B`, and for `H = T(p) + V(q)` with general `T` and
//! `V` no linear relation holds among the brackets up to the orders
//! checked beyond those that hold for any `A`, `B` (e.g. antisymmetry and
//! the Jacobi identity) — unlike `T = ½pᵀM⁻¹p`, where
//! `{V, {V, {V, T}}} = 0` and the Runge–Kutta–Nyström orders (`order_rkn`)
//! are higher. The order conditions of the sequence for general `T` and `V`
//! are therefore those of the free Lie algebra on two generators: the
//! conditions of a splitting for any `A` and `B`. An `order_rkn` claim does
//! not carry over to a split system whose parts lack that structure.
//!
//! # Three parts
//!
//! The trait has two parts: a `butcher!` table is a word in two letters
//! (drift and kick), and the verifier's order conditions are those of two
//! generators. A system `A + B + C` is stepped by making one of the flows a
//! composition itself, e.g. `flow_b` the Strang step `φ_{C,h/2} ∘ φ_{B,h} ∘
//! φ_{C,h/2}`; that is second order in the split of `B + C`, so the order
//! of the whole step is at most 2 unless the inner composition is of the
//! scheme's order. Three-letter tables and their order conditions are not
//! built.
//!
//! ```
//! use integrator_core::split::{FlowError, PartBuffers, Split, StateSpace};
//! use integrator_core::{integrate, library::Leapfrog};
//!
//! /// `H = ω(q² + p²)/2 + ε(qp)²/2`: a rotation and a squeeze along the
//! /// hyperbolae `qp = const`, both exact; not of the form `T(p) + V(q)`.
//! struct RotationSqueeze { omega: f64, eps: f64 }
//!
//! impl StateSpace for RotationSqueeze {
//!     fn state_len(&self) -> usize { 2 }
//! }
//! impl Split for RotationSqueeze {
//!     fn flow_a(&self, h: f64, z: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
//!         let (s, c) = (self.omega * h).sin_cos();
//!         let (q, p) = (z[0], z[1]);
//!         z[0] = c * q + s * p;
//!         z[1] = c * p - s * q;
//!         Ok(())
//!     }
//!     fn flow_b(&self, h: f64, z: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
//!         let g = (self.eps * z[0] * z[1] * h).exp();
//!         z[0] *= g;
//!         z[1] /= g;
//!         Ok(())
//!     }
//! }
//!
//! let sys = RotationSqueeze { omega: 1.0, eps: 0.5 };
//! let energy = |z: &[f64]| 0.5 * (z[0] * z[0] + z[1] * z[1]) + 0.25 * (z[0] * z[1]).powi(2);
//! let mut z = [1.0, 0.5];
//! let e0 = energy(&z);
//! let mut drift: f64 = 0.0;
//! integrate(&Leapfrog, &sys, &mut z, 0.0, 0.01, 1000, |_, _, z| {
//!     drift = drift.max((energy(z) - e0).abs());
//! })
//! .unwrap();
//! assert!(drift < 1e-4, "{drift}"); // a symplectic method: bounded energy error
//! ```

use crate::error::SolveError;
use crate::system::{OdeSystem, Separable};

/// A system whose state is one vector of known length: what
/// [`integrate`](crate::integrate) checks a state against before the first
/// step. Every [`OdeSystem`] (hence every Hamiltonian) is one, with
/// `state_len = dim`; a [`Split`] system that is not an `OdeSystem` says
/// its length itself.
pub trait StateSpace {
    /// The length of the state `z`.
    fn state_len(&self) -> usize;
}

impl<S: OdeSystem + ?Sized> StateSpace for S {
    #[inline]
    fn state_len(&self) -> usize {
        self.dim()
    }
}

// `Part` and `FlowError` live in `crate::error` (which names them in
// `SolveError::Flow`); they are this module's vocabulary and re-exported here.
pub use crate::error::{FlowError, Part};

/// The memory a flow keeps between its calls, owned by the step's
/// workspace ([`SplitWorkspace`](crate::scheme::SplitWorkspace) on the
/// slice path, [`SplitCarry`](crate::fixed::SplitCarry) on the fixed-size
/// path) so that stepping never allocates. Each part has its own pair of
/// vectors, each at least [`Split::buffer_len`] long (the state's length on
/// the fixed-size path). A flow that needs none of it ignores it.
#[derive(Debug)]
pub struct PartBuffers<'a> {
    /// The flow's last evaluation (the separable drift's velocity, the
    /// kick's force), kept for first same as last (`reuse`).
    pub eval: &'a mut [f64],
    /// The rounding errors of the flow's last update of the state, carried
    /// into the next (compensated summation).
    pub err: &'a mut [f64],
    /// Whether the step asks for compensated summation of the updates
    /// (the workspace's flag, default on).
    pub compensated: bool,
}

/// A system `H = A + B` stepped through the exact flows of its parts: what
/// every drift–kick sequence and composition steps (drift ↦ `flow_a`, kick
/// ↦ `flow_b`, each for the time `cᵢh` of the table's coefficient).
///
/// The order of a scheme on a split system is its `ORDER`: the order the
/// verifier decides for separable `H` with general `T(p)`, which by the
/// free Lie algebra argument (see the [module documentation](self)) is the
/// order of the splitting for any `A` and `B`. A scheme is symplectic on a
/// split system when the flows are (exact flows of Hamiltonians are), and
/// symmetric schemes are symmetric when the flows are exact (`φ_{−h} =
/// φ_h⁻¹`).
///
/// Every [`Separable`] system is a `Split` one (`A = T`, `B = V`; blanket
/// impl). Implement it for a system that is not separable but whose parts
/// have known flows; such a type also implements [`StateSpace`] (unless it
/// is an [`OdeSystem`] or a Hamiltonian, which are `StateSpace` already).
#[diagnostic::on_unimplemented(
    message = "`{Self}` is neither a separable Hamiltonian nor a split system",
    label = "`{Self}` implements neither `Separable` nor `Split`",
    note = "drift–kick sequences and compositions are products of the exact flows of two parts, so they step only systems that provide them: `Separable` ones (drifts and kicks) or ones that implement `Split`"
)]
pub trait Split: StateSpace {
    /// Whether the step checks the state for non-finite values after every
    /// flow, so that a flow that returns one stops the run with an error
    /// naming the part ([`FlowError::NonFinite`]) rather than only the step.
    /// On for every `Split` system unless it says otherwise; off for
    /// separable systems, whose drifts and kicks are the arithmetic of the
    /// scheme itself and whose non-finite values
    /// [`integrate`](crate::integrate) reports at the step that makes them
    /// (the check would cost a pass over the state per drift and kick).
    const CHECK_FINITE: bool = true;

    /// The length of each vector of [`PartBuffers`] on the slice path
    /// (default: the state's length; separable systems need `dof`).
    fn buffer_len(&self) -> usize {
        self.state_len()
    }

    /// `z ← φ_{A,h}(z)`: the exact flow of part `A` for the time `h` (any
    /// sign: symmetric schemes have negative coefficients). `reuse` is true
    /// when the previous operation on `z` was this same flow, which left
    /// `z` as it is now (first same as last across two steps): an
    /// evaluation kept in `buf.eval` that the flow itself does not change
    /// may be reused.
    fn flow_a(
        &self,
        h: f64,
        z: &mut [f64],
        buf: PartBuffers<'_>,
        reuse: bool,
    ) -> Result<(), FlowError>;

    /// `z ← φ_{B,h}(z)`: the exact flow of part `B`, as
    /// [`flow_a`](Split::flow_a).
    fn flow_b(
        &self,
        h: f64,
        z: &mut [f64],
        buf: PartBuffers<'_>,
        reuse: bool,
    ) -> Result<(), FlowError>;

    /// `z ← exp(h·B + γ·[B,[A,B]])(z)`: a *gradient kick* (modified kick),
    /// the flow of `B` for the time `h` with the bracket term of weight `γ`
    /// (a table's gradient `g` gives `γ = g·h_step³`;
    /// [`tableau::Splitting`]). Where `A`'s kinetic part is `pᵀM⁻¹p/2` and
    /// `B = V(q)`, `{V,{T,V}} = −|∇V|²_{M⁻¹}`, so this is the kick of the
    /// potential `V − (γ/h)|∇V|²_{M⁻¹}`: `p += h·F + 2γ·(∂F/∂q)·M⁻¹F`
    /// (Wisdom, Holman & Touma 1996). A system may take it exactly or, as
    /// their "lazy implementer's" kick, as `p += h·F(q + (2γ/h)·M⁻¹F(q))`,
    /// which differs by `O(γ²/h·∂³V·F²)`, terms of the third power of `B`
    /// (the Wisdom–Holman implementation says which it does).
    ///
    /// The default refuses: a system without a known `M` (every
    /// [`Separable`] one among them, whose `T` need not be quadratic) has
    /// no gradient kick, and a table that has them cannot step it.
    fn flow_b_gradient(
        &self,
        h: f64,
        gamma: f64,
        z: &mut [f64],
        buf: PartBuffers<'_>,
    ) -> Result<(), FlowError> {
        let _ = (h, gamma, z, buf);
        Err(FlowError::failed(
            "this split system has no gradient kick (Split::flow_b_gradient): a table with gradient kicks (`kick_gradient`) steps only systems that provide one, e.g. the Jacobi split of an N-body problem",
        ))
    }

    /// Up to `n` steps of a kick then a drift, `z ← φ_{A,d}(φ_{B,kick}(z))`
    /// (the kick a [gradient kick](Split::flow_b_gradient) where `gamma` is
    /// nonzero; `d = drift`, for the last of the `n` steps `drift_last`):
    /// the loop of a drift–kick–drift kernel whose drifts are merged
    /// across steps ([`Sequence::steps_merged`](crate::sequence::Sequence::steps_merged),
    /// Wisdom–Holman's way). A system may run it faster than flow by flow
    /// (its state kept in registers from step to step), giving the same
    /// bits. It returns the steps it took; it stops early, with `z` as the
    /// step it could not take found it, where a flow would fail or leave
    /// its fast path, and the caller takes that step flow by flow (with
    /// the flows' errors). The default takes none.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn kick_drift_run(
        &self,
        kick: f64,
        gamma: f64,
        drift: f64,
        drift_last: f64,
        n: usize,
        z: &mut [f64],
    ) -> usize {
        let _ = (kick, gamma, drift, drift_last, n, z);
        0
    }
}

/// `d ← d + h·s`, with compensated (Kahan) summation into `e` when
/// `compensated`: the state update of a drift or kick, the arithmetic of
/// `butcher!`'s generated updates term for term (so a separable system
/// stepped as a split one gives the bits it gave before).
#[inline(always)]
fn add_scaled(d: &mut [f64], e: &mut [f64], h: f64, s: &[f64], compensated: bool) {
    let n = d.len();
    let (e, s) = (&mut e[..n], &s[..n]);
    if compensated {
        for i in 0..n {
            let inc = e[i] + h * s[i];
            let new = d[i] + inc;
            e[i] = (d[i] - new) + inc;
            d[i] = new;
        }
    } else {
        for i in 0..n {
            d[i] += h * s[i];
        }
    }
}

/// A separable system is split as `A = T(p)` (a drift: `q += h·∇T(p)`) and
/// `B = V(q)` (a kick: `p += h·F(q)`); each flow keeps its evaluation for
/// first same as last (a drift leaves `p`, a kick `q` unchanged).
impl<S: Separable + ?Sized> Split for S {
    const CHECK_FINITE: bool = false;

    #[inline]
    fn buffer_len(&self) -> usize {
        Separable::dof(self)
    }

    #[inline(always)]
    fn flow_a(
        &self,
        h: f64,
        z: &mut [f64],
        buf: PartBuffers<'_>,
        reuse: bool,
    ) -> Result<(), FlowError> {
        let n = z.len() / 2;
        let (q, p) = z.split_at_mut(n);
        let (q, p) = (&mut q[..n], &p[..n]);
        let v = &mut buf.eval[..n];
        if !reuse {
            self.velocity(p, v);
        }
        add_scaled(q, buf.err, h, v, buf.compensated);
        Ok(())
    }

    #[inline(always)]
    fn flow_b(
        &self,
        h: f64,
        z: &mut [f64],
        buf: PartBuffers<'_>,
        reuse: bool,
    ) -> Result<(), FlowError> {
        let n = z.len() / 2;
        let (q, p) = z.split_at_mut(n);
        let (q, p) = (&q[..n], &mut p[..n]);
        let f = &mut buf.eval[..n];
        if !reuse {
            self.force(q, f);
        }
        add_scaled(p, buf.err, h, f, buf.compensated);
        Ok(())
    }
}

/// One flow of a split step, as `butcher!`'s step code calls it: the flow
/// of `part` for the time `h`, its failure as [`SolveError::Flow`] naming
/// the part, and, where the system asks for it ([`Split::CHECK_FINITE`]),
/// a non-finite value it left as [`FlowError::NonFinite`].
#[doc(hidden)]
#[inline(always)]
pub fn flow<S: Split + ?Sized>(
    sys: &S,
    part: Part,
    h: f64,
    z: &mut [f64],
    buf: PartBuffers<'_>,
    reuse: bool,
) -> Result<(), SolveError> {
    let done = match part {
        Part::A => sys.flow_a(h, z, buf, reuse),
        Part::B => sys.flow_b(h, z, buf, reuse),
    };
    checked(sys, part, z, done)
}

/// A gradient kick of a split step ([`Split::flow_b_gradient`]), its
/// failure and non-finite values reported as [`flow`] reports a kick's.
#[doc(hidden)]
#[inline]
pub fn flow_gradient<S: Split + ?Sized>(
    sys: &S,
    h: f64,
    gamma: f64,
    z: &mut [f64],
    buf: PartBuffers<'_>,
) -> Result<(), SolveError> {
    let done = sys.flow_b_gradient(h, gamma, z, buf);
    checked(sys, Part::B, z, done)
}

/// A flow's outcome as the step reports it: its failure as
/// [`SolveError::Flow`] naming the part, and, where the system asks for it
/// ([`Split::CHECK_FINITE`]), a non-finite value it left.
#[inline(always)]
fn checked<S: Split + ?Sized>(
    _sys: &S,
    part: Part,
    z: &[f64],
    done: Result<(), FlowError>,
) -> Result<(), SolveError> {
    done.map_err(|source| SolveError::Flow { part, source })?;
    if S::CHECK_FINITE
        && let Some(index) = z.iter().position(|x| !x.is_finite())
    {
        let value = z[index];
        return Err(SolveError::Flow {
            part,
            source: FlowError::NonFinite { index, value },
        });
    }
    Ok(())
}
