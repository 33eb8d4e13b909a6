//! The stage iterations, shared by the dense and the sparse linear algebra:
//! starting values, simplified Newton and fixed-point iteration (stacked or
//! stage by stage), the convergence monitor, the compensated update.

// The kernels index stage blocks of several buffers with one index.
#![allow(clippy::needless_range_loop)]

use super::collocation::{SymplecticForm, symplectic_form};
use super::settings::{Settings, Solver, Stats};
use super::symplectic_iteration::{FormScratch, FormSweeps};
use super::table::{ImplicitTable, Structure};
use crate::error::SolveError;
use crate::system::OdeSystem;

/// Which factorisation: the stacked matrix `I − h·A⊗J` of size `s·d`, or
/// the stage matrix `I − h·aᵢᵢ·J` of size `d` stored under the first stage
/// `i` with that diagonal value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Slot {
    Stacked,
    Diag(usize),
}

/// The `m × m` coefficients of a stage matrix `I − h·(C⊗J)`, row-major:
/// `q` for the rows of the first `split` components, `p` for the others.
pub(crate) struct Coefs<'a> {
    pub m: usize,
    pub q: &'a [f64],
    pub p: &'a [f64],
    pub split: usize,
}

impl Coefs<'_> {
    /// The coefficient of block `(i, j)` for component (row) `k`.
    #[inline]
    pub fn get(&self, i: usize, j: usize, k: usize) -> f64 {
        if k < self.split {
            self.q[i * self.m + j]
        } else {
            self.p[i * self.m + j]
        }
    }
}

/// What the linear algebra caches, independent of the system type.
pub(crate) trait Caches {
    /// Forget the factorisations (the table changed).
    fn clear(&mut self);
    /// Forget everything, the Jacobian included.
    fn reset(&mut self);
}

/// The Jacobian and the factorisations of the stage matrices.
pub(crate) trait Linear<Sys: ?Sized>: Caches {
    /// Whether the system provides its own Jacobian. The first call tries
    /// it at `(t, z)`; a successful try counts as an evaluation there.
    fn probe(&mut self, sys: &Sys, t: f64, z: &[f64], attempt: u64, stats: &mut Stats) -> bool;
    /// Evaluate `J = ∂f/∂z` at `(t, z)` (analytic, else finite differences
    /// if allowed, else [`SolveError::NoJacobian`]).
    fn evaluate(
        &mut self,
        sys: &Sys,
        t: f64,
        z: &[f64],
        attempt: u64,
        settings: &Settings,
        stats: &mut Stats,
    ) -> Result<(), SolveError>;
    /// How many Jacobians have been evaluated (0: none yet).
    fn version(&self) -> u64;
    /// The step attempt of the last evaluation.
    fn stamp(&self) -> u64;
    /// Make sure `slot` holds the factorisation of `I − h·(C⊗J)` for the
    /// current `J`, `h` and coefficients.
    fn prepare(
        &mut self,
        sys: &Sys,
        slot: Slot,
        coefs: &Coefs,
        h: f64,
        settings: &Settings,
        stats: &mut Stats,
    ) -> Result<(), SolveError>;
    /// `rhs ← M⁻¹·rhs` with the factorisation in `slot`.
    fn solve(&mut self, slot: Slot, rhs: &mut [f64], settings: &Settings)
    -> Result<(), SolveError>;
}

/// What the monitor says after an iteration.
enum Verdict {
    Continue,
    Converged,
    /// Re-evaluate the kept Jacobian; restart from the starting values when
    /// the iterates are unusable.
    Refresh {
        restart: bool,
    },
    /// Re-evaluate this step's Jacobian at the current iterate and go on
    /// from it (Newton proper on a strongly nonlinear step).
    Update,
    Fail(SolveError),
}

/// The convergence test: corrections down to round-off, or stagnation at
/// round-off; growth is divergence; the cap is non-convergence.
struct Monitor {
    k: usize,
    prev_delta: f64,
    prev_abs: f64,
    /// The previous iterate's distance to the solution, relative to the
    /// increments, predicted from the contraction: `θ/(1 − θ)·rel`.
    prev_est: f64,
    rises: usize,
    /// The largest correction of this solve, `|ΔZ|` (kept across refreshes).
    peak_abs: f64,
}

/// How far the corrections must have fallen from the largest of the solve
/// before a plateau counts as the round-off floor
/// ([`Settings::plateau_limit`]).
const PLATEAU_DROP: f64 = 1e4;

impl Monitor {
    fn new() -> Self {
        Monitor {
            k: 0,
            prev_delta: f64::INFINITY,
            prev_abs: 0.0,
            prev_est: f64::INFINITY,
            rises: 0,
            peak_abs: 0.0,
        }
    }

    /// After a refresh the contraction starts afresh (the count goes on).
    fn refreshed(&mut self) {
        self.prev_delta = f64::INFINITY;
        self.prev_abs = 0.0;
        self.prev_est = f64::INFINITY;
        self.rises = 0;
    }

    /// A sweep evaluates `F` at the previous iterate and corrects it. The
    /// iteration has converged, and that `F` is the one of the converged
    /// stages, when the correction is at most `tolerance` times the
    /// increments; or when the previous iterate was already that close
    /// by the contraction observed (the correction is then round-off,
    /// whatever its size); or when the corrections, relative to the stage
    /// values, stop decreasing at round-off level. `stale`: the Jacobian is
    /// from an earlier step; `updatable`: it is from this step and may be
    /// re-evaluated at the current iterate
    /// ([`Settings::jacobian_updates`]).
    fn check(&mut self, sweep: Sweep, s: &Settings, stale: bool, updatable: bool) -> Verdict {
        let Sweep { delta, rel, abs } = sweep;
        self.k += 1;
        let k = self.k;
        if !(delta.is_finite() && abs.is_finite()) {
            return if stale {
                Verdict::Refresh { restart: true }
            } else {
                Verdict::Fail(SolveError::Diverged {
                    iterations: k,
                    correction: f64::INFINITY,
                })
            };
        }
        if rel <= s.tolerance {
            return Verdict::Converged;
        }
        if delta <= s.stagnation_limit && (self.prev_est <= s.tolerance || delta >= self.prev_delta)
        {
            return Verdict::Converged;
        }
        let theta = if k >= 2 && self.prev_abs > 0.0 {
            abs / self.prev_abs
        } else {
            0.0
        };
        self.peak_abs = self.peak_abs.max(abs);
        // The round-off floor of an ill-conditioned stage system: the
        // corrections fell by orders of magnitude, then stopped falling
        // (noise fluctuates by any factor, but stays far below the peak).
        if k >= 2 && theta >= 1.0 && delta <= s.plateau_limit && abs * PLATEAU_DROP <= self.peak_abs
        {
            return Verdict::Converged;
        }
        self.prev_est = if k >= 2 && theta < 1.0 {
            theta / (1.0 - theta) * rel
        } else {
            f64::INFINITY
        };
        if k >= 2 && theta >= 1.0 && delta > s.stagnation_limit {
            if stale {
                return Verdict::Refresh { restart: true };
            }
            if updatable && delta > s.plateau_limit {
                return Verdict::Update;
            }
            self.rises += 1;
            if theta > 2.0 || self.rises >= 2 {
                return Verdict::Fail(SolveError::Diverged {
                    iterations: k,
                    correction: delta,
                });
            }
        } else {
            self.rises = 0;
        }
        if stale && theta > s.refresh_rate && delta > s.plateau_limit.max(s.stagnation_limit) {
            self.prev_delta = delta;
            self.prev_abs = abs;
            return Verdict::Refresh { restart: false };
        }
        // Not at the round-off floor, where corrections are noise and a new
        // Jacobian would change nothing.
        if updatable && theta > s.update_rate && delta > s.plateau_limit.max(s.stagnation_limit) {
            return Verdict::Update;
        }
        if k >= s.max_iterations {
            return Verdict::Fail(SolveError::NotConverged {
                iterations: k,
                correction: delta,
            });
        }
        self.prev_delta = delta;
        self.prev_abs = abs;
        Verdict::Continue
    }
}

/// Running maxima of the corrections of one sweep.
#[derive(Clone, Copy)]
struct Norms {
    /// `|ΔZᵢₖ| / (|zₖ| + |Zᵢₖ|)`: relative to the stage value.
    delta: f64,
    /// `maxᵢ|ΔZᵢₖ| / maxᵢ|Zᵢₖ|`: relative to the increments of the component.
    rel: f64,
    /// `|ΔZᵢₖ|`.
    abs: f64,
    /// The current component's `maxᵢ|ΔZᵢₖ|` and `maxᵢ|Zᵢₖ|`.
    num: f64,
    den: f64,
    finite: bool,
}

/// The corrections of one sweep, summarised for the monitor.
#[derive(Clone, Copy)]
struct Sweep {
    delta: f64,
    rel: f64,
    abs: f64,
}

impl Sweep {
    const INFINITE: Sweep = Sweep {
        delta: f64::INFINITY,
        rel: f64::INFINITY,
        abs: f64::INFINITY,
    };
}

impl Norms {
    fn new() -> Self {
        Norms {
            delta: 0.0,
            rel: 0.0,
            abs: 0.0,
            num: 0.0,
            den: 0.0,
            finite: true,
        }
    }

    /// Record the correction `new − old` of a stage component whose state
    /// component is `zk`.
    #[inline]
    fn add(&mut self, zk: f64, old: f64, new: f64) {
        let a = (new - old).abs();
        self.finite &= new.is_finite();
        self.den = self.den.max(new.abs());
        if a > 0.0 {
            let w = zk.abs() + new.abs().max(old.abs());
            let r = if w > 0.0 { (a / w).min(1.0) } else { 1.0 };
            self.delta = self.delta.max(r);
            self.abs = self.abs.max(a);
            self.num = self.num.max(a);
        }
    }

    /// Close the component whose stages were recorded since the last call.
    #[inline]
    fn end_component(&mut self) {
        if self.num > 0.0 {
            let r = if self.den > 0.0 {
                self.num / self.den
            } else {
                f64::INFINITY
            };
            self.rel = self.rel.max(r);
        }
        self.num = 0.0;
        self.den = 0.0;
    }

    fn result(&self) -> Sweep {
        if self.finite {
            Sweep {
                delta: self.delta,
                rel: self.rel,
                abs: self.abs,
            }
        } else {
            Sweep::INFINITE
        }
    }
}

/// The table seen as per-component coefficients.
pub(crate) struct Tab<'a, const S: usize> {
    aq: &'a [[f64; S]; S],
    ap: &'a [[f64; S]; S],
    bq: &'a [f64; S],
    bp: &'a [f64; S],
    c: &'a [f64; S],
    split: usize,
}

impl<'a, const S: usize> Tab<'a, S> {
    fn new(t: &'a ImplicitTable<S>, d: usize) -> Self {
        match &t.a_hat {
            Some((ah, bh)) => Tab {
                aq: &t.a,
                ap: ah,
                bq: &t.b,
                bp: bh,
                c: &t.c,
                split: d / 2,
            },
            None => Tab {
                aq: &t.a,
                ap: &t.a,
                bq: &t.b,
                bp: &t.b,
                c: &t.c,
                split: d,
            },
        }
    }

    fn stacked(&self) -> Coefs<'_> {
        Coefs {
            m: S,
            q: self.aq.as_flattened(),
            p: self.ap.as_flattened(),
            split: self.split,
        }
    }

    fn diag(&self, i: usize) -> Coefs<'_> {
        Coefs {
            m: 1,
            q: std::slice::from_ref(&self.aq[i][i]),
            p: std::slice::from_ref(&self.ap[i][i]),
            split: self.split,
        }
    }
}

/// Everything of a workspace except the linear algebra.
pub(crate) struct Core {
    pub settings: Settings,
    pub stats: Stats,
    pub d: usize,
    pub s: usize,
    /// Stage increments `Zᵢ = Yᵢ − z`, stage after stage (`s·d`).
    zs: Vec<f64>,
    /// Starting values of the current step.
    z0: Vec<f64>,
    /// `F(Yᵢ)`.
    f: Vec<f64>,
    /// `F(Yᵢ)` of the previous step, for the extrapolation.
    f_prev: Vec<f64>,
    /// Residuals and corrections.
    res: Vec<f64>,
    /// A stage value `z + Zᵢ`.
    y: Vec<f64>,
    /// The explicit part of a DIRK stage.
    r: Vec<f64>,
    /// The state the previous step left, to know whether its history applies.
    z_end: Vec<f64>,
    /// Kahan compensation of the update.
    comp: Vec<f64>,
    h_prev: f64,
    history: bool,
    /// The table the caches were made for.
    key: Vec<f64>,
    distinct_c: bool,
    /// `∫₀ˣ ℓⱼ = Σₖ lagrange[j·s + k]·x^{k+1}`.
    lagrange: Vec<f64>,
    /// `βᵢⱼ` for the `q` and the `p` components (`2·s·s`).
    beta: Vec<f64>,
    beta_r: f64,
    /// What the symplectic-form iteration keeps between steps.
    form_scratch: FormScratch,
    /// The symplectic form of the table, if it has one.
    form: Option<SymplecticForm>,
    /// Counts the calls of `step`: a Jacobian stamped with the current one
    /// is fresh.
    pub attempt: u64,
    /// `Solver::Auto` has fallen back to Newton.
    newton_sticky: bool,
}

impl Core {
    pub fn new(d: usize, s: usize) -> Self {
        let n = d * s;
        Core {
            settings: Settings::default(),
            stats: Stats::default(),
            d,
            s,
            zs: vec![0.0; n],
            z0: vec![0.0; n],
            f: vec![0.0; n],
            f_prev: vec![0.0; n],
            res: vec![0.0; n],
            y: vec![0.0; d],
            r: vec![0.0; d],
            z_end: vec![0.0; d],
            comp: vec![0.0; d],
            h_prev: 0.0,
            history: false,
            key: Vec::with_capacity(2 * s * s + 3 * s),
            distinct_c: false,
            lagrange: vec![0.0; s * s],
            beta: vec![0.0; 2 * s * s],
            beta_r: f64::NAN,
            form_scratch: FormScratch::new(d),
            form: None,
            attempt: 0,
            newton_sticky: false,
        }
    }

    /// Forget the previous steps (starting values, compensation).
    pub fn reset(&mut self) {
        self.history = false;
        self.comp.fill(0.0);
        self.key.clear();
        self.newton_sticky = false;
    }

    /// Recompute what depends on the table when it is not the one the
    /// caches were made for.
    fn sync_table<L: Caches, const S: usize>(&mut self, t: &ImplicitTable<S>, lin: &mut L) {
        let hat = t
            .a_hat
            .iter()
            .flat_map(|(ah, bh)| ah.iter().flatten().chain(bh.iter()));
        let entries = || {
            t.a.iter()
                .flatten()
                .chain(t.b.iter())
                .chain(t.c.iter())
                .chain(hat.clone())
                .copied()
        };
        let len = S * S + 2 * S + t.a_hat.map_or(0, |_| S * S + S);
        if self.key.len() == len
            && entries()
                .zip(&self.key)
                .all(|(x, y)| x.to_bits() == y.to_bits())
        {
            return;
        }
        lin.clear();
        self.key.clear();
        self.key.extend(entries());
        self.history = false;
        self.beta_r = f64::NAN;
        self.form = symplectic_form(t);
        let s = S;
        self.distinct_c = (0..s).all(|i| (0..i).all(|j| (t.c[i] - t.c[j]).abs() > 1e-8));
        if !self.distinct_c {
            return;
        }
        // Antiderivatives of the Lagrange basis on c, in monomials.
        for j in 0..s {
            let poly = &mut self.lagrange[j * s..(j + 1) * s];
            poly.fill(0.0);
            poly[0] = 1.0;
            for (deg, m) in (0..s).filter(|&m| m != j).enumerate() {
                let den = t.c[j] - t.c[m];
                for k in (0..=deg + 1).rev() {
                    let lower = if k > 0 { poly[k - 1] } else { 0.0 };
                    poly[k] = (lower - t.c[m] * poly[k]) / den;
                }
            }
            for (k, x) in poly.iter_mut().enumerate() {
                *x /= (k + 1) as f64;
            }
        }
    }

    /// Fill `z0` with the starting values; `true` when they are
    /// extrapolated from the previous step.
    fn predict<const S: usize>(&mut self, tab: &Tab<S>, h: f64, history: bool) -> bool {
        let r = h / self.h_prev;
        if !(self.settings.extrapolate && history && self.distinct_c && r.is_finite() && r > 0.0) {
            self.z0.fill(0.0);
            return false;
        }
        let (s, d) = (S, self.d);
        if r.to_bits() != self.beta_r.to_bits() {
            for i in 0..s {
                let x = 1.0 + r * tab.c[i];
                for j in 0..s {
                    let poly = &self.lagrange[j * s..(j + 1) * s];
                    let integral = poly.iter().rev().fold(0.0, |acc, &p| acc * x + p) * x;
                    self.beta[i * s + j] = integral - tab.bq[j];
                    self.beta[s * s + i * s + j] = integral - tab.bp[j];
                }
            }
            self.beta_r = r;
        }
        let hp = self.h_prev;
        for i in 0..s {
            let z0 = &mut self.z0[i * d..(i + 1) * d];
            for (k, x) in z0.iter_mut().enumerate() {
                let beta = if k < tab.split {
                    &self.beta[i * s..(i + 1) * s]
                } else {
                    &self.beta[s * s + i * s..s * s + (i + 1) * s]
                };
                let mut acc = 0.0;
                for (j, bij) in beta.iter().enumerate() {
                    acc += bij * self.f_prev[j * d + k];
                }
                *x = hp * acc;
            }
        }
        true
    }

    /// `F(Yᵢ)` at `Yᵢ = z + Zᵢ`; `false` when not finite.
    #[inline]
    fn eval_stage<Sys: OdeSystem + ?Sized, const S: usize>(
        &mut self,
        tab: &Tab<S>,
        sys: &Sys,
        t: f64,
        h: f64,
        z: &[f64],
        i: usize,
    ) -> bool {
        let d = self.d;
        let zi = &self.zs[i * d..(i + 1) * d];
        for ((y, &zk), &zik) in self.y.iter_mut().zip(z).zip(zi) {
            *y = zk + zik;
        }
        let fi = &mut self.f[i * d..(i + 1) * d];
        sys.rhs(t + tab.c[i] * h, &self.y, fi);
        self.stats.rhs_evaluations += 1;
        fi.iter().all(|x| x.is_finite())
    }

    /// Make sure a Jacobian is there; `true` when it is from this step.
    fn ensure_jacobian<Sys: ?Sized, L: Linear<Sys>>(
        &mut self,
        sys: &Sys,
        t: f64,
        z: &[f64],
        lin: &mut L,
    ) -> Result<bool, SolveError> {
        if lin.version() > 0 && lin.stamp() == self.attempt {
            return Ok(true);
        }
        if lin.version() == 0 || !self.settings.reuse_jacobian {
            lin.evaluate(sys, t, z, self.attempt, &self.settings, &mut self.stats)?;
            return Ok(true);
        }
        Ok(false)
    }

    /// `prepare`, retrying with a fresh Jacobian when a kept one gives a
    /// singular matrix.
    #[allow(clippy::too_many_arguments)]
    fn prepare<Sys: ?Sized, L: Linear<Sys>>(
        &mut self,
        sys: &Sys,
        t: f64,
        z: &[f64],
        lin: &mut L,
        slot: Slot,
        coefs: &Coefs,
        h: f64,
        fresh: &mut bool,
    ) -> Result<(), SolveError> {
        match lin.prepare(sys, slot, coefs, h, &self.settings, &mut self.stats) {
            Err(SolveError::Singular) if !*fresh => {
                lin.evaluate(sys, t, z, self.attempt, &self.settings, &mut self.stats)?;
                *fresh = true;
                lin.prepare(sys, slot, coefs, h, &self.settings, &mut self.stats)
            }
            other => other,
        }
    }

    /// Simplified Newton on all stages at once.
    fn newton_stacked<Sys: OdeSystem + ?Sized, L: Linear<Sys>, const S: usize>(
        &mut self,
        tab: &Tab<S>,
        sys: &Sys,
        t: f64,
        h: f64,
        z: &[f64],
        lin: &mut L,
    ) -> Result<(), SolveError> {
        let d = self.d;
        self.zs.copy_from_slice(&self.z0);
        // Explicit stages (a zero row of A, or of Â for the p part) have
        // Zᵢ = 0 exactly. Solving for them anyway leaves round-off in
        // corrections of components that are exactly zero, which no relative
        // test can call converged (Lobatto IIIA's first stage).
        let explicit = |i: usize, k: usize| {
            let row = if k < tab.split {
                &tab.aq[i]
            } else {
                &tab.ap[i]
            };
            row.iter().all(|&a| a == 0.0)
        };
        let zero_explicit = |v: &mut [f64]| {
            for i in 0..S {
                for k in 0..d {
                    if explicit(i, k) {
                        v[i * d + k] = 0.0;
                    }
                }
            }
        };
        zero_explicit(&mut self.zs);
        let mut fresh = self.ensure_jacobian(sys, t, z, lin)?;
        let coefs = tab.stacked();
        self.prepare(sys, t, z, lin, Slot::Stacked, &coefs, h, &mut fresh)?;
        let mut mon = Monitor::new();
        let mut updates = 0;
        loop {
            let mut finite = true;
            for i in 0..S {
                finite &= self.eval_stage(tab, sys, t, h, z, i);
            }
            let sweep = if finite {
                // −G(Z) = h·(A⊗I)·F − Z
                for i in 0..S {
                    for k in 0..d {
                        let row = if k < tab.split {
                            &tab.aq[i]
                        } else {
                            &tab.ap[i]
                        };
                        let mut acc = 0.0;
                        for (j, aij) in row.iter().enumerate() {
                            acc += aij * self.f[j * d + k];
                        }
                        self.res[i * d + k] = h * acc - self.zs[i * d + k];
                    }
                }
                lin.solve(Slot::Stacked, &mut self.res, &self.settings)?;
                zero_explicit(&mut self.res);
                let mut norms = Norms::new();
                for k in 0..d {
                    for i in 0..S {
                        let old = self.zs[i * d + k];
                        let new = old + self.res[i * d + k];
                        self.zs[i * d + k] = new;
                        norms.add(z[k], old, new);
                    }
                    norms.end_component();
                }
                norms.result()
            } else {
                Sweep::INFINITE
            };
            self.stats.newton_iterations += 1;
            let updatable = fresh && updates < self.settings.jacobian_updates;
            match mon.check(sweep, &self.settings, !fresh, updatable) {
                Verdict::Continue => {}
                Verdict::Converged => return Ok(()),
                Verdict::Fail(e) => return Err(e),
                Verdict::Update => {
                    // J at the mean of the current stage values.
                    let scale = 1.0 / S as f64;
                    for k in 0..d {
                        let mut acc = 0.0;
                        for i in 0..S {
                            acc += self.zs[i * d + k];
                        }
                        self.y[k] = z[k] + scale * acc;
                    }
                    let tc = t + h * tab.c.iter().sum::<f64>() * scale;
                    lin.evaluate(
                        sys,
                        tc,
                        &self.y,
                        self.attempt,
                        &self.settings,
                        &mut self.stats,
                    )?;
                    self.prepare(sys, t, z, lin, Slot::Stacked, &coefs, h, &mut fresh)?;
                    updates += 1;
                    mon.refreshed();
                }
                Verdict::Refresh { restart } => {
                    lin.evaluate(sys, t, z, self.attempt, &self.settings, &mut self.stats)?;
                    fresh = true;
                    self.prepare(sys, t, z, lin, Slot::Stacked, &coefs, h, &mut fresh)?;
                    if restart {
                        self.zs.copy_from_slice(&self.z0);
                        zero_explicit(&mut self.zs);
                    }
                    mon.refreshed();
                }
            }
        }
    }

    /// Fixed-point iteration on all stages at once.
    fn fixed_point_stacked<Sys: OdeSystem + ?Sized, const S: usize>(
        &mut self,
        tab: &Tab<S>,
        sys: &Sys,
        t: f64,
        h: f64,
        z: &[f64],
    ) -> Result<(), SolveError> {
        let d = self.d;
        self.zs.copy_from_slice(&self.z0);
        let mut mon = Monitor::new();
        loop {
            let mut finite = true;
            for i in 0..S {
                finite &= self.eval_stage(tab, sys, t, h, z, i);
            }
            let sweep = if finite {
                let mut norms = Norms::new();
                for k in 0..d {
                    for i in 0..S {
                        let row = if k < tab.split {
                            &tab.aq[i]
                        } else {
                            &tab.ap[i]
                        };
                        let mut acc = 0.0;
                        for (j, aij) in row.iter().enumerate() {
                            acc += aij * self.f[j * d + k];
                        }
                        let new = h * acc;
                        norms.add(z[k], self.zs[i * d + k], new);
                        self.zs[i * d + k] = new;
                    }
                    norms.end_component();
                }
                norms.result()
            } else {
                Sweep::INFINITE
            };
            self.stats.fixed_point_iterations += 1;
            match mon.check(sweep, &self.settings, false, false) {
                Verdict::Continue | Verdict::Refresh { .. } | Verdict::Update => {}
                Verdict::Converged => return Ok(()),
                Verdict::Fail(e) => return Err(e),
            }
        }
    }

    /// Lower-triangular tables, stage after stage: `Zᵢ = rᵢ + h·aᵢᵢ·F(z + Zᵢ)`
    /// with `rᵢ = h·Σⱼ₍ⱼ<ᵢ₎ aᵢⱼ·Fⱼ`, each by Newton (with the factorisation
    /// of `I − h·aᵢᵢ·J` for its diagonal value) or by fixed-point iteration.
    #[allow(clippy::too_many_arguments)]
    fn dirk<Sys: OdeSystem + ?Sized, L: Linear<Sys>, const S: usize>(
        &mut self,
        tab: &Tab<S>,
        sys: &Sys,
        t: f64,
        h: f64,
        z: &[f64],
        lin: &mut L,
        newton: bool,
        predicted: bool,
    ) -> Result<(), SolveError> {
        let d = self.d;
        let split = tab.split;
        // `None` until the first implicit stage asks for a Jacobian.
        let mut fresh: Option<bool> = None;
        for i in 0..S {
            // Explicit part.
            for k in 0..d {
                let row = if k < split { &tab.aq[i] } else { &tab.ap[i] };
                let mut acc = 0.0;
                for (j, aij) in row[..i].iter().enumerate() {
                    acc += aij * self.f[j * d + k];
                }
                self.r[k] = h * acc;
            }
            let (gq, gp) = (tab.aq[i][i], tab.ap[i][i]);
            let g = |k: usize| if k < split { gq } else { gp };
            if gq == 0.0 && gp == 0.0 {
                self.zs[i * d..(i + 1) * d].copy_from_slice(&self.r);
                if !self.eval_stage(tab, sys, t, h, z, i) {
                    return Err(SolveError::Diverged {
                        iterations: 0,
                        correction: f64::INFINITY,
                    });
                }
                continue;
            }
            // Starting value.
            if predicted {
                self.zs[i * d..(i + 1) * d].copy_from_slice(&self.z0[i * d..(i + 1) * d]);
            } else if i > 0 {
                for k in 0..d {
                    self.zs[i * d + k] = self.r[k] + h * g(k) * self.f[(i - 1) * d + k];
                }
            } else {
                self.zs[..d].copy_from_slice(&self.r);
            }
            let slot = (0..=i)
                .find(|&m| tab.aq[m][m] == gq && tab.ap[m][m] == gp)
                .unwrap_or(i);
            let coefs = tab.diag(i);
            let mut is_fresh = false;
            if newton {
                is_fresh = match fresh {
                    Some(f) => f,
                    None => self.ensure_jacobian(sys, t, z, lin)?,
                };
                self.prepare(sys, t, z, lin, Slot::Diag(slot), &coefs, h, &mut is_fresh)?;
                fresh = Some(is_fresh);
            }
            let mut mon = Monitor::new();
            let mut updates = 0;
            loop {
                let finite = self.eval_stage(tab, sys, t, h, z, i);
                let sweep = if !finite {
                    Sweep::INFINITE
                } else if newton {
                    let res = &mut self.res[i * d..(i + 1) * d];
                    for k in 0..d {
                        res[k] = self.r[k] + h * g(k) * self.f[i * d + k] - self.zs[i * d + k];
                    }
                    lin.solve(Slot::Diag(slot), res, &self.settings)?;
                    let mut norms = Norms::new();
                    for k in 0..d {
                        let old = self.zs[i * d + k];
                        let new = old + res[k];
                        self.zs[i * d + k] = new;
                        norms.add(z[k], old, new);
                        norms.end_component();
                    }
                    norms.result()
                } else {
                    let mut norms = Norms::new();
                    for k in 0..d {
                        let new = self.r[k] + h * g(k) * self.f[i * d + k];
                        norms.add(z[k], self.zs[i * d + k], new);
                        norms.end_component();
                        self.zs[i * d + k] = new;
                    }
                    norms.result()
                };
                if newton {
                    self.stats.newton_iterations += 1;
                } else {
                    self.stats.fixed_point_iterations += 1;
                }
                let updatable = newton && is_fresh && updates < self.settings.jacobian_updates;
                match mon.check(sweep, &self.settings, newton && !is_fresh, updatable) {
                    Verdict::Continue => {}
                    Verdict::Converged => break,
                    Verdict::Fail(e) => return Err(e),
                    Verdict::Update => {
                        // J at the current stage value.
                        for k in 0..d {
                            self.y[k] = z[k] + self.zs[i * d + k];
                        }
                        let ti = t + tab.c[i] * h;
                        lin.evaluate(
                            sys,
                            ti,
                            &self.y,
                            self.attempt,
                            &self.settings,
                            &mut self.stats,
                        )?;
                        self.prepare(sys, t, z, lin, Slot::Diag(slot), &coefs, h, &mut is_fresh)?;
                        updates += 1;
                        mon.refreshed();
                    }
                    Verdict::Refresh { restart } => {
                        lin.evaluate(sys, t, z, self.attempt, &self.settings, &mut self.stats)?;
                        is_fresh = true;
                        fresh = Some(true);
                        self.prepare(sys, t, z, lin, Slot::Diag(slot), &coefs, h, &mut is_fresh)?;
                        if restart {
                            self.zs[i * d..(i + 1) * d].copy_from_slice(&self.r);
                        }
                        mon.refreshed();
                    }
                }
            }
        }
        Ok(())
    }

    /// One step in the table's symplectic form: the workspace's buffers lent
    /// to [`FormSweeps`], which also updates `z`.
    fn step_symplectic<Sys: OdeSystem + ?Sized>(
        &mut self,
        sys: &Sys,
        t: f64,
        h: f64,
        z: &mut [f64],
        predicted: bool,
    ) -> Result<(), SolveError> {
        FormSweeps {
            form: self.form.as_ref().expect("a table with a symplectic form"),
            settings: &self.settings,
            stats: &mut self.stats,
            ys: &mut self.zs,
            l: &mut self.res,
            f: &mut self.f,
            z0: &self.z0,
            comp: &mut self.comp,
            scratch: &mut self.form_scratch,
            d: self.d,
            s: self.s,
        }
        .step(sys, t, h, z, predicted)
    }

    /// `z ← z + h·Σ bᵢ·F(Yᵢ)`, compensated if asked.
    fn update<const S: usize>(&mut self, tab: &Tab<S>, h: f64, z: &mut [f64]) {
        let d = self.d;
        let compensated = self.settings.compensated;
        for (k, zk) in z.iter_mut().enumerate() {
            let b = if k < tab.split { tab.bq } else { tab.bp };
            let mut acc = 0.0;
            for (i, bi) in b.iter().enumerate() {
                acc += bi * self.f[i * d + k];
            }
            let inc = h * acc;
            if compensated {
                // Kahan: comp holds what the last additions lost.
                let y = inc - self.comp[k];
                let sum = *zk + y;
                self.comp[k] = (sum - *zk) - y;
                *zk = sum;
            } else {
                *zk += inc;
            }
        }
    }
}

/// One step `z ← Ψ_h(z)`; `z` unchanged on error.
pub(crate) fn step<Sys, L, const S: usize>(
    table: &ImplicitTable<S>,
    sys: &Sys,
    t: f64,
    h: f64,
    z: &mut [f64],
    core: &mut Core,
    lin: &mut L,
) -> Result<(), SolveError>
where
    Sys: OdeSystem + ?Sized,
    L: Linear<Sys>,
{
    let d = core.d;
    assert_eq!(
        core.s, S,
        "implicit::step: the workspace was made for {} stages, the table has {S}",
        core.s
    );
    assert_eq!(
        z.len(),
        d,
        "implicit::step: the workspace was made for dimension {d}, the state has length {}",
        z.len()
    );
    assert!(
        table.a_hat.is_none() || d.is_multiple_of(2),
        "implicit::step: a partitioned table needs z = [q; p] of even length, got {d}"
    );
    core.attempt += 1;
    core.sync_table(table, lin);
    let history = core.history && core.z_end[..] == z[..];
    if !history {
        core.comp.fill(0.0);
    }
    let tab = Tab::new(table, d);
    let predicted = core.predict(&tab, h, history);
    let dirk = table.structure != Structure::Full && table.is_lower_triangular();
    let solver = match core.settings.solver {
        Solver::Auto
            if core.newton_sticky || lin.probe(sys, t, z, core.attempt, &mut core.stats) =>
        {
            Solver::Newton
        }
        Solver::Auto => Solver::FixedPoint,
        other => other,
    };
    // Symplectic tables with distinct nodes (Gauss) iterate in their
    // symplectic form and update z themselves.
    let symplectic = solver == Solver::FixedPoint
        && !dirk
        && core.settings.symplectic_form
        && core.form.is_some();
    let run = |core: &mut Core, lin: &mut L, z: &[f64], solver: Solver| match (solver, dirk) {
        (Solver::FixedPoint, true) => core.dirk(&tab, sys, t, h, z, lin, false, predicted),
        (Solver::FixedPoint, false) => core.fixed_point_stacked(&tab, sys, t, h, z),
        (_, true) => core.dirk(&tab, sys, t, h, z, lin, true, predicted),
        (_, false) => core.newton_stacked(&tab, sys, t, h, z, lin),
    };
    let mut result = if symplectic {
        core.step_symplectic(sys, t, h, z, predicted)
    } else {
        run(core, lin, z, solver)
    };
    let mut updated = symplectic && result.is_ok();
    if result.is_err() && core.settings.solver == Solver::Auto && solver == Solver::FixedPoint {
        core.newton_sticky = true;
        result = run(core, lin, z, Solver::Newton);
        updated = false;
    }
    if let Err(e) = result {
        core.stats.failures += 1;
        return Err(e);
    }
    if !updated {
        core.update(&tab, h, z);
    }
    std::mem::swap(&mut core.f, &mut core.f_prev);
    core.h_prev = h;
    core.z_end.copy_from_slice(z);
    core.history = true;
    core.stats.steps += 1;
    Ok(())
}
