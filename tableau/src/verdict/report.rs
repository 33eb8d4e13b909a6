//! The readable report of a verdict: the same layout for every kind of
//! table (name and origin, one labelled row per fact, the claims).

use super::near::{self, Near};
use super::{Analysed, ClaimVerdict, Verdict};
use crate::algebraic::file::{AlgAnalysis, AlgFile};
use crate::algebraic::generated::Generated;
use crate::analysis::stability::StabilityFunction;
use crate::analysis::{Analysis, Form};
use crate::file::TableFile;
use crate::order::OrderReport;

/// The report of `v`, as `symlab check` prints it.
pub(super) fn verdict(v: &Verdict) -> String {
    match &v.analysed {
        Analysed::Classic {
            file,
            analysis,
            near,
            certificate,
        } => {
            let mut text = classic(&v.origin, file, analysis, near.as_ref(), &v.claims);
            if let Some(Ok(proof)) = certificate.as_deref() {
                // Before the claims: the certificate's row.
                let row = format!("  {:<13}{}\n", "certificate", proof.evidence());
                match text.find("  claims\n") {
                    Some(at) => text.insert_str(at, &row),
                    None => text.push_str(&row),
                }
            }
            text
        }
        Analysed::Generated(g) => generated(&v.origin, g, &v.claims),
        Analysed::Algebraic { file, analysis } => algebraic(&v.origin, file, analysis, &v.claims),
    }
}

/// The readable report of a table with `root(...)` entries.
fn algebraic(origin: &str, f: &AlgFile, an: &AlgAnalysis, claims: &[ClaimVerdict]) -> String {
    let mut r = Report::new(&f.name, origin);
    if let Some(src) = &f.source {
        r.row("source", src);
    }
    r.row(
        "entries",
        format!(
            "real algebraic: polynomials in {} root(s) ({}), zero decided exactly",
            f.field.names.len(),
            f.field.names.join(", ")
        ),
    );
    r.row(
        "form",
        format!(
            "{}, {} stages",
            if an.pair {
                "partitioned pair (a, b on q; a_hat, b_hat on p)"
            } else {
                "Runge–Kutta table"
            },
            an.stages
        ),
    );
    let tri = |v: Option<bool>| match v {
        Some(true) => "yes",
        Some(false) => "no",
        None => "undecided (beyond budget)",
    };
    r.row(
        "c",
        format!("equals the row sums of A: {}", tri(an.row_sums_ok)),
    );
    r.row(
        "symplectic",
        format!(
            "{}: {}",
            tri(an.symplectic),
            match (an.pair, an.symplectic) {
                (false, Some(true)) => "W = BA + AᵀB − bbᵀ = 0 exactly".to_string(),
                (false, _) => "W = BA + AᵀB − bbᵀ (symmetric; entries i ≤ j below)".to_string(),
                (true, _) => format!(
                    "Wᵢⱼ = bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ = 0 for all i, j: {}; b = b̂: {}",
                    tri(an.symplectic_separable),
                    tri(an.same_weights)
                ),
            }
        ),
    );
    for e in an.w.iter().filter(|e| e.zero != Some(true)) {
        match e.zero {
            Some(false) => r.more(format!("  W[{}][{}] ≠ 0 ({})", e.i, e.j, e.approx())),
            _ => r.more(format!("  W[{}][{}] undecided (beyond budget)", e.i, e.j)),
        }
    }
    let holds = an.b_levels.iter().take_while(|v| **v == Some(true)).count();
    r.row(
        "quadrature",
        format!(
            "B({holds}) holds exactly{}",
            match an.b_levels.last() {
                Some(Some(false)) => format!(", B({}) fails", holds + 1),
                Some(None) => format!(", B({}) beyond budget", holds + 1),
                _ => String::new(),
            }
        ),
    );
    r.render(claims)
}

/// The readable report of a generated table.
fn generated(origin: &str, g: &Generated, claims: &[ClaimVerdict]) -> String {
    let mut r = Report::new(&g.name, origin);
    r.row("source", g.source);
    r.row(
        "generator",
        format!(
            "{}: nodes are the roots of P(x) = {}",
            g.generator.expression(),
            g.node_polynomial.to_text("x")
        ),
    );
    r.row(
        "exact",
        "every entry is an element of Q[x]/(P) (per stage) or Q[x, y]/(P(x), (P(x) − P(y))/(x − y)) (per pair of stages): products of fields, so each identity below is decided exactly for all stages at once",
    );
    let form = if g.kind == "rk" {
        "Runge–Kutta table"
    } else {
        "partitioned pair (Lobatto IIIA on q, IIIB on p)"
    };
    let class = if g.stages == 1 { "sdirk" } else { "implicit" };
    r.row("form", format!("{form}, {} stages, {class}", g.stages));
    r.row(
        "c",
        if g.row_sums_ok {
            "equals the row sums of A (C(1))"
        } else {
            "differs from the row sums of A (C(1) fails)"
        },
    );
    let verdict = match (g.kind == "rk", g.symplectic) {
        (true, true) => "W = BA + AᵀB − bbᵀ = 0 exactly",
        (true, false) => "W = BA + AᵀB − bbᵀ ≠ 0 (exactly)",
        (false, true) => "Wᵢⱼ = bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ = 0 for all i, j, and b = b̂, exactly",
        (false, false) => {
            "Wᵢⱼ = bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ = 0 for all i, j and b = b̂ do not both hold (exactly)"
        }
    };
    r.row("symplectic", format!("{}: {verdict}", yes_no(g.symplectic)));
    let lower = g.proven_order();
    let order = match g.order.upper {
        _ if g.kind == "prk" && g.tree_order.is_none() => {
            "the pair's order is not proven (bicoloured trees run only where the nodes need at most one square root, s ≤ 5); each table's own order below".to_string()
        }
        Some(u) if g.kind == "rk" && u == lower => format!("{u} exactly"),
        _ if g
            .tree_order
            .as_ref()
            .is_some_and(|t| g.kind == "prk" && t.order < t.limit) =>
        {
            format!(
                "{lower} exactly (the pair's order, on bicoloured trees below; each table's own order in the proof)"
            )
        }
        _ => format!("≥ {lower}"),
    };
    r.row("order", order);
    let label = "IIIA table";
    r.row(
        "proof",
        format!(
            "{}{}",
            if g.kind == "prk" {
                format!("{label}: ")
            } else {
                String::new()
            },
            g.order.text
        ),
    );
    if let Some(p) = &g.order_p {
        r.more(format!("IIIB table: {}", p.text));
    }
    let trees = match &g.tree_order {
        Some(t) => format!(
            "{} on the radical form of the table ({} trees up to order {}): order {}",
            if g.kind == "rk" {
                "checked"
            } else {
                "the pair's order checked"
            },
            if g.kind == "rk" {
                "rooted"
            } else {
                "bicoloured"
            },
            t.limit,
            if t.order >= t.limit {
                format!("≥ {}", t.limit)
            } else {
                t.order.to_string()
            }
        ),
        None => format!(
            "not enumerated (the nodes are not expressible with one square root; order {} needs no tree enumeration)",
            g.order.lower
        ),
    };
    r.row("trees", trees);
    r.row("symmetric", yes_no(g.symmetric));
    if let Some(st) = &g.stability {
        r.row("R(z)", stability_text(st, g.unimodular));
        r.row(
            "A-stable",
            format!(
                "{} (poles in Re z > 0 by an exact Routh–Hurwitz test, |R(iy)| ≤ 1 by an exact sign test of |Q(iy)|² − |P(iy)|²); R(∞) = {}",
                yes_no(g.a_stable == Some(true)),
                g.r_infinity.as_ref().map_or("-".into(), |r| r.to_string())
            ),
        );
    }
    if let (Some(w), Some(n)) = (g.max_w_rounded, g.max_w_nearest) {
        r.row(
            "f64",
            format!(
                "certified correct rounding{}; max |Wᵢⱼ| of the doubles (exact): {w:.3e} (plain nearest: {n:.3e})",
                if g.symplectic {
                    ", then b summed to 1.0 and (aᵢⱼ, aⱼᵢ) chosen among faithful roundings to minimise W"
                } else {
                    ""
                }
            ),
        );
    }
    r.row(
        "time",
        format!(
            "exact verification {:.0} ms, certified f64 coefficients {:.0} ms",
            g.verify_time.as_secs_f64() * 1e3,
            g.round_time.as_secs_f64() * 1e3
        ),
    );
    r.render(claims)
}

fn order_text(r: &OrderReport) -> String {
    match &r.first_failure {
        None => format!(
            "≥ {} (every condition up to the checker's limit, {}, holds)",
            r.order, r.limit
        ),
        Some(f) => format!(
            "{}   (first failing: order-{} condition for {} {}, residual {})",
            r.order,
            f.order,
            f.kind.noun(),
            f.tree,
            f.residual
        ),
    }
}

fn yes_no(b: bool) -> &'static str {
    if b { "yes" } else { "no" }
}

/// The readable report of a table file (or a catalogue table).
fn classic(
    origin: &str,
    tf: &TableFile,
    a: &Analysis,
    near: Option<&Near>,
    claims: &[ClaimVerdict],
) -> String {
    let mut r = Report::new(&tf.name, origin);
    if let Some(src) = &tf.source {
        r.row("source", src);
    }
    let form = match a.form {
        Form::Rk => "Runge–Kutta table",
        Form::Prk => "partitioned pair",
        Form::DriftKick => "drift–kick sequence",
        Form::Composition => "composition of Störmer–Verlet",
        Form::GradientDriftKick => "drift–kick sequence with gradient kicks (no Runge–Kutta form)",
    };
    let gradient = a.form == Form::GradientDriftKick;
    r.row(
        "form",
        format!("{form}, {} stages, {}", a.stages, a.class.name()),
    );
    if a.form != Form::Rk {
        r.row(
            "separable H",
            if a.explicit_separable {
                "explicit"
            } else {
                "implicit"
            },
        );
    }
    if gradient {
        // No Runge–Kutta form, no c.
    } else if a.row_sum_mismatch.is_empty() {
        r.row("c", "equals the row sums of A");
    } else {
        for m in &a.row_sum_mismatch {
            r.row(
                "c",
                format!(
                    "{}[{}] = {} differs from the row sum {} (the order conditions use the given c)",
                    m.field, m.row, m.given, m.row_sum
                ),
            );
        }
    }
    let rule = if a.form == Form::Rk {
        "W = BA + AᵀB − bbᵀ"
    } else {
        "Wᵢⱼ = bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ"
    };
    if gradient {
        r.row(
            "symplectic",
            "yes: a composition of exact flows of Hamiltonians (drifts, kicks, gradient kicks)",
        );
    } else if a.w_nonzero.is_empty() {
        r.row(
            "symplectic",
            format!("{}: {rule} = 0", yes_no(a.symplectic_separable)),
        );
    } else {
        r.row(
            "symplectic",
            format!(
                "{}: {rule} has nonzero entries",
                yes_no(a.symplectic_separable)
            ),
        );
        for e in &a.w_nonzero {
            r.more(format!("  W[{}][{}] = {}", e.i, e.j, e.value));
        }
    }
    if gradient {
        r.row(
            "for all H",
            "no (separable H only: drifts and kicks are the flows of T and V)",
        );
    } else if a.form != Form::Rk {
        r.row(
            "for all H",
            format!(
                "{}{}",
                yes_no(a.symplectic),
                if a.symplectic_separable && !a.symplectic {
                    " (b ≠ b̂: symplectic for separable H only)"
                } else {
                    ""
                }
            ),
        );
    }
    if a.reducible {
        r.row(
            "note",
            "the table is reducible; verdicts are taken on its irreducible form",
        );
    }
    let composition = a.form == Form::Composition;
    match &a.order {
        // On the Lie algebra: every Lie term of log Φ, for any A and B.
        _ if gradient => match &a.lie_not_computed {
            Some(why) => r.row("order", format!("not computed: {why}")),
            None => r.row(
                "order",
                format!(
                    "{}  (separable systems: every Lie term of log Φ)",
                    order_text(&a.order_separable)
                ),
            ),
        },
        Some(o) if a.form == Form::Rk => r.row("order", order_text(o)),
        Some(o) if a.form == Form::Prk => {
            r.row(
                "order",
                format!("{}  (general partitioned systems)", order_text(o)),
            );
            r.row("separable", order_text(&a.order_separable));
        }
        // The separable order, said with the conditions it was checked by;
        // a pair also states its order on general partitioned systems.
        general => {
            let what = match (composition, general.is_some()) {
                (true, true) => ", composition conditions",
                (true, false) => " (composition conditions)",
                (false, _) => "",
            };
            r.row(
                "order",
                format!(
                    "{}  (separable systems{what})",
                    order_text(&a.order_separable)
                ),
            );
            if let Some(o) = general {
                r.row(
                    "general",
                    format!(
                        "{}  (as a pair on general partitioned systems)",
                        order_text(o)
                    ),
                );
            }
        }
    }
    if gradient {
        r.row(
            "T quadratic",
            format!(
                "not decided (gradient kicks have no Runge–Kutta–Nyström trees); at least {}",
                a.order_separable.order
            ),
        );
    } else {
        r.row(
            "T quadratic",
            format!(
                "{}  (Runge–Kutta–Nyström systems, T = ½pᵀM⁻¹p)",
                order_text(&a.order_rkn)
            ),
        );
    }
    r.row("symmetric", yes_no(a.symmetric));
    if let Some(st) = &a.stability {
        r.row("R(z)", stability_text(st, a.unimodular));
    } else if let Some(why) = &a.stability_not_computed {
        r.row("R(z)", format!("not computed: beyond budget ({why})"));
    }
    let mut rows = near::processed_rows(tf);
    if let Some(n) = near {
        rows.extend(near::readable(n));
    }
    for row in rows {
        r.more_raw(row);
    }
    r.render(claims)
}

/// `R(z)` and whether `|R(iy)| = 1` on the imaginary axis.
fn stability_text(st: &StabilityFunction, unimodular: Option<bool>) -> String {
    format!(
        "{}   (|R(iy)| = 1 on the imaginary axis: {})",
        st.to_text(),
        yes_no(unimodular == Some(true))
    )
}

/// A readable report, the same layout for every kind of table (hand-written,
/// generated, with `root(...)` entries): the name and where it came from,
/// then one labelled row per fact (labels in a column of 13), continuation
/// rows under the text, and the claims with their verdicts. Each kind of
/// table states its facts as rows; only this formats them.
struct Report {
    title: String,
    rows: Vec<Row>,
}

enum Row {
    /// `  label        text`.
    Field(&'static str, String),
    /// A line under the text column (indented 15).
    More(String),
    /// A line as given (already laid out).
    Raw(String),
}

impl Report {
    fn new(name: &str, origin: &str) -> Self {
        Report {
            title: format!("{name}  ({origin})"),
            rows: Vec::new(),
        }
    }

    fn row(&mut self, label: &'static str, text: impl Into<String>) {
        self.rows.push(Row::Field(label, text.into()));
    }

    fn more(&mut self, text: String) {
        self.rows.push(Row::More(text));
    }

    fn more_raw(&mut self, line: String) {
        self.rows.push(Row::Raw(line));
    }

    /// The rows, then the claims (each as written, and its verdict).
    fn render(&self, claims: &[ClaimVerdict]) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(s, "{}", self.title);
        for row in &self.rows {
            let _ = match row {
                Row::Field(label, text) => writeln!(s, "  {label:<13}{text}"),
                Row::More(text) => writeln!(s, "{:15}{text}", ""),
                Row::Raw(line) => writeln!(s, "{line}"),
            };
        }
        if !claims.is_empty() {
            let _ = writeln!(s, "  claims");
            for c in claims {
                let _ = match &c.verdict {
                    Ok(()) => writeln!(s, "    ✓ {}", c.claim),
                    Err(e) => writeln!(s, "    ✗ {}: {e}", c.claim),
                };
            }
        }
        s
    }
}
