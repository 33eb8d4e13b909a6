//! Generic run-time table interpreters: the baseline the `butcher!` schemes
//! are measured against.
//!
//! [`RkInterpreter`] holds an explicit Runge–Kutta table `(A, b, c)` in
//! memory and steps any [`OdeSystem`] by looping over it, as the steppers of
//! most ODE libraries do (diffsol, OrdinaryDiffEq's tableau methods, SciPy):
//! stage `i` is `yᵢ = z + h Σⱼ₍ⱼ₌₀..ᵢ₋₁₎ aᵢⱼ kⱼ`, `kᵢ = f(t + cᵢh, yᵢ)`, then
//! `z ← z + h Σⱼ bⱼ kⱼ`. [`SplittingInterpreter`] does the same for a
//! drift–kick sequence on a [`Separable`] system. Both are written as a
//! competent generic implementation would be: the workspace is allocated up
//! front, every vector is cut to the system's size (as the macro's are),
//! zero coefficients are skipped, the vector loops run over zipped slices
//! (no bounds checks), and `h·aᵢⱼ` is formed once per term. What they cannot
//! do is what the macro does at compile time: unroll the stages, make the
//! coefficients literals and drop the loops over the table.
//!
//! The coefficients are the macro's (rounded by [`tableau::rounding`] with
//! the table's analysis), the arithmetic is the macro's term for term and in
//! the same order, and the update is compensated (Kahan) or plain as the
//! workspace's `compensated` flag says (default on, as for the macro), so
//! the results agree with the corresponding library scheme to the last bit
//! (the tests below allow 4 ulps).
//!
//! ```
//! use integrator_core::{Step, interp::RkInterpreter};
//!
//! /// y' = −y.
//! struct Decay;
//! impl integrator_core::OdeSystem for Decay {
//!     fn dim(&self) -> usize { 1 }
//!     fn rhs(&self, _t: f64, z: &[f64], dz: &mut [f64]) { dz[0] = -z[0] }
//! }
//!
//! let rk4 = RkInterpreter::from_catalogue("rk4").unwrap();
//! let mut ws = rk4.workspace(&Decay);
//! let mut z = [1.0];
//! for _ in 0..10 {
//!     rk4.step(&Decay, 0.0, 0.1, &mut z, &mut ws).unwrap();
//! }
//! assert!((z[0] - (-1.0f64).exp()).abs() < 1e-6);
//! ```

use crate::error::SolveError;
use crate::scheme::{SplitWorkspace, Step};
use crate::sequence::Sequence;
use crate::split::Part;
use crate::system::{OdeSystem, Separable};
use tableau::analysis::Analysis;
use tableau::file::FileError;
use tableau::rounding::{F64Rounded, round_table, round_weights};
use tableau::table::{Op, ShapeError};
use tableau::{Number, Table};

/// Why a table cannot be interpreted.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum InterpError {
    #[error(transparent)]
    File(#[from] FileError),
    #[error(transparent)]
    Table(#[from] ShapeError),
    #[error("A is {rows}×{cols} but b has {stages} entries")]
    Shape {
        rows: usize,
        cols: usize,
        stages: usize,
    },
    #[error("c has {got} entries but the table has {stages} stages")]
    Abscissae { got: usize, stages: usize },
    #[error(
        "the table is implicit (a[{row}][{col}] = {value} on or above the diagonal); only explicit tables can be interpreted"
    )]
    Implicit { row: usize, col: usize, value: f64 },
    #[error(
        "a drift–kick sequence needs as many drifts as kicks, or one more of either; got {drifts} drifts and {kicks} kicks"
    )]
    Sequence { drifts: usize, kicks: usize },
    /// A sequence whose every coefficient is zero: nothing is left once the
    /// zeros are dropped (`compose = ["0"]`).
    #[error(
        "every coefficient of `{field}` is 0: once its zeros are dropped the sequence has no flows, so it is the identity map, not a method"
    )]
    Empty { field: &'static str },
    /// A coefficient whose double is not finite: the interpreters step in
    /// `f64`, and a coefficient of `10^5000` would step to NaN.
    #[error(
        "{what} is not a finite double{value}: the interpreters step in f64 (at most ±1.8e308)"
    )]
    NotFinite { what: String, value: String },
    #[error("{found} table where {wanted} was expected")]
    Form {
        wanted: &'static str,
        found: &'static str,
    },
}

fn form_name(t: &Table) -> &'static str {
    match t {
        Table::Rk(_) => "a Runge–Kutta",
        Table::Prk(_) => "a partitioned",
        Table::Splitting(s) if s.has_gradient() => "a gradient-kick (kick_gradient)",
        Table::Splitting(_) => "a drift–kick",
        Table::Composition(_) => "a composition",
    }
}

/// `y ← y + α x`.
#[inline]
fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += alpha * xi;
    }
}

/// `d ← d + inc` with compensated (Kahan) summation: `e` holds the rounding
/// error of the previous update and receives that of this one. The
/// increment `inc` already includes `e` (as the macro's code adds it first).
#[inline]
fn compensated_add(d: &mut [f64], e: &mut [f64], inc: &[f64]) {
    for ((di, ei), inc) in d.iter_mut().zip(e.iter_mut()).zip(inc) {
        let new = *di + inc;
        *ei = (*di - new) + inc;
        *di = new;
    }
}

/// An explicit Runge–Kutta table held in memory, stepped by a loop over it.
#[derive(Clone, Debug, PartialEq)]
pub struct RkInterpreter {
    a: Vec<Vec<f64>>,
    b: Vec<f64>,
    c: Vec<f64>,
}

/// Stage derivatives and the stage value of an [`RkInterpreter`] step, and
/// the compensated summation of the update, as in
/// [`RkWorkspace`](crate::scheme::RkWorkspace).
#[derive(Clone, Debug)]
pub struct RkInterpWorkspace {
    pub k: Vec<Vec<f64>>,
    pub y: Vec<f64>,
    /// The rounding error of the last update of `z`, carried into the next.
    pub e: Vec<f64>,
    /// Compensated summation of the update `z ← z + h Σ bᵢkᵢ` (default on,
    /// as for the macro's schemes).
    pub compensated: bool,
}

impl RkInterpreter {
    /// A table `(A, b, c)`; `A` must be square with as many rows as `b` has
    /// entries and strictly lower triangular (explicit).
    pub fn new(a: Vec<Vec<f64>>, b: Vec<f64>, c: Vec<f64>) -> Result<Self, InterpError> {
        let s = b.len();
        if a.len() != s || a.iter().any(|r| r.len() != s) {
            return Err(InterpError::Shape {
                rows: a.len(),
                cols: a.iter().map(Vec::len).find(|&l| l != s).unwrap_or(s),
                stages: s,
            });
        }
        if c.len() != s {
            return Err(InterpError::Abscissae {
                got: c.len(),
                stages: s,
            });
        }
        let named = a
            .iter()
            .enumerate()
            .flat_map(|(i, r)| {
                r.iter()
                    .enumerate()
                    .map(move |(j, x)| (format!("a[{i}][{j}]"), *x))
            })
            .chain(b.iter().enumerate().map(|(i, x)| (format!("b[{i}]"), *x)))
            .chain(c.iter().enumerate().map(|(i, x)| (format!("c[{i}]"), *x)));
        for (what, x) in named {
            if !x.is_finite() {
                return Err(InterpError::NotFinite {
                    what,
                    value: format!(" ({x})"),
                });
            }
        }
        for (row, r) in a.iter().enumerate() {
            if let Some((col, &value)) = r.iter().enumerate().skip(row).find(|(_, x)| **x != 0.0) {
                return Err(InterpError::Implicit { row, col, value });
            }
        }
        Ok(RkInterpreter { a, b, c })
    }

    /// From an exact table, rounded to `f64` by [`tableau::rounding`] with
    /// the verdicts of its analysis: the very coefficients `butcher!` emits
    /// for it (weights summing to 1.0, each within an ulp of its exact
    /// value, abscissae correctly rounded).
    pub fn from_table(table: &Table) -> Result<Self, InterpError> {
        let analysis = Analysis::of(table)?;
        match round_table(table, &analysis) {
            F64Rounded::Rk(t) => Self::new(t.a, t.b, t.c),
            _ => Err(InterpError::Form {
                wanted: "an explicit Runge–Kutta table",
                found: form_name(table),
            }),
        }
    }

    /// From a table of the built-in catalogue, e.g. `"rk4"`.
    pub fn from_catalogue(id: &str) -> Result<Self, InterpError> {
        Self::from_table(&tableau::catalogue::load(id)?.table)
    }

    pub fn a(&self) -> &[Vec<f64>] {
        &self.a
    }
    pub fn b(&self) -> &[f64] {
        &self.b
    }
    pub fn c(&self) -> &[f64] {
        &self.c
    }
    pub fn stages(&self) -> usize {
        self.b.len()
    }
}

impl<S: OdeSystem + ?Sized> Step<S> for RkInterpreter {
    type Workspace = RkInterpWorkspace;

    fn workspace(&self, sys: &S) -> RkInterpWorkspace {
        let n = sys.dim();
        RkInterpWorkspace {
            k: vec![vec![0.0; n]; self.stages()],
            y: vec![0.0; n],
            e: vec![0.0; n],
            compensated: true,
        }
    }

    fn step(
        &self,
        sys: &S,
        t: f64,
        h: f64,
        z: &mut [f64],
        ws: &mut RkInterpWorkspace,
    ) -> Result<(), SolveError> {
        // Every vector cut to the system's size, as the macro does, so that
        // the two differ only in where the table is.
        let n = sys.dim();
        let z = &mut z[..n];
        let RkInterpWorkspace {
            k,
            y,
            e,
            compensated,
        } = ws;
        let y = &mut y[..n];
        for i in 0..self.b.len() {
            // Stages 0..i are done; stage i is written.
            let (done, rest) = k.split_at_mut(i);
            y.copy_from_slice(z);
            for (kj, &aij) in done.iter().zip(&self.a[i][..i]) {
                if aij != 0.0 {
                    axpy(h * aij, &kj[..n], y);
                }
            }
            sys.rhs(t + self.c[i] * h, y, &mut rest[0][..n]);
        }
        // z ← z + h Σ bⱼkⱼ, the terms added in order; compensated: the
        // increment e + h Σ bⱼkⱼ is formed in y, then added with its error
        // kept in e.
        let acc: &mut [f64] = if *compensated {
            y.copy_from_slice(&e[..n]);
            y
        } else {
            z
        };
        for (kj, &bj) in k.iter().zip(&self.b) {
            if bj != 0.0 {
                axpy(h * bj, &kj[..n], acc);
            }
        }
        if *compensated {
            compensated_add(z, &mut e[..n], y);
        }
        Ok(())
    }
}

/// A drift–kick sequence `D(d₁) K(k₁) D(d₂) …` held in memory
/// ([`Sequence`], the one description every run-time user of a sequence
/// holds), stepped by a loop over it on a [`Separable`] system.
#[derive(Clone, Debug, PartialEq)]
pub struct SplittingInterpreter {
    seq: Sequence,
}

impl SplittingInterpreter {
    /// A table's drift and kick lists as a table file writes them
    /// ([`Sequence::from_lists`]: with one more kick than drifts the
    /// sequence starts with a kick); every value finite, the two lengths
    /// differing by at most one.
    pub fn new(drift: Vec<f64>, kick: Vec<f64>) -> Result<Self, InterpError> {
        let named = (drift
            .iter()
            .enumerate()
            .map(|(i, x)| (format!("drift[{i}]"), *x)))
        .chain(
            kick.iter()
                .enumerate()
                .map(|(i, x)| (format!("kick[{i}]"), *x)),
        );
        for (what, x) in named {
            if !x.is_finite() {
                return Err(InterpError::NotFinite {
                    what,
                    value: format!(" ({x})"),
                });
            }
        }
        let (nd, nk) = (drift.len(), kick.len());
        if nd.abs_diff(nk) > 1 || nd + nk == 0 {
            return Err(InterpError::Sequence {
                drifts: nd,
                kicks: nk,
            });
        }
        Ok(SplittingInterpreter {
            seq: Sequence::from_lists(&drift, &kick),
        })
    }

    /// From an exact drift–kick sequence or a composition of Störmer–Verlet,
    /// rounded to `f64` as `butcher!` rounds it.
    pub fn from_table(table: &Table) -> Result<Self, InterpError> {
        let s = match table {
            Table::Splitting(s) => s.clone(),
            Table::Composition(c) => c.to_splitting(),
            other => {
                return Err(InterpError::Form {
                    wanted: "a drift–kick sequence or a composition",
                    found: form_name(other),
                });
            }
        };
        // Gradient kicks (the kick of V − g·h²·|∇V|²) need the gradient of
        // the force, which a separable system does not give (its T need not
        // be quadratic): refused, never stepped as plain kicks. Split systems
        // that provide one step them through `processed::Sequence`.
        if s.has_gradient() {
            return Err(InterpError::Form {
                wanted: "a drift–kick sequence of plain kicks or a composition",
                found: form_name(table),
            });
        }
        let symmetric = Analysis::of(table)?.symmetric;
        // The normal form (zeros dropped, neighbours merged), its drift and
        // kick values rounded as weight vectors, as `butcher!` does.
        let nf = s.normal_form();
        // Named by the exact value, before rounding turns it into inf.
        if let Some(o) = nf.iter().find(|o| !o.1.to_f64().is_finite()) {
            return Err(InterpError::NotFinite {
                what: format!(
                    "a {} coefficient",
                    if o.0 == Op::Drift { "drift" } else { "kick" }
                ),
                value: format!(" (≈ {})", o.1.approx_text()),
            });
        }
        if nf.is_empty() {
            return Err(InterpError::Empty {
                field: match table {
                    Table::Composition(_) => "compose",
                    _ => "drift` and `kick",
                },
            });
        }
        let values = |op: Op| -> Vec<Number> {
            nf.iter()
                .filter(|o| o.0 == op)
                .map(|o| o.1.clone())
                .collect()
        };
        let mut drift = round_weights(&values(Op::Drift), symmetric).into_iter();
        let mut kick = round_weights(&values(Op::Kick), symmetric).into_iter();
        // Back in the normal form's order, each value the next of its kind.
        let ops = nf.iter().map(|o| match o.0 {
            Op::Drift => (Part::A, drift.next().unwrap_or_default()),
            Op::Kick => (Part::B, kick.next().unwrap_or_default()),
        });
        Ok(SplittingInterpreter {
            seq: Sequence::new(ops),
        })
    }

    /// From a table of the built-in catalogue, e.g. `"forest-ruth"`.
    pub fn from_catalogue(id: &str) -> Result<Self, InterpError> {
        Self::from_table(&tableau::catalogue::load(id)?.table)
    }

    /// The sequence it steps.
    pub fn sequence(&self) -> &Sequence {
        &self.seq
    }
}

impl<S: Separable + ?Sized> Step<S> for SplittingInterpreter {
    type Workspace = SplitWorkspace;

    fn workspace(&self, sys: &S) -> SplitWorkspace {
        SplitWorkspace::new(sys.dof())
    }

    fn step(
        &self,
        sys: &S,
        t: f64,
        h: f64,
        z: &mut [f64],
        ws: &mut SplitWorkspace,
    ) -> Result<(), SolveError> {
        self.step_reusing(sys, t, h, z, ws, false)
    }

    fn step_reusing(
        &self,
        sys: &S,
        _t: f64,
        h: f64,
        z: &mut [f64],
        ws: &mut SplitWorkspace,
        reuse: bool,
    ) -> Result<(), SolveError> {
        let n = sys.dof();
        let (q, p) = z.split_at_mut(n);
        let (q, p) = (&mut q[..n], &mut p[..n]);
        let SplitWorkspace {
            v,
            f,
            eq,
            ep,
            compensated,
        } = ws;
        let (v, f) = (&mut v[..n], &mut f[..n]);
        let (eq, ep) = (&mut eq[..n], &mut ep[..n]);
        let compensated = *compensated;
        let mut skip = reuse && self.seq.merges();
        let mut apply = |is_kick: bool, c: f64| {
            if c == 0.0 {
                return;
            }
            // The evaluation, the variable it moves and that one's error.
            let (x, e, g) = if is_kick {
                if !skip {
                    sys.force(q, f);
                }
                (&mut *p, &mut *ep, &*f)
            } else {
                if !skip {
                    sys.velocity(p, v);
                }
                (&mut *q, &mut *eq, &*v)
            };
            let hc = h * c;
            if compensated {
                for ((xi, ei), gi) in x.iter_mut().zip(e.iter_mut()).zip(g) {
                    let inc = *ei + hc * gi;
                    let new = *xi + inc;
                    *ei = (*xi - new) + inc;
                    *xi = new;
                }
            } else {
                axpy(hc, g, x);
            }
            skip = false;
        };
        for &(part, c) in self.seq.ops() {
            apply(part == Part::B, c);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::library::{ForestRuth, Leapfrog, Rk4, Yoshida4};
    use crate::scheme::{RkWorkspace, Scheme};

    /// `H = ½|p|² − 1/|q|` in the plane.
    struct Kepler;
    impl Separable for Kepler {
        fn dof(&self) -> usize {
            2
        }
        fn kinetic(&self, p: &[f64]) -> f64 {
            0.5 * (p[0] * p[0] + p[1] * p[1])
        }
        fn potential(&self, q: &[f64]) -> f64 {
            -1.0 / q[0].hypot(q[1])
        }
        fn velocity(&self, p: &[f64], v: &mut [f64]) {
            v.copy_from_slice(p);
        }
        fn force(&self, q: &[f64], f: &mut [f64]) {
            let r2 = q[0] * q[0] + q[1] * q[1];
            let s = 1.0 / (r2 * r2.sqrt());
            f[0] = -q[0] * s;
            f[1] = -q[1] * s;
        }
    }

    /// Kepler orbit of eccentricity 0.6 at pericentre.
    fn start() -> [f64; 4] {
        let e: f64 = 0.6;
        [1.0 - e, 0.0, 0.0, ((1.0 + e) / (1.0 - e)).sqrt()]
    }

    fn ulps(x: f64, y: f64) -> u64 {
        if x == y {
            return 0;
        }
        let key = |v: f64| {
            let b = v.to_bits() as i64;
            if b < 0 { i64::MIN - b } else { b }
        };
        key(x).abs_diff(key(y))
    }

    /// One step from many states along the orbit, then 500 steps in a row,
    /// by the macro's scheme and by the interpreter.
    /// One step from many states along the orbit, then 500 steps in a row
    /// (reusing the last evaluation where `reuse`), by the macro's scheme and
    /// by the interpreter, both with compensated summation (the default) and
    /// without (`plain` switches it off in both workspaces).
    fn agree<M, I>(
        scheme: M,
        interp: I,
        reuse: bool,
        plain: impl Fn(&mut M::Workspace, &mut I::Workspace),
    ) where
        M: Step<Kepler>,
        I: Step<Kepler>,
    {
        let h = 0.01;
        for compensated in [true, false] {
            let workspaces = || {
                let (mut wm, mut wi) = (scheme.workspace(&Kepler), interp.workspace(&Kepler));
                if !compensated {
                    plain(&mut wm, &mut wi);
                }
                (wm, wi)
            };
            let (mut wm, mut wi) = workspaces();
            let mut z = start();
            for k in 0..200 {
                let t = k as f64 * h;
                let (mut zm, mut zi) = (z, z);
                scheme.step(&Kepler, t, h, &mut zm, &mut wm).unwrap();
                interp.step(&Kepler, t, h, &mut zi, &mut wi).unwrap();
                for (a, b) in zm.iter().zip(&zi) {
                    assert!(ulps(*a, *b) <= 4, "step {k}: {zm:?} vs {zi:?}");
                }
                z = zm;
            }
            let (mut wm, mut wi) = workspaces();
            let (mut zm, mut zi) = (start(), start());
            for k in 0..500 {
                let t = k as f64 * h;
                let r = reuse && k > 0;
                scheme
                    .step_reusing(&Kepler, t, h, &mut zm, &mut wm, r)
                    .unwrap();
                interp
                    .step_reusing(&Kepler, t, h, &mut zi, &mut wi, r)
                    .unwrap();
            }
            for (a, b) in zm.iter().zip(&zi) {
                assert!(
                    (a - b).abs() <= 1e-12 * a.abs().max(1.0),
                    "{zm:?} vs {zi:?}"
                );
            }
        }
    }

    fn plain_split(m: &mut SplitWorkspace, i: &mut SplitWorkspace) {
        m.compensated = false;
        i.compensated = false;
    }

    #[test]
    fn rk4_agrees_with_the_macro() {
        let it = RkInterpreter::from_catalogue("rk4").unwrap();
        assert_eq!(it.c(), &Rk4::C[..]);
        assert_eq!(it.b(), &Rk4::B[..]);
        assert!(it.a().iter().zip(&Rk4::A).all(|(x, y)| x[..] == y[..]));
        agree(
            Rk4,
            it,
            false,
            |m: &mut RkWorkspace<4>, i: &mut RkInterpWorkspace| {
                m.compensated = false;
                i.compensated = false;
            },
        );
    }

    #[test]
    fn leapfrog_agrees_with_the_macro() {
        let it = SplittingInterpreter::from_catalogue("leapfrog").unwrap();
        assert_eq!(
            it.sequence(),
            &Sequence::from_lists(&Leapfrog::DRIFT, &Leapfrog::KICK)
        );
        agree(Leapfrog, it.clone(), false, plain_split);
        agree(Leapfrog, it, true, plain_split);
    }

    /// A sequence with gradient kicks (WHCKL's kernel) is refused, never
    /// stepped as plain kicks; with the gradient zero it is the leapfrog.
    #[test]
    fn gradient_kicks_are_refused() {
        let table = tableau::catalogue::load("whckl-c17").unwrap().table;
        let e = SplittingInterpreter::from_table(&table).unwrap_err();
        assert!(
            matches!(e, InterpError::Form { .. }) && e.to_string().contains("kick_gradient"),
            "{e}"
        );
        let Table::Splitting(mut s) = table else {
            unreachable!("a drift–kick sequence")
        };
        s.gradient = vec![Number::zero()];
        let it = SplittingInterpreter::from_table(&Table::Splitting(s)).unwrap();
        assert_eq!(
            it.sequence(),
            &Sequence::from_lists(&Leapfrog::DRIFT, &Leapfrog::KICK)
        );
    }

    #[test]
    fn forest_ruth_agrees_with_the_macro() {
        let it = SplittingInterpreter::from_catalogue("forest-ruth").unwrap();
        assert_eq!(
            it.sequence(),
            &Sequence::from_lists(&ForestRuth::DRIFT, &ForestRuth::KICK)
        );
        agree(ForestRuth, it.clone(), false, plain_split);
        agree(ForestRuth, it, true, plain_split);
    }

    #[test]
    fn compositions_are_interpreted_as_their_sequence() {
        let it = SplittingInterpreter::from_catalogue("yoshida4").unwrap();
        assert_eq!(<Yoshida4 as Scheme>::INFO.form, "composition");
        agree(Yoshida4, it, true, plain_split);
    }

    #[test]
    fn kick_first_sequences_start_with_a_kick() {
        // K(1/2) D(1) K(1/2) is kick–drift–kick Störmer–Verlet; on the
        // oscillator from (1, 0) the first kick moves p only.
        struct Osc;
        impl Separable for Osc {
            fn dof(&self) -> usize {
                1
            }
            fn kinetic(&self, p: &[f64]) -> f64 {
                0.5 * p[0] * p[0]
            }
            fn potential(&self, q: &[f64]) -> f64 {
                0.5 * q[0] * q[0]
            }
            fn velocity(&self, p: &[f64], v: &mut [f64]) {
                v[0] = p[0];
            }
            fn force(&self, q: &[f64], f: &mut [f64]) {
                f[0] = -q[0];
            }
        }
        let kdk = SplittingInterpreter::new(vec![1.0], vec![0.5, 0.5]).unwrap();
        let mut ws = kdk.workspace(&Osc);
        let mut z = [1.0, 0.0];
        kdk.step(&Osc, 0.0, 0.5, &mut z, &mut ws).unwrap();
        // p½ = −0.25, q = 1 − 0.125 = 0.875, p = −0.25 − 0.25·0.875.
        assert_eq!(z, [0.875, -0.25 - 0.21875]);
    }

    #[test]
    fn bad_tables_are_refused() {
        assert!(matches!(
            RkInterpreter::from_catalogue("gauss2"),
            Err(InterpError::Implicit { row: 0, col: 0, .. })
        ));
        assert!(matches!(
            RkInterpreter::from_catalogue("leapfrog"),
            Err(InterpError::Form { .. })
        ));
        assert!(matches!(
            SplittingInterpreter::from_catalogue("rk4"),
            Err(InterpError::Form { .. })
        ));
        assert!(matches!(
            RkInterpreter::from_catalogue("rk5"),
            Err(InterpError::File(_))
        ));
        assert!(matches!(
            RkInterpreter::new(vec![vec![0.0]], vec![0.5, 0.5], vec![0.0, 1.0]),
            Err(InterpError::Shape { .. })
        ));
        assert!(matches!(
            SplittingInterpreter::new(vec![1.0], vec![0.5, 0.5, 0.5]),
            Err(InterpError::Sequence { .. })
        ));
    }
}
