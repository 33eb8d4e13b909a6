//! A reader that goes away ends `symlab` quietly, as `ls | head` does: the
//! process is ended by SIGPIPE (signal 13; a shell shows status 141) or has
//! already finished with its usual exit code — never a panic ("failed
//! printing to stdout: Broken pipe") with a backtrace.
#![cfg(unix)]

use std::io::Read;
use std::os::unix::process::ExitStatusExt;
use std::path::PathBuf;
use std::process::{Command, ExitStatus, Stdio};

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("symlab-pipes-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn command(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_symlab"));
    c.args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdin(Stdio::null());
    c
}

/// Run with stdout a pipe whose read end is closed at once: (status, stderr).
fn stdout_closed(args: &[&str]) -> (ExitStatus, String) {
    let mut child = command(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawns");
    drop(child.stdout.take());
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    (child.wait().unwrap(), err)
}

/// Run with stderr a pipe whose read end is closed at once: (status, stdout).
fn stderr_closed(args: &[&str]) -> (ExitStatus, String) {
    let mut child = command(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawns");
    drop(child.stderr.take());
    let mut out = String::new();
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut out)
        .unwrap();
    (child.wait().unwrap(), out)
}

fn by_sigpipe_or(status: ExitStatus, code: i32) -> bool {
    status.signal() == Some(libc_sigpipe()) || status.code() == Some(code)
}

/// SIGPIPE is 13 on every unix Rust supports.
fn libc_sigpipe() -> i32 {
    13
}

fn cases(out: &str) -> Vec<Vec<String>> {
    let cloth_out = format!("{out}/cloth");
    let compare_out = format!("{out}/compare");
    [
        vec!["check", "--builtin", "lobatto3a4", "--json"],
        vec!["check", "--builtin", "gauss2"],
        vec!["list"],
        vec![
            "compare",
            "--problem",
            "oscillator",
            "--methods",
            "leapfrog,rk4",
            "--points",
            "2",
            "--repeats",
            "1",
            "--t-end",
            "1",
            "--out",
            &compare_out,
        ],
        vec![
            "cloth",
            "scenes/paper.toml",
            "--frames",
            "1",
            "--grid",
            "5x5",
            "--render",
            "none",
            "--out",
            &cloth_out,
        ],
    ]
    .into_iter()
    .map(|v| v.into_iter().map(String::from).collect())
    .collect()
}

#[test]
fn a_closed_stdout_ends_every_command_quietly() {
    let dir = temp_dir("stdout");
    for args in cases(dir.to_str().unwrap()) {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (status, err) = stdout_closed(&args);
        assert!(
            by_sigpipe_or(status, 0),
            "{args:?}: {status:?} (expected SIGPIPE or exit 0); stderr: {err}"
        );
        assert!(err.is_empty(), "{args:?} printed on stderr: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_closed_stderr_ends_every_command_quietly() {
    let dir = temp_dir("stderr");
    for args in cases(dir.to_str().unwrap()) {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (status, out) = stderr_closed(&args);
        assert!(
            by_sigpipe_or(status, 0),
            "{args:?}: {status:?} (expected SIGPIPE or exit 0); stdout: {out}"
        );
        assert!(!out.contains("panicked"), "{args:?}: {out}");
    }
    // Errors go to stderr: with it closed the command still ends by SIGPIPE
    // or with its exit code 2, not with a panic (exit 101).
    for args in [
        vec!["check", "no-such-file.toml"],
        vec!["compare", "--problem", "kepler", "--t-end", "-1"],
        vec!["cloth", "no-such-scene.toml"],
        vec!["bogus-command"],
    ] {
        let (status, out) = stderr_closed(&args);
        assert!(
            by_sigpipe_or(status, 2),
            "{args:?}: {status:?} (expected SIGPIPE or exit 2); stdout: {out}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_closed_stdout_after_some_output_ends_with_sigpipe() {
    // `symlab list | head -c 10`: read a little, then close.
    let mut child = command(&["list"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawns");
    let mut first = [0u8; 10];
    child
        .stdout
        .as_mut()
        .unwrap()
        .read_exact(&mut first)
        .unwrap();
    drop(child.stdout.take());
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    let status = child.wait().unwrap();
    assert!(by_sigpipe_or(status, 0), "{status:?}; stderr: {err}");
    assert!(err.is_empty(), "stderr: {err}");
}
