//! Random flag values for `compare` and `paper` never panic or hang: every
//! run exits 0, 1 or 2, and a non-zero exit comes with a message that names
//! the flag. (Scene and table files get their own property tests in the
//! `cloth` and `tableau` crates; `scripts/hostile_sweep.py` runs the broad
//! sweep against a release build.)

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use proptest::prelude::*;

/// Values that broke or could break parsers and validators.
const EXTREME: &[&str] = &[
    "0",
    "-0",
    "-1",
    "1e-300",
    "-1e-300",
    "1e300",
    "1e308",
    "5e-324",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "abc",
    "",
    "1e",
    "0x10",
    "18446744073709551616",
    "-18446744073709551616",
    "1.5",
    " 2",
];

/// `symlab ARGS` with a deadline: `(exit code, stderr)`, or `None` when it
/// ran past `limit` (it is killed then).
fn run_limited(args: &[String], limit: Duration) -> Option<(i32, String)> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_symlab"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("runs");
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().expect("waits") {
            let mut err = String::new();
            use std::io::Read;
            child
                .stderr
                .take()
                .expect("piped")
                .read_to_string(&mut err)
                .ok();
            return Some((status.code().unwrap_or(-1), err));
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::sample::select(EXTREME).prop_map(str::to_string),
        // Any magnitude, either sign.
        (any::<bool>(), -320i32..320, 1u32..10)
            .prop_map(|(neg, e, m)| { format!("{}{m}e{e}", if neg { "-" } else { "" }) }),
    ]
}

fn check(args: Vec<String>, flag: &str) -> Result<(), TestCaseError> {
    let Some((code, err)) = run_limited(&args, Duration::from_secs(60)) else {
        return Err(TestCaseError::fail(format!("{args:?} ran past 60 s")));
    };
    prop_assert!(
        [0, 1, 2].contains(&code),
        "{args:?}: exit {code}, stderr {err}"
    );
    prop_assert!(!err.contains("panicked"), "{args:?}: {err}");
    if code != 0 {
        prop_assert!(
            err.starts_with("error") && err.contains(flag),
            "{args:?}: the message should name {flag}: {err}"
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn compare_flags_never_panic_or_hang(
        flag in prop::sample::select(&["--t-end", "--h-min", "--h-max", "--target", "--points", "--repeats"][..]),
        problem in prop::sample::select(&["oscillator", "pendulum", "kepler", "gyroscopic"][..]),
        v in value(),
    ) {
        let out = std::env::temp_dir().join(format!("symlab-hostile-flags-{}", std::process::id()));
        let args: Vec<String> = ["compare", "--quick", "--problem", problem, "--methods", "leapfrog,rk4", flag, &v, "--out", out.to_str().unwrap()]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let args = if problem == "gyroscopic" {
            args.into_iter().map(|a| if a == "leapfrog,rk4" { "rk4".into() } else { a }).collect()
        } else {
            args
        };
        check(args, flag)?;
        let _ = std::fs::remove_dir_all(&out);
    }

    #[test]
    fn paper_flags_never_panic_or_hang(
        flag in prop::sample::select(&["--k", "--q0", "--p0", "--h", "--steps"][..]),
        v in value(),
    ) {
        let out = std::env::temp_dir().join(format!("symlab-hostile-paper-{}", std::process::id()));
        let args: Vec<String> = ["paper", "--cloth-frames", "0", "--out", out.to_str().unwrap(), flag, &v]
            .iter()
            .map(|s| s.to_string())
            .collect();
        check(args, flag)?;
        let _ = std::fs::remove_dir_all(&out);
    }
}
