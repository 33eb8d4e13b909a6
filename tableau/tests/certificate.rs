//! Certified orders (`order = p (certified)` with a `certificate`): proven
//! by Krawczyk's test on the file's own coefficients, reported as "order p
//! within radius r of the printed coefficients", and refused once a
//! coefficient moves beyond the radius, or the radius or the claim is too
//! ambitious.

use tableau::algebraic::file::{Loaded, parse};
use tableau::claims::{Claim, parse_claim};
use tableau::verdict::{Analysed, Options, Verdict};

/// 1/(2 − 2^{1/3}) to 50 decimals: Yoshida's triple jump, whose exact
/// value is within 1e-50 of it.
const G1: &str = "1.35120719195965763404768780897146082692199937621714";

fn yoshida(g1: &str, radius: &str, claims: &str) -> String {
    format!(
        r#"name = "Yoshida's triple jump, printed to 50 digits"
claims = [{claims}]
certificate = {{ unknowns = ["g1"], radius = "{radius}" }}
let = {{ g1 = "{g1}" }}
compose = ["g1", "1 - 2*g1", "g1"]
"#
    )
}

fn verdict(text: &str) -> Verdict {
    let loaded = parse("t.toml", text).unwrap_or_else(|e| panic!("{e}"));
    assert!(matches!(loaded, Loaded::Classic(_)));
    Verdict::of("t.toml", &loaded, &Options::default()).unwrap()
}

#[test]
fn the_claim_parses_and_prints() {
    let c = parse_claim("order = 4 (certified)").unwrap();
    assert_eq!(c, Claim::CertifiedOrder { p: 4 });
    assert_eq!(c.to_string(), "order = 4 (certified)");
    // Whitespace is free, as the macro's tokens print the claim.
    assert_eq!(
        parse_claim(" order=6 ( certified )").unwrap(),
        Claim::CertifiedOrder { p: 6 }
    );
    assert_eq!(
        parse_claim("order = ( 6 , 2 ) ( certified )").unwrap(),
        Claim::CertifiedNearOrder { orders: vec![6, 2] }
    );
    assert!(parse_claim("order = 4 (certify)").is_err());
    let e = parse_claim("order = 4 (residual < 1e-9) (certified)").unwrap_err();
    assert!(e.contains("no residual bound"), "{e}");
}

#[test]
fn a_certified_composition_is_proven_and_reported_with_its_radius() {
    let v = verdict(&yoshida(
        G1,
        "1e-45",
        r#""symmetric", "order = 4 (certified)""#,
    ));
    assert!(v.claims.iter().all(|c| c.verdict.is_ok()), "{:?}", v.claims);
    let Analysed::Classic {
        certificate: Some(proof),
        ..
    } = &v.analysed
    else {
        panic!("a proof: {:?}", v.analysed)
    };
    let proof = proof.as_ref().as_ref().unwrap();
    assert_eq!(proof.conditions, ["Y₃"]);
    assert!(proof.contraction < 1.0);
    assert!(proof.next_order.is_some(), "the order is exactly 4");
    let report = v.to_string();
    assert!(
        report.contains("certificate  order 4 within radius 1e-45 of the printed coefficients (g1): Krawczyk's test"),
        "{report}"
    );
    assert!(
        report.contains("so the order there is exactly 4"),
        "{report}"
    );
    let json = v.to_json();
    assert_eq!(json["certificate"]["radius"], "1e-45");
    assert_eq!(json["certificate"]["order"], 4);
    // The printed decimals themselves do not have order 4 exactly.
    let plain = verdict(&yoshida(G1, "1e-45", r#""order = 4""#));
    assert!(plain.claims[0].verdict.is_err());
}

#[test]
fn a_coefficient_beyond_the_radius_is_refused() {
    // Moved by 1e-40, ten thousand radii: no solution in the box.
    let moved = format!("{G1} + 1e-40");
    let v = verdict(&yoshida(&moved, "1e-44", r#""order = 4 (certified)""#));
    let e = v.claims[0].verdict.as_ref().unwrap_err();
    assert!(
        e.contains("order 4 within radius 1e-44 is not proven: Krawczyk's test fails"),
        "{e}"
    );
    // Within the radius (a hundredth of it) the claim still holds.
    let near = format!("{G1} + 1e-46");
    let v = verdict(&yoshida(&near, "1e-44", r#""order = 4 (certified)""#));
    assert!(v.claims[0].verdict.is_ok(), "{:?}", v.claims);
    // A radius below the printed digits' error: refused too.
    let v = verdict(&yoshida(G1, "1e-60", r#""order = 4 (certified)""#));
    assert!(v.claims[0].verdict.is_err());
}

#[test]
fn over_claims_and_bad_certificates_are_refused() {
    // Order 6 needs Y₅ and Y₁Y₁Y₃ as well: two conditions, one unknown.
    let v = verdict(&yoshida(G1, "1e-45", r#""order = 6 (certified)""#));
    let e = v.claims[0].verdict.as_ref().unwrap_err();
    assert!(e.contains("Krawczyk's test needs a square system"), "{e}");
    assert!(e.contains("are 3 (Y₃, Y₁Y₁Y₃, Y₅)"), "{e}");
    // Bad certificates: named by field.
    for (edit, field, phrase) in [
        (
            r#"unknowns = ["g2"]"#,
            "certificate.unknowns[0]",
            "not bound in `let`",
        ),
        (r#"unknowns = []"#, "certificate.unknowns", "1 to 16"),
        (
            r#"radius = "-1""#,
            "certificate.radius",
            "positive rational",
        ),
        (
            r#"radius = "sqrt(2)""#,
            "certificate.radius",
            "positive rational",
        ),
        (r#"size = "1""#, "certificate.size", "unknown field"),
    ] {
        let text = yoshida(G1, "1e-45", r#""order = 4 (certified)""#);
        let text = if edit.starts_with("unknowns") {
            text.replace(r#"unknowns = ["g1"]"#, edit)
        } else if edit.starts_with("radius") {
            text.replace(r#"radius = "1e-45""#, edit)
        } else {
            text.replace(
                r#"radius = "1e-45""#,
                &format!("radius = \"1e-45\", {edit}"),
            )
        };
        let e = parse("t.toml", &text).unwrap_err();
        assert_eq!(e.field.as_deref(), Some(field), "{edit}: {e}");
        assert!(e.message.contains(phrase), "{edit}: {e}");
    }
    // Without a certificate the claim is refused, saying why.
    let text = yoshida(G1, "1e-45", r#""order = 4 (certified)""#).replace(
        "certificate = { unknowns = [\"g1\"], radius = \"1e-45\" }\n",
        "",
    );
    let v = verdict(&text);
    let e = v.claims[0].verdict.as_ref().unwrap_err();
    assert!(e.contains("`certificate`"), "{e}");
}

/// A drift–kick sequence `exp(b₁A) exp(B) exp((1 − b₁)A)`: consistency
/// holds identically, and order 2 is the one condition `[A,B]`: `b₁ = 1/2`
/// (Strang). Printed as 0.5 + 10⁻²⁵ with radius 10⁻²⁰ it is certified; as
/// 0.5 + 10⁻¹⁹ it is refused.
#[test]
fn a_certified_drift_kick_sequence() {
    let text = r#"name = "Strang, b1 certified"
claims = ["order = 2 (certified)"]
certificate = { unknowns = ["b1"], radius = "1e-20" }
let = { b1 = "0.5000000000000000000000001" }
drift = ["b1", "1 - b1"]
kick = ["1"]
"#;
    let v = verdict(text);
    assert!(v.claims[0].verdict.is_ok(), "{:?}", v.claims);
    let moved = text.replace("0.5000000000000000000000001", "0.5000000000000000001");
    let v = verdict(&moved);
    assert!(v.claims[0].verdict.is_err(), "{:?}", v.claims);
}

/// SABA₃ printed to 50 digits (the 3-point Gauss–Legendre nodes and
/// weights): `order = (6, 2) (certified)` is proven, the report says
/// "generalised order (6, 2) within radius …", and a weight moved beyond
/// the radius is refused.
fn saba3(b1: &str) -> String {
    format!(
        r#"name = "SABA3 to 50 digits"
claims = ["symmetric", "order = (6, 2) (certified)"]
certificate = {{ unknowns = ["a1", "b1"], radius = "1e-45" }}
let = {{ a1 = "0.11270166537925831148207346002176003891670782947084", b1 = "{b1}" }}
drift = ["a1", "1/2 - a1", "1/2 - a1", "a1"]
kick = ["b1", "1 - 2*b1", "b1"]
"#
    )
}

#[test]
fn a_certified_generalised_order() {
    let b1 = "0.27777777777777777777777777777777777777777777777777";
    let v = verdict(&saba3(b1));
    assert!(v.claims.iter().all(|c| c.verdict.is_ok()), "{:?}", v.claims);
    let report = v.to_string();
    assert!(
        report.contains("certificate  generalised order (6, 2) within radius 1e-45 of the printed coefficients (a1, b1)"),
        "{report}"
    );
    assert!(report.contains("(AAB, AAAAB)"), "{report}");
    let v = verdict(&saba3(&format!("{b1} + 1e-43")));
    let e = v.claims[1].verdict.as_ref().unwrap_err();
    assert!(
        e.contains("generalised order (6, 2) within radius 1e-45 is not proven"),
        "{e}"
    );
    // (8, 2) has three conditions on two unknowns.
    let v = verdict(&saba3(b1).replace("(6, 2) (certified)", "(8, 2) (certified)"));
    let e = v.claims[1].verdict.as_ref().unwrap_err();
    assert!(e.contains("needs a square system"), "{e}");
}

/// A chain of 60 `let` bindings, each using the one before twice
/// (`x1 = "x0 + x0"`, …), is read in linear time (it once walked 2⁶⁰
/// paths), and the certificate holds through it.
#[test]
fn a_long_chain_of_bindings_is_read_quickly() {
    let t0 = std::time::Instant::now();
    let mut lets = format!("g1 = \"{G1}\", x0 = \"g1\"");
    for i in 1..=60 {
        lets.push_str(&format!(", x{i} = \"x{} + x{}\"", i - 1, i - 1));
    }
    let text = format!(
        r#"name = "Yoshida through a chain"
claims = ["order = 4 (certified)"]
certificate = {{ unknowns = ["g1"], radius = "1e-45" }}
let = {{ {lets} }}
compose = ["x60/2^60", "1 - 2*g1", "g1"]
"#
    );
    let v = verdict(&text);
    assert!(v.claims[0].verdict.is_ok(), "{:?}", v.claims);
    assert!(t0.elapsed() < std::time::Duration::from_secs(20));
    // Printed values beyond the bit budget are refused, naming it.
    let long = format!("{G1}{}", "1".repeat(650));
    let e = parse(
        "t.toml",
        &yoshida(&long, "1e-45", r#""order = 4 (certified)""#),
    )
    .unwrap_err();
    assert!(e.message.contains("MAX_CERTIFICATE_BITS"), "{e}");
}
