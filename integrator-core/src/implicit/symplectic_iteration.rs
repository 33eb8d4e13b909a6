//! The fixed-point iteration of a symplectic table in its symplectic form
//! (`Yᵢ = z + Σⱼ μᵢⱼ·Lⱼ`, `Lⱼ = h·bⱼ·F(Yⱼ)`; the form itself, `μ` rounded so
//! that `μᵢⱼ + μⱼᵢ = 1` exactly, is [`collocation`](super::collocation)'s),
//! in the manner of IRKGL16. The stage solver (`iteration.rs`) lends it the
//! workspace's buffers for one step; this module knows nothing of the
//! solver's other paths.
//!
//! **The iteration** ([`FormSweeps::step`], taken by
//! [`Solver::FixedPoint`](super::Solver::FixedPoint), and by
//! [`Solver::Auto`](super::Solver::Auto) when the system has no Jacobian,
//! for tables with a symplectic form, unless
//! [`Settings::symplectic_form`](super::Settings::symplectic_form) is off):
//!
//! * starting values from the previous step's collocation polynomial,
//!   extrapolated to the new nodes (`Yᵢ⁽⁰⁾ = z + e + Σⱼ νᵢⱼ·Lⱼ` of the
//!   previous step, rescaled when `h` changes);
//! * fixed-point sweeps `Yᵢ ← z + (e + Σⱼ μᵢⱼ·Lⱼ)` until the stage values
//!   stop changing: a sweep that changes no stage value ends the
//!   iteration; so do two sweeps in a row in which no component's largest
//!   change `maxᵢ|ΔYᵢₖ|` falls below its smallest so far (the stagnation
//!   test: the iteration has reached round-off). The cap
//!   ([`Settings::max_iterations`](super::Settings::max_iterations)) while
//!   the changes still decrease is
//!   [`SolveError::NotConverged`](crate::SolveError::NotConverged); changes
//!   that double twice in a row above round-off are
//!   [`SolveError::Diverged`](crate::SolveError::Diverged) (a stiff
//!   problem: [`Solver::Auto`](super::Solver::Auto) then retries the step
//!   with simplified Newton and keeps Newton);
//! * `F` is evaluated once more at the final stage values if the last sweep
//!   moved them, so that the update uses the converged stages;
//! * compensated summation (unless
//!   [`Settings::compensated`](super::Settings::compensated) is off): the
//!   state is carried as `z + e` in double-double, `(z, e) ← (z + e) + Σⱼ Lⱼ`
//!   (TwoSum), and the stage values include `e`; round-off in `z` then
//!   grows like `√n`.

// The kernels index stage blocks of several buffers with one index.
#![allow(clippy::needless_range_loop)]

use super::collocation::SymplecticForm;
use super::settings::{Settings, Stats};
use super::twofold::{fast_two_sum, two_sum};
use crate::error::SolveError;
use crate::system::OdeSystem;

/// What the iteration keeps between steps besides the workspace's stage
/// buffers: the compensation `e` (state `z + e`) and the running minima of
/// the stage changes (`d` each).
pub(super) struct FormScratch {
    e: Vec<f64>,
    dmin: Vec<f64>,
}

impl FormScratch {
    pub(super) fn new(d: usize) -> Self {
        FormScratch {
            e: vec![0.0; d],
            dmin: vec![0.0; d],
        }
    }
}

/// One step's view of the workspace: the table's form and the buffers the
/// iteration works in (`s·d` for the stage buffers, `d` for `comp`).
pub(super) struct FormSweeps<'a> {
    pub form: &'a SymplecticForm,
    pub settings: &'a Settings,
    pub stats: &'a mut Stats,
    /// Stage values `Yᵢ`.
    pub ys: &'a mut [f64],
    /// `Lᵢ = h·bᵢ·F(Yᵢ)`.
    pub l: &'a mut [f64],
    /// `F(Yᵢ)`; on success, those of the converged stages.
    pub f: &'a mut [f64],
    /// Extrapolated increments (read when `predicted`).
    pub z0: &'a [f64],
    /// The compensation carried across steps (holds `−e`).
    pub comp: &'a mut [f64],
    pub scratch: &'a mut FormScratch,
    pub d: usize,
    pub s: usize,
}

impl FormSweeps<'_> {
    /// One step in the symplectic form (see the [module documentation](self)):
    /// fixed-point iteration to round-off, then the compensated update of
    /// `z`. `predicted`: `z0` holds the extrapolated increments.
    pub(super) fn step<Sys: OdeSystem + ?Sized>(
        self,
        sys: &Sys,
        t: f64,
        h: f64,
        z: &mut [f64],
        predicted: bool,
    ) -> Result<(), SolveError> {
        let FormSweeps {
            form,
            settings,
            stats,
            ys,
            l,
            f,
            z0,
            comp,
            scratch,
            d,
            s,
        } = self;
        let (mu, b, c) = (&form.mu[..], &form.b[..], &form.c[..]);
        let (e, dmin) = (&mut scratch.e[..], &mut scratch.dmin[..]);
        // The compensation: the state is z + e (`comp` holds −e); none
        // without `Settings::compensated`.
        let compensated = settings.compensated;
        for k in 0..d {
            e[k] = if compensated { -comp[k] } else { 0.0 };
        }
        for i in 0..s {
            for k in 0..d {
                let inc = if predicted { z0[i * d + k] } else { 0.0 };
                ys[i * d + k] = z[k] + (e[k] + inc);
            }
        }
        let eval = |ys: &[f64], f: &mut [f64], stats: &mut Stats| -> bool {
            let mut finite = true;
            for i in 0..s {
                let fi = &mut f[i * d..(i + 1) * d];
                sys.rhs(t + c[i] * h, &ys[i * d..(i + 1) * d], fi);
                stats.rhs_evaluations += 1;
                finite &= fi.iter().all(|x| x.is_finite());
            }
            finite
        };
        dmin.fill(f64::INFINITY);
        let cap = settings.max_iterations.max(1);
        let (mut sweeps, mut plus, mut moved) = (0usize, true, true);
        let (mut rel1, mut rel2) = (f64::INFINITY, f64::INFINITY);
        let mut result = Ok(());
        loop {
            if !eval(ys, f, stats) {
                result = Err(SolveError::Diverged {
                    iterations: sweeps,
                    correction: f64::INFINITY,
                });
                break;
            }
            sweeps += 1;
            for i in 0..s {
                let hb = h * b[i];
                for k in 0..d {
                    l[i * d + k] = hb * f[i * d + k];
                }
            }
            let (mut decreased, mut rel) = (false, 0.0f64);
            moved = false;
            for k in 0..d {
                let mut dy: f64 = 0.0;
                let mut scale = z[k].abs();
                for i in 0..s {
                    let row = &mu[i * s..(i + 1) * s];
                    let mut acc = e[k];
                    // Plain multiply–add: `mul_add` is a libm call on
                    // targets built without FMA, and one rounding more per
                    // term is far below the round-off of the state.
                    for j in 0..s {
                        acc += row[j] * l[j * d + k];
                    }
                    let new = z[k] + acc;
                    let old = ys[i * d + k];
                    let diff = (new - old).abs();
                    dy = dy.max(diff);
                    scale = scale.max(new.abs());
                    ys[i * d + k] = new;
                }
                if dy > 0.0 {
                    rel = rel.max(dy / scale);
                    moved = true;
                    if dy < dmin[k] {
                        dmin[k] = dy;
                        decreased = true;
                    }
                }
            }
            if !rel.is_finite() {
                result = Err(SolveError::Diverged {
                    iterations: sweeps,
                    correction: f64::INFINITY,
                });
                break;
            }
            if !moved {
                break;
            }
            if decreased {
                plus = true;
            } else if plus {
                plus = false;
            } else if rel <= settings.stagnation_limit {
                break;
            }
            if rel > 2.0 * rel1 && rel1 > 2.0 * rel2 && rel > settings.stagnation_limit {
                result = Err(SolveError::Diverged {
                    iterations: sweeps,
                    correction: rel,
                });
                break;
            }
            if sweeps >= cap {
                result = Err(SolveError::NotConverged {
                    iterations: sweeps,
                    correction: rel,
                });
                break;
            }
            rel2 = rel1;
            rel1 = rel;
        }
        stats.fixed_point_iterations += sweeps;
        result?;
        if moved && !eval(ys, f, stats) {
            return Err(SolveError::Diverged {
                iterations: sweeps,
                correction: f64::INFINITY,
            });
        }
        // (z, e) ← (z + e) + Σⱼ Lⱼ.
        for k in 0..d {
            let mut sum = 0.0;
            for i in 0..s {
                sum += (h * b[i]) * f[i * d + k];
            }
            if !compensated {
                z[k] += sum;
                continue;
            }
            let (hi, lo) = two_sum(z[k], sum);
            let (hi, lo) = fast_two_sum(hi, lo + e[k]);
            z[k] = hi;
            comp[k] = -lo;
        }
        Ok(())
    }
}
