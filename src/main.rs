//! `symlab`: the command-line program. Thin by design: argument parsing with
//! clap, then calls into the workspace crates; each subcommand lives in its
//! own module.

mod check;
mod cloth_cmd;
mod compare;
mod paper;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "symlab",
    version,
    about = "Butcher tables in, proven integrators out"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Analyse a Butcher table exactly: shape, class, symplecticity, order,
    /// symmetry, stability function, and the file's claims.
    Check(check::CheckArgs),
    /// List the built-in tables (use an id with `symlab check --builtin ID`).
    List(check::ListArgs),
    /// Research comparisons: work-precision sweeps (runs.csv, log-log plots
    /// and report.md), the DOP853 peer over 10-1000 orbits (--peer-study),
    /// long runs (--long) and largest stable steps (--hard).
    Compare(compare::CompareArgs),
    /// Reproduce the paper's experiments (Tan et al., section 5): tables,
    /// plots and a report in out/paper/.
    Paper(paper::PaperArgs),
    /// Simulate a cloth scene (scenes/*.toml) with any method: energy.csv,
    /// an energy plot, OBJ frames, PNG renderings and a summary in
    /// out/cloth/<scene-name>/; or --stability: the largest stable step per method.
    Cloth(cloth_cmd::ClothArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Check(args) => check::run(&args),
        Command::List(args) => check::list(&args),
        Command::Compare(args) => compare::run(&args),
        Command::Paper(args) => paper::run(&args),
        Command::Cloth(args) => cloth_cmd::run(&args),
    };
    match result {
        Ok(code) => code,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::from(2)
        }
    }
}
