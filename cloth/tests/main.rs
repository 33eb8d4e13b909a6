//! Integration tests of `cloth`, one test binary: each module is one of the
//! files beside this one (`cargo test --test integration MODULE::`).
//! One binary links the crate and its dependencies once, where a binary
//! per file linked them once per file (the README's test command took
//! about 30 minutes on a clean 2-core machine, mostly compiling and
//! linking test binaries).
//! The tests that install a global allocator of their own keep a binary
//! each: `no_alloc`, `banded_no_alloc`, `minimise_no_alloc`.

mod common;

mod auto_step;
mod avf;
mod banded;
mod bending;
mod checkpoint;
mod conservation;
mod equal_stretch;
mod hostile;
mod implicit;
mod minimise;
mod model;
mod rattle;
mod run;
mod sag;
mod scenes;
mod stencil;
mod study;
mod variable_step;
