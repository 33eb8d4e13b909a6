//! The table types: a Runge–Kutta table, a partitioned pair, a drift–kick
//! sequence and a symmetric composition of Störmer–Verlet. All entries are
//! exact [`Number`]s. Every form converts to the partitioned form, so the
//! symplecticity and order analyses run on one representation; the forms are
//! kept because each has a sharper analysis of its own (a drift–kick sequence
//! is symplectic by construction; a composition has far fewer order
//! conditions).

use crate::Number;
use crate::budget::{MAX_ENTRY_BITS, MAX_STAGES};

/// A Runge–Kutta table `(A, b, c)`. `c` is `None` when the author did not give
/// it; the analyses then use the row sums of `A`.
#[derive(Clone, Debug, PartialEq)]
pub struct Rk {
    pub a: Vec<Vec<Number>>,
    pub b: Vec<Number>,
    pub c: Option<Vec<Number>>,
}

/// A partitioned Runge–Kutta pair: `(A, b, c)` is applied to `q` (it weights
/// evaluations of `q' = ∂H/∂p`), `(Â, b̂, ĉ)` to `p` (evaluations of
/// `p' = −∂H/∂q`), as in Hairer–Lubich–Wanner, *Geometric Numerical
/// Integration*, II.2.
#[derive(Clone, Debug, PartialEq)]
pub struct Prk {
    pub q: Rk,
    pub p: Rk,
}

/// A drift–kick sequence for separable `H = T(p) + V(q)`:
/// `D(d₁) K(k₁) D(d₂) K(k₂) …`, where a drift `D(d)` is `q ← q + d·h·∇T(p)` and
/// a kick `K(k)` is `p ← p − k·h·∇V(q)`. With one more drift than kicks the
/// sequence starts and ends with a drift; with one more kick than drifts it
/// starts and ends with a kick; with equally many it starts with a drift.
///
/// `gradient` (empty for the plain kicks above, else one entry per kick)
/// makes kick `i` a *gradient kick* (a modified kick): the exact flow of
/// `kᵢ·h·B + gᵢ·h³·[B,[A,B]]`, with `A = T` the drifted part and `B = V`
/// the kicked one. For `T = pᵀM⁻¹p/2` and `B` a function of `q` alone,
/// `{V,{T,V}} = −|∇V|²_{M⁻¹}`, so it is the kick of the modified potential
/// `kᵢ·V − gᵢ·h²·|∇V|²_{M⁻¹}` (Wisdom, Holman & Touma 1996; the
/// force-gradient kicks of Chin and of Omelyan). Such a sequence has no
/// partitioned Runge–Kutta form: its analyses are the Lie-algebraic ones of
/// [`crate::near_integrable`].
#[derive(Clone, Debug, PartialEq)]
pub struct Splitting {
    pub drift: Vec<Number>,
    pub kick: Vec<Number>,
    pub gradient: Vec<Number>,
}

/// A composition `Φ_{γₘh} ∘ … ∘ Φ_{γ₁h}` of the Störmer–Verlet method
/// (drift–kick–drift), a symmetric method of order 2.
#[derive(Clone, Debug, PartialEq)]
pub struct Composition {
    pub gamma: Vec<Number>,
}

/// Any of the four forms.
#[derive(Clone, Debug, PartialEq)]
pub enum Table {
    Rk(Rk),
    Prk(Prk),
    Splitting(Splitting),
    Composition(Composition),
}

impl Rk {
    pub fn stages(&self) -> usize {
        self.b.len()
    }

    /// The abscissae: the given `c`, or the row sums of `A`.
    pub fn abscissae(&self) -> Vec<Number> {
        match &self.c {
            Some(c) => c.clone(),
            None => self.row_sums(),
        }
    }

    pub fn row_sums(&self) -> Vec<Number> {
        self.a
            .iter()
            .map(|row| row.iter().fold(Number::zero(), |acc, x| acc + x))
            .collect()
    }
}

impl Splitting {
    /// A drift–kick sequence of plain kicks (no gradient kicks).
    pub fn new(drift: Vec<Number>, kick: Vec<Number>) -> Self {
        Splitting {
            drift,
            kick,
            gradient: Vec::new(),
        }
    }

    /// Whether some kick is a gradient kick (a nonzero `gradient` entry).
    pub fn has_gradient(&self) -> bool {
        self.gradient.iter().any(|g| !g.is_zero())
    }

    /// The flows in the order applied, each `(op, coefficient, gradient)`,
    /// zeros dropped and neighbours merged where that is exact: two drifts,
    /// or two plain kicks (gradient zero). A gradient kick is never merged
    /// with a neighbouring kick (`B` and `[B,[A,B]]` do not commute), and a
    /// kick is dropped only when both its coefficient and gradient are zero.
    /// For a sequence of plain kicks this is [`Splitting::normal_form`] with a
    /// zero gradient on every flow.
    pub fn flows(&self) -> Vec<(Op, Number, Number)> {
        let mut kicks = 0;
        let mut out: Vec<(Op, Number, Number)> = Vec::new();
        for (op, x) in self.ops() {
            let g = match op {
                Op::Drift => Number::zero(),
                Op::Kick => {
                    kicks += 1;
                    self.gradient
                        .get(kicks - 1)
                        .cloned()
                        .unwrap_or_else(Number::zero)
                }
            };
            if x.is_zero() && g.is_zero() {
                continue;
            }
            match out.last_mut() {
                Some((last, y, h)) if *last == op && h.is_zero() && g.is_zero() => {
                    *y += &x;
                    if y.is_zero() {
                        out.pop();
                    }
                }
                _ => out.push((op, x, g)),
            }
        }
        out
    }

    /// The alternating sequence of operations, zeros dropped and neighbours of
    /// the same kind merged: the normal form in which two sequences define the
    /// same map for every separable `H` exactly when they are equal. It does
    /// not know gradient kicks: for a sequence with them
    /// ([`Splitting::has_gradient`]) use [`Splitting::flows`].
    pub fn normal_form(&self) -> Vec<(Op, Number)> {
        let mut out: Vec<(Op, Number)> = Vec::new();
        for (op, x) in self.ops() {
            if x.is_zero() {
                continue;
            }
            match out.last_mut() {
                Some((last, y)) if *last == op => {
                    *y += &x;
                    if y.is_zero() {
                        out.pop();
                    }
                }
                _ => out.push((op, x)),
            }
        }
        out
    }

    /// The operations in the order they are applied.
    pub fn ops(&self) -> Vec<(Op, Number)> {
        let kick_first = self.kick.len() == self.drift.len() + 1;
        let mut out = Vec::with_capacity(self.drift.len() + self.kick.len());
        let (first, second, op1, op2) = if kick_first {
            (&self.kick, &self.drift, Op::Kick, Op::Drift)
        } else {
            (&self.drift, &self.kick, Op::Drift, Op::Kick)
        };
        for i in 0..first.len().max(second.len()) {
            if let Some(x) = first.get(i) {
                out.push((op1, x.clone()));
            }
            if let Some(x) = second.get(i) {
                out.push((op2, x.clone()));
            }
        }
        out
    }

    /// The stages of the equivalent pair ([`Splitting::to_prk`]): one per
    /// drift, counting a zero drift padded before a leading kick.
    pub fn stages(&self) -> usize {
        if self.kick.len() == self.drift.len() + 1 {
            self.drift.len() + 1
        } else {
            self.drift.len()
        }
    }

    /// The equivalent explicit partitioned pair (HLW II.5): stage `i` is the
    /// state after the `i`-th drift; the `q` table has `aᵢⱼ = dⱼ` for `j ≤ i`,
    /// the `p` table `âᵢⱼ = kⱼ` for `j < i`, and `b = d`, `b̂ = k`.
    ///
    /// A sequence with gradient kicks has no such pair: this is the pair of
    /// its plain kicks only, and every analysis of a [`Table`] refuses to
    /// use it for such a sequence ([`Table::to_prk`] is `None`).
    pub fn to_prk(&self) -> Prk {
        // Bring the sequence to the form D K D K … D [K]: pad a leading zero
        // drift if it starts with a kick, and a trailing zero kick as needed.
        let mut drift = self.drift.clone();
        let mut kick = self.kick.clone();
        if kick.len() == drift.len() + 1 {
            drift.insert(0, Number::zero());
        }
        let s = drift.len();
        kick.resize(s, Number::zero());
        let zero_row = || vec![Number::zero(); s];
        let mut a = vec![zero_row(); s];
        let mut a_hat = vec![zero_row(); s];
        for i in 0..s {
            for j in 0..s {
                if j <= i {
                    a[i][j] = drift[j].clone();
                }
                if j < i {
                    a_hat[i][j] = kick[j].clone();
                }
            }
        }
        Prk {
            q: Rk {
                a,
                b: drift,
                c: None,
            },
            p: Rk {
                a: a_hat,
                b: kick,
                c: None,
            },
        }
    }
}

/// A drift or a kick.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    Drift,
    Kick,
}

impl Composition {
    /// The drift–kick sequence: Verlet `D(γ/2) K(γ) D(γ/2)` per factor, with
    /// the drifts of neighbouring factors merged.
    pub fn to_splitting(&self) -> Splitting {
        let m = self.gamma.len();
        let two = Number::from(2);
        let half = |x: &Number| x.checked_div(&two).expect("2 is not zero");
        let mut drift = Vec::with_capacity(m + 1);
        for k in 0..=m {
            let left = if k > 0 {
                half(&self.gamma[k - 1])
            } else {
                Number::zero()
            };
            let right = if k < m {
                half(&self.gamma[k])
            } else {
                Number::zero()
            };
            drift.push(left + right);
        }
        Splitting {
            drift,
            kick: self.gamma.clone(),
            gradient: Vec::new(),
        }
    }
}

impl Table {
    /// The number of stages of the equivalent (partitioned) Runge–Kutta form.
    pub fn stages(&self) -> usize {
        match self {
            Table::Rk(rk) => rk.stages(),
            Table::Prk(prk) => prk.q.stages(),
            Table::Splitting(s) => s.stages(),
            Table::Composition(c) => c.gamma.len() + 1,
        }
    }

    /// The partitioned form, if the table is not a plain Runge–Kutta table
    /// and has one: a drift–kick sequence with gradient kicks has none.
    pub fn to_prk(&self) -> Option<Prk> {
        match self {
            Table::Rk(_) => None,
            Table::Prk(prk) => Some(prk.clone()),
            Table::Splitting(s) if s.has_gradient() => None,
            Table::Splitting(s) => Some(s.to_prk()),
            Table::Composition(c) => Some(c.to_splitting().to_prk()),
        }
    }
}

/// A table whose dimensions do not fit, with the field that is wrong.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{field}: {message}")]
pub struct ShapeError {
    /// The offending field as the author wrote it: `a`, `a[2]`, `b_hat`, `kick`…
    pub field: String,
    pub message: String,
}

fn shape_err(field: impl Into<String>, message: impl Into<String>) -> ShapeError {
    ShapeError {
        field: field.into(),
        message: message.into(),
    }
}

/// Refuse a table beyond [`MAX_STAGES`].
fn too_many_stages(field: &str, what: &str, stages: usize) -> Result<(), ShapeError> {
    if stages > MAX_STAGES {
        return Err(shape_err(
            field,
            format!(
                "{what} has {stages} stages; the exact analysis takes at most {MAX_STAGES} stages (tableau::budget::MAX_STAGES)"
            ),
        ));
    }
    Ok(())
}

impl Rk {
    /// `A` square `s × s` with `s ≥ 1`, `b` and `c` of length `s`. `suffix` is
    /// `""` for the plain table and `"_hat"` for the second table of a pair.
    pub fn check_shape(&self, suffix: &str) -> Result<(), ShapeError> {
        let s = self.a.len();
        if s == 0 {
            return Err(shape_err(format!("a{suffix}"), "the table has no stages"));
        }
        too_many_stages(&format!("a{suffix}"), "the table", s)?;
        for (i, row) in self.a.iter().enumerate() {
            if row.len() != s {
                return Err(shape_err(
                    format!("a{suffix}[{i}]"),
                    format!(
                        "A must be square: row {i} has {} entries, but A has {s} rows",
                        row.len()
                    ),
                ));
            }
        }
        if self.b.len() != s {
            return Err(shape_err(
                format!("b{suffix}"),
                format!("b has {} entries, but A has {s} stages", self.b.len()),
            ));
        }
        if let Some(c) = self.c.as_ref().filter(|c| c.len() != s) {
            return Err(shape_err(
                format!("c{suffix}"),
                format!("c has {} entries, but A has {s} stages", c.len()),
            ));
        }
        Ok(())
    }
}

/// Refuse entries beyond [`MAX_ENTRY_BITS`].
fn entries_fit(field: &str, entries: &[Number]) -> Result<(), ShapeError> {
    for (i, x) in entries.iter().enumerate() {
        let bits = x.size_bits();
        if bits > MAX_ENTRY_BITS {
            return Err(shape_err(
                format!("{field}[{i}]"),
                format!(
                    "the entry is a {bits}-bit number; the exact analysis takes entries of at most {MAX_ENTRY_BITS} bits (tableau::budget::MAX_ENTRY_BITS)"
                ),
            ));
        }
    }
    Ok(())
}

impl Table {
    /// The form's name in listings and JSON: `"rk"`, `"prk"`,
    /// `"drift-kick"`, `"gradient-drift-kick"` or `"composition"`.
    pub fn form_name(&self) -> &'static str {
        match self {
            Table::Rk(_) => "rk",
            Table::Prk(_) => "prk",
            Table::Splitting(s) if s.has_gradient() => "gradient-drift-kick",
            Table::Splitting(_) => "drift-kick",
            Table::Composition(_) => "composition",
        }
    }

    /// Dimensions that fit together, and entries within
    /// [`MAX_ENTRY_BITS`]; every analysis assumes this.
    pub fn check_shape(&self) -> Result<(), ShapeError> {
        self.check_dimensions()?;
        let rk = |t: &Rk, suffix: &str| -> Result<(), ShapeError> {
            for (i, row) in t.a.iter().enumerate() {
                entries_fit(&format!("a{suffix}[{i}]"), row)?;
            }
            entries_fit(&format!("b{suffix}"), &t.b)?;
            if let Some(c) = &t.c {
                entries_fit(&format!("c{suffix}"), c)?;
            }
            Ok(())
        };
        match self {
            Table::Rk(t) => rk(t, ""),
            Table::Prk(p) => rk(&p.q, "").and_then(|()| rk(&p.p, "_hat")),
            Table::Splitting(s) => entries_fit("drift", &s.drift)
                .and_then(|()| entries_fit("kick", &s.kick))
                .and_then(|()| entries_fit("kick_gradient", &s.gradient)),
            Table::Composition(c) => entries_fit("compose", &c.gamma),
        }?;
        // The order analyses compute over the common denominator of all
        // entries (fraction-free), so it is bounded too.
        let all: Vec<&Number> = match self {
            Table::Rk(t) => t.a.iter().flatten().chain(&t.b).collect(),
            Table::Prk(p) => [&p.q, &p.p]
                .into_iter()
                .flat_map(|t| t.a.iter().flatten().chain(&t.b))
                .collect(),
            Table::Splitting(s) => s.drift.iter().chain(&s.kick).chain(&s.gradient).collect(),
            Table::Composition(c) => c.gamma.iter().collect(),
        };
        let bits = crate::number::common_denominator_bits(all);
        if bits > MAX_ENTRY_BITS {
            let field = match self {
                Table::Splitting(_) => "drift",
                Table::Composition(_) => "compose",
                _ => "a",
            };
            return Err(shape_err(
                field,
                format!(
                    "the entries' common denominator has {bits} bits; the exact analysis takes at most {MAX_ENTRY_BITS} (tableau::budget::MAX_ENTRY_BITS): so many unrelated denominators are beyond its budget"
                ),
            ));
        }
        Ok(())
    }

    fn check_dimensions(&self) -> Result<(), ShapeError> {
        match self {
            Table::Rk(rk) => rk.check_shape(""),
            Table::Prk(prk) => {
                prk.q.check_shape("")?;
                // Â's size before b̂'s length: a 3×3 `a_hat` beside a 2×2 `a`
                // is the culprit, not a `b_hat` of length 2.
                let s = prk.q.stages();
                if prk.p.a.len() != s {
                    return Err(shape_err(
                        "a_hat",
                        format!(
                            "the pair must have as many stages in both tables: a is {s}×{s}, but a_hat has {} rows",
                            prk.p.a.len()
                        ),
                    ));
                }
                prk.p.check_shape("_hat")?;
                Ok(())
            }
            Table::Splitting(s) => {
                let (d, k) = (s.drift.len(), s.kick.len());
                if d == 0 && k == 0 {
                    return Err(shape_err("drift", "the sequence is empty"));
                }
                let what = format!("the drift–kick sequence ({d} drifts, {k} kicks)");
                too_many_stages("drift", &what, s.stages())?;
                if d.abs_diff(k) > 1 {
                    return Err(shape_err(
                        "kick",
                        format!(
                            "drifts and kicks alternate, so their counts differ by at most one: {d} drifts, {k} kicks"
                        ),
                    ));
                }
                let g = s.gradient.len();
                if g != 0 && g != k {
                    return Err(shape_err(
                        "kick_gradient",
                        format!(
                            "kick_gradient has {g} entries, but there are {k} kicks: one gradient per kick (0 for a plain kick)"
                        ),
                    ));
                }
                Ok(())
            }
            Table::Composition(c) => {
                if c.gamma.is_empty() {
                    return Err(shape_err("compose", "the composition is empty"));
                }
                let what = format!("the composition ({} entries)", c.gamma.len());
                too_many_stages("compose", &what, c.gamma.len() + 1)?;
                Ok(())
            }
        }
    }
}
