//! Studies of cloth runs as a library: the energy reference and guard, the
//! growth fit of the energy error, the largest stable step, and the paper's
//! figure-5 comparison. The command line formats what these return.

pub mod energy;
pub mod figure5;
pub mod growth;
pub mod stability;
