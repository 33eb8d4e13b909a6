//! The average vector field discrete gradient of the cloth
//! (`ClothModel::avf_force`), its potential (`avf_potential`) and its
//! projected Jacobian (`avf_jacobian_values_projected`): the energy identity
//! to round-off, agreement with adaptive quadrature of `−∫∇V` and of
//! `∫(V(q + ξΔ) − V(q))/ξ`, `−F̄ = ∇U`, `q₁ = q` giving the force, zero net
//! spring force, a symmetric PSD Jacobian that is the derivative of `−F̄`
//! where nothing is projected, and a whole AVF step solved as a minimisation
//! keeping the energy.
//!
//! Configurations are seeded and include the near-degenerate ones: `δ` tiny
//! and huge, a spring compressed, a segment passing within `η` of zero
//! length (`η = 0` included), a segment ending at zero length, pinned
//! springs.

use cloth::{ClothModel, Scene};
use integrator_core::Separable;
use nalgebra::{DMatrix, Vector3};

/// 2 × 2 particles, shear springs only, pinned at (0, 0): one free–free
/// spring (particles (1, 0)–(0, 1)) and one free–pinned ((0, 0)–(1, 1)),
/// each alone, so their geometry can be set at will. Rest length √2.
const TWO: &str = r#"
gravity = [0.0, -9.81, 0.0]

[cloth]
width = 1.0
height = 1.0
nx = 2
ny = 2

[material]
density = 0.2
shear = 30.0

[pins]
corners = ["top-left"]
[simulation]
substeps = 1
frames = 1
method = "midpoint"
"#;

/// 6 × 5 particles, all three families, pinned at two corners, gravity,
/// starting stretched by 5 % (no colliders: the AVF leaves them out).
const SMALL: &str = r#"
gravity = [0.0, -9.81, 0.0]

[cloth]
width = 0.4
height = 0.3
nx = 6
ny = 5
prestretch = 1.05

[material]
density = 0.2
stretch = 30.0
shear = 8.0
bend = 0.5

[pins]
corners = ["top-left", "top-right"]
[simulation]
substeps = 1
frames = 1
method = "midpoint"
"#;

/// 5 × 5 particles, no pins, gravity: the springs' forces must cancel.
const FREE: &str = r#"
gravity = [0.0, -9.81, 0.0]

[cloth]
width = 0.5
height = 0.5
nx = 5
ny = 5
prestretch = 1.05
origin = [0.3, -0.2, 0.1]

[material]
density = 0.1
stretch = 40.0
shear = 10.0
bend = 1.0
[simulation]
substeps = 1
frames = 1
method = "midpoint"
"#;

const EPS: f64 = f64::EPSILON;

fn model(text: &str) -> ClothModel {
    ClothModel::new(&Scene::from_toml(text, "inline.toml").unwrap()).unwrap()
}

/// A deterministic pseudo-random sequence in [-1, 1).
fn noise(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

fn random_unit(r: &mut impl FnMut() -> f64) -> Vector3<f64> {
    loop {
        let v = Vector3::new(r(), r(), r());
        let n = v.norm();
        if n > 0.1 && n <= 1.0 {
            return v / n;
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Gauss–Legendre nodes and weights on [0, 1], by Newton's method on the
/// Legendre polynomial (independent of the library's tables).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for k in 1..=n {
        let mut x = (std::f64::consts::PI * (k as f64 - 0.25) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for j in 2..=n {
                let p2 = ((2 * j - 1) as f64 * x * p1 - (j - 1) as f64 * p0) / j as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-17 {
                break;
            }
        }
        out.push(((1.0 - x) / 2.0, 1.0 / ((1.0 - x * x) * dp * dp)));
    }
    out
}

/// `∫₀¹ f` of a vector-valued `f` by adaptive 10-point Gauss–Legendre:
/// starting from 32 panels, each is split until its halves agree with it to `tol·width` or to
/// 8 ulps of the panel's `∫|f|` (its round-off), at most 45 halvings deep,
/// so a jump costs a few hundred panels.
fn integrate(f: &mut dyn FnMut(f64, &mut [f64]), dim: usize, tol: f64) -> Vec<f64> {
    let rule = gauss_legendre(10);
    let mut scratch = vec![0.0; dim];
    // (∫f, max ∫|f|) over [a, b].
    let mut panel = |f: &mut dyn FnMut(f64, &mut [f64]), a: f64, b: f64| -> (Vec<f64>, f64) {
        let mut sum = vec![0.0; dim];
        let mut abs = vec![0.0; dim];
        for &(x, w) in &rule {
            f(a + (b - a) * x, &mut scratch);
            for ((s, t), v) in sum.iter_mut().zip(abs.iter_mut()).zip(&scratch) {
                *s += w * (b - a) * v;
                *t += w * (b - a) * v.abs();
            }
        }
        (sum, abs.iter().fold(0.0f64, |m, x| m.max(*x)))
    };
    let mut out = vec![0.0; dim];
    // 32 panels to start with, so that no feature hides between the nodes
    // of a coarse panel and its halves.
    let mut stack = Vec::new();
    for k in 0..32 {
        let (a, b) = (k as f64 / 32.0, (k + 1) as f64 / 32.0);
        stack.push((a, b, panel(f, a, b).0, 0usize));
    }
    let mut panels = 0;
    while let Some((a, b, whole, depth)) = stack.pop() {
        panels += 1;
        assert!(
            panels < 100_000,
            "quadrature: tolerance {tol:e} not reached at [{a}, {b}], depth {depth}"
        );
        let m = 0.5 * (a + b);
        let (left, la) = panel(f, a, m);
        let (right, ra) = panel(f, m, b);
        let err = left
            .iter()
            .zip(&right)
            .zip(&whole)
            .fold(0.0f64, |e, ((l, r), w)| e.max((l + r - w).abs()));
        if err <= tol * (b - a) || err <= 8.0 * EPS * (la + ra) || depth >= 45 {
            for ((o, l), r) in out.iter_mut().zip(&left).zip(&right) {
                *o += l + r;
            }
        } else {
            stack.push((a, m, left, depth + 1));
            stack.push((m, b, right, depth + 1));
        }
    }
    out
}

/// `−∫₀¹ ∇V(q + ξ(q₁ − q)) dξ` by adaptive quadrature of the model's force.
fn force_by_quadrature(m: &ClothModel, q: &[f64], q1: &[f64], tol: f64) -> Vec<f64> {
    let n = q.len();
    let mut x = vec![0.0; n];
    integrate(
        &mut |xi, out| {
            for ((x, a), b) in x.iter_mut().zip(q).zip(q1) {
                *x = a + xi * (b - a);
            }
            m.force(&x, out);
            // Where the positions round to a spring of length exactly 0 its
            // force is undefined (0·∞); a bounded integrand's value on such
            // a point does not matter.
            for v in out.iter_mut().filter(|v| v.is_nan()) {
                *v = 0.0;
            }
        },
        n,
        tol,
    )
}

/// `F̄` of [`TWO`] from the spring law itself: each spring's
/// `(k/L)[(d + δ/2) − L·∫₀¹ r̂ dξ]` (pulling `a` towards `b`), plus the
/// weights. `∫₀¹ r̂ dξ = (1/|δ|)∫ (p + tδ̂)/√(η² + t²) dt` over
/// `t ∈ [d·δ̂, d₁·δ̂]` (`p` the part of `d` across `δ`, `η = |p|`), by
/// adaptive quadrature on either side of `t = 0` (where `r̂` turns, or jumps
/// when `η = 0`): in `t` the integrand is evaluated without the
/// cancellation of forming `d + ξδ` near zero length.
fn two_force_by_quadrature(m: &ClothModel, q: &[f64], q1: &[f64], tol: f64) -> Vec<f64> {
    let (p0, p1) = (m.positions(q), m.positions(q1));
    let rest = 2f64.sqrt();
    let kl = 30.0 / rest;
    let mut f = vec![0.0; q.len()];
    for x in f.chunks_mut(3) {
        x.copy_from_slice(m.weight().as_slice());
    }
    // The model's orientation: d = x_b − x_a for (1, 2), d = pin − x₃.
    for (a, b) in [(1usize, 2usize), (3, 0)] {
        let d = p0[b] - p0[a];
        let delta = (p1[b] - p1[a]) - d;
        let len = delta.norm();
        let mean = if len == 0.0 {
            d / d.norm()
        } else {
            let dh = delta / len;
            let (s0, s1) = (d.dot(&dh), (p1[b] - p1[a]).dot(&dh));
            let p = d - dh * s0;
            let eta2 = p.norm_squared();
            let mut sum = Vector3::zeros();
            // Pieces `t = from + (to − from)·u` starting where `|t|` is
            // least, so that `t` near 0 carries no cancellation.
            let pieces = if s0 < 0.0 && s1 > 0.0 {
                [(0.0, s0), (0.0, s1)]
            } else if s0.abs() <= s1.abs() {
                [(s0, s1), (s1, s1)]
            } else {
                [(s1, s0), (s1, s1)]
            };
            for (from, to) in pieces {
                if from == to {
                    continue;
                }
                let part = integrate(
                    &mut |u, out| {
                        let t = from + (to - from) * u;
                        let r = (p + dh * t) / (eta2 + t * t).sqrt();
                        out.copy_from_slice(r.as_slice());
                    },
                    3,
                    tol,
                );
                sum += Vector3::from_column_slice(&part) * (to - from).abs();
            }
            sum / (s1 - s0)
        };
        let g = (d + delta * 0.5 - mean * rest) * kl;
        for (id, sign) in [(a, 1.0), (b, -1.0)] {
            if let Some(k) = m.free_index(id % 2, id / 2) {
                for c in 0..3 {
                    f[3 * k + c] += sign * g[c];
                }
            }
        }
    }
    f
}

/// The energy scale the identity's round-off is relative to: every spring
/// term `(k/L)(ℓ₀² + ℓ₁² + L² + |δ|²)` is at most `7·kL(1 + s)²` with `s`
/// the largest strain at `q` or `q₁`, i.e. `14·elastic_energy_scale(1 + s)`,
/// and gravity's terms `|m g|(|x| + |x₁|)`.
fn energy_scale(m: &ClothModel, q: &[f64], q1: &[f64]) -> f64 {
    let s = m.max_strain(q).max(m.max_strain(q1));
    let w = m.weight().norm();
    let gravity: f64 = q
        .chunks(3)
        .zip(q1.chunks(3))
        .map(|(a, b)| {
            w * (Vector3::from_column_slice(a).norm() + Vector3::from_column_slice(b).norm())
        })
        .sum();
    14.0 * m.elastic_energy_scale(1.0 + s) + gravity
}

/// `V(q₁) − V(q) + F̄·(q₁ − q)`, and the energy scale.
fn identity_defect(m: &ClothModel, q: &[f64], q1: &[f64]) -> (f64, f64) {
    let mut f = vec![0.0; q.len()];
    m.avf_force(q, q1, &mut f);
    let dq: Vec<f64> = q1.iter().zip(q).map(|(b, a)| b - a).collect();
    let defect = m.potential(q1) - m.potential(q) + dot(&f, &dq);
    (defect, energy_scale(m, q, q1))
}

/// The two springs of [`TWO`] as `(id a, id b)`; particle ids `j·2 + i`.
const TWO_SPRINGS: [(usize, usize); 2] = [(1, 2), (0, 3)];

/// Positions of [`TWO`] with the free–free spring's vector `d_ff = x₂ − x₁`
/// and the pinned one's `d_fp = x₃ − x₀` (particle 0 pinned at its start).
fn two_state(
    m: &ClothModel,
    d_ff: Vector3<f64>,
    d_fp: Vector3<f64>,
    shift: Vector3<f64>,
) -> Vec<f64> {
    let pos = m.positions(&m.initial_state()[..m.dof()]);
    let mut q = vec![0.0; m.dof()];
    let mut put = |id: usize, x: Vector3<f64>| {
        let k = m.free_index(id % 2, id / 2).unwrap();
        q[3 * k..3 * k + 3].copy_from_slice(x.as_slice());
    };
    let x1 = pos[1] + shift;
    put(1, x1);
    put(2, x1 + d_ff);
    put(3, pos[0] + d_fp);
    q
}

/// `U` of [`TWO`] by adaptive quadrature of the cancellation-free integrand
/// `(k/L)(2d·δ + ξ|δ|²)(½ − L/(ℓ(ξ) + ℓ₀))` per spring, plus gravity.
fn two_potential_by_quadrature(m: &ClothModel, q: &[f64], q1: &[f64], tol: f64) -> f64 {
    let (p0, p1) = (m.positions(q), m.positions(q1));
    let rest = 2f64.sqrt();
    let kl = 30.0 / rest;
    let mut u = 0.0;
    for (a, b) in TWO_SPRINGS {
        let d = p0[b] - p0[a];
        let delta = (p1[b] - p1[a]) - d;
        let (dd, aa, l0) = (d.dot(&delta), delta.norm_squared(), d.norm());
        u += integrate(
            &mut |xi, out| {
                let l = (d + delta * xi).norm();
                out[0] = kl * (2.0 * dd + xi * aa) * (0.5 - rest / (l + l0));
            },
            1,
            tol,
        )[0];
    }
    let w = m.weight();
    for (a, b) in q.chunks(3).zip(q1.chunks(3)) {
        u -= w.dot(&(Vector3::from_column_slice(b) - Vector3::from_column_slice(a)));
    }
    u
}

/// Pairs `(d, d₁)` for one spring of rest length `L = √2`: random lengths
/// and directions with `|δ|/L` from 1e-14 to 1e3, compressed springs,
/// segments through or near zero length, onto and from zero length, and
/// each of the closed form's cases (`s₀ ≥ 0`; `s₀ < 0` with `s₁ < 0`, with
/// `d·d₁ < 0`, and with `d·d₁ ≥ 0`).
fn spring_pairs(seed: u64) -> Vec<(Vector3<f64>, Vector3<f64>, &'static str)> {
    let l = 2f64.sqrt();
    let mut r = noise(seed);
    let mut out = Vec::new();
    for &size in &[1e-14, 1e-9, 1e-5, 1e-2, 0.1, 0.3, 0.6, 1.0, 3.0, 30.0, 1e3] {
        for _ in 0..6 {
            let d = random_unit(&mut r) * l * (1.0 + 0.4 * r());
            let d1 = d + random_unit(&mut r) * l * size * (1.0 + 0.5 * r());
            out.push((d, d1, "random"));
        }
    }
    for _ in 0..6 {
        let d = random_unit(&mut r) * l * (0.3 + 0.2 * r());
        let d1 = random_unit(&mut r) * l * (0.5 + 0.2 * r());
        out.push((d, d1, "compressed"));
        out.push((d, d * (0.7 + 0.1 * r()), "compressed, collinear"));
    }
    let e = Vector3::new(0.6, 0.8, 0.0);
    let across = Vector3::new(-0.8, 0.6, 0.0);
    for &eta in &[0.0, 1e-300, 1e-15, 1e-9, 1e-4, 0.3] {
        for &(t0, t1) in &[
            (-0.37, 0.81),
            (-1.3, 0.2),
            (-0.05, 1.7),
            (-1.0, -0.2),
            (-1.0, -0.999),
            (-1.0, 1e-3),
            (-1e-3, 1.0),
            (0.2, 1.3),
            (-1.0, 0.0),
            (0.0, 1.0),
        ] {
            let d = e * (t0 * l) + across * (eta * l);
            let d1 = e * (t1 * l) + across * (eta * l);
            out.push((d, d1, "near zero length"));
            out.push((d1, d, "near zero length, reversed"));
        }
    }
    out.push((
        Vector3::zeros(),
        Vector3::new(0.3, -0.2, 0.9),
        "from zero length",
    ));
    out.push((
        Vector3::new(0.3, -0.2, 0.9),
        Vector3::zeros(),
        "onto zero length",
    ));
    out.push((
        Vector3::new(0.3, -0.2, 0.9),
        Vector3::new(0.3, -0.2, 0.9),
        "no motion",
    ));
    out
}

/// The [`TWO`] states for a list of spring pairs: the free–free spring
/// takes each pair, the pinned one a pair further on.
fn two_states(m: &ClothModel, seed: u64) -> Vec<(Vec<f64>, Vec<f64>, &'static str)> {
    let pairs = spring_pairs(seed);
    let mut r = noise(seed ^ 0x5555);
    (0..pairs.len())
        .map(|i| {
            let (d, d1, what) = pairs[i];
            let (e, e1, _) = pairs[(i * 7 + 3) % pairs.len()];
            let shift = Vector3::new(r(), r(), r()) * 0.3;
            let shift1 = shift + Vector3::new(r(), r(), r()) * 0.2;
            (
                two_state(m, d, e, shift),
                two_state(m, d1, e1, shift1),
                what,
            )
        })
        .collect()
}

/// Random states of a scene: the start perturbed by `amp`, and `q₁` a
/// further random displacement of size `step` (both relative to the grid
/// spacing `h`).
fn random_pair(m: &ClothModel, amp: f64, step: f64, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut r = noise(seed);
    let z = m.initial_state();
    let q: Vec<f64> = z[..m.dof()].iter().map(|x| x + amp * r()).collect();
    let q1: Vec<f64> = q.iter().map(|x| x + step * r()).collect();
    (q, q1)
}

#[test]
fn energy_identity_holds_to_roundoff() {
    let mut worst: f64 = 0.0;
    let two = model(TWO);
    for seed in 1..4 {
        for (q, q1, what) in two_states(&two, seed) {
            let (defect, scale) = identity_defect(&two, &q, &q1);
            assert!(
                defect.abs() <= 32.0 * EPS * scale,
                "{what}: V(q₁) − V(q) + F̄·Δq = {defect:e}, energy scale {scale:e}"
            );
            worst = worst.max(defect.abs() / scale);
        }
    }
    for text in [SMALL, FREE] {
        let m = model(text);
        for seed in 0..40u64 {
            // Steps from 1e-12 to 10 grid spacings, positions shaken by up to
            // 0.5 spacings (springs compressed and stretched).
            let step = 0.08 * 10f64.powi(seed as i32 % 13 - 11);
            let (q, q1) = random_pair(&m, 0.04, step, seed);
            let (defect, scale) = identity_defect(&m, &q, &q1);
            assert!(
                defect.abs() <= 32.0 * EPS * scale,
                "seed {seed}: V(q₁) − V(q) + F̄·Δq = {defect:e}, energy scale {scale:e}"
            );
            worst = worst.max(defect.abs() / scale);
        }
    }
    eprintln!(
        "energy identity: worst |defect|/scale = {worst:e} ({:.1} ε)",
        worst / EPS
    );
}

#[test]
fn force_matches_adaptive_quadrature() {
    let two = model(TWO);
    let mut worst: f64 = 0.0;
    for (q, q1, what) in two_states(&two, 11) {
        let mut f = vec![0.0; q.len()];
        let scale = two.avf_force(&q, &q1, &mut f);
        let reference = two_force_by_quadrature(&two, &q, &q1, 1e-16);
        let err = f
            .iter()
            .zip(&reference)
            .fold(0.0f64, |e, (a, b)| e.max((a - b).abs()));
        assert!(
            err <= 1e-13 * scale,
            "{what}: |F̄ − quadrature| = {err:e}, force scale {scale:e}\n{f:?}\n{reference:?}"
        );
        worst = worst.max(err / scale);
    }
    let m = model(SMALL);
    for seed in 0..6u64 {
        let (q, q1) = random_pair(&m, 0.01, 0.02 * (seed + 1) as f64, seed);
        let mut f = vec![0.0; q.len()];
        let scale = m.avf_force(&q, &q1, &mut f);
        let reference = force_by_quadrature(&m, &q, &q1, 1e-14 * scale);
        let err = f
            .iter()
            .zip(&reference)
            .fold(0.0f64, |e, (a, b)| e.max((a - b).abs()));
        assert!(
            err <= 1e-13 * scale,
            "seed {seed}: {err:e} vs scale {scale:e}"
        );
        worst = worst.max(err / scale);
    }
    eprintln!("force vs quadrature: worst error/scale = {worst:e}");
}

#[test]
fn potential_matches_adaptive_quadrature() {
    let two = model(TWO);
    let mut worst: f64 = 0.0;
    for seed in [21u64, 22] {
        for (q, q1, what) in two_states(&two, seed) {
            let (u, magnitude) = two.avf_potential_and_magnitude(&q, &q1);
            assert_eq!(u, two.avf_potential(&q, &q1));
            let reference = two_potential_by_quadrature(&two, &q, &q1, 1e-16 * magnitude);
            let err = (u - reference).abs();
            assert!(
                err <= 64.0 * EPS * magnitude,
                "{what}: U = {u:e}, quadrature {reference:e}, |U|ₐ = {magnitude:e}"
            );
            if magnitude > 0.0 {
                worst = worst.max(err / magnitude);
            }
        }
    }
    eprintln!(
        "U vs quadrature: worst |error|/|U|ₐ = {worst:e} ({:.1} ε)",
        worst / EPS
    );
}

#[test]
fn potential_gradient_is_minus_the_avf_force() {
    for (text, seeds) in [(SMALL, 0..4u64), (TWO, 4..8)] {
        let m = model(text);
        for seed in seeds {
            let (q, q1) = random_pair(&m, 0.02, 0.03, seed);
            let mut f = vec![0.0; q.len()];
            let scale = m.avf_force(&q, &q1, &mut f);
            let h = 1e-5;
            let mut x = q1.clone();
            for j in 0..q.len() {
                x[j] = q1[j] + h;
                let up = m.avf_potential(&q, &x);
                x[j] = q1[j] - h;
                let down = m.avf_potential(&q, &x);
                x[j] = q1[j];
                let fd = -(up - down) / (2.0 * h);
                assert!(
                    (fd - f[j]).abs() <= 1e-7 * scale,
                    "seed {seed}, component {j}: −∂U/∂q₁ = {fd:e}, F̄ = {:e} (scale {scale:e})",
                    f[j]
                );
            }
        }
    }
}

#[test]
fn no_motion_gives_the_force_and_small_motion_the_midpoint_force() {
    let m = model(SMALL);
    for seed in 0..5u64 {
        let (q, _) = random_pair(&m, 0.02, 0.0, seed);
        let (mut f, mut g) = (vec![0.0; q.len()], vec![0.0; q.len()]);
        m.avf_force(&q, &q, &mut f);
        // The force as the spring lists sum it (`force` is the stencil
        // kernel, which sums a particle's springs in another order).
        m.force_and_scale(&q, &mut g);
        assert_eq!(f, g, "q₁ = q must give F(q) exactly");
        assert_eq!(m.avf_potential(&q, &q), 0.0);
        // |δ| ~ 1e-7·h: F̄ = F((q + q₁)/2) + O(|δ|²).
        let (_, q1) = random_pair(&m, 0.02, 1e-9, seed);
        let q1: Vec<f64> = q1.iter().zip(&q).map(|(b, a)| a + (b - a)).collect();
        let scale = m.avf_force(&q, &q1, &mut f);
        let mid: Vec<f64> = q.iter().zip(&q1).map(|(a, b)| 0.5 * (a + b)).collect();
        m.force(&mid, &mut g);
        let err = f
            .iter()
            .zip(&g)
            .fold(0.0f64, |e, (a, b)| e.max((a - b).abs()));
        assert!(err <= 1e-13 * scale, "seed {seed}: {err:e} vs {scale:e}");
    }
}

#[test]
fn springs_exert_no_net_force() {
    let m = model(FREE);
    assert_eq!(m.pinned_count(), 0);
    let n = m.free_count() as f64;
    for seed in 0..20u64 {
        let step = 0.1 * 10f64.powi(seed as i32 % 10 - 8);
        let (q, q1) = random_pair(&m, 0.05, step, seed);
        let mut f = vec![0.0; q.len()];
        let scale = m.avf_force(&q, &q1, &mut f);
        let total = f
            .chunks(3)
            .fold(Vector3::zeros(), |s, x| s + Vector3::from_column_slice(x));
        let err = (total - m.weight() * n).amax();
        let bound = 4.0 * EPS * m.active_spring_count() as f64 * scale;
        assert!(
            err <= bound,
            "seed {seed}: Σ F̄ − N·mg = {err:e} > {bound:e}"
        );
    }
}

/// The dense matrix of a Jacobian's values on the model's pattern.
fn dense(m: &ClothModel, values: &[f64]) -> DMatrix<f64> {
    let n = m.dof();
    let mut a = DMatrix::zeros(n, n);
    for (&(r, c), v) in m.force_jacobian_pattern().iter().zip(values) {
        a[(r, c)] += v;
    }
    a
}

#[test]
fn jacobian_is_symmetric_psd_and_the_derivative_where_nothing_is_projected() {
    // Stretched along the whole segment, so nothing is projected: small
    // moves of the prestretched (5 %) sheets, |δ|/ℓ below 0.05, where the
    // 4-point rule's error is far below the finite difference's; and the
    // free sheet turned rigidly by 25° (|δ|/ℓ = 0.43, every spring at least
    // 1.05·cos(12.5°) = 1.025 times its rest length on the way), where it is
    // about 7.16⁻⁸ = 1.4e-7.
    let mut cases: Vec<(&str, ClothModel, Vec<f64>, Vec<f64>)> = Vec::new();
    for (name, text, seed) in [
        ("small", SMALL, 1u64),
        ("small", SMALL, 2),
        ("free", FREE, 3),
    ] {
        let m = model(text);
        let (q, q1) = random_pair(&m, 0.0003, 0.0004 * seed as f64, seed);
        cases.push((name, m, q, q1));
    }
    {
        let m = model(FREE);
        let (q, _) = random_pair(&m, 0.0003, 0.0, 8);
        let axis = Vector3::new(0.3, 0.9, 0.3).normalize();
        let (s, c) = 25f64.to_radians().sin_cos();
        let centre = Vector3::new(0.55, -0.2, 0.35);
        let mut q1 = q.clone();
        for x in q1.chunks_mut(3) {
            let r = Vector3::from_column_slice(x) - centre;
            // Rodrigues.
            let turned = r * c + axis.cross(&r) * s + axis * (axis.dot(&r) * (1.0 - c));
            x.copy_from_slice((turned + centre + Vector3::new(0.01, -0.02, 0.03)).as_slice());
        }
        cases.push(("free, turned 25°", m, q, q1));
    }
    for (name, m, q, q1) in cases {
        let mut values = vec![0.0; m.force_jacobian_nnz()];
        m.avf_jacobian_values_projected(&q, &q1, &mut values);
        let j = dense(&m, &values);
        assert_eq!(j, j.transpose(), "not symmetric");
        let mut fp = vec![0.0; q.len()];
        let mut fm = vec![0.0; q.len()];
        let scale = m.avf_force(&q, &q1, &mut fp);
        let h = 1e-6;
        let mut x = q1.clone();
        let stiff = j.amax();
        for c in 0..q.len() {
            x[c] = q1[c] + h;
            m.avf_force(&q, &x, &mut fp);
            x[c] = q1[c] - h;
            m.avf_force(&q, &x, &mut fm);
            x[c] = q1[c];
            for r in 0..q.len() {
                let fd = (fp[r] - fm[r]) / (2.0 * h);
                assert!(
                    (fd - j[(r, c)]).abs() <= 1e-6 * stiff,
                    "{name}: ∂F̄_{r}/∂q₁_{c}: finite difference {fd:e}, Jacobian {:e} (scale {scale:e})",
                    j[(r, c)]
                );
            }
        }
    }
    // Compressed springs: the unprojected Jacobian is the derivative there
    // too, and is indefinite (so the projection had work to do).
    {
        let m = model(SMALL);
        let (q, q1) = random_pair(&m, 0.03, 0.0005, 12);
        let mut values = vec![0.0; m.force_jacobian_nnz()];
        m.avf_jacobian_values(&q, &q1, &mut values);
        let j = dense(&m, &values);
        assert_eq!(j, j.transpose(), "not symmetric");
        let min = (-j.clone()).symmetric_eigen().eigenvalues.min();
        assert!(min < -1e-3 * j.amax(), "no compressed spring: {min:e}");
        let (mut fp, mut fm) = (vec![0.0; q.len()], vec![0.0; q.len()]);
        let (h, stiff) = (1e-6, j.amax());
        let mut x = q1.clone();
        for c in 0..q.len() {
            x[c] = q1[c] + h;
            m.avf_force(&q, &x, &mut fp);
            x[c] = q1[c] - h;
            m.avf_force(&q, &x, &mut fm);
            x[c] = q1[c];
            for r in 0..q.len() {
                let fd = (fp[r] - fm[r]) / (2.0 * h);
                assert!(
                    (fd - j[(r, c)]).abs() <= 1e-6 * stiff,
                    "compressed: ∂F̄_{r}/∂q₁_{c}: finite difference {fd:e}, Jacobian {:e}",
                    j[(r, c)]
                );
            }
        }
    }
    // Compressed and crumpled, with large steps: projected, still PSD.
    let two = model(TWO);
    let mut configs: Vec<(ClothModel, Vec<f64>, Vec<f64>)> = Vec::new();
    for (q, q1, _) in two_states(&two, 31) {
        configs.push((two.clone(), q, q1));
    }
    for (text, seed) in [(SMALL, 5u64), (FREE, 6), (SMALL, 7)] {
        let m = model(text);
        let (q, q1) = random_pair(&m, 0.05, 0.05, seed);
        configs.push((m, q, q1));
    }
    for (m, q, q1) in &configs {
        let mut values = vec![0.0; m.force_jacobian_nnz()];
        m.avf_jacobian_values_projected(q, q1, &mut values);
        let k = -dense(m, &values);
        assert_eq!(k, k.transpose());
        let eig = k.clone().symmetric_eigen().eigenvalues;
        let min = eig.min();
        assert!(
            min >= -1e-12 * k.amax(),
            "−∂F̄/∂q₁ (projected) has eigenvalue {min:e}"
        );
    }
}

/// What [`avf_step`] returns.
struct Step {
    q1: Vec<f64>,
    v1: Vec<f64>,
    iterations: usize,
    /// The final `∇Ψ = (M/h)(v₁ − v) − F̄`.
    gradient: Vec<f64>,
    /// Iterations that factorised the projected Hessian.
    projected: usize,
}

/// The iteration cap of [`avf_step`].
const ITERATIONS: usize = 300;

/// One AVF step `q₁ = q + h(v + v₁)/2`, `M(v₁ − v) = hF̄(q, q₁)` as the
/// minimiser of `Ψ(q₁) = (1/h²)(q₁ − q − hv)ᵀM(q₁ − q − hv) + U(q₁)`:
/// Newton with an Armijo line search (dense, for the test), stopped on
/// `‖∇Ψ‖_∞ ≤ 1e-12·S`; the Hessian `c·M + K⁺` with the projected Jacobian,
/// or (`exact_first`) `c·M + K` with the exact one wherever that is
/// positive definite.
fn avf_step(m: &ClothModel, q: &[f64], v: &[f64], h: f64, exact_first: bool) -> Step {
    let n = q.len();
    let mut projected = 0;
    let mass = m.particle_mass();
    let c = 2.0 * mass / (h * h);
    let base: Vec<f64> = q.iter().zip(v).map(|(q, v)| q + h * v).collect();
    // (Ψ, |Ψ|ₐ): the objective and the magnitude of its terms.
    let psi = |x: &[f64]| -> (f64, f64) {
        let inertia: f64 = 0.5
            * c
            * x.iter()
                .zip(&base)
                .map(|(x, b)| (x - b) * (x - b))
                .sum::<f64>();
        let (u, magnitude) = m.avf_potential_and_magnitude(q, x);
        (inertia + u, inertia + magnitude)
    };
    let mut x = base.clone();
    let mut f = vec![0.0; n];
    let mut values = vec![0.0; m.force_jacobian_nnz()];
    for it in 1..=ITERATIONS {
        let scale = m.avf_force(q, &x, &mut f);
        let g: Vec<f64> = (0..n).map(|i| c * (x[i] - base[i]) - f[i]).collect();
        let s =
            scale.max(c * max_abs(&x.iter().zip(&base).map(|(a, b)| a - b).collect::<Vec<_>>()));
        if max_abs(&g) <= 1e-12 * s {
            let v1: Vec<f64> = (0..n).map(|i| 2.0 * (x[i] - q[i]) / h - v[i]).collect();
            return Step {
                q1: x,
                v1,
                iterations: it,
                gradient: g,
                projected,
            };
        }
        // The exact Hessian where c·M + K is positive definite, else the
        // projected one.
        m.avf_jacobian_values(q, &x, &mut values);
        let mut hess = -dense(m, &values);
        for i in 0..n {
            hess[(i, i)] += c;
        }
        let chol = match hess.cholesky() {
            Some(chol) if exact_first => chol,
            _ => {
                projected += 1;
                m.avf_jacobian_values_projected(q, &x, &mut values);
                let mut hess = -dense(m, &values);
                for i in 0..n {
                    hess[(i, i)] += c;
                }
                hess.cholesky().expect("c·M + K⁺ is positive definite")
            }
        };
        let p = -chol.solve(&nalgebra::DVector::from_column_slice(&g));
        let slope = dot(&g, p.as_slice());
        assert!(slope < 0.0, "Newton direction does not descend");
        let (phi, magnitude) = psi(&x);
        let mut alpha = 1.0;
        let mut trial = vec![0.0; n];
        for i in 0..n {
            trial[i] = x[i] + p[i];
        }
        // Where the predicted decrease is below Ψ's round-off, the line
        // search cannot judge the step: take it whole.
        if -slope > 64.0 * EPS * magnitude {
            for _ in 0..40 {
                for i in 0..n {
                    trial[i] = x[i] + alpha * p[i];
                }
                if psi(&trial).0 <= phi + 1e-4 * alpha * slope {
                    break;
                }
                alpha *= 0.5;
            }
        }
        x.copy_from_slice(&trial);
    }
    panic!("the AVF step did not converge in {ITERATIONS} Newton iterations");
}

#[test]
fn avf_steps_solved_as_minimisation_keep_energy() {
    // The small cloth at one step per 60 Hz frame, 30 steps. Per step,
    // E(q₁, v₁) − E(q, v) = (q₁ − q)·∇Ψ exactly (the energy identity of
    // F̄ with v₁ = 2(q₁ − q)/h − v): it must hold to round-off, so the
    // energy changes only by the solve's residual.
    let m = model(SMALL);
    let mass = m.particle_mass();
    let energy = |q: &[f64], v: &[f64]| 0.5 * mass * dot(v, v) + m.potential(q);
    let h = 1.0 / 60.0;
    for exact_first in [false, true] {
        let z = m.initial_state();
        let (mut q, mut v) = (z[..m.dof()].to_vec(), vec![0.0; m.dof()]);
        let e0 = energy(&q, &v);
        let (mut drift, mut worst_defect) = (0.0f64, 0.0f64);
        let (mut iterations, mut most, mut projected) = (0, 0, 0);
        for step in 0..30 {
            let s = avf_step(&m, &q, &v, h, exact_first);
            iterations += s.iterations;
            most = most.max(s.iterations);
            projected += s.projected;
            let dq: Vec<f64> = s.q1.iter().zip(&q).map(|(b, a)| b - a).collect();
            let change = energy(&s.q1, &s.v1) - energy(&q, &v);
            let defect = change - dot(&dq, &s.gradient);
            let scale = energy_scale(&m, &q, &s.q1) + mass * (dot(&v, &v) + dot(&s.v1, &s.v1));
            assert!(
                defect.abs() <= 64.0 * EPS * scale,
                "step {step}: ΔE = {change:e}, (q₁ − q)·∇Ψ = {:e}, scale {scale:e}",
                dot(&dq, &s.gradient)
            );
            worst_defect = worst_defect.max(defect.abs() / scale);
            q = s.q1;
            v = s.v1;
            drift = drift.max((energy(&q, &v) - e0).abs());
        }
        eprintln!(
            "AVF on the small cloth, 30 steps of 1/60 s, Hessian {}: |E − E₀| ≤ {drift:e} J (E₀ = {e0:e} J), energy identity defect ≤ {:e} of its scale, {:.1} Newton iterations per step (at most {most}; {projected} with the projected Hessian), max strain {:.3}",
            if exact_first {
                "exact where definite"
            } else {
                "projected"
            },
            worst_defect,
            iterations as f64 / 30.0,
            m.max_strain(&q)
        );
    }
}

/// What the AVF does not keep: angular momentum. A spring's AVF force is
/// not along the mean spring vector `D` (Gonzalez's is), so its two forces
/// have a torque about the midpoints `x̄ = (q + q₁)/2`, and `Σ x̄ × F̄`,
/// which an angular-momentum-conserving scheme has zero, is not. (With
/// gravity and pins the cloth has no angular momentum to keep anyway.)
#[test]
fn avf_forces_have_a_torque_unlike_gonzalez() {
    let free = model(&FREE.replace("gravity = [0.0, -9.81, 0.0]", ""));
    let (q, q1) = random_pair(&free, 0.03, 0.05, 13);
    let mid: Vec<f64> = q.iter().zip(&q1).map(|(a, b)| 0.5 * (a + b)).collect();
    let torque = |f: &[f64]| {
        mid.chunks(3)
            .zip(f.chunks(3))
            .fold(Vector3::zeros(), |t, (x, f)| {
                t + Vector3::from_column_slice(x).cross(&Vector3::from_column_slice(f))
            })
    };
    let mut f = vec![0.0; q.len()];
    let scale = free.avf_force(&q, &q1, &mut f);
    let avf = torque(&f).norm();
    free.discrete_gradient_force(&q, &mid, &mut f);
    let gonzalez = torque(&f).norm();
    let size = max_abs(&mid);
    eprintln!(
        "Σ x̄ × F̄: AVF {avf:e}, Gonzalez {gonzalez:e} (force scale × size {:e})",
        scale * size
    );
    assert!(
        gonzalez <= 1e-13 * scale * size,
        "Gonzalez's torque {gonzalez:e}"
    );
    assert!(
        avf >= 1e-6 * scale * size,
        "the AVF torque {avf:e} vanished"
    );
}
