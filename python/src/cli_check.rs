//! The command line's `symlab check` module, compiled here as well, so that
//! `symlab.check` returns the very report and JSON fields of `symlab check`
//! (`readable`, `to_json`, `generated_json`, `generated_readable`) rather
//! than a copy that could drift. The file lives in the binary crate, which
//! cannot be a library dependency; including it by path keeps the CLI
//! untouched. It uses only workspace crates and clap (for its argument
//! structs), never `crate::`.
#[allow(dead_code, unused_imports)]
#[path = "../../src/check.rs"]
mod check;

pub use check::{generated_json, generated_readable, readable, steps, to_json};
