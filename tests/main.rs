//! End-to-end tests of the `symlab` command line, one test binary: each module is one of the
//! files beside this one (`cargo test --test integration MODULE::`).
//! One binary links the crate and its dependencies once, where a binary
//! per file linked them once per file (the README's test command took
//! about 30 minutes on a clean 2-core machine, mostly compiling and
//! linking test binaries).

mod common;

mod check_cli;
mod cloth_cli;
mod compare_cli;
mod design_cli;
mod designed_method;
mod hostile_flags;
mod hostile_surfaces;
mod input_messages;
mod paper;
mod pipes;
mod rebound_cli;
mod resume;
mod three_readers;
