//! Processed methods: a kernel `K` (a drift–kick sequence or composition)
//! with a corrector `χ` (a drift–kick sequence, its coefficients typically
//! summing to zero), stepped as `χ Kⁿ χ⁻¹` (Wisdom, Holman & Touma 1996,
//! "symplectic correctors"; Blanes–Casas processing).
//!
//! `χ⁻¹` is applied once, on entry; the kernel every step, to the carried
//! state; `χ` only at output, to a copy — never to the carried state. Since
//! `χ Kⁿ χ⁻¹ = (χ K χ⁻¹)ⁿ`, every output is exactly what `n` steps of the
//! one method `χ K χ⁻¹` give, so its errors are that method's: the
//! *effective* orders `tableau` decides
//! ([`tableau::near_integrable::processed_orders`]), while a step costs what
//! the kernel's costs. This module is the one place that does it: a
//! processed scheme ([`Processed`]) steps any [`Split`] system, with a
//! kernel that is a `butcher!` scheme (e.g. [`crate::library::Leapfrog`])
//! or a sequence read at run time ([`Sequence`]), and [`integrate`] runs it.
//!
//! The corrector's flows are those of the split system for the times `cᵢh`,
//! `h` the kernel's step; its coefficients are doubles (the nearest to the
//! exact values of the table file that proved the orders). `χ⁻¹` is `χ`'s
//! sequence reversed with every coefficient negated: the inverse exactly
//! where the flows are exact (`φ_{−x} = φ_x⁻¹`), so `χ` after `χ⁻¹` returns
//! the state to round-off.
//!
//! ```
//! use integrator_core::library::Leapfrog;
//! use integrator_core::processed::{self, Processed, Sequence};
//! use integrator_core::split::{FlowError, PartBuffers, Split, StateSpace};
//!
//! /// `H = (q² + p²)/2 + εq`: a rotation and a constant kick.
//! struct Forced(f64);
//! impl StateSpace for Forced {
//!     fn state_len(&self) -> usize { 2 }
//! }
//! impl Split for Forced {
//!     fn flow_a(&self, h: f64, z: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
//!         let (s, c) = h.sin_cos();
//!         let (q, p) = (z[0], z[1]);
//!         z[0] = c * q + s * p;
//!         z[1] = c * p - s * q;
//!         Ok(())
//!     }
//!     fn flow_b(&self, h: f64, z: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
//!         z[1] -= h * self.0;
//!         Ok(())
//!     }
//! }
//!
//! // The Wisdom–Holman leapfrog with its corrector of order 3: effective
//! // order (4, 2), proven by tableau.
//! let file = tableau::catalogue::load("leapfrog-c3").unwrap();
//! let chi = Sequence::from_splitting(file.corrector.as_ref().unwrap());
//! let method = Processed::new(Leapfrog, chi);
//! let mut z = [1.0, 0.0];
//! processed::integrate(&method, &Forced(0.1), &mut z, 0.0, 0.1, 100, |_, _, _| {}).unwrap();
//! // The exact solution at t = 10: q = −ε + (1 + ε) cos t.
//! assert!((z[0] - (-0.1 + 1.1 * 10f64.cos())).abs() < 1e-7);
//! ```

use crate::error::{SolveError, StepError};
use crate::integrate::check_start;
use crate::scheme::{SplitWorkspace, Step};
use crate::split::{self, Part, PartBuffers, Split};

/// A drift–kick sequence read at run time: the flows in the order applied,
/// each with its coefficient (the time is `coefficient × h`). Used for a
/// corrector, and as a kernel where no `butcher!` scheme exists (it steps
/// any [`Split`] system through [`Step`]; a `butcher!` scheme of the same
/// table unrolls the same calls at compile time).
///
/// A kick may be a gradient kick ([`Split::flow_b_gradient`]): `gradient[i]`
/// is flow `i`'s weight `g` of `h³·[B,[A,B]]` (zero for a plain flow), as in
/// a table's `kick_gradient` ([`tableau::Splitting`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Sequence {
    ops: Vec<(Part, f64)>,
    gradient: Vec<f64>,
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

    /// `n` steps of size `h`, the last flow of each step and the first of
    /// the next applied as one flow for the sum of their times where they
    /// are of the same part ([`merges`](Self::merges)): the same map as `n`
    /// calls of [`apply`](Self::apply) where the flows are exact
    /// (`φ_{a} ∘ φ_{b} = φ_{a+b}`), up to rounding, at one flow less per step.
    /// This is how Wisdom–Holman codes run between outputs (REBOUND's WHFast
    /// with its safe mode off): the state is synchronised only at the end.
    /// The merged coefficient is the sum of the two doubles, rounded once.
    ///
    /// An error carries the step (1-based) in which the failing flow lies.
    pub fn steps_merged<S: Split + ?Sized>(
        &self,
        sys: &S,
        h: f64,
        n: usize,
        z: &mut [f64],
        ws: &mut SplitWorkspace,
    ) -> Result<(), (usize, SolveError)> {
        if n == 0 {
            return Ok(());
        }
        if !self.merges() {
            for k in 0..n {
                self.apply(sys, h, z, ws).map_err(|e| (k + 1, e))?;
            }
            return Ok(());
        }
        let last = self.ops.len() - 1;
        let (part, first_c) = self.ops[0];
        let last_c = self.ops[last].1;
        let merged = first_c + last_c;
        let middle = Sequence {
            ops: self.ops[1..last].to_vec(),
            gradient: self.gradient[1..last].to_vec(),
        };
        flow_in(sys, part, h * first_c, z, ws).map_err(|e| (1, e))?;
        // Drift, kick, drift (Wisdom–Holman's kernels): the system may run
        // the kicks and merged drifts in a loop of its own
        // (`Split::kick_drift_run`, the same bits); a step it does not take
        // is taken flow by flow below.
        let run =
            (part == Part::A && middle.ops.len() == 1 && middle.ops[0].0 == Part::B).then(|| {
                let (c, g) = (middle.ops[0].1, middle.gradient[0]);
                (h * c, if g == 0.0 { 0.0 } else { g * h * h * h })
            });
        let mut k = 0;
        while k < n {
            if let Some((kick, gamma)) = run {
                k += sys.kick_drift_run(kick, gamma, h * merged, h * last_c, n - k, z);
                if k == n {
                    break;
                }
            }
            middle.apply(sys, h, z, ws).map_err(|e| (k + 1, e))?;
            let c = if k + 1 < n { merged } else { last_c };
            flow_in(sys, part, h * c, z, ws).map_err(|e| (k + 1, e))?;
            k += 1;
        }
        Ok(())
    }

    /// `z ← (the sequence for step h)(z)`. The workspace's buffers are the
    /// flows' scratch; nothing is reused from an earlier call.
    pub fn apply<S: Split + ?Sized>(
        &self,
        sys: &S,
        h: f64,
        z: &mut [f64],
        ws: &mut SplitWorkspace,
    ) -> Result<(), SolveError> {
        for (&(part, c), &g) in self.ops.iter().zip(&self.gradient) {
            if g == 0.0 {
                flow_in(sys, part, h * c, z, ws)?;
            } else {
                gradient_in(sys, part, h * c, g * h * h * h, z, ws)?;
            }
        }
        Ok(())
    }
}

/// One flow of `part` for the time `x`, with the workspace's buffers of that
/// part; nothing reused from an earlier flow.
#[inline]
fn flow_in<S: Split + ?Sized>(
    sys: &S,
    part: Part,
    x: f64,
    z: &mut [f64],
    ws: &mut SplitWorkspace,
) -> Result<(), SolveError> {
    let SplitWorkspace {
        v,
        f,
        eq,
        ep,
        compensated,
    } = ws;
    let (eval, err) = match part {
        Part::A => (&mut v[..], &mut eq[..]),
        Part::B => (&mut f[..], &mut ep[..]),
    };
    let buf = PartBuffers {
        eval,
        err,
        compensated: *compensated,
    };
    split::flow(sys, part, x, z, buf, false)
}

/// A gradient kick for the time `x` with bracket weight `gamma`
/// ([`Split::flow_b_gradient`]), with the kick's buffers; a drift with a
/// gradient is refused (tables have gradients on kicks only).
#[inline]
fn gradient_in<S: Split + ?Sized>(
    sys: &S,
    part: Part,
    x: f64,
    gamma: f64,
    z: &mut [f64],
    ws: &mut SplitWorkspace,
) -> Result<(), SolveError> {
    if part == Part::A {
        return Err(SolveError::Flow {
            part,
            source: split::FlowError::failed(
                "a drift has no gradient: a gradient belongs to a kick (the flow of B)",
            ),
        });
    }
    let buf = PartBuffers {
        eval: &mut ws.f[..],
        err: &mut ws.ep[..],
        compensated: ws.compensated,
    };
    split::flow_gradient(sys, x, gamma, z, buf)
}

impl<S: Split + ?Sized> Step<S> for Sequence {
    type Workspace = SplitWorkspace;
    fn workspace(&self, sys: &S) -> SplitWorkspace {
        SplitWorkspace::new(sys.buffer_len())
    }
    fn step(
        &self,
        sys: &S,
        _t: f64,
        h: f64,
        z: &mut [f64],
        ws: &mut SplitWorkspace,
    ) -> Result<(), SolveError> {
        self.apply(sys, h, z, ws)
    }
}

/// A kernel `K` with a corrector `χ`, stepped as `χ Kⁿ χ⁻¹` (see the
/// [module documentation](self)).
#[derive(Clone, Debug)]
pub struct Processed<K> {
    kernel: K,
    corrector: Sequence,
    inverse: Sequence,
}

impl<K> Processed<K> {
    /// `kernel` processed by `corrector` (`χ`, the map applied at output).
    pub fn new(kernel: K, corrector: Sequence) -> Self {
        let inverse = corrector.inverse();
        Processed {
            kernel,
            corrector,
            inverse,
        }
    }

    pub fn kernel(&self) -> &K {
        &self.kernel
    }

    /// `χ`, applied at output.
    pub fn corrector(&self) -> &Sequence {
        &self.corrector
    }

    /// `z ← χ⁻¹(z)`: on entry, once, before the first step of size `h`.
    pub fn enter<S: Split + ?Sized>(
        &self,
        sys: &S,
        h: f64,
        z: &mut [f64],
        ws: &mut SplitWorkspace,
    ) -> Result<(), SolveError> {
        fresh(ws);
        self.inverse.apply(sys, h, z, ws)
    }

    /// `out ← χ(carried)`: the output of the carried state, which is left
    /// as it is (the next step continues from it, not from the output).
    pub fn output<S: Split + ?Sized>(
        &self,
        sys: &S,
        h: f64,
        carried: &[f64],
        out: &mut [f64],
        ws: &mut SplitWorkspace,
    ) -> Result<(), SolveError> {
        out.copy_from_slice(carried);
        fresh(ws);
        self.corrector.apply(sys, h, out, ws)
    }
}

/// Clear the carried rounding errors of a workspace: each application of
/// `χ` or `χ⁻¹` starts from an exact copy, so the errors of an earlier one
/// (of another state) must not be added to it.
fn fresh(ws: &mut SplitWorkspace) {
    ws.eq.fill(0.0);
    ws.ep.fill(0.0);
}

/// [`crate::integrate`] for a processed scheme: `n` steps of size `h` from
/// `z` at `t0`, `observe(k, t, output)` at the start and after every step,
/// each output `χ` of the carried state; on return `z` is the output after
/// the last step. The corrector has its own workspace (separate from the
/// kernel's, whose first-same-as-last evaluation and compensated-summation
/// errors carry on untouched from one step to the next). The carried state
/// starts as `χ⁻¹(z)`, so the first observation is `χ(χ⁻¹(z))`, `z` to
/// round-off.
///
/// Errors as [`crate::integrate`]'s: a failing flow of the kernel, or of
/// `χ` or `χ⁻¹`, is [`StepError::Solve`] at the step whose output it was
/// (step 0 on entry), naming the part.
pub fn integrate<S, K>(
    method: &Processed<K>,
    sys: &S,
    z: &mut [f64],
    t0: f64,
    h: f64,
    n: usize,
    mut observe: impl FnMut(usize, f64, &[f64]),
) -> Result<(), StepError>
where
    S: Split + ?Sized,
    K: Step<S>,
{
    check_start(sys, z, h)?;
    let solve = |step: usize, t: f64| move |source| StepError::Solve { step, t, source };
    let mut corrector_ws = SplitWorkspace::new(sys.buffer_len());
    let mut carried = z.to_vec();
    method
        .enter(sys, h, &mut carried, &mut corrector_ws)
        .map_err(solve(0, t0))?;
    method
        .output(sys, h, &carried, z, &mut corrector_ws)
        .map_err(solve(0, t0))?;
    observe(0, t0, z);
    let mut ws = method.kernel.workspace(sys);
    for k in 0..n {
        let t = t0 + k as f64 * h;
        method
            .kernel
            .step_reusing(sys, t, h, &mut carried, &mut ws, k > 0)
            .map_err(solve(k + 1, t))?;
        let t_next = t0 + (k + 1) as f64 * h;
        method
            .output(sys, h, &carried, z, &mut corrector_ws)
            .map_err(solve(k + 1, t_next))?;
        if let Some(index) = z.iter().position(|x| !x.is_finite()) {
            return Err(StepError::Diverged {
                step: k + 1,
                t: t_next,
                index,
                value: z[index],
            });
        }
        observe(k + 1, t_next, z);
    }
    Ok(())
}
