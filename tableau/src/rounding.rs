//! Rounding a verified table to `f64` so that the rounded coefficients keep the
//! verified properties as far as rounding allows, in the spirit of IRKGL16
//! (Antoñana, Makazaga, Murua): the weights sum to exactly `1.0` and, for a
//! symplectic table, `W = BA + AᵀB − bbᵀ` of the rounded coefficients is as
//! small as it can be made.
//!
//! Every emitted entry is a *faithful* rounding of its exact value `x`: an
//! `f64` `f` with `|f − x| ≤ ulp(x)`, where `ulp(x)` is the spacing of the
//! doubles in the binade of `x` (see [`ulp`]). Such an `f` is one of the two
//! doubles that bracket `x` or, when `x` is itself a double, `x` or one of its
//! two neighbours. Starting from the correctly rounded value of every entry:
//!
//! 1. **Weights** (`b`, `b̂`, drifts, kicks, `γ`) whose exact sum is `1` are
//!    made to sum to exactly `1.0` in `f64`, summed left to right, by moving
//!    as few entries as possible to another faithful rounding, preferring
//!    the entries closest to their rounding midpoint (the smallest rounding
//!    error after the move, in ulps). Entries that are mirror images in a
//!    symmetric method (equal exact values at `i` and `n−1−i`) move together,
//!    so palindromes stay palindromes. Exact zeros never move. See
//!    [`round_weights`].
//! 2. **Symplectic tables**: with the rounded weights fixed, each off-diagonal
//!    pair `(aᵢⱼ, aⱼᵢ)` and each diagonal entry `aᵢᵢ` is chosen among the
//!    faithful roundings so that `Wᵢⱼ`, computed exactly from the doubles, is
//!    as close as possible to its exact value (zero for a table that is
//!    symplectic as written), preferring fewer moved entries and smaller
//!    rounding errors on ties. The pairs are independent (`aᵢⱼ` occurs only
//!    in `Wᵢⱼ = Wⱼᵢ`), so this is the optimum over all faithful roundings of
//!    `A`. For a partitioned pair the same is done for `bᵢâᵢⱼ + b̂ⱼaⱼᵢ −
//!    bᵢb̂ⱼ`, whose unknowns `âᵢⱼ`, `aⱼᵢ` occur in that one condition only.
//! 3. **Abscissae** `c` are the correctly rounded exact abscissae (the given
//!    `c`, or the exact row sums), never the `f64` sums of the rounded `A`.
//!
//! [`max_abs_w`] and [`max_abs_w_pair`] report what was achieved: the largest
//! `|Wᵢⱼ|` of a rounded table, computed exactly; compare a table from
//! [`round_rk`] with the plain correct rounding [`nearest_rk`].

use std::cmp::Ordering;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

use crate::analysis::Analysis;
use crate::analysis::symplectic::w_matrix;
use crate::number::rational_to_f64;
use crate::{Composition, Number, Prk, Rk, Splitting, Table};

/// A Runge–Kutta table in `f64`.
#[derive(Clone, Debug, PartialEq)]
pub struct F64Table {
    pub a: Vec<Vec<f64>>,
    pub b: Vec<f64>,
    pub c: Vec<f64>,
}

/// A partitioned pair in `f64`: `q` is `(A, b, c)`, `p` is `(Â, b̂, ĉ)`.
#[derive(Clone, Debug, PartialEq)]
pub struct F64Pair {
    pub q: F64Table,
    pub p: F64Table,
}

/// A drift–kick sequence in `f64`.
#[derive(Clone, Debug, PartialEq)]
pub struct F64Splitting {
    pub drift: Vec<f64>,
    pub kick: Vec<f64>,
    /// The gradients of gradient kicks ([`Splitting::gradient`]), each the
    /// nearest double to its exact value; empty for plain kicks.
    pub gradient: Vec<f64>,
}

/// A composition of Störmer–Verlet in `f64`: the step fractions `γ` and the
/// equivalent drift–kick sequence (its kicks are `γ`, its drifts the rounded
/// exact `(γₖ₋₁ + γₖ)/2`, adjusted to sum to `1.0`).
#[derive(Clone, Debug, PartialEq)]
pub struct F64Composition {
    pub gamma: Vec<f64>,
    pub splitting: F64Splitting,
}

/// Any of the four forms in `f64`.
#[derive(Clone, Debug, PartialEq)]
pub enum F64Rounded {
    Rk(F64Table),
    Prk(F64Pair),
    Splitting(F64Splitting),
    Composition(F64Composition),
}

// ---------------------------------------------------------------------------
// Exact helpers

/// The exact value of a finite double (a dyadic rational); `None` for ±∞ and
/// NaN.
pub fn f64_to_rational(x: f64) -> Option<BigRational> {
    if !x.is_finite() {
        return None;
    }
    if x == 0.0 {
        return Some(BigRational::zero());
    }
    let bits = x.to_bits();
    let negative = bits >> 63 == 1;
    let biased = ((bits >> 52) & 0x7ff) as i64;
    let fraction = bits & ((1u64 << 52) - 1);
    // x = m · 2^e with an integer significand m.
    let (m, e) = if biased == 0 {
        (fraction, -1074)
    } else {
        (fraction | (1u64 << 52), biased - 1075)
    };
    let m = BigInt::from(m);
    let r = if e >= 0 {
        BigRational::from_integer(m << e as usize)
    } else {
        BigRational::new(m, BigInt::one() << (-e) as usize)
    };
    Some(if negative { -r } else { r })
}

fn exact(x: f64) -> Number {
    Number::from_rational(f64_to_rational(x).expect("only finite doubles are converted"))
}

/// `ulp(x)`: the spacing of the doubles in the binade of `x`, i.e. `2^(e−52)`
/// for `2^e ≤ |x| < 2^(e+1)` (and `2^−1074` below the normal range). `None`
/// for zero (an exact zero is never moved) and for values beyond the `f64`
/// range.
pub fn ulp(x: &Number) -> Option<BigRational> {
    if x.is_zero() {
        return None;
    }
    let m = x.to_f64().abs();
    if !m.is_finite() {
        return None;
    }
    let is_power_of_two = m.is_normal() && m.to_bits() & ((1u64 << 52) - 1) == 0;
    let spacing = if is_power_of_two && x.abs() < exact(m) {
        // |x| lies just below a power of two and rounds up to it.
        m - m.next_down()
    } else {
        m.next_up() - m
    };
    f64_to_rational(spacing)
}

/// `|f − x| ≤ ulp(x)`, decided exactly: `f` is a faithful rounding of `x`.
/// For `x = 0` only `f = 0` qualifies.
pub fn within_one_ulp(f: f64, x: &Number) -> bool {
    if !f.is_finite() {
        return false;
    }
    match ulp(x) {
        None => x.is_zero() && f == 0.0,
        Some(u) => (exact(f) - x).abs() <= Number::from_rational(u),
    }
}

/// The doubles `f` with `|f − x| ≤ ulp(x)`, the correctly rounded one first.
/// For an exact zero, or a value beyond the `f64` range, only the correctly
/// rounded value.
fn candidates(x: &Number) -> Vec<f64> {
    let r = x.to_f64();
    let mut out = vec![r];
    if x.is_zero() || !r.is_finite() {
        return out;
    }
    for f in [r.next_down(), r.next_up()] {
        if f != 0.0 && within_one_ulp(f, x) {
            out.push(f);
        }
    }
    out
}

/// The rounding error `|f − x|` in units of `ulp(x)`, approximately (for
/// ranking choices only).
fn error_in_ulps(f: f64, x: &Number) -> f64 {
    match ulp(x) {
        None => 0.0,
        Some(u) => (exact(f) - x).abs().to_f64() / rational_to_f64(&u),
    }
}

/// The `f64` sum of `w` taken strictly left to right, as generated code sums
/// the weights.
pub fn sum_left_to_right(w: &[f64]) -> f64 {
    w.iter().fold(0.0, |acc, &x| acc + x)
}

fn sum_exact(x: &[Number]) -> Number {
    x.iter().fold(Number::zero(), |acc, y| acc + y)
}

// ---------------------------------------------------------------------------
// Weights

/// Entries that move together: one index, or a mirror pair `(i, n−1−i)`.
struct Unit {
    members: Vec<usize>,
    /// The other faithful roundings, with the total error after the move (in
    /// ulps, summed over the members) as the cost.
    alternatives: Vec<(f64, f64)>,
}

/// Evaluating more choices than this gives up (and keeps the correct
/// roundings); the tables in the catalogue need a handful.
const SEARCH_BUDGET: usize = 1 << 18;

/// Round a weight vector: the correctly rounded entries, adjusted (each to
/// another faithful rounding, see the [module docs](self)) so that their `f64`
/// sum taken left to right is exactly `1.0` when the exact sum is `1`. With
/// `symmetric`, entries with equal exact values at mirror positions `i` and
/// `n−1−i` move together. The fewest entries move; among those choices the
/// one with the smallest total rounding error in ulps. If no choice of
/// faithful roundings sums to `1.0` (or the search budget runs out) the
/// correct roundings are returned unchanged.
pub fn round_weights(w: &[Number], symmetric: bool) -> Vec<f64> {
    let rounded: Vec<f64> = w.iter().map(Number::to_f64).collect();
    if !sum_exact(w).is_one() || sum_left_to_right(&rounded) == 1.0 {
        return rounded;
    }
    let n = w.len();
    let mut units = Vec::new();
    for i in 0..n.div_ceil(2) {
        let mirror = n - 1 - i;
        let members = if mirror == i {
            vec![i]
        } else if symmetric && w[i] == w[mirror] {
            vec![i, mirror]
        } else {
            units.push(vec![mirror]);
            vec![i]
        };
        units.push(members);
    }
    // Visit the units in stage order so that ties go to the earliest entries.
    units.sort_by_key(|m| m[0]);
    let units: Vec<Unit> = units
        .into_iter()
        .filter_map(|members| {
            let x = &w[members[0]];
            let alternatives: Vec<(f64, f64)> = candidates(x)
                .into_iter()
                .skip(1)
                .map(|f| (f, error_in_ulps(f, x) * members.len() as f64))
                .collect();
            (!alternatives.is_empty()).then_some(Unit {
                members,
                alternatives,
            })
        })
        .collect();
    let movable: usize = units.iter().map(|u| u.members.len()).sum();
    let mut budget = SEARCH_BUDGET;
    for moves in 1..=movable {
        let mut search = WeightSearch {
            rounded: &rounded,
            units: &units,
            work: rounded.clone(),
            best: None,
            budget: &mut budget,
        };
        search.visit(0, moves, 0.0);
        if let Some((_, found)) = search.best {
            return found;
        }
        if budget == 0 {
            break;
        }
    }
    rounded
}

struct WeightSearch<'a> {
    rounded: &'a [f64],
    units: &'a [Unit],
    work: Vec<f64>,
    best: Option<(f64, Vec<f64>)>,
    budget: &'a mut usize,
}

impl WeightSearch<'_> {
    /// Try every choice that moves exactly `remaining` more entries among the
    /// units `k..`.
    fn visit(&mut self, k: usize, remaining: usize, cost: f64) {
        if remaining == 0 {
            *self.budget = self.budget.saturating_sub(1);
            if sum_left_to_right(&self.work) == 1.0
                && self.best.as_ref().is_none_or(|(c, _)| cost < *c)
            {
                self.best = Some((cost, self.work.clone()));
            }
            return;
        }
        let available: usize = self.units[k..].iter().map(|u| u.members.len()).sum();
        if available < remaining || *self.budget == 0 {
            return;
        }
        let unit = &self.units[k];
        if unit.members.len() <= remaining {
            for &(f, c) in &unit.alternatives {
                for &i in &unit.members {
                    self.work[i] = f;
                }
                self.visit(k + 1, remaining - unit.members.len(), cost + c);
                for &i in &unit.members {
                    self.work[i] = self.rounded[i];
                }
            }
        }
        self.visit(k + 1, remaining, cost);
    }
}

// ---------------------------------------------------------------------------
// Symplecticity

/// `bᵢ·x + b̂ⱼ·y − bᵢb̂ⱼ` exactly, for doubles.
fn w_entry(bi: f64, x: f64, bj: f64, y: f64) -> Option<BigRational> {
    let (bi, bj) = (f64_to_rational(bi)?, f64_to_rational(bj)?);
    Some(&bi * f64_to_rational(x)? + &bj * f64_to_rational(y)? - &bi * &bj)
}

/// Choose `x` among the faithful roundings of `x_exact` and `y` among those of
/// `y_exact` so that `bᵢx + b̂ⱼy − bᵢb̂ⱼ` is closest to `target`; ties go to
/// fewer moved entries, then to the smaller total rounding error. `x` and `y`
/// hold the correct roundings on entry.
fn choose_pair(
    bi: f64,
    bj: f64,
    x_exact: &Number,
    y_exact: &Number,
    target: &Number,
) -> Option<(f64, f64)> {
    let xs = candidates(x_exact);
    let ys = candidates(y_exact);
    let mut best: Option<(Number, usize, f64, f64, f64)> = None;
    for (kx, &x) in xs.iter().enumerate() {
        for (ky, &y) in ys.iter().enumerate() {
            let w = w_entry(bi, x, bj, y)?;
            let dev = (Number::from_rational(w) - target).abs();
            let moved = usize::from(kx > 0) + usize::from(ky > 0);
            let err = error_in_ulps(x, x_exact) + error_in_ulps(y, y_exact);
            let better = match &best {
                None => true,
                Some((d, m, e, _, _)) => match dev.cmp(d) {
                    Ordering::Less => true,
                    Ordering::Greater => false,
                    Ordering::Equal => (moved, err) < (*m, *e),
                },
            };
            if better {
                best = Some((dev, moved, err, x, y));
            }
        }
    }
    best.map(|(_, _, _, x, y)| (x, y))
}

/// Choose `aᵢᵢ` among its faithful roundings so that `2bᵢaᵢᵢ − bᵢ²` is closest
/// to `target`.
fn choose_diagonal(bi: f64, x_exact: &Number, target: &Number) -> Option<f64> {
    let mut best: Option<(Number, usize, f64, f64)> = None;
    for (k, x) in candidates(x_exact).into_iter().enumerate() {
        let w = w_entry(bi, x, bi, x)?;
        let dev = (Number::from_rational(w) - target).abs();
        let err = error_in_ulps(x, x_exact);
        let better = match &best {
            None => true,
            Some((d, m, e, _)) => match dev.cmp(d) {
                Ordering::Less => true,
                Ordering::Greater => false,
                Ordering::Equal => (usize::from(k > 0), err) < (*m, *e),
            },
        };
        if better {
            best = Some((dev, usize::from(k > 0), err, x));
        }
    }
    best.map(|(_, _, _, x)| x)
}

// ---------------------------------------------------------------------------
// The four forms

fn nearest_matrix(a: &[Vec<Number>]) -> Vec<Vec<f64>> {
    a.iter()
        .map(|row| row.iter().map(Number::to_f64).collect())
        .collect()
}

fn nearest_vec(x: &[Number]) -> Vec<f64> {
    x.iter().map(Number::to_f64).collect()
}

/// Every entry correctly rounded, nothing adjusted: the baseline.
pub fn nearest_rk(rk: &Rk) -> F64Table {
    F64Table {
        a: nearest_matrix(&rk.a),
        b: nearest_vec(&rk.b),
        c: nearest_vec(&rk.abscissae()),
    }
}

/// Both tables correctly rounded, nothing adjusted: the baseline.
pub fn nearest_prk(prk: &Prk) -> F64Pair {
    F64Pair {
        q: nearest_rk(&prk.q),
        p: nearest_rk(&prk.p),
    }
}

/// Round a Runge–Kutta table (see the [module docs](self)): `b` by
/// [`round_weights`]; with `symplectic`, `A` chosen among its faithful
/// roundings to bring `W` of the doubles closest to the exact `W`; `c` the
/// correctly rounded exact abscissae. Expects a table of consistent shape.
pub fn round_rk(rk: &Rk, symplectic: bool, symmetric: bool) -> F64Table {
    let mut out = nearest_rk(rk);
    out.b = round_weights(&rk.b, symmetric);
    if symplectic {
        let w = w_matrix(rk, rk);
        let b = &out.b;
        for i in 0..b.len() {
            if let Some(x) = choose_diagonal(b[i], &rk.a[i][i], &w[i][i]) {
                out.a[i][i] = x;
            }
            for j in i + 1..b.len() {
                if let Some((x, y)) = choose_pair(b[i], b[j], &rk.a[i][j], &rk.a[j][i], &w[i][j]) {
                    out.a[i][j] = x;
                    out.a[j][i] = y;
                }
            }
        }
    }
    out
}

/// Round a partitioned pair: `b` and `b̂` by [`round_weights`] (equal exact
/// weights give equal doubles); with `symplectic` (the conditions `bᵢâᵢⱼ +
/// b̂ⱼaⱼᵢ = bᵢb̂ⱼ` hold exactly, i.e. symplectic at least for separable
/// Hamiltonians), each pair `(âᵢⱼ, aⱼᵢ)` chosen among its faithful roundings
/// to bring the condition of the doubles closest to its exact value; `c`, `ĉ`
/// correctly rounded.
pub fn round_prk(prk: &Prk, symplectic: bool, symmetric: bool) -> F64Pair {
    let mut out = nearest_prk(prk);
    out.q.b = round_weights(&prk.q.b, symmetric);
    out.p.b = round_weights(&prk.p.b, symmetric);
    if symplectic {
        let w = w_matrix(&prk.q, &prk.p);
        for (i, w_row) in w.iter().enumerate() {
            for (j, target) in w_row.iter().enumerate() {
                let (bi, bj) = (out.q.b[i], out.p.b[j]);
                let (x_exact, y_exact) = (&prk.p.a[i][j], &prk.q.a[j][i]);
                if let Some((x, y)) = choose_pair(bi, bj, x_exact, y_exact, target) {
                    out.p.a[i][j] = x;
                    out.q.a[j][i] = y;
                }
            }
        }
    }
    out
}

/// Round a drift–kick sequence: drifts and kicks each by [`round_weights`]
/// (adjusted to sum to `1.0` where their exact sums are `1`); the gradients
/// of gradient kicks (no sum to keep) each to the nearest double, an exact
/// zero staying zero.
pub fn round_splitting(s: &Splitting, symmetric: bool) -> F64Splitting {
    F64Splitting {
        drift: round_weights(&s.drift, symmetric),
        kick: round_weights(&s.kick, symmetric),
        gradient: s.gradient.iter().map(Number::to_f64).collect(),
    }
}

/// Round a composition: `γ` by [`round_weights`], and its drift–kick sequence
/// (kicks are the rounded `γ`, drifts the exact half-sums rounded by
/// [`round_weights`]).
pub fn round_composition(c: &Composition, symmetric: bool) -> F64Composition {
    let gamma = round_weights(&c.gamma, symmetric);
    let split = c.to_splitting();
    F64Composition {
        splitting: F64Splitting {
            drift: round_weights(&split.drift, symmetric),
            kick: gamma.clone(),
            gradient: Vec::new(),
        },
        gamma,
    }
}

/// Round any table with the verdicts of its analysis: symplectic (for a pair,
/// symplectic at least for separable Hamiltonians) and symmetric.
pub fn round_table(table: &Table, analysis: &Analysis) -> F64Rounded {
    let symmetric = analysis.symmetric;
    match table {
        Table::Rk(rk) => F64Rounded::Rk(round_rk(rk, analysis.symplectic, symmetric)),
        Table::Prk(prk) => {
            F64Rounded::Prk(round_prk(prk, analysis.symplectic_separable, symmetric))
        }
        Table::Splitting(s) => F64Rounded::Splitting(round_splitting(s, symmetric)),
        Table::Composition(c) => F64Rounded::Composition(round_composition(c, symmetric)),
    }
}

// ---------------------------------------------------------------------------
// What was achieved

/// `max |Wᵢⱼ|` over the entries of `W = BA + AᵀB − bbᵀ` of the doubles,
/// computed exactly and then correctly rounded to `f64`; `∞` if an entry is
/// not finite.
pub fn max_abs_w(t: &F64Table) -> f64 {
    max_abs_condition(t, t)
}

/// `max |bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ|` of the doubles, exactly, then rounded.
pub fn max_abs_w_pair(p: &F64Pair) -> f64 {
    max_abs_condition(&p.q, &p.p)
}

fn max_abs_condition(q: &F64Table, p: &F64Table) -> f64 {
    let mut max = BigRational::zero();
    for (i, (&bi, row)) in q.b.iter().zip(&p.a).enumerate() {
        for (j, (&bj, &x)) in p.b.iter().zip(row).enumerate() {
            match w_entry(bi, x, bj, q.a[j][i]) {
                Some(w) => max = max.max(w.abs()),
                None => return f64::INFINITY,
            }
        }
    }
    rational_to_f64(&max)
}
