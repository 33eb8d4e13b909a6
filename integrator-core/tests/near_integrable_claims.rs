//! `butcher!` claims of generalised orders for near-integrable H = A + εB
//! (drifts the flow of A, kicks that of εB), checked exactly at compile
//! time; the false ones are compile errors (integrator-macros/tests/ui/near_integrable_order_claims.rs).

use integrator_core::butcher;

butcher! {
    /// Laskar–Robutel SABA₃ (Gauss–Legendre nodes): O(εh⁶ + ε²h²).
    pub Saba3 {
        let c1 = 1/2 - sqrt(15)/10;
        let c2 = sqrt(15)/10;
        claims: [symplectic, symmetric, order = 2, order = (6, 2)],
        drift: [c1, c2, c2, c1],
        kick: [5/18, 4/9, 5/18],
    }
}

butcher! {
    /// Laskar–Robutel SBAB₄ (Lobatto nodes): O(εh⁸ + ε²h²).
    pub Sbab4 {
        let c2 = 1/2 - sqrt(21)/14;
        let c3 = sqrt(21)/14;
        claims: [symplectic, symmetric, order = (8, 2)],
        drift: [c2, c3, c3, c2],
        kick: [1/20, 49/180, 16/45, 49/180, 1/20],
    }
}

butcher! {
    /// Blanes et al. ABA(8,6,4), 40-digit coefficients (the middle ones by
    /// consistency): O(εh⁸ + ε²h⁶ + ε³h⁴) up to the residual of the digits.
    pub Aba864 {
        let c0 = 0.0711334264982231177779387300061549964174;
        let c1 = 0.241153427956640098736487795326289649618;
        let c2 = 0.521411761772814789212136078067994229991;
        let c3 = (1 - (2*c0 + 2*c1 + 2*c2))/2;
        let d0 = 0.183083687472197221961703757166430291072;
        let d1 = 0.310782859898574869507522291054262796375;
        let d2 = -0.0265646185119588006972121379164987592663;
        let d3 = 1 - (2*d0 + 2*d1 + 2*d2);
        claims: [symplectic, symmetric, order = 4 (residual < 1e-37), order = (8, 6, 4) (residual < 1e-38)],
        drift: [c0, c1, c2, c3, c3, c2, c1, c0],
        kick: [d0, d1, d2, d3, d2, d1, d0],
    }
}

#[test]
fn generalised_claims_compile_and_keep_the_classical_constants() {
    // The generalised claim adds no classical order: ORDER is the classical
    // one (claimed, or proven where none is claimed).
    assert_eq!(Saba3::ORDER, 2);
    assert_eq!(Sbab4::ORDER, 2);
    assert_eq!(Aba864::ORDER, 4);
    assert_eq!(Sbab4::KICK.len(), 5);
    assert_eq!(Aba864::DRIFT.len(), 8);
}
