//! Exact values where the conditions reduce to one polynomial in one
//! unknown (Yoshida's and Suzuki's triple and quintuple jumps): the real
//! root as `root(P, lo, hi)`, the form tableau's root files accept (one root
//! of `P` in `(lo, hi]`, isolated by Sturm sequences with tableau's own
//! [`RealRoot`]), and, for a quadratic or a cubic with one real root whose
//! Cardano radicands are rational, in radicals of rationals (`sqrt`,
//! `cbrt`), which every table file accepts. The radical form is proven, not
//! trusted: it is parsed with tableau's grammar into its exact number field,
//! `P` evaluated there must be exactly zero, and its enclosure must lie in
//! the isolating interval.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};
use tableau::Number;
use tableau::algebraic::poly::Poly as UPoly;
use tableau::algebraic::root::RealRoot;

use crate::conditions::System;
use crate::poly::Poly;

/// An exact value of the one unknown.
#[derive(Clone, Debug)]
pub struct Exact {
    /// `root(P, lo, hi)`.
    pub root: String,
    /// In radicals of rationals, when found: tableau's grammar.
    pub radicals: Option<String>,
    /// The polynomial, in the unknown's name.
    pub polynomial: String,
}

/// The univariate polynomial of a one-unknown condition.
fn univariate(p: &Poly) -> UPoly {
    let mut c = vec![BigRational::zero(); p.degree() + 1];
    for (e, v) in p.terms() {
        c[usize::from(e[0])] = v.clone();
    }
    UPoly(c).trim()
}

/// `x^(1/3)` text for a rational (`cbrt(a/b)`), or a plain rational when it
/// is a cube.
fn cbrt_text(r: &BigRational) -> String {
    format!("cbrt({})", rational_text(r))
}

fn rational_text(r: &BigRational) -> String {
    if r.is_negative() {
        format!("(-{})", r.abs())
    } else {
        r.to_string()
    }
}

/// Whether a nonnegative rational is a square, and its root.
fn rational_sqrt(r: &BigRational) -> Option<BigRational> {
    if r.is_negative() {
        return None;
    }
    let n = r.numer().sqrt();
    let d = r.denom().sqrt();
    (&n * &n == *r.numer() && &d * &d == *r.denom()).then(|| BigRational::new(n, d))
}

/// Radicals for a quadratic or a cubic with a unique real root near `x`.
fn radicals(p: &UPoly, x: f64) -> Option<String> {
    let deg = p.degree()?;
    let lead = p.lead();
    let c: Vec<BigRational> = (0..=deg).map(|k| p.coeff(k) / &lead).collect();
    let q = |n: i64, d: i64| BigRational::new(BigInt::from(n), BigInt::from(d));
    match deg {
        1 => Some(rational_text(&(-&c[0]))),
        2 => {
            // x² + c₁x + c₀: x = −c₁/2 ± sqrt(c₁²/4 − c₀)
            let disc = &c[1] * &c[1] / q(4, 1) - &c[0];
            if disc.is_negative() {
                return None;
            }
            let mid = -&c[1] / q(2, 1);
            let sign = if x >= tableau_f64(&mid) { "+" } else { "-" };
            Some(format!(
                "{} {sign} sqrt({})",
                rational_text(&mid),
                rational_text(&disc)
            ))
        }
        3 => {
            // x = y − c₂/3: y³ + py + q₀ = 0.
            let shift = &c[2] / q(3, 1);
            let pp = &c[1] - &c[2] * &c[2] / q(3, 1);
            let q0 = q(2, 27) * &c[2] * &c[2] * &c[2] - &c[2] * &c[1] / q(3, 1) + &c[0];
            let d = &q0 * &q0 / q(4, 1) + &pp * &pp * &pp / q(27, 1);
            if !d.is_positive() {
                return None; // three real roots (or a repeated one): casus irreducibilis
            }
            let s = rational_sqrt(&d)?;
            let u = -&q0 / q(2, 1) + &s;
            let v = -&q0 / q(2, 1) - &s;
            Some(format!(
                "{} + {} + {}",
                rational_text(&-shift),
                cbrt_text(&u),
                cbrt_text(&v)
            ))
        }
        _ => None,
    }
}

fn tableau_f64(r: &BigRational) -> f64 {
    crate::poly::to_f64(r)
}

/// The exact value of the single unknown of a one-condition system, near
/// `x`; `None` when the system is not of that shape or no root is isolated
/// near `x`.
pub fn exact_value(system: &System, x: f64) -> Option<Exact> {
    if system.unknowns() != 1 || system.conditions.len() != 1 {
        return None;
    }
    let p = univariate(&system.conditions[0].poly);
    // Cauchy's bound on the roots.
    let lead = p.lead().abs();
    let bound =
        p.0.iter()
            .map(|c| c.abs() / &lead)
            .fold(BigRational::one(), |a, b| if b > a { b } else { a })
            + BigRational::one();
    let mut roots = RealRoot::isolate(&p, &(-&bound), &bound);
    let xr = crate::polish::from_f64(x);
    let root = roots.iter_mut().find_map(|r| {
        r.refine_to(80);
        (r.lo < xr && xr <= r.hi || (tableau_f64(&r.lo) - x).abs() < 1e-9).then(|| r.clone())
    })?;
    let poly_text = root.poly.to_text("x");
    let root_text = format!("root({poly_text}, {}, {})", root.lo, root.hi);
    // Radicals, checked in tableau's number field.
    let radicals = radicals(&root.poly, x).filter(|text| {
        let Ok(n) = tableau::expr::parse_number(text) else {
            return false;
        };
        let mut value = Number::zero();
        let mut power = Number::one();
        for c in &root.poly.0 {
            value = &value + &(&power * &Number::from_rational(c.clone()));
            power = &power * &n;
        }
        let (lo, hi) = n.enclosure(200);
        value.is_zero() && root.lo < lo && hi <= root.hi
    });
    Some(Exact {
        root: root_text,
        radicals,
        polynomial: system.conditions[0].poly.to_text(&system.names),
    })
}
