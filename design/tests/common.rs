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
