//! Bad input and blow-ups end in a `StepError` that says what and where,
//! never in a panic, and the observer never sees a bad state.

use integrator_core::library::{ExplicitEuler, Leapfrog, Rk4, SofroniouSpaletta10, StormerVerlet};
use integrator_core::problems::{Kepler, NonSeparable, Oscillator, Pendulum};
use integrator_core::{Separable, StepError, integrate};

/// Runs `integrate` and counts the observer's calls.
fn observed<E>(
    f: impl FnOnce(&mut dyn FnMut(usize, f64, &[f64])) -> Result<(), E>,
) -> (Result<(), E>, usize) {
    let mut calls = 0;
    let result = f(&mut |_, _, _| calls += 1);
    (result, calls)
}

#[test]
fn wrong_state_length() {
    let mut z = [1.0, 0.0, 0.0];
    let (r, calls) = observed(|obs| integrate(&Leapfrog, &Pendulum, &mut z, 0.0, 0.1, 10, obs));
    assert_eq!(
        r,
        Err(StepError::Dimension {
            expected: 2,
            got: 3
        })
    );
    assert_eq!(calls, 0);
    // Through the Runge–Kutta path and a non-separable Hamiltonian (4 = 2 dof).
    let mut z = [1.0, 0.0];
    assert_eq!(
        integrate(
            &Rk4,
            &NonSeparable { eps: 0.1 },
            &mut z,
            0.0,
            0.1,
            10,
            |_, _, _| {}
        ),
        Err(StepError::Dimension {
            expected: 4,
            got: 2
        })
    );
    let mut empty: [f64; 0] = [];
    assert_eq!(
        integrate(
            &StormerVerlet,
            &Kepler { e: 0.6 },
            &mut empty,
            0.0,
            0.1,
            10,
            |_, _, _| {}
        ),
        Err(StepError::Dimension {
            expected: 4,
            got: 0
        })
    );
    assert_eq!(z, [1.0, 0.0], "a rejected state is left untouched");
}

#[test]
fn non_finite_initial_state() {
    for (index, bad) in [(0, f64::NAN), (1, f64::INFINITY), (1, f64::NEG_INFINITY)] {
        let mut z = [0.5, -0.2];
        z[index] = bad;
        let (r, calls) = observed(|obs| integrate(&Leapfrog, &Pendulum, &mut z, 0.0, 0.1, 10, obs));
        match r {
            Err(StepError::NonFiniteInitial { index: i, value }) => {
                assert_eq!(i, index);
                assert!(value.is_nan() == bad.is_nan() && (bad.is_nan() || value == bad));
            }
            other => panic!("z[{index}] = {bad}: expected NonFiniteInitial, got {other:?}"),
        }
        assert_eq!(calls, 0);
    }
    let mut z = [0.5, 0.0, 0.0, f64::NAN];
    let err = integrate(
        &Rk4,
        &NonSeparable { eps: 0.1 },
        &mut z,
        0.0,
        0.1,
        10,
        |_, _, _| {},
    )
    .unwrap_err();
    assert!(
        matches!(err, StepError::NonFiniteInitial { index: 3, .. }),
        "{err:?}"
    );
    assert_eq!(err.to_string(), "initial state is not finite: z[3] = NaN");
}

#[test]
fn bad_step_sizes() {
    for h in [0.0, -0.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut z = [0.5, 0.0];
        let (r, calls) =
            observed(|obs| integrate(&SofroniouSpaletta10, &Pendulum, &mut z, 0.0, h, 10, obs));
        match r {
            Err(StepError::StepSize(got)) => {
                assert!(got.to_bits() == h.to_bits(), "reports h = {got}, given {h}")
            }
            other => panic!("h = {h}: expected StepSize, got {other:?}"),
        }
        assert_eq!(calls, 0);
        assert_eq!(z, [0.5, 0.0]);
    }
    let mut z = [0.5, 0.0];
    let err = integrate(&Rk4, &Pendulum, &mut z, 0.0, f64::NAN, 10, |_, _, _| {}).unwrap_err();
    assert_eq!(
        err.to_string(),
        "step size h = NaN must be finite and nonzero"
    );
}

#[test]
fn negative_steps_are_fine() {
    // Not an error: integrating backwards. Leapfrog forwards then backwards
    // returns to the start (it is symmetric).
    let mut z = [0.5, 0.3];
    integrate(&Leapfrog, &Pendulum, &mut z, 0.0, 0.1, 50, |_, _, _| {}).unwrap();
    integrate(&Leapfrog, &Pendulum, &mut z, 5.0, -0.1, 50, |_, _, _| {}).unwrap();
    assert!(
        (z[0] - 0.5).abs() < 1e-13 && (z[1] - 0.3).abs() < 1e-13,
        "{z:?}"
    );
}

#[test]
fn explicit_euler_on_a_stiff_oscillator_diverges_with_the_step_named() {
    // |1 + ikh| = √(1 + 10⁴) ≈ 100 per step: the state overflows after
    // about 308/2 = 154 steps.
    let sys = Oscillator { k: 1e3 };
    let (h, t0) = (0.1, 2.0);
    let mut z = [1.0, 0.0];
    let mut last_seen = (0, f64::NAN, true);
    let r = integrate(&ExplicitEuler, &sys, &mut z, t0, h, 1000, |step, t, z| {
        last_seen = (step, t, z.iter().all(|x| x.is_finite()));
    });
    let Err(StepError::Diverged {
        step,
        t,
        index,
        value,
    }) = r
    else {
        panic!("expected Diverged, got {r:?}")
    };
    assert!((150..=160).contains(&step), "diverged at step {step}");
    assert_eq!(
        t,
        t0 + step as f64 * h,
        "t is the time at the end of the failing step"
    );
    assert!(index < 2 && !value.is_finite());
    assert!(
        !z[index].is_finite(),
        "the state is left as the failing step made it"
    );
    assert_eq!(
        last_seen.0,
        step - 1,
        "the observer saw every step before the failing one"
    );
    assert!(last_seen.2, "and only finite states");
    let msg = StepError::Diverged {
        step,
        t,
        index,
        value,
    }
    .to_string();
    assert!(
        msg.contains(&format!("step {step}")) && msg.contains(&format!("t = {t}")),
        "{msg}"
    );
    // The same with a symplectic scheme stepping far beyond its stability
    // limit (hk = 100 ≫ 2).
    let mut z = [1.0, 0.0];
    let r = integrate(&Leapfrog, &sys, &mut z, 0.0, h, 1000, |_, _, _| {});
    assert!(
        matches!(r, Err(StepError::Diverged { step, .. }) if step < 1000),
        "{r:?}"
    );
}

/// A potential whose force is NaN past `q = 1`: `V = (2/3)(1 − q)^{3/2}`,
/// force `√(1 − q)`, pushing towards the edge.
struct Cliff;
impl Separable for Cliff {
    fn dof(&self) -> usize {
        1
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        0.5 * p[0] * p[0]
    }
    fn potential(&self, q: &[f64]) -> f64 {
        2.0 / 3.0 * (1.0 - q[0]).powf(1.5)
    }
    fn velocity(&self, p: &[f64], out: &mut [f64]) {
        out[0] = p[0];
    }
    fn force(&self, q: &[f64], out: &mut [f64]) {
        out[0] = (1.0 - q[0]).sqrt();
    }
}

#[test]
fn a_force_that_returns_nan_stops_at_that_step() {
    // Pushed right from q = 0 at speed 1 with drift–kick–drift steps of 0.3,
    // the midpoint where a kick evaluates the force passes q = 1 after a few
    // steps. Which step that is, is found by stepping by hand.
    let h = 0.3;
    let mut manual = [0.0, 1.0];
    let mut expected = 0;
    let mut ws = integrator_core::Step::workspace(&Leapfrog, &Cliff);
    for k in 1..=100 {
        integrator_core::Step::step(&Leapfrog, &Cliff, 0.0, h, &mut manual, &mut ws).unwrap();
        if manual.iter().any(|x| !x.is_finite()) {
            expected = k;
            break;
        }
    }
    assert!(
        expected > 1,
        "the set-up reaches the cliff after a few steps"
    );
    let mut z = [0.0, 1.0];
    let r = integrate(&Leapfrog, &Cliff, &mut z, 0.0, h, 100, |_, _, _| {});
    match r {
        Err(StepError::Diverged {
            step,
            t,
            index,
            value,
        }) => {
            assert_eq!(step, expected);
            assert!((t - expected as f64 * h).abs() < 1e-15);
            assert!(value.is_nan() && index <= 1);
        }
        other => panic!("expected Diverged at step {expected}, got {other:?}"),
    }
    // And a system that is NaN everywhere fails at step 1, at t0 + h.
    let mut z = [2.0, 0.0];
    let r = integrate(&Rk4, &Cliff, &mut z, 1.0, 0.5, 10, |_, _, _| {});
    assert!(
        matches!(
            r,
            Err(StepError::Diverged {
                step: 1,
                t: 1.5,
                ..
            })
        ),
        "{r:?}"
    );
}
