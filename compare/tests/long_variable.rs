//! `long_variable`: the quick study runs, calibrates every method to the
//! same work, and records windows up to the end.

#[cfg(feature = "peer")]
#[test]
fn the_quick_variable_step_study_runs_at_equal_work() {
    use compare::long_variable::{VariableSettings, run};
    let s = VariableSettings {
        orbits: 20.0,
        evals_per_orbit: 3000.0,
        ..VariableSettings::full()
    };
    let runs = run(s).unwrap();
    assert_eq!(runs.len(), 3);
    for r in &runs {
        assert!(r.status.is_ok(), "{}: {:?}", r.method, r.status);
        let last = r.samples.last().unwrap();
        assert!(
            (last.1 - 40.0 * std::f64::consts::PI).abs() < 1e-6,
            "{}: {last:?}",
            r.method
        );
        assert!(last.2 > 0.0 && last.2 < 1e-3, "{}: {last:?}", r.method);
    }
    // The same work within a factor 2 (DOP853's tolerance grid is a
    // quarter decade): steps × evaluations per step.
    let evals = |r: &compare::long::LongRun| {
        r.steps as f64
            * if r.method.starts_with("dop853") {
                12.0
            } else {
                17.0
            }
    };
    let e0 = evals(&runs[0]);
    for r in &runs[1..] {
        let ratio = evals(r) / e0;
        assert!((0.5..2.0).contains(&ratio), "{}: {ratio}", r.method);
    }
}
