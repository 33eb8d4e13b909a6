//! The hard test problems: forces are exact gradients, the numerical
//! references are converged, and the problems are as hard as claimed.

use integrator_core::problems::{ExactFlow, Fpu, HenonHeiles, Kepler, reference_solution};
use integrator_core::{Separable, energy, integrate};

/// `force = −∇V` by central differences.
fn check_gradient<S: Separable>(sys: &S, q: &[f64]) {
    let n = q.len();
    let mut f = vec![0.0; n];
    sys.force(q, &mut f);
    for i in 0..n {
        let d = 1e-6;
        let (mut qp, mut qm) = (q.to_vec(), q.to_vec());
        qp[i] += d;
        qm[i] -= d;
        let fd = -(sys.potential(&qp) - sys.potential(&qm)) / (2.0 * d);
        assert!(
            (fd - f[i]).abs() <= 1e-6 * (1.0 + f[i].abs()),
            "component {i}: {fd} vs {}",
            f[i]
        );
    }
}

#[test]
fn forces_are_exact_gradients() {
    check_gradient(&HenonHeiles, &[0.3, -0.2]);
    let fpu = Fpu::stiff();
    check_gradient(&fpu, &[0.1, 0.15, -0.2, 0.05, 0.3, -0.1]);
}

#[test]
fn references_are_converged() {
    let hh = HenonHeiles;
    let z0 = HenonHeiles::chaotic_start();
    let a = hh.reference(&z0, 10.0);
    let b = reference_solution(&hh, &z0, 10.0, 4000.0);
    let diff = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(
        diff < 1e-13,
        "Hénon–Heiles reference moves by {diff:e} when the step halves"
    );

    let fpu = Fpu::stiff();
    let z0 = fpu.start();
    let a = fpu.reference(&z0, 1.0);
    let b = reference_solution(&fpu, &z0, 1.0, 80.0 * fpu.omega);
    let diff = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(
        diff < 1e-12,
        "FPU reference moves by {diff:e} when the step halves"
    );
}

#[test]
fn fpu_start_is_hlw_and_stiff() {
    let fpu = Fpu::stiff();
    let z0 = fpu.start();
    // One stiff spring carries energy ½(1 + ω²·ω⁻²) = 1; the others none.
    let i = fpu.stiff_energies(&z0);
    assert!(
        (i[0] - 1.0).abs() < 1e-14 && i[1] == 0.0 && i[2] == 0.0,
        "{i:?}"
    );
    // Leapfrog is unstable beyond hω = 2: at hω = 2.2 it blows up.
    let mut z = z0.clone();
    let r = integrate(
        &integrator_core::library::Leapfrog,
        &fpu,
        &mut z,
        0.0,
        2.2 / fpu.omega,
        2000,
        |_, _, _| {},
    );
    assert!(
        r.is_err(),
        "leapfrog beyond its stability limit should diverge"
    );
}

#[test]
fn kepler_hard_case_is_eccentric() {
    let k = Kepler { e: 0.9 };
    let z0 = k.initial_state();
    // Pericentre speed √19 ≈ 4.36 against apocentre speed ≈ 0.23.
    assert!((z0[3] - 19f64.sqrt()).abs() < 1e-14);
    let e0 = energy(&k, &z0);
    let z = k.flow(&z0, std::f64::consts::PI).unwrap();
    assert!((energy(&k, &z) - e0).abs() < 1e-13);
    assert!((z[0] + 1.9).abs() < 1e-12, "apocentre at q₁ = −(1 + e)");
}
