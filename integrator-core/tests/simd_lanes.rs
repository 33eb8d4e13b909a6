//! The eight-lane kernels of the Wisdom–Holman splits (`integrator_core::simd`):
//! every SIMD level this processor has (AVX-512, AVX2) gives the portable
//! lanes' bits — one test per level, named by it; a level the machine that
//! built the tests lacks is `#[ignore]`d with the reason (so the log shows
//! which ran) —, the Kepler lanes are the scalar drift bit for bit on each,
//! the lane kicks are the interaction's forces (against a direct sum over
//! pairs written here) for one to eight planets, and `SYMLAB_SIMD` caps the
//! level.

use integrator_core::kepler::{KeplerSolver, drift};
use integrator_core::problems::OuterSolarSystem;
use integrator_core::problems::wisdom_holman::{DemocraticHeliocentric, GradientKick, Jacobi};
use integrator_core::simd::{Level, Simd};

const G: f64 = 2.95912208286e-4;

/// A sun of mass 1 and `p` planets on mildly eccentric, inclined orbits at
/// radii 1, 1.6, 2.56, … (heliocentric positions and velocities, inertial
/// momenta): `(masses, z)`.
fn system(p: usize) -> (Vec<f64>, Vec<f64>) {
    let n = p + 1;
    let mut m = vec![1.0];
    let mut x = vec![[0.0; 3]];
    let mut v = vec![[0.0; 3]];
    for i in 1..n {
        let fi = i as f64;
        m.push(1e-3 / fi);
        let r = 1.6f64.powi(i as i32 - 1);
        let th = 0.7 * fi;
        let speed = (G / r).sqrt() * (1.0 + 0.03 * fi.sin());
        x.push([r * th.cos(), r * th.sin(), 0.02 * r * (1.3 * fi).sin()]);
        v.push([-speed * th.sin(), speed * th.cos(), 0.01 * speed * fi.cos()]);
    }
    let mut z = vec![0.0; 6 * n];
    for i in 0..n {
        for k in 0..3 {
            z[3 * i + k] = x[i][k];
            z[3 * n + 3 * i + k] = m[i] * v[i][k];
        }
    }
    (m, z)
}

fn bits(a: &[f64]) -> Vec<u64> {
    a.iter().map(|x| x.to_bits()).collect()
}

/// Every level this processor has, as the choice that runs it, said in
/// the output (with the levels it lacks).
fn available() -> Vec<Simd> {
    let (have, lack): (Vec<Level>, Vec<Level>) =
        Level::ALL.into_iter().partition(|l| l.available());
    println!("simd levels here: {have:?}; not here: {lack:?}");
    have.into_iter().map(Simd::from).collect()
}

/// Fails, saying why, where the tests were built on a machine with
/// `level` and run on one without (the `#[ignore]`s below are decided when
/// the tests are built: `build.rs`).
fn require(level: Level) {
    assert!(
        level.available(),
        "the tests were built where this processor had {level}, and run where it has not: rebuild them here"
    );
    println!("simd lanes: {level} here, compared with the portable lanes");
}

/// Integrations on `simd` and on the portable lanes give the same bits:
/// both splits, one to eight planets, both ways in time, plain, lazy and
/// exact gradient kicks, and the outer solar system over 10⁴ steps.
fn same_bits_as_portable(simd: Simd) {
    for p in 1..=8 {
        let (m, z) = system(p);
        for (h, steps) in [(0.05, 200), (-0.3, 50)] {
            let mut runs = Vec::new();
            for simd in [simd, Simd::Portable] {
                let jac = Jacobi::new(G, &m, None).unwrap().with_simd(simd);
                let mut w = vec![0.0; z.len()];
                jac.from_inertial(&z, &mut w).unwrap();
                jac.integrate(h, steps, &mut w).unwrap();
                // The lazy implementer's gradient kick and the exact one.
                jac.interaction_kick_gradient(h, 1e-3 * h * h * h, &mut w)
                    .unwrap();
                jac.interaction_kick_modified(h, 1e-3 * h * h * h, &mut w)
                    .unwrap();
                let dh = DemocraticHeliocentric::new(G, &m, None)
                    .unwrap()
                    .with_simd(simd);
                let mut u = vec![0.0; z.len()];
                dh.from_inertial(&z, &mut u).unwrap();
                dh.integrate(h, steps, &mut u).unwrap();
                runs.push((w, u));
            }
            assert_eq!(
                bits(&runs[0].0),
                bits(&runs[1].0),
                "{simd:?}: Jacobi, {p} planets, h = {h}"
            );
            assert_eq!(
                bits(&runs[0].1),
                bits(&runs[1].1),
                "{simd:?}: democratic heliocentric, {p} planets, h = {h}"
            );
        }
    }
    // The outer solar system over 10⁴ steps of 10 days.
    let z = OuterSolarSystem.initial_state();
    let mut out = Vec::new();
    for simd in [simd, Simd::Portable] {
        let jac = Jacobi::outer_solar().with_simd(simd);
        let mut w = vec![0.0; z.len()];
        jac.from_inertial(&z, &mut w).unwrap();
        jac.integrate(10.0, 10_000, &mut w).unwrap();
        out.push(w);
    }
    assert_eq!(bits(&out[0]), bits(&out[1]), "{simd:?}: outer solar system");
}

#[test]
#[cfg_attr(
    not(symlab_avx512),
    ignore = "this machine has no AVX-512F (found when the tests were built)"
)]
fn avx512_lanes_give_the_portable_bits() {
    require(Level::Avx512);
    same_bits_as_portable(Simd::Avx512);
}

#[test]
#[cfg_attr(
    not(symlab_avx2),
    ignore = "this machine has no AVX2 (found when the tests were built)"
)]
fn avx2_lanes_give_the_portable_bits() {
    require(Level::Avx2);
    same_bits_as_portable(Simd::Avx2);
}

/// The registers' loop (`Jacobi::kick_drift_run`) on `simd` against the
/// kick and the drift one flow at a time on the portable lanes: plain,
/// lazy gradient and exact modified kicks, short and long steps, and steps
/// so long (3000 days, 0.7 of Jupiter's period) that the drifts leave the
/// lanes, where the run takes no step and the flows take them all.
fn run_is_the_flows_one_by_one(simd: Simd) {
    let z = OuterSolarSystem.initial_state();
    for (h, gamma, kick) in [
        (10.0, 0.0, GradientKick::Lazy),
        (600.0, 0.0, GradientKick::Lazy),
        (-250.0, 0.0, GradientKick::Lazy),
        (10.0, 1e3 / 24.0, GradientKick::Lazy),
        (10.0, 1e3 / 24.0, GradientKick::Exact),
        (-120.0, -2e5, GradientKick::Exact),
        (3000.0, 0.0, GradientKick::Lazy),
    ] {
        let fast = Jacobi::outer_solar()
            .with_simd(simd)
            .with_gradient_kick(kick);
        let slow = Jacobi::outer_solar()
            .with_simd(Simd::Portable)
            .with_gradient_kick(kick);
        let step_kick = |split: &Jacobi, w: &mut [f64]| match (gamma, kick) {
            (0.0, _) => split.interaction_kick(h, w).unwrap(),
            (_, GradientKick::Lazy) => split.interaction_kick_gradient(h, gamma, w).unwrap(),
            (_, GradientKick::Exact) => split.interaction_kick_modified(h, gamma, w).unwrap(),
        };
        let n = 40;
        let mut w = vec![0.0; z.len()];
        fast.from_inertial(&z, &mut w).unwrap();
        let mut u = w.clone();
        let mut k = 0;
        let mut in_run = 0;
        while k < n {
            let done = fast.kick_drift_run(h, gamma, h, 0.5 * h, n - k, &mut w);
            (k, in_run) = (k + done, in_run + done);
            if k == n {
                break;
            }
            step_kick(&fast, &mut w);
            fast.kepler_flow(if k + 1 < n { h } else { 0.5 * h }, &mut w)
                .unwrap();
            k += 1;
        }
        for k in 0..n {
            step_kick(&slow, &mut u);
            slow.kepler_flow(if k + 1 < n { h } else { 0.5 * h }, &mut u)
                .unwrap();
        }
        let what = format!("{simd:?}: h = {h}, gamma = {gamma}, {kick:?}");
        assert_eq!(bits(&w), bits(&u), "{what}");
        // The loop ran where the lanes hold every planet, and not where
        // Jupiter's drift leaves them; not at all on the portable level,
        // where the flows one by one are faster.
        if simd.level() == Level::Portable {
            assert_eq!(in_run, 0, "{what}");
        } else if h.abs() < 1000.0 {
            assert_eq!(in_run, n, "{what}");
        } else {
            assert!(in_run < n, "{what}");
        }
    }
}

#[test]
#[cfg_attr(
    not(symlab_avx512),
    ignore = "this machine has no AVX-512F (found when the tests were built)"
)]
fn the_kick_drift_run_on_avx512_is_the_flows_one_by_one_bit_for_bit() {
    require(Level::Avx512);
    run_is_the_flows_one_by_one(Simd::Avx512);
}

#[test]
#[cfg_attr(
    not(symlab_avx2),
    ignore = "this machine has no AVX2 (found when the tests were built)"
)]
fn the_kick_drift_run_on_avx2_is_the_flows_one_by_one_bit_for_bit() {
    require(Level::Avx2);
    run_is_the_flows_one_by_one(Simd::Avx2);
}

#[test]
fn the_kick_drift_run_on_the_portable_lanes_is_the_flows_one_by_one_bit_for_bit() {
    run_is_the_flows_one_by_one(Simd::Portable);
}

/// The democratic heliocentric split's registers' loop
/// (`DemocraticHeliocentric::steps_in_lanes`, which `integrate` takes) on
/// `simd` against its flows one at a time on the portable lanes: short,
/// long and backward steps, and steps so long that Jupiter's drift leaves
/// the lanes, where the loop takes no step and the flows take them all.
fn democratic_run_is_the_flows_one_by_one(simd: Simd) {
    let z = OuterSolarSystem.initial_state();
    for h in [10.0, 600.0, -250.0, 3000.0] {
        let fast = DemocraticHeliocentric::outer_solar().with_simd(simd);
        let slow = DemocraticHeliocentric::outer_solar().with_simd(Simd::Portable);
        let n = 40;
        let mut w = vec![0.0; z.len()];
        fast.from_inertial(&z, &mut w).unwrap();
        let mut u = w.clone();
        // The loop and the flows, as `integrate` mixes them.
        fast.jump(0.5 * h, &mut w).unwrap();
        let (mut k, mut in_run) = (0, 0);
        while k < n {
            let done = fast.steps_in_lanes(h, n - k, &mut w);
            (k, in_run) = (k + done, in_run + done);
            if k == n {
                break;
            }
            fast.interaction_kick(0.5 * h, &mut w).unwrap();
            fast.kepler_flow(h, &mut w).unwrap();
            fast.interaction_kick(0.5 * h, &mut w).unwrap();
            fast.jump(if k + 1 < n { h } else { 0.5 * h }, &mut w)
                .unwrap();
            k += 1;
        }
        // The flows alone.
        slow.jump(0.5 * h, &mut u).unwrap();
        for k in 0..n {
            slow.interaction_kick(0.5 * h, &mut u).unwrap();
            slow.kepler_flow(h, &mut u).unwrap();
            slow.interaction_kick(0.5 * h, &mut u).unwrap();
            slow.jump(if k + 1 < n { h } else { 0.5 * h }, &mut u)
                .unwrap();
        }
        let what = format!("{simd:?}: democratic heliocentric, h = {h}");
        assert_eq!(bits(&w), bits(&u), "{what}");
        // And `integrate` is that mix.
        let mut v = vec![0.0; z.len()];
        fast.from_inertial(&z, &mut v).unwrap();
        fast.integrate(h, n, &mut v).unwrap();
        assert_eq!(bits(&v), bits(&u), "{what}: integrate");
        if simd.level() == Level::Portable {
            assert_eq!(in_run, 0, "{what}");
        } else if h.abs() < 1000.0 {
            assert_eq!(in_run, n, "{what}");
        } else {
            assert!(in_run < n, "{what}");
        }
    }
}

#[test]
#[cfg_attr(
    not(symlab_avx512),
    ignore = "this machine has no AVX-512F (found when the tests were built)"
)]
fn the_democratic_run_on_avx512_is_the_flows_one_by_one_bit_for_bit() {
    require(Level::Avx512);
    democratic_run_is_the_flows_one_by_one(Simd::Avx512);
}

#[test]
#[cfg_attr(
    not(symlab_avx2),
    ignore = "this machine has no AVX2 (found when the tests were built)"
)]
fn the_democratic_run_on_avx2_is_the_flows_one_by_one_bit_for_bit() {
    require(Level::Avx2);
    democratic_run_is_the_flows_one_by_one(Simd::Avx2);
}

#[test]
fn the_democratic_run_on_the_portable_lanes_takes_no_step() {
    democratic_run_is_the_flows_one_by_one(Simd::Portable);
}

#[test]
fn the_eight_kepler_lanes_are_the_scalar_drift_bit_for_bit() {
    // Mixed orbits side by side (different GM, e, phase; a hyperbola), at
    // steps from 10⁻⁵ of the first orbit's period (one evaluation in every
    // lane, 5, 7 or 10 Stumpff terms) to several periods (the scalar
    // fallback), both ways; 8, 5 and 1 lanes used.
    let solver = KeplerSolver::default();
    let mut orbits = Vec::new();
    for j in 0..24 {
        let fj = j as f64;
        let gm = 1.0 + 0.5 * (fj * 0.37).sin();
        let r = 1.0 + 0.3 * fj;
        let e = if j % 7 == 6 { 1.4 } else { 0.05 + 0.04 * fj };
        let speed = (gm * (1.0 + e) / r).sqrt();
        let th = 0.9 * fj;
        orbits.push((
            gm,
            [r * th.cos(), r * th.sin(), 0.1 * r],
            [-speed * th.sin(), speed * th.cos(), 0.05 * speed],
            2.0 * std::f64::consts::PI * (r * r * r / gm).sqrt(),
        ));
    }
    let simds = available();
    let mut compared = 0;
    for &simd in &simds {
        for frac in [
            1e-5, 3e-4, 2e-3, 0.01, 0.05, 0.1, 0.15, 0.22, 0.3, 1.7, -0.02, -0.2, -2.5,
        ] {
            for used in [8, 5, 1] {
                for group in orbits.chunks(used) {
                    let h = frac * group[0].3;
                    let mut gm = [1.0; 8];
                    let mut x = [[0.0; 3]; 8];
                    let mut v = [[0.0; 3]; 8];
                    for (l, o) in group.iter().enumerate() {
                        (gm[l], x[l], v[l]) = (o.0, o.1, o.2);
                    }
                    let (x_in, v_in) = (x, v);
                    solver
                        .drift_lanes8(&gm, h, &mut x, &mut v, group.len(), simd)
                        .unwrap_or_else(|(l, e)| panic!("lane {l}, h = {h}: {e}"));
                    for (l, o) in group.iter().enumerate() {
                        let (mut xs, mut vs) = (o.1, o.2);
                        drift(o.0, h, &mut xs, &mut vs).unwrap();
                        assert_eq!(
                            (bits(&x[l]), bits(&v[l])),
                            (bits(&xs), bits(&vs)),
                            "{simd:?}, lane {l} of {used}, h = {h}"
                        );
                        compared += 1;
                    }
                    for l in group.len()..8 {
                        assert_eq!((x[l], v[l]), (x_in[l], v_in[l]), "unused lane {l} moved");
                    }
                }
            }
        }
    }
    println!("{compared} lanes compared");
}

/// The inertial accelerations of the positions `x` by a direct sum over
/// pairs, and per body the sum of the magnitudes of its terms (the scale of
/// the rounding error of any order of summation).
fn accelerations(m: &[f64], x: &[f64]) -> (Vec<[f64; 3]>, Vec<f64>) {
    let n = m.len();
    let mut a = vec![[0.0; 3]; n];
    let mut size = vec![0.0; n];
    for i in 0..n {
        for j in 0..n {
            if i == j {
                continue;
            }
            let d: Vec<f64> = (0..3).map(|k| x[3 * j + k] - x[3 * i + k]).collect();
            let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            for k in 0..3 {
                a[i][k] += G * m[j] * d[k] / (r * r * r);
            }
            size[i] += G * m[j] / (r * r);
        }
    }
    (a, size)
}

#[test]
fn the_lane_kicks_are_the_interactions_forces() {
    for simd in available() {
        for p in 1..=8 {
            let (m, z) = system(p);
            let n = p + 1;
            let h = 0.7;

            // Democratic heliocentric: Pᵢ += h Σ_{j≥1} G mᵢmⱼ (Qⱼ − Qᵢ)/|Qⱼ − Qᵢ|³.
            let dh = DemocraticHeliocentric::new(G, &m, None)
                .unwrap()
                .with_simd(simd);
            let mut w = vec![0.0; 6 * n];
            dh.from_inertial(&z, &mut w).unwrap();
            let w0 = w.clone();
            dh.interaction_kick(h, &mut w).unwrap();
            let mut planets = m.clone();
            planets[0] = 0.0; // the Sun does not enter the interaction
            let (a, size) = accelerations(&planets, &w0[..3 * n]);
            for i in 1..n {
                for k in 0..3 {
                    let p0 = w0[3 * n + 3 * i + k];
                    let expected = p0 + h * m[i] * a[i][k];
                    let got = w[3 * n + 3 * i + k];
                    // A few roundings of the momentum and of the terms.
                    let bound = 4.0 * f64::EPSILON * p0.abs() + 1e-14 * h * m[i] * size[i];
                    assert!(
                        (got - expected).abs() <= bound,
                        "{simd:?}, DH, {p} planets, body {i}: {got:e} vs {expected:e}"
                    );
                }
            }

            // Jacobi: Pᵢ += h m'ᵢ (aᵢ − Σ_{j<i} mⱼaⱼ/M_{i−1} + G Mᵢ Qᵢ/|Qᵢ|³).
            let jac = Jacobi::new(G, &m, None).unwrap().with_simd(simd);
            jac.from_inertial(&z, &mut w).unwrap();
            let w0 = w.clone();
            jac.interaction_kick(h, &mut w).unwrap();
            let mut zi = vec![0.0; 6 * n];
            jac.to_inertial(&w0, &mut zi).unwrap();
            let (a, _) = accelerations(&m, &zi[..3 * n]);
            let mut interior = 0.0;
            let mut acc = [0.0; 3];
            for i in 0..n {
                if i > 0 {
                    let q = &w0[3 * i..3 * i + 3];
                    let r = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
                    let mi = interior + m[i];
                    let reduced = m[i] * interior / mi;
                    for k in 0..3 {
                        let qdd = a[i][k] - acc[k] / interior + G * mi * q[k] / (r * r * r);
                        let kick = h * reduced * qdd;
                        let expected = w0[3 * n + 3 * i + k] + kick;
                        let got = w[3 * n + 3 * i + k];
                        // The interaction is a difference of the Sun's pull
                        // and the Kepler term's: judge it against the
                        // larger of those.
                        let p0 = w0[3 * n + 3 * i + k];
                        let bound =
                            4.0 * f64::EPSILON * p0.abs() + 1e-13 * h * reduced * G * mi / (r * r);
                        assert!(
                            (got - expected).abs() <= bound,
                            "{simd:?}, Jacobi, {p} planets, body {i}, k = {k}: {got:e} vs {expected:e} (kick {kick:e})"
                        );
                    }
                }
                interior += m[i];
                for k in 0..3 {
                    acc[k] += m[i] * a[i][k];
                }
            }
        }
    }
}

#[test]
fn the_level_names_parse_and_a_wrong_one_is_an_error_naming_it() {
    for level in Level::ALL {
        assert_eq!(level.name().parse::<Level>(), Ok(level));
        assert_eq!(level.name().to_uppercase().parse::<Level>(), Ok(level));
    }
    let e = "avx".parse::<Level>().unwrap_err();
    assert_eq!(e.value, "avx");
    let msg = e.to_string();
    assert!(
        msg.contains("SYMLAB_SIMD=\"avx\"") && msg.contains("avx512, avx2 or portable"),
        "{msg}"
    );
}

#[test]
fn a_cap_lowers_the_level_auto_runs_on_and_never_raises_it() {
    use integrator_core::simd::{detected, level, set_cap};
    let best = detected();
    for cap in Level::ALL {
        set_cap(Some(cap));
        assert_eq!(level(), cap.min(best), "cap {cap}");
        assert_eq!(Simd::Auto.level(), cap.min(best), "cap {cap}");
        // A level asked for by name is not capped.
        assert_eq!(Simd::Avx2.level(), Level::Avx2.min(best));
    }
    set_cap(None);
    println!("simd: best here {best}, without set_cap {}", level());
}

/// Prints the level `SYMLAB_SIMD` leaves (the child process of the test
/// below; alone it only prints).
#[test]
fn simd_level_child() {
    println!(
        "child: cap {:?}, level {}",
        integrator_core::simd::env_cap(),
        integrator_core::simd::level()
    );
}

#[test]
fn symlab_simd_caps_the_level_of_a_process_and_a_wrong_value_is_refused_aloud() {
    use integrator_core::simd::detected;
    let child = |value: &str| {
        let out = std::process::Command::new(std::env::current_exe().unwrap())
            .args(["simd_lanes::simd_level_child", "--exact", "--nocapture"])
            .env("SYMLAB_SIMD", value)
            .output()
            .unwrap();
        assert!(out.status.success(), "{out:?}");
        (
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    for level in Level::ALL {
        let (stdout, _) = child(level.name());
        let expect = format!(
            "child: cap Ok(Some({level:?})), level {}",
            level.min(detected())
        );
        assert!(stdout.contains(&expect), "{level}: {stdout}");
    }
    let (stdout, stderr) = child("avx-512");
    assert!(stdout.contains("level portable"), "{stdout}");
    assert!(
        stderr.contains("SYMLAB_SIMD=\"avx-512\" is not a SIMD level")
            && stderr.contains("running the portable kernels"),
        "{stderr}"
    );
}
