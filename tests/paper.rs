//! End-to-end tests of `symlab paper`: it writes every listed file, and the
//! numbers it writes bear out the paper's qualitative claims about the
//! oscillator H = ½(p² + k²q²) at h = 0.1 after 200 steps (parsed from its
//! CSV output); bad arguments are exit code 2 with a message.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

mod common;
use common::symlab;

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("symlab-paper-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// One run of `symlab paper --out DIR` with the default set-up, shared by the tests.
fn default_run() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = temp_dir("default");
        let (code, out, err) = symlab(&["paper", "--out", dir.to_str().unwrap()]);
        assert_eq!(code, 0, "stdout: {out}\nstderr: {err}");
        assert!(
            out.contains("Cloth comparison (figure 5): Not available yet"),
            "{out}"
        );
        dir
    })
}

/// A CSV file as a header and rows of fields.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header = lines
        .next()
        .expect("a header")
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

/// The columns of `oscillator_h0.1_series.csv` by name.
fn series_h01() -> HashMap<String, Vec<f64>> {
    let (header, rows) = read_csv(&default_run().join("oscillator_h0.1_series.csv"));
    let mut cols: HashMap<String, Vec<f64>> =
        header.iter().map(|h| (h.clone(), Vec::new())).collect();
    for row in &rows {
        assert_eq!(row.len(), header.len());
        for (h, v) in header.iter().zip(row) {
            cols.get_mut(h).unwrap().push(
                v.parse()
                    .unwrap_or_else(|_| panic!("{h}: {v} is not a number")),
            );
        }
    }
    assert_eq!(rows.len(), 201, "200 steps and the start");
    cols
}

/// `|H − H₀|` of a method at every step, from its `{id}_dH` column.
fn energy_error(cols: &HashMap<String, Vec<f64>>, id: &str) -> Vec<f64> {
    cols[&format!("{id}_dH")].iter().map(|e| e.abs()).collect()
}

fn max(v: &[f64]) -> f64 {
    v.iter().copied().fold(0.0, f64::max)
}

const H0: f64 = 0.5; // H(q₀ = 1, p₀ = 0) with k = 1

#[test]
fn writes_every_listed_file() {
    let dir = default_run();
    let mut expected = vec!["oscillator_errors.csv".to_string(), "report.md".to_string()];
    for h in ["0.01", "0.05", "0.1"] {
        for suffix in ["series.csv", "q.svg", "p.svg", "energy.svg"] {
            expected.push(format!("oscillator_h{h}_{suffix}"));
        }
    }
    for name in &expected {
        let path = dir.join(name);
        let len = std::fs::metadata(&path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .len();
        assert!(len > 500, "{name} has {len} bytes");
        if name.ends_with(".svg") {
            assert!(
                std::fs::read_to_string(&path).unwrap().starts_with("<svg"),
                "{name}"
            );
        }
    }
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    for section in [
        "## What the paper claims",
        "## What this run measured",
        "## Where the paper",
        "## The cloth comparison (figure 5)",
    ] {
        assert!(report.contains(section), "report lacks {section}");
    }
    assert!(report.contains("Not available yet"));
    assert!(
        !report.contains("NaN") && !report.contains("inf"),
        "report has a non-finite number"
    );
}

#[test]
fn errors_table_has_every_method_and_step_size() {
    let (header, rows) = read_csv(&default_run().join("oscillator_errors.csv"));
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name}"))
    };
    let (h, method, max_q, max_p, max_rel) = (
        col("h"),
        col("method"),
        col("max_err_q"),
        col("max_err_p"),
        col("max_rel_energy_error"),
    );
    assert_eq!(rows.len(), 18);
    for step in ["0.01", "0.05", "0.1"] {
        for id in [
            "euler",
            "heun",
            "midpoint",
            "paper-dirk2",
            "gauss2",
            "symplectic-euler-a",
        ] {
            let row = rows
                .iter()
                .find(|r| r[h] == step && r[method] == id)
                .unwrap_or_else(|| panic!("{id} at {step}"));
            for c in [max_q, max_p, max_rel] {
                let v: f64 = row[c].parse().unwrap();
                assert!(
                    v.is_finite() && v >= 0.0,
                    "{id} at {step}: {} = {v}",
                    header[c]
                );
            }
        }
    }
    // The non-symplectic explicit methods' energy error grows with h.
    for id in ["euler", "heun"] {
        let e: Vec<f64> = ["0.01", "0.05", "0.1"]
            .iter()
            .map(|s| {
                rows.iter().find(|r| r[h] == *s && r[method] == id).unwrap()[max_rel]
                    .parse()
                    .unwrap()
            })
            .collect();
        assert!(e[0] < e[1] && e[1] < e[2], "{id}: {e:?}");
    }
}

#[test]
fn gauss_legendre_2_and_midpoint_keep_the_energy_to_round_off() {
    let cols = series_h01();
    for id in ["gauss2", "midpoint", "paper-dirk2"] {
        let rel = max(&energy_error(&cols, id)) / H0;
        assert!(rel <= 1e-13, "{id}: max |ΔH|/H₀ = {rel:e}");
    }
}

#[test]
fn symplectic_euler_energy_error_is_bounded_and_oscillating() {
    let cols = series_h01();
    let e = energy_error(&cols, "symplectic-euler-a");
    let (first, second) = (max(&e[1..101]), max(&e[101..]));
    assert!(
        second <= 1.5 * first,
        "first half {first:e}, second half {second:e}"
    );
    // It changes sign (returns through zero), and it is not round-off.
    let signed = &cols["symplectic-euler-a_dH"];
    let changes = signed.windows(2).filter(|w| w[0] * w[1] < 0.0).count();
    assert!(changes >= 2, "sign changes: {changes}");
    assert!(first / H0 > 1e-3);
}

#[test]
fn explicit_euler_energy_error_grows_by_more_than_an_order_of_magnitude() {
    let cols = series_h01();
    let e = energy_error(&cols, "euler");
    assert!(
        e[200] > 10.0 * e[20],
        "after 20 steps {:e}, after 200 {:e}",
        e[20],
        e[200]
    );
    assert!(e.windows(2).all(|w| w[1] > w[0]), "grows at every step");
}

#[test]
fn heun_energy_drifts() {
    let cols = series_h01();
    let e = energy_error(&cols, "heun");
    assert!(
        e.windows(2).all(|w| w[1] > w[0]),
        "|ΔH| grows at every step"
    );
    // Linear drift: after 200 steps about 10× the error after 20.
    let ratio = e[200] / e[20];
    assert!((9.0..11.0).contains(&ratio), "step 200 / step 20 = {ratio}");
    assert!(cols["heun_dH"][200] > 0.0, "Heun gains energy");
}

#[test]
fn symplectic_methods_track_the_analytic_solution_and_euler_does_not() {
    let cols = series_h01();
    let q = &cols["q_exact"];
    let err = |id: &str| {
        max(&cols[&format!("{id}_q")]
            .iter()
            .zip(q)
            .map(|(a, b)| (a - b).abs())
            .collect::<Vec<_>>())
    };
    for id in ["midpoint", "paper-dirk2", "gauss2", "symplectic-euler-a"] {
        assert!(err(id) < 0.1, "{id}: max |Δq| = {}", err(id));
    }
    assert!(err("euler") > 1.0, "explicit Euler's amplitude grows");
    assert!(err("gauss2") < err("paper-dirk2") && err("paper-dirk2") < err("midpoint"));
}

#[test]
fn other_set_ups_run() {
    let dir = temp_dir("custom");
    let (code, out, err) = symlab(&[
        "paper",
        "--out",
        dir.to_str().unwrap(),
        "--k",
        "2",
        "--q0",
        "-0.5",
        "--p0",
        "1",
        "--steps",
        "40",
        "--h",
        "0.02,0.2",
    ]);
    assert_eq!(code, 0, "stdout: {out}\nstderr: {err}");
    for name in [
        "oscillator_h0.2_energy.svg",
        "oscillator_h0.02_series.csv",
        "report.md",
    ] {
        assert!(dir.join(name).exists(), "{name}");
    }
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(report.contains("k = 2"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_arguments_are_exit_2_with_a_message() {
    let dir = temp_dir("bad");
    let out = dir.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["paper", "--bogus"], "--bogus"),
        (&["paper", "--out", out, "--k", "-1"], "--k"),
        (&["paper", "--out", out, "--k", "zero"], "--k"),
        (&["paper", "--out", out, "--steps", "5"], "--steps"),
        (&["paper", "--out", out, "--steps", "-3"], "--steps"),
        (&["paper", "--out", out, "--h", "0.1,0"], "--h"),
        (&["paper", "--out", out, "--h", "0.1,nan"], "--h"),
        (&["paper", "--out", out, "--q0", "0", "--p0", "0"], "--q0"),
    ];
    for (args, needle) in cases {
        let (code, stdout, stderr) = symlab(args);
        assert_eq!(code, 2, "{args:?}: stdout {stdout}, stderr {stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
    // An --out that is a file, not a directory.
    let file = std::env::temp_dir().join(format!("symlab-paper-file-{}", std::process::id()));
    std::fs::write(&file, "not a directory").unwrap();
    let (code, _, stderr) = symlab(&["paper", "--out", file.to_str().unwrap()]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("--out"), "{stderr}");
    let _ = std::fs::remove_file(&file);
    let _ = std::fs::remove_dir_all(&dir);
}
