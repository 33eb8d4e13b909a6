//! Generated collocation-type tables, any number of stages: Gauss–Legendre,
//! Radau IA and IIA, Lobatto IIIA, IIIB, IIIC and the Lobatto IIIA–IIIB pair,
//! built and verified exactly in the algebras of [`super::pair`].
//!
//! Every table is given by its node polynomial `P` (monic, squarefree, with
//! the nodes as roots) and three exact elements: the weights `B ∈ K`
//! (`bᵢ = B(cᵢ)`), the off-diagonal entries `A ∈ L` (`aᵢⱼ = A(cᵢ, cⱼ)`,
//! `i ≠ j`) and the diagonal `D ∈ K` (`aᵢᵢ = D(cᵢ)`).
//!
//! * Collocation (Gauss, Radau IIA, Lobatto IIIA): `aᵢⱼ = ∫₀^{cᵢ} ℓⱼ`,
//!   `bⱼ = ∫₀¹ ℓⱼ` with `ℓⱼ(t) = P(t)/((t − cⱼ)P'(cⱼ))`.
//! * Dual collocation, i.e. `D(s)` (Radau IA, Lobatto IIIB):
//!   `aᵢⱼ = bⱼ − bⱼ α_{ji}/bᵢ` with `α` the collocation matrix on the same
//!   nodes (take `q = ℓᵢ` in `D(s)`).
//! * Lobatto IIIC (`aᵢ₁ = b₁` for all `i`, and `C(s − 1)`): the collocation
//!   matrix plus a rank-one correction `g(cᵢ)·bⱼ L(cⱼ)/(b₁ L(0))` with
//!   `L = P_{s−1}(2x − 1)` (the rows of the difference are orthogonal to the
//!   polynomials of degree ≤ s − 2 under Lobatto quadrature) and
//!   `g(x) = b₁ − ∫₀ˣ ℓ₁`.

#![allow(clippy::needless_range_loop)] // index-heavy matrix code

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};
use serde::Serialize;

use super::alg::{Alg, Field};
use super::pair::{Pair, Ring};
use super::poly::{Poly, count_roots, shifted_legendre};
use super::root::{RealRoot, f64_rational, next_up};
use crate::analysis::stability::{Poly as NPoly, StabilityFunction};
use crate::rounding::F64Table;
use crate::{Number, Rk};

fn q(n: i64) -> BigRational {
    BigRational::from_integer(BigInt::from(n))
}

/// The most stages a generator builds (exact work grows like s⁴–s⁵).
pub const MAX_GENERATED_STAGES: usize = 16;

/// The families.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Family {
    Gauss,
    Radau1A,
    Radau2A,
    Lobatto3A,
    Lobatto3B,
    Lobatto3C,
}

impl Family {
    pub const ALL: [Family; 6] = [
        Family::Gauss,
        Family::Radau1A,
        Family::Radau2A,
        Family::Lobatto3A,
        Family::Lobatto3B,
        Family::Lobatto3C,
    ];

    /// The generator name, as in `gauss(8)`.
    pub fn name(self) -> &'static str {
        match self {
            Family::Gauss => "gauss",
            Family::Radau1A => "radau1a",
            Family::Radau2A => "radau2a",
            Family::Lobatto3A => "lobatto3a",
            Family::Lobatto3B => "lobatto3b",
            Family::Lobatto3C => "lobatto3c",
        }
    }

    pub fn title(self) -> &'static str {
        match self {
            Family::Gauss => "Gauss–Legendre",
            Family::Radau1A => "Radau IA",
            Family::Radau2A => "Radau IIA",
            Family::Lobatto3A => "Lobatto IIIA",
            Family::Lobatto3B => "Lobatto IIIB",
            Family::Lobatto3C => "Lobatto IIIC",
        }
    }

    fn min_stages(self) -> usize {
        match self {
            Family::Gauss | Family::Radau2A => 1,
            // Radau IA with one stage has c = 0 but row sum 1.
            _ => 2,
        }
    }

    /// The node polynomial (not yet monic).
    pub fn node_polynomial(self, s: usize) -> Poly {
        let ps = shifted_legendre(s);
        match self {
            Family::Gauss => ps,
            Family::Radau2A => ps.sub(&shifted_legendre(s - 1)),
            Family::Radau1A => ps.add(&shifted_legendre(s - 1)),
            _ => ps.sub(&shifted_legendre(s - 2)),
        }
    }

    /// The order the literature gives (Hairer–Wanner II, Table IV.5.13).
    pub fn literature_order(self, s: usize) -> usize {
        match self {
            Family::Gauss => 2 * s,
            Family::Radau1A | Family::Radau2A => 2 * s - 1,
            _ => 2 * s - 2,
        }
    }
}

/// What a generator id or expression names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Generator {
    Rk(Family, usize),
    /// The Lobatto IIIA–IIIB pair (IIIA on `q`, IIIB on `p`).
    Lobatto3A3B(usize),
}

impl Generator {
    /// Parse `gauss(8)` / `lobatto3a3b(4)` (generator syntax) or the built-in
    /// ids `gauss8`, `radau2a-5`, `lobatto3a3b4` (also with a hyphen).
    pub fn parse(text: &str) -> Result<Generator, String> {
        let t = text.trim().to_lowercase();
        let (name, num) = if let Some(open) = t.find('(') {
            let Some(inner) = t[open + 1..].strip_suffix(')') else {
                return Err(format!("`{text}`: expected NAME(STAGES), e.g. gauss(8)"));
            };
            (t[..open].trim().to_string(), inner.trim().to_string())
        } else {
            let digits = t.len() - t.chars().rev().take_while(char::is_ascii_digit).count();
            if digits == t.len() {
                return Err(format!(
                    "`{text}`: no stage count (e.g. gauss8 or gauss(8))"
                ));
            }
            (
                t[..digits].trim_end_matches('-').to_string(),
                t[digits..].to_string(),
            )
        };
        let s: usize = num
            .parse()
            .map_err(|_| format!("`{text}`: the stage count `{num}` is not a positive integer"))?;
        let g = if name == "lobatto3a3b" {
            Generator::Lobatto3A3B(s)
        } else {
            let fam = Family::ALL
                .iter()
                .find(|f| f.name() == name)
                .copied()
                .ok_or_else(|| {
                    format!(
                        "`{text}`: unknown generator `{name}`; the generators are gauss, radau1a, radau2a, lobatto3a, lobatto3b, lobatto3c, lobatto3a3b"
                    )
                })?;
            Generator::Rk(fam, s)
        };
        let (fam, s) = match g {
            Generator::Rk(f, s) => (f, s),
            Generator::Lobatto3A3B(s) => (Family::Lobatto3A, s),
        };
        if s < fam.min_stages() || s > MAX_GENERATED_STAGES {
            return Err(format!(
                "`{text}`: {} needs {} ≤ s ≤ {MAX_GENERATED_STAGES} (tableau::algebraic::family::MAX_GENERATED_STAGES)",
                fam.name(),
                fam.min_stages()
            ));
        }
        Ok(g)
    }

    /// The generator expression, `gauss(8)`.
    pub fn expression(self) -> String {
        match self {
            Generator::Rk(f, s) => format!("{}({s})", f.name()),
            Generator::Lobatto3A3B(s) => format!("lobatto3a3b({s})"),
        }
    }

    pub fn title(self) -> String {
        match self {
            Generator::Rk(f, s) => format!("{}, {s} stages (generated)", f.title()),
            Generator::Lobatto3A3B(s) => {
                format!("Lobatto IIIA–IIIB pair, {s} stages (generated)")
            }
        }
    }
}

/// A generated Runge–Kutta table, exactly.
#[derive(Clone, Debug)]
pub struct Method {
    pub family: Family,
    pub s: usize,
    pub ring: Ring,
    /// Weights `bᵢ = b(cᵢ)`.
    pub b: Poly,
    /// Off-diagonal `aᵢⱼ = a(cᵢ, cⱼ)`.
    pub a: Pair,
    /// Diagonal `aᵢᵢ = d(cᵢ)`.
    pub d: Poly,
    /// The nodes in increasing order, as isolated roots.
    pub nodes: Vec<RealRoot>,
}

impl Method {
    pub fn new(family: Family, s: usize) -> Method {
        assert!(s >= family.min_stages() && s <= MAX_GENERATED_STAGES);
        let p = family.node_polynomial(s).monic();
        let ring = Ring::new(&p);
        let nodes = RealRoot::isolate(&ring.p, &q(-1), &q(1));
        assert_eq!(nodes.len(), s, "the nodes lie in [0, 1]");
        let (b, a, d) = collocation(&ring);
        let (b, a, d) = match family {
            Family::Gauss | Family::Radau2A | Family::Lobatto3A => (b, a, d),
            Family::Radau1A | Family::Lobatto3B => {
                let (a2, d2) = dual(&ring, &b, &a, &d);
                (b, a2, d2)
            }
            Family::Lobatto3C => {
                let (a2, d2) = lobatto3c(&ring, &b, &a, &d);
                (b, a2, d2)
            }
        };
        Method {
            family,
            s,
            ring,
            b,
            a,
            d,
            nodes,
        }
    }
}

/// The collocation table on the nodes of `ring`.
fn collocation(ring: &Ring) -> (Poly, Pair, Poly) {
    let f = ring.lagrange_integral();
    let u = ring
        .p
        .derivative()
        .inverse_mod(&ring.p)
        .expect("squarefree");
    // Off-diagonal: F(x, y)·u(y).
    let fy = ring.reduce(f.clone());
    let a = ring.mul(&fy, &ring.from_y(&u));
    // Diagonal: F(x, x)·u(x); weights F(1, x)·u(x).
    let mut fxx = Poly::zero();
    let mut f1x = Poly::zero();
    for (j, c) in f.iter().enumerate() {
        fxx = fxx.add(&c.mul(&Poly::monomial(BigRational::one(), j)));
        f1x = f1x.add(&Poly::monomial(c.eval(&BigRational::one()), j));
    }
    let d = ring.mul1(&fxx, &u);
    let b = ring.mul1(&f1x, &u);
    (b, a, d)
}

/// `âᵢⱼ = bⱼ − bⱼ aⱼᵢ / bᵢ` (off-diagonal) and `âᵢᵢ = bᵢ − aᵢᵢ`.
fn dual(ring: &Ring, b: &Poly, a: &Pair, d: &Poly) -> (Pair, Poly) {
    let binv = b.inverse_mod(&ring.p).expect("nonzero weights");
    let by = ring.from_y(b);
    let t = ring.mul(&ring.mul(&by, &ring.swap(a)), &ring.from_x(&binv));
    (ring.sub(&by, &t), ring.r1(&b.sub(d)))
}

fn lobatto3c(ring: &Ring, b: &Poly, a: &Pair, d: &Poly) -> (Pair, Poly) {
    let s = ring.s;
    let zero = BigRational::zero();
    let b1 = b.eval(&zero);
    // ℓ₁(t) = P(t)/(t·P'(0)) for the node 0.
    let p_over_t = ring.p.divrem(&Poly::x()).0;
    let l1 = p_over_t.scale(&ring.p.derivative().eval(&zero).recip());
    let g = Poly::constant(b1.clone()).sub(&l1.integral());
    let leg = shifted_legendre(s - 1);
    let k = (&b1 * leg.eval(&zero)).recip();
    let v = ring.mul1(b, &leg).scale(&k); // bⱼ L(cⱼ)/(b₁ L(0))
    let corr = ring.mul(&ring.from_x(&g), &ring.from_y(&v));
    (ring.add(a, &corr), ring.r1(&d.add(&ring.mul1(&g, &v))))
}

/// Which proof gave the order.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct OrderProof {
    /// Order proven: at least this.
    pub lower: usize,
    /// Order proven: at most this (`B(p + 1)` fails), when known.
    pub upper: Option<usize>,
    /// The largest `p ≤ cap` with `B(p)`, `C(q)`, `D(r)`.
    pub b: usize,
    pub c: usize,
    pub d: usize,
    /// The words of the proof.
    pub text: String,
}

/// Everything decided about a generated table.
#[derive(Clone, Debug)]
pub struct Verdicts {
    pub weights_nonzero: bool,
    pub nodes_distinct: bool,
    pub row_sums_ok: bool,
    pub symplectic: bool,
    /// Off-diagonal and diagonal parts of `W` vanish (each a complete test).
    pub w_off_zero: bool,
    pub w_diag_zero: bool,
    pub symmetric: bool,
    pub order: OrderProof,
    pub stability: StabilityFunction,
    pub a_stable: bool,
    /// `R(∞)`.
    pub r_infinity: BigRational,
    pub unimodular: bool,
}

/// `C(k)` at level `k`: `Σⱼ aᵢⱼ cⱼ^{k−1} = cᵢᵏ/k` for all `i`.
fn c_level(ring: &Ring, a: &Pair, d: &Poly, k: usize) -> bool {
    let yk = ring.from_y(&Poly::monomial(BigRational::one(), k - 1));
    let xk = Poly::monomial(BigRational::one(), k - 1);
    let lhs = ring.trace_y(&ring.mul(a, &yk)).add(&ring.mul1(d, &xk));
    let rhs = Poly::monomial(q(k as i64).recip(), k);
    ring.r1(&lhs.sub(&rhs)).is_zero()
}

/// `D(k)` at level `k`: `Σᵢ bᵢ cᵢ^{k−1} aᵢⱼ = bⱼ(1 − cⱼᵏ)/k` for all `j`.
fn d_level(ring: &Ring, b: &Poly, a: &Pair, d: &Poly, k: usize) -> bool {
    let xk = Poly::monomial(BigRational::one(), k - 1);
    let bx = ring.mul1(b, &xk);
    // Σ_{i≠j} B(cᵢ)cᵢ^{k−1}A(cᵢ, cⱼ): swap so that the summed index is y.
    let g = ring.mul(&ring.from_x(&bx), a);
    let off = ring.trace_y(&ring.swap(&g));
    let lhs = off.add(&ring.mul1(&bx, d));
    let one_minus = Poly::constant(BigRational::one()).sub(&Poly::monomial(BigRational::one(), k));
    let rhs = ring.mul1(b, &one_minus).scale(&q(k as i64).recip());
    ring.r1(&lhs.sub(&rhs)).is_zero()
}

fn max_level(cap: usize, f: impl Fn(usize) -> bool) -> usize {
    (1..=cap).take_while(|&k| f(k)).last().unwrap_or(0)
}

/// `W = BA + AᵀB − bbᵀ` for the pair (A on q with weights b, Â on p with the
/// same weights): off-diagonal `b(x)â(x,y) + b(y)a(y,x) − b(x)b(y)`,
/// diagonal `b(â + a − b)`.
pub fn w_parts(ring: &Ring, b: &Poly, a: &Pair, d: &Poly, ah: &Pair, dh: &Poly) -> (Pair, Poly) {
    let bx = ring.from_x(b);
    let by = ring.from_y(b);
    let off = ring.sub(
        &ring.add(&ring.mul(&bx, ah), &ring.mul(&by, &ring.swap(a))),
        &ring.mul(&bx, &by),
    );
    let diag = ring.mul1(b, &dh.add(d).sub(b));
    (off, diag)
}

/// The exact stability function, from the rational matrix `M` that `A` is
/// similar to (see the module docs of [`super`]).
fn stability(m: &Method) -> StabilityFunction {
    let ring = &m.ring;
    let s = m.s;
    // Column k of M: Tr_y(A·y^k) + D·x^k.
    let mut mat = vec![vec![BigRational::zero(); s]; s];
    for k in 0..s {
        let yk = ring.from_y(&Poly::monomial(BigRational::one(), k));
        let h = ring
            .trace_y(&ring.mul(&m.a, &yk))
            .add(&ring.mul1(&m.d, &Poly::monomial(BigRational::one(), k)));
        let h = ring.r1(&h);
        for (i, row) in mat.iter_mut().enumerate() {
            row[k] = h.coeff(i);
        }
    }
    let tau: Vec<BigRational> = (0..s)
        .map(|k| ring.trace(&ring.mul1(&m.b, &Poly::monomial(BigRational::one(), k))))
        .collect();
    // det(I − zM + z e₀τᵀ) and det(I − zM) at z = 0..=s, interpolated.
    let points: Vec<BigRational> = (0..=s as i64).map(q).collect();
    let mut num_vals = Vec::new();
    let mut den_vals = Vec::new();
    for z in &points {
        let base: Vec<Vec<BigRational>> = (0..s)
            .map(|i| {
                (0..s)
                    .map(|j| {
                        let id = if i == j {
                            BigRational::one()
                        } else {
                            BigRational::zero()
                        };
                        id - z * &mat[i][j]
                    })
                    .collect()
            })
            .collect();
        den_vals.push(det(base.clone()));
        let mut nm = base;
        for (j, t) in tau.iter().enumerate() {
            nm[0][j] += z * t;
        }
        num_vals.push(det(nm));
    }
    let num = interpolate(&points, &num_vals);
    let den = interpolate(&points, &den_vals);
    let g = num.gcd(&den);
    let (num, den) = (num.divrem(&g).0, den.divrem(&g).0);
    let c0 = den.coeff(0);
    let (num, den) = (num.scale(&c0.recip()), den.scale(&c0.recip()));
    let to_n = |p: &Poly| {
        NPoly(
            p.0.iter()
                .map(|c| Number::from_rational(c.clone()))
                .collect(),
        )
    };
    StabilityFunction {
        numerator: to_n(&num),
        denominator: to_n(&den),
    }
}

fn det(mut m: Vec<Vec<BigRational>>) -> BigRational {
    let n = m.len();
    let mut d = BigRational::one();
    for c in 0..n {
        let Some(p) = (c..n).find(|&r| !m[r][c].is_zero()) else {
            return BigRational::zero();
        };
        if p != c {
            m.swap(p, c);
            d = -d;
        }
        let piv = m[c][c].clone();
        d *= &piv;
        for r in c + 1..n {
            if m[r][c].is_zero() {
                continue;
            }
            let f = &m[r][c] / &piv;
            for k in c..n {
                let t = &f * &m[c][k];
                m[r][k] -= t;
            }
        }
    }
    d
}

fn interpolate(xs: &[BigRational], ys: &[BigRational]) -> Poly {
    let mut acc = Poly::zero();
    for (i, (xi, yi)) in xs.iter().zip(ys).enumerate() {
        if yi.is_zero() {
            continue;
        }
        let mut l = Poly::one();
        let mut den = BigRational::one();
        for (j, xj) in xs.iter().enumerate() {
            if j != i {
                l = l.mul(&Poly(vec![-xj.clone(), BigRational::one()]));
                den *= xi - xj;
            }
        }
        acc = acc.add(&l.scale(&(yi / den)));
    }
    acc
}

/// `p(−z)`.
fn reflect_z(p: &Poly) -> Poly {
    Poly(
        p.0.iter()
            .enumerate()
            .map(|(k, c)| if k % 2 == 1 { -c.clone() } else { c.clone() })
            .collect(),
    )
}

/// All roots of `p` have negative real part (Routh–Hurwitz, exact): every
/// first-column entry of the Routh array is nonzero and of one sign.
fn hurwitz(p: &Poly) -> bool {
    let Some(n) = p.degree() else { return false };
    let a: Vec<BigRational> = p.0.iter().rev().cloned().collect();
    let get = |v: &Vec<BigRational>, k: usize| v.get(k).cloned().unwrap_or_else(BigRational::zero);
    let mut rows: Vec<Vec<BigRational>> = vec![
        a.iter().step_by(2).cloned().collect(),
        a.iter().skip(1).step_by(2).cloned().collect(),
    ];
    while rows.len() < n + 1 {
        let l = rows.len();
        let (pr, cr) = (&rows[l - 2], &rows[l - 1]);
        if cr.is_empty() || cr[0].is_zero() {
            return false;
        }
        let next: Vec<BigRational> = (0..pr.len().saturating_sub(1).max(1))
            .map(|k| (&cr[0] * get(pr, k + 1) - &pr[0] * get(cr, k + 1)) / &cr[0])
            .collect();
        rows.push(next);
    }
    let sign0 = a[0].is_positive();
    rows.iter().take(n + 1).all(|r| {
        r.first()
            .is_some_and(|x| !x.is_zero() && x.is_positive() == sign0)
    })
}

/// `e(t) ≥ 0` for all `t ≥ 0`.
fn nonnegative_on_half_line(e: &Poly) -> bool {
    if e.is_zero() {
        return true;
    }
    if e.lead().is_negative() {
        return false;
    }
    // Odd-multiplicity part by Yun's squarefree decomposition.
    let d = e.derivative();
    let a0 = e.gcd(&d);
    let mut b = e.divrem(&a0).0;
    let mut c = d.divrem(&a0).0;
    let mut dd = c.sub(&b.derivative());
    let mut odd = Poly::one();
    let mut i = 1;
    while b.degree().unwrap_or(0) > 0 {
        let f = b.gcd(&dd);
        if i % 2 == 1 {
            odd = odd.mul(&f);
        }
        b = b.divrem(&f).0;
        c = dd.divrem(&f).0;
        dd = c.sub(&b.derivative());
        i += 1;
    }
    if odd.degree().unwrap_or(0) == 0 {
        return true;
    }
    // Cauchy bound for the roots.
    let lead = odd.lead();
    let bound = odd
        .0
        .iter()
        .map(|c| (c / &lead).abs())
        .fold(BigRational::zero(), |a, b| a + b)
        + q(1);
    count_roots(&odd.sturm(), &BigRational::zero(), &bound) == 0
}

fn a_stability(r: &StabilityFunction) -> (bool, BigRational) {
    let to_q = |p: &NPoly| {
        Poly(
            p.0.iter()
                .map(|n| n.as_rational().expect("rational"))
                .collect(),
        )
        .trim()
    };
    let (n, d) = (to_q(&r.numerator), to_q(&r.denominator));
    let r_inf = if n.degree() == d.degree() {
        n.lead() / d.lead()
    } else {
        BigRational::zero()
    };
    // Poles in Re z > 0: D(−z) Hurwitz. |R(iy)| ≤ 1: E(y²) ≥ 0.
    let poles_ok = hurwitz(&reflect_z(&d));
    let nn = n.mul(&reflect_z(&n));
    let ddp = d.mul(&reflect_z(&d));
    let diff = ddp.sub(&nn);
    let e = Poly(
        diff.0
            .iter()
            .enumerate()
            .filter(|(k, _)| k % 2 == 0)
            .map(|(k, c)| {
                if (k / 2) % 2 == 1 {
                    -c.clone()
                } else {
                    c.clone()
                }
            })
            .collect(),
    )
    .trim();
    (poles_ok && nonnegative_on_half_line(&e), r_inf)
}

/// The order cap for the simplifying assumptions.
fn caps(s: usize) -> (usize, usize) {
    (2 * s + 1, s + 1)
}

impl Method {
    /// Decide everything exactly (see [`Verdicts`]).
    pub fn verdicts(&self) -> Verdicts {
        let ring = &self.ring;
        let weights_nonzero = self.b.gcd(&ring.p).degree() == Some(0);
        let nodes_distinct = true; // the ring asserts P squarefree
        let (off, diag) = w_parts(ring, &self.b, &self.a, &self.d, &self.a, &self.d);
        let w_off_zero = off.is_zero();
        let w_diag_zero = diag.is_zero();
        let symplectic = w_off_zero && w_diag_zero;
        let order = order_proof(ring, &self.b, &self.a, &self.d, self.s, "");
        let row_sums_ok = c_level(ring, &self.a, &self.d, 1);
        let symmetric = self.symmetric();
        let stability = stability(self);
        let unimodular = stability.unimodular_on_imaginary_axis();
        let (a_stable, r_infinity) = a_stability(&stability);
        Verdicts {
            weights_nonzero,
            nodes_distinct,
            row_sums_ok,
            symplectic,
            w_off_zero,
            w_diag_zero,
            symmetric,
            order,
            stability,
            a_stable,
            r_infinity,
            unimodular,
        }
    }

    /// Symmetric: the node set is symmetric (`P(1 − x) = (−1)ˢ P(x)`) and
    /// `b(1 − x) = b(x)`, `a(x, y) + a(1 − x, 1 − y) = b(y)`,
    /// `d(x) + d(1 − x) = b(x)`. With distinct nodes and nonzero weights the
    /// table is irreducible, and the only stage permutation that can map the
    /// adjoint's nodes `1 − cᵢ` onto the nodes is the reversal; so this is
    /// exact both ways.
    pub fn symmetric(&self) -> bool {
        let ring = &self.ring;
        let om = Poly::from_ints(&[1, -1]);
        let pr = ring.p.compose(&om);
        let sign = if self.s.is_multiple_of(2) {
            q(1)
        } else {
            q(-1)
        };
        if pr != ring.p.scale(&sign) {
            return false;
        }
        let br = ring.r1(&self.b.compose(&om));
        if br != self.b {
            return false;
        }
        let lhs = ring.sub(
            &ring.add(&self.a, &ring.reflect(&self.a)),
            &ring.from_y(&self.b),
        );
        let dl = ring.r1(&self.d.add(&self.d.compose(&om)).sub(&self.b));
        lhs.is_zero() && dl.is_zero()
    }
}

fn order_proof(ring: &Ring, b: &Poly, a: &Pair, d: &Poly, s: usize, _what: &str) -> OrderProof {
    let (bcap, ccap) = caps(s);
    let m_b = max_level(bcap, |k| {
        let t = ring.trace(&ring.mul1(b, &Poly::monomial(BigRational::one(), k - 1)));
        t == q(k as i64).recip()
    });
    let m_c = max_level(ccap, |k| c_level(ring, a, d, k));
    let m_d = max_level(ccap, |k| d_level(ring, b, a, d, k));
    let c1 = m_c >= 1;
    let lower = if c1 {
        m_b.min(m_c + m_d + 1).min(2 * m_c + 2)
    } else {
        0
    };
    let upper = (m_b < bcap && c1).then_some(m_b);
    let text = if !c1 {
        format!(
            "C(1) fails (c is not the row sums of A), so Butcher's theorem does not apply; B({m_b}) holds"
        )
    } else {
        let mut t = format!(
            "B({m_b}), C({m_c}), D({m_d}) hold exactly{}; Butcher's theorem gives order ≥ min({m_b}, {m_c}+{m_d}+1, 2·{m_c}+2) = {lower}",
            if m_b == bcap {
                " (B checked up to this level only)"
            } else {
                ""
            }
        );
        if let Some(u) = upper {
            t.push_str(&format!(
                "; B({}) fails (Σ bᵢcᵢ^{u} ≠ 1/{}, the order-{} condition of the bushy tree), so order ≤ {u}",
                u + 1,
                u + 1,
                u + 1
            ));
        }
        t
    };
    OrderProof {
        lower,
        upper,
        b: m_b,
        c: m_c,
        d: m_d,
        text,
    }
}

/// The Lobatto IIIA–IIIB pair.
#[derive(Clone, Debug)]
pub struct PairMethod {
    pub q: Method,
    pub p: Method,
}

/// What is decided about the pair.
#[derive(Clone, Debug)]
pub struct PairVerdicts {
    /// `bᵢâᵢⱼ + bⱼaⱼᵢ − bᵢbⱼ = 0` for all `i, j`, and `b = b̂`.
    pub symplectic: bool,
    pub symmetric: bool,
    pub q: Verdicts,
    pub p: Verdicts,
}

impl PairMethod {
    pub fn new(s: usize) -> PairMethod {
        PairMethod {
            q: Method::new(Family::Lobatto3A, s),
            p: Method::new(Family::Lobatto3B, s),
        }
    }

    /// The pair written out as a table file with `root(...)` entries: `a`,
    /// `b` of Lobatto IIIA (on `q`), `a_hat`, `b_hat` of Lobatto IIIB (on
    /// `p`), the nodes as roots as in [`Method::to_root_file`];
    /// `perturb = Some((i, j, text))` appends ` + text` to `a_hat[i][j]`,
    /// and `write_c` writes `c` and `c_hat` (both the nodes).
    pub fn to_root_file(
        &self,
        name: &str,
        claims: &[&str],
        perturb: Option<(usize, usize, &str)>,
        write_c: bool,
    ) -> String {
        let qt = self.q.to_root_file_with(name, claims, None, write_c);
        let pt = self.p.to_root_file_with(name, claims, perturb, write_c);
        // The IIIB body (a, b, c) renamed to a_hat, b_hat, c_hat.
        let start = pt.find("\na = [").expect("a") + 1;
        let end = pt.find("\n[let]").expect("let");
        let body = pt[start..end]
            .replacen("a = [", "a_hat = [", 1)
            .replacen("\nb = [", "\nb_hat = [", 1)
            .replacen("\nc = [", "\nc_hat = [", 1);
        let at = qt.find("\n[let]").expect("let");
        let mut out = qt[..at].to_string();
        out.push('\n');
        out.push_str(&body);
        out.push_str(&qt[at..]);
        out
    }

    pub fn verdicts(&self) -> PairVerdicts {
        let ring = &self.q.ring;
        let (off, diag) = w_parts(ring, &self.q.b, &self.q.a, &self.q.d, &self.p.a, &self.p.d);
        PairVerdicts {
            symplectic: off.is_zero() && diag.is_zero() && self.q.b == self.p.b,
            symmetric: self.q.symmetric() && self.p.symmetric(),
            q: self.q.verdicts(),
            p: self.p.verdicts(),
        }
    }
}

// ---------------------------------------------------------------------------
// Entries as numbers: certified f64, and the radical form where there is one.

impl Method {
    /// A field with the nodes as variables `0 … s−1`.
    fn node_field(&self) -> Field {
        let mut f = Field::default();
        for (i, r) in self.nodes.iter().enumerate() {
            let r = r.clone();
            // Push without deduplication: nodes are distinct roots.
            f.roots.push(r);
            f.names.push(format!("c{i}"));
        }
        f
    }

    /// `b(cᵢ)` as an [`Alg`] in variable `i`.
    pub fn b_alg(&self, i: usize) -> Alg {
        univariate_alg(&self.b, i)
    }

    /// `aᵢⱼ` as an [`Alg`] in variables `i` and `j`.
    pub fn a_alg(&self, i: usize, j: usize) -> Alg {
        if i == j {
            return univariate_alg(&self.d, i);
        }
        pair_alg(&self.a, i, j)
    }

    /// The exact entries over the field of the nodes: `(field, a, b, c)`.
    pub fn alg_table(&self) -> (Field, Vec<Vec<Alg>>, Vec<Alg>, Vec<Alg>) {
        let f = self.node_field();
        let s = self.s;
        let a = (0..s)
            .map(|i| (0..s).map(|j| f.reduce(&self.a_alg(i, j))).collect())
            .collect();
        let b = (0..s).map(|i| f.reduce(&self.b_alg(i))).collect();
        let c = (0..s).map(|i| f.var(i)).collect();
        (f, a, b, c)
    }

    /// Correctly rounded `f64` entries (nearest, ties to even), each decided
    /// on certified enclosures.
    pub fn nearest_f64(&self) -> F64Table {
        let (f, a, b, c) = self.alg_table();
        let r = |x: &Alg| f.to_f64(x).expect("within budget for generated tables");
        F64Table {
            a: a.iter().map(|row| row.iter().map(r).collect()).collect(),
            b: b.iter().map(r).collect(),
            c: c.iter().map(r).collect(),
        }
    }

    /// The rounding of `rounding.rs` for generated tables: `b` correctly
    /// rounded, moved (mirror pairs together) to another faithful rounding
    /// when that makes the left-to-right `f64` sum exactly 1; for a
    /// symplectic table, each pair `(aᵢⱼ, aⱼᵢ)` and each `aᵢᵢ` chosen among
    /// the faithful roundings (the two doubles that bracket the exact value)
    /// to make `Wᵢⱼ` of the doubles, computed exactly, as small as possible;
    /// ties keep the correct rounding. `c` correctly rounded.
    pub fn rounded_f64(&self, symplectic: bool) -> F64Table {
        let (f, a, b, c) = self.alg_table();
        let s = self.s;
        let br: Vec<Bracket> = b.iter().map(|x| bracket(&f, x)).collect();
        let mut out = F64Table {
            a: a.iter()
                .map(|row| row.iter().map(|x| bracket(&f, x).nearest).collect())
                .collect(),
            b: br.iter().map(|x| x.nearest).collect(),
            c: c.iter().map(|x| f.to_f64(x).expect("budget")).collect(),
        };
        out.b = adjust_weights(&br);
        if symplectic {
            let bq: Vec<BigRational> = out.b.iter().map(|&x| f64_rational(x)).collect();
            for i in 0..s {
                let d = bracket(&f, &a[i][i]);
                // |2bᵢaᵢᵢ − bᵢ²|
                out.a[i][i] = best_of(&d.choices(), |x| {
                    (q(2) * &bq[i] * f64_rational(x) - &bq[i] * &bq[i]).abs()
                });
                for j in i + 1..s {
                    let (x, y) = (bracket(&f, &a[i][j]), bracket(&f, &a[j][i]));
                    let mut best: Option<(BigRational, u8, f64, f64)> = None;
                    for &u in &x.choices() {
                        for &v in &y.choices() {
                            let w = (&bq[i] * f64_rational(u) + &bq[j] * f64_rational(v)
                                - &bq[i] * &bq[j])
                                .abs();
                            let moved = u8::from(u != x.nearest) + u8::from(v != y.nearest);
                            if best
                                .as_ref()
                                .is_none_or(|(bw, bm, _, _)| (&w, moved) < (bw, *bm))
                            {
                                best = Some((w, moved, u, v));
                            }
                        }
                    }
                    let (_, _, u, v) = best.expect("choices");
                    out.a[i][j] = u;
                    out.a[j][i] = v;
                }
            }
        }
        out
    }

    /// The table written out as a table file with `root(...)` entries
    /// ([`super::file`]): the nodes `c0 …` as roots of the node polynomial
    /// (integer coefficients) with isolating intervals, every entry as a
    /// polynomial in the nodes. `perturb = Some((i, j, text))` appends
    /// ` + text` to `a[i][j]` (for tests of the refusal).
    pub fn to_root_file(
        &self,
        name: &str,
        claims: &[&str],
        perturb: Option<(usize, usize, &str)>,
    ) -> String {
        self.to_root_file_with(name, claims, perturb, false)
    }

    /// [`Self::to_root_file`], with `c = ["c0", "c1", …]` written out when
    /// `write_c` (without it, `c` is left to the row sums of `a`).
    pub fn to_root_file_with(
        &self,
        name: &str,
        claims: &[&str],
        perturb: Option<(usize, usize, &str)>,
        write_c: bool,
    ) -> String {
        use num_integer::Integer;
        let mut den = BigInt::one();
        for c in &self.ring.p.0 {
            den = den.lcm(c.denom());
        }
        let ip = self.ring.p.scale(&BigRational::from_integer(den));
        // Every node a variable (rational nodes too, with an isolating
        // interval), so that each entry is the same polynomial in its nodes.
        let mut f = Field::default();
        for (i, r) in self.nodes.iter().enumerate() {
            let (lo, hi) = isolating_interval(&self.ring.p, r);
            let root = RealRoot::new(&self.ring.p, lo, hi).expect("an isolating interval");
            f.roots.push(root);
            f.names.push(format!("c{i}"));
        }
        let s = self.s;
        let a: Vec<Vec<Alg>> = (0..s)
            .map(|i| (0..s).map(|j| f.reduce(&self.a_alg(i, j))).collect())
            .collect();
        let b: Vec<Alg> = (0..s).map(|i| f.reduce(&self.b_alg(i))).collect();
        let text = |x: &Alg| alg_text(&f, x);
        let mut out = format!("name = \"{name}\"\n");
        out.push_str(&format!(
            "source = \"written out by tableau::algebraic::family::Method::to_root_file from the exact {} table\"\n",
            self.family.title()
        ));
        let cl: Vec<String> = claims.iter().map(|c| format!("\"{c}\"")).collect();
        out.push_str(&format!("claims = [{}]\n\n[let]\n", cl.join(", ")));
        for (i, r) in self.nodes.iter().enumerate() {
            let (lo, hi) = isolating_interval(&self.ring.p, r);
            out.push_str(&format!(
                "c{i} = \"root({}, {lo}, {hi})\"\n",
                ip.to_text("x"),
            ));
        }
        out.push_str("\n[table]\n");
        let _ = &mut out;
        let mut body = String::from("a = [\n");
        for i in 0..self.s {
            let row: Vec<String> = (0..self.s)
                .map(|j| {
                    let mut t = text(&a[i][j]);
                    if let Some((pi, pj, extra)) = perturb
                        && (pi, pj) == (i, j)
                    {
                        t = format!("{t} + {extra}");
                    }
                    format!("  \"{t}\"")
                })
                .collect();
            body.push_str(&format!(" [\n{}\n ],\n", row.join(",\n")));
        }
        body.push_str("]\nb = [\n");
        let bs: Vec<String> = b.iter().map(|x| format!("  \"{}\"", text(x))).collect();
        body.push_str(&bs.join(",\n"));
        body.push_str("\n]\n");
        if write_c {
            let cs: Vec<String> = (0..self.s).map(|i| format!("\"c{i}\"")).collect();
            body.push_str(&format!("c = [{}]\n", cs.join(", ")));
        }
        // TOML: top-level keys must precede [let]; put a and b first.
        let header_end = out.find("\n[let]").expect("let section");
        let mut file = out[..header_end].to_string();
        file.push('\n');
        file.push_str(&body);
        file.push_str(&out[header_end..out.find("\n[table]").expect("marker")]);
        file.push('\n');
        file
    }

    /// The table over `Q(√d)` when the nodes need at most one square root
    /// (rational nodes and one quadratic factor), for the tree-based checks
    /// of [`crate::analysis`]; `None` otherwise.
    pub fn radical_table(&self) -> Option<Rk> {
        let nodes = radical_nodes(&self.ring.p, &self.nodes)?;
        let s = self.s;
        let eval1 = |p: &Poly, x: &Number| {
            let mut acc = Number::zero();
            for c in p.0.iter().rev() {
                acc = &(&acc * x) + &Number::from_rational(c.clone());
            }
            acc
        };
        let b: Vec<Number> = nodes.iter().map(|c| eval1(&self.b, c)).collect();
        let mut a = vec![vec![Number::zero(); s]; s];
        for i in 0..s {
            for j in 0..s {
                a[i][j] = if i == j {
                    eval1(&self.d, &nodes[i])
                } else {
                    let mut acc = Number::zero();
                    for (k, cy) in self.a.0.iter().enumerate() {
                        let yk = nodes[j].powi(k as i64).ok()?;
                        acc += &(&eval1(cy, &nodes[i]) * &yk);
                    }
                    acc
                };
            }
        }
        Some(Rk {
            a,
            b,
            c: Some(nodes),
        })
    }
}

fn radical_nodes(p: &Poly, roots: &[RealRoot]) -> Option<Vec<Number>> {
    let mut rest = p.clone();
    let mut found: Vec<Number> = Vec::new();
    for cand in [q(0), q(1), BigRational::new(1.into(), 2.into())] {
        if rest.eval(&cand).is_zero() {
            rest = rest
                .divrem(&Poly(vec![-cand.clone(), BigRational::one()]))
                .0;
            found.push(Number::from_rational(cand));
        }
    }
    match rest.degree() {
        Some(0) => {}
        Some(1) => found.push(Number::from_rational(-rest.coeff(0) / rest.coeff(1))),
        Some(2) => {
            let (c0, c1, c2) = (rest.coeff(0), rest.coeff(1), rest.coeff(2));
            let disc = &c1 * &c1 - q(4) * &c0 * &c2;
            let sq = Number::from_rational(disc).sqrt().ok()?;
            let mid = Number::from_rational(-c1 / (q(2) * &c2));
            let half = Number::from_rational((q(2) * &c2).recip());
            let h = &sq * &half;
            found.push(&mid - &h);
            found.push(&mid + &h);
        }
        _ => return None,
    }
    // Order as the isolated roots: a rational node is matched exactly, an
    // irrational one by its refined isolating interval (f64 values of the
    // candidates are correctly rounded and the nodes are far apart).
    let mut out = Vec::new();
    for r in roots {
        let x = if r.is_rational() {
            let v = Number::from_rational(r.lo.clone());
            found.iter().find(|n| **n == v)?.clone()
        } else {
            let mut r = r.clone();
            r.refine_to(80);
            let (lo, hi) = (
                crate::number::rational_to_f64(&r.lo),
                crate::number::rational_to_f64(&r.hi),
            );
            found
                .iter()
                .find(|n| n.to_f64() >= lo && n.to_f64() <= hi)?
                .clone()
        };
        out.push(x);
    }
    Some(out)
}

/// An [`Alg`] as text in the grammar, variables named `c0, c1, …`.
/// An interval `(lo, hi]` with `lo < hi` holding exactly the root `r` of
/// `p`: the node's own interval, or for a rational node `r` (isolated as
/// `[r, r]`) the interval `(r − 2⁻ᵗ, r + 2⁻ᵗ]` for the first `t` that
/// isolates it, so that the file exercises the general root path.
fn isolating_interval(p: &Poly, r: &RealRoot) -> (BigRational, BigRational) {
    if !r.is_rational() {
        return (r.lo.clone(), r.hi.clone());
    }
    let seq = p.sturm();
    let mut w = BigRational::new(BigInt::one(), BigInt::from(2));
    loop {
        let (lo, hi) = (&r.lo - &w, &r.lo + &w);
        if count_roots(&seq, &lo, &hi) == 1 {
            return (lo, hi);
        }
        w /= q(2);
    }
}

fn alg_text(f: &Field, x: &Alg) -> String {
    let x = f.reduce(x);
    let mut parts = Vec::new();
    for (m, c) in x.terms() {
        let mut t = c.to_string();
        for (k, &e) in m.iter().enumerate() {
            match e {
                0 => {}
                1 => t.push_str(&format!("*c{k}")),
                _ => t.push_str(&format!("*c{k}^{e}")),
            }
        }
        parts.push(format!("({t})"));
    }
    if parts.is_empty() {
        "0".into()
    } else {
        parts.join(" + ")
    }
}

fn univariate_alg(p: &Poly, var: usize) -> Alg {
    let mut acc = Alg::zero();
    let mut f = Field::default();
    let _ = &mut f;
    for (e, c) in p.0.iter().enumerate() {
        acc = acc.add(&mono(c.clone(), &[(var, e as u32)]));
    }
    acc
}

fn pair_alg(p: &Pair, vx: usize, vy: usize) -> Alg {
    let mut acc = Alg::zero();
    for (i, j, c) in Ring::terms(p) {
        acc = acc.add(&mono(c, &[(vx, i as u32), (vy, j as u32)]));
    }
    acc
}

fn mono(c: BigRational, exps: &[(usize, u32)]) -> Alg {
    Alg::monomial(c, exps)
}

/// The two doubles that bracket an exact value (equal when it is a double),
/// and the nearest.
#[derive(Clone, Copy, Debug)]
pub struct Bracket {
    pub lower: f64,
    pub upper: f64,
    pub nearest: f64,
}

impl Bracket {
    fn choices(&self) -> Vec<f64> {
        let mut v = vec![self.nearest];
        for x in [self.lower, self.upper] {
            if !v.contains(&x) {
                v.push(x);
            }
        }
        v
    }
}

/// The largest double `≤ r`.
fn floor_f64(r: &BigRational) -> f64 {
    let d = crate::number::rational_to_f64(r);
    if f64_rational(d) > *r {
        prev_down(d)
    } else {
        d
    }
}

fn prev_down(x: f64) -> f64 {
    -next_up(-x)
}

pub fn bracket(f: &Field, x: &Alg) -> Bracket {
    let nearest = f.to_f64(x).expect("budget");
    if let Some(r) = f.reduce(x).as_rational() {
        let lower = floor_f64(&r);
        let exact = f64_rational(lower) == r;
        return Bracket {
            lower,
            upper: if exact { lower } else { next_up(lower) },
            nearest,
        };
    }
    // The nearest double is one of the bracket; the other is on the side of
    // the exact value, decided by the exact sign of x − nearest.
    let diff = x.sub(&Alg::rational(f64_rational(nearest)));
    match f.sign(&diff).expect("budget") {
        0 => Bracket {
            lower: nearest,
            upper: nearest,
            nearest,
        },
        1 => Bracket {
            lower: nearest,
            upper: next_up(nearest),
            nearest,
        },
        _ => Bracket {
            lower: prev_down(nearest),
            upper: nearest,
            nearest,
        },
    }
}

fn best_of(choices: &[f64], cost: impl Fn(f64) -> BigRational) -> f64 {
    let mut best = (cost(choices[0]), choices[0]);
    for &c in &choices[1..] {
        let k = cost(c);
        if k < best.0 {
            best = (k, c);
        }
    }
    best.1
}

/// Correctly rounded weights, moved (mirror pairs together, fewest moves
/// first, at most two units) to other faithful roundings when that makes the
/// left-to-right sum exactly 1.
fn adjust_weights(br: &[Bracket]) -> Vec<f64> {
    let base: Vec<f64> = br.iter().map(|x| x.nearest).collect();
    let sum = |v: &[f64]| v.iter().fold(0.0f64, |a, &b| a + b);
    if sum(&base) == 1.0 {
        return base;
    }
    let n = br.len();
    let mirror = |i: usize| n - 1 - i;
    let alt = |x: &Bracket| {
        if x.nearest == x.lower {
            x.upper
        } else {
            x.lower
        }
    };
    let units: Vec<Vec<usize>> = (0..n.div_ceil(2))
        .map(|i| {
            if mirror(i) != i && br[i].nearest == br[mirror(i)].nearest {
                vec![i, mirror(i)]
            } else {
                vec![i]
            }
        })
        .collect();
    let apply = |v: &mut Vec<f64>, u: &[usize]| {
        for &i in u {
            v[i] = alt(&br[i]);
        }
    };
    for a in 0..units.len() {
        let mut v = base.clone();
        apply(&mut v, &units[a]);
        if sum(&v) == 1.0 {
            return v;
        }
    }
    for a in 0..units.len() {
        for b in a + 1..units.len() {
            let mut v = base.clone();
            apply(&mut v, &units[a]);
            apply(&mut v, &units[b]);
            if sum(&v) == 1.0 {
                return v;
            }
        }
    }
    base
}

/// `max |Wᵢⱼ|` of a rounded table, computed exactly from the doubles.
pub fn max_abs_w(t: &F64Table) -> f64 {
    crate::rounding::max_abs_w(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_ids() {
        assert_eq!(
            Generator::parse("gauss8"),
            Ok(Generator::Rk(Family::Gauss, 8))
        );
        assert_eq!(
            Generator::parse("gauss(8)"),
            Ok(Generator::Rk(Family::Gauss, 8))
        );
        assert_eq!(
            Generator::parse("radau2a-5"),
            Ok(Generator::Rk(Family::Radau2A, 5))
        );
        assert_eq!(
            Generator::parse("lobatto3a3b4"),
            Ok(Generator::Lobatto3A3B(4))
        );
        assert!(Generator::parse("gauss0").is_err());
        assert!(Generator::parse("lobatto3a1").is_err());
        assert!(
            Generator::parse("foo3")
                .unwrap_err()
                .contains("unknown generator")
        );
    }

    #[test]
    fn gauss2_is_the_known_table() {
        let m = Method::new(Family::Gauss, 2);
        let rk = m.radical_table().unwrap();
        let r3 = Number::from(3).sqrt().unwrap();
        let sixth = Number::ratio(1, 6).unwrap();
        let quarter = Number::ratio(1, 4).unwrap();
        assert_eq!(rk.a[0][0], quarter);
        assert_eq!(rk.a[0][1], &quarter - &(&r3 * &sixth));
        assert_eq!(rk.b[0], Number::ratio(1, 2).unwrap());
    }
}
