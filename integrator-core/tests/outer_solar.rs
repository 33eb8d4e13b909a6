//! The outer solar system (HLW I.2.3): the published data, a converged
//! reference over HLW's 10⁵ days, conservation by a symplectic scheme.

use integrator_core::library::{KahanLi8, StormerVerlet};
use integrator_core::problems::outer_solar::{MASSES, POSITIONS};
use integrator_core::problems::{OuterSolarSystem, reference_solution};
use integrator_core::{energy, integrate};

fn rel_dist(a: &[f64], b: &[f64]) -> f64 {
    let d: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
    let r: f64 = b.iter().map(|y| y * y).sum();
    (d / r).sqrt()
}

#[test]
fn the_published_data_and_the_forces() {
    let sys = OuterSolarSystem;
    let z0 = sys.initial_state();
    assert_eq!(z0.len(), 36);
    // Jupiter at 5.4 AU from the Sun, Pluto at ~30 AU.
    let r = |i: usize| POSITIONS[i].iter().map(|x| x * x).sum::<f64>().sqrt();
    assert!((5.0..5.5).contains(&r(1)), "{}", r(1));
    assert!((29.0..31.0).contains(&r(5)), "{}", r(5));
    // Bound: negative energy; momenta are m·v.
    assert!(energy(&sys, &z0) < 0.0);
    assert_eq!(z0[18 + 3], MASSES[1] * 0.00565429);
    // The force is −∇V (central differences).
    let q = &z0[..18];
    let mut f = vec![0.0; 18];
    integrator_core::Separable::force(&sys, q, &mut f);
    for k in 0..18 {
        let h = 1e-6;
        let mut a = q.to_vec();
        let mut b = q.to_vec();
        a[k] += h;
        b[k] -= h;
        let g = -(integrator_core::Separable::potential(&sys, &a)
            - integrator_core::Separable::potential(&sys, &b))
            / (2.0 * h);
        assert!(
            (g - f[k]).abs() <= 1e-6 * f[k].abs() + 1e-16,
            "k = {k}: {g:e} vs {:e}",
            f[k]
        );
    }
    // Newton's third law: the forces sum to zero.
    for c in 0..3 {
        let s: f64 = (0..6).map(|i| f[3 * i + c]).sum();
        assert!(s.abs() < 1e-18, "{s:e}");
    }
}

#[test]
fn the_reference_over_ten_to_the_five_days_is_converged() {
    // The compare builtin's reference: Sofroniou–Spaletta order 10 with
    // h = 5 days. Halving the step and a different method (Kahan–Li 8,
    // h = 2 days) agree with it to 1e-11.
    let sys = OuterSolarSystem;
    let z0 = sys.initial_state();
    let t = 1e5;
    let r = reference_solution(&sys, &z0, t, 0.2);
    let r2 = reference_solution(&sys, &z0, t, 0.4);
    let mut k = z0.clone();
    integrate(&KahanLi8, &sys, &mut k, 0.0, 2.0, 50_000, |_, _, _| {}).unwrap();
    let d2 = rel_dist(&r2, &r);
    let dk = rel_dist(&k, &r);
    assert!(d2 < 1e-11, "h = 5 vs 2.5: {d2:e}");
    assert!(dk < 1e-11, "kahan-li8: {dk:e}");
    // And the run went somewhere: Jupiter has moved by many AU.
    assert!(rel_dist(&r, &z0) > 0.1);
}

#[test]
fn stormer_verlet_keeps_the_energy_and_the_angular_momentum() {
    // HLW Fig. I.2.4's setting: h = 10 days over 2·10⁵ days is stable for
    // Störmer–Verlet; here 10⁵ days.
    let sys = OuterSolarSystem;
    let mut z = sys.initial_state();
    let e0 = energy(&sys, &z);
    let l0 = OuterSolarSystem::angular_momentum(&z);
    let mut worst = 0.0f64;
    integrate(
        &StormerVerlet,
        &sys,
        &mut z,
        0.0,
        10.0,
        10_000,
        |_, _, z| {
            worst = worst.max(((energy(&sys, z) - e0) / e0).abs());
        },
    )
    .unwrap();
    assert!(worst < 1e-5, "energy error {worst:e}");
    let l = OuterSolarSystem::angular_momentum(&z);
    let n0 = l0.iter().map(|x| x * x).sum::<f64>().sqrt();
    for c in 0..3 {
        assert!(
            (l[c] - l0[c]).abs() < 1e-13 * n0,
            "L[{c}]: {} vs {}",
            l[c],
            l0[c]
        );
    }
}
