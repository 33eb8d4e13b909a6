//! Certificates: re-checked from the emitted text, refused once a
//! coefficient moves beyond the radius, and `symlab check`'s bound claim
//! refused once the residual exceeds it.

use design::certify::Refusal;
use design::design;
use design::verify::{VerifyError, verify_table};

use crate::common::{claims_hold, load, shifted};

fn mclachlan_table() -> (design::Family, String) {
    let mut family = load("mclachlan-sb3a.toml");
    family.starts = 60;
    let out = design(&family, "designs/mclachlan-sb3a.toml", &mut |_| {}).unwrap();
    let text = out.designs[0].table.as_ref().unwrap().1.clone();
    (family, text)
}

/// The text with `let.a1`'s value replaced by itself plus `delta`.
fn shift_a1(text: &str, delta: &str) -> String {
    shifted(text, "a1", delta)
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

/// `symlab check` proves the certified claim itself (tableau's Krawczyk
/// test on the file's own coefficients); moved by 1e-30, far beyond the
/// radius 1e-46, the claim is refused.
#[test]
fn check_proves_the_certified_claim_from_the_file() {
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

/// The certificate line's unknowns and radius, as emitted.
fn certificate_of(text: &str) -> (Vec<String>, String) {
    let line = text
        .lines()
        .find(|l| l.starts_with("certificate = "))
        .expect("a certificate");
    let doc: toml::Table = line.parse().unwrap();
    let c = doc["certificate"].as_table().unwrap();
    let unknowns = c["unknowns"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect();
    (unknowns, c["radius"].as_str().unwrap().to_string())
}

/// Every certificate the shipped certified families emit is proven by
/// `symlab check` (the report states the radius), and refused once any one
/// certified coefficient moves by ten times the radius, either way. (The
/// (10, 4) family's certificate is perturbed in its own test,
/// `aba_10_4_certified`, where one check takes seconds.)
#[test]
fn every_emitted_certificate_checks_and_is_refused_beyond_its_radius() {
    let mut checked = 0;
    for (file, starts) in [
        ("mclachlan-sb3a.toml", 60),
        ("bab6-order4.toml", 100),
        ("composition5-order4.toml", 60),
        ("srkn6-order4.toml", 100),
        ("saba3.toml", 60),
    ] {
        let mut family = load(file);
        family.starts = starts;
        let out = design(&family, file, &mut |_| {}).unwrap();
        for d in &out.designs {
            let Some((name, text)) = &d.table else {
                continue;
            };
            if !text.contains("(certified)") {
                continue;
            }
            let v = tableau::verdict::check(
                &tableau::verdict::Source::Text { origin: name, text },
                &tableau::verdict::Options::default(),
            )
            .unwrap();
            assert!(
                v.claims.iter().all(|c| c.verdict.is_ok()),
                "{name}: {:?}",
                v.claims
            );
            let (unknowns, radius) = certificate_of(text);
            let report = v.to_string();
            assert!(
                report.contains(&format!(
                    "within radius {radius} of the printed coefficients"
                )),
                "{name}: {report}"
            );
            let r: f64 = radius.parse().unwrap();
            let delta = format!("{:e}", 10.0 * r);
            for u in &unknowns {
                for sign in ["+", "-"] {
                    let key = format!("let.{u} = \"");
                    let moved: String = text
                        .lines()
                        .map(|l| match l.strip_prefix(&key) {
                            Some(v) => format!("{key}{} {sign} {delta}\"", v.trim_end_matches('"')),
                            None => l.to_string(),
                        })
                        .collect::<Vec<_>>()
                        .join("\n");
                    assert_ne!(&moved, text);
                    let verdicts = claims_hold(name, &moved);
                    let order = verdicts
                        .iter()
                        .find(|(c, _)| c.ends_with("(certified)"))
                        .unwrap();
                    let e = order.1.as_ref().unwrap_err();
                    assert!(
                        e.contains("is not proven: Krawczyk's test fails"),
                        "{name} {u} {sign}: {e}"
                    );
                }
            }
            checked += 1;
        }
    }
    assert!(checked >= 3, "{checked} certified tables");
}

/// The design committed for the pendulum comparison
/// (`designs/found/rkn-aba-8-stages-order-6-3.toml`, compiled by the
/// `designed_method` example with `butcher! { file: … }`) is what the
/// designer wrote: a certified member of `designs/rkn6-aba8.toml`, its
/// certificate re-checked from the committed text, and refused once a
/// coefficient moves beyond the radius.
#[test]
fn the_committed_pendulum_design_is_certified_in_its_family() {
    let family = load("rkn6-aba8.toml");
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../designs/found/rkn-aba-8-stages-order-6-3.toml"
    );
    let text = std::fs::read_to_string(path).unwrap();
    assert!(
        text.contains("Designed by `symlab design designs/rkn6-aba8.toml`"),
        "{text}"
    );
    verify_table(&family, path, &text).unwrap();
    match verify_table(&family, path, &shift_a1(&text, "1e-44")) {
        Err(VerifyError::Refused(_)) => {}
        other => panic!("{other:?}"),
    }
}
