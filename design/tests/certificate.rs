//! Certificates: re-checked from the emitted text, refused once a
//! coefficient moves beyond the radius, and `symlab check`'s bound claim
//! refused once the residual exceeds it.

use design::certify::Refusal;
use design::design;
use design::verify::{VerifyError, verify_table};

use crate::common::{claims_hold, load};

fn mclachlan_table() -> (design::Family, String) {
    let mut family = load("mclachlan-sb3a.toml");
    family.starts = 60;
    let out = design(&family, "designs/mclachlan-sb3a.toml", &mut |_| {}).unwrap();
    let text = out.designs[0].table.as_ref().unwrap().1.clone();
    (family, text)
}

/// The text with `let.a1`'s value replaced by itself plus `delta`.
fn shift_a1(text: &str, delta: &str) -> String {
    text.lines()
        .map(|l| match l.strip_prefix("let.a1 = \"") {
            Some(v) => format!("let.a1 = \"{} + {delta}\"", v.trim_end_matches('"')),
            None => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn the_certificate_is_rechecked_and_refused_beyond_its_radius() {
    let (family, text) = mclachlan_table();
    let cert = verify_table(&family, "t.toml", &text).unwrap();
    assert_eq!(
        cert.radius,
        "1/10000000000000000000000000000000000000000000000"
            .parse()
            .unwrap()
    );
    // Within the radius (a hundredth of it): still proven.
    verify_table(&family, "t.toml", &shift_a1(&text, "1e-48")).unwrap();
    // Ten times the radius: refused, whichever way.
    for delta in ["1e-45", "-1e-45"] {
        match verify_table(&family, "t.toml", &shift_a1(&text, delta)) {
            Err(VerifyError::Refused(Refusal::NotContained { offset, .. })) => {
                assert!(offset > 1.0, "{offset}")
            }
            other => panic!("{delta}: {other:?}"),
        }
    }
}

#[test]
fn an_edit_outside_the_parametrisation_is_refused() {
    let (family, text) = mclachlan_table();
    let edited = text.replace("\"2179/4307\"", "\"2180/4307\"");
    assert_ne!(edited, text);
    match verify_table(&family, "t.toml", &edited) {
        Err(VerifyError::Shape(m)) => assert!(m.contains("coefficient"), "{m}"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn check_decides_the_bound_claim_on_the_printed_decimals() {
    let (_, text) = mclachlan_table();
    let ok = claims_hold("t.toml", &text);
    assert!(ok.iter().all(|(_, v)| v.is_ok()), "{ok:?}");
    // Moved by 1e-30, the residuals exceed the claimed 1e-40: refused.
    let moved = shift_a1(&text, "1e-30");
    let verdicts = claims_hold("t.toml", &moved);
    let order = verdicts
        .iter()
        .find(|(c, _)| c.starts_with("order"))
        .unwrap();
    assert!(order.1.is_err(), "{order:?}");
}
