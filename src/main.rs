//! `symlab`: the command-line program. Thin by design: argument parsing with
//! clap, then calls into the workspace crates; each subcommand lives in its
//! own module.

mod check;
mod cloth_cmd;
mod compare;
mod design;
mod paper;
mod resume;
mod signals;

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
    /// out/cloth/<scene-name>/; or --stability: the largest stable step per
    /// method; or --equal-stretch: springs against constraints at ≤ 1 %
    /// stretch.
    Cloth(cloth_cmd::ClothArgs),
    /// Continue an interrupted run (cloth or compare) from the checkpoint
    /// in its output folder (DIR/checkpoint.symlab), to the same bits and
    /// the same files as a run that was never stopped.
    Resume(resume::ResumeArgs),
    /// Design a method: solve a family's order conditions (designs/*.toml)
    /// from many seeded starts, polish, prove and write the tables.
    Design(design::DesignArgs),
}

/// A closed pipe ends the process quietly, as `ls | head` does: Rust
/// ignores SIGPIPE by default, so a write to a pipe whose reader has gone
/// fails and `println!` panics ("failed printing to stdout: Broken pipe").
/// With the default disposition restored the kernel ends the process with
/// signal 13 (SIGPIPE; a shell reports exit status 141) and no message, on
/// stdout, stderr and the progress bars alike.
fn restore_sigpipe() {
    #[cfg(unix)]
    // SAFETY: called first thing in `main`, before any other thread exists;
    // SIG_DFL is a valid disposition for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// The first command-line argument that is not valid UTF-8, as a message
/// naming the flag it belongs to (clap says only "invalid UTF-8 was
/// detected"). `args[0]` is the program.
fn non_utf8_argument(args: &[std::ffi::OsString]) -> Option<String> {
    let (i, bad) = args
        .iter()
        .enumerate()
        .skip(1)
        .find(|(_, a)| a.to_str().is_none())?;
    let shown = bad.to_string_lossy();
    let lossy = shown.as_ref();
    // `--flag=VALUE`: the flag is the part before `=`.
    if let Some(rest) = lossy.strip_prefix("--")
        && let Some((flag, value)) = rest.split_once('=')
        && flag.chars().all(|c| c.is_ascii_alphanumeric() || c == '-')
        && !flag.is_empty()
    {
        return Some(format!(
            "--{flag}: the value {value:?} is not valid UTF-8 (invalid bytes shown as �)"
        ));
    }
    if lossy.starts_with('-') {
        return Some(format!(
            "argument {i} {lossy:?} is not valid UTF-8 (invalid bytes shown as �)"
        ));
    }
    match args[i - 1].to_str() {
        Some(prev) if i > 1 && prev.starts_with('-') && prev != "--" => Some(format!(
            "{prev}: the value {lossy:?} is not valid UTF-8 (invalid bytes shown as �)"
        )),
        _ => Some(format!(
            "argument {i} {lossy:?} is not valid UTF-8 (invalid bytes shown as �); \
             file names and values must be UTF-8"
        )),
    }
}

fn main() -> ExitCode {
    restore_sigpipe();
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    if let Some(msg) = non_utf8_argument(&args) {
        eprintln!("error: {msg}");
        return ExitCode::from(2);
    }
    // A SYMLAB_SIMD the kernels cannot honour is refused before anything
    // runs, rather than warned about from inside a kernel.
    if let Err(e) = integrator_core::simd::env_cap() {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    // The arguments after the subcommand, as text (checked above): a
    // checkpoint keeps them so that `symlab resume` plans the same run.
    let rest: Vec<String> = args
        .iter()
        .skip(2)
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    let cli = Cli::parse_from(args);
    let result = match cli.command {
        Command::Check(args) => check::run(&args),
        Command::List(args) => check::list(&args),
        Command::Compare(args) => compare::run(&args, &rest),
        Command::Paper(args) => paper::run(&args),
        Command::Cloth(args) => cloth_cmd::run(&args),
        Command::Resume(args) => resume::run(&args),
        Command::Design(args) => design::run(&args),
    };
    match result {
        Ok(code) => code,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::from(2)
        }
    }
}
