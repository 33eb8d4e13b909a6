//! The compile errors of false claims: each case in `tests/ui/` is a
//! `butcher!` whose claim the verifier refuses, with the message the user
//! sees (`TRYBUILD=overwrite` rewrites the `.stderr` files; read the diff).
//!
//! The cases live here, beside the macro: trybuild's project checks the
//! crate's dependencies and dev-dependencies, and integrator-core's
//! (criterion and proptest beside faer) cost CI minutes. One case is about
//! integrator-core's trait bounds (a drift–kick scheme on a system that is
//! not separable); integrator-core is a dev-dependency for it.

#[test]
fn compile_fail_diagnostics() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
}
