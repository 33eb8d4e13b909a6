//! The order conditions of a table with `root(...)` entries, decided in the
//! number field: every elementary weight `Φ(t) = Σᵢ bᵢ Φᵢ(t)` is built as a
//! real algebraic number ([`Alg`]) along the same tree splits as the
//! rational engine (`Φ(t) = contrib(last child) ⊙ Φ(t without it)`,
//! `contrib(u) = A_colour(u) Φ(u)`, or `c` for a time leaf), and the
//! condition `Φ(t) = 1/γ(t)` is one exact zero test ([`Field::is_zero`]).
//! Nothing is decided in floating point: a condition that is beyond the
//! budgets of the zero test or of the products is reported as undecided,
//! never as holding.
//!
//! **Budgets.** The products go through [`Field::try_mul`] (each within
//! [`crate::budget::MAX_ALG_PRODUCT_WORK`] and [`crate::budget::MAX_ALG_TERMS`],
//! all of them charged to the field's work limit), the trees of all orders
//! examined are at most [`MAX_ALG_TREES`], and the order at most
//! [`crate::trees::MAX_ORDER`].

use num_bigint::BigInt;
use num_rational::BigRational;

use super::alg::{Alg, Field};
use crate::budget::BeyondBudget;
use crate::trees::{Colour, Colouring, Forest};

/// The most trees (of every order examined together) whose conditions a
/// root-entry table has decided: Runge–Kutta trees up to order 10 are 719,
/// the separable bicoloured ones up to order 8 are 574.
pub const MAX_ALG_TREES: usize = 4096;

/// How the stages of one colour are weighted.
pub struct ColourRule<'a> {
    pub colour: Colour,
    /// `A Φ(child)` for a child of this colour; `None` with `fixed`.
    pub a: Option<&'a [Vec<Alg>]>,
    /// A fixed contribution (the abscissae `c` for a time leaf).
    pub fixed: Option<&'a [Alg]>,
    /// The weights, if a tree with a root of this colour is a condition.
    pub b: Option<&'a [Alg]>,
}

/// The first condition that fails.
#[derive(Clone, Debug, PartialEq)]
pub struct AlgTreeFailure {
    pub order: usize,
    /// The tree in bracket notation.
    pub tree: String,
    /// `1/γ(t)`.
    pub expected: BigRational,
    /// `Φ(t) − 1/γ(t)` correctly rounded (`None`: beyond the budget).
    pub residual: Option<f64>,
}

/// The order decided on the trees.
#[derive(Clone, Debug, PartialEq)]
pub struct AlgOrder {
    /// Every condition of order `≤ order` holds exactly (or within the
    /// bound).
    pub order: usize,
    /// The highest order examined.
    pub limit: usize,
    /// The first condition of order `order + 1` that fails.
    pub failure: Option<AlgTreeFailure>,
    /// Why a condition of order `order + 1` could not be decided.
    pub undecided: Option<String>,
    /// How many conditions were decided.
    pub conditions: usize,
}

/// Decide the conditions of every tree of `colouring` of order `1..=limit`
/// (at most [`crate::trees::MAX_ORDER`]), level by level, stopping at the
/// first level with a failing or undecided condition. With `bound` (a
/// positive rational), a residual passes when `|Φ(t) − 1/γ(t)| < bound`,
/// decided by two exact sign tests.
pub fn alg_tree_order(
    f: &Field,
    colouring: Colouring,
    rules: &[ColourRule<'_>],
    stages: usize,
    limit: usize,
    bound: Option<&BigRational>,
) -> AlgOrder {
    let limit = limit.min(crate::trees::MAX_ORDER);
    let mut out = AlgOrder {
        order: 0,
        limit,
        failure: None,
        undecided: None,
        conditions: 0,
    };
    let mut forest = Forest::new(colouring, 0);
    let mut phi: Vec<Option<Vec<Alg>>> = Vec::new();
    let mut contrib: Vec<Option<Vec<Alg>>> = Vec::new();
    let ones = vec![Alg::int(1); stages];
    for n in 1..=limit {
        forest.extend_to(n);
        if forest.len() > MAX_ALG_TREES {
            out.undecided = Some(format!(
                "the order-{n} conditions bring the trees examined to {}, beyond the budget of {MAX_ALG_TREES} (tableau::algebraic::trees::MAX_ALG_TREES)",
                forest.len()
            ));
            return out;
        }
        let range = forest.level(n);
        phi.resize(range.end, None);
        contrib.resize(range.end, None);
        for id in range {
            let tree = forest.tree(id).clone();
            let rule = rules
                .iter()
                .find(|r| r.colour == tree.colour)
                .expect("a rule for every colour of the forest");
            let step = || -> Result<Vec<Alg>, BeyondBudget> {
                Ok(match tree.split_last() {
                    None => ones.clone(),
                    Some((prefix, last)) => {
                        let c = contrib[last].as_ref().expect("a child is below the order");
                        if forest.tree(prefix).is_leaf() {
                            c.clone()
                        } else {
                            let p = phi[prefix].as_ref().expect("a prefix is below the order");
                            let mut v = Vec::with_capacity(stages);
                            for (x, y) in c.iter().zip(p) {
                                v.push(f.try_mul(x, y)?);
                            }
                            v
                        }
                    }
                })
            };
            let this = match step() {
                Ok(v) => v,
                Err(e) => {
                    out.undecided = Some(format!(
                        "the order-{n} condition for tree {}: {e}",
                        forest.bracket(id)
                    ));
                    return out;
                }
            };
            if let Some(b) = rule.b {
                out.conditions += 1;
                let expected = BigRational::new(1.into(), BigInt::from(tree.gamma));
                let decided = (|| -> Result<Option<Alg>, BeyondBudget> {
                    let mut value = Alg::rational(-expected.clone());
                    for (bi, x) in b.iter().zip(&this) {
                        value = value.add(&f.try_mul(bi, x)?);
                    }
                    let holds = match bound {
                        None => f.is_zero(&value)?,
                        Some(e) => {
                            f.sign(&value.sub(&Alg::rational(e.clone())))? < 0
                                && f.sign(&value.add(&Alg::rational(e.clone())))? > 0
                        }
                    };
                    Ok((!holds).then_some(value))
                })();
                match decided {
                    Ok(None) => {}
                    Ok(Some(residual)) => {
                        out.failure = Some(AlgTreeFailure {
                            order: n,
                            tree: forest.bracket(id),
                            expected,
                            residual: f.to_f64(&residual).ok(),
                        });
                        return out;
                    }
                    Err(e) => {
                        out.undecided = Some(format!(
                            "the order-{n} condition for tree {}: {e}",
                            forest.bracket(id)
                        ));
                        return out;
                    }
                }
            }
            if n < limit {
                let c = match (rule.a, rule.fixed) {
                    (Some(a), _) => {
                        let mut v = Vec::with_capacity(stages);
                        for row in a {
                            let mut acc = Alg::zero();
                            for (aij, x) in row.iter().zip(&this) {
                                if aij.is_zero_poly() || x.is_zero_poly() {
                                    continue;
                                }
                                match f.try_mul(aij, x) {
                                    Ok(p) => acc = acc.add(&p),
                                    Err(e) => {
                                        out.undecided = Some(format!(
                                            "the order-{} conditions (building on tree {}): {e}",
                                            n + 1,
                                            forest.bracket(id)
                                        ));
                                        return out;
                                    }
                                }
                            }
                            v.push(f.collapse(&acc));
                        }
                        v
                    }
                    (None, Some(c)) => c.to_vec(),
                    (None, None) => unreachable!("a colour contributes somehow"),
                };
                contrib[id] = Some(c);
                phi[id] = Some(this);
            }
        }
        out.order = n;
    }
    out
}
