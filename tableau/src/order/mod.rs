//! Exact order analysis: Runge–Kutta tables, partitioned pairs and
//! compositions, every condition decided in exact arithmetic.
//!
//! # Runge–Kutta tables
//!
//! For a rooted tree `t` (see [`crate::trees`]) the elementary weight is
//! `Φ(t) = Σᵢ bᵢ Φᵢ(t)` with `Φᵢ(τ) = 1` and
//! `Φᵢ([t₁,…,tₘ]) = ∏ₖ (A Φ(tₖ))ᵢ`, where `Φ(tₖ)` is the stage vector of the
//! subtree. The method has order `p` iff `Φ(t) = 1/γ(t)` for every tree with
//! `|t| ≤ p` (Butcher; HNW II.2).
//!
//! **Abscissae.** When the table gives a `c` that differs from the row sums of
//! `A`, the stages are taken at the times `t₀ + cᵢh`, and the order is the order
//! on non-autonomous problems `y' = f(t, y)`. Writing the problem autonomously
//! with `t' = 1`, the conditions are indexed by trees whose leaves may be time
//! leaves `τ_t` (a time vertex is always a leaf, since `t' = 1` has no
//! derivatives; the root is an ordinary vertex; see
//! [`Colouring::TimeLeaves`]): a time-leaf child of vertex `i` contributes `cᵢ`
//! to `Φᵢ` where an ordinary leaf contributes `(A·1)ᵢ`, and the condition is
//! again `Φ(t) = 1/γ(t)` with `γ` of the uncoloured tree. When `c` is absent
//! or equals the row sums, the time leaves contribute exactly what ordinary
//! leaves do, the extra conditions repeat the ordinary ones, and only the
//! ordinary trees are checked.
//!
//! # Partitioned pairs
//!
//! For a [`Prk`] the conditions are indexed by bicoloured trees (HLW III.2):
//! a black vertex (`_q`) is an evaluation of `q' = ∂H/∂p`, a white vertex
//! (`_p`) one of `p' = −∂H/∂q`. The weight vector a child contributes to its
//! parent is `A Φ(child)` for a black child and `Â Φ(child)` for a white one;
//! the root colour picks `b` or `b̂`. [`prk_order`] checks every bicoloured tree
//! (general partitioned systems); [`prk_order_separable`] only the trees whose
//! edges join vertices of different colours (separable systems `q' = f(p)`,
//! `p' = g(q)`, i.e. `H = T(p) + V(q)`); [`prk_order_nystrom`] only those of
//! them whose black vertices have at most one child (Runge–Kutta–Nyström
//! systems: `T = ½pᵀM⁻¹p` quadratic, so `q' = M⁻¹p` is linear and every
//! elementary differential in which `f` is differentiated twice or more
//! vanishes; [`Colouring::Nystrom`]). The given `c`, `ĉ` are not used: the
//! pairs are applied to autonomous Hamiltonian systems.
//!
//! A Runge–Kutta table `(A, b)` applied to a partitioned system is the pair
//! with both tables equal to it; [`rk_order_nystrom`] checks that pair on the
//! Nyström trees.
//!
//! # Compositions
//!
//! See [`composition_order`]: conditions on the coefficients `γₖ` themselves,
//! as words in a free algebra.
//!
//! # Residuals and bounds
//!
//! Every condition has a residual (`Φ(t) − 1/γ(t)`, or a word coefficient
//! minus its target). Without a bound the order is the highest `p` such that
//! every residual of order `≤ p` is exactly zero. With a bound `ε` (for tables
//! published as decimals) a residual passes when it is zero or `|residual| < ε`,
//! compared exactly. The check stops at the first order that fails and
//! reports its first failing condition in canonical order.

mod composition;
mod scalar;
mod weights;

use std::fmt;
use std::ops::ControlFlow;

use crate::Number;
use crate::table::{Composition, Prk, Rk};
use crate::trees::{Colouring, MAX_ORDER};

/// What indexes a condition.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ConditionKind {
    /// A rooted tree, in bracket notation ([`crate::trees`]).
    Tree,
    /// A word in the generators `Y₁, Y₃, Y₅, …` of a composition.
    Word,
    /// A Lie term of `log Φ` for a splitting `H = A + B`, named by its Lie
    /// element and leading Lyndon word ([`crate::near_integrable`]); the
    /// order of a sequence with gradient kicks, which has no trees.
    LieTerm,
}

impl ConditionKind {
    /// `"tree"` or `"word"`, for messages.
    pub fn noun(self) -> &'static str {
        match self {
            ConditionKind::Tree => "tree",
            ConditionKind::Word => "word",
            ConditionKind::LieTerm => "Lie term",
        }
    }
}

/// One order condition with its computed value: the elementary weight of a
/// tree (or a word's coefficient) and what it must equal.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Condition {
    /// `|t|`, or the weight of the word.
    pub order: usize,
    pub kind: ConditionKind,
    /// The tree in bracket notation (`[[τ]]`, `[τ_p]_q`, `[τ,τ_t]`), or the
    /// word (`Y₁²Y₃`).
    pub tree: String,
    /// `Φ(t)`, or the coefficient of the word in the composed method.
    pub value: Number,
    /// `1/γ(t)`, or the coefficient of the word in `exp(hY₁)`.
    pub expected: Number,
}

impl Condition {
    /// `value − expected`.
    pub fn residual(&self) -> Number {
        &self.value - &self.expected
    }

    /// Whether the condition holds (exactly, or within `bound`).
    pub fn holds(&self, bound: Option<&Number>) -> bool {
        within(&self.residual(), bound)
    }
}

/// Whether a residual passes: it is exactly zero, or `|residual| < bound`
/// (decided exactly).
pub fn within(residual: &Number, bound: Option<&Number>) -> bool {
    residual.is_zero() || bound.is_some_and(|b| residual.abs() < *b)
}

/// The first condition that fails.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Failure {
    /// The order of the condition (one more than the order reached).
    pub order: usize,
    pub kind: ConditionKind,
    /// The tree in bracket notation, or the word (see [`Condition::tree`]).
    pub tree: String,
    pub value: Number,
    pub expected: Number,
    /// `value − expected`, nonzero (or not below the bound).
    pub residual: Number,
}

impl fmt::Display for Failure {
    /// `the order-3 condition for tree [[τ]] fails: Φ(t) = 1/4, 1/γ(t) = 1/6, residual 1/12`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (lhs, rhs) = match self.kind {
            ConditionKind::Tree => ("Φ(t)", "1/γ(t)"),
            ConditionKind::Word | ConditionKind::LieTerm => ("coefficient", "target"),
        };
        write!(
            f,
            "the order-{} condition for {} {} fails: {lhs} = {}, {rhs} = {}, residual {}",
            self.order,
            self.kind.noun(),
            self.tree,
            self.value,
            self.expected,
            self.residual
        )
    }
}

/// The result of an order check up to `limit`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OrderReport {
    /// The order reached: every condition of order `≤ order` holds. When
    /// `order == limit` the true order is `≥ limit`.
    pub order: usize,
    /// The highest order checked.
    pub limit: usize,
    /// The first failing condition of order `order + 1`, in canonical order;
    /// `None` exactly when `order == limit`.
    pub first_failure: Option<Failure>,
    /// How many conditions were evaluated.
    pub conditions_checked: usize,
}

impl OrderReport {
    /// Every condition up to the limit holds: the order is at least `limit`.
    pub fn reached_limit(&self) -> bool {
        self.first_failure.is_none()
    }
}

impl fmt::Display for OrderReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.first_failure {
            None => write!(f, "order ≥ {} (checked up to {})", self.order, self.limit),
            Some(fail) => write!(f, "order {}: {fail}", self.order),
        }
    }
}

/// A condition as it is produced: whether it holds exactly is decided
/// cheaply; its label and its value as a [`Number`] are built only when needed.
pub(crate) struct Pending<'a> {
    order: usize,
    kind: ConditionKind,
    label: &'a dyn Fn() -> String,
    value: &'a dyn Fn() -> Number,
    expected: Number,
    /// `value == expected`, decided exactly.
    exact: bool,
}

impl Pending<'_> {
    fn into_condition(self) -> Condition {
        Condition {
            order: self.order,
            kind: self.kind,
            tree: (self.label)(),
            value: (self.value)(),
            expected: self.expected,
        }
    }
}

/// A producer of conditions, order by order.
pub(crate) trait Conditions {
    /// Evaluate the conditions of order `n` (after those of every lower order)
    /// in canonical order, handing each to `f` until it breaks.
    fn level(
        &mut self,
        n: usize,
        f: &mut dyn FnMut(Pending<'_>) -> ControlFlow<()>,
    ) -> ControlFlow<()>;
}

fn check(limit: usize, bound: Option<&Number>, source: &mut dyn Conditions) -> OrderReport {
    let mut checked = 0;
    for n in 1..=limit {
        let mut failure = None;
        let _ = source.level(n, &mut |c| {
            checked += 1;
            if c.exact {
                return ControlFlow::Continue(());
            }
            let value = (c.value)();
            let residual = &value - &c.expected;
            if within(&residual, bound) {
                ControlFlow::Continue(())
            } else {
                failure = Some(Failure {
                    order: c.order,
                    kind: c.kind,
                    tree: (c.label)(),
                    value,
                    expected: c.expected,
                    residual,
                });
                ControlFlow::Break(())
            }
        });
        if failure.is_some() {
            return OrderReport {
                order: n - 1,
                limit,
                first_failure: failure,
                conditions_checked: checked,
            };
        }
    }
    OrderReport {
        order: limit,
        limit,
        first_failure: None,
        conditions_checked: checked,
    }
}

fn collect(max_order: usize, source: &mut dyn Conditions) -> Vec<Condition> {
    let mut out = Vec::new();
    for n in 1..=max_order {
        let _ = source.level(n, &mut |c| {
            out.push(c.into_condition());
            ControlFlow::Continue(())
        });
    }
    out
}

/// Whether the order conditions of `rk` need time leaves: `c` is given and
/// differs from the row sums of `A`.
pub fn rk_uses_time_leaves(rk: &Rk) -> bool {
    rk.c.as_ref().is_some_and(|c| *c != rk.row_sums())
}

/// The order of a Runge–Kutta table, checked up to `limit` (at most
/// [`MAX_ORDER`]; a larger limit is lowered to it, and the report says so).
/// With a `c` that differs from the row sums, this is the order on
/// non-autonomous problems (see the [module docs](self)).
pub fn rk_order(rk: &Rk, limit: usize, bound: Option<&Number>) -> OrderReport {
    let limit = limit.min(MAX_ORDER);
    check(
        limit,
        bound,
        &mut *weights::rk(rk, rk_uses_time_leaves(rk), limit),
    )
}

/// The order of a partitioned pair on general partitioned systems (all
/// bicoloured trees), checked up to `limit` (at most [`MAX_ORDER`]).
pub fn prk_order(prk: &Prk, limit: usize, bound: Option<&Number>) -> OrderReport {
    let limit = limit.min(MAX_ORDER);
    check(
        limit,
        bound,
        &mut *weights::prk(prk, Colouring::Bicoloured, limit),
    )
}

/// The order of a partitioned pair on separable systems `q' = f(p)`,
/// `p' = g(q)` (bicoloured trees whose edges join different colours), checked
/// up to `limit` (at most [`MAX_ORDER`]).
pub fn prk_order_separable(prk: &Prk, limit: usize, bound: Option<&Number>) -> OrderReport {
    let limit = limit.min(MAX_ORDER);
    check(
        limit,
        bound,
        &mut *weights::prk(prk, Colouring::Separable, limit),
    )
}

/// The order of a partitioned pair on Runge–Kutta–Nyström systems: separable
/// `H = T(p) + V(q)` with `T = ½pᵀM⁻¹p` quadratic (the separable bicoloured
/// trees whose black vertices have at most one child, [`Colouring::Nystrom`]),
/// checked up to `limit` (at most [`MAX_ORDER`]). At least
/// [`prk_order_separable`], since these conditions are a subset of its.
pub fn prk_order_nystrom(prk: &Prk, limit: usize, bound: Option<&Number>) -> OrderReport {
    let limit = limit.min(MAX_ORDER);
    check(
        limit,
        bound,
        &mut *weights::prk(prk, Colouring::Nystrom, limit),
    )
}

/// The order of a Runge–Kutta table on Runge–Kutta–Nyström systems (see
/// [`prk_order_nystrom`]): the pair `(rk, rk)`, on autonomous systems, so a
/// given `c` is not used. At least the order of `rk` on autonomous problems.
pub fn rk_order_nystrom(rk: &Rk, limit: usize, bound: Option<&Number>) -> OrderReport {
    prk_order_nystrom(&rk_as_pair(rk), limit, bound)
}

/// The pair with both tables equal to `rk`.
fn rk_as_pair(rk: &Rk) -> Prk {
    Prk {
        q: rk.clone(),
        p: rk.clone(),
    }
}

/// The order of a composition `Φ_{γₘh} ∘ … ∘ Φ_{γ₁h}` of a symmetric method
/// of order 2 (Störmer–Verlet), checked up to `limit` (at most
/// [`MAX_ORDER`]).
///
/// The base method is modelled as `Φ_h = exp(hY₁ + h³Y₃ + h⁵Y₅ + …)` with
/// noncommuting free symbols `Y_k` (odd `k` only, since the method is
/// symmetric), where `Y_k` has weight `k`. The composition has order `p` iff
/// `exp(γ₁hY₁ + γ₁³h³Y₃ + …) ⋯ exp(γₘhY₁ + γₘ³h³Y₃ + …) = exp(hY₁)` up to
/// weight `p` in the free associative algebra (factors written left to right
/// in the order they are applied). The conditions are the coefficients of
/// all words of weight `≤ p`, computed exactly: the coefficient of a word
/// `w = w₁⋯wₘ` split into consecutive (possibly empty) pieces, one per factor,
/// is the sum over splittings of `∏ⱼ γⱼ^weight(wⱼ) / length(wⱼ)!`. The target
/// is `1/n!` for `Y₁ⁿ` and `0` for every other word. Within a weight, words
/// are listed by length, then lexicographically (`Y₅`, `Y₁²Y₃`, `Y₁Y₃Y₁`,
/// `Y₃Y₁²`, `Y₁⁵`). This is the standard setting for compositions of
/// symmetric methods (McLachlan 1995; Hairer–Lubich–Wanner V.3), with no
/// assumption that the `γ` are palindromic.
pub fn composition_order(
    composition: &Composition,
    limit: usize,
    bound: Option<&Number>,
) -> OrderReport {
    let limit = limit.min(MAX_ORDER);
    check(
        limit,
        bound,
        &mut *composition::word_coefficients(composition, limit),
    )
}

/// Every word coefficient of weight `≤ max_order` of a composition (see
/// [`composition_order`]), in canonical order.
pub fn composition_coefficients(composition: &Composition, max_order: usize) -> Vec<Condition> {
    let max_order = max_order.min(MAX_ORDER);
    collect(
        max_order,
        &mut *composition::word_coefficients(composition, max_order),
    )
}

/// The elementary weights `Φ(t)` (with their targets `1/γ(t)`) of every tree
/// of order `≤ max_order` that [`rk_order`] checks, in canonical order: plain
/// trees, or trees with time leaves when `c` differs from the row sums. Two
/// tables of the same kind give lists that correspond entry by entry.
pub fn rk_elementary_weights(rk: &Rk, max_order: usize) -> Vec<Condition> {
    let max_order = max_order.min(MAX_ORDER);
    collect(
        max_order,
        &mut *weights::rk(rk, rk_uses_time_leaves(rk), max_order),
    )
}

/// The elementary weights over all trees with time leaves, using
/// [`Rk::abscissae`] for the time leaves, whatever `c` is: use this to compare
/// two tables of which one has a `c` that differs from its row sums.
pub fn rk_elementary_weights_with_time(rk: &Rk, max_order: usize) -> Vec<Condition> {
    let max_order = max_order.min(MAX_ORDER);
    collect(max_order, &mut *weights::rk(rk, true, max_order))
}

/// The elementary weights of a pair over all bicoloured trees of order
/// `≤ max_order`, in canonical order.
pub fn prk_elementary_weights(prk: &Prk, max_order: usize) -> Vec<Condition> {
    let max_order = max_order.min(MAX_ORDER);
    collect(
        max_order,
        &mut *weights::prk(prk, Colouring::Bicoloured, max_order),
    )
}

/// The elementary weights of a pair over the separable bicoloured trees of
/// order `≤ max_order`, in canonical order.
pub fn prk_elementary_weights_separable(prk: &Prk, max_order: usize) -> Vec<Condition> {
    let max_order = max_order.min(MAX_ORDER);
    collect(
        max_order,
        &mut *weights::prk(prk, Colouring::Separable, max_order),
    )
}

/// The elementary weights of a pair over the Nyström trees of order
/// `≤ max_order` (see [`prk_order_nystrom`]), in canonical order.
pub fn prk_elementary_weights_nystrom(prk: &Prk, max_order: usize) -> Vec<Condition> {
    let max_order = max_order.min(MAX_ORDER);
    collect(
        max_order,
        &mut *weights::prk(prk, Colouring::Nystrom, max_order),
    )
}

/// The elementary weights of a Runge–Kutta table over the Nyström trees (the
/// pair `(rk, rk)`, see [`rk_order_nystrom`]).
pub fn rk_elementary_weights_nystrom(rk: &Rk, max_order: usize) -> Vec<Condition> {
    prk_elementary_weights_nystrom(&rk_as_pair(rk), max_order)
}
