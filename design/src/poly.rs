//! Polynomials in several unknowns with rational coefficients, and rational
//! intervals: the designer's conditions are built as these. They live in
//! `tableau::certificate::poly`, beside the Krawczyk test that `symlab check`
//! runs on an emitted table's certificate, so that the designer and the
//! verifier share one implementation.

pub use tableau::certificate::poly::*;
