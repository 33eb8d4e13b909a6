//! Constrained Hamiltonian systems and the Lobatto IIIA–IIIB pairs on them.
//!
//! A system `H = ½pᵀM⁻¹p + V(q)` with holonomic constraints `g(q) = 0`
//! ([`Constrained`]) is an index-3 differential-algebraic equation
//! `q' = M⁻¹p, p' = −∇V(q) − G(q)ᵀλ, 0 = g(q)`. Its flow is a symplectic map
//! of the cotangent bundle of the constraint manifold, but that manifold has
//! no global coordinates the library could hand to an ODE method (a sphere
//! has none), and projecting the result of an unconstrained step back onto it
//! destroys symplecticity. So the pair is applied to the DAE itself, with
//! the multipliers as unknowns (Hairer, Lubich & Wanner, *Geometric Numerical
//! Integration*, 2nd ed., Sect. VII.1; Jay, SIAM J. Numer. Anal. 33 (1996)
//! 368–387, the SPARK methods): the stages satisfy the constraints `g(Qᵢ) = 0`
//! and the new momentum the hidden constraint `G(q₁)M⁻¹p₁ = 0`. The
//! Lobatto IIIA–IIIB pair with `s` stages then defines a map of the
//! manifold's cotangent bundle to itself that is symplectic, symmetric and of
//! order `2s − 2` (Jay 1996; HLW VII.1.4). With `s = 2` it is RATTLE
//! (Andersen 1983), the symplectic and symmetric "SHAKE with velocities".
//!
//! The coefficients are read from the pair tables the library declares with
//! `butcher!` from the catalogue (`stormer-verlet`, which is the s = 2 pair,
//! and `lobatto3a3b-3`), whose claims `tableau` proves exactly; the
//! constrained step checks that their verdicts hold at compile time
//! ([`table`]).
//!
//! Two ways to solve the step's equations, chosen by the size of the
//! system:
//!
//! - [`ConstrainedPair`], for small systems (a spherical pendulum, a
//!   pendulum chain) and for either pair: the stage equations are solved by
//!   Newton's method with a dense faer LU ([`ConstrainedPair::step`]),
//!   warm-started from the last step's multipliers: for RATTLE, and
//!   wherever the curvature `∇²V + Σλₗ∇²gₗ` is not used, on the
//!   multipliers alone (the stages eliminated, size `(s−1)m`); otherwise on
//!   stages and multipliers together (size `(s−1)(d + m)`), quadratically
//!   convergent. The iteration stops at round-off; its cap is an error that
//!   names the step and time, as are a singular matrix and a non-finite
//!   value.
//! - [`rattle::Rattle`], RATTLE in its multiplier form for large sparse
//!   systems, generic over the system ([`rattle::RattleSystem`]) and the
//!   linear algebra ([`rattle::ConstraintSolver`]): a factor of
//!   `G M⁻¹ Gᵀ` kept over several steps, a refresh by the true Jacobian
//!   when it stops contracting, the velocity projection by conjugate
//!   gradients, optionally only where a state is handed out. The cloth's
//!   thousands of edge constraints run on it with a sparse Cholesky (the
//!   `cloth` crate). Only RATTLE has that form: the `s = 3` pair's interior
//!   stage moves its forces and constraint directions with the unknowns,
//!   so it has no factor to keep and takes the dense path.
//!
//! ```
//! use integrator_core::constrained::{ConstrainedPair, constrained_energy, integrate_constrained};
//! use integrator_core::problems::SphericalPendulum;
//!
//! let sys = SphericalPendulum::new(1.0, 1.0, 9.81);
//! let mut z = sys.state(1.2, 0.3, 0.0, 2.0);
//! let e0 = constrained_energy(&sys, &z);
//! let mut worst: f64 = 0.0;
//! integrate_constrained(&ConstrainedPair::rattle(), &sys, &mut z, 0.0, 0.01, 1000, |_, _, z| {
//!     worst = worst.max((constrained_energy(&sys, z) - e0).abs());
//! })
//! .unwrap();
//! assert!(worst < 1e-2 * e0.abs());
//! ```

mod dense_lu;
mod dense_rattle;
mod error;
mod integrate;
pub mod rattle;
mod step;
mod system;
pub mod table;

pub use error::{ConstrainedError, Where};
pub use integrate::{check_start, integrate_constrained};
pub use step::{ConstrainedPair, ConstrainedWorkspace, NewtonSettings};
pub use system::{Constrained, Residual, Residuals, constrained_energy, residuals};
pub use table::{LobattoPair, PairStructureError};
