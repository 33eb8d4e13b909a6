//! The minimisation layer (`integrator_core::minimise`) on a system that is
//! not a cloth: a planar chain of nonlinear springs (`½k(ℓ − L)² +
//! ¼β(ℓ − L)⁴`), with unequal masses (a diagonal mass matrix), pinned at
//! one end under gravity or free. Its midpoint steps and compositions equal
//! the generic stage solver's `ImplicitMidpoint`, `PaperDirk2` and
//! `PaperDirk4` steps to round-off; the iteration cap, non-finite input and
//! a bad step size are errors; a free chain keeps its momentum.

use integrator_core::implicit::{self, ImplicitTable, SparseJacobian, SparseWorkspace};
use integrator_core::library::{ImplicitMidpoint, PaperDirk2, PaperDirk4};
use integrator_core::minimise::{
    Mass, MidpointSettings, MidpointStepper, MinimiseError, NewtonSettings, SparsePotential,
};
use integrator_core::{OdeSystem, Separable};

/// Particles `0..n` in the plane, springs `i–(i+1)`, and with `pinned`
/// a spring from particle 0 to the origin.
struct Chain {
    n: usize,
    k: f64,
    beta: f64,
    rest: f64,
    mass: Vec<f64>,
    gravity: f64,
    pinned: bool,
}

impl Chain {
    fn new(n: usize, pinned: bool, gravity: f64) -> Chain {
        let mut mass = Vec::with_capacity(2 * n);
        for i in 0..n {
            let m = 1.0 + 0.25 * (i % 3) as f64;
            mass.extend([m, m]);
        }
        Chain {
            n,
            k: 50.0,
            beta: 400.0,
            rest: 1.0,
            mass,
            gravity,
            pinned,
        }
    }

    /// Stretched zig-zag, moving.
    fn initial(&self) -> Vec<f64> {
        let n = self.n;
        let mut z = vec![0.0; 4 * n];
        for i in 0..n {
            let t = i as f64;
            z[2 * i] = 1.08 * (t + 1.0);
            z[2 * i + 1] = 0.3 * (1.3 * t).sin();
            z[2 * n + 2 * i] = self.mass[2 * i] * 0.2 * (0.7 * t).cos();
            z[2 * n + 2 * i + 1] = self.mass[2 * i] * 0.5 * (0.9 * t + 0.3).sin();
        }
        z
    }

    /// `(a, b)` for every spring, `b = None` for the pin.
    fn springs(&self) -> impl Iterator<Item = (usize, Option<usize>)> + '_ {
        let pin = self.pinned.then_some((0, None));
        pin.into_iter()
            .chain((0..self.n - 1).map(|i| (i, Some(i + 1))))
    }

    /// `d = x_b − x_a` (or `x_a` − pin).
    fn d(&self, q: &[f64], a: usize, b: Option<usize>) -> [f64; 2] {
        match b {
            Some(b) => [q[2 * b] - q[2 * a], q[2 * b + 1] - q[2 * a + 1]],
            None => [q[2 * a], q[2 * a + 1]],
        }
    }

    /// `φ(ℓ)`, `φ'(ℓ)`, `φ''(ℓ)`.
    fn phi(&self, l: f64) -> (f64, f64, f64) {
        let e = l - self.rest;
        (
            0.5 * self.k * e * e + 0.25 * self.beta * e.powi(4),
            self.k * e + self.beta * e.powi(3),
            self.k + 3.0 * self.beta * e * e,
        )
    }

    /// The 2×2 Hessian block `φ''·d̂d̂ᵀ + (φ'/ℓ)(I − d̂d̂ᵀ)`, the second term
    /// clamped at 0 when `project` (a compressed spring).
    fn block(&self, d: [f64; 2], project: bool) -> [f64; 4] {
        let l = d[0].hypot(d[1]);
        let (_, p1, p2) = self.phi(l);
        let t = if project { (p1 / l).max(0.0) } else { p1 / l };
        let u = [d[0] / l, d[1] / l];
        let mut b = [0.0; 4];
        for r in 0..2 {
            for c in 0..2 {
                let uu = u[r] * u[c];
                b[2 * r + c] = p2 * uu + t * ((r == c) as u8 as f64 - uu);
            }
        }
        b
    }

    fn hessian_into(&self, q: &[f64], out: &mut [f64], project: bool) {
        let mut k = 0;
        for (a, b) in self.springs() {
            let blk = self.block(self.d(q, a, b), project);
            let pairs: &[(usize, usize, f64)] = match b {
                Some(b) => &[(a, a, 1.0), (b, b, 1.0), (a, b, -1.0), (b, a, -1.0)],
                None => &[(a, a, 1.0)],
            };
            for _ in pairs {
                for v in blk {
                    out[k] = v;
                    k += 1;
                }
            }
            // The signs, in the same order.
            let start = k - 4 * pairs.len();
            for (j, &(_, _, s)) in pairs.iter().enumerate() {
                for v in &mut out[start + 4 * j..start + 4 * j + 4] {
                    *v *= s;
                }
            }
        }
    }
}

impl Separable for Chain {
    fn dof(&self) -> usize {
        2 * self.n
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        p.iter().zip(&self.mass).map(|(p, m)| 0.5 * p * p / m).sum()
    }
    fn potential(&self, q: &[f64]) -> f64 {
        let mut v = 0.0;
        for (a, b) in self.springs() {
            let d = self.d(q, a, b);
            v += self.phi(d[0].hypot(d[1])).0;
        }
        for i in 0..self.n {
            v += self.mass[2 * i] * self.gravity * q[2 * i + 1];
        }
        v
    }
    fn velocity(&self, p: &[f64], out: &mut [f64]) {
        for ((o, p), m) in out.iter_mut().zip(p).zip(&self.mass) {
            *o = p / m;
        }
    }
    fn force(&self, q: &[f64], out: &mut [f64]) {
        self.force_and_scale(q, out);
    }
}

impl SparsePotential for Chain {
    fn mass(&self) -> Mass<'_> {
        Mass::Diagonal(&self.mass)
    }
    fn force_and_scale(&self, q: &[f64], out: &mut [f64]) -> f64 {
        let n = self.n;
        let mut scale: f64 = 0.0;
        let mut kappa: f64 = 0.0;
        for i in 0..n {
            out[2 * i] = 0.0;
            out[2 * i + 1] = -self.mass[2 * i] * self.gravity;
            scale = scale.max(self.mass[2 * i] * self.gravity);
        }
        for (a, b) in self.springs() {
            let d = self.d(q, a, b);
            let l = d[0].hypot(d[1]);
            let (_, p1, p2) = self.phi(l);
            scale = scale.max(p1.abs());
            kappa = kappa.max(p2);
            let f = [p1 * d[0] / l, p1 * d[1] / l];
            match b {
                Some(b) => {
                    out[2 * a] += f[0];
                    out[2 * a + 1] += f[1];
                    out[2 * b] -= f[0];
                    out[2 * b + 1] -= f[1];
                }
                None => {
                    out[2 * a] -= f[0];
                    out[2 * a + 1] -= f[1];
                }
            }
        }
        let q_max = q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        scale.max(kappa * q_max)
    }
    fn hessian_pattern(&self) -> Vec<(usize, usize)> {
        let mut pattern = Vec::new();
        for (a, b) in self.springs() {
            let pairs = match b {
                Some(b) => vec![(a, a), (b, b), (a, b), (b, a)],
                None => vec![(a, a)],
            };
            for (i, j) in pairs {
                for r in 0..2 {
                    for c in 0..2 {
                        pattern.push((2 * i + r, 2 * j + c));
                    }
                }
            }
        }
        pattern
    }
    fn hessian_values_projected(&self, q: &[f64], out: &mut [f64]) {
        self.hessian_into(q, out, true);
    }
}

/// The stage solver's view: `∂f/∂z = [[0, M⁻¹], [−∇²V, 0]]`, exact Hessian.
impl SparseJacobian for Chain {
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        let d = self.dof();
        let mut p: Vec<(usize, usize)> = (0..d).map(|k| (k, d + k)).collect();
        p.extend(self.hessian_pattern().iter().map(|&(r, c)| (d + r, c)));
        p
    }
    fn jacobian_values(&self, _t: f64, z: &[f64], values: &mut [f64]) {
        let d = self.dof();
        for (v, m) in values[..d].iter_mut().zip(&self.mass) {
            *v = 1.0 / m;
        }
        self.hessian_into(&z[..d], &mut values[d..], false);
        for v in &mut values[d..] {
            *v = -*v;
        }
    }
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// The largest difference of positions and of momenta, each relative to
/// the largest component of that half: `(positions, momenta)`.
fn difference(a: &[f64], b: &[f64]) -> (f64, f64) {
    let n = a.len() / 2;
    let half = |x: &[f64], y: &[f64]| {
        let diff = x
            .iter()
            .zip(y)
            .fold(0.0f64, |m, (u, v)| m.max((u - v).abs()));
        diff / max_abs(x).max(max_abs(y))
    };
    (half(&a[..n], &b[..n]), half(&a[n..], &b[n..]))
}

/// Run the stage solver with `table` and the minimisation with `weights`
/// for `steps` steps of `h`; returns both final states and the momentum
/// round-off scale `R = ε·Σ|h|·S/‖p‖_∞` (`S` the largest force scale met):
/// every evaluation of `F` carries about `ε·S` of round-off (the force scale
/// is the size of its terms), a kick adds `h` times it to the momenta, and
/// over the run these add up to `ε·steps·h·S` in the worst case (both
/// solvers carry it, in different bits). The positions are held to an ulp
/// per step (`ε·steps` relative).
fn both<const S: usize>(
    sys: &Chain,
    table: &ImplicitTable<S>,
    weights: &[f64],
    h: f64,
    steps: usize,
) -> (Vec<f64>, Vec<f64>, f64) {
    let settings = MidpointSettings {
        newton: NewtonSettings {
            tolerance: 1e-14,
            ..NewtonSettings::default()
        },
        ..MidpointSettings::default()
    };
    let mut stepper = MidpointStepper::new(sys, settings).unwrap();
    let mut a = sys.initial();
    let mut b = a.clone();
    let mut ws = SparseWorkspace::new(b.len(), S);
    let d = sys.dof();
    let mut f = vec![0.0; d];
    let mut s_max: f64 = 0.0;
    for k in 0..steps {
        s_max = s_max.max(sys.force_and_scale(&a[..d], &mut f));
        stepper.step(sys, weights, h, &mut a).unwrap();
        implicit::step_sparse(table, sys, k as f64 * h, h, &mut b, &mut ws).unwrap();
    }
    assert_eq!(stepper.stats().steps, steps);
    assert_eq!(stepper.stats().solves, steps * weights.len());
    assert_eq!(stepper.stats().symbolic_factorizations, 1);
    assert_eq!(stepper.stats().floor_accepts, 0);
    let r = f64::EPSILON * steps as f64 * h * s_max / max_abs(&a[d..]);
    (a, b, r)
}

/// At h = 0.01 (h·ω_max ≈ 0.3, both converge in a few iterations), 500
/// steps of the minimisation midpoint rule equal the stage solver's
/// `ImplicitMidpoint` steps to round-off: momenta within 16·R, the
/// round-off scale of [`both`] (here R ≈ 9e-13; measured 0.14 R), positions
/// within an ulp per step (measured 2.1e-14 = 0.19 ε·steps).
#[test]
fn midpoint_equals_the_stage_solver() {
    let sys = Chain::new(8, true, 9.81);
    let (a, b, r) = both(&sys, &ImplicitMidpoint::TABLE, &[1.0], 0.01, 500);
    let (dq, dp) = difference(&a, &b);
    println!(
        "midpoint: positions {dq:e} = {:.2} ε·steps, momenta {dp:e} = {:.2} R (R = {r:e})",
        dq / (500.0 * f64::EPSILON),
        dp / r
    );
    assert!(r < 1e-12, "the bound means something: R = {r:e}");
    assert!(dq < 500.0 * f64::EPSILON, "positions differ by {dq:e}");
    assert!(dp < 16.0 * r, "momenta differ by {dp:e} = {} R", dp / r);
}

/// Two midpoint steps of h/2 equal `PaperDirk2`'s step.
#[test]
fn two_weights_equal_paper_dirk2() {
    let sys = Chain::new(8, true, 9.81);
    let (a, b, r) = both(&sys, &PaperDirk2::TABLE, &[0.5, 0.5], 0.01, 500);
    let (dq, dp) = difference(&a, &b);
    println!(
        "paper-dirk2: positions {dq:e} = {:.2} ε·steps, momenta {dp:e} = {:.2} R (R = {r:e})",
        dq / (500.0 * f64::EPSILON),
        dp / r
    );
    assert!(r < 1e-12, "the bound means something: R = {r:e}");
    assert!(dq < 500.0 * f64::EPSILON, "positions differ by {dq:e}");
    assert!(dp < 16.0 * r, "momenta differ by {dp:e} = {} R", dp / r);
}

/// The triple jump (a negative middle weight, `1 − 2x < 0`) equals
/// `PaperDirk4` (three solves per step, one of them with `τ < 0`).
#[test]
fn triple_jump_with_a_negative_weight_equals_paper_dirk4() {
    let sys = Chain::new(8, true, 9.81);
    let x = 1.0 / (2.0 - 2f64.cbrt());
    let weights = [x, 1.0 - 2.0 * x, x];
    assert!(weights[1] < 0.0);
    let (a, b, r) = both(&sys, &PaperDirk4::TABLE, &weights, 0.01, 500);
    let (dq, dp) = difference(&a, &b);
    println!(
        "paper-dirk4: positions {dq:e} = {:.2} ε·steps, momenta {dp:e} = {:.2} R (R = {r:e})",
        dq / (500.0 * f64::EPSILON),
        dp / r
    );
    // The triple jump's stages are 1.35 h, −1.70 h, 1.35 h (4.4 h of kicks
    // per step, three solves): R counts h once, hence the factors.
    assert!(
        dq < 3.0 * 500.0 * f64::EPSILON,
        "positions differ by {dq:e}"
    );
    assert!(
        dp < 4.0 * 16.0 * r,
        "momenta differ by {dp:e} = {} R",
        dp / r
    );
}

/// A solve that reaches its cap is `NotConverged` naming the iterations,
/// the residual and the tolerance, and the state is unchanged.
#[test]
fn the_cap_is_an_error() {
    let sys = Chain::new(8, true, 9.81);
    let settings = MidpointSettings {
        newton: NewtonSettings {
            max_iterations: 1,
            ..NewtonSettings::default()
        },
        ..MidpointSettings::default()
    };
    let mut stepper = MidpointStepper::new(&sys, settings).unwrap();
    let mut z = sys.initial();
    let before = z.clone();
    let err = stepper.midpoint_step(&sys, 0.5, &mut z).unwrap_err();
    match &err {
        MinimiseError::NotConverged {
            iterations,
            residual,
            tolerance,
            ..
        } => {
            assert_eq!(*iterations, 1);
            assert!(*residual > *tolerance);
            assert_eq!(*tolerance, 1e-12);
        }
        other => panic!("expected NotConverged, got {other:?}"),
    }
    assert!(err.to_string().contains("1 iterations"), "{err}");
    assert_eq!(z, before);
    assert_eq!(stepper.stats().solves, 0);
}

/// Non-finite input is `NonFinite`, a bad step size and bad settings are
/// refused with the name of what is wrong; nothing is changed.
#[test]
fn bad_input_is_an_error() {
    let sys = Chain::new(5, true, 9.81);
    let mut stepper = MidpointStepper::new(&sys, MidpointSettings::default()).unwrap();
    for bad in [f64::NAN, f64::INFINITY] {
        let mut z = sys.initial();
        z[3] = bad;
        let before = z.clone();
        let err = stepper.midpoint_step(&sys, 0.01, &mut z).unwrap_err();
        assert!(
            matches!(err, MinimiseError::NonFinite { iteration: 0, .. }),
            "{err:?}"
        );
        assert_eq!(z[..3], before[..3]);
        assert!(z[4..] == before[4..]);
    }
    let mut z = sys.initial();
    for tau in [0.0, f64::NAN] {
        let err = stepper.midpoint_step(&sys, tau, &mut z).unwrap_err();
        assert!(err.to_string().contains("step size"), "{err}");
    }
    assert_eq!(z, sys.initial());
    for (settings, field) in [
        (
            NewtonSettings {
                tolerance: -1.0,
                ..NewtonSettings::default()
            },
            "tolerance",
        ),
        (
            NewtonSettings {
                max_iterations: 0,
                ..NewtonSettings::default()
            },
            "max_iterations",
        ),
    ] {
        let err = MidpointStepper::new(
            &sys,
            MidpointSettings {
                newton: settings,
                ..MidpointSettings::default()
            },
        )
        .err()
        .expect("refused");
        assert!(err.to_string().contains(field), "{err}");
    }
}

/// A free chain (no pin, no gravity) keeps its total momentum to round-off
/// at a step beyond the explicit limit (h = 0.2: h·ω_max ≈ 2.8 for the
/// linear part, more where the quartic term stiffens), with every
/// composition: `p' = p + τ·F(x̄)` and the internal forces sum to zero, so
/// each kick changes `Σp` by the round-off of `ΣF` (a few ulps of the
/// largest tension per particle), whatever the residual. The bound adds
/// those worst cases up linearly; measured drifts are 2e-16 to 6e-15 (|P| =
/// 1.3), against bounds of about 1e-11. (At h = 0.5 the midpoint rule's
/// energy grows 1.7e5-fold on this chain, the Simo–Tarnow instability, and
/// the momentum is still kept, to 4.5e-14.)
#[test]
fn a_free_chain_keeps_its_momentum() {
    let sys = Chain::new(10, false, 0.0);
    let x = 1.0 / (2.0 - 2f64.cbrt());
    let d = sys.dof();
    for weights in [vec![1.0], vec![0.5, 0.5], vec![x, 1.0 - 2.0 * x, x]] {
        let mut stepper = MidpointStepper::new(&sys, MidpointSettings::default()).unwrap();
        let mut z = sys.initial();
        let total = |z: &[f64]| {
            let (mut px, mut py) = (0.0, 0.0);
            for i in 0..sys.n {
                px += z[d + 2 * i];
                py += z[d + 2 * i + 1];
            }
            (px, py)
        };
        let p0 = total(&z);
        let h = 0.2;
        let steps = 200;
        let mut bound = 0.0;
        for _ in 0..steps {
            stepper.step(&sys, &weights, h, &mut z).unwrap();
            // Per kick τ·ΣF: each spring's force is added to one end and
            // subtracted from the other, each addition rounded to an ulp of
            // a sum of at most two tensions; then the kick is added to p.
            let tension = (0..sys.n - 1)
                .map(|i| {
                    let d = sys.d(&z[..d], i, Some(i + 1));
                    sys.phi(d[0].hypot(d[1])).1.abs()
                })
                .fold(0.0f64, f64::max);
            let p_max = max_abs(&z[d..]);
            bound += weights.len() as f64
                * 4.0
                * f64::EPSILON
                * sys.n as f64
                * (2.0 * h * tension + p_max);
        }
        // The sum Σp itself.
        bound += 2.0 * f64::EPSILON * sys.n as f64 * max_abs(&z[d..]);
        let p = total(&z);
        let drift = (p.0 - p0.0).abs().max((p.1 - p0.1).abs());
        println!(
            "{} weights: momentum drift {drift:e} (bound {bound:e}; |P| = {:e}), {:.1} iterations per step",
            weights.len(),
            p0.0.hypot(p0.1),
            stepper.stats().iterations_per_step()
        );
        assert!(drift <= bound, "momentum drift {drift:e} > {bound:e}");
        assert!(stepper.stats().iterations_per_step() > 1.0);
    }
}

/// The stage solver's Jacobian is consistent with the force (a finite
/// difference check), so the comparisons above compare like with like.
#[test]
fn the_test_system_is_consistent() {
    let sys = Chain::new(4, true, 9.81);
    let z = sys.initial();
    let d = sys.dof();
    let mut f0 = vec![0.0; d];
    let mut f1 = vec![0.0; d];
    sys.force(&z[..d], &mut f0);
    let pattern = sys.hessian_pattern();
    let mut h = vec![0.0; pattern.len()];
    sys.hessian_into(&z[..d], &mut h, false);
    let mut dense = vec![0.0; d * d];
    for (&(r, c), v) in pattern.iter().zip(&h) {
        dense[r * d + c] += v;
    }
    let eps = 1e-6;
    for c in 0..d {
        let mut q = z[..d].to_vec();
        q[c] += eps;
        sys.force(&q, &mut f1);
        for r in 0..d {
            let fd = -(f1[r] - f0[r]) / eps;
            assert!(
                (fd - dense[r * d + c]).abs() < 1e-3 * (1.0 + fd.abs()),
                "∂²V/∂q{r}∂q{c}: {fd} vs {}",
                dense[r * d + c]
            );
        }
    }
    // And the dynamics is that of the ODE the stage solver sees.
    let mut dz = vec![0.0; 2 * d];
    OdeSystem::rhs(&sys, 0.0, &z, &mut dz);
    assert_eq!(&dz[d..], &f0[..]);
}

/// An FPU chain between walls, `V = Σ φ(qᵢ − qᵢ₋₁)`, `φ(r) = ½r² + ¼βr⁴`
/// (`q₋₁ = qₙ = 0`), unit masses: a polynomial potential, so that the
/// average vector field's integrals are exact with 3-point Gauss–Legendre.
struct Fpu {
    n: usize,
    beta: f64,
}

impl Fpu {
    fn r(&self, q: &[f64], i: usize) -> f64 {
        let right = if i < self.n { q[i] } else { 0.0 };
        let left = if i > 0 { q[i - 1] } else { 0.0 };
        right - left
    }
    fn potential(&self, q: &[f64]) -> f64 {
        (0..=self.n)
            .map(|i| {
                let r = self.r(q, i);
                0.5 * r * r + 0.25 * self.beta * r.powi(4)
            })
            .sum()
    }
    /// `−∇V` into `out` (accumulated with weight `w`); the force scale.
    fn add_force(&self, q: &[f64], w: f64, out: &mut [f64]) -> f64 {
        let mut scale: f64 = 0.0;
        let mut kappa: f64 = 0.0;
        for i in 0..=self.n {
            let r = self.r(q, i);
            let t = r + self.beta * r.powi(3);
            scale = scale.max(t.abs());
            kappa = kappa.max(1.0 + 3.0 * self.beta * r * r);
            if i < self.n {
                out[i] -= w * t;
            }
            if i > 0 {
                out[i - 1] += w * t;
            }
        }
        scale.max(kappa * max_abs(q))
    }
    /// `∇²V` on the tridiagonal pattern `(i, i)`, `(i, i+1)` (upper),
    /// accumulated with weight `w`.
    fn add_hessian(&self, q: &[f64], w: f64, out: &mut [f64]) {
        for i in 0..=self.n {
            let r = self.r(q, i);
            let k = w * (1.0 + 3.0 * self.beta * r * r);
            if i < self.n {
                out[2 * i] += k;
            }
            if i > 0 {
                out[2 * (i - 1)] += k;
            }
            if i > 0 && i < self.n {
                out[2 * (i - 1) + 1] -= k;
            }
        }
    }
    fn pattern(&self) -> Vec<(usize, usize)> {
        (0..self.n)
            .flat_map(|i| [(i, i), (i, (i + 1).min(self.n - 1))])
            .collect()
    }
}

/// The average vector field step as an [`Objective`]: `q₁ = base + u`,
/// `base = q + h·v`, `c = 2/h²`, `U(q₁) = ∫₀¹ (V(q + ξΔ) − V(q))/ξ dξ`,
/// `Δ = q₁ − q`, its force `−∫₀¹ ∇V(q + ξΔ) dξ` and Hessian
/// `∫₀¹ ξ·∇²V(q + ξΔ) dξ`, by 3-point Gauss–Legendre (exact here).
struct Avf<'a> {
    sys: &'a Fpu,
    q: &'a [f64],
    base: Vec<f64>,
    c: f64,
}

const GL3: [(f64, f64); 3] = [
    (0.5 - 0.387_298_334_620_741_7, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.5 + 0.387_298_334_620_741_7, 5.0 / 18.0),
];

impl Avf<'_> {
    fn at(&self, x: &[f64], xi: f64) -> Vec<f64> {
        self.q
            .iter()
            .zip(x)
            .map(|(q, x)| q + xi * (x - q))
            .collect()
    }
}

impl integrator_core::minimise::Objective for Avf<'_> {
    fn dim(&self) -> usize {
        self.sys.n
    }
    fn base(&self) -> &[f64] {
        &self.base
    }
    fn inertia(&self) -> f64 {
        self.c
    }
    fn mass(&self) -> Mass<'_> {
        Mass::Scalar(1.0)
    }
    fn value(&self, x: &[f64]) -> (f64, f64) {
        let v0 = self.sys.potential(self.q);
        let mut u = 0.0;
        let mut mag = 0.0;
        for (xi, w) in GL3 {
            let v = self.sys.potential(&self.at(x, xi));
            u += w * (v - v0) / xi;
            mag += w * (v.abs() + v0.abs()) / xi;
        }
        (u, mag)
    }
    fn force(&self, x: &[f64], force: &mut [f64]) -> f64 {
        force.fill(0.0);
        let mut scale: f64 = 0.0;
        for (xi, w) in GL3 {
            scale = scale.max(self.sys.add_force(&self.at(x, xi), w, force));
        }
        scale
    }
    fn hessian_projected(&self, x: &[f64], values: &mut [f64]) {
        // V is convex (β > 0): its Hessian needs no projection.
        values.fill(0.0);
        for (xi, w) in GL3 {
            self.sys.add_hessian(&self.at(x, xi), w * xi, values);
        }
    }
}

/// The layer's objective serves the average vector field step too (an
/// energy-conserving, non-symplectic scheme): Newton on its objective with
/// the same machinery keeps the FPU chain's energy to round-off at a large
/// step (h = 0.5, h·ω_max ≈ 1 in the linear part, stiffer where the springs
/// stretch), where the midpoint rule's energy moves by 2e-2 (measured).
/// At tolerance 1e-14 the AVF's relative energy error over 200 steps was
/// measured 9e-15; at the default 1e-12 it is 3.3e-12: the energy error
/// follows the solver's tolerance.
#[test]
fn the_objective_serves_an_average_vector_field_step() {
    use integrator_core::minimise::Newton;
    let sys = Fpu { n: 12, beta: 2.0 };
    let n = sys.n;
    let mut q: Vec<f64> = (0..n).map(|i| 0.6 * (0.5 * i as f64).sin()).collect();
    let mut v: Vec<f64> = (0..n).map(|i| 0.4 * (0.9 * i as f64).cos()).collect();
    let energy =
        |q: &[f64], v: &[f64]| sys.potential(q) + 0.5 * v.iter().map(|v| v * v).sum::<f64>();
    let e0 = energy(&q, &v);
    let h = 0.5;
    let settings = NewtonSettings {
        tolerance: 1e-14,
        ..NewtonSettings::default()
    };
    let mut newton = Newton::new(n, &sys.pattern(), settings).unwrap();
    let mut u = vec![0.0; n];
    let mut worst: f64 = 0.0;
    for _ in 0..200 {
        let base: Vec<f64> = q.iter().zip(&v).map(|(q, v)| q + h * v).collect();
        let obj = Avf {
            sys: &sys,
            q: &q,
            base,
            c: 2.0 / (h * h),
        };
        u.fill(0.0);
        newton.solve(&obj, &mut u, None).unwrap();
        let q1: Vec<f64> = obj.base.iter().zip(&u).map(|(b, u)| b + u).collect();
        // v₁ = 2(q₁ − q)/h − v.
        let v1: Vec<f64> = q1
            .iter()
            .zip(&q)
            .zip(&v)
            .map(|((q1, q), v)| 2.0 * (q1 - q) / h - v)
            .collect();
        q = q1;
        v = v1;
        worst = worst.max(((energy(&q, &v) - e0) / e0).abs());
    }
    println!(
        "AVF: relative energy error {worst:e} over 200 steps, {:.1} Newton iterations per solve",
        newton.stats().iterations as f64 / newton.stats().solves as f64
    );
    assert!(worst < 1e-12, "AVF energy error {worst:e}");
    // The midpoint rule on the same chain and step does not keep it.
    struct Sep<'a>(&'a Fpu);
    impl Separable for Sep<'_> {
        fn dof(&self) -> usize {
            self.0.n
        }
        fn kinetic(&self, p: &[f64]) -> f64 {
            0.5 * p.iter().map(|p| p * p).sum::<f64>()
        }
        fn potential(&self, q: &[f64]) -> f64 {
            self.0.potential(q)
        }
        fn velocity(&self, p: &[f64], out: &mut [f64]) {
            out.copy_from_slice(p);
        }
        fn force(&self, q: &[f64], out: &mut [f64]) {
            self.force_and_scale(q, out);
        }
    }
    impl SparsePotential for Sep<'_> {
        fn mass(&self) -> Mass<'_> {
            Mass::Scalar(1.0)
        }
        fn force_and_scale(&self, q: &[f64], out: &mut [f64]) -> f64 {
            out.fill(0.0);
            self.0.add_force(q, 1.0, out)
        }
        fn hessian_pattern(&self) -> Vec<(usize, usize)> {
            self.0.pattern()
        }
        fn hessian_values_projected(&self, q: &[f64], out: &mut [f64]) {
            out.fill(0.0);
            self.0.add_hessian(q, 1.0, out);
        }
    }
    let sep = Sep(&sys);
    let mut z: Vec<f64> = (0..n)
        .map(|i| 0.6 * (0.5 * i as f64).sin())
        .chain((0..n).map(|i| 0.4 * (0.9 * i as f64).cos()))
        .collect();
    let mut stepper = MidpointStepper::new(&sep, MidpointSettings::default()).unwrap();
    let mut worst_mid: f64 = 0.0;
    for _ in 0..200 {
        stepper.step(&sep, &[1.0], h, &mut z).unwrap();
        worst_mid = worst_mid.max(((energy(&z[..n], &z[n..]) - e0) / e0).abs());
    }
    println!("midpoint: relative energy error {worst_mid:e}");
    assert!(worst_mid > 1e-6, "midpoint energy error {worst_mid:e}");
}
