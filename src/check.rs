//! `symlab check` and `symlab list`: the exact analysis of a table file or a
//! built-in table, as a readable report or as one JSON object. Both are
//! `tableau::verdict`'s (`symlab.check` in Python prints the same); this
//! file only reads the flags and prints.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use tableau::verdict::{self, Options, Source};

#[derive(clap::Args)]
pub struct CheckArgs {
    /// A table file (TOML; its format: guide/src/check.md).
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
    /// Print a JSON array of {id, name, form, steps, source, processed}.
    #[arg(long)]
    json: bool,
}

/// Exit 0 whenever the table parsed, whatever the verdicts; malformed input
/// is an error (exit 2) from `main`.
pub fn run(args: &CheckArgs) -> Result<ExitCode> {
    let source = match (&args.file, &args.builtin) {
        (Some(path), _) => Source::File(path),
        (None, Some(id)) => Source::Builtin(id),
        (None, None) => unreachable!("clap requires one of them"),
    };
    let options = Options {
        near_integrable: args.near_integrable,
    };
    let v = verdict::check(&source, &options)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&v.to_json())?);
    } else {
        print!("{v}");
    }
    Ok(ExitCode::SUCCESS)
}

pub fn list(args: &ListArgs) -> Result<ExitCode> {
    let rows = integrator_core::library::listing()?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&rows)?);
        return Ok(ExitCode::SUCCESS);
    }
    let w = rows.iter().map(|r| r.id.len()).max().unwrap_or(0);
    println!("{:w$}  {:<12} {:<12} name", "id", "form", "steps");
    for r in rows.iter().filter(|r| !r.processed) {
        println!("{:w$}  {:<12} {:<12} {}", r.id, r.form, r.steps, r.name);
    }
    if rows.iter().any(|r| r.processed) {
        println!(
            "\nprocessed methods (kernel + corrector, stepped χ Kⁿ χ⁻¹; `symlab check --builtin ID`, `compare --methods wh:ID`):"
        );
        for r in rows.iter().filter(|r| r.processed) {
            println!("{:w$}  {}", r.id, r.name);
        }
    }
    Ok(ExitCode::SUCCESS)
}
