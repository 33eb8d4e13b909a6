//! `butcher!` with `root(...)` entries: `let c0 = root(POLY, LO, HI);` binds a
//! real algebraic number, the entries are polynomials in such roots, and the
//! claims are decided exactly at compile time by the analysis `symlab check`
//! runs on `root(...)` table files. The tables below are rendered from
//! `tests/tables/roots/*.toml` by `tests/three_readers.rs`, which checks that
//! `symlab check` and `symlab compare --table` give the same verdicts.

use integrator_core::problems::Kepler;
use integrator_core::{Scheme, Step, butcher, energy, integrate_fixed};

include!("root_tables/gauss4_roots.rs");
include!("root_tables/radau2a5_roots.rs");
include!("root_tables/lobatto3a3b4_roots.rs");

butcher! {
    /// Gauss–Legendre 4 generated: the same table, rounded by tableau's
    /// symplecticity-aware rounding.
    pub Gauss4Generated { from: "gauss(4)" }
}

butcher! {
    /// An explicit two-stage method of order 2 with a₂₁ = √2/2, written with
    /// a root: unrolled like any explicit table.
    pub ExplicitRoot {
        let r = root(x^2 - 2, 1, 2);
        a: [[0, 0], [r/2, 0]],
        b: [1 - 1/r, 1/r],
    }
}

butcher! {
    /// Gauss–Legendre 2 via roots with its order claimed: decided on the
    /// trees in the number field Q(√3), so ORDER is the claim.
    pub Gauss2RootsOrder4 {
        let c0 = root(6*x^2 - 6*x + 1, 0, 1/2);
        let c1 = root(6*x^2 - 6*x + 1, 1/2, 1);
        claims: [symplectic, order = 4],
        a: [[1/4, c0 - 1/4], [c1 - 1/4, 1/4]],
        b: [1/2, 1/2],
    }
}

#[test]
fn the_verdicts_are_the_exact_ones() {
    assert_eq!((Gauss4Roots::SYMPLECTIC, true), (true, true));
    assert_eq!((Radau5Roots::SYMPLECTIC, false), (false, false));
    assert_eq!((Lobatto3a3b4Roots::SYMPLECTIC, true), (true, true));
    const { assert!(Lobatto3a3b4Roots::SYMPLECTIC_SEPARABLE && !Lobatto3a3b4Roots::SEPARABLE_ONLY) };
    assert_eq!(Lobatto3a3b4Roots::FORM, "prk");
    assert_eq!(Lobatto3a3b4Roots::INFO.evaluations, 8);
    assert_eq!((Gauss4Roots::STAGES, Radau5Roots::STAGES), (4, 5));
    assert_eq!(Gauss4Roots::CLASS, "implicit");
    const { assert!(!Gauss4Roots::EXPLICIT && !Gauss4Roots::SYMMETRIC) };
    // Without an order claim, ORDER is what Σbᵢ = 1 and Σbᵢcᵢ = 1/2 show;
    // with one, the claim, proven on the trees.
    assert_eq!((Gauss4Roots::ORDER, Radau5Roots::ORDER), (2, 2));
    assert_eq!(Gauss4Roots::INFO.order, 2);
    assert_eq!(
        (Gauss2RootsOrder4::ORDER, Gauss2RootsOrder4::INFO.order),
        (4, 4)
    );
    assert_eq!((ExplicitRoot::CLASS, ExplicitRoot::ORDER), ("explicit", 2));
    const { assert!(ExplicitRoot::EXPLICIT) };
}

/// Correctly rounded entries are within half an ulp of the exact values;
/// the generated table's are within one ulp (faithful, chosen to keep W
/// small), so the two differ by at most one ulp and a half.
#[test]
fn coefficients_are_the_correctly_rounded_entries() {
    let ulp = |x: f64| f64::EPSILON * x.abs().max(f64::MIN_POSITIVE);
    for i in 0..4 {
        assert!((Gauss4Roots::B[i] - Gauss4Generated::B[i]).abs() <= 1.5 * ulp(Gauss4Roots::B[i]));
        assert!((Gauss4Roots::C[i] - Gauss4Generated::C[i]).abs() <= 1.5 * ulp(Gauss4Roots::C[i]));
        for j in 0..4 {
            let (x, y) = (Gauss4Roots::A[i][j], Gauss4Generated::A[i][j]);
            assert!((x - y).abs() <= 1.5 * ulp(x), "a[{i}][{j}]: {x:e} vs {y:e}");
        }
    }
    // The nodes of Gauss 4 are symmetric about 1/2.
    assert_eq!(Gauss4Roots::C[0] + Gauss4Roots::C[3], 1.0);
    assert_eq!(ExplicitRoot::A[1][0], std::f64::consts::FRAC_1_SQRT_2);
}

fn kepler_orbit_error<S: Step<Kepler>>(scheme: &S, steps: usize) -> (f64, f64) {
    let kepler = Kepler { e: 0.5 };
    let mut z = kepler.initial_state();
    let e0 = energy(&kepler, &z);
    let mut ws = scheme.workspace(&kepler);
    let h = 2.0 * std::f64::consts::PI / steps as f64;
    for k in 0..steps {
        scheme
            .step(&kepler, k as f64 * h, h, &mut z, &mut ws)
            .unwrap();
    }
    let exact = kepler.initial_state(); // one period later
    let err = z
        .iter()
        .zip(&exact)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    (err, (energy(&kepler, &z) - e0).abs())
}

#[test]
fn gauss4_via_roots_steps_kepler_through_the_stage_solver() {
    // Order 8: one orbit of e = 0.5 in 50 steps is accurate to ~1e-7.
    let (err, de) = kepler_orbit_error(&Gauss4Roots, 50);
    assert!(err < 1e-6, "Gauss 4 via roots: error {err:e}");
    assert!(de < 1e-9, "energy error {de:e}");
    // The same steps as the generated scheme, up to the last bits of the
    // coefficients.
    let (gen_err, _) = kepler_orbit_error(&Gauss4Generated, 50);
    assert!((err - gen_err).abs() < 1e-10, "{err:e} vs {gen_err:e}");
    // Halving the step divides the error by about 2⁸.
    let (err2, _) = kepler_orbit_error(&Gauss4Roots, 100);
    assert!(err / err2 > 100.0, "{err:e} → {err2:e}");
}

#[test]
fn radau5_via_roots_steps_kepler() {
    let (err, _) = kepler_orbit_error(&Radau5Roots, 50);
    assert!(err < 1e-5, "Radau IIA 5 via roots: error {err:e}");
}

#[test]
fn lobatto_pair_via_roots_steps_kepler() {
    // Order 6: one orbit in 50 steps.
    let (err, _) = kepler_orbit_error(&Lobatto3a3b4Roots, 50);
    assert!(err < 1e-4, "Lobatto IIIA–IIIB 4 via roots: error {err:e}");
    let (err2, _) = kepler_orbit_error(&Lobatto3a3b4Roots, 100);
    assert!(err / err2 > 30.0, "{err:e} → {err2:e}");
}

#[test]
fn explicit_root_table_is_unrolled_and_second_order() {
    let kepler = Kepler { e: 0.0 };
    let run = |n: usize| {
        let mut z: [f64; 4] = kepler.initial_state().try_into().unwrap();
        let h = 2.0 * std::f64::consts::PI / n as f64;
        integrate_fixed(&ExplicitRoot, &kepler, &mut z, 0.0, h, n, |_, _, _| {}).unwrap();
        let exact = kepler.initial_state();
        z.iter()
            .zip(&exact)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    let (e1, e2) = (run(1000), run(2000));
    assert!(e1 < 1e-3, "{e1:e}");
    let rate = (e1 / e2).log2();
    assert!((rate - 2.0).abs() < 0.2, "observed order {rate}");
}
