//! The implicit schemes of the library, stepping through the stage solver
//! as `butcher!` wires them: quadratic invariants, damping, and agreement
//! with the exact propagator of their stability function on the linear
//! model.

use integrator_core::library::{
    GaussLegendre1, GaussLegendre2, GaussLegendre3, ImplicitEuler, ImplicitMidpoint,
    LobattoIIIAIIIB3, PaperDirk2, PaperDirk4, RadauIIA3,
};
use integrator_core::linear::{Propagator, gyroscopic};
use integrator_core::problems::{Kepler, Oscillator};
use integrator_core::{OdeSystem, Step, energy, integrate};

/// Max relative drift of a quantity over `n` steps.
fn drift<S, M>(m: &M, sys: &S, z0: &[f64], h: f64, n: usize, q: impl Fn(&[f64]) -> f64) -> f64
where
    S: OdeSystem,
    M: Step<S>,
{
    let mut z = z0.to_vec();
    let q0 = q(&z);
    let mut worst: f64 = 0.0;
    integrate(m, sys, &mut z, 0.0, h, n, |_, _, z| {
        worst = worst.max((q(z) - q0).abs() / q0.abs())
    })
    .unwrap();
    worst
}

#[test]
fn gauss_methods_conserve_quadratic_invariants_to_round_off() {
    let kepler = Kepler { e: 0.6 };
    let z0 = kepler.initial_state();
    let l = |z: &[f64]| Kepler::angular_momentum(z);
    let osc = Oscillator { k: 2.0 };
    let e = |z: &[f64]| energy(&osc, z);
    let n = 10_000;
    for (name, dl, de) in [
        (
            "gauss1",
            drift(&GaussLegendre1, &kepler, &z0, 0.01, n, l),
            drift(&GaussLegendre1, &osc, &[1.0, 0.0], 0.1, n, e),
        ),
        (
            "gauss2",
            drift(&GaussLegendre2, &kepler, &z0, 0.01, n, l),
            drift(&GaussLegendre2, &osc, &[1.0, 0.0], 0.1, n, e),
        ),
        (
            "gauss3",
            drift(&GaussLegendre3, &kepler, &z0, 0.01, n, l),
            drift(&GaussLegendre3, &osc, &[1.0, 0.0], 0.1, n, e),
        ),
        (
            "paper-dirk2",
            drift(&PaperDirk2, &kepler, &z0, 0.01, n, l),
            drift(&PaperDirk2, &osc, &[1.0, 0.0], 0.1, n, e),
        ),
        (
            "paper-dirk4",
            drift(&PaperDirk4, &kepler, &z0, 0.01, n, l),
            drift(&PaperDirk4, &osc, &[1.0, 0.0], 0.1, n, e),
        ),
    ] {
        // A random walk of ~√n roundings of size ε.
        let bound = 20.0 * f64::EPSILON * (n as f64).sqrt();
        assert!(dl < bound, "{name}: angular momentum drifts by {dl:e}");
        assert!(de < bound, "{name}: oscillator energy drifts by {de:e}");
    }
    // The Lobatto IIIA–IIIB pair is symplectic and conserves L too.
    let dl = drift(&LobattoIIIAIIIB3, &kepler, &z0, 0.01, n, l);
    assert!(
        dl < 20.0 * f64::EPSILON * (n as f64).sqrt(),
        "lobatto3a3b-3: {dl:e}"
    );
}

#[test]
fn radau_and_implicit_euler_damp() {
    let osc = Oscillator { k: 2.0 };
    for (name, z) in [
        ("radau2a-3", {
            let mut z = vec![1.0, 0.0];
            integrate(&RadauIIA3, &osc, &mut z, 0.0, 0.1, 1000, |_, _, _| {}).unwrap();
            z
        }),
        ("implicit-euler", {
            let mut z = vec![1.0, 0.0];
            integrate(&ImplicitEuler, &osc, &mut z, 0.0, 0.1, 1000, |_, _, _| {}).unwrap();
            z
        }),
    ] {
        let (e0, e1) = (energy(&osc, &[1.0, 0.0]), energy(&osc, &z));
        assert!(
            e1 < e0 * (1.0 - 1e-6),
            "{name}: energy {e0} → {e1} should decay"
        );
    }
}

/// On z' = Hz + u, a Gauss step solved by Newton equals the propagator
/// R(hH) = Q(hH)⁻¹P(hH) of the method's stability function (the diagonal
/// Padé approximant of exp(hH)), and its forcing term, to round-off. The
/// system is stiff-ish (frequencies 1…100, hω up to 5, where the methods'
/// own errors are of order one) and non-normal, so round-off is amplified
/// by conditioning: measured 0.3–2·10⁻¹³ relative after 10 steps, against a
/// bound of 10⁻¹².
#[test]
fn gauss_steps_equal_their_pade_propagators() {
    const STEPS: usize = 10;
    let sys = gyroscopic(6, 7, 100.0).unwrap();
    let z0: Vec<f64> = (0..sys.dim())
        .map(|i| ((i * 7 + 3) % 5) as f64 / 5.0 - 0.4)
        .collect();
    let h = 0.05;
    let check = |name: &str, stepped: Vec<f64>, p: &[f64], q: &[f64]| {
        let prop = Propagator::new(&sys, h, p, q).unwrap();
        let mut z = z0.clone();
        let mut scratch = vec![0.0; sys.dim()];
        for _ in 0..STEPS {
            prop.step(&mut z, &mut scratch);
        }
        let scale = z.iter().map(|x| x.abs()).fold(1.0, f64::max);
        let diff = stepped
            .iter()
            .zip(&z)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(
            diff < 1e-12 * scale,
            "{name}: solver and propagator differ by {diff:e}"
        );
    };
    let run = |m: &dyn Fn(&mut Vec<f64>)| {
        let mut z = z0.clone();
        m(&mut z);
        z
    };
    let z1 = run(&|z| integrate(&GaussLegendre1, &sys, z, 0.0, h, STEPS, |_, _, _| {}).unwrap());
    check(
        "gauss1",
        z1,
        &GaussLegendre1::STABILITY_P,
        &GaussLegendre1::STABILITY_Q,
    );
    let z2 = run(&|z| integrate(&GaussLegendre2, &sys, z, 0.0, h, STEPS, |_, _, _| {}).unwrap());
    check(
        "gauss2",
        z2,
        &GaussLegendre2::STABILITY_P,
        &GaussLegendre2::STABILITY_Q,
    );
    let z3 = run(&|z| integrate(&GaussLegendre3, &sys, z, 0.0, h, STEPS, |_, _, _| {}).unwrap());
    check(
        "gauss3",
        z3,
        &GaussLegendre3::STABILITY_P,
        &GaussLegendre3::STABILITY_Q,
    );
    let zm = run(&|z| integrate(&ImplicitMidpoint, &sys, z, 0.0, h, STEPS, |_, _, _| {}).unwrap());
    check(
        "midpoint",
        zm,
        &ImplicitMidpoint::STABILITY_P,
        &ImplicitMidpoint::STABILITY_Q,
    );
}
