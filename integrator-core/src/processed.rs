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
//! use integrator_core::processed::{self, Processed};
//! use integrator_core::sequence::Sequence;
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

use crate::sequence::Sequence;

/// Stepping a [`Sequence`] on a [`Split`] system: flow by flow, or `n`
/// steps with the flows at the steps' seams merged.
impl Sequence {
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
