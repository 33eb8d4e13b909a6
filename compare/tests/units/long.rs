//! Tests of `compare::long` (from its `#[cfg(test)]` module: `compare`
//! has no unit-test harness, which would compile the whole crate a second
//! time; see `compare/tests/units/mod.rs`).

use compare::long::*;
#[test]
fn window_ends_are_log_spaced() {
    let w = window_ends(1000);
    assert_eq!(w.first(), Some(&1));
    assert_eq!(w.last(), Some(&1000));
    assert!(w.windows(2).all(|p| p[0] < p[1]));
    // 20 per decade, minus the duplicates among small integers.
    assert!(w.len() > 40 && w.len() <= 61, "{}", w.len());
}

#[test]
fn exponent_of_linear_and_bounded_growth() {
    let lin: Vec<(u64, f64, f64)> = (1..=1000u64)
        .map(|k| (k, k as f64, 1e-9 * k as f64))
        .collect();
    assert!((growth_exponent(&lin).unwrap() - 1.0).abs() < 1e-9);
    let flat: Vec<(u64, f64, f64)> = (1..=1000u64).map(|k| (k, k as f64, 1e-9)).collect();
    assert!(growth_exponent(&flat).unwrap().abs() < 1e-9);
}
