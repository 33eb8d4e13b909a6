//! REBOUND as a peer (`rebound:NAME`): the exact round trip of the initial
//! state, REBOUND's leapfrog against ours, a sweep with REBOUND's rows, the
//! sweep without REBOUND (the install command, the other rows), and the
//! errors for bad names.
//!
//! REBOUND is not a dependency, so the tests that run it are `#[ignore]`d
//! with the reason; `scripts/test` (the README's test command, which CI
//! runs) installs `rebound==5.2.2` into its `.venv` and runs them with
//! `SYMLAB_PYTHON` pointing there: `cargo test -p compare --test
//! rebound_peer -- --ignored`. Run so, they fail where REBOUND does not
//! answer; none of them passes without running.

use std::path::{Path, PathBuf};

use compare::builtin;
use compare::rebound::{self, Bodies, Point, ReboundMethod};
use compare::{Method, Problem, Setup, SweepSettings, work_precision};
use integrator_core::problems::{HenonHeiles, Kepler};

/// REBOUND must answer: these tests are run on purpose (`--ignored`).
fn require_rebound() {
    if let Err(why) = rebound::probe(&rebound::python()) {
        panic!(
            "{why}\nThis test needs REBOUND: run scripts/test, or `{}` and set SYMLAB_PYTHON to that interpreter",
            rebound::INSTALL
        );
    }
}

fn bodies<P: Problem>(setup: &Setup<P>) -> Bodies {
    setup.sys.rebound_bodies(&setup.z0).unwrap().unwrap()
}

fn rebound_method<P: Problem>(id: &str, setup: &Setup<P>) -> ReboundMethod {
    match setup.method(id).unwrap() {
        Method::Rebound(r) => r,
        _ => panic!("{id} is not a REBOUND method"),
    }
}

#[test]
#[ignore = "needs REBOUND 5.2.2 under $SYMLAB_PYTHON; scripts/test installs it into .venv and runs these"]
fn the_initial_state_reaches_rebound_and_comes_back_bit_for_bit() {
    require_rebound();
    let outer = builtin::outer_solar(1e5, false).unwrap();
    let b = bodies(&outer);
    // The velocities REBOUND is given are HLW's, and m·v gives back our p.
    assert_eq!(
        b.velocities[1],
        integrator_core::problems::outer_solar::VELOCITIES[1]
    );
    let back = rebound::echo(&rebound::python(), &b).unwrap();
    let bits = |z: &[f64]| z.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&back), bits(&outer.z0));
    let kepler = builtin::kepler(true, 1.0, false).unwrap();
    let back = rebound::echo(&rebound::python(), &bodies(&kepler)).unwrap();
    assert_eq!(bits(&back), bits(&kepler.z0));
}

/// Our leapfrog (drift–kick–drift) and REBOUND's (the same sequence) on
/// the same problem, at several step counts.
fn leapfrog_pair<P: Problem>(setup: &Setup<P>, steps: &[u64]) -> Vec<(u64, f64, f64)> {
    let ours = match setup.method("leapfrog").unwrap() {
        Method::Fixed(f) => f,
        _ => unreachable!(),
    };
    let theirs = rebound_method("rebound:leapfrog", setup);
    steps
        .iter()
        .map(|&n| {
            let a = compare::sweep::fixed_run(setup, &ours, n, 1);
            let b = rebound::row(setup, &theirs, Point::Steps(n), 1.0, 1);
            assert!(a.ok() && b.ok(), "{} / {}", a.status, b.status);
            assert_eq!(b.steps, n);
            println!(
                "{} n = {n}: ours {:.6e}, REBOUND {:.6e}",
                setup.name, a.error, b.error
            );
            (n, a.error, b.error)
        })
        .collect()
}

#[test]
#[ignore = "needs REBOUND 5.2.2 under $SYMLAB_PYTHON; scripts/test installs it into .venv and runs these"]
fn rebound_leapfrog_and_ours_agree_to_round_off() {
    require_rebound();
    // Kepler e = 0.6 over 10 orbits: the same error at every step count to
    // many digits (the two differ only in the rounding of the force).
    let kepler = builtin::kepler(false, 20.0 * std::f64::consts::PI, true).unwrap();
    for (n, ours, theirs) in leapfrog_pair(&kepler, &[200, 1000, 5000]) {
        assert!(
            (ours - theirs).abs() <= 1e-6 * ours,
            "kepler n = {n}: {ours} vs {theirs}"
        );
    }
    // The outer solar system over 10⁵ days: REBOUND steps velocities, we
    // step momenta p = m v; the same method, rounded differently.
    let outer = builtin::outer_solar(1e5, true).unwrap();
    for (n, ours, theirs) in leapfrog_pair(&outer, &[500, 2000, 10000]) {
        assert!(
            (ours - theirs).abs() <= 1e-6 * ours,
            "outer-solar n = {n}: {ours} vs {theirs}"
        );
    }
}

#[test]
#[ignore = "needs REBOUND 5.2.2 under $SYMLAB_PYTHON; scripts/test installs it into .venv and runs these"]
fn a_sweep_runs_rebound_beside_ours_and_reports_it() {
    require_rebound();
    let setup = builtin::outer_solar(1e5, true).unwrap();
    let methods: Vec<Method<_>> = ["leapfrog", "rebound:whfast", "rebound:ias15"]
        .iter()
        .map(|id| setup.method(id).unwrap())
        .collect();
    let mut settings = SweepSettings::new(setup.sys.defaults(), setup.t_end);
    settings.h_min = 50.0;
    settings.h_max = 200.0;
    settings.points = 3;
    settings.repeats = 1;
    let result = work_precision(&setup, &methods, &settings).unwrap();
    assert!(result.notes.is_empty(), "{:?}", result.notes);
    assert_eq!(result.rebound.as_deref(), Some(rebound::VERSION));
    let whfast: Vec<_> = result
        .rows
        .iter()
        .filter(|r| r.method == "rebound:whfast")
        .collect();
    assert_eq!(whfast.len(), 3);
    for r in &whfast {
        assert!(r.ok(), "{}", r.status);
        assert_eq!(r.family, compare::Family::Rebound);
        assert!(r.time_s > 0.0 && r.energy_error > 0.0);
    }
    // Second order in h: four times the steps, about a sixteenth of the
    // error (Wisdom–Holman's error is that of the interaction, O(εh²)).
    let ratio = whfast[0].error / whfast[2].error;
    assert!((8.0..32.0).contains(&ratio), "{ratio}");
    // At the same step Wisdom–Holman beats leapfrog by far on this problem.
    let lf = result
        .rows
        .iter()
        .find(|r| r.method == "leapfrog" && r.steps == whfast[2].steps)
        .unwrap();
    assert!(
        whfast[2].error < 1e-2 * lf.error,
        "{} {}",
        whfast[2].error,
        lf.error
    );
    let ias15: Vec<_> = result
        .rows
        .iter()
        .filter(|r| r.method == "rebound:ias15")
        .collect();
    assert_eq!(ias15.len(), 10);
    assert!(ias15.iter().all(|r| r.ok() && r.tol > 0.0 && r.steps > 0));
    let report = result.report();
    assert!(report.contains("REBOUND 5.2.2"), "{report}");
    assert!(report.contains("## REBOUND against our fastest method"));
    let summary = result.summary();
    assert!(summary.contains("ours / REBOUND"), "{summary}");
}

/// On a CPU with AVX-512, WHFast512 runs and matches WHFast; on one
/// without, the probe says so and a sweep leaves it out with that note
/// while the rest runs. Either way the test checks what this machine has.
#[test]
#[ignore = "needs REBOUND 5.2.2 under $SYMLAB_PYTHON; scripts/test installs it into .venv and runs these"]
fn whfast512_runs_where_the_cpu_has_avx512_and_is_left_out_with_a_note_elsewhere() {
    require_rebound();
    let python = rebound::python();
    let setup = builtin::outer_solar(1e5, true).unwrap();
    let w512 = rebound_method("rebound:whfast512", &setup);
    if !rebound::cpu_has_avx512() {
        println!("whfast512: this CPU has no AVX-512F: checking that it is left out with a note");
        let why = rebound::probe_whfast512(&python).unwrap_err();
        assert!(why.contains("AVX-512"), "{why}");
        let methods = vec![setup.method("leapfrog").unwrap(), Method::Rebound(w512)];
        let mut settings = SweepSettings::new(setup.sys.defaults(), setup.t_end);
        settings.points = 2;
        settings.repeats = 1;
        let result = work_precision(&setup, &methods, &settings).unwrap();
        assert_eq!(result.methods, vec!["leapfrog".to_string()]);
        let notes = result.notes.join("\n");
        assert!(
            notes.contains("rebound:whfast512") && notes.contains("AVX-512"),
            "{notes}"
        );
        return;
    }
    println!("whfast512: this CPU has AVX-512F: running it beside WHFast");
    rebound::probe_whfast512(&python).unwrap();
    let whfast = rebound_method("rebound:whfast", &setup);
    for n in [1000, 4000] {
        let a = rebound::row(&setup, &w512, Point::Steps(n), 1.0, 1);
        let b = rebound::row(&setup, &whfast, Point::Steps(n), 1.0, 1);
        assert!(a.ok() && b.ok(), "{} / {}", a.status, b.status);
        println!("n = {n}: whfast512 {:.6e}, whfast {:.6e}", a.error, b.error);
        // The same method in the same coordinates, vectorised.
        assert!((a.error - b.error).abs() <= 1e-3 * b.error);
    }
}

/// A Python that starts but has no `rebound`: the interpreter without its
/// site-packages (`-S`), behind a wrapper script.
fn python_without_rebound(dir: &Path) -> Option<PathBuf> {
    let real = rebound::python();
    let ok = std::process::Command::new(&real)
        .args(["-S", "-c", "import json"])
        .status()
        .is_ok_and(|s| s.success());
    if !ok {
        return None;
    }
    let path = dir.join("python-without-rebound");
    std::fs::write(
        &path,
        format!("#!/bin/sh\nexec '{}' -S \"$@\"\n", real.display()),
    )
    .unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    Some(path)
}

fn sweep_without_rebound(python: &Path) {
    let setup = builtin::kepler(false, 20.0 * std::f64::consts::PI, true).unwrap();
    let whfast = rebound_method("rebound:whfast", &setup).with_python(python);
    let methods = vec![setup.method("leapfrog").unwrap(), Method::Rebound(whfast)];
    let mut settings = SweepSettings::new(setup.sys.defaults(), setup.t_end);
    settings.points = 2;
    settings.repeats = 1;
    let result = work_precision(&setup, &methods, &settings).unwrap();
    assert_eq!(result.methods, vec!["leapfrog".to_string()]);
    assert_eq!(result.rows.len(), 2);
    assert!(result.rows.iter().all(|r| r.method == "leapfrog" && r.ok()));
    assert_eq!(result.rebound, None);
    let notes = result.notes.join("\n");
    assert!(
        notes.contains(rebound::INSTALL) && notes.contains("rebound:whfast"),
        "{notes}"
    );
    assert!(result.summary().contains(rebound::INSTALL));
    assert!(result.report().contains(rebound::INSTALL));
}

#[test]
fn without_rebound_the_sweep_says_how_to_install_it_and_runs_the_rest() {
    // No interpreter at all.
    sweep_without_rebound(Path::new("/nonexistent/python3"));
    // An interpreter without the package.
    let dir = std::env::temp_dir().join(format!("symlab-rebound-missing-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let python = python_without_rebound(&dir).unwrap_or_else(|| {
        panic!(
            "no Python interpreter at '{}' to run without its site-packages (set SYMLAB_PYTHON; scripts/test does)",
            rebound::python().display()
        )
    });
    sweep_without_rebound(&python);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_names_and_problems_are_errors_naming_the_method() {
    let kepler = Kepler { e: 0.6 };
    let err = |id: &str| match Method::by_id(id, &kepler) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("{id} was accepted"),
    };
    let e = err("rebound:whfastt");
    assert!(
        e.contains("'rebound:whfastt'")
            && e.contains("--methods")
            && e.contains("whfast, whckl")
            && e.contains("saba-10-6-4"),
        "{e}"
    );
    let e = err("rebound:whfast:corrector=4");
    assert!(
        e.contains("corrector = '4'") && e.contains("0, 3, 5, 7, 11, 17"),
        "{e}"
    );
    let e = err("rebound:leapfrog:order=3");
    assert!(e.contains("order") && e.contains("2, 4, 6, 8"), "{e}");
    let e = err("rebound:whfast:kernel=fast");
    assert!(e.contains("lazy"), "{e}");
    // The unknown-method message names the rebound: methods on this problem.
    let e = err("nope");
    assert!(e.contains("rebound:NAME"), "{e}");
    // A problem that is not point masses.
    let e = match Method::by_id("rebound:whfast", &HenonHeiles) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("REBOUND on Hénon–Heiles was accepted"),
    };
    assert!(
        e.contains("rebound:whfast") && e.contains("henon-heiles") && e.contains("outer-solar"),
        "{e}"
    );
    // The names parse without REBOUND installed.
    for name in rebound::names() {
        assert!(
            Method::by_id(&format!("rebound:{name}"), &kepler).is_ok(),
            "{name}"
        );
    }
}
