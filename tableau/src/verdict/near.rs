//! The generalised (h, ε) orders of a table for near-integrable
//! `H = A + εB`, as a verdict decides them: which degrees are examined, and
//! the rows and JSON that say the result.

use serde_json::{Value, json};

use crate::Number;
use crate::claims::Claim;
use crate::file::TableFile;
use crate::near_integrable::{
    NearError, NearReport, REPORT_DEGREES, claim_degrees, near_orders, power_label,
    processed_orders,
};

/// The generalised orders of a table, as decided.
#[derive(Clone, Debug)]
pub struct Near {
    /// The degrees examined, `D(j)` for `j = 1, 2, …`.
    pub degrees: Vec<usize>,
    /// The residual bound of the table's generalised-order claim, if any.
    pub bound: Option<Number>,
    pub result: Result<NearReport, NearError>,
    pub time: std::time::Duration,
    /// The orders are a processed method's effective ones (`χ K χ⁻¹`).
    pub processed: bool,
}

/// Decide the generalised orders when the table claims one or `asked`; a
/// Runge–Kutta table or pair is left alone unless asked (then the refusal
/// is reported). The degrees are the report's, raised to one past each
/// claimed order, so a claim's next condition is shown. For a processed
/// method (a kernel with a corrector) the orders are the effective method's
/// (`χ K χ⁻¹`), always decided.
pub(super) fn decide(tf: &TableFile, asked: bool) -> Option<Near> {
    let claim = tf.claims.iter().find_map(|c| match c {
        Claim::NearOrder { orders, bound } => Some((orders.clone(), bound.clone())),
        _ => None,
    });
    if let Some(chi) = tf.corrector_table() {
        return Some(processed(tf, &chi, claim));
    }
    if claim.is_none() && !asked {
        return None;
    }
    let mut degrees = REPORT_DEGREES.to_vec();
    let mut bound = None;
    if let Some((orders, b)) = claim {
        bound = b;
        let claimed = claim_degrees(&orders);
        if claimed.len() > degrees.len() {
            degrees.resize(claimed.len(), *degrees.last().expect("nonempty"));
        }
        for (d, c) in degrees.iter_mut().zip(&claimed) {
            *d = (*d).max(c + 1);
        }
        // Non-increasing, as the truncation needs.
        for j in (0..degrees.len() - 1).rev() {
            degrees[j] = degrees[j].max(degrees[j + 1]);
        }
    }
    let start = std::time::Instant::now();
    let result = near_orders(&tf.table, &degrees, bound.as_ref());
    Some(Near {
        degrees,
        bound,
        result,
        time: start.elapsed(),
        processed: false,
    })
}

/// The effective generalised orders of a processed method. A corrector
/// makes the sequence long (the order-17 one has 63 flows each way), so the
/// degrees are those a claim needs, each one past the claimed order (so its
/// next condition is shown) and the classical order's for every power of ε
/// it bounds; without a claim, the report's degrees narrowed until they fit
/// the budget.
fn processed(
    tf: &TableFile,
    chi: &crate::Table,
    claim: Option<(Vec<usize>, Option<Number>)>,
) -> Near {
    let (candidates, bound) = match claim {
        Some((orders, bound)) => {
            let mut degrees: Vec<usize> = claim_degrees(&orders).iter().map(|d| d + 1).collect();
            let last = *orders.last().expect("a claim has an order");
            while degrees.len() < last + 1 {
                degrees.push(last + 1);
            }
            for j in (0..degrees.len() - 1).rev() {
                degrees[j] = degrees[j].max(degrees[j + 1]);
            }
            (vec![degrees], bound)
        }
        None => (
            vec![
                REPORT_DEGREES.to_vec(),
                vec![12, 6, 6, 6, 6, 6],
                vec![12, 4, 4, 4],
            ],
            None,
        ),
    };
    let start = std::time::Instant::now();
    let mut result = None;
    let mut degrees = Vec::new();
    for d in candidates {
        let r = processed_orders(&tf.table, chi, &d, bound.as_ref());
        let beyond = matches!(r, Err(NearError::Budget(_)));
        degrees = d;
        result = Some(r);
        if !beyond {
            break;
        }
    }
    Near {
        degrees,
        bound,
        result: result.expect("at least one candidate"),
        time: start.elapsed(),
        processed: true,
    }
}

/// The rows saying what a processed method is and how its orders are read.
pub(super) fn processed_rows(tf: &TableFile) -> Vec<String> {
    let Some(chi) = &tf.corrector else {
        return Vec::new();
    };
    let kernel = match &tf.kernel {
        Some(id) => format!("builtin:{id}"),
        None => "the table above".to_string(),
    };
    let flows = chi.normal_form().len();
    vec![
        format!(
            "  {:<13}kernel K = {kernel} (the rows above are its own), corrector χ of {} drifts and {} kicks ({flows} flows); stepped as χ Kⁿ χ⁻¹: χ⁻¹ once on entry, χ only at output",
            "processed",
            chi.drift.len(),
            chi.kick.len(),
        ),
        format!(
            "{:15}effective method χ K χ⁻¹: one drift–kick sequence of {} flows; its orders below and the claims are that method's (each output is exactly its n steps)",
            "",
            effective_flows(tf)
        ),
    ]
}

/// The number of flows of a processed method's effective sequence (0 when
/// it cannot be formed).
pub(super) fn effective_flows(tf: &TableFile) -> usize {
    tf.corrector_table()
        .and_then(|c| crate::near_integrable::processed_sequence(&tf.table, &c).ok())
        .map_or(0, |s| s.len())
}

/// `ε`, `ε²`, …
fn eps(j: usize) -> String {
    power_label(j, 1).trim_end_matches('h').to_string()
}

/// The report's rows for the generalised orders.
pub(super) fn readable(n: &Near) -> Vec<String> {
    let mut out = Vec::new();
    let report = match &n.result {
        Ok(r) => r,
        Err(e) => {
            out.push(format!("  {:<13}not decided: {e}", "H = A + εB"));
            return out;
        }
    };
    let generalised = report.generalised();
    let terms: Vec<String> = generalised
        .iter()
        .enumerate()
        .map(|(i, (p, _))| power_label(i + 1, *p))
        .collect();
    let at_limit = if generalised.iter().all(|g| g.1) {
        ""
    } else {
        " (≥: every condition up to the degree examined holds)"
    };
    out.push(format!(
        "  {:<13}{}generalised order {}: error O({}){at_limit}, drifts the flow of A, kicks that of εB",
        "H = A + εB",
        if n.processed { "effective " } else { "" },
        report.generalised_text(),
        terms.join(" + ")
    ));
    for part in &report.parts {
        let text = match &part.failure {
            Some(f) => format!("order {}; {f}", part.order),
            None => format!(
                "order ≥ {} (every condition up to {} holds)",
                part.order,
                power_label(part.bs, part.limit)
            ),
        };
        out.push(format!("{:15}{} part: {text}", "", eps(part.bs)));
    }
    let how = match &n.bound {
        Some(b) => format!(
            "each within |residual| < {} (the claim's bound for decimal coefficients), compared exactly",
            b.as_rational()
                .and_then(|r| crate::expr::decimal_text(&r))
                .unwrap_or_else(|| b.to_string())
        ),
        None => "each exactly".to_string(),
    };
    let degrees: Vec<String> = n.degrees.iter().map(usize::to_string).collect();
    out.push(format!(
        "{:15}proof: log Φ{} in the free algebra on {{A, B}} truncated to degree ≤ ({}) for 1, 2, … letters B ({} words); {} Lyndon coefficients tested, {how}",
        "",
        if n.processed { " (Φ = χ K χ⁻¹)" } else { "" },
        degrees.join(", "),
        report.words,
        report.conditions
    ));
    out
}

/// The `near_integrable` field of the JSON.
pub(super) fn json(n: &Near) -> Value {
    match &n.result {
        Err(e) => json!({"decided": false, "reason": e.to_string(), "degrees": n.degrees}),
        Ok(r) => json!({
            "decided": true,
            "orders": r.generalised().iter().map(|g| g.0).collect::<Vec<_>>(),
            "exact": r.generalised().iter().map(|g| g.1).collect::<Vec<_>>(),
            "parts": r.parts.iter().map(|p| json!({
                "b_letters": p.bs,
                "order": p.order,
                "limit": p.limit,
                "first_failure": p.failure.as_ref().map(|f| json!({
                    "word": f.word,
                    "lie": f.lie,
                    "degree": f.degree,
                    "value": f.value.to_string(),
                    "value_f64": f.value.to_f64(),
                })),
            })).collect::<Vec<_>>(),
            "degrees": n.degrees,
            "bound": n.bound.as_ref().map(|b| b.to_string()),
            "words": r.words,
            "conditions": r.conditions,
            "ms": n.time.as_secs_f64() * 1e3,
        }),
    }
}
