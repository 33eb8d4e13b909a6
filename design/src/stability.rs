//! The linear stability threshold of a drift–kick sequence: the largest
//! `x* = hω` such that the method is stable on the harmonic oscillator
//! `q' = p, p' = −ω²q` for every `0 < hω < x*`, and `x*/s` per force
//! evaluation, the figure by which the literature compares splitting
//! methods of different lengths (McLachlan & Gray 1997; Blanes, Casas &
//! Murua 2008, *On the linear stability of splitting methods*).
//!
//! **How.** A drift `D(a)` and a kick `K(b)` act on `(q, p)` as
//! `[[1, a·x], [0, 1]]` and `[[1, 0], [−b·x, 1]]` (`x = hω`); the step's
//! matrix `M(x)` is their product in the order applied, of determinant 1,
//! so the method is stable where `|tr M(x)/2| < 1` and unstable where it
//! exceeds 1. `p(y) = tr M/2` is a polynomial in `y = x²` with `p(0) = 1`
//! and, for a consistent method, `p(y) = 1 − y/2 + O(y²)` (a table whose
//! printed decimals make it consistent only nearly is taken as it is, as
//! long as `p` falls from 1); the threshold is
//! the first `y > 0` where `p(y)² = 1`, the first positive root of
//! `k(y) = (p(y)² − 1)/y`. It is found exactly: `k` has rational
//! coefficients (those of the table, as the designer's polished
//! coefficients or their rational enclosure), a Sturm sequence counts its
//! distinct roots in `(0, t]` at rational `t`, and bisection on rational
//! points encloses the first root in an interval as narrow as asked. A
//! point where `|p|` touches 1 without passing it (`M = ±I` there, which is
//! harmless) counts as the threshold too, so the figure is on the safe
//! side where a method has such points.
//!
//! The work is bounded: sequences of at most [`MAX_FLOWS`] flows, whose
//! polynomial has degree at most [`MAX_FLOWS`]/2 in `y`, and coefficients
//! of at most [`MAX_BITS`] bits in the Sturm sequence.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

use crate::poly::to_f64;

/// The most drifts and kicks a sequence may have.
pub const MAX_FLOWS: usize = 128;

/// The most bits a coefficient of the Sturm sequence may reach
/// (numerator and denominator together).
pub const MAX_BITS: u64 = 1 << 20;

/// One flow of a drift–kick sequence, its coefficient in units of `h`.
#[derive(Clone, Debug, PartialEq)]
pub enum Flow {
    Drift(BigRational),
    Kick(BigRational),
}

/// The threshold `x*`, enclosed: `lo ≤ x*² ≤ hi` (rationals).
#[derive(Clone, Debug, PartialEq)]
pub struct Threshold {
    pub lo: BigRational,
    pub hi: BigRational,
}

impl Threshold {
    /// `x*`, the middle of its enclosure in `f64` (the enclosure is far
    /// narrower than an `f64`'s last digit when asked at 60 bits or more).
    pub fn x(&self) -> f64 {
        let mid = (&self.lo + &self.hi) / BigRational::from_integer(2.into());
        to_f64(&mid).sqrt()
    }
}

/// Why no threshold was computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ThresholdError {
    #[error("{0} drifts and kicks; at most {MAX_FLOWS} are analysed")]
    TooLong(usize),
    #[error("the Sturm sequence's coefficients pass {MAX_BITS} bits")]
    TooLarge,
    #[error("not stable for small steps on the harmonic oscillator (tr M/2 = 1 + {0}·(hω)² + …)")]
    Inconsistent(String),
}

/// Polynomials with rational coefficients, constant first, no trailing
/// zeros.
type Poly = Vec<BigRational>;

fn trim(mut p: Poly) -> Poly {
    while p.last().is_some_and(Zero::is_zero) {
        p.pop();
    }
    p
}

fn add(a: &Poly, b: &Poly) -> Poly {
    let mut out = vec![BigRational::zero(); a.len().max(b.len())];
    for (i, c) in a.iter().enumerate() {
        out[i] += c;
    }
    for (i, c) in b.iter().enumerate() {
        out[i] += c;
    }
    trim(out)
}

/// `a + c·x·b`.
fn add_shifted(a: &Poly, c: &BigRational, b: &Poly) -> Poly {
    let mut out = vec![BigRational::zero(); a.len().max(b.len() + 1)];
    for (i, v) in a.iter().enumerate() {
        out[i] += v;
    }
    for (i, v) in b.iter().enumerate() {
        out[i + 1] += c * v;
    }
    trim(out)
}

fn mul(a: &Poly, b: &Poly) -> Poly {
    if a.is_empty() || b.is_empty() {
        return Vec::new();
    }
    let mut out = vec![BigRational::zero(); a.len() + b.len() - 1];
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            out[i + j] += x * y;
        }
    }
    trim(out)
}

/// `tr M(x)/2` as a polynomial in `y = x²`.
pub fn half_trace(flows: &[Flow]) -> Result<Poly, ThresholdError> {
    if flows.len() > MAX_FLOWS {
        return Err(ThresholdError::TooLong(flows.len()));
    }
    // M = [[m00, m01], [m10, m11]], entries polynomials in x; start at I.
    let one = vec![BigRational::one()];
    let (mut m00, mut m01, mut m10, mut m11) = (one.clone(), Vec::new(), Vec::new(), one);
    for f in flows {
        match f {
            // [[1, a x], [0, 1]] · M: the first row gains a·x times the second.
            Flow::Drift(a) => {
                m00 = add_shifted(&m00, a, &m10);
                m01 = add_shifted(&m01, a, &m11);
            }
            // [[1, 0], [−b x, 1]] · M: the second row gains −b·x times the first.
            Flow::Kick(b) => {
                let nb = -b;
                m10 = add_shifted(&m10, &nb, &m00);
                m11 = add_shifted(&m11, &nb, &m01);
            }
        }
    }
    let trace = add(&m00, &m11);
    let half = BigRational::new(1.into(), 2.into());
    // Odd powers of x cancel in the trace (M(−x) is M(x) with q or p
    // reversed); keep the even ones as powers of y.
    Ok(trim(
        trace
            .iter()
            .step_by(2)
            .map(|c| c * &half)
            .collect::<Vec<_>>(),
    ))
}

/// Polynomials with integer coefficients, constant first, no trailing
/// zeros: the Sturm sequence is kept in integers (a primitive
/// pseudo-remainder sequence, each member divided by the positive gcd of
/// its coefficients), and evaluated at dyadic points `n/2^e` by Horner's
/// rule scaled by `2^(e·degree)`, so no gcd is taken while evaluating.
type IntPoly = Vec<BigInt>;

fn trim_int(mut p: IntPoly) -> IntPoly {
    while p.last().is_some_and(Zero::is_zero) {
        p.pop();
    }
    p
}

/// `p` divided by the positive gcd of its coefficients.
fn primitive(p: IntPoly) -> IntPoly {
    use num_integer::Integer;
    let g = p.iter().fold(BigInt::zero(), |g, c| g.gcd(c));
    if g.is_zero() || g.is_one() {
        p
    } else {
        p.into_iter().map(|c| c / &g).collect()
    }
}

/// A rational polynomial as a primitive integer one of the same signs.
fn integral(p: &Poly) -> IntPoly {
    use num_integer::Integer;
    let l = p.iter().fold(BigInt::one(), |l, c| l.lcm(c.denom()));
    primitive(p.iter().map(|c| c.numer() * (&l / c.denom())).collect())
}

fn derivative_int(p: &IntPoly) -> IntPoly {
    trim_int(
        p.iter()
            .enumerate()
            .skip(1)
            .map(|(i, c)| c * BigInt::from(i))
            .collect(),
    )
}

/// `−prem(a, b)` up to a positive factor: `lc(b)^(δ+1)·a` reduced by `b`
/// (`δ = deg a − deg b`), its sign set so that it is a positive multiple of
/// `−(a mod b)`, as a Sturm sequence needs.
fn neg_prem(a: &IntPoly, b: &IntPoly) -> IntPoly {
    let lead = b.last().expect("a nonzero divisor").clone();
    let delta = a.len() - b.len();
    let mut r = a.clone();
    for _ in 0..=delta {
        if r.len() < b.len() {
            r = r.into_iter().map(|c| c * &lead).collect();
            continue;
        }
        let top = r.last().unwrap().clone();
        let shift = r.len() - b.len();
        r = r.into_iter().map(|c| c * &lead).collect();
        for (i, c) in b.iter().enumerate() {
            r[shift + i] -= &top * c;
        }
        r = trim_int(r);
    }
    // r = lc(b)^(δ+1)·(a mod b): negate when that factor is positive.
    let factor_negative = lead.is_negative() && delta.is_multiple_of(2);
    let r = if factor_negative {
        r
    } else {
        r.into_iter().map(|c| -c).collect()
    };
    primitive(r)
}

/// The sign of `p(n/2^e)`.
fn sign_at(p: &IntPoly, n: &BigInt, e: u64) -> i8 {
    // Σ cᵢ nⁱ 2^(e(d−i)) by Horner: acc ← acc·n + cᵢ·2^(e(d−i)).
    let d = p.len().saturating_sub(1);
    let mut acc = BigInt::zero();
    for (i, c) in p.iter().enumerate().rev() {
        acc = acc * n + (c << (e as usize * (d - i)));
    }
    if acc.is_positive() {
        1
    } else if acc.is_negative() {
        -1
    } else {
        0
    }
}

/// The number of sign changes of the sequence at `n/2^e` (zeros skipped).
fn changes(seq: &[IntPoly], n: &BigInt, e: u64) -> usize {
    let mut last = 0i8;
    let mut count = 0;
    for p in seq {
        let s = sign_at(p, n, e);
        if s != 0 {
            if last != 0 && s != last {
                count += 1;
            }
            last = s;
        }
    }
    count
}

/// The stability threshold of `flows` on the harmonic oscillator,
/// `x*²` enclosed to a relative width of `2^-precision`.
pub fn threshold(flows: &[Flow], precision: u32) -> Result<Threshold, ThresholdError> {
    let p = half_trace(flows)?;
    // p² − 1 = y·k(y): p(0) = 1 for any product of shears.
    let p2 = add(&mul(&p, &p), &vec![-BigRational::one()]);
    let k: Poly = p2.iter().skip(1).cloned().collect();
    let k0 = k.first().cloned().unwrap_or_else(BigRational::zero);
    // k(0) = 2·p'(0) = −(Σa)(Σb): −1 for a consistent method
    // (p = 1 − y/2 + …), near it for printed decimals. Not negative: not
    // stable for small steps, no threshold.
    if !k0.is_negative() {
        let p1 = p.get(1).cloned().unwrap_or_else(BigRational::zero);
        return Err(ThresholdError::Inconsistent(p1.to_string()));
    }
    let k = integral(&k);
    // The Sturm sequence of k, in integers.
    let mut seq = vec![k.clone(), primitive(derivative_int(&k))];
    loop {
        let [.., a, b] = seq.as_slice() else {
            unreachable!("two members at least")
        };
        if b.len() <= 1 {
            break;
        }
        let r = neg_prem(a, b);
        if r.iter().map(|c| c.bits()).sum::<u64>() > MAX_BITS {
            return Err(ThresholdError::TooLarge);
        }
        if r.is_empty() {
            break;
        }
        seq.push(r);
    }
    let zero = BigInt::zero();
    let at_zero = changes(&seq, &zero, 0);
    let count = |n: &BigInt, e: u64| at_zero - changes(&seq, n, e);
    // Cauchy's bound on the roots of k, rounded up to an integer.
    let lead = k.last().expect("k is not zero").magnitude().clone();
    let bound = BigInt::from(
        k.iter()
            .map(|c| (c.magnitude() + &lead - 1u32) / &lead)
            .max()
            .unwrap_or_default(),
    ) + 1;
    if count(&bound, 0) == 0 {
        // A nonconstant p reaches |p| = 1 again; with p = 1 − y/2 + … it
        // does so at a positive y. Not reached for a consistent method.
        return Err(ThresholdError::Inconsistent(
            "0 (p² − 1 has no positive root)".to_string(),
        ));
    }
    // lo = ln/2^e, hi = hn/2^e.
    let (mut ln, mut hn, mut e) = (BigInt::zero(), bound, 0u64);
    while (&hn - &ln) << precision as usize > hn {
        ln <<= 1;
        hn <<= 1;
        e += 1;
        let mid = (&ln + &hn) >> 1;
        if count(&mid, e) >= 1 {
            hn = mid;
        } else {
            ln = mid;
        }
    }
    let den = BigInt::one() << e as usize;
    Ok(Threshold {
        lo: BigRational::new(ln, den.clone()),
        hi: BigRational::new(hn, den),
    })
}

/// The flows of a table of tableau's splitting or composition form, with
/// their coefficients as rationals (an irrational one by the middle of a
/// 128-bit enclosure); `None` for other forms and for kicks with a
/// force-gradient term.
pub fn flows_of(table: &tableau::Table) -> Option<Vec<Flow>> {
    let rat = |n: &tableau::Number| {
        n.as_rational().unwrap_or_else(|| {
            let (lo, hi) = n.enclosure(128);
            (lo + hi) / BigRational::from_integer(2.into())
        })
    };
    match table {
        tableau::Table::Splitting(s) => {
            if s.gradient.iter().any(|g| !g.is_zero()) {
                return None;
            }
            let mut out = Vec::new();
            for i in 0..s.drift.len().max(s.kick.len()) {
                if let Some(a) = s.drift.get(i) {
                    out.push(Flow::Drift(rat(a)));
                }
                if let Some(b) = s.kick.get(i) {
                    out.push(Flow::Kick(rat(b)));
                }
            }
            Some(out)
        }
        tableau::Table::Composition(c) => {
            let half = BigRational::new(1.into(), 2.into());
            let mut out = Vec::new();
            for g in &c.gamma {
                let g = rat(g);
                out.push(Flow::Drift(&g * &half));
                out.push(Flow::Kick(g.clone()));
                out.push(Flow::Drift(&g * &half));
            }
            Some(out)
        }
        _ => None,
    }
}

/// A design's drift–kick sequence compiled for `f64` at its unknowns (the
/// layout its table is emitted in), for the search of
/// `objective = "stability"`: the threshold at `f64` coefficients, which
/// steers the search; the emitted table's threshold is computed again
/// from its printed coefficients.
pub struct CompiledFlows {
    /// `(drift, factor, coefficient)`: a drift (else a kick) of
    /// `factor · coefficient(x)`.
    items: Vec<(bool, f64, crate::poly::FPoly)>,
}

impl CompiledFlows {
    pub fn new(system: &crate::conditions::System) -> CompiledFlows {
        use crate::family::Form;
        let mut items = Vec::new();
        match system.form {
            Form::Composition => {
                for g in &system.gamma {
                    let g = g.compile();
                    items.push((true, 0.5, g.clone()));
                    items.push((false, 1.0, g.clone()));
                    items.push((true, 0.5, g));
                }
            }
            Form::Aba | Form::Bab => {
                let (first, second, first_is_drift) = match system.form {
                    Form::Aba => (&system.drift, &system.kick, true),
                    _ => (&system.kick, &system.drift, false),
                };
                for (i, f) in first.iter().enumerate() {
                    items.push((first_is_drift, 1.0, f.compile()));
                    if let Some(c) = second.get(i) {
                        items.push((!first_is_drift, 1.0, c.compile()));
                    }
                }
            }
        }
        CompiledFlows { items }
    }

    /// The threshold `x*` at the unknowns `u`: [`threshold`] on the flows'
    /// `f64` values (exact binary fractions) to 30 bits, so that a thin
    /// interval of instability, which a scan on a grid would step over, is
    /// seen; `None` where there is none (`tr M/2` does not fall from 1, or
    /// beyond the budget).
    pub fn threshold(&self, u: &[f64]) -> Option<f64> {
        let flows: Option<Vec<Flow>> = self
            .items
            .iter()
            .map(|(drift, f, p)| {
                let v = f * p.eval(u);
                // A finite double is a binary fraction: exactly a rational.
                BigRational::from_float(v).map(|r| {
                    if *drift {
                        Flow::Drift(r)
                    } else {
                        Flow::Kick(r)
                    }
                })
            })
            .collect();
        threshold(&flows?, 30).ok().map(|t| t.x())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn r(n: i64, d: i64) -> BigRational {
        BigRational::new(n.into(), d.into())
    }

    #[test]
    fn leapfrog_is_stable_up_to_two_exactly() {
        let flows = [
            Flow::Drift(r(1, 2)),
            Flow::Kick(r(1, 1)),
            Flow::Drift(r(1, 2)),
        ];
        assert_eq!(half_trace(&flows).unwrap(), vec![r(1, 1), r(-1, 2)]);
        let t = threshold(&flows, 80).unwrap();
        assert!(t.lo <= r(4, 1) && r(4, 1) <= t.hi, "{t:?}");
        assert_eq!(t.x(), 2.0);
    }

    #[test]
    fn a_sequence_unstable_for_small_steps_is_refused_and_an_inconsistent_one_measured() {
        // A negative kick: tr M/2 = 1 + y/2 > 1 at once.
        let flows = [Flow::Drift(r(1, 1)), Flow::Kick(r(-1, 1))];
        assert!(matches!(
            threshold(&flows, 40),
            Err(ThresholdError::Inconsistent(_))
        ));
        // Kicks summing to ½: tr M/2 = 1 − y/4, |tr M/2| = 1 again at y = 8.
        let flows = [
            Flow::Drift(r(1, 2)),
            Flow::Kick(r(1, 2)),
            Flow::Drift(r(1, 2)),
        ];
        let t = threshold(&flows, 80).unwrap();
        assert!(t.lo <= r(8, 1) && r(8, 1) <= t.hi, "{t:?}");
        let long = vec![Flow::Kick(r(1, 1)); MAX_FLOWS + 1];
        assert!(matches!(
            threshold(&long, 40),
            Err(ThresholdError::TooLong(_))
        ));
    }
}
