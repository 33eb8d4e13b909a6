//! Elementary weights of (coloured) trees, memoised per subtree.
//!
//! Every tree is its root with its last child split off (see
//! [`Tree::split_last`](crate::trees::Tree::split_last)), so its stage vector
//! is one elementwise product: `Φ(t) = contrib(last child) ⊙ Φ(t without it)`,
//! where `contrib(u) = A_colour(u) Φ(u)` (or `c` for a time leaf) is computed
//! once per subtree. Zero entries of the tables and of the vectors are skipped.
//! The arithmetic is fraction-free (see [`super::scalar`]): entries are scaled
//! by a common denominator `D`, and a weight of order `n` is an integer (or an
//! integer combination of radicals) over `Dⁿ`.

use std::ops::ControlFlow;

use num_bigint::BigInt;

use super::scalar::{Monomials, RadicalPoly, Scalar, common_denominator};
use super::{ConditionKind, Conditions, Pending};
use crate::Number;
use crate::table::{Prk, Rk};
use crate::trees::{Colour, Colouring, Forest};

/// The nonzero entries of a square matrix, row by row.
struct Sparse<S> {
    rows: Vec<Vec<(usize, S)>>,
}

impl<S: Scalar> Sparse<S> {
    fn new(a: &[Vec<Number>], den: &BigInt) -> Self {
        Sparse {
            rows: a
                .iter()
                .map(|row| {
                    row.iter()
                        .enumerate()
                        .filter(|(_, x)| !x.is_zero())
                        .map(|(j, x)| (j, S::from_number(x, den)))
                        .collect()
                })
                .collect(),
        }
    }

    fn apply(&self, v: &[S]) -> Vec<S> {
        self.rows
            .iter()
            .map(|row| {
                let mut acc = S::zero();
                for (j, a) in row {
                    acc.add_product(a, &v[*j]);
                }
                acc
            })
            .collect()
    }
}

/// How a subtree whose root has a given colour contributes to its parent.
enum Child<S> {
    /// `A Φ(u)`.
    Matrix(Sparse<S>),
    /// A fixed vector: `c` for a time leaf.
    Fixed(Vec<S>),
}

struct Rule<S> {
    colour: Colour,
    child: Child<S>,
    /// The weights `b` if trees with this root colour are conditions.
    root: Option<Vec<S>>,
}

/// A table as the engine needs it: per colour, `A` (or a fixed vector) and
/// `b` (if that colour may be a root).
struct Spec<'a> {
    colour: Colour,
    a: Option<&'a [Vec<Number>]>,
    fixed: Option<Vec<Number>>,
    b: Option<&'a [Number]>,
}

struct Engine<S> {
    forest: Forest,
    /// The highest order that will be asked for: subtrees below it are kept.
    top: usize,
    rules: Vec<Rule<S>>,
    ones: Vec<S>,
    /// `Dⁿ` by `n`.
    den_pows: Vec<BigInt>,
    /// Stage vectors `Φ(t)` of the trees below `top`, by id.
    phi: Vec<Option<Vec<S>>>,
    /// `contrib(t)` of the trees below `top`, by id.
    contrib: Vec<Option<Vec<S>>>,
    monomials: Monomials,
}

/// The engine for a table: integers when every entry is rational, integer
/// combinations of radicals otherwise.
fn engine(colouring: Colouring, specs: Vec<Spec<'_>>, top: usize) -> Box<dyn Conditions> {
    let entries = || {
        specs.iter().flat_map(|s| {
            let a = s.a.into_iter().flatten().flatten();
            let fixed = s.fixed.iter().flatten();
            let b = s.b.into_iter().flatten();
            a.chain(fixed).chain(b)
        })
    };
    let den = common_denominator(entries());
    if entries().all(Number::is_rational) {
        Box::new(Engine::<BigInt>::new(colouring, &specs, den, top))
    } else {
        Box::new(Engine::<RadicalPoly>::new(colouring, &specs, den, top))
    }
}

/// A Runge–Kutta table; `time` selects the trees with time leaves, which
/// contribute [`Rk::abscissae`].
pub(crate) fn rk(rk: &Rk, time: bool, top: usize) -> Box<dyn Conditions> {
    let mut specs = vec![Spec {
        colour: Colour::Y,
        a: Some(&rk.a),
        fixed: None,
        b: Some(&rk.b),
    }];
    let colouring = if time {
        specs.push(Spec {
            colour: Colour::T,
            a: None,
            fixed: Some(rk.abscissae()),
            b: None,
        });
        Colouring::TimeLeaves
    } else {
        Colouring::Plain
    };
    engine(colouring, specs, top)
}

/// A partitioned pair over `Bicoloured`, `Separable` or `Nystrom` trees.
pub(crate) fn prk(prk: &Prk, colouring: Colouring, top: usize) -> Box<dyn Conditions> {
    let specs = vec![
        Spec {
            colour: Colour::Q,
            a: Some(&prk.q.a),
            fixed: None,
            b: Some(&prk.q.b),
        },
        Spec {
            colour: Colour::P,
            a: Some(&prk.p.a),
            fixed: None,
            b: Some(&prk.p.b),
        },
    ];
    engine(colouring, specs, top)
}

impl<S: Scalar> Engine<S> {
    fn new(colouring: Colouring, specs: &[Spec<'_>], den: BigInt, top: usize) -> Self {
        let s = specs
            .iter()
            .find_map(|spec| spec.b.map(<[Number]>::len))
            .expect("a root colour");
        let convert = |v: &[Number]| v.iter().map(|x| S::from_number(x, &den)).collect();
        let rules = specs
            .iter()
            .map(|spec| Rule {
                colour: spec.colour,
                child: match (spec.a, &spec.fixed) {
                    (Some(a), _) => Child::Matrix(Sparse::new(a, &den)),
                    (None, Some(c)) => Child::Fixed(convert(c)),
                    (None, None) => unreachable!("a colour contributes somehow"),
                },
                root: spec.b.map(convert),
            })
            .collect();
        let mut den_pows = vec![BigInt::from(1)];
        for n in 1..=top {
            den_pows.push(&den_pows[n - 1] * &den);
        }
        Engine {
            forest: Forest::new(colouring, 0),
            top,
            rules,
            ones: vec![S::one(); s],
            den_pows,
            phi: Vec::new(),
            contrib: Vec::new(),
            monomials: Monomials::default(),
        }
    }
}

fn hadamard<S: Scalar>(u: &[S], v: &[S]) -> Vec<S> {
    u.iter()
        .zip(v)
        .map(|(x, y)| {
            if x.is_zero() || y.is_zero() {
                S::zero()
            } else {
                x.mul(y)
            }
        })
        .collect()
}

fn dot<S: Scalar>(u: &[S], v: &[S]) -> S {
    let mut acc = S::zero();
    for (x, y) in u.iter().zip(v) {
        acc.add_product(x, y);
    }
    acc
}

impl<S: Scalar> Conditions for Engine<S> {
    fn level(
        &mut self,
        n: usize,
        f: &mut dyn FnMut(Pending<'_>) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        assert!(
            n <= self.top,
            "order {n} asked of an engine built for {}",
            self.top
        );
        self.forest.extend_to(n);
        let range = self.forest.level(n);
        self.phi.resize(range.end, None);
        self.contrib.resize(range.end, None);
        for id in range {
            let tree = self.forest.tree(id);
            let rule = self
                .rules
                .iter()
                .find(|r| r.colour == tree.colour)
                .expect("every colour of the forest has a rule");
            let phi = match tree.split_last() {
                None => self.ones.clone(),
                Some((prefix, last)) => {
                    let c = self.contrib[last]
                        .as_ref()
                        .expect("a child is below the top order");
                    if self.forest.tree(prefix).is_leaf() {
                        c.clone()
                    } else {
                        let p = self.phi[prefix]
                            .as_ref()
                            .expect("a prefix is below the top order");
                        hadamard(c, p)
                    }
                }
            };
            if let Some(b) = &rule.root {
                let value = dot(b, &phi);
                let gamma = BigInt::from(tree.gamma);
                let den = &self.den_pows[n];
                // Φ(t) = value / Dⁿ equals 1/γ(t) iff γ·value = Dⁿ.
                let exact = value.scale(&gamma).is_integer(den);
                let forest = &self.forest;
                let monomials = &self.monomials;
                f(Pending {
                    order: n,
                    kind: ConditionKind::Tree,
                    label: &|| forest.bracket(id),
                    value: &|| value.to_number(den, monomials),
                    expected: Number::from_rational(num_rational::BigRational::new(
                        1.into(),
                        gamma.clone(),
                    )),
                    exact,
                })?;
            }
            if n < self.top {
                self.contrib[id] = Some(match &rule.child {
                    Child::Matrix(a) => a.apply(&phi),
                    Child::Fixed(c) => c.clone(),
                });
                self.phi[id] = Some(phi);
            }
        }
        ControlFlow::Continue(())
    }
}
