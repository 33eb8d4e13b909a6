//! Generalised orders of splitting methods for near-integrable systems
//! `H = A + εB`, decided exactly.
//!
//! A drift–kick sequence `exp(a₁hA) exp(b₁hB) ⋯` (drifts are the flow of
//! the integrable part `A`, kicks that of the perturbation `εB`; the `ε` is
//! carried by `B`) has `log Φ = h(A + εB) + Σ` Lie terms, and a term of
//! degree `n` with `j` letters `B` is of size `εʲ hⁿ`. The method has
//! **generalised order `(p₁, p₂, …, p_m)`** when every term with `j` `B`s and
//! degree `2 ≤ n ≤ p_j` vanishes, `p_j` read as `p_m` for `j ≥ m`; its
//! global error is then `O(ε h^{p₁} + ε² h^{p₂} + … + ε^m h^{p_m})`. This is
//! the convention of Laskar & Robutel (2001; SABAₙ and SBABₙ have order
//! `(2n, 2)`: error `O(εh^{2n} + ε²h²)`) and of Blanes, Casas, Farrés,
//! Laskar, Makazaga & Murua (2013; ABA(8,6,4) has `O(εh⁸ + ε²h⁶ + ε³h⁴)`).
//! The orders need not be non-increasing: a corrected method such as
//! SABAC₁ or SABACM₁ has `O(εh² + ε²h⁴)`, generalised order `(2, 4)`
//! (Laskar & Robutel 2001): its `ε²` error is of higher order in `h` than
//! its `ε` error. The classical order is the least of the `p_j`.
//!
//! **Gradient kicks.** A kick may be a gradient kick
//! `exp(k·h·B + g·h³·[B,[A,B]])` ([`crate::Splitting`], `kick_gradient`):
//! the product then multiplies by the truncated exponential of that
//! element of the free algebra (`[B,[A,B]] = 2·BAB − BBA − ABB`, degree 3
//! with two `B`s, so `g` carries `ε²`), and a gradient kick is never merged
//! with a neighbouring kick. Everything below holds unchanged.
//!
//! **How it is decided.** The product of exponentials and its logarithm are
//! computed in the free associative algebra on `{A, B}` truncated by
//! (number of `B`s, degree) (module `algebra`): a non-increasing degree bound
//! makes the dropped words an ideal, so the kept coefficients are exact
//! (degrees asked for that increase somewhere, as `(2, 4)` does, are
//! computed in the truncation by their least non-increasing majorant,
//! `D̃(j) = max_{i ≥ j} D(i)`, and tested only up to `D(j)`),
//! and a part with `j` `B`s costs `C(n, j)` words of degree `n` instead of
//! the full algebra's `2ⁿ`. A Lie term is zero exactly when its
//! coefficients on the Lyndon words are (module `words`), so only those are
//! tested, each one named by its Lyndon word and the bracket it leads
//! (`A²B`, `[A,[A,B]]`). Every coefficient is an exact [`Number`]; a
//! condition holds when the coefficient is exactly its target (`1` for the
//! words `A` and `B`, `0` otherwise) or, for coefficients published as
//! decimals, within a stated `|residual| < bound`, compared exactly. Nothing
//! is decided in floating point.
//!
//! **Budgets.** The degree is at most [`MAX_NEAR_DEGREE`], the words of the
//! truncation at most [`MAX_NEAR_WORDS`], and the products estimated before
//! the work starts at most [`MAX_NEAR_WORK`]; beyond them the verifier
//! refuses with a message saying which limit and by how much.

pub(crate) mod algebra;
pub(crate) mod words;

use std::fmt;

use crate::budget::BeyondBudget;
use crate::order::within;
use crate::table::Op;
use crate::{Number, Splitting, Table};
pub use algebra::Factor;
use algebra::{log_coefficient, log_work, product_of_exponentials, word_count};
use words::{Word, bracket, is_lyndon, words_with};

/// The highest degree (power of `h`) examined.
pub const MAX_NEAR_DEGREE: usize = 24;

/// The most words of the truncated algebra (the words with `j` `B`s and
/// degree at most `D(j)`, summed over `j`).
pub const MAX_NEAR_WORDS: u64 = 1 << 16;

/// The largest degree over Q of the field the coefficients span (the
/// radicals of all of them together): products in a field of degree `d`
/// cost up to `d²` products of rationals, which [`MAX_NEAR_WORK`] does not
/// count. The catalogue's tables span at most degree 8 (the correctors'
/// `sqrt(7/40)`, `sqrt(40/7)`).
pub const MAX_NEAR_FIELD_DEGREE: u64 = 16;

/// The most products of exact numbers, estimated before the work starts:
/// words × flows × the highest degree for the product of exponentials (a
/// gradient kick counting the highest degree + 4: its exponential and the
/// product with it), plus
/// `m³/6` per Lyndon word of `m` letters for the logarithm. Measured on the
/// project's 2-core machine (dev profile, which is optimised): with the
/// catalogue's 40-digit decimals a unit costs up to about 15 µs (ABA(10,6,4)
/// at degrees (16, 12, 10, 8, 8, 8, 8): 262 144 units in 4.5 s), with exact
/// radicals far less (SBAB₄: 50 ms); so the limit is about 15 s at worst.
pub const MAX_NEAR_WORK: u64 = 1 << 20;

/// The coefficient size (bits of numerators, denominators and radicands,
/// [`Number::size_bits`]) that [`MAX_NEAR_WORK`]'s unit was measured with,
/// rounded up: 40-digit decimals have about 270. Coefficients `k` times as
/// long count `k²` units a product.
pub const CALIBRATED_BITS: u64 = 320;

/// The degrees `symlab check` examines: `D(j)` for `j = 1, 2, …`. The last
/// entry, 8, is examined for every `j` from 3 to 7, i.e. every Lie term of
/// degree at most 8, so a classical order below 8 is decided; `p₁` is
/// decided up to 11, `p₂` up to 7.
pub const REPORT_DEGREES: [usize; 7] = [12, 8, 8, 8, 8, 8, 8];

/// One condition: the coefficient of a Lyndon word in `log Φ`.
#[derive(Clone, Debug, PartialEq)]
pub struct NearCondition {
    /// The number of `B`s: the power of `ε`.
    pub bs: usize,
    /// The length of the word: the power of `h`.
    pub degree: usize,
    /// The Lyndon word, runs as powers: `A³B²`.
    pub word: String,
    /// The Lie element whose leading word it is: `[A,[A,[[A,B],B]]]`.
    pub lie: String,
    /// The coefficient of the word in `log Φ` (with `h = 1`).
    pub value: Number,
    /// `1` for the words `A` and `B`, `0` otherwise.
    pub expected: Number,
    /// `value − expected`.
    pub residual: Number,
}

impl fmt::Display for NearCondition {
    /// `the ε²h⁵ condition fails: the coefficient of A³B² in log Φ (the
    /// leading word of [A,[A,[[A,B],B]]]) is 1/720 ≈ 1.389e-3, not 0`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // The canonical text when it is short, else the abbreviated one.
        let full = self.value.to_string();
        let value = if full.len() <= 120 {
            full
        } else {
            self.value.short_text()
        };
        write!(
            f,
            "the {} condition fails: the coefficient of {} in log Φ (the leading word of {}) is {} ≈ {}, not {}",
            power_label(self.bs, self.degree),
            self.word,
            self.lie,
            value,
            self.value.approx_text(),
            self.expected
        )
    }
}

/// `εh`, `ε²h⁵`.
pub fn power_label(bs: usize, degree: usize) -> String {
    let sup = |n: usize| -> String {
        const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
        if n == 1 {
            return String::new();
        }
        n.to_string()
            .bytes()
            .map(|b| SUP[usize::from(b - b'0')])
            .collect()
    };
    let e = if bs == 0 {
        String::new()
    } else {
        format!("ε{}", sup(bs))
    };
    format!("{e}h{}", sup(degree))
}

/// The order of the part with `bs` letters `B`.
#[derive(Clone, Debug, PartialEq)]
pub struct PartOrder {
    pub bs: usize,
    /// Every condition of this part up to this degree holds.
    pub order: usize,
    /// The highest degree examined; `order == limit` means `≥ limit`.
    pub limit: usize,
    /// The first condition that fails, at degree `order + 1`.
    pub failure: Option<NearCondition>,
}

/// The generalised orders found.
#[derive(Clone, Debug, PartialEq)]
pub struct NearReport {
    /// One per `j = 1, 2, …, J`.
    pub parts: Vec<PartOrder>,
    /// The words of the truncated algebra computed.
    pub words: usize,
    /// The Lyndon coefficients tested.
    pub conditions: usize,
}

impl NearReport {
    /// The generalised order as published: `p₁, p₂, …` up to the first part
    /// whose order is the least of it and every later part (the classical
    /// order when that part is the least of all), each with whether it is
    /// exact (`false`: at least this, the limit examined). When that first
    /// part is `p₁` itself and the later parts are all of higher order, as
    /// for a corrected method (`O(εh² + ε²h⁴)`), the least order of the
    /// later parts follows: `(2, 4)`, each later power of `ε` of order at
    /// least its last entry.
    pub fn generalised(&self) -> Vec<(usize, bool)> {
        let Some(least) = self.parts.iter().map(|p| p.order).min() else {
            return Vec::new();
        };
        let mut out = Vec::new();
        for p in &self.parts {
            out.push((p.order, p.failure.is_some()));
            if p.order == least {
                break;
            }
        }
        if out.len() == 1
            && let Some(rest) = self.parts[1..].iter().min_by_key(|p| p.order)
            && rest.order > least
        {
            out.push((rest.order, rest.failure.is_some()));
        }
        out
    }

    /// `(8, 6, 4)`, with `≥` where the limit was reached.
    pub fn generalised_text(&self) -> String {
        let items: Vec<String> = self
            .generalised()
            .iter()
            .map(|(p, exact)| {
                if *exact {
                    p.to_string()
                } else {
                    format!("≥{p}")
                }
            })
            .collect();
        format!("({})", items.join(", "))
    }
}

/// Why a generalised order cannot be decided.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum NearError {
    /// The table is not a drift–kick sequence or a composition.
    #[error(
        "a near-integrable (generalised) order is a property of a drift–kick sequence or a composition (H = A + εB, drifts the flow of A, kicks that of εB); this table is {0}"
    )]
    Form(&'static str),
    /// The degrees are not a nonempty list of positive numbers.
    #[error("{0}")]
    Degrees(String),
    #[error("{0}")]
    Budget(#[from] BeyondBudget),
}

/// The drift–kick sequence of a table, in the order applied: letters `0`
/// (drift, `A`) and `1` (kick, `B`) with their coefficients, and gradient
/// kicks `exp(k·B + g·[B,[A,B]])` as [`Factor::Gradient`] (never merged
/// with a neighbouring kick: `B` and `[B,[A,B]]` do not commute).
fn ops_of(table: &Table) -> Result<Vec<Factor>, NearError> {
    let splitting: Splitting = match table {
        Table::Splitting(s) => s.clone(),
        Table::Composition(c) => c.to_splitting(),
        Table::Rk(_) => return Err(NearError::Form("a Runge–Kutta table")),
        Table::Prk(_) => return Err(NearError::Form("a partitioned pair")),
    };
    Ok(splitting
        .flows()
        .into_iter()
        .map(|(op, x, g)| match op {
            Op::Drift => Factor::Letter(0, x),
            Op::Kick if g.is_zero() => Factor::Letter(1, x),
            Op::Kick => Factor::Gradient {
                kick: x,
                gradient: g,
            },
        })
        .collect())
}

/// A factor with its coefficients negated: the inverse flow
/// (`exp(−X) = exp(X)⁻¹`).
fn inverse(f: &Factor) -> Factor {
    match f {
        Factor::Letter(l, x) => Factor::Letter(*l, -x),
        Factor::Gradient { kick, gradient } => Factor::Gradient {
            kick: -kick,
            gradient: -gradient,
        },
    }
}

/// The drift–kick sequence of a processed method `χ Kⁿ χ⁻¹` per step, as
/// applied: `χ⁻¹`'s flows, then the kernel `K`'s, then the corrector `χ`'s,
/// neighbours of the same letter merged (`exp(xX) exp(yX) = exp((x + y)X)`)
/// and what cancels dropped; a gradient kick is merged with nothing.
///
/// **Why this is the effective method.** The corrector `χ` is applied only
/// at output and its inverse once on entry (Wisdom, Holman & Touma 1996;
/// Blanes–Casas processing), so `n` steps give `χ Kⁿ χ⁻¹ = (χ K χ⁻¹)ⁿ`
/// (maps composed right to left: `χ⁻¹` first): the output after `n` steps
/// is exactly what `n` steps of the one method `χ K χ⁻¹` would give, and
/// its errors are that method's. `χ⁻¹` is `χ`'s sequence reversed with
/// every coefficient negated (the flows are exact, `φ_{−x} = φ_x⁻¹`), so
/// `χ K χ⁻¹` is one drift–kick sequence and its orders are decided exactly
/// as any sequence's. The corrector need not be consistent (its drifts and
/// kicks typically sum to zero).
pub fn processed_sequence(kernel: &Table, corrector: &Table) -> Result<Vec<Factor>, NearError> {
    let k = ops_of(kernel)?;
    let chi = ops_of(corrector)?;
    let mut ops: Vec<Factor> = chi.iter().rev().map(inverse).collect();
    ops.extend(k);
    ops.extend(chi);
    let mut merged: Vec<Factor> = Vec::with_capacity(ops.len());
    for f in ops {
        match (merged.last_mut(), &f) {
            (Some(Factor::Letter(m, y)), Factor::Letter(l, x)) if m == l => {
                *y += x;
                if y.is_zero() {
                    merged.pop();
                }
            }
            (_, Factor::Letter(_, x)) if x.is_zero() => {}
            _ => merged.push(f),
        }
    }
    Ok(merged)
}

/// [`processed_sequence`] as a drift–kick table (a kick-first sequence gets
/// a leading zero drift, as table files write it).
pub fn processed_table(kernel: &Table, corrector: &Table) -> Result<Table, NearError> {
    let ops = processed_sequence(kernel, corrector)?;
    let mut drift = Vec::new();
    let mut kick = Vec::new();
    let mut gradient = Vec::new();
    let is_drift = |f: &Factor| matches!(f, Factor::Letter(0, _));
    if ops.first().is_some_and(|f| !is_drift(f)) {
        drift.push(Number::zero());
    }
    let mut last_drift = drift.len() == 1;
    for f in ops {
        // Two kicks in a row (a gradient kick beside a kick) are written
        // with a zero drift between them, two drifts cannot occur (merged).
        match f {
            Factor::Letter(0, x) => {
                drift.push(x);
                last_drift = true;
                continue;
            }
            _ if !last_drift => drift.push(Number::zero()),
            _ => {}
        }
        last_drift = false;
        match f {
            Factor::Letter(_, x) => {
                kick.push(x);
                gradient.push(Number::zero());
            }
            Factor::Gradient {
                kick: x,
                gradient: g,
            } => {
                kick.push(x);
                gradient.push(g);
            }
        }
    }
    if gradient.iter().all(Number::is_zero) {
        gradient.clear();
    }
    Ok(Table::Splitting(Splitting {
        drift,
        kick,
        gradient,
    }))
}

/// The effective generalised orders of a kernel `K` with a corrector
/// (processor) `χ`, applied as `χ Kⁿ χ⁻¹` with `χ` only at output: the
/// orders of the one sequence `χ K χ⁻¹` ([`processed_sequence`]), decided
/// exactly as [`near_orders`] decides any sequence's.
pub fn processed_orders(
    kernel: &Table,
    corrector: &Table,
    degrees: &[usize],
    bound: Option<&Number>,
) -> Result<NearReport, NearError> {
    decide_ops(&processed_sequence(kernel, corrector)?, degrees, bound)
}

/// Check one claim of a processed method (kernel `K`, corrector `χ`): the
/// order claims are about the effective method `χ K χ⁻¹`, the method whose
/// errors the corrected output has — `order = (p₁, p₂, …)` its generalised
/// order, `order = p` its classical order (every Lie term of degree ≤ `p`
/// vanishes, decided on the same truncated algebra); `symmetric` means the
/// effective sequence is a palindrome; `symplectic` and `explicit` hold for
/// every drift–kick sequence and are the kernel's (checked by the caller on
/// the kernel, `None` here). `order_rkn` is not decided for a processed
/// method (an error, never accepted unchecked).
pub fn check_processed_claim(
    kernel: &Table,
    corrector: &Table,
    claim: &crate::claims::Claim,
) -> Option<Result<(), String>> {
    use crate::claims::Claim;
    let what = "of the processed method χ K χ⁻¹ (corrector χ at output only, χ⁻¹ once on entry)";
    let effective = match processed_table(kernel, corrector) {
        Ok(t) => t,
        Err(e) => return Some(Err(format!("{e}"))),
    };
    Some(match claim {
        Claim::NearOrder { orders, bound } => check_near_claim(&effective, orders, bound.as_ref())
            .map(|_| ())
            .map_err(|e| format!("{e} (the effective order {what})")),
        Claim::Order { p, bound } => check_near_claim(&effective, &[*p], bound.as_ref())
            .map(|_| ())
            .map_err(|e| format!("order = {p} {what} (classical: every Lie term): {e}")),
        Claim::OrderRkn { .. } => Err(format!(
            "order_rkn is not decided for a processed method; claim the effective orders {what} as `order = p` or `order = (p1, p2, …)`"
        )),
        Claim::CertifiedOrder { .. } | Claim::CertifiedNearOrder { .. } => Err(format!(
            "a certified order is not decided for a processed method; claim the effective orders {what} as `order = p` or `order = (p1, p2, …)`"
        )),
        Claim::Symmetric => {
            let ops = match &effective {
                Table::Splitting(s) => s.flows(),
                _ => unreachable!("processed_table builds a sequence"),
            };
            let n = ops.len();
            if (0..n).all(|i| ops[i] == ops[n - 1 - i]) {
                Ok(())
            } else {
                Err(format!(
                    "not symmetric: the drift–kick sequence {what} ({n} flows) is not a palindrome"
                ))
            }
        }
        Claim::Symplectic | Claim::Explicit => return None,
    })
}

/// Decide the order of every part `j = 1..=degrees.len()` up to degree
/// `degrees[j − 1]`, exactly or, with `bound`, up to `|residual| < bound`.
/// The degrees need not be non-increasing (`[2, 4, 4]` for a claim `(2,
/// 4)`): the product is computed in the truncation by their least
/// non-increasing majorant, whose kept coefficients are exact, and each
/// part is tested up to its own degree.
pub fn near_orders(
    table: &Table,
    degrees: &[usize],
    bound: Option<&Number>,
) -> Result<NearReport, NearError> {
    decide_ops(&ops_of(table)?, degrees, bound)
}

/// [`near_orders`] of a sequence of flows.
fn decide_ops(
    ops: &[Factor],
    degrees: &[usize],
    bound: Option<&Number>,
) -> Result<NearReport, NearError> {
    let (full, lyndon) = prepare(ops, degrees)?;
    let p = product_of_exponentials(ops, &full);
    let mut conditions = 0;
    // Consistency of the drifts: the coefficient of A is Σ aᵢ, target 1.
    let a = Word::from_letters(&[0]);
    let drift_failure = {
        conditions += 1;
        condition(&p, a, bound)
    };
    let mut parts = Vec::with_capacity(degrees.len());
    for (j, words) in (1..).zip(&lyndon) {
        let limit = degrees[j - 1];
        let mut failure = drift_failure.clone();
        if failure.is_none() {
            for w in words {
                conditions += 1;
                if let Some(f) = condition(&p, *w, bound) {
                    failure = Some(f);
                    break;
                }
            }
        }
        let order = failure.as_ref().map_or(limit, |f| f.degree - 1);
        parts.push(PartOrder {
            bs: j,
            order,
            limit,
            failure,
        });
    }
    Ok(NearReport {
        parts,
        words: p.len(),
        conditions,
    })
}

/// Every Lyndon coefficient of `log Φ` with `j = 1..=degrees.len()` letters
/// `B` and degree at most `degrees[j − 1]` (and the word `A`), whether it
/// holds or not: the residuals a bound for decimal coefficients is measured
/// from.
pub fn near_coefficients(
    table: &Table,
    degrees: &[usize],
) -> Result<Vec<NearCondition>, NearError> {
    let ops = ops_of(table)?;
    let (full, lyndon) = prepare(&ops, degrees)?;
    let p = product_of_exponentials(&ops, &full);
    let mut out = vec![coefficient(&p, Word::from_letters(&[0]))];
    for w in lyndon.iter().flatten() {
        out.push(coefficient(&p, *w));
    }
    Ok(out)
}

/// `D̃(j) = max_{i ≥ j} D(i)`: the least non-increasing list at least
/// `degrees` entry by entry.
fn majorant(degrees: &[usize]) -> Vec<usize> {
    let mut out = degrees.to_vec();
    for j in (0..out.len().saturating_sub(1)).rev() {
        out[j] = out[j].max(out[j + 1]);
    }
    out
}

/// Check the degrees against the budgets; the truncation (with `D(0) =
/// D(1)`) and the Lyndon words of each part.
#[allow(clippy::type_complexity)]
fn prepare(ops: &[Factor], degrees: &[usize]) -> Result<(Vec<usize>, Vec<Vec<Word>>), NearError> {
    if degrees.is_empty() || degrees.contains(&0) {
        return Err(NearError::Degrees(
            "the degrees examined are a nonempty list of positive numbers".into(),
        ));
    }
    let top = degrees.iter().copied().max().unwrap_or(0);
    if top > MAX_NEAR_DEGREE {
        return Err(BeyondBudget(format!(
            "degree {top} asked for, and the near-integrable verifier examines at most degree {MAX_NEAR_DEGREE} (tableau::near_integrable::MAX_NEAR_DEGREE)"
        ))
        .into());
    }
    // A product of two numbers dense in a field of degree d over Q costs up
    // to d² products of rationals, which the work estimate below does not
    // count: an entry such as 1/(cbrt(2) + … + cbrt(11)) (d = 243) ran 27 s
    // on ABA(10,4). The catalogue's coefficients span degree 8 at most.
    let degree = crate::number::field_degree(ops.iter().flat_map(|f| match f {
        Factor::Letter(_, x) => vec![x],
        Factor::Gradient { kick, gradient } => vec![kick, gradient],
    }));
    if degree > MAX_NEAR_FIELD_DEGREE {
        return Err(BeyondBudget(format!(
            "the coefficients span a field of degree {degree} over Q, and the near-integrable verifier takes at most degree {MAX_NEAR_FIELD_DEGREE} (tableau::near_integrable::MAX_NEAR_FIELD_DEGREE)"
        ))
        .into());
    }
    let bits = ops
        .iter()
        .flat_map(|f| match f {
            Factor::Letter(_, x) => vec![x],
            Factor::Gradient { kick, gradient } => vec![kick, gradient],
        })
        .map(Number::size_bits)
        .max()
        .unwrap_or(0);
    let size_factor = (bits / CALIBRATED_BITS).max(1).saturating_pow(2);
    let size = if size_factor > 1 {
        format!(
            " (coefficients of up to {bits} bits count {size_factor}× a product of the calibrated size)"
        )
    } else {
        String::new()
    };
    truncation(ops, degrees, size_factor, &size)
}

/// The truncation for `degrees` (with `D(0) = D(1)`, in the least
/// non-increasing majorant) and the Lyndon words of each part, within
/// [`MAX_NEAR_DEGREE`], [`MAX_NEAR_WORDS`] and [`MAX_NEAR_WORK`] (products
/// counted `size_factor` times; `size` says why, for the message).
#[allow(clippy::type_complexity)]
pub(crate) fn truncation<T>(
    ops: &[Factor<T>],
    degrees: &[usize],
    size_factor: u64,
    size: &str,
) -> Result<(Vec<usize>, Vec<Vec<Word>>), NearError> {
    if degrees.is_empty() || degrees.contains(&0) {
        return Err(NearError::Degrees(
            "the degrees examined are a nonempty list of positive numbers".into(),
        ));
    }
    let top = degrees.iter().copied().max().unwrap_or(0);
    if top > MAX_NEAR_DEGREE {
        return Err(BeyondBudget(format!(
            "degree {top} asked for, and the near-integrable verifier examines at most degree {MAX_NEAR_DEGREE} (tableau::near_integrable::MAX_NEAR_DEGREE)"
        ))
        .into());
    }
    // D(0) = D(1): the powers of A; the truncation is the least
    // non-increasing majorant of the degrees asked for (the dropped words
    // must form an ideal; see the module `algebra`).
    let mut full = vec![top];
    full.extend_from_slice(&majorant(degrees));
    let count = word_count(&full);
    if count > MAX_NEAR_WORDS {
        return Err(BeyondBudget(format!(
            "the truncated algebra for degrees {degrees:?} has {count} words, more than the {MAX_NEAR_WORDS} the near-integrable verifier takes on (tableau::near_integrable::MAX_NEAR_WORDS)"
        ))
        .into());
    }
    let lyndon: Vec<Vec<Word>> = (1..=degrees.len())
        .map(|j| {
            (1..=degrees[j - 1])
                .flat_map(|n| words_with(n, j))
                .filter(|w| is_lyndon(&w.letters()))
                .collect()
        })
        .collect();
    // A letter factor updates each word through its trailing run: at most
    // `top` products per word. A gradient factor costs its exponential (each
    // kept word is reached by one power of E, from at most 4 words of the
    // power below: 4 products per word) and the product with it (at most
    // `top` suffixes per word): `top + 4` per word.
    let factor_work: u64 = ops
        .iter()
        .map(|f| match f {
            Factor::Letter(..) => top as u64,
            Factor::Gradient { .. } => top as u64 + 4,
        })
        .sum();
    // Products of long numbers cost more than the calibrated unit (40-digit
    // decimals, a few hundred bits): a coefficient of degree n in the flows'
    // coefficients has about n times their bits, and a product costs at
    // most the square of its length (`size_factor`). `1/2 + 1/3^10000` ran
    // 35 s on a budget that counted products alone.
    let work = count
        .saturating_mul(factor_work)
        .saturating_mul(size_factor)
        .saturating_add(
            lyndon
                .iter()
                .flatten()
                .map(|w| log_work(usize::from(w.len)))
                .sum::<u64>()
                .saturating_mul(size_factor),
        );
    if work > MAX_NEAR_WORK {
        return Err(BeyondBudget(format!(
            "deciding degrees {degrees:?} for {} flows needs about {work} exact products{size}, more than the {MAX_NEAR_WORK} the near-integrable verifier takes on (tableau::near_integrable::MAX_NEAR_WORK)",
            ops.len()
        ))
        .into());
    }
    Ok((full, lyndon))
}

/// The condition of Lyndon word `w`, if it fails.
fn condition(
    p: &std::collections::HashMap<Word, Number>,
    w: Word,
    bound: Option<&Number>,
) -> Option<NearCondition> {
    let c = coefficient(p, w);
    (!within(&c.residual, bound)).then_some(c)
}

/// The coefficient of Lyndon word `w` in `log Φ`, as a condition.
fn coefficient(p: &std::collections::HashMap<Word, Number>, w: Word) -> NearCondition {
    let value = log_coefficient(p, w);
    let expected = if w.len == 1 {
        Number::one()
    } else {
        Number::zero()
    };
    let residual = &value - &expected;
    NearCondition {
        bs: w.bs(),
        degree: usize::from(w.len),
        word: w.label(),
        lie: bracket(&w.letters()),
        value,
        expected,
        residual,
    }
}

/// The degrees a claim `(p₁, …, p_m)` needs: `p_j` for `j < m`, and `p_m`
/// for `m ≤ j < p_m` (a Lie term of degree `n` has at most `n − 1` `B`s
/// besides the word `B` itself).
pub fn claim_degrees(orders: &[usize]) -> Vec<usize> {
    let Some(&last) = orders.last() else {
        return Vec::new();
    };
    let mut out = orders.to_vec();
    while out.len() < last.saturating_sub(1) {
        out.push(last);
    }
    out
}

/// Check a claimed generalised order exactly (or within `bound`); the error
/// names the first failing condition: its power `εʲhⁿ`, Lyndon word, Lie
/// element, exact value and a float approximation.
pub fn check_near_claim(
    table: &Table,
    orders: &[usize],
    bound: Option<&Number>,
) -> Result<NearReport, String> {
    let claimed = tuple_text(orders);
    if orders.is_empty() || orders.contains(&0) {
        return Err(format!(
            "order = {claimed}: a generalised order is a nonempty list of orders of at least 1"
        ));
    }
    let report = near_orders(table, &claim_degrees(orders), bound)
        .map_err(|e| format!("order = {claimed}: {e}"))?;
    for part in &report.parts {
        if let Some(f) = &part.failure {
            let within = match bound {
                Some(b) => format!(" (residual not below {b})"),
                None => String::new(),
            };
            return Err(format!(
                "order = {claimed} claimed, but the ε{} part has order {} < {}: {f}{within}",
                power_label(part.bs, 1)
                    .trim_end_matches('h')
                    .trim_start_matches('ε'),
                part.order,
                part.limit
            ));
        }
    }
    Ok(report)
}

/// `(8, 6, 4)`.
pub fn tuple_text(orders: &[usize]) -> String {
    let items: Vec<String> = orders.iter().map(usize::to_string).collect();
    format!("({})", items.join(", "))
}
