//! `symlab check` and `symlab list`: the exact analysis of a table file or a
//! built-in table, as a readable report or as one JSON object.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use serde_json::{Value, json};
use tableau::analysis::{self, Analysis, Form};
use tableau::file::TableFile;
use tableau::order::OrderReport;
use tableau::{catalogue, file};

#[derive(clap::Args)]
pub struct CheckArgs {
    /// A table file (TOML; see README for the format).
    #[arg(required_unless_present = "builtin", conflicts_with = "builtin")]
    file: Option<PathBuf>,
    /// Analyse a built-in table instead (`symlab list` shows the ids).
    #[arg(long, value_name = "ID")]
    builtin: Option<String>,
    /// Print one JSON object instead of the readable report.
    #[arg(long)]
    json: bool,
}

#[derive(clap::Args)]
pub struct ListArgs {
    /// Print a JSON array of {id, name, form, steps, source}.
    #[arg(long)]
    json: bool,
}

/// Exit 0 whenever the table parsed, whatever the verdicts; malformed input
/// is an error (exit 2) from `main`.
pub fn run(args: &CheckArgs) -> Result<ExitCode> {
    let (origin, tf) = match (&args.file, &args.builtin) {
        (Some(path), _) => (path.display().to_string(), file::load(path)?),
        (None, Some(id)) => (format!("builtin:{id}"), catalogue::load(id)?),
        (None, None) => unreachable!("clap requires one of them"),
    };
    let analysis = Analysis::of(&tf.table).map_err(|e| anyhow::anyhow!("{origin}: field {e}"))?;
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&to_json(&tf, &analysis))?
        );
    } else {
        print!("{}", readable(&origin, &tf, &analysis));
    }
    Ok(ExitCode::SUCCESS)
}

pub fn list(args: &ListArgs) -> Result<ExitCode> {
    let mut rows = Vec::new();
    for entry in catalogue::entries() {
        let tf = catalogue::load(entry.id)?;
        rows.push((entry.id, tf));
    }
    if args.json {
        let v: Vec<Value> = rows
            .iter()
            .map(|(id, tf)| {
                json!({
                    "id": id,
                    "name": tf.name,
                    "form": form_name(&tf.table),
                    "steps": steps(id),
                    "source": tf.source,
                })
            })
            .collect();
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        let w = rows.iter().map(|(id, _)| id.len()).max().unwrap_or(0);
        println!("{:w$}  {:<12} {:<12} name", "id", "form", "steps");
        for (id, tf) in &rows {
            println!(
                "{id:w$}  {:<12} {:<12} {}",
                form_name(&tf.table),
                steps(id),
                tf.name
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// What the library scheme of this id steps, as its `Step` impls say: `any
/// ODE` (Runge–Kutta tables, explicit ones unrolled, implicit ones through
/// the stage solver: any `OdeSystem`), `separable H` (drift–kick sequences,
/// compositions, explicit pairs and pairs symplectic only for separable H:
/// `Separable` systems), `any H` (implicit pairs symplectic for every H:
/// any `Hamiltonian`), `-` (not in the library).
pub fn steps(id: &str) -> &'static str {
    match integrator_core::library::info(id) {
        Some(i) if i.form == "rk" => "any ODE",
        Some(i) if i.separable_only || i.explicit => "separable H",
        Some(_) => "any H",
        None => "-",
    }
}

fn form_name(t: &tableau::Table) -> &'static str {
    match t {
        tableau::Table::Rk(_) => "rk",
        tableau::Table::Prk(_) => "prk",
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
        "order_rkn": a.order_rkn.order,
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

pub fn readable(origin: &str, tf: &TableFile, a: &Analysis) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(s, "{}  ({origin})", tf.name);
    if let Some(src) = &tf.source {
        let _ = writeln!(s, "  source       {src}");
    }
    let form = match a.form {
        Form::Rk => "Runge–Kutta table",
        Form::Prk => "partitioned pair",
        Form::DriftKick => "drift–kick sequence",
        Form::Composition => "composition of Störmer–Verlet",
    };
    let _ = writeln!(
        s,
        "  form         {form}, {} stages, {}",
        a.stages,
        a.class.name()
    );
    if a.form != Form::Rk {
        let _ = writeln!(
            s,
            "  separable H  {}",
            if a.explicit_separable {
                "explicit"
            } else {
                "implicit"
            }
        );
    }
    if a.row_sum_mismatch.is_empty() {
        let _ = writeln!(s, "  c            equals the row sums of A");
    } else {
        for m in &a.row_sum_mismatch {
            let _ = writeln!(
                s,
                "  c            {}[{}] = {} differs from the row sum {} (the order conditions use the given c)",
                m.field, m.row, m.given, m.row_sum
            );
        }
    }
    let rule = if a.form == Form::Rk {
        "W = BA + AᵀB − bbᵀ"
    } else {
        "Wᵢⱼ = bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ"
    };
    if a.w_nonzero.is_empty() {
        let _ = writeln!(
            s,
            "  symplectic   {}: {rule} = 0",
            yes_no(a.symplectic_separable)
        );
    } else {
        let _ = writeln!(
            s,
            "  symplectic   {}: {rule} has nonzero entries",
            yes_no(a.symplectic_separable)
        );
        for e in &a.w_nonzero {
            let _ = writeln!(s, "                 W[{}][{}] = {}", e.i, e.j, e.value);
        }
    }
    if a.form != Form::Rk {
        let _ = writeln!(
            s,
            "  for all H    {}{}",
            yes_no(a.symplectic),
            if a.symplectic_separable && !a.symplectic {
                " (b ≠ b̂: symplectic for separable H only)"
            } else {
                ""
            }
        );
    }
    if a.reducible {
        let _ = writeln!(
            s,
            "  note         the table is reducible; verdicts are taken on its irreducible form"
        );
    }
    match &a.order {
        Some(o) if a.form == Form::Rk => {
            let _ = writeln!(s, "  order        {}", order_text(o));
        }
        Some(o) if a.form == Form::Prk => {
            let _ = writeln!(
                s,
                "  order        {}  (general partitioned systems)",
                order_text(o)
            );
            let _ = writeln!(s, "  separable    {}", order_text(&a.order_separable));
        }
        Some(o) => {
            let what = if a.form == Form::Composition {
                ", composition conditions"
            } else {
                ""
            };
            let _ = writeln!(
                s,
                "  order        {}  (separable systems{what})",
                order_text(&a.order_separable)
            );
            let _ = writeln!(
                s,
                "  general      {}  (as a pair on general partitioned systems)",
                order_text(o)
            );
        }
        None => {
            let what = if a.form == Form::Composition {
                " (composition conditions)"
            } else {
                ""
            };
            let _ = writeln!(
                s,
                "  order        {}  (separable systems{what})",
                order_text(&a.order_separable)
            );
        }
    }
    let _ = writeln!(
        s,
        "  T quadratic  {}  (Runge–Kutta–Nyström systems, T = ½pᵀM⁻¹p)",
        order_text(&a.order_rkn)
    );
    let _ = writeln!(s, "  symmetric    {}", yes_no(a.symmetric));
    if let Some(r) = &a.stability {
        let _ = writeln!(
            s,
            "  R(z)         {}   (|R(iy)| = 1 on the imaginary axis: {})",
            r.to_text(),
            yes_no(a.unimodular == Some(true))
        );
    } else if let Some(why) = &a.stability_not_computed {
        let _ = writeln!(s, "  R(z)         not computed: beyond budget ({why})");
    }
    if !tf.claims.is_empty() {
        let _ = writeln!(s, "  claims");
        for c in &tf.claims {
            match analysis::check_claim(&tf.table, a, c) {
                Ok(()) => {
                    let _ = writeln!(s, "    ✓ {c}");
                }
                Err(e) => {
                    let _ = writeln!(s, "    ✗ {c}: {e}");
                }
            }
        }
    }
    s
}
