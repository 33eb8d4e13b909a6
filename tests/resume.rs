//! Resumable runs end to end: a `symlab cloth` run of the hammock scene
//! (RATTLE) stopped by SIGTERM exits 143 with a checkpoint, and `symlab
//! resume` on its folder ends with the files of the run that was never
//! stopped, byte for byte (energy.csv, the OBJ frames, the renderings);
//! the same after SIGKILL at several points; a damaged checkpoint is
//! refused with exit 2 naming the file; a `compare` sweep stopped and
//! resumed has the same rows apart from the wall times; a `paper` run
//! stopped and resumed writes the same files.

#![cfg(unix)]

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use crate::common;
use common::symlab;

const SCENE: &str = "scenes/hammock-inextensible.toml";
/// Small enough for the dev profile, long enough to be stopped part-way.
const GRID: &str = "10x10";
const FRAMES: &str = "240";
const RENDER: &str = "0,1,120,240";

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("symlab-resume-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn cloth_args<'a>(out: &'a str, every: &'a str) -> Vec<&'a str> {
    vec![
        "cloth",
        SCENE,
        "--grid",
        GRID,
        "--frames",
        FRAMES,
        "--obj-every",
        "40",
        "--render",
        RENDER,
        "--checkpoint-every",
        every,
        "--out",
        out,
    ]
}

fn spawn(args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_symlab"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starts")
}

fn signal(child: &Child, sig: i32) {
    // SAFETY: kill(2) on the pid of a child this test started and has not
    // yet waited for.
    let r = unsafe { libc::kill(child.id() as libc::pid_t, sig) };
    assert_eq!(r, 0, "kill failed");
}

/// Wait until `path` exists (the child's first checkpoint), at most 60 s.
fn wait_for(path: &Path, child: &mut Child) {
    let start = Instant::now();
    while !path.exists() {
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the run ended ({status}) before writing {}", path.display());
        }
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no checkpoint after 60 s"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

fn finish(child: Child) -> (i32, String, String) {
    let out = child.wait_with_output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The files of a finished cloth run that must match byte for byte.
fn outputs(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut names = vec!["energy.csv".to_string()];
    for k in [0, 40, 80, 120, 160, 200, 240] {
        names.push(format!("frames/frame_{k:04}.obj"));
    }
    for k in [0, 1, 120, 240] {
        names.push(format!("render_{k:04}.png"));
    }
    names
        .into_iter()
        .map(|n| {
            let bytes = std::fs::read(dir.join(&n))
                .unwrap_or_else(|e| panic!("{}: {e}", dir.join(&n).display()));
            (n, bytes)
        })
        .collect()
}

fn assert_same_outputs(reference: &Path, resumed: &Path) {
    for ((name, a), (_, b)) in outputs(reference).iter().zip(outputs(resumed)) {
        assert!(*a == b, "{name} differs from the uninterrupted run's");
    }
}

/// The summary without the lines that hold wall-clock times, and with the
/// output folder's name made neutral.
fn summary_without_times(stdout: &str, dir: &Path) -> String {
    const TIMED: [&str; 4] = ["wall time", "per frame", "real time", "time split"];
    stdout
        .lines()
        .filter(|l| !TIMED.iter().any(|t| l.trim_start().starts_with(t)))
        .map(|l| l.replace(&dir.display().to_string(), "DIR"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The uninterrupted run, once per test binary.
fn reference() -> (PathBuf, String) {
    static REF: std::sync::OnceLock<(PathBuf, String)> = std::sync::OnceLock::new();
    REF.get_or_init(|| {
        let dir = temp_dir("reference");
        let (code, stdout, stderr) = symlab(&cloth_args(dir.to_str().unwrap(), "off"));
        assert_eq!(code, 0, "stderr: {stderr}");
        assert!(
            !dir.join("checkpoint.symlab").exists(),
            "a finished run leaves no checkpoint"
        );
        (dir, stdout)
    })
    .clone()
}

#[test]
fn sigterm_then_resume_ends_with_the_uninterrupted_runs_bytes() {
    let (reference, ref_stdout) = reference();
    let dir = temp_dir("sigterm");
    let out = dir.to_str().unwrap().to_string();
    let ckpt = dir.join("checkpoint.symlab");
    let mut child = spawn(&cloth_args(&out, "0"));
    wait_for(&ckpt, &mut child);
    signal(&child, libc::SIGTERM);
    let (code, stdout, stderr) = finish(child);
    assert_eq!(
        code, 143,
        "SIGTERM part-way must exit 143\nstdout: {stdout}\nstderr: {stderr}"
    );
    assert!(stdout.contains("stopped by SIGTERM"), "{stdout}");
    assert!(stdout.contains("symlab resume"), "{stdout}");
    assert!(ckpt.is_file());
    // The frames so far are written: energy.csv is a prefix of the
    // uninterrupted run's.
    let partial = std::fs::read_to_string(dir.join("energy.csv")).unwrap();
    let full = std::fs::read_to_string(reference.join("energy.csv")).unwrap();
    assert!(full.starts_with(&partial), "energy.csv so far is a prefix");
    let stopped_rows = partial.lines().count() - 1;
    assert!(
        stopped_rows < 241,
        "stopped part-way ({stopped_rows} frames)"
    );

    let (code, stdout, stderr) = symlab(&["resume", &out]);
    assert_eq!(code, 0, "stderr: {stderr}");
    assert_same_outputs(&reference, &dir);
    assert_eq!(
        summary_without_times(&stdout, &dir),
        summary_without_times(&ref_stdout, &reference),
        "the summary of the resumed run"
    );
    assert!(!ckpt.exists(), "the finished run removed its checkpoint");
    // Nothing left to resume.
    let (code, _, stderr) = symlab(&["resume", &out]);
    assert_eq!(code, 2);
    assert!(stderr.contains("no checkpoint"), "{stderr}");
}

#[test]
fn sigint_exits_130_and_resumes_to_the_same_bytes() {
    let (reference, _) = reference();
    let dir = temp_dir("sigint");
    let out = dir.to_str().unwrap().to_string();
    let ckpt = dir.join("checkpoint.symlab");
    let mut child = spawn(&cloth_args(&out, "0"));
    wait_for(&ckpt, &mut child);
    std::thread::sleep(Duration::from_millis(100));
    signal(&child, libc::SIGINT);
    let (code, stdout, stderr) = finish(child);
    assert_eq!(code, 130, "stdout: {stdout}\nstderr: {stderr}");
    assert!(stdout.contains("stopped by SIGINT"), "{stdout}");
    let (code, _, stderr) = symlab(&["resume", &out]);
    assert_eq!(code, 0, "stderr: {stderr}");
    assert_same_outputs(&reference, &dir);
}

/// The wall time of the reference run (spawn to exit), measured once: the
/// kill points below are fractions of it, so that they fall inside the run
/// on a fast machine as on a slow one (fixed delays of 150 and 600 ms
/// outlasted the whole run on a 2-core AMD EPYC Zen 5).
fn reference_time() -> Duration {
    static TIME: std::sync::OnceLock<Duration> = std::sync::OnceLock::new();
    *TIME.get_or_init(|| {
        let dir = temp_dir("reference-time");
        let start = Instant::now();
        let (code, _, stderr) = symlab(&cloth_args(dir.to_str().unwrap(), "0"));
        assert_eq!(code, 0, "stderr: {stderr}");
        start.elapsed()
    })
}

#[test]
fn killed_at_several_points_and_resumed_gives_the_same_bytes() {
    let (reference, _) = reference();
    let whole = reference_time();
    // Right after the first checkpoint, about a tenth and a third of the
    // way on (the run checkpoints after every frame).
    for (i, share) in [0.0, 0.1, 0.35].into_iter().enumerate() {
        let mut delay = whole.mul_f64(share);
        let mut tries = 0;
        let dir = loop {
            let dir = temp_dir(&format!("kill{i}-{tries}"));
            let out = dir.to_str().unwrap().to_string();
            let ckpt = dir.join("checkpoint.symlab");
            let mut child = spawn(&cloth_args(&out, "0"));
            wait_for(&ckpt, &mut child);
            std::thread::sleep(delay);
            // SIGKILL: no clean stop; the last whole checkpoint must do.
            signal(&child, libc::SIGKILL);
            let (code, _, _) = finish(child);
            if code == 0 {
                // The run ended before the signal came (a machine faster
                // than the reference run said): kill it earlier. A kill
                // must happen; the test does not pass without one.
                tries += 1;
                assert!(
                    tries < 6,
                    "the run ended before SIGKILL at every delay down to {delay:?}"
                );
                delay /= 2;
                continue;
            }
            assert_eq!(code, -1, "killed by SIGKILL");
            break dir;
        };
        let out = dir.to_str().unwrap().to_string();
        // Never a half-written checkpoint under its own name.
        let (code, stdout, stderr) = symlab(&["resume", &out]);
        assert_eq!(
            code, 0,
            "delay {delay:?}\nstdout: {stdout}\nstderr: {stderr}"
        );
        assert_same_outputs(&reference, &dir);
    }
}

#[test]
fn a_resumed_run_stopped_again_resumes_to_the_same_bytes() {
    let (reference, _) = reference();
    let dir = temp_dir("twice");
    let out = dir.to_str().unwrap().to_string();
    let ckpt = dir.join("checkpoint.symlab");
    let mut child = spawn(&cloth_args(&out, "0"));
    wait_for(&ckpt, &mut child);
    signal(&child, libc::SIGTERM);
    assert_eq!(finish(child).0, 143);
    let first = std::fs::read(&ckpt).unwrap();
    let mut child = spawn(&["resume", &out]);
    // Wait for the resumed run's own checkpoint (a different file).
    let start = Instant::now();
    while std::fs::read(&ckpt).is_ok_and(|b| b == first) {
        assert!(child.try_wait().unwrap().is_none(), "finished too soon");
        assert!(start.elapsed() < Duration::from_secs(60));
        std::thread::sleep(Duration::from_millis(5));
    }
    signal(&child, libc::SIGTERM);
    let (code, stdout, stderr) = finish(child);
    assert_eq!(code, 143, "stdout: {stdout}\nstderr: {stderr}");
    let (code, _, stderr) = symlab(&["resume", &out]);
    assert_eq!(code, 0, "stderr: {stderr}");
    assert_same_outputs(&reference, &dir);
}

/// A stopped run's folder with its checkpoint.
fn stopped_run(name: &str) -> (PathBuf, PathBuf) {
    let dir = temp_dir(name);
    let out = dir.to_str().unwrap().to_string();
    let ckpt = dir.join("checkpoint.symlab");
    let mut child = spawn(&cloth_args(&out, "0"));
    wait_for(&ckpt, &mut child);
    signal(&child, libc::SIGTERM);
    assert_eq!(finish(child).0, 143);
    (dir, ckpt)
}

#[test]
fn a_damaged_checkpoint_is_refused_with_exit_2_naming_the_file() {
    let (dir, ckpt) = stopped_run("damaged");
    let out = dir.to_str().unwrap();
    let good = std::fs::read(&ckpt).unwrap();
    let name = ckpt.display().to_string();
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "garbage in the middle",
            {
                let mut b = good.clone();
                let mid = b.len() / 2;
                b[mid..mid + 16].copy_from_slice(b"garbage garbage!");
                b
            },
            "corrupted",
        ),
        ("truncated", good[..good.len() - 100].to_vec(), "truncated"),
        ("cut in its header", good[..12].to_vec(), "truncated"),
        ("empty", Vec::new(), "truncated"),
        (
            "not a checkpoint",
            b"this is not a checkpoint at all".to_vec(),
            "not a symlab checkpoint",
        ),
        (
            "bytes appended",
            {
                let mut b = good.clone();
                b.extend_from_slice(b"junk");
                b
            },
            "appended",
        ),
    ];
    for (what, bytes, says) in cases {
        std::fs::write(&ckpt, &bytes).unwrap();
        let (code, stdout, stderr) = symlab(&["resume", out]);
        assert_eq!(
            code, 2,
            "{what}: exit 2\nstdout: {stdout}\nstderr: {stderr}"
        );
        assert!(stderr.contains(&name), "{what}: names the file: {stderr}");
        assert!(stderr.contains(says), "{what}: says {says:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{what}: {stderr}");
        // Nothing was run: the damaged file is left for the user to see.
        assert_eq!(std::fs::read(&ckpt).unwrap(), bytes, "{what}");
    }
    // The good file still resumes.
    std::fs::write(&ckpt, &good).unwrap();
    let (code, _, stderr) = symlab(&["resume", out]);
    assert_eq!(code, 0, "stderr: {stderr}");
}

#[test]
fn resume_without_a_checkpoint_or_folder_is_a_clear_error() {
    let dir = temp_dir("empty");
    let (code, _, stderr) = symlab(&["resume", dir.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(stderr.contains(dir.to_str().unwrap()), "{stderr}");
    assert!(stderr.contains("no checkpoint"), "{stderr}");
    let missing = dir.join("missing");
    let (code, _, stderr) = symlab(&["resume", missing.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(stderr.contains("no such directory"), "{stderr}");
}

#[test]
fn checkpoint_flag_and_output_folder_are_checked_before_the_run() {
    let dir = temp_dir("flags");
    let out = dir.to_str().unwrap();
    let (code, _, stderr) = symlab(&[
        "cloth",
        SCENE,
        "--grid",
        GRID,
        "--frames",
        "2",
        "--checkpoint-every",
        "5 fortnights",
        "--out",
        out,
    ]);
    assert_eq!(code, 2);
    assert!(stderr.contains("--checkpoint-every"), "{stderr}");
    // A spring scene's explicit method cannot be checkpointed yet: said,
    // not ignored.
    let (code, _, stderr) = symlab(&[
        "cloth",
        "scenes/paper.toml",
        "--frames",
        "1",
        "--checkpoint-every",
        "1s",
        "--out",
        out,
    ]);
    assert_eq!(code, 2);
    assert!(stderr.contains("cannot be checkpointed"), "{stderr}");
    // An output folder that is a file.
    let file = dir.join("a-file");
    std::fs::write(&file, "x").unwrap();
    let (code, _, stderr) = symlab(&[
        "cloth",
        SCENE,
        "--grid",
        GRID,
        "--frames",
        "2",
        "--out",
        file.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(stderr.contains(file.to_str().unwrap()), "{stderr}");
}

/// runs.csv without its time_s column.
fn rows_without_times(csv: &str) -> Vec<String> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let t = header.iter().position(|c| *c == "time_s").unwrap();
    std::iter::once(header.join(","))
        .chain(lines.map(|l| {
            let mut f: Vec<&str> = l.split(',').collect();
            f.remove(t);
            f.join(",")
        }))
        .collect()
}

fn compare_args<'a>(out: &'a str, every: &'a str) -> Vec<&'a str> {
    vec![
        "compare",
        "--problem",
        "kepler",
        "--methods",
        "stormer-verlet,forest-ruth,rk4,gauss2,kahan-li8",
        "--points",
        "12",
        "--t-end",
        "60",
        "--repeats",
        "1",
        "--checkpoint-every",
        every,
        "--out",
        out,
    ]
}

#[test]
fn a_compare_sweep_stopped_and_resumed_has_the_same_rows() {
    let ref_dir = temp_dir("compare-ref");
    let (code, _, stderr) = symlab(&compare_args(ref_dir.to_str().unwrap(), "off"));
    assert_eq!(code, 0, "stderr: {stderr}");
    let want = rows_without_times(&std::fs::read_to_string(ref_dir.join("runs.csv")).unwrap());

    let dir = temp_dir("compare");
    let out = dir.to_str().unwrap().to_string();
    let ckpt = dir.join("checkpoint.symlab");
    let mut child = spawn(&compare_args(&out, "0"));
    wait_for(&ckpt, &mut child);
    signal(&child, libc::SIGTERM);
    let (code, stdout, stderr) = finish(child);
    assert_eq!(code, 143, "stdout: {stdout}\nstderr: {stderr}");
    assert!(stdout.contains("stopped by SIGTERM"), "{stdout}");
    assert!(
        !dir.join("runs.csv").exists(),
        "no runs.csv of a partial sweep"
    );
    let (code, stdout, stderr) = symlab(&["resume", &out]);
    assert_eq!(code, 0, "stderr: {stderr}");
    assert!(stdout.contains("rows done are not run again"), "{stdout}");
    let got = rows_without_times(&std::fs::read_to_string(dir.join("runs.csv")).unwrap());
    assert_eq!(got, want);
    assert!(!ckpt.exists());
}

fn paper_args(out: &str) -> Vec<&str> {
    vec!["paper", "--cloth-frames", "3", "--out", out]
}

/// cloth_runs.csv without its wall-time columns.
fn cloth_rows_without_times(csv: &str) -> Vec<String> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let timed: Vec<usize> = ["stepping_seconds", "ms_per_frame"]
        .iter()
        .map(|c| header.iter().position(|h| h == c).unwrap())
        .collect();
    let keep = |fields: Vec<&str>| -> String {
        fields
            .into_iter()
            .enumerate()
            .filter(|(i, _)| !timed.contains(i))
            .map(|(_, f)| f)
            .collect::<Vec<_>>()
            .join(",")
    };
    std::iter::once(keep(header.clone()))
        .chain(lines.map(|l| keep(l.split(',').collect())))
        .collect()
}

/// Every file a paper run wrote, but report.md and cloth_runs.csv (which
/// hold wall times), by name.
fn paper_files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .filter(|n| n != "report.md" && n != "cloth_runs.csv")
        .map(|n| {
            let bytes = std::fs::read(dir.join(&n)).unwrap();
            (n, bytes)
        })
        .collect();
    files.sort();
    files
}

/// A `symlab paper` run stopped by SIGTERM after a cloth run exits 143
/// with a checkpoint; `symlab resume` ends with the files of the run that
/// was never stopped (the wall times in the run table aside), and removes
/// the checkpoint. The same after SIGKILL, which leaves the checkpoint of
/// the last finished run.
#[test]
fn a_paper_run_stopped_and_resumed_writes_the_same_files() {
    let ref_dir = temp_dir("paper-ref");
    let (code, _, stderr) = symlab(&paper_args(ref_dir.to_str().unwrap()));
    assert_eq!(code, 0, "stderr: {stderr}");
    assert!(!ref_dir.join("checkpoint.symlab").exists());
    let want_files = paper_files(&ref_dir);
    assert!(want_files.len() > 10, "{} files", want_files.len());
    let want_rows =
        cloth_rows_without_times(&std::fs::read_to_string(ref_dir.join("cloth_runs.csv")).unwrap());

    for (name, sig, code_want) in [
        ("paper-term", libc::SIGTERM, 143),
        ("paper-kill", libc::SIGKILL, -1),
    ] {
        let dir = temp_dir(name);
        let out = dir.to_str().unwrap().to_string();
        let ckpt = dir.join("checkpoint.symlab");
        let mut child = spawn(&paper_args(&out));
        wait_for(&ckpt, &mut child);
        signal(&child, sig);
        let (code, stdout, stderr) = finish(child);
        assert_eq!(code, code_want, "stdout: {stdout}\nstderr: {stderr}");
        if sig == libc::SIGTERM {
            assert!(stdout.contains("stopped by SIGTERM after"), "{stdout}");
            assert!(stdout.contains("symlab resume"), "{stdout}");
        }
        assert!(ckpt.exists(), "{name}: the checkpoint is kept");
        assert!(
            !dir.join("report.md").exists(),
            "{name}: no report of a partial run"
        );
        let (code, stdout, stderr) = symlab(&["resume", &out]);
        assert_eq!(code, 0, "{name}: stdout: {stdout}\nstderr: {stderr}");
        assert!(stdout.contains("resuming the paper run"), "{stdout}");
        assert!(
            !ckpt.exists(),
            "{name}: a finished run leaves no checkpoint"
        );
        let got = paper_files(&dir);
        assert_eq!(
            got.iter().map(|(n, _)| n).collect::<Vec<_>>(),
            want_files.iter().map(|(n, _)| n).collect::<Vec<_>>(),
            "{name}"
        );
        for ((n, a), (_, b)) in got.iter().zip(&want_files) {
            assert!(a == b, "{name}: {n} differs from the uninterrupted run's");
        }
        let rows =
            cloth_rows_without_times(&std::fs::read_to_string(dir.join("cloth_runs.csv")).unwrap());
        assert_eq!(rows, want_rows, "{name}");
    }
}
