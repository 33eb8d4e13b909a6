//! The growth of the energy error over a run (work in progress).
