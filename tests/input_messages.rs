//! Bad input is refused with exit code 2 and a message that names what the
//! user wrote — the file and its field, the flag, the line and column of a
//! CSV — never a panic, never the name of something the user did not write
//! (the built-in "gyroscopic" problem, a flag that was not given, a derived
//! quantity).

use crate::common;

use common::symlab;
use std::path::PathBuf;

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("symlab-input-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn assert_clean(stderr: &str) {
    for bad in ["panicked", "RUST_BACKTRACE", "gyroscopic"] {
        assert!(!stderr.contains(bad), "{stderr}");
    }
}

const LINEAR: &str =
    "m = [[2.0, 0.0], [0.0, 1.0]]\nk = [[3.0, -1.0], [-1.0, 2.0]]\nq0 = [1.0, 0.0]\n";

/// Each hostile problem file: (extra lines, then flags) and the words the
/// message must contain besides the file's path.
#[test]
fn problem_file_errors_name_the_file_and_its_field() {
    let dir = temp_dir("problem-file");
    let out = dir.join("out");
    let cases: &[(&str, &[&str], &[&str])] = &[
        ("t_end = -1.0\n", &[], &["field t_end", "-1"]),
        ("t_end = 0.0\n", &[], &["field t_end", "> 0"]),
        ("t_end = nan\n", &[], &["field t_end", "NaN"]),
        ("t_end = inf\n", &[], &["field t_end", "inf"]),
        ("h_min = -1e-3\n", &[], &["field h_min"]),
        ("h_max = 0.0\n", &[], &["field h_max"]),
        ("h_max = nan\n", &[], &["field h_max"]),
        ("t_end = \"ten\"\n", &[], &["field t_end", "invalid type"]),
        ("h_min = [1.0]\n", &[], &["field h_min", "invalid type"]),
        // Refused like the flags, not clamped: both fields named.
        (
            "h_min = 0.5\nh_max = 0.1\n",
            &[],
            &["field h_min (0.5)", "field h_max (0.1)"],
        ),
        (
            "h_max = 20.0\nt_end = 10.0\n",
            &[],
            &["field h_max (20)", "field t_end (10)"],
        ),
        (
            "h_min = 0.5\n",
            &[],
            &["field h_min (0.5)", "give --h-max too"],
        ),
        (
            "t_end = 1e300\n",
            &[],
            &["field t_end", "steps per run", "give --h-min"],
        ),
        ("h_min = 1e-300\n", &[], &["field h_min", "steps per run"]),
        (
            "h_max = 1e300\n",
            &[],
            &["field h_max", "the default end time (10)"],
        ),
        // A file's field against a flag: both named.
        (
            "h_max = 0.5\n",
            &["--t-end", "0.1"],
            &["field h_max (0.5)", "--t-end (0.1)"],
        ),
        (
            "h_min = 0.05\n",
            &["--h-max", "0.01"],
            &["field h_min (0.05)", "--h-max (0.01)"],
        ),
        (
            "t_end = 1e6\nh_max = 1.0\n",
            &["--h-min", "1e-6"],
            &["--h-min", "field t_end"],
        ),
        // The matrices and the start.
        ("", &[], &[]),
    ];
    for (k, (extra, flags, want)) in cases.iter().enumerate() {
        if extra.is_empty() {
            continue;
        }
        let path = dir.join(format!("case{k}.toml"));
        std::fs::write(&path, format!("{LINEAR}{extra}")).unwrap();
        let p = path.to_str().unwrap();
        let mut args = vec!["compare", "--problem-file", p, "--quick", "--out"];
        args.push(out.to_str().unwrap());
        args.extend_from_slice(flags);
        let (code, _, stderr) = symlab(&args);
        assert_eq!(code, 2, "{extra} {flags:?}: {stderr}");
        assert!(stderr.contains(p), "{extra} {flags:?}: {stderr}");
        for w in *want {
            assert!(
                stderr.contains(w),
                "{extra} {flags:?}: want {w:?} in {stderr}"
            );
        }
        assert!(
            !stderr.contains("default smallest step 0.0001 over --t-end"),
            "{stderr}"
        );
        assert_clean(&stderr);
    }
    let whole: &[(&str, &[&str])] = &[
        ("m = [[1.0]]\nq0 = [1.0]\n", &["field k is missing"]),
        ("m = [[0.0]]\nk = [[1.0]]\nq0 = [1.0]\n", &["field m:"]),
        (
            "m = [[1.0]]\nk = [[1.0]]\ng = [[1.0]]\nq0 = [1.0]\n",
            &["field g:"],
        ),
        ("m = [[1.0]]\nk = [[1.0, 2.0]]\nq0 = [1.0]\n", &["field k:"]),
        (
            "m = [[1.0]]\nk = [[1.0]]\nf = [1.0, 2.0]\nq0 = [1.0]\n",
            &["field f:"],
        ),
        (
            "m = [[1.0]]\nk = [[1.0]]\nq0 = [1e200]\n",
            &["fields q0 and p0", "inf"],
        ),
        (
            "m = [[1.0]]\nk = [[1.0]]\nq0 = [1.0]\np0 = [1e300]\n",
            &["fields q0 and p0"],
        ),
        (
            "m = [[1.0]]\nk = [[1e308]]\nq0 = [1.0]\n",
            &["fields q0 and p0"],
        ),
        ("m = [[1.0]]\nk = [[1.0]]\nq0 = [1.0, 2.0]\n", &["field q0"]),
        (
            "m = [[1.0]]\nk = [[1.0]]\nq0 = [1.0]\nbogus = 1\n",
            &["bogus"],
        ),
    ];
    for (k, (text, want)) in whole.iter().enumerate() {
        let path = dir.join(format!("whole{k}.toml"));
        std::fs::write(&path, text).unwrap();
        let p = path.to_str().unwrap();
        let (code, _, stderr) = symlab(&[
            "compare",
            "--problem-file",
            p,
            "--quick",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{text}: {stderr}");
        assert!(stderr.contains(p), "{text}: {stderr}");
        for w in *want {
            assert!(stderr.contains(w), "{text}: want {w:?} in {stderr}");
        }
        assert_clean(&stderr);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_non_utf8_argument_names_its_flag() {
    use std::os::unix::ffi::OsStrExt;
    let bad = std::ffi::OsStr::from_bytes(b"\xff");
    let with_eq = std::ffi::OsStr::from_bytes(b"--methods=rk4\xff");
    for (args, want) in [
        (
            vec!["compare".into(), "--methods".into(), bad.to_owned()],
            "--methods",
        ),
        (vec!["compare".into(), with_eq.to_owned()], "--methods"),
        (
            vec![
                "cloth".into(),
                "scenes/paper.toml".into(),
                "--method".into(),
                bad.to_owned(),
            ],
            "--method",
        ),
        (vec!["check".into(), bad.to_owned()], "argument 2"),
    ] {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_symlab"))
            .args(&args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.contains(want) && stderr.contains("not valid UTF-8"),
            "{args:?}: {stderr}"
        );
        assert_clean(&stderr);
    }
}

#[test]
fn paper_cloth_frames_beyond_the_limit_names_the_flag() {
    let dir = temp_dir("paper");
    let (code, _, stderr) = symlab(&[
        "paper",
        "--cloth-frames",
        "1000001",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("--cloth-frames") && stderr.contains("1000000"),
        "{stderr}"
    );
    assert!(!stderr.contains("frames:"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A CSV written by `compare`, then edited: negative and non-finite times
/// and errors in ok rows are refused naming line and column.
#[test]
fn compare_from_refuses_impossible_rows_naming_line_and_column() {
    let dir = temp_dir("from");
    let header = "problem,method,order,symplectic,h,tol,steps,error,energy_error,time_s,evals,newton_iterations,fixed_point_iterations,factorizations,status";
    let good = "kepler,rk4,4,false,1e-1,NaN,100,1e-6,1e-7,1e-3,400,0,0,0,ok";
    let cases = [
        (
            "kepler,rk4,4,false,1e-1,NaN,100,1e-6,1e-7,-1e-3,400,0,0,0,ok",
            "line 3: column time_s",
        ),
        (
            "kepler,rk4,4,false,1e-1,NaN,100,-1e-6,1e-7,1e-3,400,0,0,0,ok",
            "line 3: column error",
        ),
        (
            "kepler,rk4,4,false,1e-1,NaN,100,inf,1e-7,1e-3,400,0,0,0,ok",
            "line 3: column error",
        ),
        (
            "kepler,rk4,4,false,1e-1,NaN,100,NaN,1e-7,1e-3,400,0,0,0,ok",
            "line 3: column error",
        ),
        (
            "kepler,rk4,4,false,1e-1,NaN,100,1e-6,1e-7,NaN,400,0,0,0,ok",
            "line 3: column time_s",
        ),
        (
            "kepler,rk4,4,false,-1e-1,NaN,100,1e-6,1e-7,1e-3,400,0,0,0,ok",
            "line 3: column h",
        ),
        (
            "kepler,rk4,4,false,1e-1,NaN,-100,1e-6,1e-7,1e-3,400,0,0,0,ok",
            "line 3: column steps",
        ),
    ];
    for (k, (row, want)) in cases.iter().enumerate() {
        let path = dir.join(format!("runs{k}.csv"));
        std::fs::write(&path, format!("{header}\n{good}\n{row}\n")).unwrap();
        let p = path.to_str().unwrap();
        let (code, _, stderr) = symlab(&["compare", "--from", p]);
        assert_eq!(code, 2, "{row}: {stderr}");
        assert!(
            stderr.contains(p) && stderr.contains(want),
            "{row}: {stderr}"
        );
        assert_clean(&stderr);
    }
    // Failed rows carry NaN (documented): accepted.
    let path = dir.join("failed.csv");
    std::fs::write(
        &path,
        format!("{header}\n{good}\nkepler,euler,1,false,1e-1,NaN,100,NaN,inf,NaN,100,0,0,0,\"diverged at step 4\"\n"),
    )
    .unwrap();
    let (code, _, stderr) = symlab(&["compare", "--from", path.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A scene edited to one hostile value: the error names the field written.
fn paper_scene_with(dir: &std::path::Path, name: &str, from: &str, to: &str) -> String {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/paper.toml")).unwrap();
    assert!(text.contains(from), "{from}");
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path.to_str().unwrap().to_string()
}

#[test]
fn scene_fields_with_extreme_values_are_blamed_on_the_field_written() {
    let dir = temp_dir("scenes");
    let out = dir.join("out");
    let origin = "origin = [0.0, 0.0, 0.0]";
    let shear = "shear = 50.75 ";
    let cases = [
        ("width = 1.0", "width = 1e-300", "cloth.width"),
        ("width = 1.0", "width = 1e-200", "cloth.width"),
        ("height = 1.0", "height = 1e308", "cloth.height"),
        (
            origin,
            "origin = [0.0, 0.0, 0.0]\nprestretch = 1e308",
            "cloth.prestretch",
        ),
        (
            origin,
            "origin = [0.0, 0.0, 0.0]\nprestretch = 1e-300",
            "cloth.prestretch",
        ),
        (origin, "origin = [1e300, 0.0, 0.0]", "cloth.origin"),
        ("density = 0.01378", "density = 1e308", "material.density"),
        ("density = 0.01378", "density = 1e-306", "material.density"),
        (shear, "shear = 50.75\nbend = 1e308 ", "material.bend"),
        ("stretch = 50.75", "stretch = 1e308", "material.stretch"),
    ];
    for (k, (from, to, field)) in cases.iter().enumerate() {
        let path = paper_scene_with(&dir, &format!("s{k}"), from, to);
        let (code, _, stderr) = symlab(&[
            "cloth",
            &path,
            "--frames",
            "1",
            "--render",
            "none",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{to}: {stderr}");
        assert!(
            stderr.contains(&format!("{path}: {field}:")),
            "{to}: want {field} in {stderr}"
        );
        assert_clean(&stderr);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cloth_stability_honours_solver_and_refuses_energy_schemes_on_colliders() {
    let dir = temp_dir("stability");
    let out = dir.to_str().unwrap();
    // A normal run and --stability refuse avf on a scene with colliders with
    // the same reason.
    let (code, _, run_err) = symlab(&[
        "cloth",
        "scenes/sphere.toml",
        "--method",
        "avf",
        "--frames",
        "1",
        "--out",
        out,
    ]);
    assert_eq!(code, 2, "{run_err}");
    assert!(
        run_err.contains("--method avf: avf handles springs and gravity"),
        "{run_err}"
    );
    let (code, _, stab_err) = symlab(&[
        "cloth",
        "scenes/sphere.toml",
        "--stability",
        "--methods",
        "discrete-gradient",
        "--out",
        out,
    ]);
    assert_eq!(code, 2, "{stab_err}");
    assert!(
        stab_err
            .contains("--methods discrete-gradient: discrete-gradient handles springs and gravity")
            && stab_err.contains("this scene has colliders"),
        "{stab_err}"
    );
    // --solver: local-global on colliders refused in both; a solver for
    // methods that are no minimisation refused, not ignored.
    let (code, _, err) = symlab(&[
        "cloth",
        "scenes/sphere.toml",
        "--stability",
        "--methods",
        "midpoint",
        "--solver",
        "local-global",
        "--out",
        out,
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--solver local-global") && err.contains("colliders"),
        "{err}"
    );
    let (code, _, err) = symlab(&[
        "cloth",
        "scenes/paper.toml",
        "--stability",
        "--methods",
        "rk4",
        "--solver",
        "local-global",
        "--out",
        out,
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--solver local-global") && err.contains("rk4"),
        "{err}"
    );
    let (code, _, err) = symlab(&[
        "cloth",
        "scenes/paper.toml",
        "--method",
        "rk4",
        "--solver",
        "newton",
        "--frames",
        "1",
        "--out",
        out,
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--solver newton"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_run_tolerance_that_cannot_mean_anything_is_refused() {
    let dir = temp_dir("tolerance");
    for t in ["1e-300", "5e-324", "1e300", "2"] {
        let (code, _, err) = symlab(&[
            "cloth",
            "scenes/paper.toml",
            "--method",
            "midpoint",
            "--tolerance",
            t,
            "--frames",
            "1",
            "--out",
            dir.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{t}: {err}");
        assert!(
            err.contains("--tolerance: must be between 1e-15 and 1"),
            "{t}: {err}"
        );
        assert_clean(&err);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A `SYMLAB_SIMD` that names no level is refused before anything runs,
/// exit 2, naming the variable and its value; a valid one is taken.
#[test]
fn a_bad_simd_cap_is_refused_by_name() {
    let run = |value: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_symlab"))
            .args(["list"])
            .env("SYMLAB_SIMD", value)
            .output()
            .expect("symlab runs")
    };
    let bad = run("avx3");
    assert_eq!(bad.status.code(), Some(2));
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(
        err.contains("SYMLAB_SIMD=\"avx3\" is not a SIMD level"),
        "{err}"
    );
    assert!(bad.stdout.is_empty());
    for good in ["portable", "AVX2", "avx512", ""] {
        assert_eq!(run(good).status.code(), Some(0), "SYMLAB_SIMD={good:?}");
    }
}
