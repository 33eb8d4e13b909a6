//! Exact analysis of Butcher tables.
//!
//! `tableau` holds everything that must be decided exactly and identically at
//! compile time (by the `butcher!` macro) and at run time (by `symlab check`):
//! the [`Number`] field (rationals extended by real radicals), the expression
//! grammar, the table types and their analyses; and, in [`algebraic`], real
//! algebraic numbers (roots of rational polynomials with isolating intervals,
//! exact zero tests) with the generated Gauss, Radau and Lobatto tables of any
//! number of stages, verified in products of fields. It depends on neither faer nor
//! syn, so the macro and the CLI share one verifier.

pub mod algebraic;
pub mod analysis;
pub mod budget;
pub mod catalogue;
pub mod certificate;
pub mod claims;
pub mod embedded;
pub mod expr;
pub mod file;
pub mod midpoint;
pub mod near_integrable;
pub mod number;
pub mod order;
pub mod rounding;
pub mod table;
pub mod trees;
pub mod verdict;

pub use number::{Number, NumberError};
pub use table::{Composition, Prk, Rk, Splitting, Table};
