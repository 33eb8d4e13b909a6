//! End-to-end tests of `symlab paper`: it writes every listed file, and the
//! numbers it writes bear out the paper's qualitative claims about the
//! oscillator H = ½(p² + k²q²) at h = 0.1 after 200 steps (parsed from its
//! CSV output); the cloth comparison of figure 5 (a short run) shows what the
//! report says it shows; bad arguments are exit code 2 with a message.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use crate::common;
use common::symlab;

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("symlab-paper-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Frames of the cloth comparison in the shared run (0.2 s at 60 Hz: long
/// enough for every explicit method at one step per frame to blow up, short
/// enough for a debug build).
const CLOTH_FRAMES: &str = "12";

/// One run of `symlab paper --out DIR` with the default set-up (and a short
/// cloth comparison), shared by the tests.
fn default_run() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = temp_dir("default");
        let (code, out, err) = symlab(&[
            "paper",
            "--out",
            dir.to_str().unwrap(),
            "--cloth-frames",
            CLOTH_FRAMES,
        ]);
        assert_eq!(code, 0, "stdout: {out}\nstderr: {err}");
        assert!(
            out.contains("Cloth comparison (figure 5), paper scene at 60 Hz frames:"),
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
    expected.extend(
        [
            "cloth_runs.csv",
            "cloth_energy.svg",
            "cloth_euler_x256.png",
            "cloth_symplectic-euler-a_x256.png",
            "cloth_stormer-verlet_x256.png",
            "cloth_implicit-euler_x16.png",
            "cloth_gauss2_x16.png",
            "cloth_rattle_x4.png",
        ]
        .map(String::from),
    );
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
    for text in [
        "every explicit method blows up, symplectic Euler included",
        "The paper's qualitative claim holds once the step is stable",
        "| 25×25 |",
    ] {
        assert!(report.contains(text), "report lacks \"{text}\"");
    }
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
        "--cloth-frames",
        "0",
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
fn a_method_that_diverges_is_reported_in_its_row_and_the_command_goes_on() {
    let dir = temp_dir("diverge");
    let (code, out, err) = symlab(&[
        "paper",
        "--out",
        dir.to_str().unwrap(),
        "--h",
        "10,1e-300",
        "--cloth-frames",
        "0",
    ]);
    assert_eq!(code, 0, "stdout: {out}\nstderr: {err}");
    assert!(out.contains("stopped: diverged at step"), "{out}");
    let (header, rows) = read_csv(&dir.join("oscillator_errors.csv"));
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (method, h, status) = (col("method"), col("h"), col("status"));
    for r in &rows {
        let expect_ok =
            r[h] != "10" || ["midpoint", "gauss2", "paper-dirk2"].contains(&r[method].as_str());
        assert_eq!(r[status] == "ok", expect_ok, "{r:?}");
        for v in &r[col("max_err_q")..col("status")] {
            assert!(!v.contains("NaN"), "{r:?}");
        }
    }
    // A tiny step gives short file names, not 300 digits.
    assert!(dir.join("oscillator_h1e-300_series.csv").exists());
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(
        report.contains("Runs that stopped before step 200"),
        "{report}"
    );
    assert!(
        !report.contains("NaN") && !report.contains(" inf"),
        "{report}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `cloth_runs.csv` as (method, substeps) → the row by column name.
fn cloth_runs() -> HashMap<(String, usize), HashMap<String, String>> {
    let text = std::fs::read_to_string(default_run().join("cloth_runs.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let mut out = HashMap::new();
    for line in lines {
        // The last column (why a run stopped) is quoted and may hold commas.
        let fields: Vec<&str> = line.splitn(header.len(), ',').collect();
        assert_eq!(fields.len(), header.len(), "{line}");
        let row: HashMap<String, String> = header
            .iter()
            .zip(&fields)
            .map(|(h, v)| (h.to_string(), v.to_string()))
            .collect();
        let key = (row["method"].clone(), row["substeps"].parse().unwrap());
        out.insert(key, row);
    }
    out
}

#[test]
fn cloth_at_one_step_per_frame_blows_up_every_explicit_method() {
    let runs = cloth_runs();
    assert_eq!(runs.len(), 15, "{:?}", runs.keys());
    for id in ["euler", "symplectic-euler-a", "stormer-verlet"] {
        let r = &runs[&(id.to_string(), 1)];
        assert_eq!(r["completed"], "false", "{id}: {r:?}");
        assert!(r["stopped"].contains("blew up"), "{id}: {r:?}");
        let h_omega: f64 = r["h_omega_max"].parse().unwrap();
        assert!(h_omega > 100.0, "{id}: h·ω_max = {h_omega}");
    }
    // The midpoint family as energy minimisation, at one step per frame:
    // over the shared run's 0.2 s its solves converge (its energy blows up
    // later, at about 0.6 s: guide/src/cloth.md).
    for id in ["midpoint", "paper-dirk2", "paper-dirk4"] {
        let r = &runs[&(id.to_string(), 1)];
        assert_eq!(r["completed"], "true", "{id}: {r:?}");
        let h_omega: f64 = r["h_omega_max"].parse().unwrap();
        assert!(h_omega > 100.0, "{id}: h·ω_max = {h_omega}");
    }
    // The energy-conserving comparison, also a minimisation: it runs and
    // keeps the energy to its solver's tolerance (6.1e-6 of E_ref over
    // 10 s measured; docs/results/paper.md).
    let r = &runs[&("avf".to_string(), 1)];
    assert_eq!(r["completed"], "true", "avf: {r:?}");
    let worst: f64 = r["max_relative_energy_error"].parse().unwrap();
    assert!(worst < 1e-5, "avf: max |H − H₀|/E_ref = {worst:e}");
}

#[test]
fn cloth_substepped_symplectic_euler_is_bounded_and_explicit_euler_is_not() {
    let runs = cloth_runs();
    let num =
        |id: &str, k: usize, col: &str| -> f64 { runs[&(id.to_string(), k)][col].parse().unwrap() };
    let euler = &runs[&("euler".to_string(), 256)];
    assert_eq!(euler["completed"], "false", "{euler:?}");
    for id in ["symplectic-euler-a", "stormer-verlet"] {
        let r = &runs[&(id.to_string(), 256)];
        assert_eq!(r["completed"], "true", "{id}: {r:?}");
        let worst = num(id, 256, "max_relative_energy_error");
        assert!(worst < 1e-2, "{id}: max |H − H₀|/E_ref = {worst:e}");
        assert!(num(id, 256, "h_omega_max") < 2.0);
    }
    // Gauss–Legendre keeps the energy far better than implicit Euler, which
    // loses it (numerical damping).
    let gauss = num("gauss2", 16, "max_relative_energy_error");
    let ie = num("implicit-euler", 16, "final_relative_energy_error");
    assert!(gauss < 1e-4, "gauss2: {gauss:e}");
    assert!(
        ie < 0.0 && -ie > 10.0 * gauss,
        "implicit Euler: {ie:e}, gauss2 {gauss:e}"
    );
    // The same sheet inextensible: RATTLE at 4 steps per frame runs the
    // shared run's 0.2 s (the sheet whips only at about 1.4 s) with a
    // bounded energy error (1.1e-5 measured), solving its constraints by
    // simplified Newton every step.
    let r = &runs[&("rattle".to_string(), 4)];
    assert_eq!(r["completed"], "true", "rattle: {r:?}");
    let rattle = num("rattle", 4, "max_relative_energy_error");
    assert!(rattle < 1e-3, "rattle: max |H − H₀|/E_ref = {rattle:e}");
    assert!(num("rattle", 4, "newton_per_step") >= 1.0);
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
        (
            &["paper", "--out", out, "--h", "0.1,0.1"],
            "--h: step size 0.1 is given twice",
        ),
        (
            &["paper", "--out", out, "--steps", "100000000000"],
            "--steps",
        ),
        (&["paper", "--out", out, "--q0", "nan"], "--q0"),
        (&["paper", "--out", out, "--q0", "0", "--p0", "0"], "--q0"),
        // Energies that underflow or overflow make relative errors meaningless.
        (&["paper", "--out", out, "--k", "1e-300"], "--k 1e-300"),
        (&["paper", "--out", out, "--q0", "1e-200"], "--q0 1e-200"),
        (
            &["paper", "--out", out, "--k", "1e200"],
            "not a normal positive",
        ),
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
