//! Stage solvers for implicit Runge–Kutta tables and partitioned pairs.
//!
//! `butcher!` emits, for every implicit table, an [`ImplicitTable`] constant
//! and a `Step` impl that calls [`step`]; the functions here can also be
//! called directly with a table built by hand.
//!
//! The stage equations are solved for the increments `Zᵢ = Yᵢ − z`,
//!
//! ```text
//! G(Z) = Z − h·(A⊗I)·F(z + Z) = 0,      F(Y)ᵢ = f(t + cᵢh, Yᵢ),
//! ```
//!
//! * by **simplified Newton**, `(I − h·A⊗J)·ΔZ = −G(Z)` with `J = ∂f/∂z` at
//!   the start of the step, the matrix factorised with faer's dense
//!   partial-pivoting LU ([`step`]) or its sparse LU ([`step_sparse`]);
//! * or by **fixed-point iteration** `Z ← h·(A⊗I)·F(z + Z)`;
//!
//! in both cases down to round-off: until the corrections no longer change
//! the stage values, or stop decreasing at round-off level (the stagnation
//! test of Hairer's GNI codes), since a loose tolerance silently costs a
//! symplectic method its symplecticity and its round-off its random walk.
//! An iteration that does not get there is an error
//! ([`SolveError::NotConverged`], [`SolveError::Diverged`],
//! [`SolveError::Singular`]), and `z` is left as it was: never a silently
//! wrong step.
//!
//! * Lower-triangular tables ([`Structure::Dirk`], [`Structure::Sdirk`]) are
//!   solved stage by stage: `s` systems of size `d`, one factorisation of
//!   `I − h·aᵢᵢ·J` per distinct diagonal value, instead of one of size `s·d`.
//! * Starting values: for tables with distinct `cᵢ` (collocation), the
//!   previous step's collocation polynomial extrapolated,
//!   `Zᵢ⁽⁰⁾ = h·Σⱼ βᵢⱼ·Fⱼ` with `βᵢⱼ = ∫₀^{1+cᵢ} ℓⱼ − bⱼ` (rescaled when `h`
//!   changes), for Newton and fixed point alike.
//! * The update `z ← z + h·Σ bᵢ·F(Yᵢ)` reuses the last evaluations (no
//!   extra ones) and is compensated (Kahan), the compensation carried
//!   across steps.
//! * Symplectic tables with distinct nodes (Gauss–Legendre), wherever
//!   fixed-point iteration is used, iterate in their **symplectic form**
//!   as IRKGL16 does ([`collocation`]): `Yᵢ = z + Σⱼ μᵢⱼ·h·bⱼ·Fⱼ` with
//!   `μᵢⱼ = aᵢⱼ/bⱼ` computed in double-double and rounded so that
//!   `μᵢⱼ + μⱼᵢ = 1` exactly (the rounded method is exactly symplectic),
//!   sweeps until the stage values stop changing, and the state carried as
//!   `z + e` in double-double ([`Settings::symplectic_form`]).
//! * A partitioned pair (`a_hat`) acts on `z = [q; p]`: `(A, b)` on the
//!   first half of the components, `(Â, b̂)` on the second; the Newton
//!   matrix has rows `I − h·(A⊗J)` for `q` and `I − h·(Â⊗J)` for `p`.
//!
//! ```
//! use integrator_core::implicit::{self, ImplicitTable, ImplicitWorkspace};
//! use integrator_core::OdeSystem;
//!
//! /// q' = p, p' = −q.
//! struct Oscillator;
//! impl OdeSystem for Oscillator {
//!     fn dim(&self) -> usize { 2 }
//!     fn rhs(&self, _t: f64, z: &[f64], dz: &mut [f64]) { dz[0] = z[1]; dz[1] = -z[0]; }
//!     fn jacobian(&self, _t: f64, _z: &[f64], j: &mut [f64]) -> bool {
//!         j.copy_from_slice(&[0.0, 1.0, -1.0, 0.0]);
//!         true
//!     }
//! }
//!
//! // The implicit midpoint rule.
//! const MIDPOINT: ImplicitTable<1> = ImplicitTable::new([[0.5]], [1.0], [0.5]);
//! let mut ws = ImplicitWorkspace::new(2, 1);
//! let mut z = [1.0, 0.0];
//! for k in 0..1000 {
//!     implicit::step(&MIDPOINT, &Oscillator, k as f64 * 0.1, 0.1, &mut z, &mut ws).unwrap();
//! }
//! // The midpoint rule conserves quadratic invariants.
//! assert!((z[0] * z[0] + z[1] * z[1] - 1.0).abs() < 1e-13);
//! // A linear system: one Jacobian, one factorisation for the whole run.
//! assert_eq!(ws.stats().factorizations, 1);
//! ```

pub mod collocation;
mod dense;
mod iteration;
mod settings;
mod sparse;
mod symplectic_iteration;
mod table;
mod twofold;
mod workspace;

pub use collocation::{FormSource, SymplecticForm, symplectic_form};
pub use settings::{Settings, Solver, Stats};
pub use sparse::SparseJacobian;
pub use table::{ImplicitTable, Structure, structure_of};
pub use workspace::{ImplicitWorkspace, SparseWorkspace};

use crate::error::SolveError;
use crate::system::OdeSystem;

/// One step `z ← Ψ_h(z)` of the implicit table from `t` to `t + h`, with
/// dense linear algebra (see the [module documentation](self)).
///
/// On error `z` is unchanged and the workspace still holds the previous
/// step's history, so the step can be retried (e.g. with a smaller `h`).
///
/// # Panics
///
/// If the workspace was made for another dimension than `z.len()` or
/// another stage count than `S`, or if a partitioned table is applied to a
/// state of odd length.
pub fn step<Sys: OdeSystem + ?Sized, const S: usize>(
    table: &ImplicitTable<S>,
    sys: &Sys,
    t: f64,
    h: f64,
    z: &mut [f64],
    ws: &mut ImplicitWorkspace,
) -> Result<(), SolveError> {
    iteration::step(table, sys, t, h, z, &mut ws.core, &mut ws.linear)
}

/// [`step`] for systems with a sparse Jacobian: the Newton matrices are
/// faer sparse matrices, their symbolic LU computed once per workspace and
/// matrix shape, the numeric LU per new Jacobian or `h`.
/// [`Solver::Auto`] means Newton here.
///
/// # Panics
///
/// As [`step`]; also if the Jacobian's pattern has an entry outside
/// `dim × dim`.
pub fn step_sparse<Sys: SparseJacobian + ?Sized, const S: usize>(
    table: &ImplicitTable<S>,
    sys: &Sys,
    t: f64,
    h: f64,
    z: &mut [f64],
    ws: &mut SparseWorkspace,
) -> Result<(), SolveError> {
    iteration::step(table, sys, t, h, z, &mut ws.core, &mut ws.linear)
}
