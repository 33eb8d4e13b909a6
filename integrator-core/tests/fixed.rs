//! The fixed-size path (`StepFixed`, `integrate_fixed`) does the slice
//! path's arithmetic: bit-identical states after many steps, for every
//! form of explicit table (Runge–Kutta, drift–kick, composition, explicit
//! partitioned pair with first same as last), plain and compensated; and
//! it keeps `integrate`'s checks.

use integrator_core::fixed::{StepFixed, integrate_fixed, integrate_fixed_with};
use integrator_core::library::*;
use integrator_core::{Separable, Step, StepError, integrate};

/// Kepler with an anharmonic perturbation, so that no step is trivially
/// exact: H = |p|²/2 − 1/|q| − ε/|q|³.
struct PerturbedKepler;

impl Separable for PerturbedKepler {
    fn dof(&self) -> usize {
        2
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        0.5 * (p[0] * p[0] + p[1] * p[1])
    }
    fn potential(&self, q: &[f64]) -> f64 {
        let r = q[0].hypot(q[1]);
        -1.0 / r - 1e-3 / (r * r * r)
    }
    fn velocity(&self, p: &[f64], v: &mut [f64]) {
        v[0] = p[0];
        v[1] = p[1];
    }
    fn force(&self, q: &[f64], f: &mut [f64]) {
        let r2 = q[0] * q[0] + q[1] * q[1];
        let r = r2.sqrt();
        let c = -1.0 / (r2 * r) - 3e-3 / (r2 * r2 * r);
        f[0] = c * q[0];
        f[1] = c * q[1];
    }
}

const Z0: [f64; 4] = [0.4, 0.0, 0.0, 2.0]; // e = 0.6
const H: f64 = 1e-3;
const STEPS: usize = 3000;

/// The slice path through `integrate` (compensated, first same as last)
/// and with direct plain `step` calls, against the fixed path the same two
/// ways.
fn same_bits<M>(method: M)
where
    M: Step<PerturbedKepler> + StepFixed<PerturbedKepler, 4>,
    <M as Step<PerturbedKepler>>::Workspace: PlainWorkspace,
{
    let sys = PerturbedKepler;
    // Compensated, reusing.
    let mut a = Z0;
    integrate(&method, &sys, &mut a, 0.0, H, STEPS, |_, _, _| {}).unwrap();
    let mut b = Z0;
    integrate_fixed(&method, &sys, &mut b, 0.0, H, STEPS, |_, _, _| {}).unwrap();
    assert_eq!(
        a.map(f64::to_bits),
        b.map(f64::to_bits),
        "compensated: {a:?} vs {b:?}"
    );
    // Plain, reusing.
    let mut ws = method.workspace(&sys);
    ws.set_plain();
    let mut a = Z0;
    for k in 0..STEPS {
        method
            .step_reusing(&sys, k as f64 * H, H, &mut a, &mut ws, k > 0)
            .unwrap();
    }
    let mut b = Z0;
    integrate_fixed_with(&method, &sys, &mut b, 0.0, H, STEPS, false, |_, _, _| {}).unwrap();
    assert_eq!(
        a.map(f64::to_bits),
        b.map(f64::to_bits),
        "plain: {a:?} vs {b:?}"
    );
    // The state moved (the test compares something).
    assert!((a[0] - Z0[0]).abs() > 1e-3);
}

/// Switch a slice-path workspace to plain summation.
trait PlainWorkspace {
    fn set_plain(&mut self);
}
impl<const S: usize> PlainWorkspace for integrator_core::scheme::RkWorkspace<S> {
    fn set_plain(&mut self) {
        self.compensated = false;
    }
}
impl PlainWorkspace for integrator_core::scheme::SplitWorkspace {
    fn set_plain(&mut self) {
        self.compensated = false;
    }
}
impl<const S: usize> PlainWorkspace for integrator_core::scheme::PrkWorkspace<S> {
    fn set_plain(&mut self) {
        self.compensated = false;
    }
}

#[test]
fn runge_kutta_tables_step_the_same_bits() {
    same_bits(ExplicitEuler);
    same_bits(Heun);
    same_bits(Rk4);
    same_bits(Rk38);
}

#[test]
fn drift_kick_and_compositions_step_the_same_bits() {
    same_bits(Leapfrog);
    same_bits(ForestRuth);
    same_bits(Pefrl);
    same_bits(Yoshida6);
    same_bits(KahanLi8);
    same_bits(BlanesMoanSrkn11b);
    same_bits(SofroniouSpaletta10);
}

#[test]
fn partitioned_pairs_step_the_same_bits() {
    // Störmer–Verlet has first same as last through the carry's force slot.
    same_bits(StormerVerlet);
    same_bits(SymplecticEulerA);
    same_bits(SymplecticEulerB);
}

#[test]
fn integrate_fixed_checks_like_integrate() {
    let sys = PerturbedKepler;
    let mut short = [1.0, 0.0];
    assert_eq!(
        integrate_fixed(&Leapfrog, &sys, &mut short, 0.0, H, 1, |_, _, _| {}),
        Err(StepError::Dimension {
            expected: 4,
            got: 2
        })
    );
    let mut z = Z0;
    assert!(matches!(
        integrate_fixed(&Leapfrog, &sys, &mut z, 0.0, f64::NAN, 1, |_, _, _| {}),
        Err(StepError::StepSize(h)) if h.is_nan()
    ));
    assert!(matches!(
        integrate_fixed(&Leapfrog, &sys, &mut z, 0.0, 0.0, 1, |_, _, _| {}),
        Err(StepError::StepSize(_))
    ));
    let mut bad = [f64::INFINITY, 0.0, 0.0, 1.0];
    assert!(matches!(
        integrate_fixed(&Rk4, &sys, &mut bad, 0.0, H, 1, |_, _, _| {}),
        Err(StepError::NonFiniteInitial { index: 0, .. })
    ));
}

/// H = p²/2 − q⁴/4: the force q³ pushes outwards, and every explicit
/// scheme overflows after a few steps of size 1.
struct Repulsive;

impl Separable for Repulsive {
    fn dof(&self) -> usize {
        1
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        0.5 * p[0] * p[0]
    }
    fn potential(&self, q: &[f64]) -> f64 {
        -0.25 * q[0].powi(4)
    }
    fn velocity(&self, p: &[f64], v: &mut [f64]) {
        v[0] = p[0];
    }
    fn force(&self, q: &[f64], f: &mut [f64]) {
        f[0] = q[0].powi(3);
    }
}

#[test]
fn a_divergence_names_its_step_and_leaves_the_state() {
    let mut z = [1.0, 0.0];
    let mut seen = 0;
    let err =
        integrate_fixed(&Rk4, &Repulsive, &mut z, 0.0, 1.0, 1000, |k, _, _| seen = k).unwrap_err();
    let StepError::Diverged { step, .. } = err else {
        panic!("expected a divergence, got {err}")
    };
    assert_eq!(step, seen + 1, "the observer saw every step before it");
    assert!(step < 1000);
    assert!(
        z.iter().any(|v| !v.is_finite()),
        "z is left at the diverged state"
    );
    // The slice path agrees on where and what.
    let mut w = [1.0, 0.0];
    let slice = integrate(&Rk4, &Repulsive, &mut w, 0.0, 1.0, 1000, |_, _, _| {});
    assert_eq!(slice.unwrap_err().to_string(), err.to_string());
}

#[test]
fn observers_see_every_state() {
    let sys = PerturbedKepler;
    let mut z = Z0;
    let mut times = Vec::new();
    integrate_fixed(&Rk4, &sys, &mut z, 1.0, 0.5, 4, |k, t, x| {
        assert_eq!(x.len(), 4);
        times.push((k, t));
    })
    .unwrap();
    assert_eq!(times, [(0, 1.0), (1, 1.5), (2, 2.0), (3, 2.5), (4, 3.0)]);
}
