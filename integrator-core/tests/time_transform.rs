//! The logarithmic Hamiltonian: the library's drift–kick schemes applied to
//! it are symplectic in the extended phase space and reversible, and for
//! Kepler leapfrog on it follows the exact orbit.

use integrator_core::library::{ForestRuth, KahanLi8, Leapfrog, Rk4};
use integrator_core::problems::Kepler;
use integrator_core::time_transform::{LogHamiltonian, TimeTransformError};
use integrator_core::{Separable, Step, energy};

use crate::common;
use common::symplecticity_defect as defect;

type Sys = LogHamiltonian<Kepler>;
/// One step `w ← Ψ_h(w)` of a scheme on the extended system.
type StepFn = fn(&Sys, f64, &mut [f64]);

fn one_step<M: Step<Sys> + Default>(sys: &Sys, h: f64, w: &mut [f64]) {
    let m = M::default();
    let mut ws = m.workspace(sys);
    m.step(sys, 0.0, h, w, &mut ws)
        .expect("explicit steps do not fail");
}

/// `Ψ'` of one step on `sys` (the finite differences `symplectic_in_fact.rs`
/// measures the library's schemes with).
fn jacobian(step: StepFn, sys: &Sys, h: f64, w: &[f64]) -> Vec<Vec<f64>> {
    common::jacobian(|w| step(sys, h, w), w, 3e-3)
}

fn start(e: f64) -> (Sys, Vec<f64>) {
    let kepler = Kepler { e };
    let z0 = kepler.initial_state();
    let sys = LogHamiltonian::new(kepler);
    let w = sys.extend(&z0, 0.0).unwrap();
    (sys, w)
}

#[test]
fn drift_kick_schemes_are_symplectic_in_the_extended_phase_space() {
    let (sys, w0) = start(0.6);
    // Off the energy surface too: symplecticity holds on the whole domain.
    let mut off = w0.clone();
    off[4] += 0.05;
    off[0] += 0.1;
    let schemes: [(&str, StepFn); 3] = [
        ("leapfrog", one_step::<Leapfrog>),
        ("forest-ruth", one_step::<ForestRuth>),
        ("kahan-li8", one_step::<KahanLi8>),
    ];
    for w in [&w0, &off] {
        for (id, step) in schemes {
            let d = defect(&jacobian(step, &sys, 0.2, w));
            assert!(d < 1e-11, "{id}: defect {d:e}");
        }
        // A Runge–Kutta baseline on the same system is not symplectic.
        let d = defect(&jacobian(one_step::<Rk4>, &sys, 0.2, w));
        assert!(d > 1e-6, "rk4: defect {d:e}");
    }
}

#[test]
fn symmetric_schemes_are_reversible_to_round_off() {
    let (sys, w0) = start(0.9);
    for (id, step) in [
        (
            "leapfrog",
            one_step::<Leapfrog> as fn(&Sys, f64, &mut [f64]),
        ),
        ("forest-ruth", one_step::<ForestRuth>),
        ("kahan-li8", one_step::<KahanLi8>),
    ] {
        let mut w = w0.clone();
        for _ in 0..50 {
            step(&sys, 0.05, &mut w);
        }
        assert!(sys.time(&w) > 0.0);
        for _ in 0..50 {
            step(&sys, -0.05, &mut w);
        }
        let err = w
            .iter()
            .zip(&w0)
            .map(|(a, b)| (a - b).abs() / b.abs().max(1.0))
            .fold(0.0, f64::max);
        assert!(err < 1e-13, "{id}: back to the start within {err:e}");
    }
}

/// Angular momentum and the Runge–Lenz vector of a Kepler state.
fn invariants(z: &[f64]) -> (f64, [f64; 2]) {
    let [x, y, u, v] = [z[0], z[1], z[2], z[3]];
    let l = x * v - y * u;
    let r = x.hypot(y);
    (l, [v * l - x / r, -u * l - y / r])
}

#[test]
fn leapfrog_on_the_logarithmic_hamiltonian_keeps_keplers_orbit() {
    let (sys, mut w) = start(0.9);
    let kepler = Kepler { e: 0.9 };
    let z0 = kepler.initial_state();
    let (l0, a0) = invariants(&z0);
    let e0 = energy(&kepler, &z0);
    // ∫ dt/r over one orbit of a = 1 is 2π: 100 steps of s per orbit.
    let ds = 2.0 * std::f64::consts::PI / 100.0;
    let mut ws = Step::<Sys>::workspace(&Leapfrog, &sys);
    let (mut worst_l, mut worst_a, mut worst_e) = (0.0f64, 0.0f64, 0.0f64);
    let mut phase = Vec::new();
    for k in 1..=1_000_000usize {
        Leapfrog
            .step_reusing(&sys, 0.0, ds, &mut w, &mut ws, k > 1)
            .unwrap();
        if k % 1000 == 0 {
            let (z, t) = sys.restrict(&w);
            let (l, a) = invariants(&z);
            worst_l = worst_l.max((l - l0).abs());
            worst_a = worst_a.max((a[0] - a0[0]).abs().max((a[1] - a0[1]).abs()));
            worst_e = worst_e.max(((energy(&kepler, &z) - e0) / e0).abs());
            // The phase error: the mean anomaly of the state (a = 1, so
            // the mean motion is 1) against t, unwrapped by continuity.
            let m = mean_anomaly(&z, 0.9);
            let prev = phase.last().map_or(0.0, |p: &(f64, f64)| p.1);
            let tau = 2.0 * std::f64::consts::PI;
            let mut step = (m - t - prev).rem_euclid(tau);
            if step > std::f64::consts::PI {
                step -= tau;
            }
            phase.push((t, prev + step));
        }
    }
    let (_, t_end) = sys.restrict(&w);
    assert!(
        t_end > 2.0 * std::f64::consts::PI * 9990.0,
        "10⁴ orbits: t = {t_end}"
    );
    // The orbit: L, A and H to round-off after 10⁶ steps.
    assert!(worst_l < 1e-11, "angular momentum drift {worst_l:e}");
    assert!(worst_a < 1e-11, "Runge–Lenz drift {worst_a:e}");
    assert!(worst_e < 1e-11, "energy drift {worst_e:e}");
    // The phase error grows linearly: tenfold over ten times as long.
    let (t1, e1) = phase[99];
    let (t10, e10) = phase[999];
    let growth = (e10 / e1) / (t10 / t1);
    assert!(
        e1.abs() > 1e-6 && (0.9..1.1).contains(&growth),
        "phase error {e1:e} at t = {t1}, {e10:e} at t = {t10}"
    );
}

/// The mean anomaly `M = E − e sin E` of a Kepler state with `a = 1`
/// (`r = 1 − e cos E`, `q·p = e sin E`).
fn mean_anomaly(z: &[f64], e: f64) -> f64 {
    let r = z[0].hypot(z[1]);
    let qp = z[0] * z[2] + z[1] * z[3];
    let ecc = qp.atan2(1.0 - r);
    ecc - e * ecc.sin()
}

#[test]
fn a_potential_that_is_not_negative_is_refused() {
    let (sys, _) = start(0.5);
    // At q = 0 the Kepler potential is −∞; far away it is ~0⁻; a positive
    // potential comes from a shifted system.
    #[derive(Clone)]
    struct Spring;
    impl Separable for Spring {
        fn dof(&self) -> usize {
            1
        }
        fn kinetic(&self, p: &[f64]) -> f64 {
            0.5 * p[0] * p[0]
        }
        fn potential(&self, q: &[f64]) -> f64 {
            0.5 * q[0] * q[0]
        }
        fn velocity(&self, p: &[f64], v: &mut [f64]) {
            v[0] = p[0];
        }
        fn force(&self, q: &[f64], f: &mut [f64]) {
            f[0] = -q[0];
        }
    }
    let e = LogHamiltonian::new(Spring)
        .extend(&[1.0, 0.0], 0.0)
        .unwrap_err();
    assert!(matches!(e, TimeTransformError::PotentialNotNegative { .. }));
    assert!(e.to_string().contains("V(q) < 0"), "{e}");
    assert!(matches!(
        sys.extend(&[1.0, 0.0], 0.0),
        Err(TimeTransformError::Dimension {
            expected: 4,
            got: 2
        })
    ));
    assert!(matches!(
        sys.extend(&[1.0, 0.0, f64::NAN, 0.0], 0.0),
        Err(TimeTransformError::NonFinite { index: 2, .. })
    ));
}

#[test]
fn kepler_force_and_potential_give_the_bits_of_force_and_potential() {
    // The logarithmic Hamiltonian's kick takes both from one call; Kepler
    // shares the square root, and must not change a bit by it.
    let kepler = Kepler { e: 0.9 };
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 * 4.0 - 2.0
    };
    for _ in 0..1000 {
        let q = [next(), next()];
        let (mut a, mut b) = ([0.0; 2], [0.0; 2]);
        kepler.force(&q, &mut a);
        let v = kepler.force_and_potential(&q, &mut b);
        assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits), "q = {q:?}");
        assert_eq!(v.to_bits(), kepler.potential(&q).to_bits(), "q = {q:?}");
    }
}
