//! The generalised orders the verifier proves, measured: on a near-integrable
//! system `H = A + εB` the global error of a splitting of generalised order
//! `(p₁, p₂)` is `C₁ ε h^{p₁} + C₂ ε² h^{p₂} + …`. Both terms are measured
//! separately, each in the regime where it dominates:
//!
//! - **the `ε` term**: `ε` of 1e-6 or 1e-7, steps where `ε h^{p₁} ≫ ε² h^{p₂}`; the
//!   error must be linear in `ε` (doubling `ε` doubles it) and its slope in
//!   `h` must be `p₁`;
//! - **the `ε²` term**: `ε = 0.02`, small steps where `ε² h^{p₂} ≫ ε h^{p₁}`;
//!   the error must be quadratic in `ε` (doubling `ε` multiplies it by
//!   four) and its slope in `h` must be `p₂`.
//!
//! The system: `A = (q² + p²)/2` (the harmonic oscillator, flow a rotation)
//! and `B = q⁴/4` (flow a kick `p ← p − hεq³`), so `{{A, B}, B} ∝ q⁶ ≠ 0`:
//! the `ε²` terms do not vanish. The whole `H = p²/2 + q²/2 + εq⁴/4` is
//! separable, and the reference is Kahan–Li 8 on it with steps small enough
//! that its error is below 1e-15.
//!
//! SABA₂ and SBAB₂ have `(4, 2)`, SABA₃ and SBAB₃ `(6, 2)` (Laskar & Robutel
//! 2001), proven exactly by `butcher!` from their catalogue claims.

use integrator_core::library::{KahanLi8, Saba2, Saba3, Sbab2, Sbab3};
use integrator_core::{Scheme, Separable, Step, integrate};

/// `H = (q² + p²)/2 + ε q⁴/4`, split as the oscillator and the quartic kick.
use crate::quartic;
use quartic::Quartic as Perturbed;

/// The same `H` as a separable Hamiltonian, for the reference.
struct Whole {
    eps: f64,
}

impl Separable for Whole {
    fn dof(&self) -> usize {
        1
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        0.5 * p[0] * p[0]
    }
    fn potential(&self, q: &[f64]) -> f64 {
        let q2 = q[0] * q[0];
        0.5 * q2 + 0.25 * self.eps * q2 * q2
    }
    fn velocity(&self, p: &[f64], out: &mut [f64]) {
        out[0] = p[0];
    }
    fn force(&self, q: &[f64], out: &mut [f64]) {
        out[0] = -q[0] - self.eps * q[0] * q[0] * q[0];
    }
}

const Z0: [f64; 2] = [1.0, 0.5];
const T: f64 = 100.0;
/// Reference steps: Kahan–Li 8 at h = 0.0025.
const REFERENCE_STEPS: usize = 40_000;

fn reference(eps: f64) -> [f64; 2] {
    let mut z = Z0;
    integrate(
        &KahanLi8,
        &Whole { eps },
        &mut z,
        0.0,
        T / REFERENCE_STEPS as f64,
        REFERENCE_STEPS,
        |_, _, _| {},
    )
    .unwrap();
    z
}

/// Error at `T` of `M` with `n` steps, in the Euclidean norm: the error is
/// mostly a phase error along a near-circular orbit, whose Euclidean size
/// does not depend on where on the orbit the run ends (the max norm would
/// change with the final phase, which moves with `ε`).
fn error<M: Scheme + Step<Perturbed> + Default>(eps: f64, n: usize, exact: &[f64; 2]) -> f64 {
    let mut z = Z0;
    integrate(
        &M::default(),
        &Perturbed { eps },
        &mut z,
        0.0,
        T / n as f64,
        n,
        |_, _, _| {},
    )
    .unwrap();
    (z[0] - exact[0]).hypot(z[1] - exact[1])
}

/// Least-squares slope of `log e` against `log h`.
fn slope(points: &[(f64, f64)]) -> f64 {
    let k = points.len() as f64;
    let (xs, ys): (Vec<f64>, Vec<f64>) = points.iter().map(|(h, e)| (h.ln(), e.ln())).unzip();
    let (mx, my) = (xs.iter().sum::<f64>() / k, ys.iter().sum::<f64>() / k);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// What one regime measured: the slope in `h` and `log₂` of the error's
/// growth when `ε` doubles (1 for the `ε` term, 2 for the `ε²` term).
struct Regime {
    slope: f64,
    eps_power: f64,
}

fn regime<M: Scheme + Step<Perturbed> + Default>(eps: f64, steps: &[usize]) -> Regime {
    let (exact, exact2) = (reference(eps), reference(2.0 * eps));
    let mut points = Vec::new();
    let mut powers = Vec::new();
    for &n in steps {
        let (e, e2) = (
            error::<M>(eps, n, &exact),
            error::<M>(2.0 * eps, n, &exact2),
        );
        println!(
            "  {:>8} ε = {eps:.0e}, h = {:.4}: error {e:.3e}, with 2ε {e2:.3e}",
            M::INFO.name,
            T / n as f64
        );
        points.push((T / n as f64, e));
        powers.push((e2 / e).log2());
    }
    Regime {
        slope: slope(&points),
        eps_power: powers.iter().sum::<f64>() / powers.len() as f64,
    }
}

/// The order a measured slope shows, by the rule of `tests/convergence.rs`:
/// the admissible order nearest to the slope, where a symmetric scheme's
/// orders are even (its error terms have odd powers of `h` only; the
/// slopes of order-6 methods at these steps, 5.97 and 6.37, still carry the
/// `h⁸` term) and any integer otherwise.
fn inferred<M: Scheme>(slope: f64) -> usize {
    if M::INFO.symmetric {
        2 * (slope / 2.0).round() as usize
    } else {
        slope.round() as usize
    }
}

/// Checks both terms of `M`, whose proven generalised order is `(p1, p2)`.
fn check<M: Scheme + Step<Perturbed> + Default>(
    (p1, p2): (usize, usize),
    (eps, first): (f64, &[usize]),
    second: &[usize],
) -> Vec<String> {
    let mut failures = Vec::new();
    let a = regime::<M>(eps, first);
    let b = regime::<M>(0.02, second);
    println!(
        "{}: ε term slope {:.2} (p₁ = {p1}), ε power {:.2}; ε² term slope {:.2} (p₂ = {p2}), ε power {:.2}",
        M::INFO.name,
        a.slope,
        a.eps_power,
        b.slope,
        b.eps_power
    );
    if inferred::<M>(a.slope) != p1 || (a.eps_power - 1.0).abs() > 0.1 {
        failures.push(format!(
            "{}: the ε term measured slope {:.2}, ε power {:.2}; proven p₁ = {p1}",
            M::INFO.name,
            a.slope,
            a.eps_power
        ));
    }
    if inferred::<M>(b.slope) != p2 || (b.eps_power - 2.0).abs() > 0.2 {
        failures.push(format!(
            "{}: the ε² term measured slope {:.2}, ε power {:.2}; proven p₂ = {p2}",
            M::INFO.name,
            b.slope,
            b.eps_power
        ));
    }
    failures
}

#[test]
fn reference_is_converged() {
    for eps in [1e-6, 0.04] {
        let a = reference(eps);
        let mut b = Z0;
        let n = 2 * REFERENCE_STEPS;
        integrate(
            &KahanLi8,
            &Whole { eps },
            &mut b,
            0.0,
            T / n as f64,
            n,
            |_, _, _| {},
        )
        .unwrap();
        let d = (a[0] - b[0]).abs().max((a[1] - b[1]).abs());
        assert!(d < 1e-14, "ε = {eps}: reference moves by {d:e}");
    }
}

#[test]
fn both_terms_scale_with_the_proven_generalised_orders() {
    // The ε term: ε = 1e-6 and steps of 0.5 … 0.125 for order 4; ε = 1e-7
    // and steps of 0.8 … 0.4 for order 6, where ε²h² stays below 1 % of it
    // and the error above round-off. The ε² term: steps of 0.02 … 0.005.
    let order4 = (1e-6, &[200, 400, 800][..]);
    let order6 = (1e-7, &[125, 175, 250][..]);
    let small = [5000, 10000, 20000];
    let mut failures = Vec::new();
    failures.extend(check::<Saba2>((4, 2), order4, &small));
    failures.extend(check::<Sbab2>((4, 2), order4, &small));
    failures.extend(check::<Saba3>((6, 2), order6, &small));
    failures.extend(check::<Sbab3>((6, 2), order6, &small));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
