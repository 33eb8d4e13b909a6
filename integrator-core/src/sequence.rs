//! The one description of a drift–kick sequence, read at run time.
//!
//! A step `D(d₁) K(k₁) D(d₂) …` is a list of flows, each a part of a split
//! Hamiltonian (`A`, the drift; `B`, the kick) with its coefficient (the
//! flow's time is `coefficient × h`), and, for a gradient kick, the weight of
//! `h³·[B,[A,B]]`. Every run-time user of such a step holds this type, so a
//! sequence is built, rounded, reversed and merged in one place:
//!
//! - [`crate::processed`] steps it on any [`Split`](crate::split::Split)
//!   system (a kernel, a corrector, the Wisdom–Holman runs of `compare`,
//!   whose seam-merged loop is [`Sequence::steps_merged`]);
//! - [`crate::interp::SplittingInterpreter`] steps it on a
//!   [`Separable`](crate::Separable) system with the `butcher!` scheme's
//!   arithmetic (its own inner loop, first evaluation reused);
//! - the cloth's banded two-thread stepper applies it to its rows of the
//!   sheet (its own inner loop, in `cloth::step::banded`).
//!
//! Each keeps its own inner loop for speed; what the flows are, how zero
//! coefficients, merged neighbours and the first-same-as-last evaluation are
//! decided, is decided here. The coefficients are doubles: the nearest to
//! the exact values ([`Sequence::from_splitting`]), or rounded as `butcher!`
//! rounds a scheme's weights where bit agreement with the scheme matters
//! ([`SplittingInterpreter::from_table`](crate::interp::SplittingInterpreter::from_table)).

use crate::split::Part;

/// A drift–kick sequence read at run time: the flows in the order applied,
/// each with its coefficient (the time is `coefficient × h`). Used for a
/// corrector, and as a kernel where no `butcher!` scheme exists (it steps
/// any [`Split`](crate::split::Split) system through
/// [`Step`](crate::Step); a `butcher!` scheme of the same
/// table unrolls the same calls at compile time).
///
/// A kick may be a gradient kick ([`Split::flow_b_gradient`](crate::split::Split::flow_b_gradient)): `gradient[i]`
/// is flow `i`'s weight `g` of `h³·[B,[A,B]]` (zero for a plain flow), as in
/// a table's `kick_gradient` ([`tableau::Splitting`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Sequence {
    pub(crate) ops: Vec<(Part, f64)>,
    pub(crate) gradient: Vec<f64>,
}

impl Sequence {
    /// The flows in the order applied; zero coefficients are dropped.
    pub fn new(ops: impl IntoIterator<Item = (Part, f64)>) -> Self {
        let ops: Vec<(Part, f64)> = ops.into_iter().filter(|(_, c)| *c != 0.0).collect();
        let gradient = vec![0.0; ops.len()];
        Sequence { ops, gradient }
    }

    /// Flows with gradients: `(part, coefficient, g)` in the order applied,
    /// `g` the weight of `h³·[B,[A,B]]` of a gradient kick (zero for a plain
    /// flow; a drift with a nonzero `g` is refused when stepped). Plain flows
    /// with a zero coefficient are dropped.
    pub fn with_gradients(ops: impl IntoIterator<Item = (Part, f64, f64)>) -> Self {
        let (ops, gradient) = ops
            .into_iter()
            .filter(|(_, c, g)| *c != 0.0 || *g != 0.0)
            .map(|(p, c, g)| ((p, c), g))
            .unzip();
        Sequence { ops, gradient }
    }

    /// Each flow's gradient weight `g` (zero for a plain flow), beside
    /// [`ops`](Self::ops).
    pub fn gradients(&self) -> &[f64] {
        &self.gradient
    }

    /// Whether some flow is a gradient kick.
    pub fn has_gradient(&self) -> bool {
        self.gradient.iter().any(|g| *g != 0.0)
    }

    /// A table's drift and kick lists, interleaved as a table file writes
    /// them: drift first, unless there is one kick more than drifts.
    pub fn from_lists(drift: &[f64], kick: &[f64]) -> Self {
        let kick_first = kick.len() == drift.len() + 1;
        let (first, second, p1, p2) = if kick_first {
            (kick, drift, Part::B, Part::A)
        } else {
            (drift, kick, Part::A, Part::B)
        };
        let mut ops = Vec::with_capacity(drift.len() + kick.len());
        for i in 0..first.len().max(second.len()) {
            if let Some(&x) = first.get(i) {
                ops.push((p1, x));
            }
            if let Some(&x) = second.get(i) {
                ops.push((p2, x));
            }
        }
        Sequence::new(ops)
    }

    /// An exact drift–kick sequence of `tableau`, each coefficient the
    /// nearest double to its exact value, in its normal form (neighbours of
    /// the same kind merged exactly before rounding).
    ///
    /// With gradient kicks the flows are taken as written, zeros dropped and
    /// plain neighbours of the same kind merged exactly; a gradient kick is
    /// never merged with a plain one (`B` and `[B,[A,B]]` need not commute).
    pub fn from_splitting(s: &tableau::Splitting) -> Self {
        let part = |op| match op {
            tableau::table::Op::Drift => Part::A,
            tableau::table::Op::Kick => Part::B,
        };
        if !s.has_gradient() {
            return Sequence::new(
                s.normal_form()
                    .into_iter()
                    .map(|(op, x)| (part(op), x.to_f64())),
            );
        }
        let zero = tableau::Number::zero();
        let mut kicks = 0;
        let mut merged: Vec<(tableau::table::Op, tableau::Number, tableau::Number)> = Vec::new();
        for (op, x) in s.ops() {
            let g = if op == tableau::table::Op::Kick {
                kicks += 1;
                s.gradient
                    .get(kicks - 1)
                    .cloned()
                    .unwrap_or_else(|| zero.clone())
            } else {
                zero.clone()
            };
            if x.is_zero() && g.is_zero() {
                continue;
            }
            match merged.last_mut() {
                Some((o, y, h)) if *o == op && h.is_zero() && g.is_zero() => *y += &x,
                _ => merged.push((op, x, g)),
            }
        }
        Sequence::with_gradients(
            merged
                .into_iter()
                .map(|(op, x, g)| (part(op), x.to_f64(), g.to_f64())),
        )
    }

    /// The flows, in the order applied.
    pub fn ops(&self) -> &[(Part, f64)] {
        &self.ops
    }

    /// The inverse: the flows reversed, every coefficient negated.
    ///
    /// A gradient kick's inverse is the gradient kick of the negated
    /// coefficient and weight: exactly its inverse where the kick is exact.
    pub fn inverse(&self) -> Sequence {
        Sequence {
            ops: self.ops.iter().rev().map(|&(p, c)| (p, -c)).collect(),
            gradient: self.gradient.iter().rev().map(|g| -g).collect(),
        }
    }

    /// The library's or catalogue's drift–kick sequence or composition
    /// `id` (`tableau::catalogue`), as [`from_splitting`](Self::from_splitting)
    /// gives it (gradient kicks included); `None` for an id that is not one.
    pub fn from_catalogue(id: &str) -> Option<Sequence> {
        match tableau::catalogue::load(id).ok()?.table {
            tableau::Table::Splitting(s) => Some(Sequence::from_splitting(&s)),
            tableau::Table::Composition(c) => Some(Sequence::from_splitting(&c.to_splitting())),
            _ => None,
        }
    }

    /// Whether the last flow of a step and the first of the next are of the
    /// same part, so that [`steps_merged`](Self::steps_merged) saves one flow
    /// per step (the Wisdom–Holman leapfrog `A(h/2) B(h) A(h/2)`: one Kepler
    /// drift per step instead of two).
    /// A gradient kick at either end does not merge.
    pub fn merges(&self) -> bool {
        self.ops.len() >= 2
            && self.ops.first().map(|o| o.0) == self.ops.last().map(|o| o.0)
            && self.gradient.first() == Some(&0.0)
            && self.gradient.last() == Some(&0.0)
    }

    /// The number of flows of `part` in a step.
    pub fn count(&self, part: Part) -> usize {
        self.ops.iter().filter(|o| o.0 == part).count()
    }

    /// The part of the first flow (`None` for the identity).
    pub fn first_part(&self) -> Option<Part> {
        self.ops.first().map(|o| o.0)
    }
}
