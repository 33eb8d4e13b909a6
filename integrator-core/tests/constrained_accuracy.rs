//! The Lobatto IIIA–IIIB pairs on constrained systems: the constraints
//! hold to round-off after every step, RATTLE read from the table is the
//! textbook RATTLE, the orders are 2 and 4 against an independent reference,
//! and the energy stays bounded over long runs.
//!
//! Residuals are measured in units of their round-off, `|r|/(ε·scale)`
//! (`integrator_core::constrained::Residual`): `scale = ‖∇gₗ‖₁‖q‖∞` for
//! `gₗ(q)` and `‖∇gₗ‖₁‖M⁻¹p‖∞` for `(G M⁻¹ p)ₗ`.

use integrator_core::constrained::{
    Constrained, ConstrainedPair, NewtonSettings, constrained_energy, integrate_constrained,
    residuals,
};
use integrator_core::problems::{PendulumChain, SphericalPendulum};

/// The bound on every residual after every step, in units of `ε·scale`.
const RESIDUAL_ULPS: f64 = 16.0;

fn sphere() -> (SphericalPendulum, Vec<f64>) {
    let sys = SphericalPendulum::new(1.0, 1.0, 9.81);
    let z = sys.state(1.2, 0.3, 0.0, 2.0);
    (sys, z)
}

fn chain(dim: usize, n: usize) -> (PendulumChain, Vec<f64>) {
    let sys = PendulumChain::uniform(dim, n, 1.0, 9.81).unwrap();
    let angles: Vec<f64> = (0..n).map(|i| 0.3 + 0.9 * (i as f64 * 0.7).sin()).collect();
    let rates: Vec<f64> = (0..n).map(|i| 0.5 * (i as f64 * 1.3).cos()).collect();
    let mut z = sys.state(&angles, &rates);
    if dim == 3 {
        // The links lie in the x–z plane, so momenta along y are tangent:
        // give the spatial chain motion out of that plane.
        for i in 0..n {
            z[n * 3 + i * 3 + 1] = 0.2 * (i as f64 + 1.0).sin();
        }
    }
    (sys, z)
}

/// The largest position and velocity residual (in ulps of their scale)
/// over `n` steps.
fn worst_residuals<S: Constrained, const K: usize>(
    method: &ConstrainedPair<K>,
    sys: &S,
    z0: &[f64],
    h: f64,
    n: usize,
) -> (f64, f64) {
    let mut z = z0.to_vec();
    let (mut wp, mut wv): (f64, f64) = (0.0, 0.0);
    integrate_constrained(method, sys, &mut z, 0.0, h, n, |k, _, z| {
        if k > 0 {
            let r = residuals(sys, z);
            wp = wp.max(r.worst_position().1);
            wv = wv.max(r.worst_velocity().1);
        }
    })
    .unwrap();
    (wp, wv)
}

#[test]
fn constraints_hold_to_round_off_after_every_step() {
    let (sp, zs) = sphere();
    let (c2, z2) = chain(2, 10);
    let (c3, z3) = chain(3, 4);
    let rattle = ConstrainedPair::rattle();
    let lob3 = ConstrainedPair::lobatto3a3b3();
    let cases = [
        (
            "sphere, RATTLE",
            worst_residuals(&rattle, &sp, &zs, 0.05, 2000),
        ),
        (
            "sphere, s = 3",
            worst_residuals(&lob3, &sp, &zs, 0.05, 2000),
        ),
        (
            "planar chain of 10, RATTLE",
            worst_residuals(&rattle, &c2, &z2, 2e-3, 1000),
        ),
        (
            "planar chain of 10, s = 3",
            worst_residuals(&lob3, &c2, &z2, 2e-3, 1000),
        ),
        (
            "spatial chain of 4, RATTLE",
            worst_residuals(&rattle, &c3, &z3, 5e-3, 1000),
        ),
        (
            "spatial chain of 4, s = 3",
            worst_residuals(&lob3, &c3, &z3, 5e-3, 1000),
        ),
    ];
    for (name, (wp, wv)) in cases {
        println!("{name}: worst |g| {wp:.2} ε·scale, worst |G M⁻¹ p| {wv:.2} ε·scale");
        assert!(wp <= RESIDUAL_ULPS, "{name}: |g| = {wp} ε·scale");
        assert!(wv <= RESIDUAL_ULPS, "{name}: |G M⁻¹ p| = {wv} ε·scale");
    }
    // The bound can fail: Newton stopped at 1e12 round-off units (after its
    // first correction of the predictor, ~h²|g| ≈ 4e-5 here) leaves the
    // position residuals far above it.
    let loose = NewtonSettings {
        tolerance: 1e12,
        ..NewtonSettings::default()
    };
    let (wp, _) = worst_residuals(&rattle.with_settings(loose), &c2, &z2, 2e-3, 1000);
    println!("planar chain of 10, RATTLE stopped at 1e12 units: worst |g| {wp:.3e} ε·scale");
    assert!(wp > 100.0 * RESIDUAL_ULPS, "{wp}");
}

/// The textbook RATTLE on the spherical pendulum, written independently of
/// the library: the position multiplier from the quadratic `|q₁|² = L²`
/// (the root nearest zero), the velocity multiplier by projecting onto
/// `q₁⊥`.
fn textbook_rattle(sys: &SphericalPendulum, h: f64, z: &mut [f64]) {
    let (m, l, g) = (sys.mass, sys.length, sys.gravity);
    let q0 = [z[0], z[1], z[2]];
    let p0 = [z[3], z[4], z[5]];
    let force = [0.0, 0.0, -m * g];
    // q₁ = a − β q₀, a = q₀ + h/m (p₀ + h/2 F), β = h²λ/m.
    let a: Vec<f64> = (0..3)
        .map(|i| q0[i] + h / m * (p0[i] + 0.5 * h * force[i]))
        .collect();
    let dot = |x: &[f64], y: &[f64]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
    let (aq, aa, qq) = (dot(&a, &q0), dot(&a, &a), dot(&q0, &q0));
    // qq β² − 2 aq β + (aa − L²) = 0; the small root, written stably.
    let c = aa - l * l;
    let beta = c / (aq + (aq * aq - qq * c).sqrt());
    let q1: Vec<f64> = (0..3).map(|i| a[i] - beta * q0[i]).collect();
    let phalf: Vec<f64> = (0..3).map(|i| m * (q1[i] - q0[i]) / h).collect();
    let pt: Vec<f64> = (0..3).map(|i| phalf[i] + 0.5 * h * force[i]).collect();
    let k = dot(&q1, &pt) / dot(&q1, &q1);
    for i in 0..3 {
        z[i] = q1[i];
        z[3 + i] = pt[i] - k * q1[i];
    }
}

#[test]
fn rattle_read_from_the_table_is_the_textbook_rattle() {
    let (sys, z0) = sphere();
    let h = 0.05;
    let mut z = z0.clone();
    let mut y = z0.clone();
    let mut worst: f64 = 0.0;
    integrate_constrained(
        &ConstrainedPair::rattle(),
        &sys,
        &mut z,
        0.0,
        h,
        200,
        |k, _, z| {
            if k > 0 {
                textbook_rattle(&sys, h, &mut y);
                for i in 0..6 {
                    worst = worst.max((z[i] - y[i]).abs());
                }
            }
        },
    )
    .unwrap();
    println!("RATTLE (table) against textbook RATTLE, 200 steps: max |Δz| = {worst:.2e}");
    // Both are the same map; the difference is rounding, amplified along the
    // chaotic-free but sheared orbit by at most a few hundred ulps.
    assert!(worst < 1e-12, "{worst}");
}

/// The exact solution at `t`, from the ODE in spherical coordinates by
/// classical RK4 with `n` steps (error `O((t/n)⁴)`).
fn reference(sys: &SphericalPendulum, z0: &[f64], t: f64, n: usize) -> Vec<f64> {
    let mut y = sys.to_local(z0);
    let h = t / n as f64;
    let f = |y: &[f64]| {
        let mut o = [0.0; 4];
        sys.local_rhs(y, &mut o);
        o
    };
    for _ in 0..n {
        let k1 = f(&y);
        let y2: Vec<f64> = (0..4).map(|i| y[i] + 0.5 * h * k1[i]).collect();
        let k2 = f(&y2);
        let y3: Vec<f64> = (0..4).map(|i| y[i] + 0.5 * h * k2[i]).collect();
        let k3 = f(&y3);
        let y4: Vec<f64> = (0..4).map(|i| y[i] + h * k3[i]).collect();
        let k4 = f(&y4);
        for i in 0..4 {
            y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
    sys.from_local(&y)
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0, |w: f64, (x, y)| w.max((x - y).abs()))
}

/// Least-squares slope of `log err` against `log h`.
fn slope(h: &[f64], e: &[f64]) -> f64 {
    let x: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let y: Vec<f64> = e.iter().map(|v| v.ln()).collect();
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

fn errors<const K: usize>(
    method: &ConstrainedPair<K>,
    sys: &SphericalPendulum,
    z0: &[f64],
    t: f64,
    exact: &[f64],
    steps: &[usize],
) -> (Vec<f64>, Vec<f64>) {
    let mut hs = Vec::new();
    let mut es = Vec::new();
    for &n in steps {
        let h = t / n as f64;
        let mut z = z0.to_vec();
        integrate_constrained(method, sys, &mut z, 0.0, h, n, |_, _, _| {}).unwrap();
        hs.push(h);
        es.push(max_diff(&z, exact));
    }
    (hs, es)
}

#[test]
fn orders_two_and_four_on_the_spherical_pendulum() {
    let (sys, z0) = sphere();
    let t = 2.0;
    let exact = reference(&sys, &z0, t, 40_000);
    // The reference itself: RK4 with twice the steps agrees to round-off,
    // and so does the s = 3 pair with 4000 steps (error ~ 1e-13).
    let finer = reference(&sys, &z0, t, 80_000);
    let ref_err = max_diff(&exact, &finer);
    let mut z = z0.clone();
    integrate_constrained(
        &ConstrainedPair::lobatto3a3b3(),
        &sys,
        &mut z,
        0.0,
        t / 4000.0,
        4000,
        |_, _, _| {},
    )
    .unwrap();
    let pair_err = max_diff(&exact, &z);
    println!(
        "reference: RK4 40000 vs 80000 steps {ref_err:.2e}; s = 3 pair at h = 5e-4 {pair_err:.2e}"
    );
    assert!(ref_err < 1e-12, "{ref_err}");
    assert!(pair_err < 1e-11, "{pair_err}");

    let (h2, e2) = errors(
        &ConstrainedPair::rattle(),
        &sys,
        &z0,
        t,
        &exact,
        &[40, 80, 160, 320, 640],
    );
    let (h4, e4) = errors(
        &ConstrainedPair::lobatto3a3b3(),
        &sys,
        &z0,
        t,
        &exact,
        &[20, 40, 80, 160, 320],
    );
    let (s2, s4) = (slope(&h2, &e2), slope(&h4, &e4));
    let fmt = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.3e}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    println!(
        "RATTLE: h {}\n        err {}\n        slope {s2:.3}",
        fmt(&h2),
        fmt(&e2)
    );
    println!(
        "s = 3:  h {}\n        err {}\n        slope {s4:.3}",
        fmt(&h4),
        fmt(&e4)
    );
    assert!((s2 - 2.0).abs() < 0.1, "RATTLE slope {s2}");
    assert!((s4 - 4.0).abs() < 0.15, "s = 3 slope {s4}");
}

/// Energy error over a long run: its maximum over the whole run against
/// its maximum over the first tenth (a drift would grow with time), and
/// the least-squares trend over the run against the error's range.
fn energy_run<S: Constrained, const K: usize>(
    method: &ConstrainedPair<K>,
    sys: &S,
    z0: &[f64],
    h: f64,
    n: usize,
) -> (f64, f64, f64) {
    let e0 = constrained_energy(sys, z0);
    let mut z = z0.to_vec();
    let mut err = Vec::with_capacity(n + 1);
    integrate_constrained(method, sys, &mut z, 0.0, h, n, |_, _, z| {
        err.push(constrained_energy(sys, z) - e0);
    })
    .unwrap();
    let first = err[..n / 10].iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let all = err.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let t: Vec<f64> = (0..=n).map(|k| k as f64).collect();
    let m = (n + 1) as f64;
    let (mt, me) = (t.iter().sum::<f64>() / m, err.iter().sum::<f64>() / m);
    let stt: f64 = t.iter().map(|x| (x - mt).powi(2)).sum();
    let ste: f64 = t.iter().zip(&err).map(|(x, e)| (x - mt) * (e - me)).sum();
    let trend = (ste / stt * n as f64).abs();
    (first, all, trend)
}

#[test]
fn energy_stays_bounded_over_long_runs() {
    let (sp, zs) = sphere();
    // A chain of 5 swinging moderately (0.2–0.4 rad): quasi-periodic. A
    // chain whipped into chaos visits regions of faster motion, where the
    // energy error of any fixed step is larger, so the first tenth is no
    // yardstick there.
    let c2 = PendulumChain::uniform(2, 5, 1.0, 9.81).unwrap();
    let angles: Vec<f64> = (0..5).map(|i| 0.3 + 0.1 * (i as f64).sin()).collect();
    let z2 = c2.state(&angles, &[0.0; 5]);
    let runs = [
        (
            "sphere, RATTLE, h = 0.05, 2·10⁵ steps",
            energy_run(&ConstrainedPair::rattle(), &sp, &zs, 0.05, 200_000),
        ),
        (
            "sphere, s = 3, h = 0.1, 5·10⁴ steps",
            energy_run(&ConstrainedPair::lobatto3a3b3(), &sp, &zs, 0.1, 50_000),
        ),
        (
            "planar chain of 5, RATTLE, h = 2e-3, 10⁵ steps",
            energy_run(&ConstrainedPair::rattle(), &c2, &z2, 2e-3, 100_000),
        ),
    ];
    for (name, (first, all, trend)) in runs {
        println!(
            "{name}: max |ΔH| first tenth {first:.3e}, whole run {all:.3e}, linear trend over the run {trend:.3e}"
        );
        assert!(
            all <= 1.5 * first,
            "{name}: the energy error grows: {first} → {all}"
        );
        assert!(
            trend <= 0.1 * all,
            "{name}: the energy drifts: trend {trend} of {all}"
        );
    }
}

/// Newton iterations per step, warm-started from the last step's
/// multipliers against every step started cold (the same states).
fn iterations_per_step<S: Constrained, const K: usize>(
    method: &ConstrainedPair<K>,
    sys: &S,
    z0: &[f64],
    h: f64,
    n: usize,
) -> (f64, f64) {
    let (mut warm, mut cold) = (method.workspace(sys), method.workspace(sys));
    let mut z = z0.to_vec();
    let mut cold_total = 0;
    for k in 0..n {
        let mut y = z.clone();
        cold.reset();
        method.step(sys, 0.0, h, &mut y, &mut cold).unwrap();
        cold_total += cold.iterations;
        method
            .step(sys, k as f64 * h, h, &mut z, &mut warm)
            .unwrap();
    }
    (
        warm.total_iterations as f64 / n as f64,
        cold_total as f64 / n as f64,
    )
}

#[test]
fn the_warm_start_saves_newton_iterations() {
    let (sp, zs) = sphere();
    let (c2, z2) = chain(2, 10);
    let cases = [
        (
            "sphere, RATTLE, h = 0.05",
            iterations_per_step(&ConstrainedPair::rattle(), &sp, &zs, 0.05, 400),
        ),
        (
            "sphere, s = 3, h = 0.05",
            iterations_per_step(&ConstrainedPair::lobatto3a3b3(), &sp, &zs, 0.05, 400),
        ),
        (
            "chain of 10, RATTLE, h = 2e-3",
            iterations_per_step(&ConstrainedPair::rattle(), &c2, &z2, 2e-3, 400),
        ),
        (
            "chain of 10, s = 3, h = 2e-3",
            iterations_per_step(&ConstrainedPair::lobatto3a3b3(), &c2, &z2, 2e-3, 400),
        ),
    ];
    for (name, (warm, cold)) in cases {
        println!("{name}: Newton iterations per step {warm:.2} warm, {cold:.2} cold");
        assert!(warm < cold, "{name}: warm {warm}, cold {cold}");
    }
}

/// The chain without its curvature (`Constrained::curvature` left at its
/// default): the simplified Newton iteration.
struct NoCurvature(PendulumChain);

impl Constrained for NoCurvature {
    fn dof(&self) -> usize {
        self.0.dof()
    }
    fn constraints(&self) -> usize {
        self.0.constraints()
    }
    fn inverse_mass(&self, out: &mut [f64]) {
        self.0.inverse_mass(out)
    }
    fn potential(&self, q: &[f64]) -> f64 {
        self.0.potential(q)
    }
    fn grad_potential(&self, q: &[f64], out: &mut [f64]) {
        self.0.grad_potential(q, out)
    }
    fn constraint(&self, q: &[f64], out: &mut [f64]) {
        self.0.constraint(q, out)
    }
    fn constraint_jacobian(&self, q: &[f64], out: &mut [f64]) {
        self.0.constraint_jacobian(q, out)
    }
}

#[test]
fn simplified_newton_without_curvature_reaches_the_same_step() {
    let (c, z0) = chain(2, 6);
    let plain = NoCurvature(c.clone());
    let method = ConstrainedPair::lobatto3a3b3();
    let h = 1e-2;
    let (mut za, mut zb) = (z0.clone(), z0.clone());
    let (mut wa, mut wb) = (method.workspace(&c), method.workspace(&plain));
    let mut worst: f64 = 0.0;
    for k in 0..100 {
        // Both from the same state each step, so only one step's solves differ.
        zb.copy_from_slice(&za);
        method.step(&c, k as f64 * h, h, &mut za, &mut wa).unwrap();
        method
            .step(&plain, k as f64 * h, h, &mut zb, &mut wb)
            .unwrap();
        worst = worst.max(
            za.iter()
                .zip(&zb)
                .fold(0.0, |a: f64, (x, y)| a.max((x - y).abs())),
        );
    }
    let scale = z0.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    println!(
        "s = 3 on a chain of 6: Newton {:.2} iterations per step, simplified {:.2}; steps agree to {:.1} ε·max|z|",
        wa.total_iterations as f64 / 100.0,
        wb.total_iterations as f64 / 100.0,
        worst / (f64::EPSILON * scale)
    );
    assert!(worst <= 64.0 * f64::EPSILON * scale, "{worst}");
    assert!(wa.total_iterations < wb.total_iterations);
}
