//! Tests of `compare::versus`: the verdicts of a design against the
//! library, each branch reached by rows made for it.

use compare::versus::{TIME_MARGIN, Verdict, versus};
use compare::{Family, Row};

/// A run of `method` with error `error` at cost `evals` (time proportional,
/// `ms_per_eval` milliseconds each).
fn row(method: &str, error: f64, evals: u64, ms_per_eval: f64, interpreted: bool) -> Row {
    Row {
        problem: "p".into(),
        method: method.into(),
        family: Family::Splitting,
        order: 4,
        symplectic: true,
        h: 1.0 / evals as f64,
        tol: f64::NAN,
        steps: evals,
        error,
        energy_error: 0.0,
        time_s: evals as f64 * ms_per_eval * 1e-3,
        evals,
        newton_iterations: 0,
        fixed_point_iterations: 0,
        factorizations: 0,
        status: "ok".into(),
        interpreted,
    }
}

/// Two runs bracketing 1e-7: errors 1e-5 and 1e-9 at `n` and `10 n`.
fn ladder(method: &str, n: u64, ms: f64, interpreted: bool) -> Vec<Row> {
    vec![
        row(method, 1e-5, n, ms, interpreted),
        row(method, 1e-9, 10 * n, ms, interpreted),
    ]
}

#[test]
fn level_within_the_margin_and_the_library_ahead_beyond_it() {
    let designs = vec!["d".to_string()];
    // 3 % fewer evaluations: level.
    let mut rows = ladder("lib", 100, 1.0, false);
    rows.extend(ladder("d", 97, 1.0, false));
    let v = versus(&rows, &designs, &[1e-7]);
    assert!(
        matches!(v.targets[0].evaluations, Verdict::Level { .. }),
        "{v:?}"
    );
    assert!(matches!(v.targets[0].time, Verdict::Level { .. }), "{v:?}");
    assert!(
        v.targets[0].line().contains("level"),
        "{}",
        v.targets[0].line()
    );
    // The design needs twice the evaluations and time: the library's.
    let mut rows = ladder("lib", 100, 1.0, false);
    rows.extend(ladder("d", 200, 1.0, false));
    let v = versus(&rows, &designs, &[1e-7]);
    match &v.targets[0].evaluations {
        Verdict::LibraryLess { ratio } => assert!((ratio - 2.0).abs() < 1e-9, "{ratio}"),
        other => panic!("{other:?}"),
    }
    assert!(
        !v.markdown().contains("the design wins"),
        "{}",
        v.markdown()
    );
}

/// An interpreted design's time is ranked only against interpreted library
/// rows: a generated library row twice as fast does not make it lose, and
/// without an interpreted row the time verdict is undecided, naming
/// `interp:ID`.
#[test]
fn times_compare_only_between_rows_stepped_alike() {
    let designs = vec!["d".to_string()];
    let mut rows = ladder("lib", 100, 0.5, false);
    rows.extend(ladder("d", 50, 1.0, true));
    let v = versus(&rows, &designs, &[1e-7]);
    assert!(
        matches!(v.targets[0].evaluations, Verdict::DesignLess { .. }),
        "{v:?}"
    );
    match &v.targets[0].time {
        Verdict::Undecided { why } => assert!(why.contains("interp:ID"), "{why}"),
        other => panic!("{other:?}"),
    }
    rows.extend(ladder("interp:lib", 100, 1.0, true));
    let v = versus(&rows, &designs, &[1e-7]);
    match &v.targets[0].time {
        Verdict::DesignLess { ratio } => assert!(*ratio > TIME_MARGIN, "{ratio}"),
        other => panic!("{other:?}"),
    }
    let (m, _) = v.targets[0]
        .fastest_generated
        .clone()
        .expect("named beside");
    assert_eq!(m, "lib");
    let text = v.markdown();
    assert!(text.contains("needs 2.00× fewer evaluations"), "{text}");
    assert!(text.contains("the design wins"), "{text}");
    assert!(text.contains("| d | yes | interpreter |"), "{text}");
    assert!(text.contains("| lib |  | generated |"), "{text}");
}

/// A method whose cheapest run is already below the error has an upper
/// bound only: shown with `≤`, never ranked; an error no design brackets
/// is undecided.
#[test]
fn upper_bounds_are_not_ranked() {
    let designs = vec!["d".to_string()];
    let mut rows = ladder("lib", 100, 1.0, false);
    rows.extend(vec![
        row("d", 1e-8, 10, 1.0, false),
        row("d", 1e-10, 100, 1.0, false),
    ]);
    let v = versus(&rows, &designs, &[1e-7]);
    assert!(
        matches!(v.targets[0].evaluations, Verdict::Undecided { .. }),
        "{v:?}"
    );
    assert!(v.markdown().contains("≤ 10 |"), "{}", v.markdown());
}
