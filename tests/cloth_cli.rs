//! End-to-end tests of `symlab cloth`: the files a run writes (energy.csv
//! with its documented header, OBJ frames, PNG renderings, the energy plot)
//! and its summary; clear errors with exit code 2 for bad input; a run
//! that blows up stops with exit code 1 naming the step, time and method;
//! implicit methods and the stability search.

use std::path::{Path, PathBuf};

/// The documented header of energy.csv (README, "Cloth").
const ENERGY_HEADER: &str = "frame,step,time,kinetic,potential,total,relative_energy_error,springs,gravity,colliders,momentum_x,momentum_y,momentum_z,max_strain";

mod common;
use common::symlab;

/// A fresh directory under the system's temporary directory.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("symlab-cloth-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn is_png(path: &Path) -> bool {
    std::fs::read(path).is_ok_and(|b| b.starts_with(b"\x89PNG\r\n\x1a\n"))
}

#[test]
fn a_short_paper_run_writes_every_output_and_a_summary() {
    let dir = temp_dir("paper");
    let out = dir.to_str().unwrap();
    let (code, stdout, stderr) =
        symlab(&["cloth", "scenes/paper.toml", "--frames", "3", "--out", out]);
    assert_eq!(code, 0, "stderr: {stderr}");
    // energy.csv: the documented header and one row per frame (0..=3).
    let csv = std::fs::read_to_string(dir.join("energy.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], ENERGY_HEADER);
    assert_eq!(lines.len(), 1 + 4);
    let first: Vec<&str> = lines[1].split(',').collect();
    assert_eq!(first.len(), ENERGY_HEADER.split(',').count());
    assert_eq!(first[0], "0");
    assert_eq!(
        first[6].parse::<f64>().unwrap(),
        0.0,
        "no energy error at the start"
    );
    let last: Vec<&str> = lines[4].split(',').collect();
    assert_eq!(last[0], "3");
    assert_eq!(last[1], "768", "3 frames × 256 substeps");
    // kinetic + potential = total.
    let f = |k: usize| last[k].parse::<f64>().unwrap();
    assert!((f(3) + f(4) - f(5)).abs() <= 1e-12 * (f(3).abs() + f(4).abs()));
    // OBJ frames: every 10th (frame 0) and the last.
    let obj = std::fs::read_to_string(dir.join("frames/frame_0000.obj")).unwrap();
    assert_eq!(obj.lines().filter(|l| l.starts_with("v ")).count(), 625);
    assert_eq!(
        obj.lines().filter(|l| l.starts_with("f ")).count(),
        2 * 24 * 24
    );
    assert!(dir.join("frames/frame_0003.obj").is_file());
    assert!(!dir.join("frames/frame_0001.obj").exists());
    // Renderings of the first, middle and last frames.
    for k in [0, 1, 3] {
        let png = dir.join(format!("render_{k:04}.png"));
        assert!(is_png(&png), "{}", png.display());
    }
    // The energy plot.
    let svg = std::fs::read_to_string(dir.join("energy.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("relative energy error"));
    // The summary.
    for needle in [
        "method       symplectic-euler-a",
        "steps        768 over 3 frames",
        "h = 6.5104e-5 s",
        "wall time",
        "ms of stepping per 60 Hz frame",
        "real time",
        "max relative error",
        "max strain",
        "render_0003.png",
    ] {
        assert!(stdout.contains(needle), "missing {needle:?} in\n{stdout}");
    }
    // Not a terminal: no progress bar on stderr.
    assert!(stderr.is_empty(), "{stderr}");
    // A second run into the same directory leaves no stale frames behind.
    let (code, _, stderr) = symlab(&[
        "cloth",
        "scenes/paper.toml",
        "--frames",
        "1",
        "--out",
        out,
        "--render",
        "1",
        "--obj-every",
        "1",
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(!dir.join("frames/frame_0003.obj").exists());
    assert!(!dir.join("render_0000.png").exists());
    assert!(is_png(&dir.join("render_0001.png")));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_scenes_and_arguments_exit_2_naming_the_file_and_field() {
    let dir = temp_dir("bad");
    let scene = dir.join("bad.toml");
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper.toml"))
            .unwrap();
    std::fs::write(&scene, text.replace("density = 0.01378", "density = -1.0")).unwrap();
    let path = scene.to_str().unwrap();
    let (code, _, stderr) = symlab(&["cloth", path]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("bad.toml") && stderr.contains("material.density"),
        "{stderr}"
    );
    let (code, _, stderr) = symlab(&["cloth", "scenes/no-such-scene.toml"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("no-such-scene.toml"), "{stderr}");
    let out = dir.to_str().unwrap();
    for (args, needles) in [
        (
            vec!["--method", "verlet"],
            vec!["--method", "verlet", "stormer-verlet", "gauss2"],
        ),
        (
            vec!["--method", "lobatto3a-2"],
            vec!["--method", "lobatto3a-2", "does not step cloth"],
        ),
        (vec!["--dt", "-1"], vec!["--dt", "positive"]),
        (
            vec!["--dt", "1e-4", "--substeps", "3"],
            vec!["--dt", "--substeps"],
        ),
        (vec!["--substeps", "0"], vec!["--substeps"]),
        (vec!["--render", "1,x"], vec!["--render", "\"x\""]),
        (
            vec!["--render", "400"],
            vec!["--render", "400", "last frame"],
        ),
        (vec!["--grid", "1x9"], vec!["--grid"]),
    ] {
        let mut all = vec!["cloth", "scenes/paper.toml", "--frames", "2", "--out", out];
        all.extend(&args);
        let (code, _, stderr) = symlab(&all);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        for n in needles {
            assert!(stderr.contains(n), "{args:?}: missing {n:?} in {stderr}");
        }
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_blow_up_stops_with_exit_1_naming_step_time_and_method() {
    let dir = temp_dir("blowup");
    let out = dir.to_str().unwrap();
    let (code, _, stderr) = symlab(&[
        "cloth",
        "scenes/paper.toml",
        "--method",
        "euler",
        "--dt",
        "1e-3",
        "--frames",
        "60",
        "--out",
        out,
    ]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("Explicit Euler") && stderr.contains("blew up at step"),
        "{stderr}"
    );
    assert!(
        stderr.contains("t = ") && stderr.contains("last good frame"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"));
    // The files hold the frames before the blow-up (here only the initial
    // one: explicit Euler at 10 times its stability limit lasts 9 steps),
    // all finite and within the blow-up limit of the energy error.
    let csv = std::fs::read_to_string(dir.join("energy.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert!(!rows.is_empty() && rows.len() < 61, "{} rows", rows.len());
    assert!(!csv.contains("NaN") && !csv.contains("inf"));
    for row in &rows {
        let rel: f64 = row.split(',').nth(6).unwrap().parse().unwrap();
        assert!(rel.abs() <= 100.0, "{row}");
    }
    let last_good = rows.len() - 1;
    for entry in std::fs::read_dir(dir.join("frames")).unwrap() {
        let name = entry.unwrap().file_name().into_string().unwrap();
        let k: usize = name
            .trim_start_matches("frame_")
            .trim_end_matches(".obj")
            .parse()
            .unwrap();
        assert!(
            k <= last_good,
            "{name} after the last good frame {last_good}"
        );
        let obj = std::fs::read_to_string(dir.join("frames").join(&name)).unwrap();
        assert!(!obj.contains("NaN") && !obj.contains("inf"), "{name}");
    }
    assert!(
        dir.join(format!("frames/frame_{last_good:04}.obj"))
            .is_file()
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn implicit_methods_run_from_the_command_line() {
    let dir = temp_dir("implicit");
    let out = dir.to_str().unwrap();
    let (code, stdout, stderr) = symlab(&[
        "cloth",
        "scenes/paper.toml",
        "--grid",
        "8x8",
        "--method",
        "gauss2",
        "--dt",
        "2e-3",
        "--frames",
        "2",
        "--out",
        out,
        "--render",
        "none",
        "--obj-every",
        "0",
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("8 × 8 particles"), "{stdout}");
    assert!(
        stdout.contains("Gauss–Legendre, 2 stages") && stdout.contains("implicit, order 4"),
        "{stdout}"
    );
    assert!(
        stdout.contains("newton") && stdout.contains("(1 symbolic)"),
        "{stdout}"
    );
    assert!(stdout.contains("h = 2.0000e-3 s"), "{stdout}");
    assert!(!dir.join("frames").exists() && !dir.join("render_0000.png").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_stability_search_prints_a_table_and_writes_a_csv() {
    let dir = temp_dir("stability");
    let out = dir.to_str().unwrap();
    let (code, stdout, stderr) = symlab(&[
        "cloth",
        "scenes/paper.toml",
        "--grid",
        "6x6",
        "--stability",
        "--duration",
        "0.2",
        "--methods",
        "stormer-verlet,euler,gauss2",
        "--out",
        out,
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("2/ω_max") && stdout.contains("2/ω_bound"),
        "{stdout}"
    );
    let csv = std::fs::read_to_string(dir.join("stability.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(
        &header[..5],
        ["method", "explicit", "symplectic", "order", "h_stable"]
    );
    assert_eq!(
        &header[header.len() - 2..],
        ["name", "limit"],
        "quoted text last"
    );
    let rows: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    assert_eq!(rows.len(), 3);
    let h = |id: &str| -> Option<f64> {
        rows.iter()
            .find(|r| r[0] == id)
            .and_then(|r| r[4].parse().ok())
    };
    let h_linear: f64 = rows[0][header.iter().position(|c| *c == "h_linear").unwrap()]
        .parse()
        .unwrap();
    // Störmer–Verlet is stable up to about the linear limit 2/ω_max.
    let sv = h("stormer-verlet").expect("a stable step for Störmer–Verlet");
    assert!(
        sv > 0.5 * h_linear && sv < 2.0 * h_linear,
        "{sv} vs {h_linear}"
    );
    // Gauss–Legendre goes further.
    let g2 = h("gauss2").expect("a stable step for gauss2");
    assert!(g2 > sv, "{g2} vs {sv}");
    std::fs::remove_dir_all(&dir).unwrap();
}
