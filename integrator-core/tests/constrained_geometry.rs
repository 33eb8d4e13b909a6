//! Symplectic on the constraint manifold and time-reversible, measured.
//!
//! The step maps the cotangent bundle of the sphere to itself; in local
//! coordinates (spherical angles `θ, φ` and their conjugate momenta
//! `p_θ, p_φ`, `SphericalPendulum::{from_local, to_local}`) it is a map of
//! ℝ⁴, and symplecticity on the manifold means that this map's Jacobian
//! `Ψ'` satisfies `Ψ'ᵀJΨ' = J`. `Ψ'` comes from the finite differences of
//! `symplectic_in_fact.rs` (`common::jacobian`: central differences with
//! `δ, δ/2, δ/4` and two Richardson rounds), each evaluation a cold step
//! from its own workspace, so that the warm start cannot couple them. The
//! tolerance is that file's, `1e-11`: what the differences resolve. A map
//! that is not symplectic (explicit Euler followed by a projection onto the
//! manifold) misses it by orders of magnitude, so the test can fail.

use integrator_core::constrained::{ConstrainedPair, integrate_constrained};
use integrator_core::problems::{PendulumChain, SphericalPendulum};

use crate::common;
use common::{jacobian, symplecticity_defect};

const TOL: f64 = 1e-11;

fn sphere() -> SphericalPendulum {
    SphericalPendulum::new(1.3, 0.7, 9.81)
}

/// One cold step of `method` in local coordinates.
fn local_step<const K: usize>(
    method: &ConstrainedPair<K>,
    sys: &SphericalPendulum,
    h: f64,
    y: &mut [f64],
) {
    let mut z = sys.from_local(y);
    let mut ws = method.workspace(sys);
    method
        .step(sys, 0.0, h, &mut z, &mut ws)
        .expect("the step converges");
    y.copy_from_slice(&sys.to_local(&z));
}

/// Explicit Euler, then the position scaled back onto the sphere and the
/// momentum projected onto its tangent plane: a consistent constrained
/// method that is not symplectic.
fn projected_euler_step(sys: &SphericalPendulum, h: f64, y: &mut [f64]) {
    let z = sys.from_local(y);
    let (m, l, g) = (sys.mass, sys.length, sys.gravity);
    let mut q: Vec<f64> = (0..3).map(|i| z[i] + h * z[3 + i] / m).collect();
    let mut p: Vec<f64> = z[3..].to_vec();
    p[2] -= h * m * g;
    let r = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
    q.iter_mut().for_each(|x| *x *= l / r);
    let k = (q[0] * p[0] + q[1] * p[1] + q[2] * p[2]) / (l * l);
    (0..3).for_each(|i| p[i] -= k * q[i]);
    let z1: Vec<f64> = q.into_iter().chain(p).collect();
    y.copy_from_slice(&sys.to_local(&z1));
}

/// Local states away from the poles (θ ∈ (0, π)) and from the cut of φ.
fn local_states(sys: &SphericalPendulum) -> Vec<[f64; 4]> {
    let ml2 = sys.mass * sys.length * sys.length;
    vec![
        [1.2, 0.3, 0.0, ml2 * 1.2_f64.sin().powi(2) * 2.0],
        [0.7, -1.1, 0.8 * ml2, 0.5 * ml2],
        [2.0, 2.0, -1.5 * ml2, -ml2],
    ]
}

#[test]
fn symplectic_on_the_manifold_in_local_coordinates() {
    let sys = sphere();
    let rattle = ConstrainedPair::rattle();
    let lob3 = ConstrainedPair::lobatto3a3b3();
    for y0 in local_states(&sys) {
        for h in [0.02, 0.1] {
            let d2 =
                symplecticity_defect(&jacobian(|y| local_step(&rattle, &sys, h, y), &y0, 3e-3));
            let d3 = symplecticity_defect(&jacobian(|y| local_step(&lob3, &sys, h, y), &y0, 3e-3));
            let de =
                symplecticity_defect(&jacobian(|y| projected_euler_step(&sys, h, y), &y0, 3e-3));
            println!(
                "y0 = {y0:.3?}, h = {h}: defect RATTLE {d2:.2e}, s = 3 {d3:.2e}, projected Euler {de:.2e}"
            );
            assert!(d2 < TOL, "RATTLE: {d2}");
            assert!(d3 < TOL, "s = 3: {d3}");
            assert!(
                de > 1e3 * TOL,
                "the control is not resolved as non-symplectic: {de}"
            );
        }
    }
}

/// Forward `n` steps, momenta flipped, `n` steps, flipped again: the start,
/// to a bound in units of `ε·max|z|`.
fn round_trip<S: integrator_core::constrained::Constrained, const K: usize>(
    method: &ConstrainedPair<K>,
    sys: &S,
    z0: &[f64],
    h: f64,
    n: usize,
) -> f64 {
    let d = sys.dof();
    let mut z = z0.to_vec();
    integrate_constrained(method, sys, &mut z, 0.0, h, n, |_, _, _| {}).unwrap();
    z[d..].iter_mut().for_each(|p| *p = -*p);
    integrate_constrained(method, sys, &mut z, n as f64 * h, h, n, |_, _, _| {}).unwrap();
    z[d..].iter_mut().for_each(|p| *p = -*p);
    let scale = z0.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let err = z
        .iter()
        .zip(z0)
        .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
    err / (f64::EPSILON * scale)
}

/// The bound of the round trip, in units of `ε·max|z|`: rounding errors of
/// 2n steps, grown by the flow's shear over the run (measured: 2–13).
const ROUND_TRIP_ULPS: f64 = 256.0;

#[test]
fn reversible_forward_flip_back_flip_returns_to_the_start() {
    let sys = sphere();
    let z0 = sys.from_local(&local_states(&sys)[1]);
    let chain = PendulumChain::uniform(2, 6, 1.0, 9.81).unwrap();
    let angles: Vec<f64> = (0..6).map(|i| 0.4 + 0.3 * (i as f64).cos()).collect();
    let zc = chain.state(&angles, &[0.3, -0.2, 0.1, 0.0, 0.2, -0.1]);
    let cases = [
        (
            "sphere, RATTLE, h = 0.05, 200 steps",
            round_trip(&ConstrainedPair::rattle(), &sys, &z0, 0.05, 200),
        ),
        (
            "sphere, s = 3, h = 0.1, 100 steps",
            round_trip(&ConstrainedPair::lobatto3a3b3(), &sys, &z0, 0.1, 100),
        ),
        (
            "chain of 6, RATTLE, h = 5e-3, 200 steps",
            round_trip(&ConstrainedPair::rattle(), &chain, &zc, 5e-3, 200),
        ),
        (
            "chain of 6, s = 3, h = 1e-2, 100 steps",
            round_trip(&ConstrainedPair::lobatto3a3b3(), &chain, &zc, 1e-2, 100),
        ),
    ];
    for (name, ulps) in cases {
        println!("{name}: back at the start to {ulps:.1} ε·max|z|");
        assert!(ulps < ROUND_TRIP_ULPS, "{name}: {ulps}");
    }
}
