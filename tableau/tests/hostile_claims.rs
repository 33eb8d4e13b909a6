//! Hostile claims and coefficients on the near-integrable, gradient-kick and
//! processed readers (issue 35): an order too large for any list sized by
//! it, coefficients whose products are long, values far outside `f64`. Each
//! is refused quickly with a message naming the claim or the budget, never
//! an abort or an hour of work.

use std::time::{Duration, Instant};

use tableau::Number;
use tableau::analysis::{Analysis, check_file_claim};
use tableau::file::parse_table_file;

/// A near-integrable file (ABA 8,6,4-like: a plain drift–kick sequence).
fn near(claim: &str, drift: &str) -> String {
    format!(
        "name = \"near\"\nclaims = [\"{claim}\"]\ndrift = [\"{drift}\", \"1 - 2*({drift})\", \"{drift}\"]\nkick = [\"1/2\", \"1/2\"]\n"
    )
}

/// A kernel with gradient kicks (WHCKL's).
fn gradient(claim: &str) -> String {
    format!(
        "name = \"gradient\"\nclaims = [\"{claim}\"]\ndrift = [\"1/2\", \"1/2\"]\nkick = [\"1\"]\nkick_gradient = [\"1/24\"]\n"
    )
}

/// A processed method: leapfrog with the corrector of order 3 (the
/// catalogue's leapfrog-c3, whose true claims are `order = 2` and
/// `order = (4, 2)`).
fn processed(claim: &str) -> String {
    format!(
        "name = \"processed\"\nclaims = [\"{claim}\"]\nkernel = \"leapfrog\"\nlet.a1 = \"sqrt(7/40)\"\nlet.b1 = \"-1/96*sqrt(40/7)\"\ncorrector_drift = [\"a1\", \"-2*a1\", \"a1 - a1\", \"2*a1\", \"-a1\"]\ncorrector_kick = [\"-b1\", \"b1\", \"b1\", \"-b1\"]\n"
    )
}

/// Parse and check every claim within `limit`: the first failure's text.
fn verdict(text: &str, limit: Duration) -> Result<(), String> {
    let start = Instant::now();
    let result = (|| {
        let tf = parse_table_file("t.toml", text).map_err(|e| e.to_string())?;
        let an = Analysis::of(&tf.table).map_err(|e| e.to_string())?;
        for c in &tf.claims {
            check_file_claim(&tf, &an, c).map_err(|e| e.to_string())?;
        }
        Ok(())
    })();
    assert!(
        start.elapsed() < limit,
        "took {:?} (limit {limit:?}) for\n{text}",
        start.elapsed()
    );
    result
}

#[test]
fn huge_orders_are_refused_naming_the_claim_on_every_reader() {
    for claim in [
        "order = (99999999999)",
        "order = 18446744073709551615",
        "order = 18446744073709551616",
        "order = (8, 99999999999)",
        "order = (65)",
        "order_rkn = 99999999999",
    ] {
        for text in [near(claim, "1/4"), gradient(claim), processed(claim)] {
            let e = verdict(&text, Duration::from_secs(5)).unwrap_err();
            assert!(
                e.contains("beyond every budget") && e.contains("MAX_CLAIMED_ORDER"),
                "{claim}: {e}"
            );
        }
    }
    // The largest order a claim may state still reaches the analyses, which
    // refuse it at their own (lower) limits, naming them.
    let e = verdict(&near("order = (64)", "1/4"), Duration::from_secs(5)).unwrap_err();
    assert!(e.contains("MAX_NEAR_DEGREE"), "{e}");
    let e = verdict(&processed("order = (64, 2)"), Duration::from_secs(5)).unwrap_err();
    assert!(e.contains("MAX_NEAR_DEGREE"), "{e}");
}

#[test]
fn long_coefficients_count_against_the_near_integrable_budget() {
    // 1/2 + 1/3^10000: a short entry whose value has 15 850-bit numerator
    // and denominator. The work estimate counted products, not their size,
    // and the claim ran 35 s; now it is refused at once, naming the budget.
    let e = verdict(
        &near("order = (4, 2)", "1/2 + 1/3^10000"),
        Duration::from_secs(5),
    )
    .unwrap_err();
    assert!(e.contains("MAX_NEAR_WORK") && e.contains("bits"), "{e}");
    // The catalogue's 40-digit decimals are not affected: ABA(8,6,4)'s claims
    // are still decided.
    let aba = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("catalogue/aba-8-6-4.toml"),
    )
    .unwrap();
    verdict(&aba, Duration::from_secs(60)).unwrap();
}

#[test]
fn the_processed_claims_are_the_effective_methods() {
    // True of χ K χ⁻¹, false of the kernel (leapfrog is order 2, (2, 2)).
    verdict(&processed("order = (4, 2)"), Duration::from_secs(30)).unwrap();
    let e = verdict(&processed("order = (6, 2)"), Duration::from_secs(30)).unwrap_err();
    assert!(e.contains("effective"), "{e}");
}

#[test]
fn values_far_outside_f64_are_printed_with_their_exponent() {
    let cases = [
        ("10^5000", "1.000e5000"),
        ("-3*10^5000", "-3.000e5000"),
        ("1/10^5000", "1.000e-5000"),
        ("7/2^2000", "6.097e-602"),
        ("1/3", "3.333e-1"),
        ("0", "0"),
        ("sqrt(2)*10^400", "1.414e400"),
    ];
    for (text, want) in cases {
        let x: Number = tableau::expr::parse_number(text).unwrap();
        assert_eq!(x.approx_text(), want, "{text}");
    }
    // In a failing condition's message: never "inf".
    let e = verdict(&near("order = (4, 2)", "10^500"), Duration::from_secs(10)).unwrap_err();
    assert!(!e.contains("inf") && !e.contains("NaN"), "{e}");
}
