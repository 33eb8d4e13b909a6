//! End-to-end tests of `symlab compare`: the documented CSV columns, clear
//! errors with exit code 2, and the observed orders of a small sweep.

use std::collections::BTreeMap;
use std::path::PathBuf;

mod common;
use common::symlab;

/// A fresh directory under the system temp dir.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("symlab-compare-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Split one CSV line, honouring double quotes.
fn fields(line: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                chars.next();
                out.last_mut().unwrap().push('"');
            }
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(String::new()),
            c => out.last_mut().unwrap().push(c),
        }
    }
    out
}

/// The rows of a CSV file as maps from column to value.
fn read_csv(path: &std::path::Path) -> (Vec<String>, Vec<BTreeMap<String, String>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header = fields(lines.next().expect("a header"));
    let rows = lines
        .map(|l| {
            let f = fields(l);
            assert_eq!(f.len(), header.len(), "row {l:?}");
            header.iter().cloned().zip(f).collect()
        })
        .collect();
    (header, rows)
}

const COLUMNS: [&str; 15] = [
    "problem",
    "method",
    "order",
    "symplectic",
    "h",
    "tol",
    "steps",
    "error",
    "energy_error",
    "time_s",
    "evals",
    "newton_iterations",
    "fixed_point_iterations",
    "factorizations",
    "status",
];

#[test]
fn quick_run_writes_the_documented_columns_and_plots() {
    let dir = temp_dir("quick");
    let (code, out, err) = symlab(&[
        "compare",
        "--problem",
        "kepler",
        "--quick",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "stderr: {err}");
    assert!(out.contains("Wall time to reach relative error"), "{out}");
    let (header, rows) = read_csv(&dir.join("runs.csv"));
    assert_eq!(header, COLUMNS);
    assert!(!rows.is_empty());
    for r in &rows {
        assert_eq!(r["problem"], "kepler");
        if r["status"] == "ok" {
            let e: f64 = r["error"].parse().unwrap();
            let t: f64 = r["time_s"].parse().unwrap();
            assert!(
                e.is_finite() && e >= 0.0 && t.is_finite() && t >= 0.0,
                "{r:?}"
            );
            assert!(r["evals"].parse::<u64>().unwrap() > 0);
        }
    }
    // Implicit methods report their solver's work, explicit ones none.
    let gauss = rows
        .iter()
        .find(|r| r["method"] == "gauss2" && r["status"] == "ok")
        .unwrap();
    assert_eq!(gauss["symplectic"], "true");
    let solver_work: u64 = gauss["newton_iterations"].parse::<u64>().unwrap()
        + gauss["fixed_point_iterations"].parse::<u64>().unwrap();
    assert!(solver_work > 0, "{gauss:?}");
    let leapfrog = rows.iter().find(|r| r["method"] == "leapfrog").unwrap();
    assert_eq!(leapfrog["newton_iterations"], "0");
    if cfg!(feature = "peer") {
        let peer: Vec<_> = rows.iter().filter(|r| r["method"] == "dop853").collect();
        assert!(!peer.is_empty());
        for r in peer {
            assert!(r["tol"].parse::<f64>().unwrap() > 0.0);
            assert_eq!(r["status"], "ok");
        }
    }
    for f in ["error_vs_time.svg", "error_vs_evals.svg"] {
        assert!(std::fs::metadata(dir.join(f)).unwrap().len() > 1000, "{f}");
    }
    // The help documents every column.
    let (code, help, _) = symlab(&["compare", "--help"]);
    assert_eq!(code, 0);
    for c in COLUMNS {
        assert!(help.contains(c), "--help does not document {c}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_linear_problem_runs_propagators_and_refuses_separable_schemes() {
    let dir = temp_dir("gyro");
    let (code, _, err) = symlab(&[
        "compare",
        "--problem",
        "gyroscopic",
        "--methods",
        "rk4,gauss2-propagator",
        "--quick",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "stderr: {err}");
    let (_, rows) = read_csv(&dir.join("runs.csv"));
    assert!(
        rows.iter()
            .any(|r| r["method"] == "gauss2-propagator" && r["status"] == "ok")
    );
    let (code, _, err) = symlab(&[
        "compare",
        "--problem",
        "gyroscopic",
        "--methods",
        "leapfrog",
        "--quick",
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("cannot step") && err.contains("Separable"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_arguments_are_clear_errors_with_exit_code_2() {
    let cases: &[(&[&str], &str)] = &[
        (&["--problem", "nope"], "nope"),
        (
            &["--problem", "kepler", "--methods", "leapfrog,nope"],
            "unknown method 'nope'",
        ),
        (
            &["--problem", "kepler", "--h-min", "0"],
            "--h-min must be a finite number > 0",
        ),
        (
            &["--problem", "kepler", "--h-max", "-0.1"],
            "--h-max must be a finite number > 0",
        ),
        (&["--problem", "kepler", "--t-end", "abc"], "--t-end"),
        (
            &["--problem", "kepler", "--t-end", "nan"],
            "--t-end must be a finite number > 0",
        ),
        (
            &["--problem", "kepler", "--h-min", "0.1", "--h-max", "0.01"],
            "must not exceed",
        ),
        (&["--problem", "kepler", "--points", "0"], "--points"),
        (
            &["--long", "--problem", "fpu"],
            "--long runs on kepler, oscillator or henon-heiles",
        ),
        (
            &["--long", "--problem", "kepler", "--steps", "5"],
            "--steps must be between",
        ),
        (&["--methods", "rk4"], "--problem is required"),
    ];
    for (args, needle) in cases {
        let mut all = vec!["compare", "--quick"];
        all.extend_from_slice(args);
        let (code, _, err) = symlab(&all);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(
            err.contains(needle),
            "{args:?}: expected {needle:?} in {err}"
        );
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

/// Least-squares slope of ln y against ln x.
fn slope(pts: &[(f64, f64)]) -> f64 {
    let n = pts.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = pts.iter().map(|(x, y)| (x.ln(), y.ln())).unzip();
    let mx = lx.iter().sum::<f64>() / n;
    let my = ly.iter().sum::<f64>() / n;
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

#[test]
fn error_slopes_match_the_orders_on_the_pendulum() {
    let dir = temp_dir("slopes");
    let (code, _, err) = symlab(&[
        "compare",
        "--problem",
        "pendulum",
        "--methods",
        "symplectic-euler-a,leapfrog,rk4,yoshida6",
        "--t-end",
        "10",
        "--h-min",
        "0.0125",
        "--h-max",
        "0.05",
        "--points",
        "4",
        "--repeats",
        "1",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "stderr: {err}");
    let (_, rows) = read_csv(&dir.join("runs.csv"));
    let mut orders = Vec::new();
    for m in ["symplectic-euler-a", "leapfrog", "rk4", "yoshida6"] {
        let mine: Vec<_> = rows.iter().filter(|r| r["method"] == m).collect();
        let order: f64 = mine[0]["order"].parse().unwrap();
        let pts: Vec<(f64, f64)> = mine
            .iter()
            .filter(|r| r["status"] == "ok")
            .map(|r| (r["h"].parse().unwrap(), r["error"].parse().unwrap()))
            .filter(|&(_, e): &(f64, f64)| e > 1e-13)
            .collect();
        assert!(pts.len() >= 3, "{m}: {pts:?}");
        let s = slope(&pts);
        assert!((s - order).abs() <= 0.5, "{m}: slope {s}, order {order}");
        orders.push(order as usize);
    }
    assert_eq!(orders, [1, 2, 4, 6]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn quick_long_and_hard_runs_write_their_files() {
    let dir = temp_dir("long");
    let (code, out, err) = symlab(&[
        "compare",
        "--long",
        "--problem",
        "oscillator",
        "--quick",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "stderr: {err}");
    assert!(out.contains("exponent"), "{out}");
    let (header, rows) = read_csv(&dir.join("long.csv"));
    assert_eq!(
        header,
        [
            "problem",
            "method",
            "order",
            "symplectic",
            "compensated",
            "h",
            "step",
            "t",
            "energy_error"
        ]
    );
    assert!(
        rows.iter()
            .any(|r| r["method"] == "gauss2" && r["compensated"] == "false")
    );
    // Heun's energy error on the oscillator grows linearly: |R(ih)|² = 1 + h⁴/4.
    let (_, fits) = read_csv(&dir.join("long_fit.csv"));
    let heun = fits.iter().find(|r| r["method"] == "heun").unwrap();
    let e: f64 = heun["exponent"].parse().unwrap();
    assert!((e - 1.0).abs() < 0.1, "heun exponent {e}");
    assert!(dir.join("long_energy.svg").exists());

    let (code, out, err) = symlab(&[
        "compare",
        "--hard",
        "--problem",
        "fpu",
        "--quick",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "stderr: {err}");
    assert!(out.contains("| problem | method |"), "{out}");
    let (_, hard) = read_csv(&dir.join("hard.csv"));
    for r in &hard {
        let h: f64 = r["h_stable"].parse().unwrap();
        assert!(h > 0.0 && h.is_finite(), "{r:?}");
    }
    // Leapfrog is linearly stable for hω < 2; the energy bound stops it
    // earlier (its energy error grows like (hω)²).
    let leapfrog = hard.iter().find(|r| r["method"] == "leapfrog").unwrap();
    let hw: f64 = leapfrog["h_omega_max"].parse().unwrap();
    assert!(hw > 0.5 && hw < 2.0, "leapfrog h·ω = {hw}");
    assert!(dir.join("hard.md").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
