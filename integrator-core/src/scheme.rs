//! Schemes: what `butcher!` implements for a verified table.
//!
//! A scheme is a zero-sized type. [`Step<S>`] is implemented for exactly the
//! systems `S` it may be applied to: explicit Runge–Kutta tables for every
//! [`OdeSystem`](crate::OdeSystem) (hence every Hamiltonian), drift–kick
//! sequences and compositions for every [`Split`](crate::Split) system (the
//! exact flows of two parts; every [`Separable`](crate::Separable) system is
//! one, `A = T`, `B = V`), explicit pairs for separable systems only. The
//! caller owns the workspace, so stepping never allocates.
//!
//! The order of a drift–kick sequence or composition on a split system is
//! its `order` ([`Info::order`]): the verifier decides it for separable
//! `H = T(p) + V(q)` with a general `T`, whose order conditions are those of
//! the free Lie algebra on two generators, hence those of a splitting for
//! any parts `A` and `B` (see [`split`](crate::split)). The higher
//! Runge–Kutta–Nyström order some tables also claim (`order_rkn`, for
//! quadratic `T`) does not carry over.

use crate::error::SolveError;

/// Facts about a scheme, proven at compile time by `butcher!`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Info {
    pub name: &'static str,
    /// `"rk"`, `"prk"`, `"drift-kick"` or `"composition"`.
    pub form: &'static str,
    pub stages: usize,
    pub order: usize,
    pub symplectic: bool,
    pub symplectic_separable: bool,
    pub separable_only: bool,
    pub symmetric: bool,
    pub explicit: bool,
    pub class: &'static str,
    /// Right-hand-side evaluations per step (force plus velocity evaluations
    /// for separable schemes), without first-same-as-last reuse.
    pub evaluations: usize,
    /// `Some(b)` when the table is a composition of implicit midpoint steps
    /// of sizes `b₁h, …, b_sh` (`aᵢᵢ = bᵢ/2`, `aᵢⱼ = bⱼ` for `j < i`), decided
    /// by `butcher!` on the exact entries (`tableau::midpoint`), never on the
    /// doubles; the weights are the table's `b` as rounded for stepping.
    ///
    /// Why it is a fact of the scheme: for `M q̈ = −∇V(q)` each midpoint step
    /// is an energy minimisation, so a solver may step such a table (a user's
    /// as well as the library's) as successive minimisations, which descend
    /// at any step size, instead of through the generic stage equations.
    pub midpoint_weights: Option<&'static [f64]>,
}

/// Implemented by every `butcher!` type.
pub trait Scheme: Copy + Default + 'static {
    const INFO: Info;
}

/// One step of a scheme on a system `S`, in place: `z ← Ψ_h(z)`.
#[diagnostic::on_unimplemented(
    message = "the scheme `{Self}` cannot step the system `{S}`",
    label = "`{Self}` does not implement `Step<{S}>`",
    note = "drift–kick sequences and compositions step systems that implement `Split` (every `Separable` one does); explicit partitioned pairs are symplectic only for separable Hamiltonians, so they step only systems that implement `Separable`; implicit partitioned pairs step systems that implement `Hamiltonian`"
)]
pub trait Step<S: ?Sized> {
    /// Scratch memory for one system size, requested up front.
    type Workspace;
    fn workspace(&self, sys: &S) -> Self::Workspace;
    /// `z ← Ψ_h(z)` for the step from `t` to `t + h`. Explicit schemes fail
    /// only where a flow of a [`Split`](crate::Split) system fails
    /// ([`SolveError::Flow`], naming the part; `z` is then what the flows
    /// before it left); implicit ones return the reason their stage solve
    /// failed, and leave `z` unchanged then.
    fn step(
        &self,
        sys: &S,
        t: f64,
        h: f64,
        z: &mut [f64],
        ws: &mut Self::Workspace,
    ) -> Result<(), SolveError>;
    /// Like [`step`](Step::step), but when `reuse` is true the first
    /// evaluation is taken from the end of the previous step (first same as
    /// last). Only valid when `z` is exactly what the previous call left:
    /// [`integrate`](crate::integrate) guarantees it; callers of `step` need
    /// not care.
    fn step_reusing(
        &self,
        sys: &S,
        t: f64,
        h: f64,
        z: &mut [f64],
        ws: &mut Self::Workspace,
        reuse: bool,
    ) -> Result<(), SolveError> {
        let _ = reuse;
        self.step(sys, t, h, z, ws)
    }
}

/// Stage derivatives of an explicit Runge–Kutta step.
#[derive(Clone, Debug)]
pub struct RkWorkspace<const S: usize> {
    pub k: [Vec<f64>; S],
    pub y: Vec<f64>,
    /// The rounding error of the last update of `z`, carried into the next
    /// (compensated summation).
    pub e: Vec<f64>,
    /// Compensated summation of the update `z ← z + h Σ bᵢkᵢ` (default on).
    pub compensated: bool,
}

impl<const S: usize> RkWorkspace<S> {
    pub fn new(dim: usize) -> Self {
        RkWorkspace {
            k: std::array::from_fn(|_| vec![0.0; dim]),
            y: vec![0.0; dim],
            e: vec![0.0; dim],
            compensated: true,
        }
    }
}

/// Buffers of a drift–kick step: the last evaluations of the flows (for a
/// separable system the velocity and the force), handed to the flows of
/// parts `A` (`v`, `eq`) and `B` (`f`, `ep`) as
/// [`PartBuffers`](crate::split::PartBuffers).
#[derive(Clone, Debug)]
pub struct SplitWorkspace {
    pub v: Vec<f64>,
    pub f: Vec<f64>,
    /// Carried rounding errors of the drifts (`q`) and kicks (`p`): of the
    /// flows of parts `A` and `B`.
    pub eq: Vec<f64>,
    pub ep: Vec<f64>,
    /// Compensated summation of every drift and kick (default on).
    pub compensated: bool,
}

impl SplitWorkspace {
    /// Vectors of length `dof` (a split system's
    /// [`buffer_len`](crate::Split::buffer_len)).
    pub fn new(dof: usize) -> Self {
        SplitWorkspace {
            v: vec![0.0; dof],
            f: vec![0.0; dof],
            eq: vec![0.0; dof],
            ep: vec![0.0; dof],
            compensated: true,
        }
    }
}

/// Stage values and evaluations of an explicit partitioned step.
#[derive(Clone, Debug)]
pub struct PrkWorkspace<const S: usize> {
    /// `f(Pᵢ) = ∂T/∂p` at the stage momenta.
    pub fv: [Vec<f64>; S],
    /// `g(Qᵢ) = −∂V/∂q` at the stage positions.
    pub gf: [Vec<f64>; S],
    pub q: Vec<f64>,
    pub p: Vec<f64>,
    /// Carried rounding errors of the updates of `q` and `p`.
    pub eq: Vec<f64>,
    pub ep: Vec<f64>,
    /// Compensated summation of the update (default on).
    pub compensated: bool,
}

impl<const S: usize> PrkWorkspace<S> {
    pub fn new(dof: usize) -> Self {
        PrkWorkspace {
            fv: std::array::from_fn(|_| vec![0.0; dof]),
            gf: std::array::from_fn(|_| vec![0.0; dof]),
            q: vec![0.0; dof],
            p: vec![0.0; dof],
            eq: vec![0.0; dof],
            ep: vec![0.0; dof],
            compensated: true,
        }
    }
}
