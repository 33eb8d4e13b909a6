//! Brouwer's law: with compensated summation the round-off part of the
//! energy error of Gauss–Legendre 2 grows like a random walk, √n at most;
//! without it, faster.
//!
//! The orbit is circular (Kepler with e = 0): by rotational symmetry the
//! method's truncation error in the energy is then a constant reached after
//! the first step, so what grows over 10⁶ steps is round-off alone. (On an
//! eccentric orbit the O(h⁴) oscillation of the energy would hide it unless
//! h were tiny.)

use integrator_core::library::GaussLegendre2;
use integrator_core::problems::Kepler;
use integrator_core::{Step, energy};

/// The running maximum of |E − E₀| at geometrically spaced step counts.
fn energy_error_growth(compensated: bool, n: usize, h: f64) -> Vec<(f64, f64)> {
    let k = Kepler { e: 0.0 };
    let mut z = k.initial_state();
    let mut ws = GaussLegendre2.workspace(&k);
    ws.settings_mut().compensated = compensated;
    let e0 = energy(&k, &z);
    let (mut next, mut max_err) = (1000usize, 0.0f64);
    let mut samples = Vec::new();
    for i in 1..=n {
        GaussLegendre2.step(&k, 0.0, h, &mut z, &mut ws).unwrap();
        max_err = max_err.max((energy(&k, &z) - e0).abs());
        if i == next {
            samples.push((i as f64, max_err.max(f64::EPSILON / 4.0)));
            next = next * 3 / 2;
        }
    }
    samples
}

/// Least-squares slope of log y against log x.
fn exponent(samples: &[(f64, f64)]) -> f64 {
    let pts: Vec<(f64, f64)> = samples.iter().map(|(x, y)| (x.ln(), y.ln())).collect();
    let m = pts.len() as f64;
    let (sx, sy) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    let (mx, my) = (sx / m, sy / m);
    let num: f64 = pts.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let den: f64 = pts.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    num / den
}

#[test]
fn compensated_summation_gives_brouwer_growth() {
    let n = 1_000_000;
    let with = energy_error_growth(true, n, 1e-3);
    let without = energy_error_growth(false, n, 1e-3);
    let (a, b) = (exponent(&with), exponent(&without));
    let (ea, eb) = (with.last().unwrap().1, without.last().unwrap().1);
    println!(
        "fitted exponents over 10³…10⁶ steps: compensated {a:.2} (final error {ea:.1e}), plain {b:.2} (final error {eb:.1e})"
    );
    assert!(
        a < 0.5,
        "compensated: exponent {a:.2} is not below √n growth"
    );
    assert!(
        b > a + 0.2,
        "plain summation should grow faster: {b:.2} vs {a:.2}"
    );
    assert!(
        eb > 10.0 * ea,
        "plain summation should end far worse: {eb:e} vs {ea:e}"
    );
}

/// The same for an explicit scheme: leapfrog conserves the angular momentum
/// of a central-force problem exactly, so its error in `L` is round-off
/// alone, and the generated step code's compensated drifts and kicks keep
/// it to a random walk.
#[test]
fn generated_code_compensates_too() {
    use integrator_core::library::Leapfrog;
    let run = |compensated: bool| {
        let k = Kepler { e: 0.6 };
        let mut z = k.initial_state();
        let mut ws = Leapfrog.workspace(&k);
        ws.compensated = compensated;
        let l0 = Kepler::angular_momentum(&z);
        let (mut next, mut max_err) = (1000usize, 0.0f64);
        let mut samples = Vec::new();
        for i in 1..=1_000_000usize {
            Leapfrog.step(&k, 0.0, 0.01, &mut z, &mut ws).unwrap();
            max_err = max_err.max((Kepler::angular_momentum(&z) - l0).abs());
            if i == next {
                samples.push((i as f64, max_err.max(f64::EPSILON / 4.0)));
                next = next * 3 / 2;
            }
        }
        samples
    };
    let (with, without) = (run(true), run(false));
    let (a, b) = (exponent(&with), exponent(&without));
    let (ea, eb) = (with.last().unwrap().1, without.last().unwrap().1);
    println!(
        "leapfrog, angular momentum: compensated {a:.2} (final {ea:.1e}), plain {b:.2} (final {eb:.1e})"
    );
    assert!(a < 0.6, "compensated: exponent {a:.2}");
    assert!(
        eb > 3.0 * ea,
        "plain summation should end worse: {eb:e} vs {ea:e}"
    );
}
