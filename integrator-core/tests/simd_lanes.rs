//! The eight-lane kernels of the Wisdom–Holman splits (`integrator_core::simd`):
//! the AVX-512 lanes and the portable ones give the same bits (on a
//! processor without AVX-512, the lanes it runs against themselves, said in
//! the output), the Kepler lanes
//! are the scalar drift bit for bit on both, and the lane kicks are the
//! interaction's forces (against a direct sum over pairs written here) for
//! one to eight planets.

use integrator_core::kepler::{KeplerSolver, drift};
use integrator_core::problems::OuterSolarSystem;
use integrator_core::problems::wisdom_holman::{DemocraticHeliocentric, Jacobi};
use integrator_core::simd::{Simd, has_avx512};

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

/// The lanes `Simd::Auto` picks on this CPU against the portable ones. On a
/// CPU without AVX-512 both are the portable lanes (this CPU has no other
/// variant yet), and the test says so rather than pass as if it had
/// compared AVX-512: what it then checks is that two runs of the same
/// lanes agree to the bit.
#[test]
fn the_lanes_auto_picks_and_the_portable_ones_give_the_same_bits() {
    if has_avx512() {
        println!("simd lanes: AVX-512F here: comparing the AVX-512 lanes with the portable ones");
    } else {
        println!(
            "simd lanes: no AVX-512F here: Auto runs the portable lanes, so this compares the portable lanes with themselves"
        );
    }
    for p in 1..=8 {
        let (m, z) = system(p);
        for (h, steps) in [(0.05, 200), (-0.3, 50)] {
            let mut runs = Vec::new();
            for simd in [Simd::Auto, Simd::Portable] {
                let jac = Jacobi::new(G, &m, None).unwrap().with_simd(simd);
                let mut w = vec![0.0; z.len()];
                jac.from_inertial(&z, &mut w).unwrap();
                jac.integrate(h, steps, &mut w).unwrap();
                // The lazy implementer's gradient kick too.
                jac.interaction_kick_gradient(h, 1e-3 * h * h * h, &mut w)
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
                "Jacobi, {p} planets, h = {h}"
            );
            assert_eq!(
                bits(&runs[0].1),
                bits(&runs[1].1),
                "democratic heliocentric, {p} planets, h = {h}"
            );
        }
    }
    // The outer solar system over 10⁴ steps of 10 days.
    let z = OuterSolarSystem.initial_state();
    let mut out = Vec::new();
    for simd in [Simd::Auto, Simd::Portable] {
        let jac = Jacobi::outer_solar().with_simd(simd);
        let mut w = vec![0.0; z.len()];
        jac.from_inertial(&z, &mut w).unwrap();
        jac.integrate(10.0, 10_000, &mut w).unwrap();
        out.push(w);
    }
    assert_eq!(bits(&out[0]), bits(&out[1]));
}

#[test]
fn the_kick_drift_run_is_the_flows_one_by_one_bit_for_bit() {
    // The registers' loop (`Jacobi::kick_drift_run`) against the kick and
    // the drift one flow at a time on the portable lanes: plain and
    // gradient kicks, short and long steps, and steps so long (3000 days,
    // 0.7 of Jupiter's period) that the drifts leave the lanes, where the
    // run takes no step and the flows take them all.
    let z = OuterSolarSystem.initial_state();
    let fast = Jacobi::outer_solar();
    let slow = Jacobi::outer_solar().with_simd(Simd::Portable);
    for (h, gamma) in [
        (10.0, 0.0),
        (600.0, 0.0),
        (-250.0, 0.0),
        (10.0, 1e3 / 24.0),
        (3000.0, 0.0),
    ] {
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
            if gamma == 0.0 {
                fast.interaction_kick(h, &mut w).unwrap();
            } else {
                fast.interaction_kick_gradient(h, gamma, &mut w).unwrap();
            }
            fast.kepler_flow(if k + 1 < n { h } else { 0.5 * h }, &mut w)
                .unwrap();
            k += 1;
        }
        for k in 0..n {
            if gamma == 0.0 {
                slow.interaction_kick(h, &mut u).unwrap();
            } else {
                slow.interaction_kick_gradient(h, gamma, &mut u).unwrap();
            }
            slow.kepler_flow(if k + 1 < n { h } else { 0.5 * h }, &mut u)
                .unwrap();
        }
        assert_eq!(bits(&w), bits(&u), "h = {h}, gamma = {gamma}");
        if has_avx512() {
            // The loop ran where the lanes hold every planet, and not where
            // Jupiter's drift leaves them.
            if h.abs() < 1000.0 {
                assert_eq!(in_run, n, "h = {h}");
            } else {
                assert!(in_run < n, "h = {h}");
            }
        } else {
            assert_eq!(in_run, 0);
        }
    }
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
    let simds: &[Simd] = if has_avx512() {
        &[Simd::Auto, Simd::Portable]
    } else {
        eprintln!("no AVX-512F: the portable lanes only");
        &[Simd::Portable]
    };
    let mut compared = 0;
    for &simd in simds {
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
    for simd in [Simd::Auto, Simd::Portable] {
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
