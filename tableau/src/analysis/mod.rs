//! Every verdict about a table, decided exactly: shape, class, symplecticity,
//! order, symmetry and the stability function. [`Analysis::of`] is what both
//! `symlab check` and the `butcher!` macro run, so they always agree.

pub mod class;
mod modular;
pub mod reduce;
pub mod stability;
pub mod symmetry;
pub mod symplectic;

use serde::Serialize;

use crate::budget::BeyondBudget;
use crate::claims::Claim;
use crate::order::{self, OrderReport};
use crate::table::{Composition, ShapeError, Splitting};
use crate::{Number, Prk, Rk, Table};

pub use class::Class;
pub use stability::StabilityFunction;
pub use symplectic::WEntry;

/// The default order limits: every table is checked at least this far.
/// Runge–Kutta tables have few rooted trees (1205 up to order 10); pairs on
/// general partitioned systems have many bicoloured trees (24 314 up to 8).
pub const RK_ORDER_LIMIT: usize = 10;
pub const PRK_ORDER_LIMIT: usize = 8;
pub const SEPARABLE_ORDER_LIMIT: usize = 10;
pub const COMPOSITION_ORDER_LIMIT: usize = 12;
/// Runge–Kutta–Nyström systems have few trees (1668 up to order 12).
pub const RKN_ORDER_LIMIT: usize = 12;

/// The highest orders a claim can ask for: above these the checker refuses
/// (it never accepts a claim it has not checked).
pub const MAX_RK_ORDER: usize = 12;
pub const MAX_PRK_ORDER: usize = 9;
pub const MAX_SEPARABLE_ORDER: usize = 12;
pub const MAX_COMPOSITION_ORDER: usize = 14;
pub const MAX_RKN_ORDER: usize = 14;

/// The written forms of a table: the four forms, and a drift–kick sequence
/// with gradient kicks (`kick_gradient`), which has no partitioned
/// Runge–Kutta form and is analysed on the Lie algebra alone.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Form {
    Rk,
    Prk,
    DriftKick,
    Composition,
    GradientDriftKick,
}

/// The order limit of a sequence with gradient kicks: every Lie term of
/// degree at most this is examined (lowered where the near-integrable
/// budgets require; the report states the limit examined).
pub const GRADIENT_ORDER_LIMIT: usize = 10;

/// Everything known about a table. The fields mirror the JSON report of
/// `symlab check --json` (see `docs` in design.md); the extra fields carry
/// the evidence behind each verdict.
#[derive(Clone, Debug)]
pub struct Analysis {
    pub form: Form,
    pub stages: usize,
    pub class: Class,
    /// Rows `i` whose given `cᵢ` differs from the row sum of `A` (both tables
    /// for a pair); empty when `c` is absent or agrees.
    pub row_sum_mismatch: Vec<RowSumMismatch>,
    /// RK: `W = 0` on the irreducible form. Pair: conditions hold and `b = b̂`.
    pub symplectic: bool,
    /// Symplectic for separable Hamiltonians (RK: same as `symplectic`).
    pub symplectic_separable: bool,
    /// Nonzero entries of `W` (RK) or of `bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ` (pair), for the
    /// table as written.
    pub w_nonzero: Vec<WEntry>,
    /// The stages a reduction to irreducible form removed or merged.
    pub reducible: bool,
    /// Explicit (stage by stage, no solves) on separable systems.
    pub explicit_separable: bool,
    /// Order on general systems (for a drift–kick sequence or a composition:
    /// of its equivalent partitioned pair on general partitioned systems,
    /// which is informative only — such schemes step separable systems).
    /// `None` for a sequence with gradient kicks, which has no such pair.
    pub order: Option<OrderReport>,
    /// Order on separable systems (RK: same as `order`). For a sequence with
    /// gradient kicks ([`Form::GradientDriftKick`]): its classical order for
    /// any `A` and `B`, every Lie term of `log Φ` of degree at most `order`
    /// vanishing ([`crate::near_integrable`]), failures named by Lie term
    /// ([`crate::order::ConditionKind::LieTerm`]); `limit` 0 when even that
    /// is beyond the near-integrable budgets (`lie_not_computed` says why).
    pub order_separable: OrderReport,
    /// For [`Form::GradientDriftKick`]: why its order on the Lie algebra was
    /// not computed (beyond the budgets); `None` otherwise.
    pub lie_not_computed: Option<String>,
    /// Order on Runge–Kutta–Nyström systems: separable `H = T(p) + V(q)` with
    /// `T = ½pᵀM⁻¹p` quadratic, so that `q' = M⁻¹p` is linear in `p` (the
    /// Nyström trees, [`crate::trees::Colouring::Nystrom`]); at least
    /// `order_separable`. Every form is checked as the partitioned pair it
    /// is: a Runge–Kutta table as the pair `(A, b)`, `(A, b)` on autonomous
    /// systems (a given `c` is not used), a drift–kick sequence as its
    /// equivalent pair, and a composition of Störmer–Verlet as the pair of
    /// its drift–kick sequence (`D(γ/2) K(γ) D(γ/2)` per factor, neighbouring
    /// drifts merged). For a composition this is therefore the order of
    /// composing that particular base method, not the order of the
    /// composition conditions, which hold for any symmetric second-order base
    /// method and are what `order_separable` reports.
    ///
    /// A sequence with gradient kicks has no Nyström trees: its order on
    /// these systems is not decided. Its report is the one thing known, that
    /// it is at least `order_separable` (`order == limit`, no failure:
    /// "≥ p"), and an `order_rkn` claim is refused.
    pub order_rkn: OrderReport,
    /// The method is its own adjoint, decided on the irreducible form (exact
    /// both ways).
    pub symmetric: bool,
    pub stability: Option<StabilityFunction>,
    /// Why `stability` is `None` for a Runge–Kutta table: its exact
    /// computation is beyond the budget ([`crate::budget`]). `None` when it
    /// was computed, and for the partitioned forms (which have none).
    pub stability_not_computed: Option<BeyondBudget>,
    /// `|R(iy)| = 1` for all real `y` (RK only).
    pub unimodular: Option<bool>,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RowSumMismatch {
    /// `"c"` or `"c_hat"`.
    pub field: &'static str,
    pub row: usize,
    #[serde(serialize_with = "serialize_display")]
    pub given: Number,
    #[serde(serialize_with = "serialize_display")]
    pub row_sum: Number,
}

pub(crate) fn serialize_display<S: serde::Serializer, T: std::fmt::Display>(
    x: &T,
    s: S,
) -> Result<S::Ok, S::Error> {
    s.collect_str(x)
}

impl Analysis {
    /// Analyse a table with the default order limits. The shape is checked
    /// first; nothing else runs on a table whose dimensions do not fit.
    pub fn of(table: &Table) -> Result<Analysis, ShapeError> {
        table.check_shape()?;
        Ok(match table {
            Table::Rk(rk) => Self::of_rk(rk),
            Table::Prk(prk) => Self::of_prk(prk, Form::Prk, None),
            Table::Splitting(s) => Self::of_splitting(s),
            Table::Composition(c) => Self::of_composition(c),
        })
    }

    fn of_rk(rk: &Rk) -> Analysis {
        let w = symplectic::w_matrix(rk, rk);
        let (irreducible, reducible) = reduce::reduce(&[rk]);
        let red = &irreducible[0];
        let symplectic = symplectic::vanishes(&symplectic::w_matrix(red, red));
        let symmetric = symmetry::equal_up_to_permutation(&irreducible, &[symmetry::adjoint(red)]);
        let order = order::rk_order(rk, RK_ORDER_LIMIT, None);
        let stability = StabilityFunction::of(rk);
        let unimodular = stability
            .as_ref()
            .ok()
            .map(StabilityFunction::unimodular_on_imaginary_axis);
        let class = class::classify(rk);
        Analysis {
            form: Form::Rk,
            stages: rk.stages(),
            class,
            row_sum_mismatch: row_sum_mismatch(rk, "c"),
            lie_not_computed: None,
            symplectic,
            symplectic_separable: symplectic,
            w_nonzero: symplectic::nonzero_entries(&w),
            reducible,
            explicit_separable: class == Class::Explicit,
            order: Some(order.clone()),
            order_separable: order,
            order_rkn: order::rk_order_nystrom(rk, RKN_ORDER_LIMIT, None),
            symmetric,
            unimodular,
            stability_not_computed: stability.as_ref().err().cloned(),
            stability: stability.ok(),
        }
    }

    /// `symmetric_override` carries the exact verdict of a drift–kick
    /// sequence, which its normal form decides more directly.
    fn of_prk(prk: &Prk, form: Form, symmetric_override: Option<bool>) -> Analysis {
        let w = symplectic::w_matrix(&prk.q, &prk.p);
        let (irreducible, reducible) = reduce::reduce(&[&prk.q, &prk.p]);
        let (rq, rp) = (&irreducible[0], &irreducible[1]);
        let conditions = symplectic::vanishes(&symplectic::w_matrix(rq, rp));
        let same_weights = rq.b == rp.b;
        let symmetric = symmetric_override.unwrap_or_else(|| {
            symmetry::equal_up_to_permutation(
                &irreducible,
                &[symmetry::adjoint(rq), symmetry::adjoint(rp)],
            )
        });
        let mut mismatch = row_sum_mismatch(&prk.q, "c");
        mismatch.extend(row_sum_mismatch(&prk.p, "c_hat"));
        Analysis {
            form,
            stages: prk.q.stages(),
            class: class::classify(&prk.q).max(class::classify(&prk.p)),
            row_sum_mismatch: mismatch,
            lie_not_computed: None,
            symplectic: conditions && same_weights,
            symplectic_separable: conditions,
            w_nonzero: symplectic::nonzero_entries(&w),
            reducible,
            explicit_separable: class::explicit_on_separable(&prk.q, &prk.p),
            order: Some(order::prk_order(prk, PRK_ORDER_LIMIT, None)),
            order_separable: order::prk_order_separable(prk, SEPARABLE_ORDER_LIMIT, None),
            order_rkn: order::prk_order_nystrom(prk, RKN_ORDER_LIMIT, None),
            symmetric,
            stability: None,
            stability_not_computed: None,
            unimodular: None,
        }
    }

    fn of_splitting(s: &Splitting) -> Analysis {
        if s.has_gradient() {
            return Self::of_gradient(s);
        }
        Self::of_prk(
            &s.to_prk(),
            Form::DriftKick,
            Some(symmetry::splitting_is_symmetric(s)),
        )
    }

    /// A sequence with gradient kicks: no partitioned form, so no tree is
    /// used. Symplectic (a composition of exact flows of Hamiltonians) and
    /// explicit by construction; symmetric when its normal form
    /// ([`Splitting::flows`]) is a palindrome; its order the classical order
    /// on the Lie algebra ([`lie_order`]).
    fn of_gradient(s: &Splitting) -> Analysis {
        let table = Table::Splitting(s.clone());
        let (order_separable, lie_not_computed) = match lie_order(&table, GRADIENT_ORDER_LIMIT) {
            Ok(r) => (r, None),
            Err(why) => (
                OrderReport {
                    order: 0,
                    limit: 0,
                    first_failure: None,
                    conditions_checked: 0,
                },
                Some(why),
            ),
        };
        let order_rkn = OrderReport {
            order: order_separable.order,
            limit: order_separable.order,
            first_failure: None,
            conditions_checked: 0,
        };
        Analysis {
            form: Form::GradientDriftKick,
            stages: s.stages(),
            class: Class::Explicit,
            row_sum_mismatch: Vec::new(),
            symplectic: false,
            symplectic_separable: true,
            w_nonzero: Vec::new(),
            reducible: false,
            explicit_separable: true,
            order: None,
            order_separable,
            lie_not_computed,
            order_rkn,
            symmetric: symmetry::splitting_is_symmetric(s),
            stability: None,
            stability_not_computed: None,
            unimodular: None,
        }
    }

    fn of_composition(c: &Composition) -> Analysis {
        let split = c.to_splitting();
        let mut a = Self::of_prk(
            &split.to_prk(),
            Form::Composition,
            Some(symmetry::splitting_is_symmetric(&split)),
        );
        a.order_separable = order::composition_order(c, COMPOSITION_ORDER_LIMIT, None);
        a
    }

    /// JSON `kind`: `"rk"` or `"prk"` (drift–kick sequences and compositions
    /// are partitioned methods).
    /// `"gradient-drift-kick"` for a sequence with gradient kicks, which has
    /// no partitioned form.
    pub fn kind(&self) -> &'static str {
        match self.form {
            Form::Rk => "rk",
            Form::GradientDriftKick => "gradient-drift-kick",
            _ => "prk",
        }
    }

    /// A scheme that is symplectic only for separable Hamiltonians (a pair with
    /// `b ≠ b̂`, a drift–kick sequence, a composition) steps only separable
    /// systems; its `order` claim means the order on separable systems.
    pub fn separable_only(&self) -> bool {
        match self.form {
            Form::Rk => false,
            Form::Prk => !self.symplectic,
            Form::DriftKick | Form::Composition | Form::GradientDriftKick => true,
        }
    }

    /// The order that an `order = p` claim is about.
    pub fn claimed_order_report(&self) -> &OrderReport {
        match (&self.order, self.separable_only()) {
            (Some(general), false) => general,
            _ => &self.order_separable,
        }
    }
}

/// Why a claim does not hold, in words that name the exact evidence.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct ClaimError(pub String);

/// Check one claim against a table. Order claims above the default limit are
/// re-checked with a higher limit where the checker supports it, and refused
/// with a message where it does not: a claim is never accepted unchecked.
pub fn check_claim(table: &Table, analysis: &Analysis, claim: &Claim) -> Result<(), ClaimError> {
    match claim {
        Claim::Symplectic => check_symplectic(analysis),
        Claim::Symmetric => {
            if analysis.symmetric {
                Ok(())
            } else {
                Err(ClaimError(match analysis.form {
                    Form::DriftKick | Form::Composition | Form::GradientDriftKick => {
                        "not symmetric: the drift–kick sequence (zeros dropped, neighbours merged) is not a palindrome".into()
                    }
                    _ => "not symmetric: the adjoint table (a*ᵢⱼ = b_{s+1−j} − a_{s+1−i,s+1−j}) is not the table under any stage permutation".into(),
                }))
            }
        }
        Claim::Explicit => {
            if analysis.explicit_separable {
                Ok(())
            } else {
                Err(ClaimError(format!(
                    "not explicit: {}",
                    first_implicit_entry(table)
                )))
            }
        }
        Claim::Order { p, bound } if analysis.form == Form::GradientDriftKick => {
            crate::near_integrable::check_near_claim(table, &[*p], bound.as_ref())
                .map(|_| ())
                .map_err(|e| {
                    ClaimError(format!(
                        "order = {p} (classical, a drift–kick sequence with gradient kicks: every Lie term of degree ≤ {p} must vanish): {e}"
                    ))
                })
        }
        Claim::Order { p, bound } => check_order(table, analysis, *p, bound.as_ref()),
        Claim::OrderRkn { p, .. } if analysis.form == Form::GradientDriftKick => {
            Err(ClaimError(format!(
                "order_rkn = {p} is not decided for a drift–kick sequence with gradient kicks (kick_gradient): it has no Runge–Kutta–Nyström trees; claim its order on the Lie algebra as `order = p` or `order = (p1, p2, …)`"
            )))
        }
        Claim::OrderRkn { p, bound } => check_order_rkn(table, analysis, *p, bound.as_ref()),
        Claim::NearOrder { orders, bound } => {
            crate::near_integrable::check_near_claim(table, orders, bound.as_ref())
                .map(|_| ())
                .map_err(ClaimError)
        }
        Claim::CertifiedOrder { .. } | Claim::CertifiedNearOrder { .. } => Err(ClaimError(format!(
            "`{claim}` is proven only from a table file's `certificate` (unknowns, radius; see tableau::certificate), which this table does not come with"
        ))),
    }
}

/// Check one claim of a table file: [`check_claim`] on its table, except
/// for a processed method (a kernel with a corrector), whose order and
/// symmetry claims are about the effective method `χ K χ⁻¹`
/// ([`crate::near_integrable::check_processed_claim`]); its `symplectic`
/// and `explicit` claims are the kernel's (the corrector, a drift–kick
/// sequence, is both). `analysis` is the analysis of the file's table (the
/// kernel).
pub fn check_file_claim(
    file: &crate::file::TableFile,
    analysis: &Analysis,
    claim: &Claim,
) -> Result<(), ClaimError> {
    if let Some(chi) = file.corrector_table()
        && let Some(verdict) =
            crate::near_integrable::check_processed_claim(&file.table, &chi, claim)
    {
        return verdict.map_err(ClaimError);
    }
    match (claim, &file.certificate) {
        (Claim::CertifiedOrder { p }, Some(spec)) => {
            return crate::certificate::prove(spec, *p)
                .map(|_| ())
                .map_err(ClaimError);
        }
        (Claim::CertifiedNearOrder { orders }, Some(spec)) => {
            return crate::certificate::prove_orders(spec, orders, true)
                .map(|_| ())
                .map_err(ClaimError);
        }
        _ => {}
    }
    check_claim(&file.table, analysis, claim)
}

fn check_symplectic(a: &Analysis) -> Result<(), ClaimError> {
    if a.symplectic_separable {
        return Ok(());
    }
    let shown: Vec<String> = a
        .w_nonzero
        .iter()
        .take(6)
        .map(|e| format!("W[{}][{}] = {}", e.i, e.j, e.value))
        .collect();
    let more = if a.w_nonzero.len() > 6 {
        format!(" and {} more", a.w_nonzero.len() - 6)
    } else {
        String::new()
    };
    let rule = if a.form == Form::Rk {
        "W = BA + AᵀB − bbᵀ must vanish"
    } else {
        "Wᵢⱼ = bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ must vanish"
    };
    Err(ClaimError(format!(
        "not symplectic: {}{more} ({rule})",
        shown.join(", ")
    )))
}

fn check_order(
    table: &Table,
    a: &Analysis,
    p: usize,
    bound: Option<&Number>,
) -> Result<(), ClaimError> {
    let separable = a.separable_only();
    let (max_limit, what) = match (a.form, separable) {
        (Form::Rk, _) => (MAX_RK_ORDER, "Runge–Kutta tables"),
        (Form::Composition, _) => (MAX_COMPOSITION_ORDER, "compositions"),
        (_, true) => (MAX_SEPARABLE_ORDER, "pairs on separable systems"),
        (_, false) => (MAX_PRK_ORDER, "pairs on general partitioned systems"),
    };
    if p > max_limit {
        return Err(ClaimError(format!(
            "order {p} cannot be decided: the checker verifies order conditions of {what} up to order {max_limit}"
        )));
    }
    let default = a.claimed_order_report();
    let report = if bound.is_none() && p <= default.limit {
        default.clone()
    } else {
        match table {
            Table::Rk(rk) => order::rk_order(rk, p, bound),
            Table::Composition(c) => order::composition_order(c, p, bound),
            _ => {
                let prk = table.to_prk().expect("partitioned");
                if separable {
                    order::prk_order_separable(&prk, p, bound)
                } else {
                    order::prk_order(&prk, p, bound)
                }
            }
        }
    };
    let scope = if a.form == Form::Rk {
        ""
    } else if separable {
        " (on separable systems)"
    } else {
        " (on general partitioned systems)"
    };
    verdict(&report, "order", p, bound, scope)
}

/// An `order_rkn = p` claim: the order on Runge–Kutta–Nyström systems (see
/// [`Analysis::order_rkn`]), for every form.
fn check_order_rkn(
    table: &Table,
    a: &Analysis,
    p: usize,
    bound: Option<&Number>,
) -> Result<(), ClaimError> {
    if p > MAX_RKN_ORDER {
        return Err(ClaimError(format!(
            "order_rkn {p} cannot be decided: the checker verifies order conditions on Runge–Kutta–Nyström systems (T quadratic) up to order {MAX_RKN_ORDER}"
        )));
    }
    let report = if bound.is_none() && p <= a.order_rkn.limit {
        a.order_rkn.clone()
    } else {
        match table {
            Table::Rk(rk) => order::rk_order_nystrom(rk, p, bound),
            _ => {
                let prk = table.to_prk().expect("partitioned");
                order::prk_order_nystrom(&prk, p, bound)
            }
        }
    };
    verdict(
        &report,
        "order_rkn",
        p,
        bound,
        " (on Runge–Kutta–Nyström systems, T quadratic)",
    )
}

/// Whether `report` reaches `p`; if not, the failing condition, for a claim
/// `keyword = p` about the systems named in `scope`.
fn verdict(
    report: &OrderReport,
    keyword: &str,
    p: usize,
    bound: Option<&Number>,
    scope: &str,
) -> Result<(), ClaimError> {
    if report.order >= p {
        return Ok(());
    }
    let f = report
        .first_failure
        .as_ref()
        .expect("an order below the limit comes with its failing condition");
    let how = match bound {
        Some(b) => format!("residual {} is not below {b}", f.residual),
        None => format!("residual {}", f.residual),
    };
    // A residual this small usually means rounded decimal coefficients: say
    // how to claim the order honestly.
    let hint = if bound.is_none() && f.residual.to_f64().abs() < 1e-8 {
        format!(
            "; if the coefficients are rounded decimals, claim a bound: `{keyword} = {p} (residual < 1e-14)`"
        )
    } else {
        String::new()
    };
    Err(ClaimError(format!(
        "{keyword} {p} claimed{scope} but the order-{} condition for {} {} fails: {how}{hint}",
        f.order,
        f.kind.noun(),
        f.tree
    )))
}

fn first_implicit_entry(table: &Table) -> String {
    let check = |rk: &Rk, name: &str, strict: bool| -> Option<String> {
        let s = rk.a.len();
        for i in 0..s {
            for j in (if strict { i } else { i + 1 })..s {
                if !rk.a[i][j].is_zero() {
                    return Some(format!("{name}[{i}][{j}] = {} ≠ 0", rk.a[i][j]));
                }
            }
        }
        None
    };
    match table {
        Table::Rk(rk) => check(rk, "a", true).unwrap_or_default(),
        _ => {
            let prk = table.to_prk().expect("partitioned");
            check(&prk.q, "a", false)
                .or_else(|| check(&prk.p, "a_hat", false))
                .map(|e| {
                    format!(
                        "{e}, and the stages depend on each other in a cycle on separable systems"
                    )
                })
                .unwrap_or_default()
        }
    }
}

fn row_sum_mismatch(rk: &Rk, field: &'static str) -> Vec<RowSumMismatch> {
    let Some(c) = &rk.c else { return Vec::new() };
    rk.row_sums()
        .into_iter()
        .zip(c)
        .enumerate()
        .filter(|(_, (sum, given))| sum != *given)
        .map(|(row, (row_sum, given))| RowSumMismatch {
            field,
            row,
            given: given.clone(),
            row_sum,
        })
        .collect()
}

/// The classical order of a drift–kick sequence on the Lie algebra, as an
/// order report: every Lie term of `log Φ` of degree at most `order`
/// vanishes (and the drifts and kicks are consistent), examined up to
/// `limit`, or less where the near-integrable budgets allow less (the
/// report's `limit` is what was examined). The failure is the first failing
/// Lie term of the least degree. An error when not even degree 2 fits the
/// budgets.
pub fn lie_order(table: &Table, limit: usize) -> Result<OrderReport, String> {
    use crate::near_integrable::{NearError, claim_degrees, near_orders};
    let mut limit = limit.max(1);
    let report = loop {
        match near_orders(table, &claim_degrees(&[limit]), None) {
            Ok(r) => break r,
            Err(NearError::Budget(_)) if limit > 2 => limit -= 1,
            Err(e) => return Err(e.to_string()),
        }
    };
    let order = report.parts.iter().map(|p| p.order).min().unwrap_or(limit);
    let first_failure = report
        .parts
        .iter()
        .filter(|p| p.order == order)
        .find_map(|p| p.failure.as_ref())
        .map(|f| order::Failure {
            order: f.degree,
            kind: order::ConditionKind::LieTerm,
            tree: if f.degree == 1 {
                f.lie.clone()
            } else {
                format!("{} (leading word {})", f.lie, f.word)
            },
            value: f.value.clone(),
            expected: f.expected.clone(),
            residual: f.residual.clone(),
        });
    Ok(OrderReport {
        order,
        limit,
        first_failure,
        conditions_checked: report.conditions,
    })
}
