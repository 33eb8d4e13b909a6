//! Studies of cloth runs as a library: the energy reference and guard, the
//! growth fit of the energy error, and the largest stable step. The command
//! line formats what these return.

pub mod energy;
pub mod growth;
pub mod stability;
