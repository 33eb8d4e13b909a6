//! Tests of `compare::sweep` (from its `#[cfg(test)]` module: `compare`
//! has no unit-test harness, which would compile the whole crate a second
//! time; see `compare/tests/units/mod.rs`).

use compare::sweep::*;
#[test]
fn step_counts_are_log_spaced_and_distinct() {
    let s = step_counts(10.0, 1e-3, 0.1, 5);
    assert_eq!(s, vec![100, 316, 1000, 3162, 10000]);
    assert_eq!(step_counts(1.0, 0.5, 0.5, 3), vec![2]);
    let t = tolerances(PEER_TOLERANCES);
    assert_eq!(t.len(), 15);
    assert!((t[0] - 1e-4).abs() < 1e-18 && (t[14] - 1e-18).abs() < 1e-30);
    assert!((t[4] - 1e-8).abs() < 1e-20 && (t[11] - 1e-15).abs() < 1e-27);
}

#[test]
fn median_of_even_and_odd() {
    assert_eq!(median(vec![3.0, 1.0, 2.0]), 2.0);
    assert_eq!(median(vec![4.0, 1.0, 2.0, 3.0]), 2.5);
    assert!(median(vec![]).is_nan());
}
