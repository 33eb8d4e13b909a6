//! The product's runs as jobs, shared by the command line and Python.
//!
//! A front end turns what its user wrote (flags, keyword arguments) into a
//! request; the job checks it (an error names the field, which each front
//! end shows as its flag or keyword), plans it, and runs it into files,
//! reporting progress through an observer and returning data — the front
//! end only draws bars and prints. So `symlab cloth` and
//! `symlab.cloth.run` get the same energy guard, the same schedule and the
//! same summary.
//!
//! - [`cloth`]: a cloth scene run into `energy.csv`, the energy plot, OBJ
//!   frames, PNG renderings and a summary, with checkpoints.
//! - [`paper`]: the experiments of Tan et al.'s section 5, reproduced.

pub mod cloth;
pub mod paper;
