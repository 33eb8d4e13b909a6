//! A problem's N-body ability, an optional capability of a [`Problem`](crate::Problem):
//! its point masses ([`Bodies`], what REBOUND is given: the `rebound:` methods)
//! and, through [`Problem::wisdom_holman`](crate::Problem::wisdom_holman), its
//! Jacobi split (the `wh:` methods). Doubles cross to REBOUND as hexadecimal
//! floats ([`hex`], [`unhex`]), so that it starts from our bits.

mod bodies;
mod hexfloat;

pub use bodies::{Bodies, Layout};
pub use hexfloat::{hex, unhex};
