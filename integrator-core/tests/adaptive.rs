//! Reversible adaptive step-size control: the map of a symmetric method
//! under either controller is time-reversible to round-off (explicit and
//! implicit Gauss methods alike), its energy error stays bounded where the
//! same method with the naive rule `h = ε·σ(yₙ)` drifts, and a method that
//! is not symmetric is refused.

use std::f64::consts::PI;

use integrator_core::adaptive::{
    AdaptiveError, Controller, DistancePower, Reversible, StepDensity,
};
use integrator_core::library::{GaussLegendre2, KahanLi8, Leapfrog, Rk4, SymplecticEulerA};
use integrator_core::problems::Kepler;
use integrator_core::{Scheme, Step, energy};

const CONTROLLERS: [Controller; 2] = [Controller::Implicit, Controller::Integrating];

/// `n` steps forward from `z0`, the momenta flipped, `n` steps forward
/// again, flipped back: the largest deviation from `z0` relative to `|z0|`,
/// and the time reached in the first leg.
fn round_trip<M>(m: M, controller: Controller, e: f64, eps: f64, n: usize) -> (f64, f64)
where
    M: Scheme + Step<Kepler>,
{
    round_trip_with(m, controller, e, eps, n, |_| {})
}

fn round_trip_with<M>(
    m: M,
    controller: Controller,
    e: f64,
    eps: f64,
    n: usize,
    prepare: impl Fn(&mut <M as Step<Kepler>>::Workspace),
) -> (f64, f64)
where
    M: Scheme + Step<Kepler>,
{
    let sys = Kepler { e };
    let z0 = sys.initial_state();
    let r = Reversible::new(m, DistancePower::new(1.0), controller).unwrap();
    let mut z = z0.clone();
    let mut zeta = r.start_control(&sys, 0.0, &z).unwrap();
    let mut ws = m.workspace(&sys);
    prepare(&mut ws);
    let mut trial = vec![];
    let mut t = 0.0;
    for _ in 0..n {
        let (h, _) = r
            .step(&sys, t, &mut z, &mut zeta, eps, &mut ws, &mut trial)
            .unwrap();
        t += h;
    }
    let t_forward = t;
    for p in &mut z[2..] {
        *p = -*p;
    }
    for _ in 0..n {
        let (h, _) = r
            .step(&sys, t, &mut z, &mut zeta, eps, &mut ws, &mut trial)
            .unwrap();
        t -= h;
    }
    for p in &mut z[2..] {
        *p = -*p;
    }
    let scale = z0.iter().map(|x| x.abs()).fold(0.0, f64::max);
    let dev = z
        .iter()
        .zip(&z0)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    (dev / scale, t_forward)
}

#[test]
fn the_adaptive_map_is_time_reversible_to_round_off() {
    for controller in CONTROLLERS {
        // Through two pericentre passages of e = 0.9, steps varying by ~20×.
        let (dev, t) = round_trip(Leapfrog, controller, 0.9, 0.02, 1000);
        assert!(t > 2.0 * PI, "{controller:?}: t = {t}");
        assert!(dev < 1e-12, "leapfrog {controller:?}: deviation {dev:e}");
        let (dev, _) = round_trip(KahanLi8, controller, 0.9, 0.2, 100);
        assert!(dev < 1e-12, "kahan-li8 {controller:?}: deviation {dev:e}");
        // The implicit Gauss method. Its stage solver stops at round-off or
        // when the corrections stagnate below `stagnation_limit` (1e-12 by
        // default, relative): a step's result then depends on the starting
        // values to that level, and the round trip through the pericentre
        // at ε = 0.05 misses by ~1e-8. With the stagnation test at 1e-15 the
        // stages are solved to round-off and so is the round trip.
        let strict = |ws: &mut integrator_core::implicit::ImplicitWorkspace| {
            ws.settings_mut().stagnation_limit = 1e-15;
            ws.settings_mut().plateau_limit = 0.0;
        };
        let (dev, t) = round_trip_with(GaussLegendre2, controller, 0.9, 0.05, 150, strict);
        assert!(t > PI, "gauss2 {controller:?}: t = {t}");
        assert!(dev < 1e-12, "gauss2 {controller:?}: deviation {dev:e}");
    }
}

#[test]
fn a_non_reversible_map_is_seen_by_the_round_trip() {
    // The same round trip with the naive rule h = ε·σ(yₙ) misses by far
    // more than round-off: the test can fail.
    let sys = Kepler { e: 0.9 };
    let z0 = sys.initial_state();
    let d = DistancePower::new(1.0);
    let mut ws = Leapfrog.workspace(&sys);
    let mut z = z0.clone();
    for leg in 0..2 {
        for _ in 0..1000 {
            let h = 0.02 * d.sigma(&sys, &z);
            Leapfrog.step(&sys, 0.0, h, &mut z, &mut ws).unwrap();
        }
        if leg == 0 {
            for p in &mut z[2..] {
                *p = -*p;
            }
        }
    }
    for p in &mut z[2..] {
        *p = -*p;
    }
    let dev = z
        .iter()
        .zip(&z0)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(dev > 1e-6, "naive rule: deviation {dev:e}");
}

/// The largest relative energy error over `[0, T/10]` and over
/// `[T/2, T]` of `orbits` orbits of e = 0.9.
fn energy_windows(
    step: &mut dyn FnMut(&Kepler, &mut [f64], f64) -> f64,
    orbits: f64,
) -> (f64, f64) {
    let sys = Kepler { e: 0.9 };
    let mut z = sys.initial_state();
    let e0 = energy(&sys, &z);
    let t_end = orbits * 2.0 * PI;
    let (mut early, mut late) = (0.0f64, 0.0f64);
    let mut t = 0.0;
    while t < t_end {
        t += step(&sys, &mut z, t);
        let err = ((energy(&sys, &z) - e0) / e0).abs();
        if t <= 0.1 * t_end {
            early = early.max(err);
        } else if t >= 0.5 * t_end {
            late = late.max(err);
        }
    }
    (early, late)
}

#[test]
fn the_energy_error_stays_bounded_where_the_naive_rule_drifts() {
    let orbits = 400.0;
    let eps = 0.02;
    for controller in CONTROLLERS {
        let r = Reversible::new(Leapfrog, DistancePower::new(1.0), controller).unwrap();
        let sys = Kepler { e: 0.9 };
        let mut zeta = r.start_control(&sys, 0.0, &sys.initial_state()).unwrap();
        let mut ws = Leapfrog.workspace(&sys);
        let mut trial = vec![];
        let (early, late) = energy_windows(
            &mut |sys, z, t| {
                r.step(sys, t, z, &mut zeta, eps, &mut ws, &mut trial)
                    .unwrap()
                    .0
            },
            orbits,
        );
        assert!(early > 0.0 && early < 1e-2, "{controller:?}: {early:e}");
        assert!(
            late < 1.5 * early,
            "{controller:?}: early {early:e}, late {late:e}"
        );
    }
    // Same method, same density, the step chosen from yₙ alone: the energy
    // error grows along the run.
    let d = DistancePower::new(1.0);
    let sys = Kepler { e: 0.9 };
    let mut ws = Leapfrog.workspace(&sys);
    let (early, late) = energy_windows(
        &mut |sys, z, _| {
            let h = eps * d.sigma(sys, z);
            Leapfrog.step(sys, 0.0, h, z, &mut ws).unwrap();
            h
        },
        orbits,
    );
    assert!(
        late > 3.0 * early,
        "naive rule: early {early:e}, late {late:e}"
    );
}

#[test]
fn integrate_lands_on_the_end_time_and_matches_the_exact_flow() {
    let sys = Kepler { e: 0.9 };
    let t_end = 3.0 * 2.0 * PI + 1.0;
    let exact = sys.exact(t_end);
    for controller in CONTROLLERS {
        let r = Reversible::new(KahanLi8, DistancePower::new(1.0), controller).unwrap();
        let mut z = sys.initial_state();
        let mut last_t = 0.0;
        let run = r
            .integrate_observed(&sys, &mut z, 0.0, t_end, 0.05, |t, _| {
                last_t = t;
                true
            })
            .unwrap();
        assert_eq!(last_t, t_end);
        assert!(run.h_max > 10.0 * run.h_min, "{run:?}");
        let err = z
            .iter()
            .zip(&exact)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-7, "{controller:?}: error {err:e}");
    }
}

#[test]
fn bad_input_is_a_clear_error() {
    let d = DistancePower::new(1.0);
    for err in [
        Reversible::new(Rk4, d, Controller::Implicit).unwrap_err(),
        Reversible::new(SymplecticEulerA, d, Controller::Integrating).unwrap_err(),
    ] {
        assert!(matches!(err, AdaptiveError::NotSymmetric { .. }), "{err}");
        assert!(err.to_string().contains("not symmetric"), "{err}");
    }
    let sys = Kepler { e: 0.6 };
    let r = Reversible::new(Leapfrog, d, Controller::Integrating).unwrap();
    let mut z = sys.initial_state();
    for (eps, t_end) in [
        (0.0, 1.0),
        (f64::NAN, 1.0),
        (0.1, -1.0),
        (0.1, f64::INFINITY),
    ] {
        let err = r.integrate(&sys, &mut z, 0.0, t_end, eps).unwrap_err();
        assert!(
            matches!(
                err,
                AdaptiveError::Epsilon(_) | AdaptiveError::EndTime { .. }
            ),
            "{err}"
        );
    }
    // At the origin σ = 0: no step can be chosen.
    let mut origin = vec![0.0, 0.0, 1.0, 0.0];
    let err = r.integrate(&sys, &mut origin, 0.0, 1.0, 0.1).unwrap_err();
    assert!(err.to_string().contains("σ = 0"), "{err}");
    let mut short = vec![1.0, 0.0];
    let err = r.integrate(&sys, &mut short, 0.0, 1.0, 0.1).unwrap_err();
    assert!(matches!(err, AdaptiveError::Dimension { .. }), "{err}");
}
