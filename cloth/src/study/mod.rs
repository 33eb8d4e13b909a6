//! Studies of cloth runs as a library: the energy reference and guard, the
//! growth fit of the energy error, the largest stable step, the paper's
//! figure-5 comparison, and the spring model against the constrained one
//! at equal stretch. The command line formats what these return.

pub mod energy;
pub mod equal_stretch;
pub mod figure5;
pub mod growth;
pub mod stability;
