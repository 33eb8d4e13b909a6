//! `symlab check` and `symlab list`: the exact analysis of a table file or a
//! built-in table, as a readable report or as one JSON object.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use serde_json::{Value, json};
use tableau::analysis::{self, Analysis, Form};
use tableau::catalogue;
use tableau::file::TableFile;
use tableau::order::OrderReport;

#[derive(clap::Args)]
pub struct CheckArgs {
    /// A table file (TOML; see README for the format).
    #[arg(required_unless_present = "builtin", conflicts_with = "builtin")]
    file: Option<PathBuf>,
    /// Analyse a built-in table instead (`symlab list` shows the ids), or a
    /// generated one: gauss, radau1a, radau2a, lobatto3a, lobatto3b,
    /// lobatto3c with the stage count (`gauss8`, `radau2a5`, `gauss(8)`), or
    /// the Lobatto IIIA–IIIB pair (`lobatto3a3b4`); the catalogue's
    /// hand-written table wins where both exist (`gauss3`), `gauss(3)` always
    /// generates.
    #[arg(long, value_name = "ID")]
    builtin: Option<String>,
    /// Print one JSON object instead of the readable report.
    #[arg(long)]
    json: bool,
    /// Also decide the generalised orders (p₁, p₂, …) of a drift–kick
    /// sequence or composition for near-integrable H = A + εB (drifts the
    /// flow of A, kicks that of εB). Done without the flag for a table that
    /// claims one (`order = (8, 6, 4)`).
    #[arg(long)]
    near_integrable: bool,
}

#[derive(clap::Args)]
pub struct ListArgs {
    /// Print a JSON array of {id, name, form, steps, source}.
    #[arg(long)]
    json: bool,
}

/// The stack of the thread that reads and analyses a table. The analysis
/// recurses only as deep as an entry is nested (at most
/// `tableau::expr::MAX_DEPTH` levels), and every collocation table with s ≤ 8
/// written with `root(...)` entries is checked on a 2 MiB stack in the debug
/// build; 16 MiB is margin. Its own thread also turns a panic of the analysis
/// into an error instead of a crash.
const ANALYSIS_STACK_BYTES: usize = 16 << 20;

/// Exit 0 whenever the table parsed, whatever the verdicts; malformed input
/// is an error (exit 2) from `main`.
pub fn run(args: &CheckArgs) -> Result<ExitCode> {
    std::thread::scope(|scope| {
        let worker = std::thread::Builder::new()
            .name("check".into())
            .stack_size(ANALYSIS_STACK_BYTES)
            .spawn_scoped(scope, || run_here(args))
            .map_err(|e| anyhow::anyhow!("cannot start the analysis thread: {e}"))?;
        worker.join().unwrap_or_else(|panic| {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            Err(anyhow::anyhow!(
                "internal error: the analysis panicked ({what}); please report it with the table"
            ))
        })
    })
}

fn run_here(args: &CheckArgs) -> Result<ExitCode> {
    let (origin, tf) = match (&args.file, &args.builtin) {
        (Some(path), _) => match tableau::algebraic::file::load(path)? {
            tableau::algebraic::file::Loaded::Classic(tf) => (path.display().to_string(), *tf),
            tableau::algebraic::file::Loaded::Generated(g) => {
                return print_generated(&path.display().to_string(), &g, args.json);
            }
            tableau::algebraic::file::Loaded::Algebraic(a) => {
                return print_algebraic(&path.display().to_string(), &a, args.json);
            }
        },
        (None, Some(id)) => {
            let generator_syntax = id.contains('(');
            match catalogue::find(id) {
                Some(entry) if !generator_syntax => (format!("builtin:{id}"), entry.load()?),
                _ => match tableau::algebraic::generated::Generated::new(id) {
                    Ok(g) => return print_generated(&format!("builtin:{id}"), &g, args.json),
                    Err(gen_err) if generator_syntax => {
                        anyhow::bail!("builtin:{id}: {gen_err}")
                    }
                    Err(gen_err) => match catalogue::load(id) {
                        Err(e) if gen_err.contains("unknown generator") => {
                            anyhow::bail!(
                                "{e} (or a generated table: gauss8, radau2a5, lobatto3a3b4, …)"
                            )
                        }
                        _ => anyhow::bail!("builtin:{id}: {gen_err}"),
                    },
                },
            }
        }
        (None, None) => unreachable!("clap requires one of them"),
    };
    let analysis = Analysis::of(&tf.table).map_err(|e| anyhow::anyhow!("{origin}: field {e}"))?;
    let near = near_integrable(&tf, args.near_integrable);
    if args.json {
        let mut v = to_json(&tf, &analysis);
        if let Some(n) = &near {
            v["near_integrable"] = near_json(n);
        }
        if let (Some(chi), Some(c)) = (&tf.corrector, tf.corrector_table()) {
            let effective =
                tableau::near_integrable::processed_sequence(&tf.table, &c).map_or(0, |s| s.len());
            v["processed"] = json!({
                "kernel": tf.kernel,
                "corrector_drift": chi.drift.iter().map(|x| x.to_string()).collect::<Vec<_>>(),
                "corrector_kick": chi.kick.iter().map(|x| x.to_string()).collect::<Vec<_>>(),
                "effective_flows": effective,
            });
        }
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        let mut text = readable(&origin, &tf, &analysis);
        let mut rows = processed_rows(&tf);
        if let Some(n) = &near {
            rows.extend(near_readable(n));
        }
        if !rows.is_empty() {
            text = insert_before_claims(&text, &rows);
        }
        print!("{text}");
    }
    Ok(ExitCode::SUCCESS)
}

/// The generalised orders of a near-integrable table, as decided.
struct Near {
    /// The degrees examined, `D(j)` for `j = 1, 2, …`.
    degrees: Vec<usize>,
    /// The residual bound of the table's generalised-order claim, if any.
    bound: Option<tableau::Number>,
    result: Result<tableau::near_integrable::NearReport, tableau::near_integrable::NearError>,
    time: std::time::Duration,
    /// The orders are a processed method's effective ones (`χ K χ⁻¹`).
    processed: bool,
}

/// Decide the generalised orders when the table claims one or `asked`; a
/// Runge–Kutta table or pair is left alone unless asked (then the refusal
/// is reported). The degrees are the report's, raised to one past each
/// claimed order, so a claim's next condition is shown. For a processed
/// method (a kernel with a corrector) the orders are the effective method's
/// (`χ K χ⁻¹`), always decided.
fn near_integrable(tf: &TableFile, asked: bool) -> Option<Near> {
    use tableau::claims::Claim;
    use tableau::near_integrable::{REPORT_DEGREES, claim_degrees, near_orders};
    let claim = tf.claims.iter().find_map(|c| match c {
        Claim::NearOrder { orders, bound } => Some((orders.clone(), bound.clone())),
        _ => None,
    });
    if let Some(chi) = tf.corrector_table() {
        return Some(processed_near(tf, &chi, claim));
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
fn processed_near(
    tf: &TableFile,
    chi: &tableau::Table,
    claim: Option<(Vec<usize>, Option<tableau::Number>)>,
) -> Near {
    use tableau::near_integrable::{REPORT_DEGREES, claim_degrees, processed_orders};
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
        let beyond = matches!(r, Err(tableau::near_integrable::NearError::Budget(_)));
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
fn processed_rows(tf: &TableFile) -> Vec<String> {
    let Some(chi) = &tf.corrector else {
        return Vec::new();
    };
    let kernel = match &tf.kernel {
        Some(id) => format!("builtin:{id}"),
        None => "the table above".to_string(),
    };
    let flows = chi.normal_form().len();
    let effective = tf
        .corrector_table()
        .and_then(|c| tableau::near_integrable::processed_sequence(&tf.table, &c).ok())
        .map_or(0, |s| s.len());
    vec![
        format!(
            "  {:<13}kernel K = {kernel} (the rows above are its own), corrector χ of {} drifts and {} kicks ({flows} flows); stepped as χ Kⁿ χ⁻¹: χ⁻¹ once on entry, χ only at output",
            "processed",
            chi.drift.len(),
            chi.kick.len(),
        ),
        format!(
            "{:15}effective method χ K χ⁻¹: one drift–kick sequence of {effective} flows; its orders below and the claims are that method's (each output is exactly its n steps)",
            ""
        ),
    ]
}

/// `ε`, `ε²`, …
fn eps(j: usize) -> String {
    tableau::near_integrable::power_label(j, 1)
        .trim_end_matches('h')
        .to_string()
}

fn near_readable(n: &Near) -> Vec<String> {
    let mut out = Vec::new();
    let report = match &n.result {
        Ok(r) => r,
        Err(e) => {
            out.push(format!("  {:<13}not decided: {e}", "H = A + εB"));
            return out;
        }
    };
    use tableau::near_integrable::power_label;
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
                .and_then(|r| tableau::expr::decimal_text(&r))
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

fn near_json(n: &Near) -> Value {
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

/// The report with `lines` inserted before its claims (or at its end).
fn insert_before_claims(report: &str, lines: &[String]) -> String {
    let block: String = lines.iter().map(|l| format!("{l}\n")).collect();
    match report.find("\n  claims\n") {
        Some(i) => format!("{}{block}{}", &report[..=i], &report[i + 1..]),
        None => format!("{report}{block}"),
    }
}

fn print_generated(
    origin: &str,
    g: &tableau::algebraic::generated::Generated,
    json: bool,
) -> Result<ExitCode> {
    if json {
        println!("{}", serde_json::to_string_pretty(&generated_json(g))?);
    } else {
        print!("{}", generated_readable(origin, g));
    }
    Ok(ExitCode::SUCCESS)
}

fn print_algebraic(
    origin: &str,
    f: &tableau::algebraic::file::AlgFile,
    json: bool,
) -> Result<ExitCode> {
    let an = f.analyse();
    let claims: Vec<(String, Result<(), String>)> = f
        .claims
        .iter()
        .map(|c| (c.to_string(), f.check_claim(&an, c)))
        .collect();
    if json {
        // W is symmetric (Wᵢⱼ = bᵢaᵢⱼ + bⱼaⱼᵢ − bᵢbⱼ): the analysis decides
        // i ≤ j and both (i, j) and (j, i) are listed, as for other tables.
        let w: Vec<Value> =
            an.w.iter()
                .filter(|e| e.zero != Some(true))
                .flat_map(|e| {
                    let one = |i: usize, j: usize| {
                        json!({"i": i, "j": j, "zero": e.zero, "value_f64": e.value})
                    };
                    if e.i == e.j || an.pair {
                        vec![one(e.i, e.j)]
                    } else {
                        vec![one(e.i, e.j), one(e.j, e.i)]
                    }
                })
                .collect();
        let mut v = json!({
            "name": f.name,
            "kind": if an.pair { "prk" } else { "rk" },
            "stages": an.stages,
            "entries": "algebraic",
            "roots": f.field.names,
            "row_sums_ok": an.row_sums_ok,
            "symplectic": an.symplectic,
            "symplectic_separable": an.symplectic_separable,
            "w_nonzero": w,
            "b_levels": an.b_levels,
            "claims": claims.iter().map(|(c, v)| json!({"claim": c, "holds": v.is_ok(), "reason": v.as_ref().err()})).collect::<Vec<_>>(),
        });
        if an.pair {
            v["b_hat_levels"] = json!(an.b_hat_levels);
        }
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(ExitCode::SUCCESS);
    }
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
    r.claims = claims;
    print!("{}", r.render());
    Ok(ExitCode::SUCCESS)
}

/// The JSON of design.md for a generated table, plus `generator`,
/// `node_polynomial`, `order_proof`, `order_upper`, `a_stable`, `claims`,
/// `max_w_rounded` and the timings.
pub fn generated_json(g: &tableau::algebraic::generated::Generated) -> Value {
    let claims: Vec<Value> = g
        .claims
        .iter()
        .map(|(c, v)| {
            json!({
                "claim": c.to_string(),
                "holds": v.is_ok(),
                "reason": v.as_ref().err().map(|e| e.to_string()),
            })
        })
        .collect();
    json!({
        "name": g.name,
        "generator": g.generator.expression(),
        "node_polynomial": g.node_polynomial.to_text("x"),
        "kind": g.kind,
        "stages": g.stages,
        "class": if g.stages == 1 { "sdirk" } else { "implicit" },
        "row_sums_ok": g.row_sums_ok,
        "symplectic": g.symplectic,
        "symplectic_separable": g.symplectic,
        "order": if g.kind == "prk" && g.tree_order.is_none() {
            Value::Null
        } else {
            json!(g.proven_order())
        },
        "order_upper": g.order.upper,
        "order_proof": g.order.text,
        "order_proof_p": g.order_p.as_ref().map(|o| o.text.clone()),
        "tree_order": g.tree_order.as_ref().map(|t| t.order),
        "tree_order_limit": g.tree_order.as_ref().map(|t| t.limit),
        "symmetric": g.symmetric,
        "stability_function": g.stability.as_ref().map(|r| r.to_text()),
        "a_stable": g.a_stable,
        "r_infinity": g.r_infinity.as_ref().map(|r| r.to_string()),
        "claims": claims,
        "max_w_rounded": g.max_w_rounded,
        "max_w_nearest": g.max_w_nearest,
        "verify_ms": g.verify_time.as_secs_f64() * 1e3,
        "round_ms": g.round_time.as_secs_f64() * 1e3,
    })
}

/// The readable report of a generated table.
pub fn generated_readable(origin: &str, g: &tableau::algebraic::generated::Generated) -> String {
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
    r.claims = g
        .claims
        .iter()
        .map(|(c, v)| {
            (
                c.to_string(),
                v.as_ref().map_err(|e| e.to_string()).copied(),
            )
        })
        .collect();
    r.render()
}

pub fn list(args: &ListArgs) -> Result<ExitCode> {
    // (id, form, name, source), in the order of the library's list (grouped
    // by kind); a generated table (`from: "gauss8"`) has no catalogue file.
    let mut rows: Vec<(String, &'static str, String, Option<String>)> = Vec::new();
    for (id, info) in integrator_core::library::REGISTRY {
        rows.push(match catalogue::find(id) {
            Some(entry) => {
                let tf = entry.load()?;
                (id.to_string(), form_name(&tf.table), tf.name, tf.source)
            }
            None => (
                id.to_string(),
                info.form,
                info.name.to_string(),
                Some("generated by tableau::algebraic (symlab check --builtin ID)".to_string()),
            ),
        });
    }
    // A catalogue file not (yet) in the library's list is still listed; a
    // processed method (a kernel with a corrector, not one scheme of the
    // library) is listed apart, after the table (readable output only).
    let mut processed = Vec::new();
    for entry in catalogue::entries() {
        if !rows.iter().any(|r| r.0 == entry.id) {
            let tf = entry.load()?;
            if tf.corrector.is_some() {
                processed.push((entry.id, tf.name));
                continue;
            }
            rows.push((
                entry.id.to_string(),
                form_name(&tf.table),
                tf.name,
                tf.source,
            ));
        }
    }
    if args.json {
        let v: Vec<Value> = rows
            .iter()
            .map(|(id, form, name, source)| {
                json!({
                    "id": id,
                    "name": name,
                    "form": form,
                    "steps": steps(id),
                    "source": source,
                })
            })
            .collect();
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        let w = rows.iter().map(|r| r.0.len()).max().unwrap_or(0);
        println!("{:w$}  {:<12} {:<12} name", "id", "form", "steps");
        for (id, form, name, _) in &rows {
            println!("{id:w$}  {form:<12} {:<12} {name}", steps(id));
        }
        if !processed.is_empty() {
            println!(
                "\nprocessed methods (kernel + corrector, stepped χ Kⁿ χ⁻¹; `symlab check --builtin ID`, `compare --methods wh:ID`):"
            );
            for (id, name) in &processed {
                println!("{id:w$}  {name}");
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// What the library scheme of this id steps, as its `Step` impls say: `any
/// ODE` (Runge–Kutta tables, explicit ones unrolled, implicit ones through
/// the stage solver: any `OdeSystem`), `split H` (drift–kick sequences and
/// compositions: any `Split` system, the exact flows of two parts, separable
/// H among them), `separable H` (explicit pairs and pairs symplectic only for
/// separable H: `Separable` systems), `any H` (implicit pairs symplectic for
/// every H: any `Hamiltonian`), `-` (not in the library).
pub fn steps(id: &str) -> &'static str {
    match integrator_core::library::info(id) {
        Some(i) if i.form == "rk" => "any ODE",
        Some(i) if i.form == "drift-kick" || i.form == "composition" => "split H",
        Some(i) if i.separable_only || i.explicit => "separable H",
        Some(_) => "any H",
        None => "-",
    }
}

fn form_name(t: &tableau::Table) -> &'static str {
    match t {
        tableau::Table::Rk(_) => "rk",
        tableau::Table::Prk(_) => "prk",
        tableau::Table::Splitting(s) if s.has_gradient() => "gradient-drift-kick",
        tableau::Table::Splitting(_) => "drift-kick",
        tableau::Table::Composition(_) => "composition",
    }
}

/// The JSON object of design.md, field for field.
pub fn to_json(tf: &TableFile, a: &Analysis) -> Value {
    let order_report = a.order.as_ref().unwrap_or(&a.order_separable);
    json!({
        "name": tf.name,
        "kind": a.kind(),
        "stages": a.stages,
        "class": a.class.name(),
        "row_sums_ok": a.row_sum_mismatch.is_empty(),
        "symplectic": a.symplectic,
        "symplectic_separable": a.symplectic_separable,
        "order": a.order.as_ref().map(|o| o.order),
        "order_separable": a.order_separable.order,
        "order_limit": order_report.limit,
        // A sequence with gradient kicks has no Nyström trees: its order on
        // RKN systems is not decided (null), only bounded below.
        "order_rkn": (a.form != Form::GradientDriftKick).then_some(a.order_rkn.order),
        "symmetric": a.symmetric,
        "stability_function": a.stability.as_ref().map(|r| r.to_text()),
        "stability_not_computed": a.stability_not_computed.as_ref().map(|e| e.to_string()),
        "w_nonzero": a.w_nonzero,
    })
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
pub fn readable(origin: &str, tf: &TableFile, a: &Analysis) -> String {
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
    r.claims = tf
        .claims
        .iter()
        .map(|c| {
            let verdict = analysis::check_file_claim(tf, a, c).map_err(|e| e.to_string());
            (c.to_string(), verdict)
        })
        .collect();
    r.render()
}

/// `R(z)` and whether `|R(iy)| = 1` on the imaginary axis.
fn stability_text(
    st: &tableau::analysis::stability::StabilityFunction,
    unimodular: Option<bool>,
) -> String {
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
    /// Each claim as written, and its verdict.
    claims: Vec<(String, Result<(), String>)>,
}

enum Row {
    /// `  label        text`.
    Field(&'static str, String),
    /// A line under the text column (indented 15).
    More(String),
}

impl Report {
    fn new(name: &str, origin: &str) -> Self {
        Report {
            title: format!("{name}  ({origin})"),
            rows: Vec::new(),
            claims: Vec::new(),
        }
    }

    fn row(&mut self, label: &'static str, text: impl Into<String>) {
        self.rows.push(Row::Field(label, text.into()));
    }

    fn more(&mut self, text: String) {
        self.rows.push(Row::More(text));
    }

    fn render(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(s, "{}", self.title);
        for row in &self.rows {
            let _ = match row {
                Row::Field(label, text) => writeln!(s, "  {label:<13}{text}"),
                Row::More(text) => writeln!(s, "{:15}{text}", ""),
            };
        }
        if !self.claims.is_empty() {
            let _ = writeln!(s, "  claims");
            for (c, v) in &self.claims {
                let _ = match v {
                    Ok(()) => writeln!(s, "    ✓ {c}"),
                    Err(e) => writeln!(s, "    ✗ {c}: {e}"),
                };
            }
        }
        s
    }
}
