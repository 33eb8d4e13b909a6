//! End-to-end tests of `symlab cloth`: the files a run writes (energy.csv
//! with its documented header, OBJ frames, PNG renderings, the energy plot)
//! and its summary; clear errors with exit code 2 for bad input; a run
//! that blows up stops with exit code 1 naming the step, time and method;
//! implicit methods and the stability search.

use std::path::{Path, PathBuf};

/// The documented header of energy.csv (guide/src/cloth.md).
const ENERGY_HEADER: &str = "frame,step,time,kinetic,potential,total,relative_energy_error,springs,gravity,colliders,momentum_x,momentum_y,momentum_z,max_strain";

use crate::common;
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
            vec!["--method", "lobatto3a-22"],
            vec!["--method", "lobatto3a-22", "unknown method", "lobatto3a-2"],
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

// ---- Hostile, huge and long input (issue 13) ----

/// The paper scene with each `(from, to)` replaced, written to `dir/name`.
fn paper_variant(dir: &Path, name: &str, edits: &[(&str, &str)]) -> String {
    let mut text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper.toml"))
            .unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{from}");
        text = text.replacen(from, to, 1);
    }
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// Run `symlab ARGS`, timed: (exit code, stdout, stderr, seconds).
fn timed(args: &[&str]) -> (i32, String, String, f64) {
    let clock = std::time::Instant::now();
    let (code, stdout, stderr) = symlab(args);
    (code, stdout, stderr, clock.elapsed().as_secs_f64())
}

fn assert_clean(stderr: &str) {
    for bad in ["panicked", "memory allocation", "unexpected argument"] {
        assert!(!stderr.contains(bad), "{bad:?} in {stderr}");
    }
}

#[test]
fn scenes_with_a_non_finite_start_are_errors_naming_file_and_field_not_panics() {
    let dir = temp_dir("nonfinite");
    let out = dir.to_str().unwrap();
    let sphere = "[[colliders]]\ntype = \"sphere\"\ncenter = [0.5, -1.0, 0.5]\nstiffness = 1e4\n";
    for (name, edits, field) in [
        (
            "wide.toml",
            vec![("width = 1.0", "width = 1e308")],
            "cloth.width",
        ),
        (
            "stiff.toml",
            vec![("stretch = 50.75", "stretch = 1e308")],
            "material.stretch",
        ),
        (
            "tiny.toml",
            vec![
                ("width = 1.0", "width = 1e-300"),
                ("height = 1.0", "height = 1e-300"),
            ],
            "cloth.width",
        ),
        (
            "ball.toml",
            vec![(
                "[simulation]",
                &format!("{sphere}radius = 1e308\n\n[simulation]"),
            )],
            "colliders[0].radius",
        ),
        (
            "deep.toml",
            vec![(
                "[simulation]",
                "[[colliders]]\ntype = \"sphere\"\ncenter = [0.5, -1.0, 0.5]\nstiffness = 1e300\nradius = 1e150\n\n[simulation]",
            )],
            "colliders[0]",
        ),
        (
            "rate.toml",
            vec![("frame_rate = 60.0", "frame_rate = 1e308")],
            "simulation.frame_rate",
        ),
        (
            "tall.toml",
            vec![("ny = 25", "ny = 100000000000")],
            "cloth.ny",
        ),
        (
            "long.toml",
            vec![("frames = 300", "frames = 9223372036854775807")],
            "simulation.frames",
        ),
    ] {
        let path = paper_variant(&dir, name, &edits);
        let (code, _, stderr, secs) = timed(&["cloth", &path, "--frames", "3", "--out", out]);
        assert_eq!(code, 2, "{name}: {stderr}");
        assert!(
            stderr.contains(name) && stderr.contains(&format!("{field}:")),
            "{name}: expected {field} in {stderr}"
        );
        assert_clean(&stderr);
        assert!(secs < 10.0, "{name}: {secs} s");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_flag_values_name_the_flag() {
    let dir = temp_dir("flags");
    let out = dir.to_str().unwrap();
    let max = u64::MAX.to_string();
    let beyond = "18446744073709551616";
    for (args, flag) in [
        (vec!["--frames", "-1"], "--frames"),
        (vec!["--substeps", "-1"], "--substeps"),
        (vec!["--obj-every", "-1"], "--obj-every"),
        (vec!["--frames", "1.5"], "--frames"),
        (vec!["--frames", beyond], "--frames"),
        (vec!["--render", "-1"], "--render"),
        (vec!["--grid", "-1x2"], "--grid"),
        (vec!["--dt", "-inf"], "--dt"),
        (vec!["--stability", "--tolerance", "-1"], "--tolerance"),
        (vec!["--stability", "--tolerance", "1e-300"], "--tolerance"),
        (
            vec!["--stability", "--tolerance", "1e300"],
            "--tolerance: must be at most 100",
        ),
        (vec!["--stability", "--duration", "-1"], "--duration"),
        // Long runs: refused before the run, naming the flag.
        (vec!["--dt", "1e-12"], "--dt"),
        (vec!["--dt", "1e-300"], "--dt"),
        (vec!["--substeps", &max], "--substeps"),
        (vec!["--frames", &max], "--frames"),
        (vec!["--frames", "1000001", "--substeps", "1"], "--frames"),
        (vec!["--frames", "100000", "--substeps", "100000"], "--"),
        (vec!["--stability", "--duration", "1e-300"], "--duration"),
        (vec!["--stability", "--duration", "1e300"], "--duration"),
        // Huge grids: refused before anything is built.
        (vec!["--grid", "100000000x2"], "--grid"),
        (vec!["--grid", "2x100000000"], "--grid"),
        (vec!["--grid", "99999999999999999999x2"], "--grid"),
        (
            vec!["--grid", "512x512", "--method", "gauss2"],
            "--method gauss2",
        ),
    ] {
        let mut all = vec!["cloth", "scenes/paper.toml", "--out", out];
        all.extend(&args);
        let (code, _, stderr, secs) = timed(&all);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(
            stderr.contains(flag),
            "{args:?}: {flag} not named in {stderr}"
        );
        assert_clean(&stderr);
        assert!(secs < 10.0, "{args:?}: {secs} s");
    }
    // The step limit is in the message, as documented.
    let (_, _, stderr) = symlab(&["cloth", "scenes/paper.toml", "--dt", "1e-12", "--out", out]);
    assert!(stderr.contains("1000000000 steps"), "{stderr}");
    let (_, _, stderr) = symlab(&[
        "cloth",
        "scenes/paper.toml",
        "--grid",
        "3000x3000",
        "--out",
        out,
    ]);
    assert!(stderr.contains("4194304 particles"), "{stderr}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_explicit_2048_squared_run_fits_in_4_gb() {
    // The sparse Jacobian layout (8 GB here) is only for implicit methods.
    // One step of 1/60 s is far beyond the stability limit at this
    // resolution, so the run stops at step 1 (exit 1) — what matters is
    // that it starts, steps and stops within the memory limit.
    let dir = temp_dir("huge");
    let out = dir.to_str().unwrap();
    let args = [
        "cloth",
        "scenes/paper.toml",
        "--grid",
        "2048x2048",
        "--frames",
        "1",
        "--substeps",
        "1",
        "--render",
        "none",
        "--obj-every",
        "0",
        "--out",
        out,
    ];
    let limited = std::process::Command::new("prlimit")
        .arg("--as=4000000000")
        .arg(env!("CARGO_BIN_EXE_symlab"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output();
    let (code, stderr) = match limited {
        Ok(o) => (
            o.status.code().unwrap_or(-1),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        ),
        // No prlimit here: without the limit, still no abort.
        Err(_) => {
            let (code, _, stderr) = symlab(&args);
            (code, stderr)
        }
    };
    assert!(code == 0 || code == 1, "exit {code}: {stderr}");
    assert!(
        code == 0 || stderr.contains("blew up at step 1"),
        "{stderr}"
    );
    assert_clean(&stderr);
    assert!(!dir.join("render_0000.png").exists(), "--render none");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_degenerate_grid_renders_in_time_proportional_to_the_image() {
    let dir = temp_dir("sliver");
    let out = dir.to_str().unwrap();
    let (code, stdout, stderr, secs) = timed(&[
        "cloth",
        "scenes/paper.toml",
        "--grid",
        "100000x2",
        "--frames",
        "0",
        "--obj-every",
        "0",
        "--out",
        out,
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(is_png(&dir.join("render_0000.png")), "{stdout}");
    assert!(secs < 20.0, "{secs} s");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_cloth_at_rest_without_gravity_or_pins_does_not_blow_up() {
    // H₀ is round-off (1e-31 J); E_ref has the elastic floor, so round-off
    // is not divided by round-off.
    let dir = temp_dir("rest");
    let out = dir.to_str().unwrap();
    let path = paper_variant(
        &dir,
        "rest.toml",
        &[
            ("gravity = [0.0, -9.81, 0.0]", ""),
            ("edges = [\"top\"]", ""),
        ],
    );
    let (code, stdout, stderr) = symlab(&["cloth", &path, "--frames", "5", "--out", out]);
    assert_eq!(code, 0, "{stderr}");
    let line = stdout
        .lines()
        .find(|l| l.contains("max relative error"))
        .unwrap();
    let worst: f64 = line
        .split("max relative error ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(worst < 1e-12, "{line}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_run_that_blows_up_with_render_none_renders_nothing() {
    let dir = temp_dir("blowup-none");
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
        "--render",
        "none",
        "--out",
        out,
    ]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("blew up at step"), "{stderr}");
    let pngs = std::fs::read_dir(&dir)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .ends_with(".png")
        })
        .count();
    assert_eq!(pngs, 0);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
#[cfg_attr(not(unix), ignore = "reads /dev/zero, which only Unix has")]
fn an_endless_scene_file_is_read_up_to_a_limit() {
    let (code, _, stderr, secs) = timed(&["cloth", "/dev/zero"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("/dev/zero") && stderr.contains("16 MiB"),
        "{stderr}"
    );
    assert!(secs < 10.0, "{secs} s");
}

#[test]
fn a_run_whose_energy_overflows_stops_naming_the_step_in_words() {
    // Gravity of 1e200 m/s²: finite scales at the start, the energy
    // overflows within a step or two.
    let dir = temp_dir("overflow");
    let out = dir.to_str().unwrap();
    let path = paper_variant(
        &dir,
        "heavy.toml",
        &[(
            "gravity = [0.0, -9.81, 0.0]",
            "gravity = [0.0, -1e200, 0.0]",
        )],
    );
    let (code, _, stderr) = symlab(&["cloth", &path, "--frames", "3", "--out", out]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("blew up at step"), "{stderr}");
    assert!(!stderr.contains("NaN"), "{stderr}");
    assert_clean(&stderr);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The midpoint family through the minimisation solvers at one step per
/// frame (a small grid, a few frames: CI), with the solver line in the
/// summary; bad `--solver`, `--tolerance` and `--dt` exit 2 naming the flag.
#[test]
fn the_midpoint_family_runs_as_minimisation_and_bad_solver_flags_name_the_flag() {
    let dir = temp_dir("minimise");
    let out = dir.to_str().unwrap();
    for (method, solver) in [
        ("midpoint", "newton"),
        ("paper-dirk2", "newton"),
        ("midpoint", "local-global"),
        ("avf", "newton"),
    ] {
        let (code, stdout, stderr) = symlab(&[
            "cloth",
            "scenes/paper.toml",
            "--grid",
            "8x8",
            "--method",
            method,
            "--solver",
            solver,
            "--dt",
            "0.0166667",
            "--frames",
            "3",
            "--out",
            out,
            "--render",
            "none",
            "--obj-every",
            "0",
        ]);
        assert_eq!(code, 0, "{method} {solver}: {stderr}");
        assert!(
            stdout.contains(&format!(
                "solver       {solver} minimisation, tolerance 1e-12"
            )) && stdout.contains("iterations per step")
                && stdout.contains("(1 symbolic, "),
            "{stdout}"
        );
        assert!(stdout.contains("(1 per frame at"), "{stdout}");
    }
    for (args, flag) in [
        (
            vec!["--method", "midpoint", "--solver", "bogus"],
            "--solver",
        ),
        (
            vec!["--method", "midpoint", "--tolerance", "0"],
            "--tolerance",
        ),
        (
            vec!["--method", "midpoint", "--tolerance", "-1e-3"],
            "--tolerance",
        ),
        (vec!["--method", "midpoint", "--dt", "abc"], "--dt"),
    ] {
        let mut full = vec!["cloth", "scenes/paper.toml", "--frames", "1", "--out", out];
        full.extend(args.iter().copied());
        let (code, _, stderr) = symlab(&full);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stderr.contains(flag), "{args:?}: {stderr}");
        assert_clean(&stderr);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The issue's question, answered by the command itself: at one step per
/// 60 Hz frame on the paper scene the implicit midpoint rule's energy grows
/// exponentially (the steps converge; the method is unstable at this step),
/// and the run says so with the fitted growth before the failure; symplectic
/// Euler at its substeps stays bounded, and its summary says that too.
#[test]
fn the_energy_growth_is_fitted_and_reported_not_hidden() {
    let dir = temp_dir("growth");
    let out = dir.to_str().unwrap();
    let (code, _, stderr) = symlab(&[
        "cloth",
        "scenes/paper.toml",
        "--method",
        "midpoint",
        "--dt",
        "0.0166667",
        "--frames",
        "60",
        "--out",
        out,
        "--render",
        "none",
        "--obj-every",
        "0",
    ]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("grows exponentially") && stderr.contains("not energy-stable"),
        "{stderr}"
    );
    assert_clean(&stderr);
    let (code, stdout, stderr) = symlab(&[
        "cloth",
        "scenes/paper.toml",
        "--frames",
        "60",
        "--out",
        out,
        "--render",
        "none",
        "--obj-every",
        "0",
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("growth       max |H − H₀|/E_ref per quarter")
            && stdout.contains("bounded"),
        "{stdout}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A 4 × 4 sheet pinned along its top edge under gravity, no colliders (so
/// that the energy schemes take it), at 1200 steps per second: small enough
/// for every solver, well within every explicit scheme's stability limit.
const SMALL_SHEET: &str = r#"
name = "small"
gravity = [0.0, -9.81, 0.0]

[cloth]
width = 0.3
height = 0.3
nx = 4
ny = 4
plane = "vertical"

[material]
density = 0.1
stretch = 10.0
shear = 2.0

[pins]
edges = ["top"]

[simulation]
substeps = 20
frames = 2
method = "leapfrog"
"#;

/// Every method id that `symlab list` lists, and the energy schemes, runs a
/// few frames of a small scene through the one loop, and the summary names
/// its kind (explicit or implicit, and for an implicit one how it is
/// solved) and its order, the facts taken from the library independently
/// of the cloth crate.
#[test]
fn every_listed_method_and_energy_scheme_runs_and_the_summary_names_kind_and_order() {
    let dir = temp_dir("every-method");
    let scene = dir.join("small.toml");
    std::fs::write(&scene, SMALL_SHEET).unwrap();
    let (code, list, stderr) = symlab(&["list", "--json"]);
    assert_eq!(code, 0, "{stderr}");
    let rows: Vec<serde_json::Value> = serde_json::from_str(&list).unwrap();
    // Every library scheme; the processed methods (a kernel with a
    // corrector, `wh:ID` in the comparisons) are not cloth methods.
    let mut ids: Vec<String> = rows
        .iter()
        .filter(|r| r["processed"] == false)
        .map(|r| r["id"].as_str().unwrap().to_string())
        .collect();
    assert!(ids.len() >= 50, "{} ids", ids.len());
    assert!(rows.iter().all(|r| r["processed"].is_boolean()));
    ids.extend(["avf", "discrete-gradient"].map(String::from));
    let out = dir.join("out");
    let mut failures = Vec::new();
    for id in &ids {
        let (kind, order, how) = match integrator_core::library::info(id) {
            Some(i) if i.explicit => ("explicit", i.order, None),
            Some(i) if i.midpoint_weights.is_some() => {
                ("implicit", i.order, Some("(energy minimisation)"))
            }
            Some(i) => ("implicit", i.order, Some("(sparse stage solver)")),
            None if id == "avf" => ("implicit", 2, Some("(energy minimisation)")),
            None => ("implicit", 2, Some("(discrete gradient (Newton))")),
        };
        let (code, stdout, stderr) = symlab(&[
            "cloth",
            scene.to_str().unwrap(),
            "--method",
            id,
            "--out",
            out.to_str().unwrap(),
            "--render",
            "none",
            "--obj-every",
            "0",
        ]);
        let line = stdout
            .lines()
            .find(|l| l.trim_start().starts_with("method"))
            .unwrap_or("")
            .to_string();
        let facts = format!("— {kind}, order {order}, ");
        if code != 0 || !line.contains(&facts) || how.is_some_and(|h| !line.ends_with(h)) {
            failures.push(format!("{id}: exit {code}, method line {line:?}, {stderr}"));
        }
        if code == 0 {
            assert!(
                stdout.contains("steps        40 over 2 frames"),
                "{id}: {stdout}"
            );
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The inextensible sheet (warp and weft as length constraints) runs with
/// RATTLE and says so: the method with its kind and order, the constraints,
/// and what the constraint solver did.
#[test]
fn the_inextensible_scene_runs_with_rattle_and_names_it() {
    let dir = temp_dir("inextensible");
    let out = dir.to_str().unwrap();
    let (code, stdout, stderr) = symlab(&[
        "cloth",
        "scenes/paper64-inextensible.toml",
        "--frames",
        "3",
        "--out",
        out,
        "--render",
        "none",
    ]);
    assert_eq!(code, 0, "stderr: {stderr}");
    for needle in [
        "method       rattle (RATTLE",
        "implicit, order 2, symplectic (constraint solve",
        "8001 length constraints (warp and weft, inextensible)",
        "tension waves: ℓ/√(|g|·L)",
        "constraints  RATTLE:",
        "time split   forces",
        "steps        21 over 3 frames",
    ] {
        assert!(stdout.contains(needle), "missing {needle:?} in\n{stdout}");
    }
    // A spring method on it, and rattle on a spring scene: refused, naming
    // what to use.
    // A method that does not fit the model is refused, naming what fits.
    for (scene, method, needle) in [
        (
            "scenes/paper64-inextensible.toml",
            "stormer-verlet",
            "rattle",
        ),
        ("scenes/paper.toml", "rattle", "inextensible"),
    ] {
        let (code, _, stderr) = symlab(&[
            "cloth", scene, "--frames", "1", "--out", out, "--method", method,
        ]);
        assert_ne!(code, 0, "{scene} --method {method}");
        assert!(stderr.contains(needle), "{stderr}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_equal_stretch_study_prints_both_models_and_writes_a_csv() {
    let dir = temp_dir("equal-stretch");
    let out = dir.to_str().unwrap();
    let (code, stdout, stderr) = symlab(&[
        "cloth",
        "scenes/paper64-inextensible.toml",
        "--equal-stretch",
        "--grid",
        "6x6",
        "--frames",
        "20",
        "--out",
        out,
    ]);
    assert_eq!(code, 0, "{stderr}");
    for model in [
        "springs, 1 thread",
        "RATTLE, no bending",
        "RATTLE, bending 3e-6 N·m",
        "← taken",
    ] {
        assert!(stdout.contains(model), "{model}: {stdout}");
    }
    let csv = std::fs::read_to_string(dir.join("equal_stretch.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert!(lines[0].starts_with("model,method,stiffness_n,"), "{csv}");
    assert_eq!(lines.len(), 1 + 3, "{csv}");
    // The springs' stretch, measured at every step, within 1 %.
    let header: Vec<&str> = lines[0].split(',').collect();
    let col = header.iter().position(|h| *h == "max_stretch").unwrap();
    let springs: Vec<&str> = lines[1].split(',').collect();
    let stretch: f64 = springs[col].parse().unwrap();
    assert!(stretch > 0.0 && stretch <= 0.01, "{stretch}");
    std::fs::remove_dir_all(&dir).unwrap();

    // Flags that mean nothing to the study are refused, naming them; so is
    // a spring scene, naming its field.
    let (code, _, stderr) = symlab(&[
        "cloth",
        "scenes/paper64-inextensible.toml",
        "--equal-stretch",
        "--method",
        "stormer-verlet",
    ]);
    assert_eq!(code, 2);
    assert!(stderr.contains("--method"), "{stderr}");
    let (code, _, stderr) = symlab(&["cloth", "scenes/paper.toml", "--equal-stretch"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("material.stretch"), "{stderr}");
}
