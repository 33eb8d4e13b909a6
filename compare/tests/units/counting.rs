//! Tests of `compare::counting` (from its `#[cfg(test)]` module: `compare`
//! has no unit-test harness, which would compile the whole crate a second
//! time; see `compare/tests/units/mod.rs`).

use compare::counting::*;
use integrator_core::problems::Kepler;
use integrator_core::{OdeSystem, Separable};

#[test]
fn counts_force_and_velocity_through_the_blanket_rhs() {
    let c: Counting<Kepler> = Counting::new(Kepler { e: 0.5 });
    let z = Kepler { e: 0.5 }.initial_state();
    let mut dz = vec![0.0; 4];
    c.rhs(0.0, &z, &mut dz);
    c.rhs(0.0, &z, &mut dz);
    let mut f = [0.0; 2];
    c.force(&z[..2], &mut f);
    assert_eq!(
        c.counts(),
        Counts {
            velocity: 2,
            force: 3,
            rhs: 0
        }
    );
}

#[test]
fn counts_rhs_of_an_ode_system() {
    let sys = integrator_core::linear::gyroscopic(3, 1, 10.0).unwrap();
    let c: Counting<_, AsOde> = Counting::new(sys);
    let mut dz = vec![0.0; 6];
    c.rhs(0.0, &[1.0; 6], &mut dz);
    let mut j = vec![0.0; 36];
    assert!(c.jacobian(0.0, &[1.0; 6], &mut j));
    assert_eq!(
        c.counts(),
        Counts {
            velocity: 0,
            force: 0,
            rhs: 1
        }
    );
}
