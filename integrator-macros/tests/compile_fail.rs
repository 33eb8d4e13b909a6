//! The compile errors of false claims: each case in `tests/ui/` is a
//! `butcher!` whose claim the verifier refuses, with the message the user
//! sees (`TRYBUILD=overwrite` rewrites the `.stderr` files; read the diff).
//!
//! The cases live here, beside the macro, and use nothing but it: trybuild's
//! project checks the crate's dependencies and dev-dependencies from
//! scratch, and integrator-core's (faer, criterion, proptest) cost CI
//! minutes. What a generated scheme can step (its trait bounds) is checked
//! by a `compile_fail,E0277` doctest in the guide (`guide/src/butcher.md`,
//! compiled with compare's doctests), against the already built library.

#[test]
fn compile_fail_diagnostics() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
}
