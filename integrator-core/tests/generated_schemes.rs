//! `butcher!` with a generated table: `from: "gauss8"` declares a scheme
//! whose table `tableau::algebraic` generates and proves exactly at compile
//! time (roots of the Legendre polynomial, not radicals), stepped by the
//! stage solver.

use integrator_core::problems::Kepler;
use integrator_core::{Scheme, Step, butcher, energy};

butcher! {
    /// Gauss–Legendre, 5 stages, with the literature's claims.
    pub Gauss5 { from: "gauss5" }
}

butcher! {
    /// Gauss–Legendre, 8 stages, order 16, with claims of our own.
    pub Gauss8 {
        claims: [symplectic, symmetric, order = 16],
        from: "gauss(8)",
    }
}

butcher! {
    /// Radau IIA, 4 stages: order 7, not symplectic.
    pub Radau4 { from: "radau2a4" }
}

butcher! {
    /// The Lobatto IIIA–IIIB pair with 4 stages.
    pub LobattoPair4 { from: "lobatto3a3b4" }
}

#[test]
fn the_verified_facts_are_the_literature_s() {
    assert_eq!((Gauss8::STAGES, Gauss8::ORDER), (8, 16));
    // Proven at compile time: the assertions are constants.
    const { assert!(Gauss8::SYMPLECTIC && Gauss8::SYMMETRIC && !Gauss8::EXPLICIT) };
    assert_eq!(Gauss5::ORDER, 10);
    assert_eq!((Radau4::ORDER, Radau4::SYMPLECTIC), (7, false));
    const { assert!(LobattoPair4::SYMPLECTIC) };
    assert_eq!(LobattoPair4::FORM, "prk");
    assert_eq!(Gauss8::INFO.class, "implicit");
    // The weights sum to one in floating point; the nodes lie in (0, 1).
    assert_eq!(Gauss8::B.iter().sum::<f64>(), 1.0);
    assert!(Gauss8::C.iter().all(|c| *c > 0.0 && *c < 1.0));
    // Gauss: |R(iy)| = 1, so P(z) = Q(−z); constant terms one.
    assert_eq!(Gauss8::STABILITY_Q[0], 1.0);
    for (k, (p, q)) in Gauss8::STABILITY_P
        .iter()
        .zip(&Gauss8::STABILITY_Q)
        .enumerate()
    {
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        assert_eq!(*p, sign * q, "coefficient {k}");
    }
}

#[test]
fn gauss8_steps_kepler_to_round_off_level_energy() {
    let kepler = Kepler { e: 0.5 };
    let mut z = kepler.initial_state();
    let e0 = energy(&kepler, &z);
    let mut ws = Step::<Kepler>::workspace(&Gauss8, &kepler);
    let h = 2.0 * std::f64::consts::PI / 50.0;
    for k in 0..50 {
        Gauss8
            .step(&kepler, k as f64 * h, h, &mut z, &mut ws)
            .unwrap();
    }
    let exact = kepler.initial_state(); // one period later
    let err = z
        .iter()
        .zip(&exact)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(err < 1e-9, "one orbit, 50 steps: error {err:e}");
    assert!((energy(&kepler, &z) - e0).abs() < 1e-13);
}
