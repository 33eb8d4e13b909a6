//! The multi-start solver, in `f64`: Levenberg–Marquardt onto the
//! conditions from each start, then, where unknowns are left free, the
//! objective (the sum of squares of the error terms) minimised on the
//! condition manifold by projected Gauss–Newton: a step of the linearised
//! problem `min |e + J_e·dx|² + μ|dx|²` subject to `F + J_F·dx = 0` (a
//! small KKT system), pulled back onto `F = 0` by minimum-norm Newton steps,
//! accepted when the objective decreases, with `μ` adapted as in
//! Levenberg–Marquardt. Every Jacobian is the exact derivative of the
//! condition polynomials, compiled to `f64`.
//!
//! **Deterministic.** The starts come from one SplitMix64 stream seeded by
//! the family's seed, one start after another on one thread; the solutions
//! are deduplicated and ranked in that order, so a seed gives the same
//! solutions, bit for bit, every run. **Bounded.** No start begins after the
//! family's `max_seconds`; the result says whether the cap stopped the
//! search.

// The normal equations and KKT systems index J and its transpose together,
// as the formulas do.
#![allow(clippy::needless_range_loop)]

use std::time::{Duration, Instant};

use crate::conditions::System;
use crate::family::Family;
use crate::linalg::{pivot_columns, solve_f64};
use crate::poly::FPoly;

/// Where the search stands, for a progress bar.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// Starts run so far.
    pub done: usize,
    /// Starts asked for.
    pub total: usize,
    /// Distinct solutions so far.
    pub found: usize,
}

/// One real solution of the conditions (a local minimum of the objective on
/// them, when unknowns are free).
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    /// The unknowns, in [`System::names`]' order.
    pub x: Vec<f64>,
    /// `max |F_i(x)|`.
    pub residual: f64,
    /// `Σ e_j(x)²` over the error terms of degree `p + 1`.
    pub objective: f64,
    /// The effective error `s · (Σ e_j²)^{1/(2p)}` (see [`effective_error`]).
    pub effective_error: f64,
    /// How many starts ended here.
    pub hits: usize,
    /// The rank of the conditions' Jacobian here (full: the number of
    /// conditions).
    pub rank: usize,
    /// The stability threshold `x* = hω` at the `f64` unknowns
    /// ([`crate::stability::CompiledFlows`]), with
    /// `objective = "stability"`; `None` otherwise.
    pub threshold: Option<f64>,
}

/// How many of the error search's solutions `objective = "stability"`
/// starts its maximisation from (the best by the error first).
pub const STABILITY_STARTS: usize = 16;

/// The outcome of a search.
#[derive(Clone, Debug)]
pub struct Search {
    /// Distinct solutions, best objective first.
    pub solutions: Vec<Solution>,
    pub starts_run: usize,
    /// Starts that converged onto the conditions.
    pub converged: usize,
    /// The time cap stopped the search before every start ran.
    pub capped: bool,
    pub elapsed: Duration,
}

/// SplitMix64 (Steele, Lea & Flood 2014): a tiny generator whose stream is
/// fixed by its seed on every platform, so the starts need no dependency.
pub struct SplitMix64(u64);

impl SplitMix64 {
    pub fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[-r, r)`.
    pub fn symmetric(&mut self, r: f64) -> f64 {
        let u = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        r * (2.0 * u - 1.0)
    }
}

/// The effective error `E_f = s·(Σ e_j²)^{1/(2p)}` of a method with `s`
/// stages and order `p` whose error terms of degree `p + 1` are `e_j`: the
/// leading local error per unit of work, as methods with different numbers
/// of stages are compared in the literature (McLachlan 1995; Blanes & Moan
/// 2002 write `E_f = s·E_{p+1}^{1/p}` with `E_{p+1}` the Euclidean norm of
/// the error coefficients). Here the coefficients are those of the Lyndon
/// words in `log Φ`; a paper's basis of the Lie algebra may weight them
/// differently, which can move the minimiser when unknowns are free.
pub fn effective_error(stages: usize, order: usize, objective: f64) -> f64 {
    stages as f64 * objective.sqrt().powf(1.0 / order as f64)
}

/// The system compiled for `f64`.
pub struct Compiled {
    pub f: Vec<FPoly>,
    /// `∂F_i/∂x_j`.
    pub jf: Vec<Vec<FPoly>>,
    pub e: Vec<FPoly>,
    pub je: Vec<Vec<FPoly>>,
    pub n: usize,
}

impl Compiled {
    pub fn new(system: &System) -> Compiled {
        let n = system.unknowns();
        let compile_all = |polys: Vec<&crate::poly::Poly>| -> (Vec<FPoly>, Vec<Vec<FPoly>>) {
            let f = polys.iter().map(|p| p.compile()).collect();
            let j = polys
                .iter()
                .map(|p| (0..n).map(|k| p.derivative(k).compile()).collect())
                .collect();
            (f, j)
        };
        // Each condition scaled so that its largest coefficient is 1: the
        // same solutions, but the high-degree Lie terms (coefficients of
        // order 1/n!) weigh in Levenberg–Marquardt as much as the low ones.
        let scaled: Vec<crate::poly::Poly> = system
            .conditions
            .iter()
            .map(|c| {
                let big = c
                    .poly
                    .terms()
                    .map(|(_, k)| num_traits::Signed::abs(k))
                    .max()
                    .unwrap_or_else(num_traits::One::one);
                c.poly
                    .scale(&(num_rational::BigRational::from_integer(1.into()) / big))
            })
            .collect();
        let (f, jf) = compile_all(scaled.iter().collect());
        let (e, je) = compile_all(system.error_terms.iter().map(|c| &c.poly).collect());
        Compiled { f, jf, e, je, n }
    }

    fn values(ps: &[FPoly], x: &[f64]) -> Vec<f64> {
        ps.iter().map(|p| p.eval(x)).collect()
    }

    fn jacobian(js: &[Vec<FPoly>], x: &[f64]) -> Vec<Vec<f64>> {
        js.iter()
            .map(|row| row.iter().map(|p| p.eval(x)).collect())
            .collect()
    }

    pub fn residual(&self, x: &[f64]) -> f64 {
        Self::values(&self.f, x)
            .iter()
            .fold(0.0_f64, |a, v| a.max(v.abs()))
    }

    pub fn objective(&self, x: &[f64]) -> f64 {
        let mut s = 0.0;
        for v in Self::values(&self.e, x) {
            s += v * v;
        }
        s
    }

    pub fn condition_jacobian(&self, x: &[f64]) -> Vec<Vec<f64>> {
        Self::jacobian(&self.jf, x)
    }

    /// How far `x` is from a stationary point of the objective on the
    /// conditions: the part of the objective's gradient (exact derivatives)
    /// orthogonal to the conditions' gradients, relative to the whole
    /// gradient; 0 at a constrained minimum (the Lagrange condition), 1 when
    /// the gradient is tangent to the conditions' surface.
    pub fn stationarity(&self, x: &[f64]) -> f64 {
        let e = Self::values(&self.e, x);
        let je = Self::jacobian(&self.je, x);
        let g: Vec<f64> = (0..self.n)
            .map(|k| 2.0 * e.iter().zip(&je).map(|(ei, row)| ei * row[k]).sum::<f64>())
            .collect();
        let j = self.condition_jacobian(x);
        let m = j.len();
        let mut a = vec![vec![0.0; m]; m];
        let mut rhs = vec![0.0; m];
        for p in 0..m {
            for q in 0..m {
                a[p][q] = (0..self.n).map(|k| j[p][k] * j[q][k]).sum();
            }
            rhs[p] = (0..self.n).map(|k| j[p][k] * g[k]).sum();
        }
        let lambda = if m == 0 {
            Vec::new()
        } else {
            match solve_f64(&a, &rhs) {
                Some(l) => l,
                None => return f64::NAN,
            }
        };
        let norm = |v: &[f64]| v.iter().map(|t| t * t).sum::<f64>().sqrt();
        let r: Vec<f64> = (0..self.n)
            .map(|k| g[k] - (0..m).map(|p| j[p][k] * lambda[p]).sum::<f64>())
            .collect();
        norm(&r) / norm(&g)
    }

    /// Levenberg–Marquardt on `|F|²` from `x`; the point reached.
    fn levenberg_marquardt(&self, mut x: Vec<f64>) -> Vec<f64> {
        let n = self.n;
        let mut mu = 1e-3;
        let norm2 = |v: &[f64]| v.iter().fold(0.0, |a, b| a + b * b);
        let mut fx = Self::values(&self.f, &x);
        let mut cost = norm2(&fx);
        for _ in 0..200 {
            if cost < 1e-30 || !cost.is_finite() {
                break;
            }
            let j = Self::jacobian(&self.jf, &x);
            // (JᵀJ + μ·diag) dx = −Jᵀf
            let mut a = vec![vec![0.0; n]; n];
            let mut g = vec![0.0; n];
            for (row, fi) in j.iter().zip(&fx) {
                for p in 0..n {
                    g[p] -= row[p] * fi;
                    for q in 0..n {
                        a[p][q] += row[p] * row[q];
                    }
                }
            }
            let mut accepted = false;
            for _ in 0..30 {
                let mut m = a.clone();
                for (p, row) in m.iter_mut().enumerate() {
                    row[p] += mu * (1.0 + a[p][p]);
                }
                let Some(dx) = solve_f64(&m, &g) else {
                    mu *= 10.0;
                    continue;
                };
                let trial: Vec<f64> = x.iter().zip(&dx).map(|(a, b)| a + b).collect();
                let ft = Self::values(&self.f, &trial);
                let ct = norm2(&ft);
                if ct.is_finite() && ct < cost {
                    let small = dx.iter().fold(0.0_f64, |a, v| a.max(v.abs()))
                        < 1e-15 * (1.0 + x.iter().fold(0.0_f64, |a, v| a.max(v.abs())));
                    x = trial;
                    fx = ft;
                    cost = ct;
                    mu = (mu / 3.0).max(1e-15);
                    accepted = !small;
                    break;
                }
                mu *= 10.0;
            }
            if !accepted {
                break;
            }
        }
        x
    }

    /// Minimum-norm Newton steps `dx = −J_Fᵀ(J_F J_Fᵀ)⁻¹F` back onto the
    /// conditions; `None` when they do not converge.
    /// A local maximum of the stability threshold on the conditions from
    /// `x` (on them): a compass search, each trial moved back onto the
    /// conditions, its step halved when no direction improves, down to
    /// `10⁻⁹`. The threshold is not smooth (it jumps where `|tr M/2|`
    /// reaches 1 inside the interval), which a compass search tolerates.
    pub fn maximise_stability(
        &self,
        flows: &crate::stability::CompiledFlows,
        mut x: Vec<f64>,
    ) -> Vec<f64> {
        let Some(mut best) = flows.threshold(&x) else {
            return x;
        };
        let mut step = 0.05;
        let mut trials = 0;
        while step > 1e-9 && trials < 20_000 {
            let mut improved = false;
            for k in 0..self.n {
                for sign in [1.0, -1.0] {
                    trials += 1;
                    let mut t = x.clone();
                    t[k] += sign * step;
                    let Some(t) = self.retract(t) else { continue };
                    if let Some(v) = flows.threshold(&t)
                        && v > best * (1.0 + 1e-12)
                    {
                        x = t;
                        best = v;
                        improved = true;
                    }
                }
            }
            if !improved {
                step *= 0.5;
            }
        }
        x
    }

    fn retract(&self, mut x: Vec<f64>) -> Option<Vec<f64>> {
        let m = self.f.len();
        for _ in 0..20 {
            let fx = Self::values(&self.f, &x);
            let r = fx.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
            if r < 1e-14 {
                return Some(x);
            }
            let j = Self::jacobian(&self.jf, &x);
            let mut jjt = vec![vec![0.0; m]; m];
            for p in 0..m {
                for q in 0..m {
                    let mut s = 0.0;
                    for k in 0..self.n {
                        s += j[p][k] * j[q][k];
                    }
                    jjt[p][q] = s;
                }
            }
            let neg: Vec<f64> = fx.iter().map(|v| -v).collect();
            let y = solve_f64(&jjt, &neg)?;
            for k in 0..self.n {
                let mut s = 0.0;
                for p in 0..m {
                    s += j[p][k] * y[p];
                }
                x[k] += s;
            }
            if !x.iter().all(|v| v.is_finite()) {
                return None;
            }
        }
        (self.residual(&x) < 1e-12).then_some(x)
    }

    /// Projected Gauss–Newton on the objective, from a point on the
    /// conditions.
    fn minimise(&self, mut x: Vec<f64>) -> Vec<f64> {
        let n = self.n;
        let m = self.f.len();
        let mut obj = self.objective(&x);
        let mut mu = 1e-6;
        let mut stalls = 0;
        for _ in 0..500 {
            let fx = Self::values(&self.f, &x);
            let jf = Self::jacobian(&self.jf, &x);
            let ex = Self::values(&self.e, &x);
            let je = Self::jacobian(&self.je, &x);
            let mut h = vec![vec![0.0; n]; n];
            let mut g = vec![0.0; n];
            for (row, ei) in je.iter().zip(&ex) {
                for p in 0..n {
                    g[p] -= row[p] * ei;
                    for q in 0..n {
                        h[p][q] += row[p] * row[q];
                    }
                }
            }
            let mut improved = false;
            for _ in 0..25 {
                // [H + μI, J_Fᵀ; J_F, 0] [dx; λ] = [−J_eᵀe; −F]
                let mut k = vec![vec![0.0; n + m]; n + m];
                let mut rhs = vec![0.0; n + m];
                for p in 0..n {
                    for q in 0..n {
                        k[p][q] = h[p][q];
                    }
                    k[p][p] += mu * (1.0 + h[p][p]);
                    rhs[p] = g[p];
                }
                for i in 0..m {
                    for p in 0..n {
                        k[p][n + i] = jf[i][p];
                        k[n + i][p] = jf[i][p];
                    }
                    rhs[n + i] = -fx[i];
                }
                let Some(sol) = solve_f64(&k, &rhs) else {
                    mu *= 10.0;
                    continue;
                };
                let trial: Vec<f64> = (0..n).map(|p| x[p] + sol[p]).collect();
                if let Some(t) = self.retract(trial) {
                    let ot = self.objective(&t);
                    if ot < obj {
                        let rel = (obj - ot) / obj.max(1e-300);
                        x = t;
                        obj = ot;
                        mu = (mu / 3.0).max(1e-12);
                        improved = true;
                        stalls = if rel < 1e-13 { stalls + 1 } else { 0 };
                        break;
                    }
                }
                mu *= 10.0;
                if mu > 1e12 {
                    break;
                }
            }
            if !improved || stalls >= 3 {
                break;
            }
        }
        x
    }
}

/// Run the search for a family's system.
pub fn search(system: &System, family: &Family, progress: &mut dyn FnMut(Progress)) -> Search {
    let started = Instant::now();
    let cap = Duration::from_secs_f64(family.max_seconds);
    let c = Compiled::new(system);
    let n = c.n;
    let free = n - system.conditions.len();
    let mut rng = SplitMix64::new(family.seed);
    let mut solutions: Vec<Solution> = Vec::new();
    let mut converged = 0;
    let mut starts_run = 0;
    let mut capped = false;
    for _ in 0..family.starts {
        if started.elapsed() >= cap {
            capped = true;
            break;
        }
        let x0: Vec<f64> = (0..n).map(|_| rng.symmetric(family.range)).collect();
        starts_run += 1;
        let mut x = c.levenberg_marquardt(x0);
        if c.residual(&x) < 1e-10 {
            if free > 0 && !c.e.is_empty() {
                x = c.minimise(x);
            }
            let residual = c.residual(&x);
            if residual < 1e-10 {
                converged += 1;
                record(&c, system, &mut solutions, x, residual);
            }
        }
        progress(Progress {
            done: starts_run,
            total: family.starts,
            found: solutions.len(),
        });
    }
    solutions.sort_by(|a, b| a.objective.total_cmp(&b.objective));
    if family.objective == crate::family::Objective::Stability {
        let flows = crate::stability::CompiledFlows::new(system);
        let mut moved = Vec::new();
        for s in solutions.iter().take(STABILITY_STARTS) {
            // The time cap holds here too: past it the solutions are kept
            // where the error search left them.
            let x = if free > 0 && started.elapsed() < cap {
                c.maximise_stability(&flows, s.x.clone())
            } else {
                capped |= free > 0;
                s.x.clone()
            };
            let residual = c.residual(&x);
            if residual < 1e-10 {
                record(&c, system, &mut moved, x, residual);
            }
        }
        for s in &mut moved {
            s.threshold = flows.threshold(&s.x);
        }
        moved.sort_by(|a, b| {
            b.threshold
                .unwrap_or(0.0)
                .total_cmp(&a.threshold.unwrap_or(0.0))
        });
        solutions = moved;
    }
    Search {
        solutions,
        starts_run,
        converged,
        capped,
        elapsed: started.elapsed(),
    }
}

/// Add a solution, or count a hit on one already found (the same to about
/// `1e-6` relative; the free unknowns of a minimum are only as accurate as
/// the minimisation).
fn record(c: &Compiled, system: &System, out: &mut Vec<Solution>, x: Vec<f64>, residual: f64) {
    let scale = 1.0 + x.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    for s in out.iter_mut() {
        let d =
            s.x.iter()
                .zip(&x)
                .fold(0.0_f64, |a, (p, q)| a.max((p - q).abs()));
        if d < 1e-6 * scale {
            s.hits += 1;
            // Keep the better point of the two.
            let obj = c.objective(&x);
            if obj < s.objective {
                s.objective = obj;
                s.effective_error = effective_error(system.stages, system.order, obj);
                s.x = x;
                s.residual = residual;
            }
            return;
        }
    }
    let objective = c.objective(&x);
    let rank = pivot_columns(&c.condition_jacobian(&x), 1e-10).len();
    out.push(Solution {
        effective_error: effective_error(system.stages, system.order, objective),
        x,
        residual,
        objective,
        hits: 1,
        rank,
        threshold: None,
    });
}
