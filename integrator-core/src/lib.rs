//! Hamiltonian systems, schemes and the scheme library.
//!
//! Schemes are declared with [`butcher!`], which verifies every claim of a
//! table exactly at compile time and emits step code specialised to it:
//!
//! ```
//! use integrator_core::butcher;
//!
//! butcher! {
//!     /// Two-stage Gauss–Legendre collocation, order 4.
//!     pub GaussLegendre2 {
//!         claims: [symplectic, symmetric, order = 4],
//!         a: [[1/4, 1/4 - sqrt(3)/6],
//!             [1/4 + sqrt(3)/6, 1/4]],
//!         b: [1/2, 1/2],
//!     }
//! }
//! assert!(GaussLegendre2::SYMPLECTIC);
//! assert_eq!(GaussLegendre2::ORDER, 4);
//! ```
//!
//! A false claim does not compile:
//!
//! ```compile_fail
//! use integrator_core::butcher;
//! butcher! {
//!     pub Rk4 {
//!         claims: [symplectic], // error: not symplectic: W[0][0] = -1/36, …
//!         a: [[0, 0, 0, 0], [1/2, 0, 0, 0], [0, 1/2, 0, 0], [0, 0, 1, 0]],
//!         b: [1/6, 1/3, 1/3, 1/6],
//!     }
//! }
//! ```

// The macro's expansion names paths as `::integrator_core::…`, which must
// resolve inside this crate too (its tests and doctests declare schemes).
extern crate self as integrator_core;

pub mod adaptive;
pub mod checkpoint;
pub mod constrained;
mod error;
pub mod fixed;
pub mod implicit;
mod integrate;
pub mod interp;
pub mod kepler;
pub mod library;
pub mod linear;
pub mod minimise;
pub mod problems;
pub mod processed;
pub mod scheme;
pub mod search;
pub mod sequence;
pub mod simd;
pub mod split;
mod system;
pub mod time_transform;

pub use error::{SolveError, StepError};
pub use fixed::{StepFixed, integrate_fixed};
pub use integrate::{check_start, integrate};
pub use integrator_macros::butcher;
pub use scheme::{Info, Scheme, Step};
pub use split::{FlowError, Part, PartBuffers, Split, StateSpace};
pub use system::{Hamiltonian, OdeSystem, Separable, energy};
