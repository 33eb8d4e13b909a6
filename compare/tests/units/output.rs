//! Tests of `compare::output` (from its `#[cfg(test)]` module: `compare`
//! has no unit-test harness, which would compile the whole crate a second
//! time; see `compare/tests/units/mod.rs`).

use compare::output::*;
use compare::row::COLUMNS;
use compare::*;
fn row(method: &str, h: f64, error: f64, time_s: f64, evals: u64) -> Row {
    Row {
        problem: "p".into(),
        method: method.into(),
        family: Family::ExplicitRk,
        order: 2,
        symplectic: false,
        h,
        tol: f64::NAN,
        steps: 1,
        error,
        energy_error: 0.0,
        time_s,
        evals,
        newton_iterations: 0,
        fixed_point_iterations: 0,
        factorizations: 0,
        status: "ok".into(),
        interpreted: false,
    }
}

#[test]
fn runs_csv_round_trips() {
    let mut rows = vec![
        row("rk4", 0.1, 1e-6, 1e-3, 10),
        row("dop853", 0.2, 1e-9, 2e-3, 30),
    ];
    rows[0].status = "solver failed at step 3: a, \"b\"".into();
    rows[1].family = Family::Peer;
    let path = std::env::temp_dir().join(format!("symlab-runs-{}.csv", std::process::id()));
    write_csv(&path, &rows).unwrap();
    let back = read_runs(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    assert_eq!(back.len(), 2);
    assert_eq!(back[0].status, rows[0].status);
    assert_eq!(back[0].family, Family::ExplicitRk);
    assert_eq!(back[1].family, Family::Peer);
    assert_eq!(back[1].time_s, 2e-3);
    assert!(back[0].tol.is_nan());
}

#[test]
fn names_with_commas_quotes_and_newlines_round_trip() {
    let mut rows = vec![
        row("my,scheme", 0.1, 1e-6, 1e-3, 10),
        row("say \"hi\"", 0.2, 1e-7, 2e-3, 20),
        row("two\nlines\r\n", 0.3, 1e-8, 3e-3, 30),
    ];
    rows[0].problem = "a, \"b\"\nc".into();
    rows[1].status = "panicked at step 3: called `Option::unwrap()`, \"x\"\nnext".into();
    let path = std::env::temp_dir().join(format!("symlab-quoted-{}.csv", std::process::id()));
    write_csv(&path, &rows).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\"my,scheme\""), "{text}");
    assert!(text.contains("\"say \"\"hi\"\"\""), "{text}");
    let back = read_runs(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    assert_eq!(back.len(), 3);
    for (a, b) in rows.iter().zip(&back) {
        assert_eq!(a.problem, b.problem);
        assert_eq!(a.method, b.method);
        assert_eq!(a.status, b.status);
        assert_eq!(a.error, b.error);
    }
    assert_eq!(csv_field("plain"), "plain");
    assert_eq!(csv_field("a,b"), "\"a,b\"");
}

#[test]
fn runs_that_cannot_be_are_refused_naming_line_and_column() {
    let good = row("rk4", 0.1, 1e-6, 1e-3, 10);
    let dir = std::env::temp_dir();
    type Edit = Box<dyn Fn(&mut Row)>;
    let cases: Vec<(Edit, &str)> = vec![
        (
            Box::new(|r| r.time_s = -1e-3),
            "line 3: column time_s is -1e-3",
        ),
        (
            Box::new(|r| r.error = -1e-6),
            "line 3: column error is -1e-6",
        ),
        (
            Box::new(|r| r.error = f64::INFINITY),
            "line 3: column error is inf",
        ),
        (
            Box::new(|r| r.error = f64::NAN),
            "line 3: column error is NaN",
        ),
        (
            Box::new(|r| r.time_s = f64::NAN),
            "line 3: column time_s is NaN",
        ),
        (Box::new(|r| r.h = 0.0), "line 3: column h is 0"),
        (
            Box::new(|r| r.energy_error = -1.0),
            "line 3: column energy_error is -1e0",
        ),
        (Box::new(|r| r.tol = 0.0), "line 3: column tol is 0"),
    ];
    for (i, (edit, want)) in cases.into_iter().enumerate() {
        let mut bad = good.clone();
        edit(&mut bad);
        let path = dir.join(format!("symlab-bad-{}-{i}.csv", std::process::id()));
        write_csv(&path, &[good.clone(), bad]).unwrap();
        let e = read_runs(&path).unwrap_err().to_string();
        std::fs::remove_file(&path).unwrap();
        assert!(e.contains(want), "{e} (want {want})");
    }
    // A failed row carries NaN: accepted.
    let mut failed = good.clone();
    failed.status = "diverged at step 4".into();
    failed.error = f64::NAN;
    failed.time_s = f64::NAN;
    let path = dir.join(format!("symlab-failed-{}.csv", std::process::id()));
    write_csv(&path, &[good, failed]).unwrap();
    assert_eq!(read_runs(&path).unwrap().len(), 2);
    // An unterminated quote names its line.
    std::fs::write(&path, format!("{}\n\"rk4,oops\n", COLUMNS.join(","))).unwrap();
    let e = read_runs(&path).unwrap_err().to_string();
    std::fs::remove_file(&path).unwrap();
    assert!(e.contains("line 2: a quoted field is not closed"), "{e}");
}

#[test]
fn fitted_order_drops_the_round_off_plateau() {
    // error = h⁴ down to a floor of 1e-10 (round-off accumulated over a
    // long run): the plateau must not pull the slope down.
    let rows: Vec<Row> = (0..12)
        .map(|i| {
            let h = 0.2 * 0.6f64.powi(i);
            row("m", h, (h.powi(4)).max(1e-10), 1.0, 1)
        })
        .collect();
    let p = fitted_order(&rows, "m").unwrap();
    assert!((p - 4.0).abs() < 0.05, "fitted order {p}");
    // Without a plateau every point counts.
    let clean: Vec<Row> = (0..6)
        .map(|i| {
            let h = 0.1 * 0.5f64.powi(i);
            row("m", h, 2.0 * h * h, 1.0, 1)
        })
        .collect();
    assert!((fitted_order(&clean, "m").unwrap() - 2.0).abs() < 1e-9);
}

#[test]
fn slope_of_a_power_law() {
    let pts: Vec<(f64, f64)> = (1..6)
        .map(|i| (i as f64, 3.0 * (i as f64).powi(4)))
        .collect();
    assert!((loglog_slope(&pts).unwrap() - 4.0).abs() < 1e-12);
    assert!(loglog_slope(&[(1.0, 1.0)]).is_none());
}

#[test]
fn time_to_error_interpolates_in_log_log_and_sorts() {
    let rows = vec![
        row("a", 0.1, 1e-6, 1e-3, 10),
        row("a", 0.01, 1e-10, 1e-1, 100),
        row("b", 0.1, 1e-7, 1e-4, 10),
        row("b", 0.01, 1e-9, 1e-2, 100),
        row("c", 0.1, 1e-3, 1e-4, 10),
    ];
    let t = time_to_error(&rows, 1e-8);
    assert_eq!(t.len(), 2);
    assert_eq!(t[0].0, "b");
    assert!((t[0].1 - 1e-3).abs() < 1e-12);
    assert!((t[1].1 - 1e-2).abs() < 1e-12);
    assert_eq!(not_bracketed(&rows, 1e-8), vec!["c".to_string()]);
}
