//! A cloth scene run into files (see the crate documentation).
