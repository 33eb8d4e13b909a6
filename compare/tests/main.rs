//! Integration tests of `compare`, one test binary: each module is one of the
//! files beside this one (`cargo test --test integration MODULE::`).
//! One binary links the crate and its dependencies once, where a binary
//! per file linked them once per file (the README's test command took
//! about 30 minutes on a clean 2-core machine, mostly compiling and
//! linking test binaries).

mod adaptive;
mod hostile_api;
mod long_variable;
mod rebound_hostile;
mod rebound_peer;
mod time_transformed;
mod units;
mod wisdom_holman;
mod your_scheme;
