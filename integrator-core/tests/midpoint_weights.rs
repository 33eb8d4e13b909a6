//! `Info::midpoint_weights`: `butcher!` marks a table that is a composition of
//! implicit midpoint steps, deciding it on the exact entries, so that a
//! minimisation solver can step a user's table of that shape as well as the
//! library's.

use integrator_core::library::{GaussLegendre2, ImplicitMidpoint, PaperDirk2, PaperDirk4};
use integrator_core::{Scheme, butcher};

butcher! {
    /// A user's composition of three midpoint steps (1/4, 1/2, 1/4):
    /// symmetric, symplectic, order 2.
    pub QuarterHalfQuarter {
        claims: [symplectic, symmetric, order = 2],
        a: [[1/8, 0, 0], [1/4, 1/4, 0], [1/4, 1/2, 1/8]],
        b: [1/4, 1/2, 1/4],
    }
}

butcher! {
    /// The same shape except that one entry differs from 1/8 by 10⁻³⁰:
    /// its doubles are those of `QuarterHalfQuarter`, its exact table is not
    /// a midpoint composition (nor symplectic).
    pub NearlyQuarterHalfQuarter {
        claims: [order = 1],
        a: [[1/8 + 1/1000000000000000000000000000000, 0, 0], [1/4, 1/4, 0], [1/4, 1/2, 1/8]],
        b: [1/4, 1/2, 1/4],
    }
}

butcher! {
    /// Generated: the one-stage Gauss table is the midpoint rule.
    pub Gauss1 { from: "gauss1" }
}

#[test]
fn library_midpoint_family_is_marked() {
    assert_eq!(ImplicitMidpoint::INFO.midpoint_weights, Some(&[1.0][..]));
    assert_eq!(PaperDirk2::INFO.midpoint_weights, Some(&[0.5, 0.5][..]));
    let w = PaperDirk4::INFO.midpoint_weights.expect("the triple jump");
    assert_eq!(w.len(), 3);
    assert!(
        w[1] < 0.0,
        "the middle weight of the triple jump is negative"
    );
    assert_eq!(w, &PaperDirk4::B[..]);
    assert_eq!(GaussLegendre2::INFO.midpoint_weights, None);
    assert_eq!(Gauss1::INFO.midpoint_weights, Some(&[1.0][..]));
}

#[test]
fn a_users_table_of_that_shape_is_marked() {
    assert_eq!(
        QuarterHalfQuarter::INFO.midpoint_weights,
        Some(&[0.25, 0.5, 0.25][..])
    );
}

#[test]
fn the_decision_is_exact_not_on_the_doubles() {
    // The doubles agree entry by entry…
    assert_eq!(NearlyQuarterHalfQuarter::A, QuarterHalfQuarter::A);
    // …the exact tables do not.
    assert_eq!(NearlyQuarterHalfQuarter::INFO.midpoint_weights, None);
    const { assert!(!NearlyQuarterHalfQuarter::INFO.symplectic) };
}
