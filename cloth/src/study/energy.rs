//! The energy of a run measured against a reference scale (work in progress).
