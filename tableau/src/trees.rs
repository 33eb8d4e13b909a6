//! Rooted trees, plain and coloured, in a canonical form: the index set of the
//! order conditions of Runge–Kutta methods (Butcher; Hairer–Nørsett–Wanner
//! II.2; Hairer–Lubich–Wanner, *Geometric Numerical Integration*, III.1–III.2).
//!
//! # Representation
//!
//! A tree is a root of some [`Colour`] with a multiset of subtrees, its
//! children. A [`Forest`] holds every (sub)tree up to a given order, each
//! identified by a [`TreeId`]: ids grow with the order, and each tree stores
//! its children as a non-decreasing list of ids. A tree is therefore stored
//! exactly once (the canonical form is the sorted child list), and equality of
//! trees is equality of ids.
//!
//! Within one order, trees are listed by root colour (in the order of
//! [`Colouring::colours`]) and then lexicographically by their child lists.
//! For plain trees this is the order of the tables in Hairer–Lubich–Wanner:
//! `τ`, `[τ]`, `[τ²]`, `[[τ]]`, `[τ³]`, `[τ,[τ]]`, `[[τ²]]`, `[[[τ]]]`, …
//!
//! # Bracket notation
//!
//! [`Forest::bracket`] writes a tree as text, in Butcher's notation:
//!
//! * `τ` is the tree with one vertex;
//! * `[t₁,…,tₘ]` is a root whose children are the subtrees `t₁,…,tₘ`, written
//!   in canonical order; a subtree repeated `k` times is written once with the
//!   superscript `k`, so `[τ²]` is `[τ,τ]` (the "cherry") and `[[τ]²]` is
//!   `[[τ],[τ]]`. `[[τ]]` is the chain of three vertices.
//!
//! Coloured vertices carry a suffix after the leaf symbol or after the closing
//! bracket of the subtree they root:
//!
//! * bicoloured trees ([`Colouring::Bicoloured`], [`Colouring::Separable`],
//!   [`Colouring::Nystrom`]): `_q` for a black vertex (an evaluation of
//!   `q' = ∂H/∂p`, weighted by the table `(A, b)` of the `q` component), `_p`
//!   for a white vertex (an evaluation of `p' = −∂H/∂q`, weighted by
//!   `(Â, b̂)`). `[τ_p]_q` is a black root with one white child; `[τ_p²]_q` a
//!   black root with two white leaves (the superscript counts the whole
//!   subtree `τ_p`).
//! * trees with time leaves ([`Colouring::TimeLeaves`]): ordinary vertices are
//!   unmarked, a time leaf is `τ_t`. `[τ,τ_t]` is a root with one ordinary
//!   leaf and one time leaf.
//!
//! # Order, symmetry, density
//!
//! For `t = [t₁^m₁ … t_k^m_k]` with distinct `tᵢ` (distinct as coloured trees):
//! the order `|t|` is the number of vertices; the symmetry
//! `σ(t) = ∏ mᵢ! σ(tᵢ)^mᵢ` (`σ(τ) = 1`); the density `γ(t) = |t| ∏ γ(tᵢ)^mᵢ`
//! (`γ(τ) = 1`), which ignores colours. The exact solution of `y' = f(y)` has
//! the B-series `Σ h^|t| / (σ(t) γ(t)) F(t)(y₀)`.

use std::collections::HashMap;
use std::ops::Range;

/// The index of a tree in its [`Forest`].
pub type TreeId = usize;

/// The highest order a [`Forest`] generates: `σ` and `γ` stay within `u64`
/// (and the number of trees is astronomically large well before).
pub const MAX_ORDER: usize = 20;

/// The colour of a vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Colour {
    /// An ordinary vertex: the only colour of plain trees, and the
    /// `y`-vertices (evaluations of `f`) of trees with time leaves.
    Y,
    /// A time leaf: `t' = 1` for the non-autonomous problem `y' = f(t, y)`
    /// written autonomously. Time vertices are always leaves and never roots.
    T,
    /// A black vertex: an evaluation of `q' = ∂H/∂p` (table `A, b`).
    Q,
    /// A white vertex: an evaluation of `p' = −∂H/∂q` (table `Â, b̂`).
    P,
}

/// Which trees a [`Forest`] holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Colouring {
    /// Ordinary rooted trees (OEIS A000081): the order conditions of
    /// Runge–Kutta methods on autonomous problems.
    Plain,
    /// Bicoloured rooted trees, any vertex black or white (OEIS A000151): the
    /// order conditions of partitioned Runge–Kutta methods on general
    /// partitioned systems `q' = f(q, p)`, `p' = g(q, p)`.
    Bicoloured,
    /// Bicoloured trees in which every edge joins vertices of different
    /// colours (twice A000081): the order conditions on separable systems
    /// `q' = f(p)`, `p' = g(q)`, where `f` does not depend on `q` nor `g` on `p`.
    Separable,
    /// The [`Separable`](Colouring::Separable) trees in which every black
    /// vertex ([`Colour::Q`], an evaluation of the velocity `q' = ∂H/∂p`) has
    /// at most one child: the order conditions on Runge–Kutta–Nyström
    /// systems, separable `H = T(p) + V(q)` with `T = ½pᵀM⁻¹p` quadratic, so
    /// that `q' = M⁻¹p` is linear in `p` and its second and higher
    /// derivatives (the elementary differentials of a black vertex with two
    /// or more children) vanish. These are the Nyström trees of
    /// Hairer–Nørsett–Wanner I, II.14 (black = "meagre", white = "fat").
    ///
    /// Counts per order `n` (`Pₙ` white roots, `Qₙ` black roots): `Q₁ = 1`,
    /// `Qₙ = Pₙ₋₁` (a black root has one white child), and `Pₙ` is the
    /// number of multisets of black subtrees of total order `n − 1`. From
    /// `n = 1`:
    ///
    /// * white roots (conditions on `b̂`, the `p` component): 1, 1, 2, 3, 6,
    ///   10, 20, 36, 72, 137, 275, 541;
    /// * black roots (conditions on `b`, the `q` component): 1, 1, 1, 2, 3,
    ///   6, 10, 20, 36, 72, 137, 275;
    /// * both: 2, 2, 3, 5, 9, 16, 30, 56, 108, 209, 412, 816.
    Nystrom,
    /// Trees whose leaves may be time leaves ([`Colour::T`]); the root is an
    /// ordinary vertex. The order conditions of a Runge–Kutta method with
    /// abscissae `c` on non-autonomous problems `y' = f(t, y)`: a time leaf
    /// child of vertex `i` contributes `cᵢ` where an ordinary leaf contributes
    /// `(A·1)ᵢ`.
    TimeLeaves,
}

impl Colouring {
    /// The vertex colours, in the order used for canonical listing.
    pub fn colours(self) -> &'static [Colour] {
        match self {
            Colouring::Plain => &[Colour::Y],
            Colouring::TimeLeaves => &[Colour::Y, Colour::T],
            Colouring::Bicoloured | Colouring::Separable | Colouring::Nystrom => {
                &[Colour::Q, Colour::P]
            }
        }
    }

    /// Whether a tree whose root has this colour is an order condition (time
    /// leaves are only ever children).
    pub fn is_root_colour(self, colour: Colour) -> bool {
        colour != Colour::T
    }

    /// Whether a vertex of colour `parent` may have a child of colour `child`.
    pub fn allows_child(self, parent: Colour, child: Colour) -> bool {
        match self {
            Colouring::Plain | Colouring::Bicoloured => true,
            Colouring::TimeLeaves => parent == Colour::Y,
            Colouring::Separable | Colouring::Nystrom => parent != child,
        }
    }

    /// Whether a vertex of this colour has at most one child (otherwise any
    /// number). Only the black vertices of [`Colouring::Nystrom`] are so
    /// limited.
    pub fn at_most_one_child(self, colour: Colour) -> bool {
        self == Colouring::Nystrom && colour == Colour::Q
    }

    /// Whether a vertex of this colour may have children at all.
    fn may_have_children(self, colour: Colour) -> bool {
        self.colours()
            .iter()
            .any(|&child| self.allows_child(colour, child))
    }
}

/// One tree of a [`Forest`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Tree {
    /// `|t|`, the number of vertices.
    pub order: usize,
    /// The colour of the root.
    pub colour: Colour,
    /// The children, non-decreasing ids.
    pub children: Vec<TreeId>,
    /// `σ(t)`, the order of the automorphism group.
    pub sigma: u64,
    /// `γ(t)`, the density.
    pub gamma: u64,
    /// The tree without its last child, and that child.
    split: Option<(TreeId, TreeId)>,
}

impl Tree {
    /// For a tree with children: the same root with its last child removed
    /// (a smaller tree of the same forest), and that last child. `None` for
    /// a single vertex. Weights of trees are built along this split.
    pub fn split_last(&self) -> Option<(TreeId, TreeId)> {
        self.split
    }

    pub fn is_leaf(&self) -> bool {
        self.children.is_empty()
    }
}

/// All trees of one [`Colouring`] up to some order, in canonical order.
///
/// ```
/// use tableau::trees::{Colouring, Forest};
/// let forest = Forest::new(Colouring::Plain, 4);
/// let names: Vec<String> = forest.conditions(3).map(|t| forest.bracket(t)).collect();
/// assert_eq!(names, ["[τ²]", "[[τ]]"]);
/// assert_eq!(forest.tree(forest.conditions(3).nth(1).unwrap()).gamma, 6);
/// ```
#[derive(Clone, Debug)]
pub struct Forest {
    colouring: Colouring,
    trees: Vec<Tree>,
    /// `levels[n]`: the ids of the trees of order `n` (`levels[0]` is empty).
    levels: Vec<Range<TreeId>>,
    /// `(root colour, children) → id`, to find the prefix of a new tree.
    index: HashMap<(Colour, Vec<TreeId>), TreeId>,
}

impl Forest {
    /// Every tree of `colouring` of order `≤ max_order`.
    ///
    /// # Panics
    /// If `max_order > MAX_ORDER`.
    pub fn new(colouring: Colouring, max_order: usize) -> Forest {
        let mut forest = Forest {
            colouring,
            trees: Vec::new(),
            levels: vec![Range::default()],
            index: HashMap::new(),
        };
        forest.extend_to(max_order);
        forest
    }

    pub fn colouring(&self) -> Colouring {
        self.colouring
    }

    /// The highest order generated so far.
    pub fn max_order(&self) -> usize {
        self.levels.len() - 1
    }

    /// Generate the trees of the orders up to `max_order` not generated yet.
    /// Existing ids do not change.
    ///
    /// # Panics
    /// If `max_order > MAX_ORDER`.
    pub fn extend_to(&mut self, max_order: usize) {
        assert!(
            max_order <= MAX_ORDER,
            "trees of order {max_order} requested; the limit is {MAX_ORDER}"
        );
        while self.max_order() < max_order {
            self.generate_level();
        }
    }

    /// Number of trees (every colour, time leaves included).
    pub fn len(&self) -> usize {
        self.trees.len()
    }

    pub fn is_empty(&self) -> bool {
        self.trees.is_empty()
    }

    pub fn tree(&self, id: TreeId) -> &Tree {
        &self.trees[id]
    }

    /// The ids of all (sub)trees of order `n`, including those whose root
    /// colour is not a root colour (the time leaf).
    pub fn level(&self, n: usize) -> Range<TreeId> {
        self.levels.get(n).cloned().unwrap_or(0..0)
    }

    /// The trees of order `n` that index order conditions, in canonical order.
    pub fn conditions(&self, n: usize) -> impl Iterator<Item = TreeId> + '_ {
        self.level(n)
            .filter(move |&id| self.colouring.is_root_colour(self.trees[id].colour))
    }

    /// The number of trees of order `n` that index order conditions.
    pub fn count(&self, n: usize) -> usize {
        self.conditions(n).count()
    }

    /// The bracket notation of a tree (see the [module docs](self)).
    pub fn bracket(&self, id: TreeId) -> String {
        let mut out = String::new();
        self.write_bracket(id, &mut out);
        out
    }

    fn write_bracket(&self, id: TreeId, out: &mut String) {
        let t = &self.trees[id];
        if t.is_leaf() {
            out.push('τ');
        } else {
            out.push('[');
            let mut i = 0;
            while i < t.children.len() {
                let c = t.children[i];
                let run = t.children[i..].iter().take_while(|&&d| d == c).count();
                if i > 0 {
                    out.push(',');
                }
                self.write_bracket(c, out);
                if run > 1 {
                    out.push_str(&superscript(run));
                }
                i += run;
            }
            out.push(']');
        }
        out.push_str(match t.colour {
            Colour::Y => "",
            Colour::T => "_t",
            Colour::Q => "_q",
            Colour::P => "_p",
        });
    }

    fn generate_level(&mut self) {
        let n = self.max_order() + 1;
        let start = self.trees.len();
        for &colour in self.colouring.colours() {
            if n == 1 {
                self.push(1, colour, Vec::new(), None);
            } else if self.colouring.may_have_children(colour) {
                let leaf = self.index[&(colour, Vec::new())];
                let mut stack = Vec::new();
                self.children_dfs(n, colour, n - 1, 0, leaf, &mut stack);
            }
        }
        self.levels.push(start..self.trees.len());
    }

    /// Emit, in lexicographic order, every tree of order `n` with root
    /// `colour` whose child list starts with `stack` (that prefix tree is
    /// `prefix`), the remaining children having total order `remaining` and
    /// ids `≥ min_id`.
    ///
    /// A root limited to one child ([`Colouring::at_most_one_child`]) is only
    /// called with an empty `stack` and takes one child of order
    /// `remaining`: its prefix is the leaf of its colour, which exists, so
    /// every tree's prefix (the tree without its last child) is still in the
    /// forest.
    fn children_dfs(
        &mut self,
        n: usize,
        colour: Colour,
        remaining: usize,
        min_id: TreeId,
        prefix: TreeId,
        stack: &mut Vec<TreeId>,
    ) {
        let end = self.levels[remaining].end;
        let start = if self.colouring.at_most_one_child(colour) {
            debug_assert!(stack.is_empty(), "a one-child root gets one child");
            self.levels[remaining].start.max(min_id)
        } else {
            min_id
        };
        for c in start..end {
            let child = &self.trees[c];
            if !self.colouring.allows_child(colour, child.colour) {
                continue;
            }
            let oc = child.order;
            stack.push(c);
            if oc == remaining {
                self.push(n, colour, stack.clone(), Some((prefix, c)));
            } else {
                let next = self.index[&(colour, stack.clone())];
                self.children_dfs(n, colour, remaining - oc, c, next, stack);
            }
            stack.pop();
        }
    }

    fn push(
        &mut self,
        order: usize,
        colour: Colour,
        children: Vec<TreeId>,
        split: Option<(TreeId, TreeId)>,
    ) {
        let mut sigma: u64 = 1;
        let mut gamma = order as u64;
        let mut i = 0;
        while i < children.len() {
            let c = &self.trees[children[i]];
            let run = children[i..]
                .iter()
                .take_while(|&&d| d == children[i])
                .count();
            for k in 1..=run as u64 {
                sigma *= k * c.sigma;
                gamma *= c.gamma;
            }
            i += run;
        }
        let id = self.trees.len();
        self.index.insert((colour, children.clone()), id);
        self.trees.push(Tree {
            order,
            colour,
            children,
            sigma,
            gamma,
            split,
        });
    }
}

/// `n` in superscript digits.
fn superscript(n: usize) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    n.to_string()
        .bytes()
        .map(|b| DIGITS[(b - b'0') as usize])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Counts of rooted trees (per root colour) by the Euler transform: `a(n+1) = (1/n) Σ_{j=1..n} s(j) a(n+1−j)`
    /// where `s(j) = Σ_{d|j} d·c(d)` and `c(d)` is the number of admissible
    /// child trees of order `d`. Independent of the generator.
    fn euler_counts(max: usize, child_counts: impl Fn(usize, &[u64]) -> u64) -> Vec<u64> {
        // a[n]: trees of order n per root colour (all colours alike here).
        let mut a = vec![0u64; max + 1];
        a[1] = 1;
        // b[n]: the number of child multisets of total order n (Euler transform).
        let mut b = vec![0u64; max + 1];
        b[0] = 1;
        for n in 1..max {
            let c: Vec<u64> = (0..=n)
                .map(|d| if d == 0 { 0 } else { child_counts(d, &a) })
                .collect();
            let mut sum = 0u64;
            for j in 1..=n {
                let s: u64 = (1..=j)
                    .filter(|d| j % d == 0)
                    .map(|d| d as u64 * c[d])
                    .sum();
                sum += s * b[n - j];
            }
            b[n] = sum / n as u64;
            a[n + 1] = b[n];
        }
        a
    }

    const A000081: [usize; 10] = [1, 1, 2, 4, 9, 20, 48, 115, 286, 719];
    const A000151: [usize; 10] = [2, 4, 14, 52, 214, 916, 4116, 18996, 89894, 433196];

    #[test]
    fn plain_counts_match_a000081() {
        let f = Forest::new(Colouring::Plain, 10);
        let counts: Vec<usize> = (1..=10).map(|n| f.count(n)).collect();
        assert_eq!(counts, A000081);
        let euler = euler_counts(10, |d, a| a[d]);
        assert_eq!(
            euler[1..].iter().map(|&x| x as usize).collect::<Vec<_>>(),
            A000081
        );
    }

    #[test]
    fn bicoloured_counts_match_a000151() {
        // Per root colour the count is A000151/2; children of either colour.
        let euler = euler_counts(10, |d, a| 2 * a[d]);
        let twice: Vec<usize> = euler[1..].iter().map(|&x| 2 * x as usize).collect();
        assert_eq!(twice, A000151);
        let f = Forest::new(Colouring::Bicoloured, 8);
        let counts: Vec<usize> = (1..=8).map(|n| f.count(n)).collect();
        assert_eq!(counts, A000151[..8]);
    }

    #[test]
    fn separable_counts_are_twice_a000081() {
        let f = Forest::new(Colouring::Separable, 10);
        let counts: Vec<usize> = (1..=10).map(|n| f.count(n)).collect();
        let twice: Vec<usize> = A000081.iter().map(|x| 2 * x).collect();
        assert_eq!(counts, twice);
        for id in 0..f.len() {
            let t = f.tree(id);
            for &c in &t.children {
                assert_ne!(f.tree(c).colour, t.colour);
            }
        }
    }

    /// Whether a tree of the Separable forest has every black vertex with at
    /// most one child: brute force, vertex by vertex.
    fn black_vertices_have_one_child(f: &Forest, id: TreeId) -> bool {
        let t = f.tree(id);
        (t.colour != Colour::Q || t.children.len() <= 1)
            && t.children
                .iter()
                .all(|&c| black_vertices_have_one_child(f, c))
    }

    /// The RKN counts: per order, (white roots, black roots), by the
    /// recurrence `Q₁ = 1`, `Qₙ = Pₙ₋₁`, `Pₙ` = the Euler transform of `Q` at
    /// `n − 1` (multisets of black subtrees).
    fn nystrom_recurrence(max: usize) -> Vec<(u64, u64)> {
        let mut p = vec![0u64; max + 1];
        let mut q = vec![0u64; max + 1];
        p[1] = 1;
        q[1] = 1;
        for n in 2..=max {
            q[n] = p[n - 1];
            // b[m]: multisets of black subtrees of total order m.
            let m = n - 1;
            let mut b = vec![0u64; m + 1];
            b[0] = 1;
            for k in 1..=m {
                let mut sum = 0;
                for j in 1..=k {
                    let s: u64 = (1..=j)
                        .filter(|d| j % d == 0)
                        .map(|d| d as u64 * q[d])
                        .sum();
                    sum += s * b[k - j];
                }
                b[k] = sum / k as u64;
            }
            p[n] = b[m];
        }
        (1..=max).map(|n| (p[n], q[n])).collect()
    }

    #[test]
    fn nystrom_trees_are_the_separable_trees_with_one_child_per_black_vertex() {
        let max = 10;
        let nystrom = Forest::new(Colouring::Nystrom, max);
        let separable = Forest::new(Colouring::Separable, max);
        let recurrence = nystrom_recurrence(max);
        let mut totals = Vec::new();
        for n in 1..=max {
            // The same trees, in the same canonical order, with the same σ, γ.
            let filtered: Vec<(String, u64, u64)> = separable
                .conditions(n)
                .filter(|&id| black_vertices_have_one_child(&separable, id))
                .map(|id| {
                    (
                        separable.bracket(id),
                        separable.tree(id).sigma,
                        separable.tree(id).gamma,
                    )
                })
                .collect();
            let generated: Vec<(String, u64, u64)> = nystrom
                .conditions(n)
                .map(|id| {
                    (
                        nystrom.bracket(id),
                        nystrom.tree(id).sigma,
                        nystrom.tree(id).gamma,
                    )
                })
                .collect();
            assert_eq!(generated, filtered, "order {n}");
            let per_root = |colour| {
                nystrom
                    .conditions(n)
                    .filter(|&id| nystrom.tree(id).colour == colour)
                    .count() as u64
            };
            assert_eq!(
                (per_root(Colour::P), per_root(Colour::Q)),
                recurrence[n - 1]
            );
            totals.push(nystrom.count(n));
        }
        // The counts quoted for Runge–Kutta–Nyström methods (Hairer–Nørsett–
        // Wanner I, II.14): the conditions on y' (white roots) number 1, 1, 2,
        // 3, 6, 10, 20, 36, 72, 137 by order, those on y (black roots) the
        // same shifted by one. The filter and the recurrence above derive
        // them independently of the generator.
        let white: Vec<u64> = recurrence.iter().map(|r| r.0).collect();
        assert_eq!(white, [1, 1, 2, 3, 6, 10, 20, 36, 72, 137]);
        assert_eq!(totals, [2, 2, 3, 5, 9, 16, 30, 56, 108, 209]);
        let three: Vec<String> = nystrom
            .conditions(3)
            .map(|id| nystrom.bracket(id))
            .collect();
        assert_eq!(three, ["[[τ_q]_p]_q", "[τ_q²]_p", "[[τ_p]_q]_p"]);
        for id in 0..nystrom.len() {
            let t = nystrom.tree(id);
            if t.colour == Colour::Q {
                assert!(t.children.len() <= 1, "{}", nystrom.bracket(id));
            }
        }
        // Further out, the recurrence (the doc comment's sequences).
        let far = nystrom_recurrence(12);
        let f12 = Forest::new(Colouring::Nystrom, 12);
        assert_eq!(f12.count(11), 412);
        assert_eq!(f12.count(12), 816);
        assert_eq!(far[11], (541, 275));
    }

    #[test]
    fn time_leaf_counts_match_the_euler_transform() {
        // Children: ordinary subtrees, plus the time leaf at order 1.
        let euler = euler_counts(9, |d, a| a[d] + u64::from(d == 1));
        let f = Forest::new(Colouring::TimeLeaves, 9);
        let counts: Vec<u64> = (1..=9).map(|n| f.count(n) as u64).collect();
        assert_eq!(counts, euler[1..]);
        assert_eq!(counts[..4], [1, 2, 5, 13]);
        for id in 0..f.len() {
            let t = f.tree(id);
            if t.colour == Colour::T {
                assert!(t.is_leaf());
            }
        }
    }

    fn factorial(n: u64) -> u64 {
        (1..=n).product()
    }

    /// `Σ n!/σ(t)` counts labelled trees: `n^(n−1)` rooted labelled trees, times
    /// `kⁿ` colourings; `Σ n!/(σ(t)γ(t)) = (n−1)!·kⁿ` (the number of monotone
    /// labellings summed over trees).
    #[test]
    fn symmetry_and_density_sum_rules() {
        for (colouring, k) in [(Colouring::Plain, 1u64), (Colouring::Bicoloured, 2)] {
            let f = Forest::new(colouring, 8);
            for n in 1..=8u64 {
                let fact = factorial(n);
                let mut labelled = 0;
                let mut monotone = 0;
                for id in f.conditions(n as usize) {
                    let t = f.tree(id);
                    assert_eq!(fact % t.sigma, 0);
                    labelled += fact / t.sigma;
                    monotone += fact / (t.sigma * t.gamma);
                    assert_eq!(fact % (t.sigma * t.gamma), 0);
                }
                assert_eq!(labelled, k.pow(n as u32) * n.pow(n as u32 - 1));
                assert_eq!(monotone, k.pow(n as u32) * factorial(n - 1));
            }
        }
        let f = Forest::new(Colouring::Separable, 8);
        for n in 1..=8u64 {
            let labelled: u64 = f
                .conditions(n as usize)
                .map(|id| factorial(n) / f.tree(id).sigma)
                .sum();
            assert_eq!(labelled, 2 * n.pow(n as u32 - 1));
        }
    }

    #[test]
    fn small_trees_in_canonical_order() {
        let f = Forest::new(Colouring::Plain, 5);
        let table: Vec<(String, u64, u64)> = (1..=4)
            .flat_map(|n| f.conditions(n).collect::<Vec<_>>())
            .map(|id| (f.bracket(id), f.tree(id).sigma, f.tree(id).gamma))
            .collect();
        let expected = [
            ("τ", 1, 1),
            ("[τ]", 1, 2),
            ("[τ²]", 2, 3),
            ("[[τ]]", 1, 6),
            ("[τ³]", 6, 4),
            ("[τ,[τ]]", 1, 8),
            ("[[τ²]]", 2, 12),
            ("[[[τ]]]", 1, 24),
        ];
        let expected: Vec<(String, u64, u64)> = expected
            .iter()
            .map(|&(s, a, b)| (s.to_string(), a, b))
            .collect();
        assert_eq!(table, expected);
        let five: Vec<(String, u64)> = f
            .conditions(5)
            .map(|id| (f.bracket(id), f.tree(id).gamma))
            .collect();
        assert_eq!(five.len(), 9);
        assert_eq!(five[0], ("[τ⁴]".to_string(), 5));
        assert!(five.contains(&("[[τ]²]".to_string(), 20)));
        assert_eq!(five[8], ("[[[[τ]]]]".to_string(), 120));
        let bushy = Forest::new(Colouring::Plain, 12);
        let b = bushy.conditions(12).next().unwrap();
        assert_eq!(bushy.bracket(b), "[τ¹¹]");
        assert_eq!(bushy.tree(b).sigma, factorial(11));
    }

    #[test]
    fn coloured_brackets() {
        let f = Forest::new(Colouring::Bicoloured, 3);
        let two: Vec<String> = f.conditions(2).map(|id| f.bracket(id)).collect();
        assert_eq!(two, ["[τ_q]_q", "[τ_p]_q", "[τ_q]_p", "[τ_p]_p"]);
        assert!(f.conditions(3).any(|id| f.bracket(id) == "[τ_p²]_q"));
        assert!(f.conditions(3).any(|id| f.bracket(id) == "[τ_q,τ_p]_q"));
        let t = Forest::new(Colouring::TimeLeaves, 3);
        let three: Vec<String> = t.conditions(3).map(|id| t.bracket(id)).collect();
        assert_eq!(three, ["[τ²]", "[τ,τ_t]", "[τ_t²]", "[[τ]]", "[[τ_t]]"]);
        let s = Forest::new(Colouring::Separable, 3);
        let three: Vec<String> = s.conditions(3).map(|id| s.bracket(id)).collect();
        assert_eq!(
            three,
            ["[τ_p²]_q", "[[τ_q]_p]_q", "[τ_q²]_p", "[[τ_p]_q]_p"]
        );
    }

    #[test]
    fn extension_keeps_ids_and_splits_are_consistent() {
        for colouring in [Colouring::Bicoloured, Colouring::Nystrom] {
            extension_keeps_ids_and_splits(colouring);
        }
    }

    fn extension_keeps_ids_and_splits(colouring: Colouring) {
        let mut f = Forest::new(colouring, 4);
        let before: Vec<String> = (0..f.len()).map(|id| f.bracket(id)).collect();
        f.extend_to(6);
        let after: Vec<String> = (0..before.len()).map(|id| f.bracket(id)).collect();
        assert_eq!(before, after);
        for id in 0..f.len() {
            let t = f.tree(id);
            if let Some((p, c)) = t.split_last() {
                let prefix = f.tree(p);
                assert_eq!(prefix.colour, t.colour);
                assert_eq!(prefix.order + f.tree(c).order, t.order);
                assert_eq!(&t.children[..t.children.len() - 1], &prefix.children[..]);
                assert_eq!(*t.children.last().unwrap(), c);
            } else {
                assert!(t.is_leaf());
            }
        }
    }

    #[test]
    fn order_ten_is_cheap() {
        let start = std::time::Instant::now();
        let f = Forest::new(Colouring::Plain, 10);
        let s = Forest::new(Colouring::Separable, 10);
        assert_eq!(f.count(10), 719);
        assert_eq!(s.count(10), 1438);
        // Not a timing assertion (speed belongs in benchmarks); a sanity print.
        eprintln!("order-10 forests in {:?}", start.elapsed());
    }
}
