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
//! The fixed-point iteration that steps a table in this form is
//! in `implicit/symplectic_iteration.rs`; this module only
//! computes the form.

// The kernels index stage blocks of several buffers with one index.
#![allow(clippy::needless_range_loop)]

use super::table::ImplicitTable;
use super::twofold::{Dd, two_sum};

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
