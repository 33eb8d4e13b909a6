//! Hamiltonian systems, stage solvers and the scheme library.
//!
//! For now: the `butcher!` macro, which declares a scheme from a Butcher
//! table and verifies its claims exactly at compile time.
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
//! assert_eq!(GaussLegendre2::A[0][1], 0.25 - 3f64.sqrt() / 6.0);
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

pub use integrator_macros::butcher;
