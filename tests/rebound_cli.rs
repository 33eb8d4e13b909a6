//! `symlab compare --methods …,rebound:NAME`: REBOUND's rows beside ours,
//! the install command and the other rows where REBOUND is missing, and
//! errors naming a bad name. The test that runs REBOUND is `#[ignore]`d
//! with its reason; `scripts/test` runs it with REBOUND installed.

use std::path::PathBuf;
use std::process::Command;

/// `symlab ARGS` with `SYMLAB_PYTHON` set (or not): (exit code, stdout,
/// stderr).
fn symlab(python: Option<&str>, args: &[&str]) -> (i32, String, String) {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_symlab"));
    cmd.args(args).current_dir(env!("CARGO_MANIFEST_DIR"));
    if let Some(p) = python {
        cmd.env("SYMLAB_PYTHON", p);
    }
    let out = cmd.output().expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("symlab-rebound-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The `method` and `status` columns of a runs.csv (no quoted commas in
/// these runs' ids).
fn methods_and_status(dir: &std::path::Path) -> Vec<(String, String)> {
    let text = std::fs::read_to_string(dir.join("runs.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let m = header.iter().position(|c| *c == "method").unwrap();
    let s = header.iter().position(|c| *c == "status").unwrap();
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[m].to_string(), f[s].to_string())
        })
        .collect()
}

#[test]
fn without_rebound_the_command_says_how_to_install_it_and_goes_on() {
    let dir = temp_dir("missing");
    let out = dir.to_str().unwrap();
    let (code, stdout, stderr) = symlab(
        Some("/nonexistent/python3"),
        &[
            "compare",
            "--problem",
            "kepler",
            "--methods",
            "leapfrog,rebound:whfast",
            "--quick",
            "--out",
            out,
        ],
    );
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("pip install rebound==5.2.2") && stdout.contains("rebound:whfast"),
        "{stdout}"
    );
    let rows = methods_and_status(&dir);
    assert!(!rows.is_empty());
    assert!(
        rows.iter().all(|(m, s)| m == "leapfrog" && s == "ok"),
        "{rows:?}"
    );
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(report.contains("pip install rebound==5.2.2"), "{report}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_rebound_names_are_errors_naming_the_flag_value() {
    for (methods, wanted) in [
        ("leapfrog,rebound:nope", "unknown REBOUND integrator 'nope'"),
        ("rebound:whfast:corrector=2", "corrector = '2'"),
    ] {
        let (code, _, stderr) = symlab(
            None,
            &[
                "compare",
                "--problem",
                "outer-solar",
                "--methods",
                methods,
                "--quick",
            ],
        );
        assert_eq!(code, 2, "{methods}: {stderr}");
        assert!(
            stderr.contains(wanted) && stderr.contains("--methods"),
            "{methods}: {stderr}"
        );
    }
    let (code, _, stderr) = symlab(
        None,
        &[
            "compare",
            "--problem",
            "pendulum",
            "--methods",
            "rebound:whfast",
            "--quick",
        ],
    );
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("rebound:whfast") && stderr.contains("pendulum"),
        "{stderr}"
    );
}

/// REBOUND is not a dependency: `scripts/test` installs it into `.venv`
/// and runs this with `SYMLAB_PYTHON` set there (`cargo test --test
/// rebound_cli -- --ignored`); run so, it fails where REBOUND is missing.
#[test]
#[ignore = "needs REBOUND 5.2.2 under $SYMLAB_PYTHON; scripts/test installs it into .venv and runs these"]
fn rebound_rows_stand_beside_ours() {
    let probe = Command::new(compare::rebound::python())
        .args(["-c", "import rebound"])
        .status();
    assert!(
        probe.is_ok_and(|s| s.success()),
        "REBOUND does not import under '{}': run scripts/test, or `pip install rebound==5.2.2` and set SYMLAB_PYTHON",
        compare::rebound::python().display()
    );
    let dir = temp_dir("rows");
    let out = dir.to_str().unwrap();
    let (code, stdout, stderr) = symlab(
        None,
        &[
            "compare",
            "--problem",
            "kepler",
            "--methods",
            "leapfrog,rebound:whfast,rebound:leapfrog",
            "--quick",
            "--out",
            out,
        ],
    );
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("ours / REBOUND"), "{stdout}");
    let rows = methods_and_status(&dir);
    for m in ["leapfrog", "rebound:whfast", "rebound:leapfrog"] {
        let mine: Vec<_> = rows.iter().filter(|(id, _)| id == m).collect();
        assert_eq!(mine.len(), 4, "{m}: {rows:?}");
        assert!(mine.iter().all(|(_, s)| s == "ok"), "{m}: {rows:?}");
    }
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(report.contains("REBOUND 5.2.2"), "{report}");
    let _ = std::fs::remove_dir_all(&dir);
}
