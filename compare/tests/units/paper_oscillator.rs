//! Tests of `compare::paper_oscillator`: the paper's qualitative claims, on
//! the numbers the module computes (they were its `#[cfg(test)]` module;
//! see `compare/tests/units/mod.rs`).

use compare::CompareError;
use compare::paper_oscillator::*;

fn run_h01() -> Experiment {
    let config = Config {
        step_sizes: vec![0.1],
        ..Config::default()
    };
    experiment(&config).unwrap()
}

#[test]
fn gauss_methods_conserve_the_quadratic_energy_to_round_off() {
    let exp = run_h01();
    for m in [
        Method::GaussLegendre2,
        Method::ImplicitMidpoint,
        Method::PaperDirk2,
    ] {
        let r = exp.get(m, 0.1).unwrap();
        let rel = r.max_energy_error() / r.energy0;
        assert!(rel <= 1e-13, "{}: relative energy error {rel:e}", m.label());
    }
}

#[test]
fn symplectic_euler_energy_error_is_bounded_and_oscillates() {
    let exp = run_h01();
    let r = exp.get(Method::SymplecticEuler, 0.1).unwrap();
    let (first, second) = r.energy_error_halves();
    assert!(
        second <= 1.5 * first,
        "first half {first:e}, second half {second:e}"
    );
    assert!(
        r.energy_sign_changes() >= 2,
        "sign changes: {}",
        r.energy_sign_changes()
    );
    // Not round-off: an O(h) oscillation.
    assert!(r.max_energy_error() / r.energy0 > 1e-3);
}

#[test]
fn explicit_euler_energy_error_grows_by_more_than_ten() {
    let exp = run_h01();
    let r = exp.get(Method::ExplicitEuler, 0.1).unwrap();
    let n = r.steps();
    assert!(r.energy_error[n].abs() > 10.0 * r.energy_error[n / 10].abs());
    assert_eq!(r.energy_error_decreases(), 0);
}

#[test]
fn heun_energy_drifts_monotonically_and_linearly() {
    let exp = run_h01();
    let r = exp.get(Method::Heun, 0.1).unwrap();
    assert_eq!(
        r.energy_error_decreases(),
        0,
        "|H − H₀| grows at every step"
    );
    let ratio = r.energy_error[200].abs() / r.energy_error[20].abs();
    assert!((9.0..11.0).contains(&ratio), "step 200 / step 20 = {ratio}");
    assert!(
        r.energy_error[200] > 0.0,
        "Heun gains energy on the oscillator"
    );
}

#[test]
fn symplectic_methods_have_a_phase_error_growing_linearly() {
    let exp = run_h01();
    let r = exp.get(Method::ImplicitMidpoint, 0.1).unwrap();
    let phase = r.phase_error();
    let ratio = phase[200] / phase[100];
    assert!((1.9..2.1).contains(&ratio), "phase error 200/100 = {ratio}");
    // The midpoint rule rotates by 2·atan(hk/2) per step, slower than hk.
    let predicted = -200.0 * (0.1 - 2.0 * (0.05f64).atan());
    assert!((phase[200] - predicted).abs() < 1e-10 * predicted.abs().max(1.0) + 1e-12);
}

#[test]
fn the_papers_closed_form_agrees_with_the_exact_flow() {
    let config = Config::default();
    let exp = run_h01();
    let r = exp.get(Method::Heun, 0.1).unwrap();
    assert!(paper_closed_form_deviation(r, &config) < 1e-14);
}

/// The default set-up changed by `f`.
fn with(f: impl FnOnce(&mut Config)) -> Config {
    let mut c = Config::default();
    f(&mut c);
    c
}

#[test]
fn bad_set_ups_are_refused_with_the_field_named() {
    let cases = [
        (with(|c| c.k = 0.0), "k"),
        (with(|c| c.p0 = f64::INFINITY), "q0"),
        (with(|c| c.steps = MAX_STEPS + 1), "steps"),
        (with(|c| c.q0 = 1e-200), "k"),
        (with(|c| c.step_sizes = vec![f64::NAN]), "step_sizes"),
    ];
    for (c, field) in cases {
        match experiment(&c) {
            Err(CompareError::Setting { name, why }) => {
                assert_eq!(name, field, "{why}");
                assert!(why.contains(field), "{why}");
            }
            other => panic!("{c:?}: {other:?}"),
        }
    }
}

#[test]
fn csv_has_a_row_per_run() {
    let exp = run_h01();
    let csv = errors_csv(&exp);
    assert_eq!(csv.lines().count(), 1 + Method::ALL.len());
    let series = series_csv(&exp, 0.1);
    assert_eq!(series.lines().count(), 1 + 201);
    assert_eq!(
        series.lines().next().unwrap().split(',').count(),
        4 + 3 * Method::ALL.len()
    );
}
