//! Certified orders: a table file whose coefficients are decimals near an
//! exact solution of its order conditions (as `symlab design` prints them)
//! claims `order = p (certified)` and gives a `certificate`:
//!
//! ```toml
//! claims = ["symplectic", "symmetric", "order = 4 (certified)"]
//! certificate = { unknowns = ["a1", "a2"], radius = "1e-46" }
//! let = { a1 = "0.0792036964311954…", a2 = "0.3531729221793324…", b1 = "0.2095151066133620…" }
//! drift = ["a1", "a2", "1 - 2*(a1 + a2)", "a2", "a1"]
//! kick = ["b1", "1/2 - b1", "1/2 - b1", "b1"]
//! ```
//!
//! **What is proven.** The certified unknowns `x` (names bound in `let` to
//! rational constants) are the only variables; every other name is the
//! exact number it is bound to. The method's coefficients are then
//! polynomials in `x` (read from the file's own expressions, never from a
//! claim), and so is every Lie term of `log Φ` (the Lyndon coefficients of
//! the product of the flows' exponentials in the free algebra: on `{A, B}`
//! for a drift–kick sequence, on `{Y₁, Y₃, …}` for a composition of
//! Störmer–Verlet, as [`crate::order::composition_order`] and
//! [`crate::near_integrable`] define them). The conditions of degree
//! `1..=p` that do not vanish identically (checked as polynomials, not
//! assumed) must be exactly as many as the unknowns: the square system
//! `F(x) = 0`. Krawczyk's test ([`krawczyk`]) on the box `x̃ ± r` around
//! the printed values, in exact rational interval arithmetic, proves that
//! the box holds exactly one solution `x*` of `F = 0`: the method with the
//! coefficients at `x*` has order at least `p` (every Lie term of degree
//! `≤ p` vanishes), and it differs from the printed method by at most `r`
//! in each certified unknown. When a Lie term of degree `p + 1` is bounded
//! away from zero on the box, its order is exactly `p`. The claim is
//! accepted only on this basis, and the verdict says "order p within radius
//! r of the printed coefficients", never that the printed decimals have
//! order `p` (they satisfy the conditions only to about `10⁻⁵⁰`).
//!
//! Nothing is read from the file's comments, and the test is run anew
//! every time: the file is not trusted.
//!
//! **Budgets.** At most [`MAX_CERTIFIED_UNKNOWNS`] unknowns and order
//! [`MAX_CERTIFIED_ORDER`]; the products of polynomials (term pairs) are
//! counted against [`MAX_CERTIFICATE_WORK`] and no polynomial may have more
//! than [`MAX_CERTIFICATE_TERMS`] terms; beyond them the claim is refused
//! as undecided, saying which limit.

pub mod poly;

use std::collections::{BTreeMap, HashMap};

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};

use crate::Number;
use crate::expr::{self, BinOp, Expr, ExprKind};
use crate::number::order::{qle, qlt};
pub use poly::{Interval, Poly};

/// The most certified unknowns.
pub const MAX_CERTIFIED_UNKNOWNS: usize = 16;
/// The highest certified order (the error terms are of degree one more).
pub const MAX_CERTIFIED_ORDER: usize = 10;
/// The most terms of one polynomial.
pub const MAX_CERTIFICATE_TERMS: usize = 1 << 14;
/// The most products of terms (pairs of terms multiplied) in building the
/// conditions: about a minute at worst on the project's 2-core machine.
pub const MAX_CERTIFICATE_WORK: u64 = 1 << 27;
/// The most terms held at once by the product of the flows' exponentials
/// (every word's polynomial together): a memory bound, a few hundred MB at
/// most.
pub const MAX_CERTIFICATE_HELD_TERMS: usize = 1 << 21;
/// The most bits (numerator and denominator) of a certified unknown's
/// printed value, of the radius and of any coefficient of the flows'
/// polynomials: 50 printed digits are about 340 bits.
pub const MAX_CERTIFICATE_BITS: u64 = 4096;
/// The deepest nesting of `let` bindings followed (as the file reader's).
const MAX_DEPTH: usize = 64;

/// The flows of a certified table as polynomials in its unknowns.
#[derive(Clone, Debug, PartialEq)]
pub enum Flows {
    /// A drift–kick sequence in the order applied: `0` a drift (`A`), `1` a
    /// kick (`B`).
    Sequence(Vec<(u8, Poly)>),
    /// A composition of Störmer–Verlet: the step sizes `γ`.
    Composition(Vec<Poly>),
}

/// A table file's `certificate`, read and turned into polynomials.
#[derive(Clone, Debug, PartialEq)]
pub struct CertificateSpec {
    /// The certified unknowns (names bound in `let`).
    pub unknowns: Vec<String>,
    /// The printed values of the unknowns.
    pub x: Vec<BigRational>,
    /// The radius of the box (max norm).
    pub radius: BigRational,
    pub flows: Flows,
}

/// One Lie-term condition: its Lyndon word, degree and polynomial
/// (coefficient minus target).
#[derive(Clone, Debug, PartialEq)]
pub struct LieCondition {
    pub word: String,
    pub degree: usize,
    pub poly: Poly,
}

/// What a certificate proves.
#[derive(Clone, Debug, PartialEq)]
pub struct Proof {
    /// The order `p` of the claim: every Lie term of degree `≤ p` vanishes
    /// at the solution in the box (for a generalised order, its least entry).
    pub order: usize,
    /// A generalised order `(p₁, p₂, …)` of the claim (`order = (6, 2)
    /// (certified)`): a Lie term with `j` letters `B` and degree `≤ p_j`
    /// vanishes there. Empty for a classical order.
    pub generalised: Vec<usize>,
    pub radius: BigRational,
    pub unknowns: Vec<String>,
    /// The conditions solved (as many as the unknowns).
    pub conditions: Vec<String>,
    /// `max_i Σ_j |I − Y·J(X)|_{ij}`.
    pub contraction: f64,
    /// `max_i |(Y·F(x̃))_i| / r`.
    pub offset: f64,
    /// A Lie term of degree `p + 1` bounded away from zero on the box, with
    /// its enclosure: the order is exactly `p`. `None`: at least `p`.
    pub next_order: Option<(String, f64, f64)>,
}

impl Proof {
    /// `order 4` or `generalised order (6, 2)`.
    pub fn what(&self) -> String {
        if self.generalised.is_empty() {
            format!("order {}", self.order)
        } else {
            format!(
                "generalised order {}",
                crate::near_integrable::tuple_text(&self.generalised)
            )
        }
    }

    /// `order 4 within radius 1e-46 of the printed coefficients (a1, a2)`.
    pub fn summary(&self) -> String {
        format!(
            "{} within radius {} of the printed coefficients ({})",
            self.what(),
            radius_text(&self.radius),
            self.unknowns.join(", ")
        )
    }

    /// The summary with the evidence, for the report.
    pub fn evidence(&self) -> String {
        let exact = match &self.next_order {
            Some((w, lo, hi)) if !self.generalised.is_empty() => format!(
                "; the Lie term {w}, one degree beyond the claim in its power of ε, lies in [{lo:.6e}, {hi:.6e}] on the box"
            ),
            None if !self.generalised.is_empty() => String::new(),
            Some((w, lo, hi)) => format!(
                "; the degree-{} Lie term {w} lies in [{lo:.6e}, {hi:.6e}] on the box, so the order there is exactly {}",
                self.order + 1,
                self.order
            ),
            None => format!(
                "; no degree-{} Lie term is bounded away from zero on the box, so the order there is at least {}",
                self.order + 1,
                self.order
            ),
        };
        format!(
            "{}: Krawczyk's test in exact rational interval arithmetic proves exactly one solution of the {} order conditions ({}) in the box (contraction {:.3e}, offset {:.3e}){exact}",
            self.summary(),
            self.conditions.len(),
            self.conditions.join(", "),
            self.contraction,
            self.offset
        )
    }
}

/// A radius as a short decimal where it is a power of ten, else exactly.
pub fn radius_text(r: &BigRational) -> String {
    if r.numer().is_one() {
        let d = r.denom().to_string();
        if d.starts_with('1') && d[1..].bytes().all(|b| b == b'0') {
            return format!("1e-{}", d.len() - 1);
        }
    }
    crate::expr::decimal_text(r).unwrap_or_else(|| r.to_string())
}

/// Why Krawczyk's test did not prove the box.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Refusal {
    #[error("the Jacobian at the printed point is singular in f64")]
    Singular,
    #[error(
        "Krawczyk's test fails for radius {radius:.3e}: |Y·F(x̃)| = {offset:.3e}·r and the contraction is {contraction:.3e} (their sum must be < 1)"
    )]
    NotContained {
        radius: f64,
        offset: f64,
        contraction: f64,
    },
    #[error(
        "no error term of degree {degree} is bounded away from zero on the box, so the order is not proven to be exactly {order}"
    )]
    NextOrder { degree: usize, order: usize },
}

/// Krawczyk's test on the box `x ± radius` in the unknowns `determined`
/// (the others fixed at their values in `x`) for the square system
/// `conditions` (one per determined unknown), and a bound of the
/// `error_terms` on the box.
///
/// For the box `X = x̃ ± r` and any nonsingular `Y`, the Krawczyk operator
/// `K(X) = x̃ − Y·F(x̃) + (I − Y·J(X))·(X − x̃)` contains every zero of `F`
/// in `X`, and `K(X) ⊂ int X` proves that `X` holds exactly one
/// (Krawczyk 1969; Moore 1977; Rump 1983). Here `x̃` and `r` are rationals,
/// `F(x̃)` is exact, `J(X)` is an enclosure of the Jacobian over `X` from
/// exact rational interval arithmetic on the derivative polynomials (no
/// rounding mode is involved anywhere), and `Y` is any rational matrix (an
/// `f64` inverse of `J(x̃)`, converted exactly): the test is a proof for
/// whatever `Y` is, and a poor `Y` only makes it fail. Componentwise,
/// `K(X) ⊂ int X` reads `|(Y·F(x̃))_i| + r·Σ_j |I − Y·J(X)|_{ij} < r`, with
/// `|·|` the magnitude of an interval, decided exactly.
///
/// Returns the contraction, the offset and the first error term whose
/// enclosure excludes zero (`None` if none does).
#[allow(clippy::type_complexity, clippy::needless_range_loop)]
pub fn krawczyk(
    conditions: &[&Poly],
    error_terms: &[(&str, &Poly)],
    x: &[BigRational],
    determined: &[usize],
    radius: &BigRational,
) -> Result<(f64, f64, Option<(String, f64, f64)>), Refusal> {
    let m = determined.len();
    if conditions.len() != m || m == 0 {
        return Err(Refusal::Singular);
    }
    let fx: Vec<BigRational> = conditions.iter().map(|c| c.eval_rational(x)).collect();
    let jac: Vec<Vec<Poly>> = conditions
        .iter()
        .map(|c| determined.iter().map(|&j| c.derivative(j)).collect())
        .collect();
    let j_point: Vec<Vec<f64>> = jac
        .iter()
        .map(|row| row.iter().map(|p| to_f64(&p.eval_rational(x))).collect())
        .collect();
    let y_f = inverse_f64(&j_point).ok_or(Refusal::Singular)?;
    let y: Vec<Vec<BigRational>> = y_f
        .iter()
        .map(|row| {
            row.iter()
                .map(|&v| BigRational::from_float(v).unwrap_or_else(BigRational::zero))
                .collect()
        })
        .collect();
    let boxed: Vec<Interval> = x
        .iter()
        .enumerate()
        .map(|(i, v)| {
            if determined.contains(&i) {
                Interval::around(v, radius)
            } else {
                Interval::point(v.clone())
            }
        })
        .collect();
    let j_box: Vec<Vec<Interval>> = jac
        .iter()
        .map(|row| row.iter().map(|p| p.eval_interval(&boxed)).collect())
        .collect();
    let mut worst_offset = BigRational::zero();
    let mut worst_contraction = BigRational::zero();
    let mut contained = true;
    for i in 0..m {
        let mut yf = BigRational::zero();
        for k in 0..m {
            yf += &y[i][k] * &fx[k];
        }
        let mut row_sum = BigRational::zero();
        for j in 0..m {
            let mut mij = Interval::point(if i == j {
                BigRational::one()
            } else {
                BigRational::zero()
            });
            for k in 0..m {
                mij = mij.sub(&j_box[k][j].scale(&y[i][k]));
            }
            row_sum += mij.magnitude();
        }
        // |Y F|_i + r Σ_j |M_ij| < r
        if qle(radius, &(yf.abs() + radius * &row_sum)) {
            contained = false;
        }
        let off = yf.abs() / radius;
        if qlt(&worst_offset, &off) {
            worst_offset = off;
        }
        if qlt(&worst_contraction, &row_sum) {
            worst_contraction = row_sum;
        }
    }
    let offset = to_f64(&worst_offset);
    let contraction = to_f64(&worst_contraction);
    if !contained {
        return Err(Refusal::NotContained {
            radius: to_f64(radius),
            offset,
            contraction,
        });
    }
    let next = error_terms.iter().find_map(|(w, p)| {
        let v = p.eval_interval(&boxed);
        v.excludes_zero()
            .then(|| (w.to_string(), to_f64(&v.lo), to_f64(&v.hi)))
    });
    Ok((contraction, offset, next))
}

fn to_f64(r: &BigRational) -> f64 {
    r.to_f64().unwrap_or(f64::NAN)
}

/// Solve `a·x = b` in `f64` by Gaussian elimination with partial pivoting;
/// `None` if singular. (Only the preconditioner `Y` comes from it: never a
/// decision.)
#[allow(clippy::needless_range_loop)] // elimination indexes as the formula does
fn solve_f64(a: &[Vec<f64>], b: &[f64]) -> Option<Vec<f64>> {
    let n = a.len();
    let mut m: Vec<Vec<f64>> = a.to_vec();
    let mut x = b.to_vec();
    for col in 0..n {
        let piv = (col..n).max_by(|&i, &j| m[i][col].abs().total_cmp(&m[j][col].abs()))?;
        if m[piv][col] == 0.0 || !m[piv][col].is_finite() {
            return None;
        }
        m.swap(col, piv);
        x.swap(col, piv);
        for row in col + 1..n {
            let f = m[row][col] / m[col][col];
            for k in col..n {
                let t = f * m[col][k];
                m[row][k] -= t;
            }
            let t = f * x[col];
            x[row] -= t;
        }
    }
    for row in (0..n).rev() {
        let mut s = x[row];
        for k in row + 1..n {
            s -= m[row][k] * x[k];
        }
        x[row] = s / m[row][row];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The inverse of a square matrix in `f64`, column by column.
fn inverse_f64(a: &[Vec<f64>]) -> Option<Vec<Vec<f64>>> {
    let n = a.len();
    let mut cols = Vec::with_capacity(n);
    for j in 0..n {
        let mut e = vec![0.0; n];
        e[j] = 1.0;
        cols.push(solve_f64(a, &e)?);
    }
    Some(
        (0..n)
            .map(|i| (0..n).map(|j| cols[j][i]).collect())
            .collect(),
    )
}

// ---------------------------------------------------------------------------
// The Lie conditions with polynomial coefficients.

/// A word: letters `0, 1, …` (`A`, `B` for a sequence; `Y₁, Y₃, …` for a
/// composition).
type Word = Vec<u8>;

/// The term products spent, against [`MAX_CERTIFICATE_WORK`].
struct Budget {
    spent: u64,
}

impl Budget {
    fn mul(&mut self, a: &Poly, b: &Poly) -> Result<Poly, String> {
        let pairs = (a.len() as u64).saturating_mul(b.len() as u64);
        self.spent = self.spent.saturating_add(pairs);
        if self.spent > MAX_CERTIFICATE_WORK {
            return Err(format!(
                "building the order conditions needs more than {MAX_CERTIFICATE_WORK} products of terms (tableau::certificate::MAX_CERTIFICATE_WORK)"
            ));
        }
        let r = a.mul(b);
        if r.len() > MAX_CERTIFICATE_TERMS {
            return Err(format!(
                "a polynomial of {} terms, beyond {MAX_CERTIFICATE_TERMS} (tableau::certificate::MAX_CERTIFICATE_TERMS)",
                r.len()
            ));
        }
        Ok(r)
    }
}

fn composition(flows: &Flows) -> bool {
    matches!(flows, Flows::Composition(_))
}

/// A letter's weight: 1 for `A`, `B`; `2l + 1` for `Y_{2l+1}` of a
/// composition.
pub fn letter_weight(comp: bool, l: u8) -> usize {
    if comp { 2 * usize::from(l) + 1 } else { 1 }
}

/// The sum of the letters' weights.
pub fn word_weight(comp: bool, w: &[u8]) -> usize {
    w.iter().map(|&l| letter_weight(comp, l)).sum()
}

/// `AAB`, `Y₁Y₁Y₃`.
pub fn word_label(comp: bool, w: &[u8]) -> String {
    const SUB: [&str; 8] = ["₁", "₃", "₅", "₇", "₉", "₁₁", "₁₃", "₁₅"];
    w.iter()
        .map(|&l| {
            if comp {
                format!("Y{}", SUB[usize::from(l).min(7)])
            } else if l == 0 {
                "A".to_string()
            } else {
                "B".to_string()
            }
        })
        .collect()
}

/// Every word of weight exactly `n`, sorted.
pub fn words_of_weight(comp: bool, n: usize) -> Vec<Word> {
    let letters: Vec<u8> = if comp {
        (0..).take_while(|&l| 2 * l < n).map(|l| l as u8).collect()
    } else {
        vec![0, 1]
    };
    let mut out = Vec::new();
    let mut stack: Vec<(Word, usize)> = vec![(Vec::new(), 0)];
    while let Some((w, wt)) = stack.pop() {
        if wt == n {
            out.push(w);
            continue;
        }
        for &l in &letters {
            let lw = letter_weight(comp, l);
            if wt + lw <= n {
                let mut v = w.clone();
                v.push(l);
                stack.push((v, wt + lw));
            }
        }
    }
    out.sort();
    out
}

/// Lyndon: strictly smaller than each of its proper suffixes.
pub fn is_lyndon(w: &[u8]) -> bool {
    !w.is_empty() && (1..w.len()).all(|i| w < &w[i..])
}

/// `n!`.
pub fn factorial(n: usize) -> BigInt {
    (1..=n).map(BigInt::from).product()
}

/// The coefficients of every word of weight `≤ top` in the product of the
/// flows' exponentials: `exp(x·L)` for a drift or kick, `exp(γY₁ + γ³Y₃ +
/// …)` for a step of Störmer–Verlet.
fn product(
    flows: &Flows,
    top: usize,
    nvars: usize,
    budget: &mut Budget,
    keep: &dyn Fn(&[u8]) -> bool,
) -> Result<HashMap<Word, Poly>, String> {
    let comp = composition(flows);
    let mut words: Vec<Word> = vec![Vec::new()];
    for n in 1..=top {
        words.extend(words_of_weight(comp, n).into_iter().filter(|w| keep(w)));
    }
    let one = Poly::constant(nvars, BigRational::one());
    let mut p: HashMap<Word, Poly> = words
        .iter()
        .map(|w| {
            let v = if w.is_empty() {
                one.clone()
            } else {
                Poly::zero(nvars)
            };
            (w.clone(), v)
        })
        .collect();
    let max_len = words.iter().map(Vec::len).max().unwrap_or(0);
    let inv_fact: Vec<BigRational> = (0..=max_len.max(top))
        .map(|k| BigRational::new(BigInt::one(), factorial(k)))
        .collect();
    let factors: Vec<(Option<u8>, &Poly)> = match flows {
        Flows::Sequence(f) => f.iter().map(|(l, x)| (Some(*l), x)).collect(),
        Flows::Composition(g) => g.iter().map(|x| (None, x)).collect(),
    };
    for (letter, x) in factors {
        let mut powers = vec![one.clone()];
        for k in 1..=top {
            let next = budget.mul(&powers[k - 1], x)?;
            powers.push(next);
        }
        let e = |v: &[u8]| -> Option<Poly> {
            match letter {
                Some(l) => v
                    .iter()
                    .all(|c| *c == l)
                    .then(|| powers[v.len()].scale(&inv_fact[v.len()])),
                None => Some(powers[word_weight(comp, v)].scale(&inv_fact[v.len()])),
            }
        };
        let mut next = HashMap::with_capacity(p.len());
        for w in &words {
            let mut acc = p[w].clone();
            for i in 0..w.len() {
                let u = &p[&w[..i]];
                if u.is_zero() {
                    continue;
                }
                if let Some(ev) = e(&w[i..])
                    && !ev.is_zero()
                {
                    acc = acc.add(&budget.mul(u, &ev)?);
                }
            }
            next.insert(w.clone(), acc);
        }
        let held: usize = next.values().map(Poly::len).sum();
        if held > MAX_CERTIFICATE_HELD_TERMS {
            return Err(format!(
                "the product of the flows' exponentials holds {held} terms, beyond {MAX_CERTIFICATE_HELD_TERMS} (tableau::certificate::MAX_CERTIFICATE_HELD_TERMS)"
            ));
        }
        p = next;
    }
    Ok(p)
}

/// The coefficient of `w` in `log P`.
fn log_coefficient(
    p: &HashMap<Word, Poly>,
    w: &[u8],
    nvars: usize,
    budget: &mut Budget,
) -> Result<Poly, String> {
    let n = w.len();
    let mut s: Vec<Vec<Poly>> = vec![vec![Poly::zero(nvars); n + 1]; n + 1];
    s[0][n] = Poly::constant(nvars, BigRational::one());
    for k in 1..=n {
        for i in (0..n).rev() {
            let mut acc = Poly::zero(nvars);
            for j in i + 1..=n {
                let rest = &s[k - 1][j];
                if rest.is_zero() {
                    continue;
                }
                let piece = &p[&w[i..j]];
                if !piece.is_zero() {
                    acc = acc.add(&budget.mul(piece, rest)?);
                }
            }
            s[k][i] = acc;
        }
    }
    let mut out = Poly::zero(nvars);
    for (k, row) in s.iter().enumerate().skip(1) {
        let sign = if k % 2 == 1 { 1 } else { -1 };
        out = out.add(&row[0].scale(&BigRational::new(sign.into(), (k as i64).into())));
    }
    Ok(out)
}

/// Every Lyndon coefficient of `log Φ` of degree `1..=order + 1`, minus its
/// target (`1` for the letters of weight one), as polynomials in `nvars`
/// unknowns: `(conditions of degree ≤ order, error terms of degree order +
/// 1)`, both without the identically zero ones.
#[allow(clippy::type_complexity)]
pub fn lie_conditions(
    flows: &Flows,
    nvars: usize,
    orders: &[usize],
) -> Result<(Vec<LieCondition>, Vec<LieCondition>), String> {
    let comp = composition(flows);
    if orders.is_empty() || (comp && orders.len() > 1) {
        return Err(
            "a generalised order (p1, p2, …) is for drift–kick sequences; a composition has a classical order".into(),
        );
    }
    // The degree up to which a word with j letters B is imposed.
    let limit = |w: &[u8]| -> usize {
        let j = if comp {
            1
        } else {
            w.iter().filter(|&&l| l == 1).count().max(1)
        };
        orders[(j - 1).min(orders.len() - 1)]
    };
    let top = orders.iter().copied().max().unwrap_or(0) + 1;
    let mut budget = Budget { spent: 0 };
    // The words the product needs: every word for a classical order; for a
    // generalised one, a word with j letters B only up to the length
    // M_j = max over k ≥ j of (p_k + 1), the longest Lie term with at least
    // j letters B that is imposed or bounded away from zero. M_j does not
    // increase with j, so the factors (substrings) of a kept word are kept,
    // as the product and the logarithm need; at (10, 4) this keeps about 50
    // of the 4094 words up to degree 11.
    let reach = |j: usize| -> usize {
        (j.max(1)..=top)
            .map(|k| orders[(k - 1).min(orders.len() - 1)] + 1)
            .max()
            .unwrap_or(top)
            .min(top)
    };
    let keep = |w: &[u8]| -> bool {
        comp || orders.len() == 1 || w.len() <= reach(w.iter().filter(|&&l| l == 1).count())
    };
    let prod = product(flows, top, nvars, &mut budget, &keep)?;
    let mut conditions = Vec::new();
    let mut errors = Vec::new();
    for degree in 1..=top {
        for w in words_of_weight(comp, degree) {
            if !is_lyndon(&w) || !keep(&w) {
                continue;
            }
            let mut poly = log_coefficient(&prod, &w, nvars, &mut budget)?;
            if degree == 1 {
                poly = poly.sub(&Poly::constant(nvars, BigRational::one()));
            }
            if poly.is_zero() {
                continue;
            }
            let c = LieCondition {
                word: word_label(comp, &w),
                degree,
                poly,
            };
            let l = limit(&w);
            if degree <= l {
                conditions.push(c);
            } else if degree == l + 1 {
                errors.push(c);
            }
        }
    }
    Ok((conditions, errors))
}

/// Prove the claim `order = p (certified)` from the certificate: see the
/// [module docs](self). The error says what failed: a condition that is a
/// nonzero constant, a system that is not square, Krawczyk's test, or a
/// budget.
pub fn prove(spec: &CertificateSpec, p: usize) -> Result<Proof, String> {
    prove_orders(spec, &[p], false)
}

/// Prove `order = (p₁, p₂, …) (certified)` (`near`), or with one entry and
/// `near == false` the classical `order = p (certified)`.
pub fn prove_orders(spec: &CertificateSpec, orders: &[usize], near: bool) -> Result<Proof, String> {
    let m = spec.unknowns.len();
    let p = orders.iter().copied().min().unwrap_or(0);
    let what = if near {
        format!(
            "generalised order {}",
            crate::near_integrable::tuple_text(orders)
        )
    } else {
        format!("order {p}")
    };
    if p == 0 || orders.iter().any(|&q| q > MAX_CERTIFIED_ORDER) {
        return Err(format!(
            "{what} cannot be certified: the certificate's conditions are built for orders 1 to {MAX_CERTIFIED_ORDER} (tableau::certificate::MAX_CERTIFIED_ORDER)"
        ));
    }
    let (conditions, errors) = lie_conditions(&spec.flows, m, orders)
        .map_err(|e| format!("{what} cannot be decided from the certificate: {e}"))?;
    if let Some(c) = conditions.iter().find(|c| c.poly.as_constant().is_some()) {
        return Err(format!(
            "{what} claimed but the degree-{} Lie term {} is the constant {} whatever the certified unknowns are (the other coefficients are exact as printed)",
            c.degree,
            c.word,
            c.poly.as_constant().expect("constant")
        ));
    }
    if conditions.len() != m {
        let words: Vec<&str> = conditions.iter().map(|c| c.word.as_str()).collect();
        return Err(format!(
            "the certificate cannot prove {what}: the order conditions that do not vanish identically are {} ({}), and the certified unknowns {} ({}); Krawczyk's test needs a square system (certify as many unknowns as there are conditions; the others are exact as printed)",
            conditions.len(),
            words.join(", "),
            m,
            spec.unknowns.join(", ")
        ));
    }
    let polys: Vec<&Poly> = conditions.iter().map(|c| &c.poly).collect();
    let err_polys: Vec<(&str, &Poly)> = errors.iter().map(|c| (c.word.as_str(), &c.poly)).collect();
    let determined: Vec<usize> = (0..m).collect();
    let (contraction, offset, next_order) =
        krawczyk(&polys, &err_polys, &spec.x, &determined, &spec.radius).map_err(|e| {
            format!(
                "{what} within radius {} is not proven: {e}",
                radius_text(&spec.radius)
            )
        })?;
    Ok(Proof {
        order: p,
        generalised: if near { orders.to_vec() } else { Vec::new() },
        radius: spec.radius.clone(),
        unknowns: spec.unknowns.clone(),
        conditions: conditions.iter().map(|c| c.word.clone()).collect(),
        contraction,
        offset,
        next_order,
    })
}

// ---------------------------------------------------------------------------
// Reading the certificate of a table file.

/// Read the `certificate` of a table file: `doc` is the file's TOML, `lets`
/// the values its reader bound (every binding evaluated, so names and
/// cycles are already checked), `table` the table it read. Errors name the
/// field.
pub fn read_spec(
    doc: &toml::Table,
    values: &BTreeMap<String, Number>,
    table: &crate::Table,
) -> Result<CertificateSpec, (String, String)> {
    let err = |field: &str, m: String| (field.to_string(), m);
    let cert = match doc.get("certificate") {
        Some(toml::Value::Table(t)) => t,
        _ => {
            return Err(err(
                "certificate",
                "expected a table, as in certificate = { unknowns = [\"a1\", \"a2\"], radius = \"1e-46\" }".into(),
            ));
        }
    };
    for key in cert.keys() {
        if !["unknowns", "radius"].contains(&key.as_str()) {
            return Err(err(
                &format!("certificate.{key}"),
                format!("unknown field `{key}` (the fields are unknowns, radius)"),
            ));
        }
    }
    let unknowns: Vec<String> = match cert.get("unknowns") {
        Some(toml::Value::Array(a)) => a
            .iter()
            .enumerate()
            .map(|(i, v)| {
                v.as_str().map(str::to_string).ok_or_else(|| {
                    err(
                        &format!("certificate.unknowns[{i}]"),
                        "expected a name, a string".into(),
                    )
                })
            })
            .collect::<Result<_, _>>()?,
        _ => {
            return Err(err(
                "certificate.unknowns",
                "missing or not an array of the names (bound in `let`) the certificate is about"
                    .into(),
            ));
        }
    };
    if unknowns.is_empty() || unknowns.len() > MAX_CERTIFIED_UNKNOWNS {
        return Err(err(
            "certificate.unknowns",
            format!(
                "{} unknowns; a certificate has 1 to {MAX_CERTIFIED_UNKNOWNS} (tableau::certificate::MAX_CERTIFIED_UNKNOWNS)",
                unknowns.len()
            ),
        ));
    }
    let radius = match cert.get("radius") {
        Some(toml::Value::String(s)) => {
            parse_radius(s).map_err(|m| err("certificate.radius", m))?
        }
        _ => {
            return Err(err(
                "certificate.radius",
                "missing or not a string: the radius of the box, as \"1e-46\"".into(),
            ));
        }
    };
    // The `let` bindings and the method's entries as text.
    let mut lets: Vec<(String, String)> = Vec::new();
    if let Some(toml::Value::Table(t)) = doc.get("let") {
        for (k, v) in t {
            match v {
                toml::Value::String(s) => lets.push((k.clone(), s.clone())),
                toml::Value::Integer(n) => lets.push((k.clone(), n.to_string())),
                _ => {}
            }
        }
    }
    let texts = |key: &str| -> Result<Option<Vec<String>>, (String, String)> {
        let Some(v) = doc.get(key) else {
            return Ok(None);
        };
        let toml::Value::Array(items) = v else {
            return Err(err(key, "expected an array".into()));
        };
        items
            .iter()
            .enumerate()
            .map(|(i, v)| match v {
                toml::Value::String(s) => Ok(s.clone()),
                toml::Value::Integer(n) => Ok(n.to_string()),
                _ => Err(err(
                    &format!("{key}[{i}]"),
                    "expected a string or an integer".into(),
                )),
            })
            .collect::<Result<Vec<_>, _>>()
            .map(Some)
    };
    spec_from_parts(
        &unknowns,
        radius,
        &lets,
        values,
        [texts("drift")?, texts("kick")?, texts("compose")?],
        table,
    )
}

/// A certificate's radius: a positive rational in the grammar (`"1e-46"`).
pub fn parse_radius(text: &str) -> Result<BigRational, String> {
    expr::parse_number(text)
        .map_err(|e| e.to_string())?
        .as_rational()
        .filter(|r| r.is_positive())
        .ok_or_else(|| "the radius must be a positive rational".into())
}

/// The certificate of a table given as text: the certified `unknowns`,
/// the `radius`, the `let` bindings `(name, text)` with their values
/// (`values`, as the table's reader bound them), and the entries of
/// `drift`, `kick` and `compose` as written (`None` where absent); `table`
/// is the table read from them. Errors are `(field, message)`. Both
/// `symlab check` (through [`read_spec`]) and the `butcher!` macro (from its
/// tokens) read certificates here.
pub fn spec_from_parts(
    unknowns: &[String],
    radius: BigRational,
    lets: &[(String, String)],
    values: &BTreeMap<String, Number>,
    entries: [Option<Vec<String>>; 3],
    table: &crate::Table,
) -> Result<CertificateSpec, (String, String)> {
    let err = |field: &str, m: String| (field.to_string(), m);
    let unknowns = unknowns.to_vec();
    let lets_map = values;
    if unknowns.is_empty() || unknowns.len() > MAX_CERTIFIED_UNKNOWNS {
        return Err(err(
            "certificate.unknowns",
            format!(
                "{} unknowns; a certificate has 1 to {MAX_CERTIFIED_UNKNOWNS} (tableau::certificate::MAX_CERTIFIED_UNKNOWNS)",
                unknowns.len()
            ),
        ));
    }
    let mut defs: BTreeMap<String, Expr> = BTreeMap::new();
    for (k, text) in lets {
        if let Ok(e) = expr::parse(text) {
            defs.insert(k.clone(), e);
        }
    }
    let mut x = Vec::with_capacity(unknowns.len());
    for (i, u) in unknowns.iter().enumerate() {
        let field = format!("certificate.unknowns[{i}]");
        if unknowns[..i].contains(u) {
            return Err(err(&field, format!("`{u}` is listed twice")));
        }
        let Some(e) = defs.get(u) else {
            return Err(err(&field, format!("`{u}` is not bound in `let`")));
        };
        if !e.names().is_empty() {
            return Err(err(
                &field,
                format!(
                    "`{u}` must be bound to a constant (its printed value), not an expression in other names"
                ),
            ));
        }
        let v = lets_map
            .get(u)
            .and_then(Number::as_rational)
            .ok_or_else(|| err(&field, format!("`{u}` must be a rational number")))?;
        x.push(v);
    }
    let mut cx = Symbolic {
        unknowns: &unknowns,
        dependent: dependent_names(&unknowns, &defs),
        defs: &defs,
        lets: lets_map,
        memo: BTreeMap::new(),
        budget: Budget { spent: 0 },
    };
    let [drift_text, kick_text, compose_text] = entries;
    let entries = |cx: &mut Symbolic<'_>,
                   key: &str,
                   texts: &Option<Vec<String>>|
     -> Result<Vec<Poly>, (String, String)> {
        let Some(items) = texts else {
            return Err(err(key, "missing".into()));
        };
        items
            .iter()
            .enumerate()
            .map(|(i, text)| {
                let field = format!("{key}[{i}]");
                let e = expr::parse(text).map_err(|e| err(&field, e.to_string()))?;
                cx.poly(&e, 0).map_err(|m| err(&field, m))
            })
            .collect()
    };
    let flows = match table {
        crate::Table::Splitting(s) if !s.has_gradient() => {
            let drift = entries(&mut cx, "drift", &drift_text)?;
            let kick = entries(&mut cx, "kick", &kick_text)?;
            let mut f = Vec::new();
            for i in 0..drift.len().max(kick.len()) {
                if let Some(d) = drift.get(i) {
                    f.push((0u8, d.clone()));
                }
                if let Some(k) = kick.get(i) {
                    f.push((1u8, k.clone()));
                }
            }
            Flows::Sequence(f)
        }
        crate::Table::Composition(_) => {
            Flows::Composition(entries(&mut cx, "compose", &compose_text)?)
        }
        _ => {
            return Err(err(
                "certificate",
                "a certificate is about a drift–kick sequence (plain kicks) or a composition"
                    .into(),
            ));
        }
    };
    let bits = |r: &BigRational| r.numer().bits() + r.denom().bits();
    let widest = x
        .iter()
        .chain(std::iter::once(&radius))
        .map(bits)
        .chain(match &flows {
            Flows::Sequence(f) => f
                .iter()
                .flat_map(|(_, p)| p.terms().map(|(_, c)| bits(c)).collect::<Vec<_>>())
                .collect::<Vec<_>>(),
            Flows::Composition(g) => g
                .iter()
                .flat_map(|p| p.terms().map(|(_, c)| bits(c)).collect::<Vec<_>>())
                .collect(),
        })
        .max()
        .unwrap_or(0);
    if widest > MAX_CERTIFICATE_BITS {
        return Err(err(
            "certificate",
            format!(
                "a printed value, the radius or a coefficient has {widest} bits, beyond {MAX_CERTIFICATE_BITS} (tableau::certificate::MAX_CERTIFICATE_BITS; 50 printed digits are about 340)"
            ),
        ));
    }
    let used = match &flows {
        Flows::Sequence(f) => f
            .iter()
            .flat_map(|(_, p)| p.variables())
            .collect::<Vec<_>>(),
        Flows::Composition(g) => g.iter().flat_map(Poly::variables).collect(),
    };
    for (i, u) in unknowns.iter().enumerate() {
        if !used.contains(&i) {
            return Err(err(
                &format!("certificate.unknowns[{i}]"),
                format!("`{u}` does not occur in the method's coefficients"),
            ));
        }
    }
    Ok(CertificateSpec {
        unknowns,
        x,
        radius,
        flows,
    })
}

/// The unknowns and every binding that uses one, directly or through
/// others: a fixed point, at most one pass per binding, each pass linear in
/// the bindings' names.
fn dependent_names(
    unknowns: &[String],
    defs: &BTreeMap<String, Expr>,
) -> std::collections::BTreeSet<String> {
    let mut dep: std::collections::BTreeSet<String> = unknowns.iter().cloned().collect();
    let names: Vec<(&String, Vec<String>)> = defs
        .iter()
        .map(|(k, e)| {
            let ns = e
                .names()
                .iter()
                .filter_map(|n| match &n.kind {
                    ExprKind::Name(n) => Some(n.clone()),
                    _ => None,
                })
                .collect();
            (k, ns)
        })
        .collect();
    for _ in 0..=names.len() {
        let before = dep.len();
        for (k, ns) in &names {
            if !dep.contains(*k) && ns.iter().any(|n| dep.contains(n)) {
                dep.insert((*k).clone());
            }
        }
        if dep.len() == before {
            break;
        }
    }
    dep
}

/// Evaluates expressions as polynomials in the certified unknowns.
struct Symbolic<'a> {
    unknowns: &'a [String],
    /// The names that depend on an unknown (the unknowns, and the `let`
    /// bindings that use one, directly or through others).
    dependent: std::collections::BTreeSet<String>,
    defs: &'a BTreeMap<String, Expr>,
    lets: &'a BTreeMap<String, Number>,
    memo: BTreeMap<String, Poly>,
    budget: Budget,
}

impl Symbolic<'_> {
    fn nvars(&self) -> usize {
        self.unknowns.len()
    }

    /// Whether the expression depends on an unknown (through `let`): one
    /// look-up per name (the dependent names are found once, in
    /// [`dependent_names`]; a chain of bindings each using the one before
    /// twice is not walked exponentially).
    fn depends(&self, e: &Expr, _depth: usize) -> bool {
        e.names().iter().any(|n| match &n.kind {
            ExprKind::Name(n) => self.dependent.contains(n),
            _ => false,
        })
    }

    fn constant(&self, e: &Expr) -> Result<BigRational, String> {
        let v = expr::eval(e, &|n| self.lets.get(n).cloned()).map_err(|err| format!("{err:?}"))?;
        v.as_rational().ok_or_else(|| {
            format!("{v} is irrational; a certified table's coefficients are polynomials with rational coefficients in its unknowns")
        })
    }

    /// `depth` counts the `let` bindings followed (each expression's own
    /// nesting is bounded by the grammar).
    fn poly(&mut self, e: &Expr, depth: usize) -> Result<Poly, String> {
        if depth > MAX_DEPTH {
            return Err(format!("`let` bindings nested more than {MAX_DEPTH} deep"));
        }
        let m = self.nvars();
        if !self.depends(e, depth) {
            return Ok(Poly::constant(m, self.constant(e)?));
        }
        Ok(match &e.kind {
            ExprKind::Name(n) => {
                if let Some(i) = self.unknowns.iter().position(|u| u == n) {
                    Poly::var(m, i)
                } else if let Some(p) = self.memo.get(n) {
                    p.clone()
                } else {
                    let d = self
                        .defs
                        .get(n)
                        .ok_or_else(|| format!("unknown name `{n}`"))?;
                    let p = self.poly(d, depth + 1)?;
                    self.memo.insert(n.clone(), p.clone());
                    p
                }
            }
            ExprKind::Neg(x) => Poly::zero(m).sub(&self.poly(x, depth)?),
            ExprKind::Binary { op, lhs, rhs } => match op {
                BinOp::Add => self.poly(lhs, depth)?.add(&self.poly(rhs, depth)?),
                BinOp::Sub => self.poly(lhs, depth)?.sub(&self.poly(rhs, depth)?),
                BinOp::Mul => {
                    let (a, b) = (self.poly(lhs, depth)?, self.poly(rhs, depth)?);
                    self.budget.mul(&a, &b)?
                }
                BinOp::Div => {
                    if self.depends(rhs, depth) {
                        return Err("division by an expression in the certified unknowns: the coefficients must be polynomials in them".into());
                    }
                    let d = self.constant(rhs)?;
                    if d.is_zero() {
                        return Err("division by zero".into());
                    }
                    self.poly(lhs, depth)?.scale(&d.recip())
                }
            },
            ExprKind::Pow { base, exp } => {
                if self.depends(exp, depth) {
                    return Err("an exponent in the certified unknowns".into());
                }
                let k = self.constant(exp)?;
                let k = k
                    .is_integer()
                    .then(|| k.to_integer().to_u32())
                    .flatten()
                    .filter(|&k| k <= 32)
                    .ok_or("the exponent of a power of the certified unknowns must be an integer in 0..=32")?;
                let b = self.poly(base, depth)?;
                let mut r = Poly::constant(m, BigRational::one());
                for _ in 0..k {
                    r = self.budget.mul(&r, &b)?;
                }
                r
            }
            ExprKind::Call { .. } => {
                return Err("sqrt/cbrt of an expression in the certified unknowns: the coefficients must be polynomials in them".into());
            }
            ExprKind::Int(_) | ExprKind::Decimal(_) => unreachable!("constants do not depend"),
        })
    }
}
