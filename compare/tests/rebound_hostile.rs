//! A REBOUND interpreter that misbehaves (issue 35): one that answers with
//! no timings, one that floods its output. Neither needs REBOUND: each is a
//! stand-in script given as the method's interpreter, so these tests run
//! everywhere.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use compare::builtin;
use compare::rebound::{self, Point};
use compare::{Method, Problem};

/// A temporary directory of this test's own.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "symlab-rebound-hostile-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// An executable script at `dir/name`.
fn script(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    path
}

/// The interpreter line of the stand-ins, which are Python scripts: the
/// comparisons' interpreter (`SYMLAB_PYTHON`, default `python3`), through
/// `env` where it is a bare name.
fn shebang() -> String {
    let python = rebound::python();
    if python.is_absolute() {
        python.display().to_string()
    } else {
        format!("/usr/bin/env {}", python.display())
    }
}

/// `rebound:whfast` on Kepler (e = 0.6) with `python` as its interpreter.
fn whfast_with(
    python: &Path,
) -> (
    compare::Setup<integrator_core::problems::Kepler>,
    rebound::ReboundMethod,
) {
    let setup = builtin::kepler(false, 2.0 * std::f64::consts::PI, true).unwrap();
    let m = match setup.method("rebound:whfast").unwrap() {
        Method::Rebound(r) => r.with_python(python),
        _ => unreachable!(),
    };
    (setup, m)
}

#[test]
#[cfg_attr(not(unix), ignore = "the stand-in interpreters are shell scripts")]
fn an_answer_without_timings_is_a_failed_row_not_ok_with_a_nan_time() {
    let dir = temp_dir("no-times");
    // Answers the probe, and every run with the state it was given, the
    // step count and an empty list of timings.
    let fake = script(
        &dir,
        "python-no-times",
        &format!(
            "#!{}\nimport json, sys\nreq = json.loads(sys.stdin.read())\nif 'probe' in req:\n    print(json.dumps({{'ok': True, 'rebound': '5.2.2'}}))\nelse:\n    s = req['run']\n    print(json.dumps({{'ok': True, 'rebound': '5.2.2', 'positions': s['positions'], 'velocities': s['velocities'], 'steps': req['steps'] or 10, 'times': [], 'reproducible': True, 'samples': []}}))\n",
            shebang()
        ),
    );
    let (setup, m) = whfast_with(&fake);
    let row = rebound::row(&setup, &m, Point::Steps(100), 0.1, 3);
    assert!(!row.ok(), "{}", row.status);
    assert!(
        row.status.starts_with("rebound failed") && row.status.contains("timings"),
        "{}",
        row.status
    );
    // Timings that are not numbers are refused the same way.
    let fake = script(
        &dir,
        "python-bad-times",
        &std::fs::read_to_string(&fake)
            .unwrap()
            .replace("'times': []", "'times': ['x', 1, 2]"),
    );
    let (setup, m) = whfast_with(&fake);
    let row = rebound::row(&setup, &m, Point::Steps(100), 0.1, 3);
    assert!(row.status.contains("timings"), "{}", row.status);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
#[cfg_attr(not(unix), ignore = "the stand-in interpreters are shell scripts")]
fn a_flooding_interpreter_is_stopped_with_a_message() {
    let dir = temp_dir("flood");
    // Writes without end to stdout, then (second script) to stderr.
    for (name, text) in [
        ("python-flood-out", "#!/bin/sh\nexec yes symlab\n"),
        ("python-flood-err", "#!/bin/sh\nexec yes symlab >&2\n"),
    ] {
        let fake = script(&dir, name, text);
        let start = Instant::now();
        let why = rebound::probe(&fake).unwrap_err();
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "{name}: {:?}",
            start.elapsed()
        );
        assert!(why.contains("REBOUND does not answer"), "{name}: {why}");
        // A sweep leaves the method out with that note, and runs the rest.
        let (setup, m) = whfast_with(&fake);
        let availability = rebound::availability([&m]);
        assert_eq!(availability.left_out, vec!["rebound:whfast".to_string()]);
        assert!(
            availability
                .notes
                .iter()
                .any(|n| n.contains("rebound:whfast")),
            "{:?}",
            availability.notes
        );
        assert!(setup.sys.rebound_bodies(&setup.z0).is_some());
    }
    let _ = std::fs::remove_dir_all(&dir);
}
