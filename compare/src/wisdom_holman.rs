//! Wisdom–Holman methods in a comparison: any splitting of the library (a
//! drift–kick sequence or composition, `symlab list`'s `splittings`) stepped
//! on the Jacobi split `H = H_Kepler + H_interaction` of an N-body problem,
//! drifts as exact Kepler flows and kicks as the interaction
//! ([`integrator_core::problems::wisdom_holman`]). `wh:leapfrog` is the
//! classical Wisdom–Holman map; `wh:ID` for a near-integrable table (SABA,
//! ABA(8,6,4), …) is the method its authors designed.
//!
//! A processed method of the catalogue (a kernel with a corrector `χ`,
//! e.g. `wh:leapfrog-c11`, the Wisdom–Holman map with the corrector of
//! order 11) runs as `χ Kⁿ χ⁻¹` ([`integrator_core::processed`]): `χ⁻¹` on
//! the Jacobi state once after the conversion, `χ` on a copy before each
//! conversion back for an observation (and once at the end of a timed
//! run), never on the carried state. Its kernel is the library's
//! `butcher!` scheme where the file names one (`kernel = "leapfrog"`), else
//! the file's sequence stepped at run time. The row's
//! order is the effective classical order the file claims and `tableau`
//! proves.
//!
//! The timed run steps the method's drift–kick sequence (the catalogue's
//! table of the id, or the processed method's kernel) with the last flow of
//! each step merged with the first of the next
//! ([`Sequence::steps_merged`]): `wh:leapfrog` makes one Kepler drift per
//! step, as Wisdom–Holman codes do between outputs. The observed run (errors,
//! energy, kicks) synchronises after every step, so it steps the `butcher!`
//! scheme unmerged; the two are the same map up to rounding (tested in
//! `tests/wisdom_holman.rs`). A processed method's observed run applies its
//! corrector after every step for the observer, but counts the kicks of the
//! last one only, so its count is the timed run's (χ⁻¹, the kernel's steps,
//! one χ) and compares with a plain method's.
//!
//! The problem's state stays the inertial `z = [x; p]`: a run converts it to
//! Jacobi coordinates before the first step and back for every observation
//! and at the end, so errors are measured as for every other method. The
//! timed run converts twice (start and end), as REBOUND's WHFast does with
//! its safe mode off.
//!
//! A user's N-body problem (inertial state `[x; p]`, body 0 the central
//! mass) gets these methods through one constructor:
//!
//! ```
//! use compare::Method;
//! use integrator_core::problems::OuterSolarSystem;
//! use integrator_core::problems::wisdom_holman::Jacobi;
//!
//! let split = Jacobi::outer_solar(); // or Jacobi::new(G, &masses, names)
//! let m: Method<OuterSolarSystem> = Method::wisdom_holman("wh:kahan-li8", &split).unwrap();
//! assert_eq!(m.id(), "wh:kahan-li8");
//! assert!(Method::<OuterSolarSystem>::wisdom_holman("wh:rk4", &split).is_err());
//! ```

use std::cell::Cell;

use integrator_core::problems::wisdom_holman::{GradientKick, Jacobi, WarmJacobi};
use integrator_core::processed::Processed;
use integrator_core::scheme::SplitWorkspace;
use integrator_core::sequence::Sequence;
use integrator_core::split::{FlowError, PartBuffers, Split, StateSpace};
use integrator_core::{Scheme, Step};

use crate::error::{CompareError, Result};
use crate::interpreted::{VerifiedForm, VerifiedTable};
use crate::method::{Fixed, Method};
use crate::problem::{Family, Problem};
use crate::stepper::{Outcome, Status, Stepper, Workspace};

/// The prefix of the Wisdom–Holman method ids.
pub const PREFIX: &str = "wh:";

/// The timed run of a `wh:` row: converted in, `χ⁻¹` (the identity for a
/// plain splitting), `n` steps of the kernel's sequence merged across steps,
/// `χ`, converted out — as REBOUND's WHFast with its safe mode off.
fn bare_merged(
    split: &Jacobi,
    method: &Processed<Sequence>,
    z: &mut [f64],
    h: f64,
    n: usize,
) -> bool {
    let mut w = vec![0.0; z.len()];
    if split.from_inertial(z, &mut w).is_err() {
        return false;
    }
    // With the warm start on, the run's own history of Kepler roots (see
    // `WarmJacobi`); off (the default), the split itself, so that the
    // default run is the code it was before the warm start existed.
    let stepped = if split.kepler_warm_start() {
        steps(&WarmJacobi::new(split), method, &mut w, h, n)
    } else {
        steps(split, method, &mut w, h, n)
    };
    stepped.is_some_and(|out| split.to_inertial(&out, z).is_ok() && z.iter().all(|x| x.is_finite()))
}

/// `χ⁻¹`, `n` merged steps and `χ` on `split`: the corrected output, or
/// `None` where a flow failed.
fn steps<S: Split>(
    split: &S,
    method: &Processed<Sequence>,
    w: &mut [f64],
    h: f64,
    n: usize,
) -> Option<Vec<f64>> {
    let mut ws = SplitWorkspace::new(split.buffer_len());
    if method.enter(split, h, w, &mut ws).is_err()
        || method
            .kernel()
            .steps_merged(split, h, n, w, &mut ws)
            .is_err()
    {
        return None;
    }
    let mut out = vec![0.0; w.len()];
    method
        .output(split, h, w, &mut out, &mut ws)
        .ok()
        .map(|()| out)
}

/// The split with its interaction kicks counted: one kick is one N-body
/// force evaluation, the `evals` of a Wisdom–Holman row. Its Kepler flows
/// carry the run's own history of roots ([`WarmJacobi`]: the warm start
/// where the split has it on, a fresh history per run).
pub struct Counting<'a> {
    split: WarmJacobi<'a>,
    kicks: Cell<u64>,
}

impl StateSpace for Counting<'_> {
    fn state_len(&self) -> usize {
        self.split.state_len()
    }
}

impl Split for Counting<'_> {
    fn flow_a(
        &self,
        h: f64,
        w: &mut [f64],
        buf: PartBuffers<'_>,
        reuse: bool,
    ) -> std::result::Result<(), FlowError> {
        self.split.flow_a(h, w, buf, reuse)
    }
    fn flow_b(
        &self,
        h: f64,
        w: &mut [f64],
        buf: PartBuffers<'_>,
        reuse: bool,
    ) -> std::result::Result<(), FlowError> {
        self.kicks.set(self.kicks.get() + 1);
        self.split.flow_b(h, w, buf, reuse)
    }
    /// Two force evaluations: the lazy modified kick evaluates the
    /// interaction at the positions and at the shifted ones.
    fn flow_b_gradient(
        &self,
        h: f64,
        gamma: f64,
        w: &mut [f64],
        buf: PartBuffers<'_>,
    ) -> std::result::Result<(), FlowError> {
        self.kicks.set(self.kicks.get() + 2);
        self.split.flow_b_gradient(h, gamma, w, buf)
    }
}

fn failed(step: usize, reason: impl ToString) -> Status {
    Status::SolverFailed {
        step,
        reason: reason.to_string(),
    }
}

/// The facts of a `wh:ID` row: the splitting's verified order (for general
/// parts `A`, `B`: see [`integrator_core::split`]) and symplecticity; stepped
/// as a processed method with no corrector (`χ` the identity). `None` where
/// the catalogue has no table of the id (every library splitting has one).
fn fixed<P, M>(id: &str, scheme: M, split: &Jacobi) -> Option<Method<P>>
where
    P: Problem,
    M: Scheme
        + Step<Jacobi, Workspace = SplitWorkspace>
        + for<'a> Step<Counting<'a>, Workspace = SplitWorkspace>
        + Send
        + Sync
        + 'static,
{
    let sequence = Sequence::from_catalogue(id.strip_prefix(PREFIX).unwrap_or(id))?;
    let identity = Sequence::new([]);
    Some(Method::Fixed(Fixed {
        id: id.to_string(),
        order: M::INFO.order,
        symplectic: M::INFO.symplectic_separable,
        family: Family::Splitting,
        interpreted: false,
        stepper: Box::new(WhStepper::new(scheme, sequence, identity, split)),
    }))
}

/// A `wh:` method on the Jacobi split of an N-body problem, as a
/// [`Stepper`] of the problem's inertial state: a kernel `M` (a `butcher!`
/// splitting, or a sequence) with a corrector `χ` at output only
/// ([`Processed`]; the identity for a plain splitting), and the conversions.
pub struct WhStepper<M> {
    method: Processed<M>,
    split: Jacobi,
    /// The kernel's sequence with the corrector, for the timed run (merged
    /// across steps).
    timed: Processed<Sequence>,
}

impl<M> WhStepper<M> {
    /// `kernel`, whose drift–kick sequence is `sequence`, processed by
    /// `chi` on `split`.
    pub fn new(kernel: M, sequence: Sequence, chi: Sequence, split: &Jacobi) -> Self {
        WhStepper {
            timed: Processed::new(sequence, chi.clone()),
            method: Processed::new(kernel, chi),
            split: split.clone(),
        }
    }
}

impl<M> WhStepper<M>
where
    M: for<'a> Step<Counting<'a>, Workspace = SplitWorkspace>,
{
    fn run_observed(
        &self,
        counting: &Counting<'_>,
        z: &mut [f64],
        h: f64,
        n: usize,
        compensated: bool,
        observe: &mut dyn FnMut(usize, f64, &[f64]) -> bool,
    ) -> Status {
        if !(h.is_finite() && h != 0.0) {
            return failed(0, format!("step size h = {h} must be finite and nonzero"));
        }
        let mut w = vec![0.0; z.len()];
        if let Err(e) = self.split.from_inertial_checked(z, &mut w) {
            return failed(0, e);
        }
        let mut chi_ws = SplitWorkspace::new(counting.buffer_len());
        if let Err(e) = self.method.enter(counting, h, &mut w, &mut chi_ws) {
            return failed(0, format!("the corrector's inverse on entry: {e}"));
        }
        if !observe(0, 0.0, z) {
            return Status::Stopped { step: 0 };
        }
        let mut out = vec![0.0; w.len()];
        let mut ws = self.method.kernel().workspace(counting);
        ws.set_compensated(compensated);
        for k in 0..n {
            let t = k as f64 * h;
            if let Err(e) =
                self.method
                    .kernel()
                    .step_reusing(counting, t, h, &mut w, &mut ws, k > 0)
            {
                return failed(k + 1, e);
            }
            // The outputs before the last are the harness's (it observes
            // every step), not the method's: their kicks are not counted,
            // so the count is what the timed run does (χ⁻¹, the kernel's
            // steps, one χ).
            let kicks = counting.kicks.get();
            if let Err(e) = self.method.output(counting, h, &w, &mut out, &mut chi_ws) {
                return failed(k + 1, format!("the corrector at output: {e}"));
            }
            if k + 1 < n {
                counting.kicks.set(kicks);
            }
            if let Err(e) = self.split.to_inertial(&out, z) {
                return failed(k + 1, e);
            }
            if z.iter().any(|x| !x.is_finite()) {
                return Status::Diverged { step: k + 1 };
            }
            if !observe(k + 1, (k + 1) as f64 * h, z) {
                return Status::Stopped { step: k + 1 };
            }
        }
        Status::Ok
    }
}

impl<P, M> Stepper<P> for WhStepper<M>
where
    P: Problem,
    M: Step<Jacobi, Workspace = SplitWorkspace>
        + for<'a> Step<Counting<'a>, Workspace = SplitWorkspace>
        + Send
        + Sync,
{
    fn observed(
        &self,
        _sys: &P,
        z: &mut [f64],
        h: f64,
        n: usize,
        compensated: bool,
        observe: &mut dyn FnMut(usize, f64, &[f64]) -> bool,
    ) -> Outcome {
        let counting = Counting {
            split: WarmJacobi::new(&self.split),
            kicks: Cell::new(0),
        };
        let status = self.run_observed(&counting, z, h, n, compensated, observe);
        Outcome {
            status,
            evals: counting.kicks.get(),
            newton_iterations: 0,
            fixed_point_iterations: 0,
            factorizations: 0,
            steps: None,
        }
    }

    /// Converted twice and corrected twice (`χ⁻¹` after the conversion in,
    /// `χ` before the conversion out), the drifts merged across steps, as
    /// REBOUND's WHFast with a corrector and its safe mode off.
    fn bare(&self, _sys: &P, z: &mut [f64], h: f64, n: usize) -> bool {
        bare_merged(&self.split, &self.timed, z, h, n)
    }
}

/// The row of a processed `wh:ID`: `kernel` with the corrector `chi`, of the
/// effective classical `order`; `kernel_sequence` the kernel's drift–kick
/// sequence for the timed run (merged across steps).
fn processed<P, M>(
    id: &str,
    kernel: M,
    kernel_sequence: Sequence,
    chi: Sequence,
    order: usize,
    split: &Jacobi,
) -> Method<P>
where
    P: Problem,
    M: Step<Jacobi, Workspace = SplitWorkspace>
        + for<'a> Step<Counting<'a>, Workspace = SplitWorkspace>
        + Send
        + Sync
        + 'static,
{
    Method::Fixed(Fixed {
        id: id.to_string(),
        order,
        symplectic: true,
        family: Family::Splitting,
        interpreted: false,
        stepper: Box::new(WhStepper::new(kernel, kernel_sequence, chi, split)),
    })
}

/// Generates [`wh_method`] and [`wh_processed`] from the library's one
/// scheme list (`integrator_core::for_each_scheme!`): its splittings (drift–kick
/// sequences and compositions) are the kernels the Jacobi split takes.
macro_rules! splittings {
    (
        explicit_rk: [$($eid:literal => $ety:ident),* $(,)?],
        implicit_rk: [$($rid:literal => $rty:ident),* $(,)?],
        explicit_pairs: [$($xid:literal => $xty:ident),* $(,)?],
        splittings: [$($sid:literal => $sty:ident),* $(,)?],
        implicit_pairs: [$($iid:literal => $ity:ident),* $(,)?] $(,)?
    ) => {
        /// The splitting `base` on the Wisdom–Holman split `split` of an
        /// N-body problem, as the method `id` (`wh:BASE`); `None` for a
        /// `base` that is not a splitting.
        fn wh_method<P: Problem>(id: &str, base: &str, split: &Jacobi) -> Option<Method<P>> {
            match base {
                $($sid => fixed(id, integrator_core::library::$sty, split),)*
                _ => None,
            }
        }

        /// A processed method `wh:ID` (a catalogue file with a corrector)
        /// whose kernel is the library splitting `kernel`: the kernel's
        /// `butcher!` step, the corrector `chi` at output only. `None` for a
        /// `kernel` that is not a splitting of the library.
        fn wh_processed<P: Problem>(
            id: &str,
            kernel: &str,
            chi: Sequence,
            order: usize,
            split: &Jacobi,
        ) -> Option<Method<P>> {
            Some(match kernel {
                $($sid => processed(
                    id,
                    integrator_core::library::$sty,
                    Sequence::from_catalogue($sid)?,
                    chi,
                    order,
                    split,
                ),)*
                _ => return None,
            })
        }
    };
}

integrator_core::for_each_scheme!(splittings);

/// The catalogue's processed method `base` as `wh:ID` (`None` when `base`
/// is not a processed method of the catalogue): the corrector as doubles,
/// the kernel the library's scheme of the id it names, else its sequence.
fn processed_method<P: Problem>(id: &str, base: &str, split: &Jacobi) -> Option<Method<P>> {
    let file = tableau::catalogue::load(base).ok()?;
    let corrector = file.corrector.as_ref()?;
    let chi = Sequence::from_splitting(corrector);
    // The effective classical order, as claimed (and proven: the catalogue's
    // claims are checked by tableau's tests); the kernel's where none is.
    let order = file
        .claims
        .iter()
        .find_map(|c| match c {
            tableau::claims::Claim::Order { p, .. } => Some(*p),
            _ => None,
        })
        .unwrap_or(2);
    if let Some(kernel) = &file.kernel
        && let Some(m) = wh_processed(id, kernel, chi.clone(), order, split)
    {
        return Some(m);
    }
    let kernel = match &file.table {
        tableau::Table::Splitting(s) => Sequence::from_splitting(s),
        tableau::Table::Composition(c) => Sequence::from_splitting(&c.to_splitting()),
        _ => return None,
    };
    // Not marked interpreted: every `wh:` row's timed run steps its
    // sequence (merged across steps), so their times compare.
    Some(processed(id, kernel.clone(), kernel, chi, order, split))
}

/// A verified table file on the Wisdom–Holman split, as the method
/// `wh:STEM` (`STEM` the file's id): a drift–kick sequence or composition,
/// with its corrector if it has one (stepped `χ Kⁿ χ⁻¹` like the
/// catalogue's processed methods). The file's sequence is stepped as the
/// catalogue's `wh:` methods' timed runs are (merged across steps), so the
/// row is not marked interpreted and its times compare with theirs. Its
/// order is the classical order the file claims, else the last entry of a
/// claimed generalised order (the order for `ε` of order one), else the
/// proven order of its printed coefficients.
pub fn table_method<P: Problem>(t: &VerifiedTable, split: &Jacobi) -> Result<Method<P>> {
    let not_a_splitting = |what: &str| CompareError::TableFile {
        path: t.path.clone(),
        why: format!(
            "{PREFIX}{}: the Wisdom–Holman split takes a drift–kick sequence or a composition, not {what}",
            t.id
        ),
    };
    let VerifiedForm::Classic { file, analysis } = &t.form else {
        return Err(not_a_splitting("a generated or root(...) table"));
    };
    let kernel = match &file.table {
        tableau::Table::Splitting(s) => Sequence::from_splitting(s),
        tableau::Table::Composition(c) => Sequence::from_splitting(&c.to_splitting()),
        _ => return Err(not_a_splitting("a Runge–Kutta table or pair")),
    };
    let chi = file
        .corrector
        .as_ref()
        .map(Sequence::from_splitting)
        .unwrap_or_else(|| Sequence::new([]));
    let order = file
        .claims
        .iter()
        .find_map(|c| match c {
            tableau::claims::Claim::Order { p, .. }
            | tableau::claims::Claim::CertifiedOrder { p } => Some(*p),
            _ => None,
        })
        .or_else(|| {
            file.claims.iter().find_map(|c| match c {
                tableau::claims::Claim::NearOrder { orders, .. }
                | tableau::claims::Claim::CertifiedNearOrder { orders } => orders.last().copied(),
                _ => None,
            })
        })
        .unwrap_or(analysis.claimed_order_report().order);
    Ok(Method::Fixed(Fixed {
        id: format!("{PREFIX}{}", t.id),
        order,
        symplectic: analysis.symplectic_separable,
        family: Family::Splitting,
        interpreted: false,
        stepper: Box::new(WhStepper::new(kernel.clone(), kernel, chi, split)),
    }))
}

/// The ids of the catalogue's processed methods (a kernel with a corrector;
/// WHCKL's kernel with its gradient kick, `kick_gradient`, among them: the
/// Jacobi split takes it as the lazy implementer's modified kick,
/// [`Jacobi::interaction_kick_gradient`]).
pub fn processed_ids() -> Vec<&'static str> {
    tableau::catalogue::entries()
        .iter()
        .filter(|e| e.load().is_ok_and(|f| f.corrector.is_some()))
        .map(|e| e.id)
        .collect()
}

/// WHCKM (REBOUND's `kernel = "modifiedkick"`): the tables of WHCKL with
/// the modified kick taken exactly. `wh:whckm-…` is the catalogue's
/// `whckl-…` on the split with [`GradientKick::Exact`]
/// ([`Jacobi::interaction_kick_modified`]) instead of the lazy kick.
const EXACT_KICK: (&str, &str) = ("whckm-", "whckl-");

/// `wh:ID` on `split`, or an error naming the id: `ID` must be a splitting
/// of the library (`symlab list`: a drift–kick sequence or composition), a
/// processed method of the catalogue (a kernel with a corrector), or
/// `whckm-…` for a `whckl-…` of the catalogue ([`EXACT_KICK`]).
pub fn method<P: Problem>(id: &str, split: &Jacobi) -> Result<Method<P>> {
    let Some(base) = id.strip_prefix(PREFIX) else {
        return Err(CompareError::method(
            id,
            format!("method '{id}' is not a Wisdom–Holman id ({PREFIX}ID)"),
        ));
    };
    let exact = base.strip_prefix(EXACT_KICK.0).and_then(|rest| {
        let exact = split.clone().with_gradient_kick(GradientKick::Exact);
        processed_method(id, &format!("{}{rest}", EXACT_KICK.1), &exact)
    });
    if let Some(m) = exact {
        return Ok(m);
    }
    wh_method(id, base, split)
        .or_else(|| processed_method(id, base, split))
        .ok_or_else(|| {
            CompareError::method(
                id,
                format!(
                    "method '{id}': '{base}' is neither a splitting of the library nor a processed method of the catalogue; Wisdom–Holman steps a drift–kick sequence or composition: {}; or a kernel with its corrector: {}",
                    crate::library::SPLITTING_IDS.join(", "),
                    processed_and_exact_ids().join(", ")
                ),
            )
        })
}

/// The catalogue's processed methods, then their WHCKM forms
/// ([`EXACT_KICK`]).
fn processed_and_exact_ids() -> Vec<String> {
    let processed = processed_ids();
    let exact = processed
        .iter()
        .filter_map(|id| id.strip_prefix(EXACT_KICK.1))
        .map(|rest| format!("{}{rest}", EXACT_KICK.0));
    processed
        .iter()
        .map(|id| id.to_string())
        .chain(exact)
        .collect()
}

/// Every `wh:ID`: the library's splittings, then the catalogue's processed
/// methods and their WHCKM forms.
pub fn ids() -> Vec<String> {
    crate::library::SPLITTING_IDS
        .iter()
        .map(|id| id.to_string())
        .chain(processed_and_exact_ids())
        .map(|id| format!("{PREFIX}{id}"))
        .collect()
}
