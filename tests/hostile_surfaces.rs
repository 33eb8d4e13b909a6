//! The surfaces added since the last hostile sweep, tried as a hostile user
//! would (issue 35): huge orders in the claims of near-integrable, gradient
//! and processed files through `check` and `compare --table`; a processed
//! file in `compare --table` (stepped with its corrector, its effective
//! claims accepted); absurd end times of problems with a computed
//! reference; `--quick --long`; a user's problem file named in the
//! refusals; the peer study with `rebound:` and no REBOUND; an inextensible
//! scene whose prestretch makes its pins impossible. Each is a clean refusal
//! naming what the user wrote, or a correct run.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// `symlab ARGS` with `env` set: (exit code, stdout, stderr, seconds).
fn symlab_env(args: &[&str], env: &[(&str, &str)]) -> (i32, String, String, f64) {
    let start = Instant::now();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_symlab"));
    cmd.args(args).current_dir(env!("CARGO_MANIFEST_DIR"));
    for (k, v) in env {
        cmd.env(k, v);
    }
    let out = cmd.output().expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        start.elapsed().as_secs_f64(),
    )
}

fn symlab(args: &[&str]) -> (i32, String, String, f64) {
    symlab_env(args, &[])
}

/// A two-point sweep on `problem` with the table file at `path`.
fn compare_table(problem: &str, path: &str) -> (i32, String, String, f64) {
    let mut args = vec!["compare", "--problem", problem];
    if problem == "kepler" {
        args.extend(["--methods", "leapfrog"]);
    }
    args.extend(["--table", path, "--points", "2", "--repeats", "1"]);
    symlab(&args)
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("symlab-hostile-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// The catalogue's leapfrog with the corrector of order 3, as a user's
/// file, with `claims`.
fn processed_file(claims: &str) -> String {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tableau/catalogue/leapfrog-c3.toml"),
    )
    .unwrap();
    let line = text
        .lines()
        .find(|l| l.starts_with("claims"))
        .expect("a claims line");
    text.replace(line, &format!("claims = [{claims}]"))
}

/// `runs.csv` as rows of (column → value).
fn rows(path: &Path) -> Vec<std::collections::HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(str::to_string))
                .collect()
        })
        .collect()
}

#[test]
fn huge_orders_are_refused_in_check_and_compare_naming_the_claim() {
    let dir = temp_dir("orders");
    let near = "name = \"near\"\ndrift = [\"1/4\", \"1/2\", \"1/4\"]\nkick = [\"1/2\", \"1/2\"]\n";
    let gradient =
        "name = \"grad\"\ndrift = [\"1/2\", \"1/2\"]\nkick = [\"1\"]\nkick_gradient = [\"1/24\"]\n";
    for claim in ["order = (99999999999)", "order = 18446744073709551615"] {
        for (kind, body) in [
            ("near", near.to_string()),
            ("gradient", gradient.to_string()),
            ("processed", processed_file(&format!("\"{claim}\""))),
        ] {
            let text = if kind == "processed" {
                body
            } else {
                format!("claims = [\"{claim}\"]\n{body}")
            };
            let path = write(&dir, &format!("{kind}.toml"), &text);
            for (args, (code, _, err, secs)) in [
                ("check", symlab(&["check", &path])),
                ("compare --table", compare_table("kepler", &path)),
            ] {
                assert_eq!(code, 2, "{kind} {claim} {args:?}: {err}");
                assert!(
                    err.contains(&path) && err.contains("beyond every budget"),
                    "{kind} {claim} {args:?}: {err}"
                );
                assert!(secs < 20.0, "{kind} {claim}: {secs} s");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_processed_table_runs_with_its_corrector_and_its_effective_claims_hold() {
    let dir = temp_dir("processed");
    let path = write(
        &dir,
        "mylf3.toml",
        &processed_file("\"symplectic\", \"order = 2\", \"order = (4, 2)\""),
    );
    let out = dir.join("out");
    let (code, _, err, _) = symlab(&[
        "compare",
        "--problem",
        "kepler",
        "--methods",
        "leapfrog",
        "--table",
        &path,
        "--h-min",
        "0.01",
        "--h-max",
        "0.1",
        "--points",
        "3",
        "--repeats",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let rows = rows(&out.join("runs.csv"));
    let of = |m: &str| -> Vec<(String, f64, u64)> {
        rows.iter()
            .filter(|r| r["method"] == m)
            .map(|r| {
                assert_eq!(r["status"], "ok", "{m}: {r:?}");
                (
                    r["steps"].clone(),
                    r["error"].parse().unwrap(),
                    r["evals"].parse().unwrap(),
                )
            })
            .collect()
    };
    let (lf, lf3) = (of("leapfrog"), of("mylf3"));
    assert_eq!(lf.len(), 3);
    assert_eq!(lf.len(), lf3.len());
    for ((n, a, ea), (m, b, eb)) in lf.iter().zip(&lf3) {
        assert_eq!(n, m);
        // The corrector changes the output: not the kernel's rows.
        assert!(
            a != b,
            "n = {n}: the processed method gave the kernel's error {a}"
        );
        // Its cost is the kernel's plus χ⁻¹ on entry and one χ, whatever
        // the number of steps, as the timed run pays; the observer's outputs
        // after every step are not counted. χ's four kicks cost three
        // evaluations: the middle two meet across a zero drift (`a1 - a1`)
        // and are one.
        assert_eq!(*eb, ea + 6, "n = {n}: evaluations");
    }
    // A claim false of the effective method is refused, naming the claim.
    let bad = write(&dir, "bad.toml", &processed_file("\"order = (6, 2)\""));
    let (code, _, err, _) = compare_table("kepler", &bad);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("order = (6, 2)") && err.contains(&bad),
        "{err}"
    );
    // A processed method steps split systems only: the linear model refuses
    // it, saying so.
    let (code, _, err, _) = compare_table("gyroscopic", &path);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("processed method") && err.contains("mylf3"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_end_time_beyond_the_reference_budget_is_refused_at_once() {
    for problem in ["outer-solar", "henon-heiles", "fpu"] {
        // A sweep of few steps (so the step-count check lets it through),
        // whose reference would take 10¹⁴ steps and more.
        let (code, _, err, secs) = symlab(&[
            "compare",
            "--problem",
            problem,
            "--t-end",
            "1e15",
            "--h-min",
            "1e13",
            "--h-max",
            "1e14",
            "--points",
            "2",
            "--repeats",
            "1",
        ]);
        assert_eq!(code, 2, "{problem}: {err}");
        assert!(
            err.contains("MAX_REFERENCE_STEPS") && err.contains(problem),
            "{problem}: {err}"
        );
        assert!(secs < 20.0, "{problem}: {secs} s");
    }
}

#[test]
fn quick_long_on_the_outer_solar_system_runs() {
    let dir = temp_dir("long");
    let (code, out, err, _) = symlab(&[
        "compare",
        "--problem",
        "outer-solar",
        "--quick",
        "--long",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("--steps"), "{err}");
    assert!(out.contains("1000 steps"), "{out}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_users_problem_file_is_named_in_the_refusals() {
    let dir = temp_dir("named");
    let path = write(
        &dir,
        "two-masses.toml",
        "m = [[2.0, 0.0], [0.0, 1.0]]\nk = [[3.0, -1.0], [-1.0, 2.0]]\nq0 = [1.0, 0.0]\n",
    );
    for method in [
        "wh:leapfrog",
        "rebound:whfast",
        "logh:leapfrog",
        "adaptive:leapfrog",
        "leapfrog",
    ] {
        let (code, _, err, _) = symlab(&[
            "compare",
            "--problem-file",
            &path,
            "--methods",
            method,
            "--quick",
        ]);
        assert_eq!(code, 2, "{method}: {err}");
        assert!(
            err.contains("two-masses") && !err.contains("gyroscopic problem"),
            "{method}: {err}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
#[cfg_attr(
    not(feature = "peer"),
    ignore = "needs the `peer` feature (DOP853, on by default)"
)]
fn the_peer_study_without_rebound_says_so_and_counts_rebound_as_a_peer() {
    let dir = temp_dir("peer");
    let (code, _, err, _) = symlab_env(
        &[
            "compare",
            "--peer-study",
            "--quick",
            "--problem",
            "kepler",
            "--methods",
            "kahan-li8,dop853,rebound:whfast",
            "--out",
            dir.to_str().unwrap(),
        ],
        &[("SYMLAB_PYTHON", "/nonexistent/python3")],
    );
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("note:")
            && err.contains("rebound:whfast")
            && err.contains("pip install rebound"),
        "{err}"
    );
    let md = std::fs::read_to_string(dir.join("peer.md")).unwrap();
    assert!(
        md.contains("ours kahan-li8; peers dop853, rebound:whfast"),
        "{md}"
    );
    let csv = std::fs::read_to_string(dir.join("peer.csv")).unwrap();
    assert!(!csv.contains("rebound:whfast"), "{csv}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_prestretch_that_makes_the_pins_impossible_is_blamed_on_the_prestretch() {
    let dir = temp_dir("prestretch");
    // The top row pinned: its first edge joins two pinned particles, which
    // the prestretch puts 1 % further apart than the edge's length.
    let scene = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper64-inextensible.toml"),
    )
    .unwrap();
    let scene = scene.replacen("[cloth]\n", "[cloth]\nprestretch = 1.01\n", 1);
    assert!(
        scene.contains("prestretch = 1.01"),
        "the scene has a [cloth] table"
    );
    let path = write(&dir, "stretched.toml", &scene);
    let (code, _, err, _) = symlab(&["cloth", &path, "--grid", "8x8", "--frames", "1"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("cloth.prestretch") && err.contains("both pinned"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_composition_of_zero_steps_is_refused_naming_compose() {
    let dir = temp_dir("compose");
    let path = write(&dir, "zero.toml", "name = \"zero\"\ncompose = [\"0\"]\n");
    let (code, _, err, _) = compare_table("kepler", &path);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("`compose`") && err.contains("identity map") && err.contains("zero"),
        "{err}"
    );
    // `check` reports what it is (order 0) and exits 0, as for any table.
    let (code, out, err, _) = symlab(&["check", &path]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("order        0"), "{out}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_coefficient_far_beyond_f64_is_printed_with_its_exponent_not_inf() {
    let dir = temp_dir("huge");
    let path = write(
        &dir,
        "huge.toml",
        "name = \"huge\"\nclaims = [\"order = (2, 2)\"]\ndrift = [\"10^5000\", \"1 - 10^5000\"]\nkick = [\"1\"]\n",
    );
    let (code, out, err, _) = symlab(&["check", &path]);
    assert_eq!(code, 0, "{err}");
    assert!(!out.contains("inf") && !out.contains("NaN"), "{out}");
    assert!(out.contains("≈ 1.000e5000"), "{out}");
    // `compare` steps in doubles: such a table is refused, naming the
    // coefficient, instead of a run that diverges at its first step.
    let unclaimed = write(
        &dir,
        "huge2.toml",
        "name = \"huge\"\ndrift = [\"10^5000\", \"1 - 10^5000\"]\nkick = [\"1\"]\n",
    );
    let (code, _, err, _) = compare_table("kepler", &unclaimed);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("not a finite double") && err.contains("1.000e5000"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
