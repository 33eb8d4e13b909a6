//! Tests of `compare::nbody::bodies` (from its `#[cfg(test)]` module: `compare`
//! has no unit-test harness, which would compile the whole crate a second
//! time; see `compare/tests/units/mod.rs`).

use compare::nbody::*;
#[test]
fn bodies_round_trip_the_momenta_or_name_the_body() {
    let z = [1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.5, 0.25, 0.0, 0.0, 0.0, 0.0];
    let b = Bodies::from_momenta(1.0, &["a", "b"], &[2.0, 1.0], &z).unwrap();
    assert_eq!(b.velocities[0], [0.25, 0.125, 0.0]);
    assert_eq!(b.state(&b.positions, &b.velocities), z.to_vec());
    let e = Bodies::from_momenta(1.0, &["a", "b"], &[2.0, 0.0], &z).unwrap_err();
    assert!(e.contains("body 1 (b)") && e.contains("mass"), "{e}");
    // 0.1 / 3 × 3 ≠ 0.1 in doubles: no velocity gives back that momentum.
    let mut w = z;
    w[6] = 0.1;
    let m = (1..1000)
        .map(|k| 1.0 + k as f64 * 1e-3)
        .find(|m| m * (0.1 / m) != 0.1)
        .unwrap();
    let e = Bodies::from_momenta(1.0, &["a", "b"], &[m, 1.0], &w).unwrap_err();
    assert!(e.contains("body 0 (a), momentum component x"), "{e}");
}
