//! The Kepler drift (`integrator_core::kepler`) against the exact two-body
//! flow computed in double-double arithmetic (`double_double`, about 106
//! bits, an independent method): every conic from circular to `e = 0.999`
//! and hyperbolic orbits, steps from 10⁻⁴ of a period to ten periods and
//! backwards; the invariants; the group property of a flow; bad input; and
//! the growth of the rounding error over 10⁶ orbits.
//!
//! Accuracy is judged against the conditioning of the flow: an exact map
//! evaluated in f64 starts from a state that its first operations round by
//! `ε`, and the flow carries that perturbation on with its Jacobian. With
//! `κ` the scaled norm of that Jacobian (positions relative to `|x|`,
//! velocities to `|v|`, in and out), the error of an evaluation that is
//! exact up to rounding is a few `ε·(1 + κ)`.

use crate::double_double;

use double_double::Dd;
use integrator_core::kepler::{KeplerError, KeplerSolver, LANES, drift};
use std::f64::consts::PI;

const EPS: f64 = f64::EPSILON;

/// The state at true anomaly `nu` on the conic of semi-major axis `a`
/// (negative for hyperbolae) and eccentricity `e`, rotated out of the
/// plane by fixed, generic angles.
pub(crate) fn state(gm: f64, a: f64, e: f64, nu: f64) -> ([f64; 3], [f64; 3]) {
    let p = a * (1.0 - e * e);
    let r = p / (1.0 + e * nu.cos());
    let w = (gm / p).sqrt();
    let x = [r * nu.cos(), r * nu.sin(), 0.0];
    let v = [-w * nu.sin(), w * (e + nu.cos()), 0.0];
    (rotate(x), rotate(v))
}

fn rotate(u: [f64; 3]) -> [f64; 3] {
    let (o, i, w) = (0.7f64, 0.4f64, 1.9f64);
    let rz = |u: [f64; 3], t: f64| {
        [
            t.cos() * u[0] - t.sin() * u[1],
            t.sin() * u[0] + t.cos() * u[1],
            u[2],
        ]
    };
    let rx = |u: [f64; 3], t: f64| {
        [
            u[0],
            t.cos() * u[1] - t.sin() * u[2],
            t.sin() * u[1] + t.cos() * u[2],
        ]
    };
    rz(rx(rz(u, w), i), o)
}

fn norm(u: &[f64; 3]) -> f64 {
    (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt()
}

fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `max(|Δx|/|x_ref|, |Δv|/|v_ref|)`.
pub(crate) fn scaled_error(x: &[f64; 3], v: &[f64; 3], xr: &[Dd; 3], vr: &[Dd; 3]) -> f64 {
    let dx = [0, 1, 2].map(|k| (Dd::new(x[k]) - xr[k]).f64());
    let dv = [0, 1, 2].map(|k| (Dd::new(v[k]) - vr[k]).f64());
    let xr = xr.map(Dd::f64);
    let vr = vr.map(Dd::f64);
    (norm(&dx) / norm(&xr)).max(norm(&dv) / norm(&vr))
}

/// The reference, rounded to f64.
pub(crate) fn reference(gm: f64, h: f64, x: [f64; 3], v: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let (xr, vr) = double_double::flow(gm, h, x, v)
        .unwrap_or_else(|| panic!("the reference solve converges: h = {h}, x = {x:?}, v = {v:?}"));
    (xr.map(Dd::f64), vr.map(Dd::f64))
}

/// `κ`: the ∞-norm of the flow's Jacobian scaled by `|x|, |v|` in and
/// out, by central differences of the double-double flow (relative
/// increments 1e-7, so κ is good to a few digits, all a bound needs).
pub(crate) fn kappa(gm: f64, h: f64, x: [f64; 3], v: [f64; 3]) -> f64 {
    let (xr, vr) = reference(gm, h, x, v);
    let (sx_out, sv_out) = (norm(&xr), norm(&vr));
    let (sx_in, sv_in) = (norm(&x), norm(&v));
    let mut rows = [0.0f64; 6];
    for j in 0..6 {
        let d = 1e-7 * if j < 3 { sx_in } else { sv_in };
        let shifted = |sign: f64| {
            let (mut xp, mut vp) = (x, v);
            if j < 3 {
                xp[j] += sign * d;
            } else {
                vp[j - 3] += sign * d;
            }
            reference(gm, h, xp, vp)
        };
        let (p, m) = (shifted(1.0), shifted(-1.0));
        let scale_in = if j < 3 { sx_in } else { sv_in };
        for i in 0..3 {
            rows[i] += ((p.0[i] - m.0[i]) / (2.0 * d)).abs() * scale_in / sx_out;
            rows[3 + i] += ((p.1[i] - m.1[i]) / (2.0 * d)).abs() * scale_in / sv_out;
        }
    }
    rows.iter().cloned().fold(0.0, f64::max)
}

/// The bound every evaluation of the flow must meet: `C·ε·(1 + κ)`.
/// Measured, the worst `error/(ε(1 + κ))` over the grid below is printed by
/// the test; `C = 8` is "a few ulps".
pub(crate) const C: f64 = 8.0;

struct Case {
    gm: f64,
    a: f64,
    e: f64,
    nu: f64,
    h: f64,
}

/// The grid: two unit systems (GM = 1, a = 1; the Sun's GM in AU³/day² with
/// Jupiter's a), every eccentricity of the issue, starting at the
/// pericentre, on the way out, near the apocentre and on the way in; steps
/// from 10⁻⁴ of a period to 10.3 periods, both ways.
fn bound_cases() -> Vec<Case> {
    let mut out = Vec::new();
    for (gm, a) in [(1.0f64, 1.0f64), (2.95912208286e-4, 5.2)] {
        for e in [0.0, 0.1, 0.5, 0.9, 0.99, 0.999] {
            let period = 2.0 * PI * (a * a * a / gm).sqrt();
            for nu in [0.0, 1.0, PI - 0.3, -2.0, -0.05] {
                for k in [1e-4, 0.05, 1.0 / 3.0, 0.77, 3.0, 10.3, -0.05, -3.6] {
                    out.push(Case {
                        gm,
                        a,
                        e,
                        nu,
                        h: k * period,
                    });
                }
            }
        }
    }
    out
}

/// Hyperbolae with `e = 1.001, 1.5, 3`, `a = −1`, starting at the
/// pericentre and at 80 % of the asymptote's angle on either side, steps in
/// units of `1/n = √(|a|³/GM)` from 10⁻³ to 30, both ways.
fn hyperbolic_cases() -> Vec<Case> {
    let mut out = Vec::new();
    let (gm, a) = (1.0, -1.0);
    for e in [1.001, 1.5, 3.0] {
        let nu_max = (-1.0f64 / e).acos();
        for nu in [0.0, 0.8 * nu_max, -0.8 * nu_max] {
            for k in [1e-3, 0.05, 0.5, 3.0, 30.0, -0.5, -30.0] {
                out.push(Case { gm, a, e, nu, h: k });
            }
        }
    }
    out
}

#[test]
fn the_drift_is_the_exact_flow_to_a_few_ulps_times_the_conditioning() {
    let mut worst: f64 = 0.0;
    let mut worst_case = String::new();
    let mut worst_error: f64 = 0.0;
    for c in bound_cases().into_iter().chain(hyperbolic_cases()) {
        let (x0, v0) = state(c.gm, c.a, c.e, c.nu);
        let (mut x, mut v) = (x0, v0);
        drift(c.gm, c.h, &mut x, &mut v)
            .unwrap_or_else(|err| panic!("e = {}, nu = {}, h = {}: {err}", c.e, c.nu, c.h));
        let (xr, vr) = double_double::flow(c.gm, c.h, x0, v0).expect("reference converges");
        let err = scaled_error(&x, &v, &xr, &vr);
        let k = kappa(c.gm, c.h, x0, v0);
        let ratio = err / (EPS * (1.0 + k));
        worst_error = worst_error.max(err);
        if ratio > worst {
            worst = ratio;
            worst_case = format!(
                "gm = {}, e = {}, nu = {}, h = {}: error {err:e}, κ = {k:e}",
                c.gm, c.e, c.nu, c.h
            );
        }
        assert!(
            ratio <= C,
            "gm = {}, e = {}, nu = {}, h = {}: error {err:e} > {C}·ε·(1 + κ), κ = {k:e}",
            c.gm,
            c.e,
            c.nu,
            c.h
        );
    }
    println!("worst error/(ε(1 + κ)) = {worst:.2} at {worst_case}; largest error {worst_error:e}");
}

#[test]
fn steps_of_several_periods_land_where_the_remainder_does() {
    // A step of k whole periods plus h lands where h does, up to the
    // rounding of kP itself (the period is known to a few ulps, and the
    // flow's phase sensitivity turns that into ~ε·k·κ).
    for e in [0.0, 0.5, 0.9, 0.999] {
        let (x0, v0) = state(1.0, 1.0, e, 0.4);
        let period = 2.0 * PI;
        for k in [1.0, 3.0, 17.0] {
            let h = 0.3 * period;
            let (mut xa, mut va) = (x0, v0);
            drift(1.0, h + k * period, &mut xa, &mut va).unwrap();
            let (xr, vr) = double_double::flow(1.0, h + k * period, x0, v0).unwrap();
            let err = scaled_error(&xa, &va, &xr, &vr);
            let kap = kappa(1.0, h + k * period, x0, v0);
            assert!(
                err <= C * EPS * (1.0 + kap),
                "e = {e}, k = {k}: {err:e}, κ = {kap:e}"
            );
        }
    }
}

fn energy(gm: f64, x: &[f64; 3], v: &[f64; 3]) -> (f64, f64) {
    let (t, u) = (
        0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]),
        gm / norm(x),
    );
    (t - u, t + u)
}

fn lrl(gm: f64, x: &[f64; 3], v: &[f64; 3]) -> [f64; 3] {
    let l = cross(x, v);
    let a = cross(v, &l);
    let r = norm(x);
    [0, 1, 2].map(|k| a[k] - gm * x[k] / r)
}

#[test]
fn energy_angular_momentum_and_the_lrl_vector_are_kept_to_round_off() {
    // n steps of 0.137 P: each invariant may wander like a random walk of
    // rounding errors, ~ε√n times the size of its terms, never drift like
    // ε·n. The bound is 8ε√n times the size of the invariant's terms
    // (`|v|²/2 + GM/r`; `|x||v|`; `GM + |v||L|`), the scale of the rounding
    // of one evaluation; the measured worst ratios are printed.
    let n = 4000;
    let mut worst = [0.0f64; 3];
    for e in [0.0, 0.1, 0.5, 0.9, 0.99, 0.999] {
        for gm in [1.0, 2.95912208286e-4] {
            let (x0, v0) = state(gm, 1.0, e, 0.3);
            let period = 2.0 * PI / gm.sqrt();
            let h = 0.137 * period;
            let (e0, _) = energy(gm, &x0, &v0);
            let l0 = cross(&x0, &v0);
            let a0 = lrl(gm, &x0, &v0);
            let (mut x, mut v) = (x0, v0);
            let (mut de, mut dl, mut da) = (0.0f64, 0.0f64, 0.0f64);
            let (mut e_scale, mut a_scale, mut l_scale) = (0.0f64, 0.0f64, 0.0f64);
            for _ in 0..n {
                drift(gm, h, &mut x, &mut v).unwrap();
                let (en, sc) = energy(gm, &x, &v);
                e_scale = e_scale.max(sc);
                de = de.max((en - e0).abs());
                let l = cross(&x, &v);
                // |x||v|: the size of the cross product's terms.
                l_scale = l_scale.max(norm(&x) * norm(&v));
                dl = dl.max(norm(&[l[0] - l0[0], l[1] - l0[1], l[2] - l0[2]]));
                let a = lrl(gm, &x, &v);
                // |v × L| and GM: the sizes of the LRL vector's two terms.
                a_scale = a_scale.max(gm + norm(&v) * norm(&l));
                da = da.max(norm(&[a[0] - a0[0], a[1] - a0[1], a[2] - a0[2]]));
            }
            let unit = EPS * (n as f64).sqrt();
            let ratios = [
                de / (unit * e_scale),
                dl / (unit * l_scale),
                da / (unit * a_scale),
            ];
            for (w, r) in worst.iter_mut().zip(ratios) {
                *w = w.max(r);
            }
            // At e = 0.999 each step passes a pericentre at r = a/1000 and
            // its conditioning κ (≈ 3.7e3 here, against 5–330 for e ≤ 0.99)
            // enlarges what one step's rounding does to the invariants;
            // measured, up to 17 (not 8) times ε√n·scale, so there the bound is
            // 8·√(1 + κ).
            let bound = if e > 0.99 {
                8.0 * (1.0 + kappa(gm, h, x0, v0)).sqrt()
            } else {
                8.0
            };
            println!("e = {e}, GM = {gm}: ratios {ratios:.2?}, bound {bound:.1}");
            let what = ["energy", "angular momentum", "LRL vector"];
            for (r, w) in ratios.iter().zip(what) {
                assert!(
                    *r <= bound,
                    "e = {e}, GM = {gm}: {w} {:e} > {bound}·ε√n·scale",
                    r * unit
                );
            }
        }
    }
    println!(
        "worst error/(ε√n·scale): energy {:.2}, L {:.2}, LRL {:.2}",
        worst[0], worst[1], worst[2]
    );
}

#[test]
fn the_flow_is_a_group_to_round_off() {
    // φ_{h1}∘φ_{h2} = φ_{h1+h2} and φ_{−h}∘φ_h = id; the rounding of each
    // drift is carried by the Jacobian of the next, hence the products of
    // conditionings in the bound.
    let mut cases: Vec<(f64, f64, f64, f64, f64)> = Vec::new(); // (a, e, nu, h1, h2)
    for e in [0.0, 0.5, 0.9, 0.999] {
        let p = 2.0 * PI;
        cases.push((1.0, e, 0.7, 0.3 * p, 0.45 * p));
        cases.push((1.0, e, -1.3, 2.2 * p, -0.7 * p));
        cases.push((1.0, e, 2.9, 0.01 * p, 4.5 * p));
    }
    for e in [1.001, 1.5, 3.0] {
        cases.push((-1.0, e, 0.2, 0.7, 2.5));
        cases.push((-1.0, e, -0.4, 3.0, -1.0));
    }
    for (a, e, nu, h1, h2) in cases {
        let gm = 1.0;
        let (x0, v0) = state(gm, a, e, nu);
        let (mut x, mut v) = (x0, v0);
        drift(gm, h2, &mut x, &mut v).unwrap();
        let (xm, vm) = (x, v);
        drift(gm, h1, &mut x, &mut v).unwrap();
        let (mut y, mut w) = (x0, v0);
        drift(gm, h1 + h2, &mut y, &mut w).unwrap();
        let k1 = kappa(gm, h1, xm, vm);
        let k2 = kappa(gm, h2, x0, v0);
        let k12 = kappa(gm, h1 + h2, x0, v0);
        let yd = y.map(Dd::new);
        let wd = w.map(Dd::new);
        let d = scaled_error(&x, &v, &yd, &wd);
        let bound = C * EPS * ((1.0 + k1) * (1.0 + k2) + 1.0 + k12);
        assert!(
            d <= bound,
            "e = {e}, h1 = {h1}, h2 = {h2}: {d:e} > {bound:e}"
        );

        // Back again.
        let (mut x, mut v) = (x0, v0);
        drift(gm, h1, &mut x, &mut v).unwrap();
        let kb = kappa(gm, -h1, x, v);
        drift(gm, -h1, &mut x, &mut v).unwrap();
        let d = scaled_error(&x, &v, &x0.map(Dd::new), &v0.map(Dd::new));
        let k = kappa(gm, h1, x0, v0);
        let bound = C * EPS * (1.0 + kb) * (1.0 + k);
        assert!(d <= bound, "e = {e}, h = ±{h1}: {d:e} > {bound:e}");
    }
}

#[test]
fn bad_input_is_an_error_and_leaves_the_state_alone() {
    let (x0, v0) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    for gm in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let (mut x, mut v) = (x0, v0);
        let err = drift(gm, 0.1, &mut x, &mut v).unwrap_err();
        assert!(matches!(err, KeplerError::BadGm { .. }), "{err}");
        assert!(err.to_string().contains("GM"), "{err}");
        assert_eq!((x, v), (x0, v0));
    }
    let (mut x, mut v) = (x0, v0);
    assert!(matches!(
        drift(1.0, f64::NAN, &mut x, &mut v),
        Err(KeplerError::BadStep { .. })
    ));
    let (mut x, mut v) = ([0.0; 3], v0);
    assert_eq!(
        drift(1.0, 0.1, &mut x, &mut v),
        Err(KeplerError::ZeroPosition)
    );
    let (mut x, mut v) = (x0, [0.0, f64::INFINITY, 0.0]);
    let err = drift(1.0, 0.1, &mut x, &mut v).unwrap_err();
    assert_eq!(
        err,
        KeplerError::NonFinite {
            what: "v",
            index: 1,
            value: f64::INFINITY
        }
    );
    assert!(err.to_string().contains("v[1]"), "{err}");

    // A solve allowed one iteration cannot converge on a long step of an
    // eccentric orbit: the error carries the count and the residual.
    let solver = KeplerSolver {
        max_iterations: 1,
        ..KeplerSolver::default()
    };
    let (x1, v1) = state(1.0, 1.0, 0.9, 0.5);
    let (mut x, mut v) = (x1, v1);
    let err = solver.drift(1.0, 2.345, &mut x, &mut v).unwrap_err();
    match &err {
        KeplerError::NotConverged {
            iterations,
            residual,
            ..
        } => {
            assert_eq!(*iterations, 1);
            assert!(residual.is_finite() && *residual != 0.0, "{err}");
        }
        other => panic!("expected NotConverged, got {other}"),
    }
    assert!(
        err.to_string().contains("did not converge in 1 iterations"),
        "{err}"
    );
    assert_eq!((x, v), (x1, v1));

    // A hyperbola followed beyond the range of f64.
    let (mut x, mut v) = ([1.0, 0.0, 0.0], [0.0, 10.0, 0.0]);
    let err = drift(1.0, f64::MAX / 4.0, &mut x, &mut v).unwrap_err();
    assert!(matches!(err, KeplerError::Overflow { .. }), "{err}");
    assert_eq!((x, v), ([1.0, 0.0, 0.0], [0.0, 10.0, 0.0]));

    // h = 0 is the identity, bit for bit.
    let (mut x, mut v) = (x1, v1);
    drift(1.0, 0.0, &mut x, &mut v).unwrap();
    assert_eq!((x, v), (x1, v1));
}

/// The slope of the least-squares line through `(ln t, ln y)`.
fn fitted_exponent(t: &[f64], y: &[f64]) -> f64 {
    let n = t.len() as f64;
    let lx: Vec<f64> = t.iter().map(|t| t.ln()).collect();
    let ly: Vec<f64> = y.iter().map(|y| y.ln()).collect();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = lx.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

fn sci(v: &[f64]) -> String {
    v.iter()
        .map(|x| format!("{x:.2e}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The growth of the rounding error: eight orbits (e = 0, 0.1, 0.5, 0.9,
/// two starting phases each) stepped with `h = frac·P` for `10^top`
/// orbits; at half-decades from 10^2.5 orbits, the RMS over the runs of
/// the energy error (relative to the size of the energy's terms) and of
/// the phase error `n·(Δx·v)/|v|²` (the along-track error as an angle,
/// against the double-double flow over the whole time `k·h`), and the
/// exponents fitted to them.
struct Growth {
    steps: Vec<usize>,
    energy: Vec<f64>,
    phase: Vec<f64>,
    energy_exponent: f64,
    phase_exponent: f64,
}

fn growth(frac: f64, top: f64) -> Growth {
    let gm = 1.0;
    let period = 2.0 * PI;
    let h = frac * period;
    let points = ((top - 2.5) / 0.5).round() as usize + 1;
    let steps: Vec<usize> = (0..points)
        .map(|j| (10f64.powf(2.5 + 0.5 * j as f64) / frac).round() as usize)
        .collect();
    let mut e_sq = vec![0.0; points];
    let mut m_sq = vec![0.0; points];
    let mut runs = 0;
    for e in [0.0, 0.1, 0.5, 0.9] {
        for nu in [0.3, 2.5] {
            runs += 1;
            let (x0, v0) = state(gm, 1.0, e, nu);
            let (e0, scale) = energy(gm, &x0, &v0);
            let (mut x, mut v) = (x0, v0);
            let mut done = 0;
            for (c, &k) in steps.iter().enumerate() {
                for _ in done..k {
                    drift(gm, h, &mut x, &mut v).unwrap();
                }
                done = k;
                let de = (energy(gm, &x, &v).0 - e0) / scale;
                let t = Dd::new(h) * Dd::new(k as f64);
                let (xr, vr) = double_double::flow_dd(gm, t, x0, v0).expect("reference");
                let dx = [0, 1, 2].map(|i| (Dd::new(x[i]) - xr[i]).f64());
                let vr = vr.map(Dd::f64);
                let along = (dx[0] * vr[0] + dx[1] * vr[1] + dx[2] * vr[2])
                    / (vr[0] * vr[0] + vr[1] * vr[1] + vr[2] * vr[2]);
                let dm = along * 2.0 * PI / period;
                e_sq[c] += de * de;
                m_sq[c] += dm * dm;
            }
        }
    }
    let t: Vec<f64> = steps.iter().map(|&k| k as f64).collect();
    let rms = |s: &[f64]| {
        s.iter()
            .map(|x| (x / runs as f64).sqrt())
            .collect::<Vec<_>>()
    };
    let (energy, phase) = (rms(&e_sq), rms(&m_sq));
    Growth {
        energy_exponent: fitted_exponent(&t, &energy),
        phase_exponent: fitted_exponent(&t, &phase),
        steps,
        energy,
        phase,
    }
}

#[test]
fn the_rounding_error_grows_like_rounding_error() {
    // 16.2 steps per orbit (h = P/(10φ), φ the golden ratio, so that the
    // steps never fall back on the same phases) over 10⁵ orbits. Unbiased
    // rounding makes the energy a random walk, |ΔE| ~ t^½, and the phase,
    // which integrates the mean motion's error, ~ t^{3/2}; a systematic
    // error of b ulps per step adds b·n, and its phase b·n². Before the
    // Stumpff series compensated its coefficients' rounding and f or ġ
    // came from the Wronskian identity (see `kepler::update`), there was
    // such a bias, a few thousandths of an ulp per step, and the fitted
    // exponents were 0.81 (energy) and 1.76 (phase), with RMS(ΔE)/n at 10⁵
    // orbits 0.0062 ulp; measured now, 0.58, 1.54 and 0.0010 (the
    // remaining ~0.001 ulp per step is largest at e = 0, where every step
    // repeats nearly the same scalar arithmetic, so that its roundings
    // correlate: the likely cause, not a proven one).
    // The test bounds the exponents near the random walk's and that bias
    // bound below 0.003 ulp, so the bias cannot come back unnoticed.
    let g = growth(0.1 / 1.618033988749895, 5.0);
    println!(
        "energy RMS {}, fitted exponent {:.3}",
        sci(&g.energy),
        g.energy_exponent
    );
    println!(
        "phase RMS {}, fitted exponent {:.3}",
        sci(&g.phase),
        g.phase_exponent
    );
    let n = *g.steps.last().unwrap() as f64;
    let bias = g.energy.last().unwrap() / n / EPS;
    println!("energy bias per step ≤ {bias:.4} ulp");
    assert!(
        (0.4..=0.7).contains(&g.energy_exponent),
        "energy error grows like t^{:.3}, not like rounding's random walk (½)",
        g.energy_exponent
    );
    assert!(
        (1.3..=1.7).contains(&g.phase_exponent),
        "phase error grows like t^{:.3}, not like rounding's t^{{3/2}}",
        g.phase_exponent
    );
    assert!(
        bias < 0.003,
        "a systematic energy error of {bias:.4} ulp per step"
    );
}

#[test]
#[ignore = "a measurement (10⁶ orbits, about a minute in release): cargo test --release -p integrator-core --test integration kepler_flow::a_million_orbits -- --ignored --nocapture"]
fn a_million_orbits() {
    for frac in [0.1 / 1.618033988749895, 0.6 / 1.618033988749895] {
        let g = growth(frac, 6.0);
        let n = *g.steps.last().unwrap() as f64;
        println!(
            "h = {frac:.4} P, 10⁶ orbits: energy RMS {}, exponent {:.3}, bias ≤ {:.4} ulp/step",
            sci(&g.energy),
            g.energy_exponent,
            g.energy.last().unwrap() / n / EPS
        );
        println!(
            "h = {frac:.4} P, 10⁶ orbits: phase RMS {}, exponent {:.3}",
            sci(&g.phase),
            g.phase_exponent
        );
        assert!(
            g.energy
                .iter()
                .chain(&g.phase)
                .all(|x| x.is_finite() && *x < 1e-3)
        );
    }
}

#[test]
fn lanes_give_the_scalar_drift_bit_for_bit() {
    // Every orbit of the accuracy grid and the hyperbolae, four at a time
    // in mixed groups (different GM, e and phase side by side), at steps
    // from 10⁻⁵ of a period (the one-evaluation path in every lane, with
    // 5, 7 or 10 Stumpff terms) to several periods (the scalar fallback),
    // both ways; and groups of fewer than LANES orbits.
    let solver = KeplerSolver::default();
    let mut orbits: Vec<(f64, [f64; 3], [f64; 3], f64)> = Vec::new(); // (gm, x, v, period or 1/n)
    for c in bound_cases().into_iter().step_by(8) {
        let (x, v) = state(c.gm, c.a, c.e, c.nu);
        orbits.push((c.gm, x, v, 2.0 * PI * (c.a.powi(3) / c.gm).sqrt()));
    }
    for c in hyperbolic_cases().into_iter().step_by(7) {
        let (x, v) = state(c.gm, c.a, c.e, c.nu);
        orbits.push((c.gm, x, v, 1.0));
    }
    let mut quick_lanes = 0;
    let mut compared = 0;
    for frac in [
        1e-5, 3e-4, 2e-3, 0.01, 0.03, 0.05, 0.1, 0.15, 0.22, 0.3, 1.7, -0.02, -0.2, -2.5,
    ] {
        for used in [LANES, 1, LANES - 1] {
            for group in orbits.chunks(used) {
                // One h for the group (the lanes share it), from the
                // first orbit's period.
                let h = frac * group[0].3;
                let mut gm = [1.0; LANES];
                let mut x = [[0.0; 3]; LANES];
                let mut v = [[0.0; 3]; LANES];
                for (l, o) in group.iter().enumerate() {
                    gm[l] = o.0;
                    x[l] = o.1;
                    v[l] = o.2;
                }
                let (x_in, v_in) = (x, v);
                solver
                    .drift_lanes(&gm, h, &mut x, &mut v, group.len())
                    .unwrap_or_else(|(l, e)| panic!("lane {l}, h = {h}: {e}"));
                for (l, o) in group.iter().enumerate() {
                    let (mut xs, mut vs) = (o.1, o.2);
                    solver.drift(o.0, h, &mut xs, &mut vs).unwrap();
                    let bits = |a: &[f64; 3]| a.map(f64::to_bits);
                    assert_eq!(
                        (bits(&x[l]), bits(&v[l])),
                        (bits(&xs), bits(&vs)),
                        "lane {l}, GM = {}, h = {h}, x = {:?}, v = {:?}",
                        o.0,
                        o.1,
                        o.2
                    );
                    compared += 1;
                    if frac.abs() < 0.05 {
                        quick_lanes += 1;
                    }
                }
                for l in group.len()..LANES {
                    assert_eq!((x[l], v[l]), (x_in[l], v_in[l]), "padding lane {l} moved");
                }
            }
        }
    }
    println!("{compared} lanes compared, {quick_lanes} at steps under P/20");
}

#[test]
fn a_failing_lane_is_named_and_the_lanes_after_it_are_left_alone() {
    let solver = KeplerSolver::default();
    let (x0, v0) = state(1.0, 1.0, 0.3, 0.5);
    let gm = [1.0, 1.0, -2.0, 1.0];
    let mut x = [x0; LANES];
    let mut v = [v0; LANES];
    let err = solver
        .drift_lanes(&gm, 0.01, &mut x, &mut v, LANES)
        .unwrap_err();
    assert_eq!(err.0, 2);
    assert!(
        matches!(err.1, KeplerError::BadGm { gm } if gm == -2.0),
        "{:?}",
        err.1
    );
    let (mut xs, mut vs) = (x0, v0);
    drift(1.0, 0.01, &mut xs, &mut vs).unwrap();
    assert_eq!((x[0], v[0]), (xs, vs));
    assert_eq!((x[1], v[1]), (xs, vs));
    assert_eq!((x[2], v[2]), (x0, v0));
    assert_eq!((x[3], v[3]), (x0, v0));

    // A non-finite coordinate in lane 1, and h = 0 (the identity).
    let mut x = [x0; LANES];
    let mut v = [v0; LANES];
    v[1][2] = f64::NAN;
    let err = solver
        .drift_lanes(&[1.0; LANES], 0.01, &mut x, &mut v, 3)
        .unwrap_err();
    assert!(
        matches!(
            err,
            (
                1,
                KeplerError::NonFinite {
                    what: "v",
                    index: 2,
                    ..
                }
            )
        ),
        "{err:?}"
    );
    let mut x = [x0; LANES];
    let mut v = [v0; LANES];
    solver
        .drift_lanes(&[1.0; LANES], 0.0, &mut x, &mut v, LANES)
        .unwrap();
    assert_eq!((x, v), ([x0; LANES], [v0; LANES]));
}

#[test]
#[ignore = "a diagnostic: KEP_BIAS_STEPS=… cargo test -p integrator-core --test integration kepler_flow::energy_bias -- --ignored --nocapture"]
fn energy_bias_per_step() {
    // The signed mean over many orbits of the energy change after n
    // steps, divided by n: a systematic error per step, with its standard
    // error (the spread of the runs / √runs / n).
    let n: usize = std::env::var("KEP_BIAS_STEPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(100_000);
    for frac in [0.1 / 1.618033988749895, 1.0 / 433.0] {
        let mut d = Vec::new();
        for e in [0.0, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9] {
            for j in 0..8 {
                let nu = 0.37 + 0.77 * j as f64;
                let (x0, v0) = state(1.0, 1.0, e, nu);
                let (e0, scale) = energy(1.0, &x0, &v0);
                let (mut x, mut v) = (x0, v0);
                for _ in 0..n {
                    drift(1.0, frac * 2.0 * PI, &mut x, &mut v).unwrap();
                }
                d.push((energy(1.0, &x, &v).0 - e0) / scale / EPS);
            }
            let last = &d[d.len() - 8..];
            let m = last.iter().sum::<f64>() / 8.0;
            println!(
                "  e = {e}: mean {:+.5} ulp/step, runs {:?}",
                m / n as f64,
                last.iter().map(|x| x.round()).collect::<Vec<_>>()
            );
        }
        let runs = d.len() as f64;
        let mean = d.iter().sum::<f64>() / runs;
        let sd = (d.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (runs - 1.0)).sqrt();
        println!(
            "h = P/{:.1}, {n} steps, {runs} runs: bias per step {:+.5} ± {:.5} ulp, spread {:.1} ulp (random walk √n = {:.0})",
            1.0 / frac,
            mean / n as f64,
            sd / runs.sqrt() / n as f64,
            sd,
            (n as f64).sqrt()
        );
    }
}

#[test]
#[ignore = "a measurement (the evaluation counts quoted at KeplerSolver::DEFAULT_MAX_ITERATIONS): cargo test --release -p integrator-core --test integration kepler_flow::evaluation_counts -- --ignored --nocapture"]
fn evaluation_counts() {
    // The fewest evaluations (Halley or bisection steps) with which each
    // solve of the accuracy grid succeeds: `max_iterations` probed from 1.
    let mut counts = Vec::new();
    let mut worst = (0, String::new());
    for c in bound_cases().into_iter().chain(hyperbolic_cases()) {
        let (x0, v0) = state(c.gm, c.a, c.e, c.nu);
        let k = (1..=KeplerSolver::DEFAULT_MAX_ITERATIONS)
            .find(|&k| {
                let solver = KeplerSolver {
                    max_iterations: k,
                    ..KeplerSolver::default()
                };
                let (mut x, mut v) = (x0, v0);
                solver.drift(c.gm, c.h, &mut x, &mut v).is_ok()
            })
            .expect("every solve of the grid converges");
        if k > worst.0 {
            worst = (k, format!("e = {}, ν = {:.2}, h = {:.3e}", c.e, c.nu, c.h));
        }
        counts.push(k);
    }
    let n = counts.len() as f64;
    let share = |m: usize| counts.iter().filter(|&&k| k <= m).count() as f64 / n;
    println!(
        "{} solves: 1 evaluation {:.0} %, ≤ 2 {:.0} %, ≤ 3 {:.0} %, at most {} ({})",
        counts.len(),
        100.0 * share(1),
        100.0 * share(2),
        100.0 * share(3),
        worst.0,
        worst.1
    );
}
