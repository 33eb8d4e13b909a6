//! Helpers shared by the test modules.

use design::poly::Poly;
use num_rational::BigRational;
use tableau::Number;

/// A family file of the repository's `designs/` folder.
pub fn family_path(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("designs")
        .join(name)
}

pub fn load(name: &str) -> design::Family {
    design::load_family(&family_path(name)).unwrap()
}

/// A polynomial evaluated in tableau's exact number field.
pub fn eval_number(p: &Poly, x: &[Number]) -> Number {
    let mut out = Number::zero();
    for (e, c) in p.terms() {
        let mut t = Number::from_rational(c.clone());
        for (xi, &k) in x.iter().zip(e) {
            for _ in 0..k {
                t = &t * xi;
            }
        }
        out = &out + &t;
    }
    out
}

pub fn q(n: i64, d: i64) -> BigRational {
    BigRational::new(n.into(), d.into())
}

/// Every claim of a table text holds in `symlab check`'s verifier.
pub fn claims_hold(origin: &str, text: &str) -> Vec<(String, Result<(), String>)> {
    let v = tableau::verdict::check(
        &tableau::verdict::Source::Text { origin, text },
        &tableau::verdict::Options::default(),
    )
    .unwrap();
    v.claims.into_iter().map(|c| (c.claim, c.verdict)).collect()
}

/// A table's text with `let.NAME`'s value replaced by itself plus `delta`
/// (to move a certified coefficient beyond its radius).
pub fn shifted(text: &str, name: &str, delta: &str) -> String {
    let prefix = format!("let.{name} = \"");
    text.lines()
        .map(|l| match l.strip_prefix(&prefix) {
            Some(v) => format!("{prefix}{} + {delta}\"", v.trim_end_matches('"')),
            None => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The claim containing `claim` is refused once `let.NAME` moves by
/// `delta` (beyond the certificate's radius).
pub fn refused_when_moved(origin: &str, text: &str, name: &str, delta: &str, claim: &str) {
    let moved = shifted(text, name, delta);
    assert_ne!(moved, text, "no let.{name} in the table");
    let refused = claims_hold(origin, &moved);
    let (c, verdict) = refused
        .iter()
        .find(|(c, _)| c.contains(claim))
        .unwrap_or_else(|| panic!("no claim {claim}"));
    assert!(verdict.is_err(), "{c} holds with {name} moved by {delta}");
}

/// The number of decimal digits after the point in which `a` and `b`
/// agree: `⌊−log₁₀|a − b|⌋`.
pub fn agreement(a: &BigRational, b: &BigRational) -> i64 {
    let d = num_traits::Signed::abs(&(a - b));
    let mut k = 0;
    let ten = BigRational::from_integer(10.into());
    let mut bound = BigRational::from_integer(1.into());
    while d < bound && k < 200 {
        bound /= &ten;
        k += 1;
    }
    k - 1
}
