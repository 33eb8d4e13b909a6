//! Symplectic collocation (Gauss–Legendre) tables for high-precision long
//! runs, in the manner of IRKGL16 (Antoñana, Makazaga and Murua, "Reducing
//! and monitoring round-off error propagation for symplectic implicit
//! Runge–Kutta schemes", Numer. Algorithms 76, 2017).
//!
//! **The symplectic form.** With `Lⱼ = h·(bⱼ·F(Yⱼ))` the step reads
//!
//! ```text
//! Yᵢ = z + Σⱼ μᵢⱼ·Lⱼ,      z ← z + Σⱼ Lⱼ,      μᵢⱼ = aᵢⱼ/bⱼ.
//! ```
//!
//! A table is symplectic iff `bᵢaᵢⱼ + bⱼaⱼᵢ − bᵢbⱼ = bᵢbⱼ(μᵢⱼ + μⱼᵢ − 1) = 0`,
//! i.e. `μᵢⱼ + μⱼᵢ = 1` (and `μᵢᵢ = ½`). Whatever the rounded `hbⱼ` are,
//! the Runge–Kutta method that the floating-point step applies (weights
//! `b̃ⱼ`, coefficients `μ̃ᵢⱼ·b̃ⱼ`) is then *exactly* symplectic when the
//! stored `μ̃ᵢⱼ + μ̃ⱼᵢ = 1` holds exactly in `f64`: the coefficient rounding
//! adds no symplecticity defect at all, only the rounding of the
//! arithmetic of each step remains. [`symplectic_form`] computes the `μᵢⱼ`
//! in double-double arithmetic and rounds each pair `(μᵢⱼ, μⱼᵢ)` so that
//! `μ̃ⱼᵢ = 1 − μ̃ᵢⱼ` exactly, both within an ulp of the larger (and,
//! for a symmetric table, so that `μ̃ₛ₊₁₋ᵢ,ₛ₊₁₋ⱼ = μ̃ⱼᵢ`: the rounded table
//! stays symmetric).
//!
//! For a Gauss–Legendre table the exact coefficients are recomputed rather
//! than taken from the `f64` table: the nodes are refined by Newton's method
//! on the Legendre polynomial `Pₛ(2c − 1)` in double-double arithmetic,
//! `bⱼ = 1/((1 − xⱼ²)·Pₛ'(xⱼ)²)`, and `aᵢⱼ = ∫₀^{cᵢ} ℓⱼ` by the Gauss
//! quadrature of the refined nodes itself (exact for the degree `s − 1` of
//! `ℓⱼ`). The table is recognised as Gauss only if its `f64` entries agree
//! with these to `1e-14`; other symplectic tables with distinct nodes get
//! their `μᵢⱼ = aᵢⱼ/bⱼ` from their `f64` entries (the pairs still sum to 1
//! exactly).
//!
//! **The iteration** (`Core::step_symplectic`, taken by
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

use super::iteration::Core;
use super::table::ImplicitTable;
use super::twofold::{Dd, fast_two_sum, two_sum};
use crate::error::SolveError;
use crate::system::OdeSystem;

/// How the coefficients of a [`SymplecticForm`] were obtained.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FormSource {
    /// Recomputed in double-double arithmetic from the Gauss–Legendre
    /// nodes, refined from the table's `c` (the table's `f64` entries agree
    /// with them to `1e-14`).
    GaussNodes,
    /// `μᵢⱼ = aᵢⱼ/bⱼ` from the table's `f64` entries (in double-double).
    Table,
}

/// The symplectic form `(μ, b, c)` of a symplectic Runge–Kutta table with
/// distinct nodes (see the [module documentation](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct SymplecticForm {
    /// `μᵢⱼ ≈ aᵢⱼ/bⱼ`, row-major `s × s`; `μᵢᵢ = ½` and, when [`exact`](Self::exact),
    /// `μᵢⱼ + μⱼᵢ = 1` exactly in `f64`.
    pub mu: Vec<f64>,
    /// The weights, correctly rounded (up to double-double accuracy);
    /// palindromic for a symmetric table.
    pub b: Vec<f64>,
    /// The nodes, correctly rounded (up to double-double accuracy).
    pub c: Vec<f64>,
    pub source: FormSource,
    /// The table is symmetric (`cᵢ + cₛ₊₁₋ᵢ = 1`, `aᵢⱼ + aₛ₊₁₋ᵢ,ₛ₊₁₋ⱼ = bⱼ`),
    /// and the rounding kept it so.
    pub symmetric: bool,
    /// Every pair was rounded with `μᵢⱼ + μⱼᵢ = 1` exactly. (Always found for
    /// tables whose off-diagonal `μ` lie in `[−1, 2]`, by Sterbenz's lemma.)
    pub exact: bool,
    /// The largest distance of a rounded `μᵢⱼ` from its double-double value,
    /// in ulps of the larger of `μᵢⱼ` and `μⱼᵢ`.
    pub max_error_ulps: f64,
}

/// The symplectic form of `table`, or `None` unless it is a fully implicit
/// Runge–Kutta table (not a partitioned pair) with distinct nodes, nonzero
/// weights, and `|bᵢaᵢⱼ + bⱼaⱼᵢ − bᵢbⱼ| ≤ 1e-13` (symplectic up to the
/// rounding of its `f64` entries).
pub fn symplectic_form<const S: usize>(table: &ImplicitTable<S>) -> Option<SymplecticForm> {
    if S == 0 || table.a_hat.is_some() || table.is_lower_triangular() {
        return None;
    }
    let (a, b, c) = (&table.a, &table.b, &table.c);
    let finite = a.iter().flatten().chain(b).chain(c).all(|x| x.is_finite());
    if !finite || b.contains(&0.0) {
        return None;
    }
    if !(0..S).all(|i| (0..i).all(|j| (c[i] - c[j]).abs() > 1e-8)) {
        return None;
    }
    for i in 0..S {
        for j in 0..S {
            let w = b[i] * a[i][j] + b[j] * a[j][i] - b[i] * b[j];
            if w.abs() > 1e-13 {
                return None;
            }
        }
    }
    let mirror = |i: usize| S - 1 - i;
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-14;
    let (cd, bd, ad, source) = match gauss(c) {
        Some((cd, bd, ad))
            if (0..S).all(|j| close(bd[j].to_f64(), b[j]))
                && (0..S).all(|i| (0..S).all(|j| close(ad[i][j].to_f64(), a[i][j]))) =>
        {
            (cd, bd, ad, FormSource::GaussNodes)
        }
        _ => (
            c.iter().map(|&x| Dd::from_f64(x)).collect(),
            b.iter().map(|&x| Dd::from_f64(x)).collect(),
            a.iter()
                .map(|row| row.iter().map(|&x| Dd::from_f64(x)).collect())
                .collect(),
            FormSource::Table,
        ),
    };
    let symmetric = (0..S).all(|i| {
        close(c[i] + c[mirror(i)], 1.0)
            && close(b[i], b[mirror(i)])
            && (0..S).all(|j| close(a[i][j] + a[mirror(i)][mirror(j)], b[j]))
    });
    let mut mu = vec![f64::NAN; S * S];
    let mut exact = true;
    let mut max_error_ulps: f64 = 0.0;
    for i in 0..S {
        mu[i * S + i] = 0.5;
        let m = ad[i][i] / bd[i];
        max_error_ulps = max_error_ulps.max(ulps(0.5, m));
    }
    for i in 0..S {
        for j in i + 1..S {
            if !mu[i * S + j].is_nan() {
                continue;
            }
            let m = ad[i][j] / bd[j];
            let (x, y, ok) = round_pair(m);
            exact &= ok;
            let big = larger(m).hi;
            let err = |x: f64, v: Dd| (Dd::from_f64(x) - v).to_f64().abs() / ulp(big);
            max_error_ulps = max_error_ulps.max(err(x, m)).max(err(y, Dd::ONE - m));
            mu[i * S + j] = x;
            mu[j * S + i] = y;
            if symmetric {
                // μ_{i'j'} = 1 − μᵢⱼ = μⱼᵢ and μ_{j'i'} = μᵢⱼ.
                mu[mirror(i) * S + mirror(j)] = y;
                mu[mirror(j) * S + mirror(i)] = x;
            }
        }
    }
    let mut bs: Vec<f64> = bd.iter().map(|x| x.to_f64()).collect();
    let mut cs: Vec<f64> = cd.iter().map(|x| x.to_f64()).collect();
    if symmetric {
        for i in S.div_ceil(2)..S {
            bs[i] = bs[mirror(i)];
            cs[i] = (Dd::ONE - cd[mirror(i)]).to_f64();
        }
    }
    Some(SymplecticForm {
        mu,
        b: bs,
        c: cs,
        source,
        symmetric,
        exact,
        max_error_ulps,
    })
}

/// The spacing of the doubles at `|x|`.
fn ulp(x: f64) -> f64 {
    let x = x.abs();
    if x == 0.0 {
        f64::from_bits(1)
    } else {
        x.next_up() - x
    }
}

/// `|x − m|` in ulps of `m`.
fn ulps(x: f64, m: Dd) -> f64 {
    (Dd::from_f64(x) - m).to_f64().abs() / ulp(m.hi)
}

/// The larger of `m` and `1 − m` in magnitude: the pair's errors are
/// measured in its ulps.
fn larger(m: Dd) -> Dd {
    let n = Dd::ONE - m;
    if m.hi.abs() >= n.hi.abs() { m } else { n }
}

/// Rounds the pair `(m, 1 − m)` to `(x, y)` with `x + y = 1` exactly, each
/// within an ulp of the larger of the two (a pair such as `(−0.077…,
/// 1.077…)` cannot have both sum and relative accuracy: the small entry
/// lies on the grid of the large one), the largest error as small as
/// possible; `false` (and the nearest roundings) when no such pair sums to
/// 1 exactly.
fn round_pair(m: Dd) -> (f64, f64, bool) {
    let n = Dd::ONE - m;
    let big = larger(m);
    let faithful = |v: Dd| {
        let r = v.to_f64();
        [r, r.next_up(), r.next_down()]
    };
    let mut best: Option<(f64, f64, f64)> = None;
    let mut consider = |x: f64, y: f64| {
        let (s, e) = two_sum(x, y);
        let err = |x: f64, v: Dd| (Dd::from_f64(x) - v).to_f64().abs() / ulp(big.hi);
        if s != 1.0 || e != 0.0 || err(x, m) > 1.0 || err(y, n) > 1.0 {
            return;
        }
        let score = err(x, m).max(err(y, n));
        if best.is_none_or(|(_, _, b)| score < b) {
            best = Some((x, y, score));
        }
    };
    for x in faithful(m) {
        consider(x, 1.0 - x);
    }
    for y in faithful(n) {
        consider(1.0 - y, y);
    }
    match best {
        Some((x, y, _)) => (x, y, true),
        None => (m.to_f64(), n.to_f64(), false),
    }
}

/// `(Pₛ(x), Pₛ'(x))` of the Legendre polynomial of degree `s ≥ 1`, by the
/// three-term recurrence.
fn legendre(s: usize, x: Dd) -> (Dd, Dd) {
    let (mut p0, mut p1) = (Dd::ONE, x);
    for n in 1..s {
        let nf = n as f64;
        let p2 = (x * p1 * (2.0 * nf + 1.0) - p0 * nf) / (nf + 1.0);
        p0 = p1;
        p1 = p2;
    }
    // Pₛ' = s·(x·Pₛ − Pₛ₋₁)/(x² − 1).
    let dp = (x * p1 - p0) * (s as f64) / (x * x - Dd::ONE);
    (p1, dp)
}

/// The Gauss–Legendre nodes, weights and coefficients on `[0, 1]` in
/// double-double, the nodes refined from `c`; `None` when some `cᵢ` is not
/// within `4e-15` of a root of `Pₛ(2x − 1)`.
#[allow(clippy::type_complexity)]
fn gauss(c: &[f64]) -> Option<(Vec<Dd>, Vec<Dd>, Vec<Vec<Dd>>)> {
    let s = c.len();
    let mut nodes = Vec::with_capacity(s);
    let mut weights = Vec::with_capacity(s);
    for &ci in c {
        if !(ci > 0.0 && ci < 1.0) {
            return None;
        }
        // 2c is exact; x = 2c − 1 in double-double.
        let mut x = Dd::from_f64(2.0 * ci) - Dd::ONE;
        for _ in 0..6 {
            let (p, dp) = legendre(s, x);
            let step = p / dp;
            x = x - step;
            if step.hi.abs() <= 1e-34 {
                break;
            }
        }
        let node = (Dd::ONE + x) * 0.5;
        if (node - Dd::from_f64(ci)).to_f64().abs() > 4e-15 {
            return None;
        }
        let (_, dp) = legendre(s, x);
        weights.push(Dd::ONE / ((Dd::ONE - x * x) * dp * dp));
        nodes.push(node);
    }
    // aᵢⱼ = ∫₀^{cᵢ} ℓⱼ = cᵢ·Σₖ bₖ·ℓⱼ(cᵢ·cₖ).
    let lagrange = |j: usize, x: Dd| {
        let mut v = Dd::ONE;
        for m in (0..s).filter(|&m| m != j) {
            v = v * (x - nodes[m]) / (nodes[j] - nodes[m]);
        }
        v
    };
    let a = (0..s)
        .map(|i| {
            (0..s)
                .map(|j| {
                    let mut acc = Dd::ZERO;
                    for k in 0..s {
                        acc = acc + weights[k] * lagrange(j, nodes[i] * nodes[k]);
                    }
                    nodes[i] * acc
                })
                .collect()
        })
        .collect();
    Some((nodes, weights, a))
}

impl Core {
    /// One step in the symplectic form (see the [module documentation](self)):
    /// fixed-point iteration to round-off, then the compensated update of
    /// `z`. `predicted`: `z0` holds the extrapolated increments.
    pub(super) fn step_symplectic<Sys: OdeSystem + ?Sized>(
        &mut self,
        sys: &Sys,
        t: f64,
        h: f64,
        z: &mut [f64],
        predicted: bool,
    ) -> Result<(), SolveError> {
        let (d, s) = (self.d, self.s);
        let form = self.form.as_ref().expect("a table with a symplectic form");
        let (mu, b, c) = (&form.mu[..], &form.b[..], &form.c[..]);
        let (ys, l, f) = (&mut self.zs, &mut self.res, &mut self.f);
        let (e, dmin, stats) = (&mut self.e, &mut self.dmin, &mut self.stats);
        // The compensation: the state is z + e (`comp` holds −e); none
        // without `Settings::compensated`.
        let compensated = self.settings.compensated;
        for k in 0..d {
            e[k] = if compensated { -self.comp[k] } else { 0.0 };
        }
        for i in 0..s {
            for k in 0..d {
                let inc = if predicted { self.z0[i * d + k] } else { 0.0 };
                ys[i * d + k] = z[k] + (e[k] + inc);
            }
        }
        let eval = |ys: &[f64], f: &mut [f64], stats: &mut super::Stats| -> bool {
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
        let cap = self.settings.max_iterations.max(1);
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
            } else if rel <= self.settings.stagnation_limit {
                break;
            }
            if rel > 2.0 * rel1 && rel1 > 2.0 * rel2 && rel > self.settings.stagnation_limit {
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
            self.comp[k] = -lo;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gauss2() -> ImplicitTable<2> {
        let r = 3f64.sqrt() / 6.0;
        ImplicitTable::new(
            [[0.25, 0.25 - r], [0.25 + r, 0.25]],
            [0.5, 0.5],
            [0.5 - r, 0.5 + r],
        )
    }

    #[test]
    fn gauss2_form_against_independent_digits() {
        let form = symplectic_form(&gauss2()).expect("Gauss 2 is symplectic");
        assert_eq!(form.source, FormSource::GaussNodes);
        assert!(form.symmetric && form.exact);
        // μ₁₂ = 1/2 − √3/3, μ₂₁ = 1/2 + √3/3; c = 1/2 ∓ √3/6 (40 digits).
        let mu12: f64 = "-0.07735026918962576450914878050195745564760"
            .parse()
            .unwrap();
        let mu21: f64 = "1.077350269189625764509148780501957455648".parse().unwrap();
        let c1: f64 = "0.2113248654051871177454256097490212721762"
            .parse()
            .unwrap();
        // μ₁₂ lies on the grid of μ₂₁ = 1 − μ₁₂: within an ulp of μ₂₁.
        assert!((form.mu[1] - mu12).abs() <= ulp(mu21), "{}", form.mu[1]);
        assert!((form.mu[2] - mu21).abs() <= ulp(mu21), "{}", form.mu[2]);
        assert_eq!(form.mu[1] + form.mu[2], 1.0);
        assert_eq!(two_sum(form.mu[1], form.mu[2]).1, 0.0);
        assert_eq!(form.c[0], c1);
        assert_eq!(form.b, vec![0.5, 0.5]);
        assert!(form.max_error_ulps <= 1.0);
    }

    #[test]
    fn non_gauss_tables() {
        // A perturbed node is not Gauss: the form comes from the table.
        let mut t = gauss2();
        t.c[0] += 1e-12;
        t.c[1] -= 1e-12;
        let form = symplectic_form(&t).expect("still symplectic");
        assert_eq!(form.source, FormSource::Table);
        // Radau IIA 2 is not symplectic; DIRK and explicit tables have none.
        let radau = ImplicitTable::new(
            [[5.0 / 12.0, -1.0 / 12.0], [0.75, 0.25]],
            [0.75, 0.25],
            [1.0 / 3.0, 1.0],
        );
        assert!(symplectic_form(&radau).is_none());
        let dirk = ImplicitTable::new([[0.25, 0.0], [0.5, 0.25]], [0.5, 0.5], [0.25, 0.75]);
        assert!(symplectic_form(&dirk).is_none());
    }

    #[test]
    fn legendre_nodes_in_double_double() {
        // P₈'s largest root on [−1, 1]: 0.9602898564975362316835608685694729904282.
        let x = Dd::from_f64(0.9602898564975362);
        let mut x = x;
        for _ in 0..4 {
            let (p, dp) = legendre(8, x);
            x = x - p / dp;
        }
        let want: f64 = "0.9602898564975362316835608685694729904282"
            .parse()
            .unwrap();
        assert_eq!(x.to_f64(), want);
        // Its weight: 0.1012285362903762591525313543099621901154.
        let (_, dp) = legendre(8, x);
        let w = (Dd::from_f64(2.0) / ((Dd::ONE - x * x) * dp * dp)).to_f64();
        let want: f64 = "0.1012285362903762591525313543099621901154"
            .parse()
            .unwrap();
        assert_eq!(w, want);
    }
}
