//! The constants `butcher!` emits: verdicts, and coefficients that are the
//! doubles nearest to the exact values.

use integrator_core::butcher;

butcher! {
    /// Störmer–Verlet: the Lobatto IIIA–IIIB pair, order 2.
    pub StormerVerlet {
        claims: [symplectic, symmetric, order = 2],
        a: [[0, 0], [1/2, 1/2]],        b: [1/2, 1/2],
        a_hat: [[1/2, 0], [1/2, 0]],    b_hat: [1/2, 1/2],
    }
}

butcher! {
    /// Forest–Ruth / Yoshida, order 4, as a drift–kick sequence.
    pub ForestRuth {
        let x = 1/(2 - cbrt(2));
        claims: [symplectic, symmetric, explicit, order = 4],
        drift: [x/2, (1 - x)/2, (1 - x)/2, x/2],
        kick:  [x, 1 - 2*x, x],
    }
}

butcher! {
    /// RK4, without a symplectic claim: a baseline.
    Rk4 {
        claims: [explicit, order = 4],
        a: [[0, 0, 0, 0], [1/2, 0, 0, 0], [0, 1/2, 0, 0], [0, 0, 1, 0]],
        b: [1/6, 1/3, 1/3, 1/6],
    }
}

butcher! {
    /// Lobatto IIIB with its c, which is not the row sums.
    LobattoIIIB2 {
        claims: [order = 2],
        a: [[1/2, 0], [1/2, 0]],
        b: [1/2, 1/2],
        c: [0, 1],
    }
}

#[test]
fn verdicts() {
    const { assert!(StormerVerlet::SYMPLECTIC && StormerVerlet::SYMMETRIC) };
    assert_eq!(StormerVerlet::ORDER, 2);
    assert_eq!(StormerVerlet::FORM, "prk");
    const {
        assert!(
            ForestRuth::SYMPLECTIC_SEPARABLE && ForestRuth::SEPARABLE_ONLY && ForestRuth::EXPLICIT
        )
    };
    const { assert!(!Rk4::SYMPLECTIC && !Rk4::SYMMETRIC) };
    assert_eq!(Rk4::CLASS, "explicit");
    assert_eq!(LobattoIIIB2::C, [0.0, 1.0]);
}

#[test]
fn coefficients_are_the_nearest_doubles() {
    // x = 1/(2 − 2^(1/3)) = 1.35120719195965763404…: nearest double …6575.
    assert_eq!(ForestRuth::KICK[0], 1.351_207_191_959_657_5);
    assert_eq!(ForestRuth::DRIFT.len(), 4);
    // RK4's correctly rounded weights sum to 1 − 2⁻⁵³… in floating point; the
    // emitted ones sum to exactly 1.0, each still within one ulp of 1/6, 1/3.
    let nearest = [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0];
    assert_ne!(nearest.iter().sum::<f64>(), 1.0);
    assert_eq!(Rk4::B.iter().sum::<f64>(), 1.0);
    for (e, n) in Rk4::B.iter().zip(nearest) {
        assert!((e - n).abs() <= f64::EPSILON * n, "{e} vs {n}");
    }
}

// The compile errors of false claims (trybuild) are integrator-macros'
// tests: `integrator-macros/tests/compile_fail.rs`.

butcher! {
    /// The triple jump with its coefficients rounded to 17 digits: the order
    /// conditions hold only to a residual, which the claim states.
    RoundedTripleJump {
        claims: [symplectic, symmetric, order = 4 (residual < 1e-15)],
        compose: [1.3512071919596576, -1.7024143839193152, 1.3512071919596576],
    }
}

butcher! {
    /// McLachlan–Atela 4 typed in (catalogue: mclachlan-atela4): order 3 on
    /// separable systems, 4 on Runge–Kutta–Nyström systems (T quadratic).
    McAte4 {
        claims: [
            symplectic,
            order = 3 (residual < 1e-17),
            order_rkn = 4 (residual < 1e-17),
        ],
        drift: [0, 0.5153528374311229364, -0.085782019412973646, 0.4415830236164665242,
                0.1288461583653841854],
        kick: [0.1344961992774310892, -0.2248198030794208058, 0.7563200005156682911,
               0.3340036032863214255],
    }
}

#[test]
fn bounded_claims_compile() {
    // The order constant is the `order` claim, on general separable systems.
    assert_eq!(McAte4::ORDER, 3);
    assert_eq!(RoundedTripleJump::ORDER, 4);
    assert_eq!(RoundedTripleJump::GAMMA[1], -1.702_414_383_919_315);
}
