//! Tests of `compare::builtin` (from its `#[cfg(test)]` module: `compare`
//! has no unit-test harness, which would compile the whole crate a second
//! time; see `compare/tests/units/mod.rs`).

use compare::builtin::*;
use compare::*;
use integrator_core::OdeSystem;
use integrator_core::linear::{self, LinearHamiltonian};
use integrator_core::problems::{Fpu, HenonHeiles, Kepler, Oscillator, OuterSolarSystem, Pendulum};
#[test]
fn omega_max_of_the_gyroscopic_system_is_near_the_spread() {
    let sys = linear::gyroscopic(10, 7, 1e4).unwrap();
    let w = omega_max(&sys);
    assert!((0.99e4..=1.0e4 + 0.3).contains(&w), "{w}");
}

/// Each built-in problem of a fixed size names that size in
/// `STACK_SIZES`, so its timed runs keep the stack path (and no other
/// size is compiled for it); the gyroscopic system has none.
#[test]
fn fixed_size_problems_keep_their_stack_path() {
    fn has<P: Problem>(p: &P) -> bool {
        let n = p.start().len();
        assert_eq!(n, p.dim(), "{}", p.name());
        P::STACK_SIZES.contains(n)
            && StackSizes::SIZES
                .iter()
                .all(|&m| m == n || !P::STACK_SIZES.contains(m))
    }
    assert!(has(&Oscillator { k: 1.0 }));
    assert!(has(&Pendulum));
    assert!(has(&Kepler { e: 0.6 }));
    assert!(has(&HenonHeiles));
    assert!(has(&Fpu::stiff()));
    assert!(has(&OuterSolarSystem));
    let gyro = linear::gyroscopic(10, 7, 1e4).unwrap();
    assert_eq!(LinearHamiltonian::STACK_SIZES, StackSizes::NONE);
    assert!(!StackSizes::SIZES.contains(&gyro.dim()));
}

#[test]
fn stack_sizes_name_only_sizes_with_a_path() {
    assert!(StackSizes::only(36).contains(36));
    assert!(!StackSizes::only(36).contains(4));
    assert!(StackSizes::ALL.contains(6) && !StackSizes::ALL.contains(8));
    assert!(!StackSizes::NONE.contains(2));
    // A size without a stack path: a compile error in a `const`, a
    // panic here.
    assert!(std::panic::catch_unwind(|| StackSizes::only(8)).is_err());
}

#[test]
fn names_round_trip() {
    for b in Builtin::ALL {
        assert_eq!(Builtin::from_name(b.name()).unwrap(), b);
    }
    assert!(
        Builtin::from_name("nope")
            .unwrap_err()
            .to_string()
            .contains("kepler-hard")
    );
    assert_eq!(Kepler { e: 0.6 }.name(), "kepler");
    assert_eq!(Kepler { e: 0.9 }.name(), "kepler-hard");
}
