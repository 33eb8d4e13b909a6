//! One generated table, verified: the verdicts, how each was proven, the
//! claims checked against them, and the `f64` coefficients. This is what
//! `symlab check --builtin gauss8` and `generate = "gauss(8)"` table files
//! report.
//!
//! ```
//! use tableau::algebraic::generated::{Generated, GeneratedTable};
//! let g = Generated::new("gauss(4)").unwrap();
//! assert!(g.symplectic && g.symmetric);
//! assert_eq!(g.order.lower, 8);
//! assert_eq!(g.order.upper, Some(8));
//! assert!(g.claims.iter().all(|(_, verdict)| verdict.is_ok()));
//! let GeneratedTable::Rk(t) = &g.f64_table else { unreachable!() };
//! assert_eq!(t.b.iter().sum::<f64>(), 1.0);
//! ```

use std::time::{Duration, Instant};

use num_rational::BigRational;

use super::family::{Family, Generator, Method, OrderProof, PairMethod, max_abs_w};
use super::poly::Poly;
use crate::analysis::ClaimError;
use crate::analysis::stability::StabilityFunction;
use crate::claims::Claim;
use crate::order::OrderReport;
use crate::rounding::{F64Pair, F64Table};
use crate::{Prk, Rk};

/// The `f64` coefficients of a generated table.
#[derive(Clone, Debug, PartialEq)]
pub enum GeneratedTable {
    Rk(F64Table),
    /// The Lobatto IIIA–IIIB pair: `q` is IIIA, `p` is IIIB.
    Prk(F64Pair),
}

/// A generated table and everything decided about it.
#[derive(Clone, Debug)]
pub struct Generated {
    pub generator: Generator,
    pub name: String,
    /// Where the construction comes from.
    pub source: &'static str,
    pub stages: usize,
    /// The monic node polynomial.
    pub node_polynomial: Poly,
    /// `"rk"` or `"prk"`.
    pub kind: &'static str,
    /// `c` equals the row sums of `A` (both tables for the pair).
    pub row_sums_ok: bool,
    /// Every weight is nonzero (so, with distinct nodes, the table is
    /// irreducible and the symmetry verdict is exact both ways).
    pub weights_nonzero: bool,
    /// RK: `W = 0`. Pair: `bᵢâᵢⱼ + bⱼaⱼᵢ = bᵢbⱼ` for all `i, j` and `b = b̂`.
    pub symplectic: bool,
    pub symmetric: bool,
    /// The order proof of the (first) table: simplifying assumptions and
    /// Butcher's theorem.
    pub order: OrderProof,
    /// The pair's `p` table (IIIB).
    pub order_p: Option<OrderProof>,
    /// Rooted-tree check on the radical form, where the nodes need at most
    /// one square root (bicoloured trees for the pair).
    pub tree_order: Option<OrderReport>,
    /// RK only.
    pub stability: Option<StabilityFunction>,
    pub a_stable: Option<bool>,
    pub r_infinity: Option<BigRational>,
    pub unimodular: Option<bool>,
    /// The claims checked: the literature's.
    pub claims: Vec<(Claim, Result<(), ClaimError>)>,
    /// Symplecticity-aware rounding (see [`Method::rounded_f64`]) for
    /// symplectic tables, the correct rounding otherwise.
    pub f64_table: GeneratedTable,
    /// `max |Wᵢⱼ|` of `f64_table` and of the plain correct rounding, exactly
    /// computed from the doubles (RK only).
    pub max_w_rounded: Option<f64>,
    pub max_w_nearest: Option<f64>,
    /// Time for the exact verification (verdicts and claims).
    pub verify_time: Duration,
    /// Time for the certified `f64` coefficients.
    pub round_time: Duration,
}

/// The literature's claims for a generator.
pub fn literature_claims(g: Generator) -> Vec<Claim> {
    let order = |p| Claim::Order { p, bound: None };
    match g {
        Generator::Rk(f, s) => {
            let mut c = Vec::new();
            if f == Family::Gauss {
                c.push(Claim::Symplectic);
            }
            if matches!(f, Family::Gauss | Family::Lobatto3A | Family::Lobatto3B) {
                c.push(Claim::Symmetric);
            }
            c.push(order(f.literature_order(s)));
            c
        }
        Generator::Lobatto3A3B(_) => vec![Claim::Symplectic, Claim::Symmetric],
    }
}

fn source(g: Generator) -> &'static str {
    match g {
        Generator::Rk(Family::Gauss, _) => {
            "Butcher 1964 (Gauss collocation); Hairer–Wanner, Solving ODEs II, Sect. IV.5"
        }
        Generator::Rk(Family::Radau1A | Family::Radau2A, _) => {
            "Butcher 1964, Ehle 1969; Hairer–Wanner, Solving ODEs II, Sect. IV.5"
        }
        Generator::Rk(_, _) => {
            "Ehle 1969, Chipman 1971; Hairer–Wanner, Solving ODEs II, Sect. IV.5"
        }
        Generator::Lobatto3A3B(_) => {
            "Sun Geng 1993, Jay 1996; Hairer–Lubich–Wanner, Geometric Numerical Integration, Sect. II.2"
        }
    }
}

impl Generated {
    /// Build and verify the table a generator names (`gauss(8)`, `gauss8`,
    /// `lobatto3a3b(4)` …) with the literature's claims.
    pub fn new(text: &str) -> Result<Generated, String> {
        let g = Generator::parse(text)?;
        Ok(Generated::with_claims(g, literature_claims(g)))
    }

    pub fn with_claims(g: Generator, claims: Vec<Claim>) -> Generated {
        let t0 = Instant::now();
        let mut out = match g {
            Generator::Rk(f, s) => Self::rk(g, Method::new(f, s)),
            Generator::Lobatto3A3B(s) => Self::pair(g, PairMethod::new(s)),
        };
        out.claims = claims
            .into_iter()
            .map(|c| {
                let v = out.check_claim(&c);
                (c, v)
            })
            .collect();
        out.verify_time = t0.elapsed() - out.round_time;
        out
    }

    fn rk(g: Generator, m: Method) -> Generated {
        let v = m.verdicts();
        let tree_order = m
            .radical_table()
            .map(|rk| crate::order::rk_order(&rk, crate::analysis::RK_ORDER_LIMIT, None));
        let t = Instant::now();
        let nearest = m.nearest_f64();
        let rounded = if v.symplectic {
            m.rounded_f64(true)
        } else {
            nearest.clone()
        };
        let round_time = t.elapsed();
        Generated {
            generator: g,
            name: g.title(),
            source: source(g),
            stages: m.s,
            node_polynomial: m.ring.p.clone(),
            kind: "rk",
            row_sums_ok: v.row_sums_ok,
            weights_nonzero: v.weights_nonzero,
            symplectic: v.symplectic,
            symmetric: v.symmetric,
            order: v.order,
            order_p: None,
            tree_order,
            a_stable: Some(v.a_stable),
            r_infinity: Some(v.r_infinity),
            unimodular: Some(v.unimodular),
            stability: Some(v.stability),
            claims: Vec::new(),
            max_w_rounded: Some(max_abs_w(&rounded)),
            max_w_nearest: Some(max_abs_w(&nearest)),
            f64_table: GeneratedTable::Rk(rounded),
            verify_time: Duration::ZERO,
            round_time,
        }
    }

    fn pair(g: Generator, m: PairMethod) -> Generated {
        let v = m.verdicts();
        let tree_order = match (m.q.radical_table(), m.p.radical_table()) {
            (Some(q), Some(p)) => Some(crate::order::prk_order(
                &Prk { q, p },
                crate::analysis::PRK_ORDER_LIMIT,
                None,
            )),
            _ => None,
        };
        let t = Instant::now();
        let q = m.q.nearest_f64();
        let p = m.p.nearest_f64();
        let round_time = t.elapsed();
        Generated {
            generator: g,
            name: g.title(),
            source: source(g),
            stages: m.q.s,
            node_polynomial: m.q.ring.p.clone(),
            kind: "prk",
            row_sums_ok: v.q.row_sums_ok && v.p.row_sums_ok,
            weights_nonzero: v.q.weights_nonzero,
            symplectic: v.symplectic,
            symmetric: v.symmetric,
            order: v.q.order,
            order_p: Some(v.p.order),
            tree_order,
            stability: None,
            a_stable: None,
            r_infinity: None,
            unimodular: None,
            claims: Vec::new(),
            max_w_rounded: None,
            max_w_nearest: None,
            f64_table: GeneratedTable::Prk(F64Pair { q, p }),
            verify_time: Duration::ZERO,
            round_time,
        }
    }

    /// The order proven for the method: the simplifying-assumption bound,
    /// raised by the tree check where it ran. For the pair, the tree check
    /// on bicoloured trees is the only proof of the pair's order.
    pub fn proven_order(&self) -> usize {
        let trees = self.tree_order.as_ref().map_or(0, |t| t.order);
        if self.kind == "prk" {
            trees
        } else {
            self.order.lower.max(trees)
        }
    }

    /// Check one claim exactly; an order claim beyond what is proven is
    /// refused with the proof's words.
    pub fn check_claim(&self, claim: &Claim) -> Result<(), ClaimError> {
        match claim {
            Claim::Symplectic => {
                if self.symplectic {
                    Ok(())
                } else if self.kind == "rk" {
                    Err(ClaimError(
                        "not symplectic: W = BA + AᵀB − bbᵀ ≠ 0 (decided exactly in the product of fields Q[x, y]/(P(x), (P(x) − P(y))/(x − y)) × Q[x]/(P))".into(),
                    ))
                } else {
                    Err(ClaimError(
                        "not symplectic: bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ ≠ 0 or b ≠ b̂".into(),
                    ))
                }
            }
            Claim::Symmetric => {
                if self.symmetric {
                    Ok(())
                } else {
                    Err(ClaimError("not symmetric: the adjoint (nodes 1 − cᵢ, aᵢⱼ ↦ b_σ(j) − a_σ(i)σ(j)) is not the table under the reversal of the stages, the only permutation that can match the nodes".into()))
                }
            }
            Claim::Explicit => Err(ClaimError(
                "not explicit: a collocation-type table is implicit".into(),
            )),
            Claim::Order { p, bound: _ } => {
                let proven = self.proven_order();
                if proven >= *p {
                    return Ok(());
                }
                if self.kind == "rk"
                    && let Some(u) = self.order.upper
                    && u < *p
                {
                    return Err(ClaimError(format!(
                        "order {p} claimed but the order is at most {u}: {}",
                        self.order.text
                    )));
                }
                Err(ClaimError(format!(
                    "order {p} claimed but only order ≥ {proven} is proven{}",
                    if self.kind == "prk" {
                        " (the pair's order is checked on bicoloured trees, which runs only where the nodes need at most one square root, s ≤ 5)".to_string()
                    } else {
                        format!(": {}", self.order.text)
                    }
                )))
            }
            Claim::OrderRkn { .. } => Err(ClaimError(
                "order_rkn is not decided for generated tables".into(),
            )),
            Claim::NearOrder { .. } => Err(ClaimError(
                "a generalised order `order = (P1, P2, …)` is a property of a drift–kick sequence or a composition, not of a generated Runge–Kutta table".into(),
            )),
            Claim::CertifiedOrder { .. } | Claim::CertifiedNearOrder { .. } => Err(ClaimError(
                "a certified order is about a drift–kick sequence or composition with a `certificate`; a generated table's order is proven exactly: claim `order = p`".into(),
            )),
        }
    }

    /// The exact tables over `Q(√d)`, where they exist (for cross-checks).
    pub fn radical_rk(&self) -> Option<Rk> {
        match self.generator {
            Generator::Rk(f, s) => Method::new(f, s).radical_table(),
            Generator::Lobatto3A3B(_) => None,
        }
    }
}
