//! Integration tests of `tableau`, one test binary: each module is one of the
//! files beside this one (`cargo test --test integration MODULE::`).
//! One binary links the crate and its dependencies once, where a binary
//! per file linked them once per file (the README's test command took
//! about 30 minutes on a clean 2-core machine, mostly compiling and
//! linking test binaries).

mod algebraic;
mod analysis;
mod catalogue;
mod catalogue_optimised;
mod certificate;
mod files;
mod generated;
mod grammar;
mod hostile;
mod hostile_claims;
mod near_integrable;
mod number;
mod order;
mod root_files;
mod rounding;
