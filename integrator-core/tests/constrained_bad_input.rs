//! Bad input to the constrained steppers: errors that name the constraint,
//! the field, or the step and time, never a panic.

use integrator_core::constrained::{
    Constrained, ConstrainedError, ConstrainedPair, LobattoPair, NewtonSettings, Where,
    integrate_constrained,
};
use integrator_core::library::GaussLegendre2;
use integrator_core::problems::{PendulumChain, SphericalPendulum};

fn run<S: Constrained, const K: usize>(
    method: &ConstrainedPair<K>,
    sys: &S,
    z: &mut [f64],
    t0: f64,
    h: f64,
    n: usize,
) -> ConstrainedError {
    integrate_constrained(method, sys, z, t0, h, n, |_, _, _| {}).unwrap_err()
}

#[test]
fn an_initial_state_off_the_manifold_names_the_constraint() {
    let sys = PendulumChain::uniform(2, 4, 1.0, 9.81).unwrap();
    let mut z = sys.state(&[0.1, 0.2, 0.3, 0.4], &[0.0; 4]);
    // The last bob moved by 1e-6: only link 4 is violated.
    z[3 * 2] += 1e-6;
    let e = run(&ConstrainedPair::rattle(), &sys, &mut z, 0.0, 1e-3, 10);
    let msg = e.to_string();
    println!("{msg}");
    assert!(
        matches!(e, ConstrainedError::OffManifold { constraint: 3, .. }),
        "{e:?}"
    );
    assert!(msg.contains("link 4 (bob 3 – bob 4)"), "{msg}");

    // A momentum with a radial component on the sphere.
    let sp = SphericalPendulum::new(1.0, 1.0, 9.81);
    let mut z = sp.state(1.0, 0.0, 0.5, 0.0);
    for i in 0..3 {
        z[3 + i] += 1e-8 * z[i];
    }
    let e = run(&ConstrainedPair::lobatto3a3b3(), &sp, &mut z, 0.0, 1e-2, 10);
    println!("{e}");
    assert!(
        matches!(e, ConstrainedError::OffTangent { constraint: 0, .. }),
        "{e:?}"
    );
    assert!(e.to_string().contains("the rod"), "{e}");
}

#[test]
fn a_zero_length_link_is_a_degenerate_constraint_named_at_the_start() {
    // Link 2 has length 0 and bobs 1 and 2 coincide: its gradient vanishes
    // and G loses rank.
    let sys = PendulumChain::new(2, vec![0.5, 0.0, 0.5], vec![1.0; 3], 9.81).unwrap();
    let mut z = sys.state(&[0.3, 0.0, 0.5], &[0.0; 3]);
    let e = run(&ConstrainedPair::rattle(), &sys, &mut z, 0.0, 1e-3, 10);
    println!("{e}");
    assert!(
        matches!(
            e,
            ConstrainedError::Degenerate {
                where_: Where::Start,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(
        e.to_string()
            .contains("link 2 (bob 1 – bob 2) has a zero gradient"),
        "{e}"
    );
}

/// Two constraints with dependent gradients (a spherical pendulum whose rod
/// is constrained twice) have no zero row but a singular `G M⁻¹ Gᵀ`.
struct DoubleRod(SphericalPendulum);

impl Constrained for DoubleRod {
    fn dof(&self) -> usize {
        3
    }
    fn constraints(&self) -> usize {
        2
    }
    fn inverse_mass(&self, out: &mut [f64]) {
        self.0.inverse_mass(out)
    }
    fn potential(&self, q: &[f64]) -> f64 {
        self.0.potential(q)
    }
    fn grad_potential(&self, q: &[f64], out: &mut [f64]) {
        self.0.grad_potential(q, out)
    }
    fn constraint(&self, q: &[f64], out: &mut [f64]) {
        self.0.constraint(q, &mut out[..1]);
        out[1] = 2.0 * out[0];
    }
    fn constraint_jacobian(&self, q: &[f64], out: &mut [f64]) {
        self.0.constraint_jacobian(q, &mut out[..3]);
        for a in 0..3 {
            out[3 + a] = 2.0 * out[a];
        }
    }
}

#[test]
fn dependent_constraints_are_degenerate() {
    let sys = DoubleRod(SphericalPendulum::new(1.0, 1.0, 9.81));
    let mut z = sys.0.state(1.0, 0.0, 0.5, 0.3);
    let e = run(&ConstrainedPair::rattle(), &sys, &mut z, 0.0, 1e-2, 10);
    println!("{e}");
    assert!(matches!(e, ConstrainedError::Degenerate { .. }), "{e:?}");
    assert!(e.to_string().contains("dependent"), "{e}");
}

#[test]
fn an_absurd_step_fails_with_the_step_and_time_and_leaves_the_state() {
    // h = 100 on a swinging pendulum: the line of RATTLE's position step
    // misses the sphere, so g(q₁) = 0 has no solution.
    let sys = SphericalPendulum::new(1.0, 1.0, 9.81);
    let z0 = sys.state(1.0, 0.0, 0.5, 2.0);
    for (name, e, z) in [
        {
            let mut z = z0.clone();
            let e = run(&ConstrainedPair::rattle(), &sys, &mut z, 2.5, 100.0, 3);
            ("RATTLE", e, z)
        },
        {
            let mut z = z0.clone();
            let e = run(
                &ConstrainedPair::lobatto3a3b3(),
                &sys,
                &mut z,
                2.5,
                100.0,
                3,
            );
            ("s = 3", e, z)
        },
    ] {
        println!("{name}: {e}");
        let where_ = match &e {
            ConstrainedError::NotConverged { where_, .. }
            | ConstrainedError::Diverged { where_, .. }
            | ConstrainedError::Degenerate { where_, .. } => *where_,
            other => panic!("{name}: unexpected {other:?}"),
        };
        assert_eq!(where_, Where::Step { step: 1, t: 2.5 }, "{name}");
        assert!(e.to_string().contains("step 1 (from t = 2.5)"), "{e}");
        assert_eq!(z, z0, "{name}: the failed step left the state changed");
    }
}

#[test]
fn the_iteration_cap_is_an_error_never_accepted() {
    // One Newton iteration cannot reach round-off from a cold start; the
    // later steps of the run are never reached.
    let sys = PendulumChain::uniform(3, 3, 1.0, 9.81).unwrap();
    let mut z = sys.state(&[0.5, 0.6, 0.7], &[1.0, -1.0, 0.5]);
    let one = NewtonSettings {
        max_iterations: 1,
        ..NewtonSettings::default()
    };
    let e = run(
        &ConstrainedPair::lobatto3a3b3().with_settings(one),
        &sys,
        &mut z,
        0.0,
        0.01,
        5,
    );
    println!("{e}");
    assert!(
        matches!(
            e,
            ConstrainedError::NotConverged {
                where_: Where::Step { step: 1, .. },
                iterations: 1,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(
        e.to_string()
            .contains("did not converge in 1 Newton iterations"),
        "{e}"
    );
}

#[test]
fn malformed_input_is_named() {
    let sys = SphericalPendulum::new(1.0, 1.0, 9.81);
    let z = sys.state(1.0, 0.0, 0.5, 0.3);
    let r = ConstrainedPair::rattle();
    let mut short = z[..5].to_vec();
    assert!(matches!(
        run(&r, &sys, &mut short, 0.0, 0.1, 1),
        ConstrainedError::Dimension {
            expected: 6,
            got: 5
        }
    ));
    for h in [0.0, f64::NAN, f64::INFINITY] {
        let mut zz = z.clone();
        assert!(matches!(
            run(&r, &sys, &mut zz, 0.0, h, 1),
            ConstrainedError::StepSize(_)
        ));
    }
    let mut nan = z.clone();
    nan[4] = f64::NAN;
    assert!(matches!(
        run(&r, &sys, &mut nan, 0.0, 0.1, 1),
        ConstrainedError::NonFiniteInitial { index: 4, .. }
    ));
    let heavy = SphericalPendulum::new(1.0, 0.0, 9.81);
    let mut zz = z.clone();
    let e = run(&r, &heavy, &mut zz, 0.0, 0.1, 1);
    assert!(
        matches!(e, ConstrainedError::Mass { index: 0, .. }),
        "{e:?}"
    );

    let e = PendulumChain::new(2, vec![1.0, 1.0], vec![1.0, -1.0], 9.81).unwrap_err();
    assert_eq!(e.field, "masses[1]");
    let e = PendulumChain::new(4, vec![1.0], vec![1.0], 9.81).unwrap_err();
    assert_eq!(e.field, "dim");
    let e = PendulumChain::new(2, vec![1.0, f64::NAN], vec![1.0, 1.0], 9.81).unwrap_err();
    assert_eq!(e.field, "lengths[1]");
}

#[test]
fn a_table_without_the_lobatto_structure_is_refused_naming_the_entry() {
    // Gauss–Legendre 2 as both halves: its first row of A does not vanish.
    let e = LobattoPair::new(
        "gauss2",
        GaussLegendre2::A,
        GaussLegendre2::B,
        GaussLegendre2::A,
        GaussLegendre2::B,
        4,
    )
    .unwrap_err();
    println!("{e}");
    assert!(e.to_string().contains("A[0][0]"), "{e}");
}

#[test]
fn a_workspace_made_for_another_system_or_pair_is_refused() {
    let sphere = SphericalPendulum::new(1.0, 1.0, 9.81);
    let chain = PendulumChain::uniform(2, 3, 1.0, 9.81).unwrap();
    let mut z = sphere.state(1.0, 0.0, 0.5, 0.3);
    let rattle = ConstrainedPair::rattle();
    let mut ws = rattle.workspace(&chain);
    let e = rattle
        .step(&sphere, 0.0, 0.01, &mut z, &mut ws)
        .unwrap_err();
    assert!(matches!(e, ConstrainedError::Workspace { .. }), "{e:?}");
    let mut ws = rattle.workspace(&sphere);
    let e = ConstrainedPair::lobatto3a3b3()
        .step(&sphere, 0.0, 0.01, &mut z, &mut ws)
        .unwrap_err();
    println!("{e}");
    assert!(e.to_string().contains("made for 2 stages"), "{e}");
    let e = rattle
        .step(&sphere, 0.0, f64::NAN, &mut z, &mut ws)
        .unwrap_err();
    assert!(matches!(e, ConstrainedError::StepSize(_)), "{e:?}");
}
