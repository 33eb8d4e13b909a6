//! End-to-end tests of `symlab compare`: the documented CSV columns, clear
//! errors with exit code 2, and the observed orders of a small sweep.

use std::collections::BTreeMap;
use std::path::PathBuf;

use crate::common;
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
            "--long runs on kepler, kepler-hard, oscillator or henon-heiles",
        ),
        (
            &["--long", "--problem", "kepler-hard", "--methods", "rk4"],
            "--methods does not apply",
        ),
        // Time-transformed and reversible adaptive methods: bad bases.
        (
            &["--problem", "kepler-hard", "--methods", "adaptive:rk4"],
            "'rk4' is not symmetric",
        ),
        (
            &["--problem", "kepler", "--methods", "adaptive-implicit:nope"],
            "unknown base method 'nope'",
        ),
        (
            &["--problem", "fpu", "--methods", "adaptive:leapfrog"],
            "has no step density",
        ),
        (
            &["--problem", "kepler", "--methods", "logh:nope"],
            "unknown base method 'nope'",
        ),
        (
            &["--long", "--problem", "kepler", "--steps", "5"],
            "--steps must be between",
        ),
        (&["--methods", "rk4"], "--problem is required"),
        (
            &["--problem", "kepler", "--methods", "rk4,,leapfrog"],
            "--methods has an empty entry",
        ),
        // A sweep's flag given to a mode that has no sweep is named.
        (
            &["--long", "--problem", "kepler", "--h-min", "0.1"],
            "--h-min",
        ),
        (&["--hard", "--points", "5"], "--points"),
        // Negative numbers name their flag (not clap's "unexpected argument").
        (
            &["--problem", "kepler", "--t-end", "-1e-300"],
            "--t-end must be",
        ),
        (&["--problem", "kepler", "--points", "-1"], "--points"),
        (&["--problem", "kepler", "--repeats", "-3"], "--repeats"),
        (
            &["--problem", "kepler", "--h-min", "-inf"],
            "--h-min must be",
        ),
        // A flag the user did not give is not blamed.
        (&["--problem", "kepler", "--h-min", "5"], "give --h-max too"),
        (
            &["--problem", "kepler", "--h-max", "1e-9"],
            "give --h-min too",
        ),
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

/// The cells of the Markdown table rows that follow `heading` (up to the
/// next heading), header and separator skipped.
fn table_after(md: &str, heading: &str) -> Vec<Vec<String>> {
    let start = md
        .find(heading)
        .unwrap_or_else(|| panic!("no {heading:?} in\n{md}"));
    let rest = &md[start + heading.len()..];
    let end = rest.find("\n#").unwrap_or(rest.len());
    rest[..end]
        .lines()
        .filter(|l| l.starts_with('|'))
        .skip(2)
        .map(|l| {
            l.trim_matches('|')
                .split('|')
                .map(|c| c.trim().to_string())
                .collect()
        })
        .collect()
}

#[test]
fn quick_run_writes_a_report_with_a_sorted_time_table() {
    let dir = temp_dir("report");
    let (code, out, err) = symlab(&[
        "compare",
        "--problem",
        "kepler",
        "--methods",
        "kahan-li6,rk4,leapfrog,dop853",
        "--quick",
        "--target",
        "1e-6",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "stderr: {err}");
    assert!(out.contains("report.md"), "{out}");
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    for heading in [
        "# Work–precision sweep: Kepler e = 0.6",
        "## Summary",
        "## Wall time to reach relative error 1e-6 over T = 62.8319 (10 orbits), fastest first",
        "## Did not reach 1e-6 within the sweep",
    ] {
        assert!(md.contains(heading), "no {heading:?} in\n{md}");
    }
    let summary = table_after(&md, "## Summary");
    assert_eq!(summary.len(), 4, "{md}");
    let times = table_after(&md, "fastest first");
    assert!(!times.is_empty(), "{md}");
    let t: Vec<f64> = times.iter().map(|r| r[3].parse().unwrap()).collect();
    assert!(t.windows(2).all(|w| w[0] <= w[1]), "not sorted: {t:?}");
    let ranks: Vec<&str> = times.iter().map(|r| r[0].as_str()).collect();
    assert_eq!(ranks[0], "1");
    // Leapfrog stays far above 1e-6 at 10⁴ steps; the reason is spelled out.
    assert!(
        md.contains("- leapfrog: smallest error") && md.contains("at 10⁴ steps"),
        "{md}"
    );
    if cfg!(feature = "peer") {
        assert!(
            md.contains("## Peer: DOP853 against our fastest method"),
            "{md}"
        );
        let duels = table_after(&md, "## Peer");
        assert!(!duels.is_empty(), "{md}");
        for d in &duels {
            assert!(
                ["ours", "dop853", "undetermined", "tie (within 10 %)"].contains(&d[6].as_str()),
                "{d:?}"
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
#[cfg_attr(
    not(feature = "peer"),
    ignore = "needs the `peer` feature (DOP853, on by default)"
)]
fn quick_peer_study_writes_rows_for_each_run_length() {
    let dir = temp_dir("peer");
    let (code, out, err) = symlab(&[
        "compare",
        "--peer-study",
        "--quick",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "stderr: {err}");
    assert!(out.contains("peer.md"), "{out}");
    let (header, rows) = read_csv(&dir.join("peer.csv"));
    assert_eq!(header[..15], COLUMNS);
    assert_eq!(header[15], "t_end");
    let two_pi = 2.0 * std::f64::consts::PI;
    for problem in ["kepler", "kepler-hard"] {
        for orbits in [1.0, 10.0] {
            let mine: Vec<_> = rows
                .iter()
                .filter(|r| {
                    let t: f64 = r["t_end"].parse().unwrap();
                    r["problem"] == problem && (t - orbits * two_pi).abs() < 1e-9
                })
                .collect();
            for m in [
                "dop853",
                "kahan-li8",
                "logh:kahan-li8",
                "adaptive:kahan-li8",
            ] {
                assert!(
                    mine.iter().any(|r| r["method"] == m),
                    "{problem} {orbits} {m}"
                );
            }
        }
    }
    let md = std::fs::read_to_string(dir.join("peer.md")).unwrap();
    assert!(md.contains("## Verdict"), "{md}");
    let verdict = table_after(&md, "## Verdict");
    // One row per eccentricity, run length and target 1e-6, 1e-8, 1e-10.
    assert_eq!(verdict.len(), 12, "{md}");
    let mut want = vec![];
    for e in ["0.6", "0.9"] {
        for orbits in ["1", "10"] {
            for target in ["1e-6", "1e-8", "1e-10"] {
                want.push((e, orbits, target));
            }
        }
    }
    for (row, (e, orbits, target)) in verdict.iter().zip(want) {
        assert_eq!(
            (row[0].as_str(), row[1].as_str(), row[2].as_str()),
            (e, orbits, target)
        );
    }
    for heading in [
        "## e = 0.6, 1 orbit (T = 6.28)",
        "## e = 0.9, 10 orbits (T = 62.83)",
    ] {
        assert!(md.contains(heading), "no {heading:?} in\n{md}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_peer_study_refuses_other_modes_and_settings() {
    let cases: &[(&[&str], &str)] = &[
        (&["--peer-study", "--hard"], "cannot be used with"),
        (&["--peer-study", "--long"], "cannot be used with"),
        (&["--peer-study", "--from", "x.csv"], "cannot be used with"),
        (
            &["--peer-study", "--problem", "fpu"],
            "--peer-study runs on kepler (e = 0.6) and kepler-hard (e = 0.9) only",
        ),
        (
            &["--peer-study", "--t-end", "10"],
            "--t-end does not apply to --peer-study",
        ),
        (
            &["--peer-study", "--methods", "rk4"],
            "keep it in --methods",
        ),
        (&["--peer-study", "--target", "0"], "--target must be"),
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

/// A copy of a table file under a new name (the method id is the file
/// name), with extra lines appended.
fn table_copy(dir: &std::path::Path, from: &str, name: &str, extra: &str) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let text = std::fs::read_to_string(format!("tests/tables/{from}.toml")).unwrap();
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, format!("{extra}\n{text}")).unwrap();
    path
}

#[test]
fn table_files_join_the_sweep_and_match_the_generated_schemes() {
    let dir = temp_dir("table");
    let fr = table_copy(
        &dir,
        "forest-ruth",
        "my-forest-ruth",
        "claims = [\"symplectic\", \"order = 4\"]",
    );
    let g2 = table_copy(&dir, "gauss2", "my-gauss2", "");
    let out = dir.join("out");
    let (code, stdout, err) = symlab(&[
        "compare",
        "--problem",
        "kepler",
        "--methods",
        "forest-ruth,gauss2",
        "--table",
        fr.to_str().unwrap(),
        "--table",
        g2.to_str().unwrap(),
        "--points",
        "3",
        "--h-min",
        "0.01",
        "--h-max",
        "0.1",
        "--repeats",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "stderr: {err}");
    assert!(stdout.contains("interpreted"), "{stdout}");
    let (header, rows) = read_csv(&out.join("runs.csv"));
    let mut with = COLUMNS.to_vec();
    with.push("interpreted");
    assert_eq!(header, with);
    for (table, library) in [("my-forest-ruth", "forest-ruth"), ("my-gauss2", "gauss2")] {
        let mine: Vec<_> = rows.iter().filter(|r| r["method"] == table).collect();
        let lib: Vec<_> = rows.iter().filter(|r| r["method"] == library).collect();
        assert_eq!(mine.len(), 3, "{table}");
        assert_eq!(mine.len(), lib.len());
        for (a, b) in mine.iter().zip(&lib) {
            assert_eq!(a["interpreted"], "true");
            assert_eq!(b["interpreted"], "false");
            assert_eq!(a["status"], "ok", "{a:?}");
            assert_eq!(a["steps"], b["steps"]);
            assert_eq!(a["evals"], b["evals"], "{table}: evaluations");
            assert_eq!(a["order"], b["order"]);
            assert_eq!(a["symplectic"], b["symplectic"]);
            let (ea, eb): (f64, f64) = (a["error"].parse().unwrap(), b["error"].parse().unwrap());
            // The same steps up to round-off: the errors agree far below
            // their own size.
            assert!(
                (ea - eb).abs() <= 1e-12 + 1e-9 * eb,
                "{table}: {ea} vs {eb}"
            );
        }
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("## Interpreted tables"), "{report}");
    assert!(report.contains("my-forest-ruth (interpreted)"), "{report}");
    assert!(report.contains("--example my_scheme"), "{report}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn table_files_with_false_claims_or_bad_fields_are_refused() {
    let dir = temp_dir("badtable");
    let false_claim = table_copy(
        &dir,
        "gauss2-perturbed",
        "almost-gauss2",
        "claims = [\"order = 4\", \"symplectic\"]",
    );
    let malformed = table_copy(&dir, "not-a-number", "broken", "");
    let taken = table_copy(&dir, "rk4", "rk4", "");
    let cases: Vec<(&PathBuf, Vec<&str>)> = vec![
        (
            &false_claim,
            vec![
                "almost-gauss2.toml",
                "claim `symplectic` does not hold",
                "W[0][1]",
            ],
        ),
        (&malformed, vec!["broken.toml", "field a[0][0]"]),
        (&taken, vec!["rk4", "taken"]),
    ];
    for (path, needles) in cases {
        let (code, _, err) = symlab(&[
            "compare",
            "--quick",
            "--problem",
            "kepler",
            "--table",
            path.to_str().unwrap(),
            "--out",
            dir.join("out").to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{path:?}: {err}");
        for n in needles {
            assert!(err.contains(n), "{path:?}: expected {n:?} in {err}");
        }
        assert!(!err.contains("panicked"), "{err}");
    }
    // A drift–kick table cannot step the linear (non-separable) problem.
    let fr = table_copy(&dir, "forest-ruth", "fr", "");
    let (code, _, err) = symlab(&[
        "compare",
        "--quick",
        "--problem",
        "gyroscopic",
        "--table",
        fr.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("'fr'") && err.contains("separable"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_linear_problem_from_a_file_runs_against_its_exact_flow() {
    let dir = temp_dir("linfile");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("two-masses.toml");
    std::fs::write(
        &path,
        "m = [[2.0, 0.0], [0.0, 1.0]]\ng = [[0.0, 0.5], [-0.5, 0.0]]\nk = [[3.0, -1.0], [-1.0, 2.0]]\n\
         f = [0.1, 0.0]\nq0 = [1.0, 0.0]\nt_end = 10.0\nh_min = 0.01\nh_max = 0.5\n",
    )
    .unwrap();
    let out = dir.join("out");
    let (code, _, err) = symlab(&[
        "compare",
        "--problem-file",
        path.to_str().unwrap(),
        "--methods",
        "rk4,gauss2,gauss2-propagator",
        "--points",
        "4",
        "--repeats",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let (_, rows) = read_csv(&out.join("runs.csv"));
    assert!(
        rows.iter()
            .all(|r| r["problem"] == "two-masses" && r["status"] == "ok")
    );
    let rk4: Vec<f64> = rows
        .iter()
        .filter(|r| r["method"] == "rk4")
        .map(|r| r["error"].parse().unwrap())
        .collect();
    // Errors fall like h⁴: 4 points over a factor of 50 in h.
    assert!(rk4[0] / rk4[3] > 1e5, "{rk4:?}");
    // Bad files name the field.
    for (text, needle) in [
        (
            "m = [[1.0]]\nk = [[1.0]]\nq0 = [1.0, 2.0]\n",
            "field q0 has 2 entries",
        ),
        ("m = [[1.0]]\nk = [[1.0]]\nq0 = [1.0]\nspeed = 3\n", "speed"),
        ("m = [[-1.0]]\nk = [[1.0]]\nq0 = [1.0]\n", "M"),
        (
            "m = [[1.0]]\nk = [[1.0]]\nq0 = [1.0]\nt_end = -1.0\n",
            "t_end",
        ),
    ] {
        std::fs::write(&path, text).unwrap();
        let (code, _, err) = symlab(&[
            "compare",
            "--quick",
            "--problem-file",
            path.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{text}: {err}");
        assert!(
            err.contains("two-masses.toml") && err.contains(needle),
            "{text}: {err}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn absurd_steps_are_divergences_never_ok_with_an_infinite_error() {
    let dir = temp_dir("absurd");
    let (code, _, err) = symlab(&[
        "compare",
        "--problem",
        "oscillator",
        "--t-end",
        "1e15",
        "--h-min",
        "1e14",
        "--h-max",
        "1e15",
        "--methods",
        "rk4,leapfrog,gauss2,euler",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let (_, rows) = read_csv(&dir.join("runs.csv"));
    assert!(!rows.is_empty());
    for r in &rows {
        let e: f64 = r["error"].parse().unwrap();
        let de: f64 = r["energy_error"].parse().unwrap();
        if r["status"] == "ok" {
            assert!(e.is_finite() && de.is_finite(), "{r:?}");
        } else {
            assert!(
                r["status"].starts_with("diverged at step")
                    || r["status"].starts_with("solver failed at step"),
                "{r:?}"
            );
            assert!(e.is_nan(), "{r:?}");
        }
    }
    assert!(
        rows.iter()
            .any(|r| r["status"].starts_with("diverged at step"))
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
