//! `symlab paper`: the experiments of Tan et al.'s section 5, reproduced.
//!
//! 1. The oscillator `H = ½(p² + k²q²)` (their figures 2–4): six schemes at
//!    three step sizes against the analytic solution
//!    ([`compare::paper_oscillator`] runs them and writes the CSV of errors
//!    and the CSV of every step), and plots ([`figures`]).
//! 2. The cloth comparison of their figure 5 (explicit Euler against
//!    symplectic Euler on the undamped scene at 16.7 ms frames, with
//!    Störmer–Verlet, implicit Euler and Gauss–Legendre 2): [`cloth`].
//! 3. `report.md`: claims, measurements, differences ([`report`]).
//!
//! This module parses and checks the flags (its messages name them), calls
//! the library, and writes and prints what it returns.

pub mod cloth;
pub mod figures;
pub mod report;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result, bail};

use compare::paper_oscillator::{
    Config, Experiment, Invalid, MAX_STEPS, MIN_STEPS, errors_csv, experiment, h_name, series_csv,
};

#[derive(clap::Args, Debug)]
pub struct PaperArgs {
    /// The directory to write the tables, plots and report into (created if
    /// missing; files of the same names are overwritten).
    #[arg(long, value_name = "DIR", default_value = "out/paper")]
    pub out: PathBuf,
    /// The frequency k of H = ½(p² + k²q²) (the paper does not state it).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub k: f64,
    /// The initial position q₀.
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub q0: f64,
    /// The initial momentum p₀.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub p0: f64,
    /// Steps per run (the paper: 200).
    #[arg(long, default_value_t = 200, allow_hyphen_values = true)]
    pub steps: usize,
    /// The step sizes, comma-separated (the paper: 0.01, 0.05 and 0.1).
    #[arg(long = "h", value_name = "H,...", value_delimiter = ',', default_values_t = [0.01, 0.05, 0.1], allow_hyphen_values = true)]
    pub step_sizes: Vec<f64>,
    /// Frames of the cloth comparison (figure 5), at 60 Hz; 0 skips it; at
    /// most 10⁶.
    #[arg(long, value_name = "N", default_value_t = cloth::DEFAULT_FRAMES, allow_hyphen_values = true)]
    pub cloth_frames: usize,
}

impl PaperArgs {
    /// The oscillator's set-up, checked: a set-up the experiment cannot
    /// measure is refused naming the flags at fault.
    pub fn config(&self) -> Result<Config> {
        checked(Config {
            k: self.k,
            q0: self.q0,
            p0: self.p0,
            steps: self.steps,
            step_sizes: self.step_sizes.clone(),
        })
    }
}

/// `config`, or why it is refused, naming the flags.
fn checked(config: Config) -> Result<Config> {
    match config.check() {
        Ok(()) => Ok(config),
        Err(why) => bail!("{}", flag_message(&why)),
    }
}

/// Why the oscillator's set-up is refused, naming the flags.
fn flag_message(why: &Invalid) -> String {
    match why {
        Invalid::K(k) => format!("--k must be a finite positive number (got {k})"),
        Invalid::StartNotFinite { q0, p0 } => {
            format!("--q0 and --p0 must be finite (got q0 = {q0}, p0 = {p0})")
        }
        Invalid::AtRest => "--q0 and --p0 are both 0: the oscillator would rest at its equilibrium with zero energy".into(),
        Invalid::TooFewSteps(n) => format!(
            "--steps must be at least {MIN_STEPS} (got {n}): the claims compare the run's halves and its first {MIN_STEPS} steps"
        ),
        Invalid::TooManySteps(n) => format!(
            "--steps must be at most {MAX_STEPS} (got {n}): every step is plotted and written"
        ),
        Invalid::Energy { k, q0, p0, energy0 } => format!(
            "--k {k:e}, --q0 {q0:e}, --p0 {p0:e}: the energy H(q0, p0) = {energy0:e} is not a normal positive f64, \
             so relative energy errors |H − H0|/H0 would be meaningless; choose values whose \
             energy lies between 1e-300 and 1e300"
        ),
        Invalid::NoStepSizes => "--h needs at least one step size".into(),
        Invalid::StepSize(h) => {
            format!("--h: every step size must be a finite positive number (got {h})")
        }
        Invalid::RepeatedStepSize(h) => format!("--h: step size {h} is given twice"),
    }
}

/// The names of every file the oscillator part writes, in the report's order.
pub fn oscillator_files(config: &Config) -> Vec<String> {
    let mut names = vec!["oscillator_errors.csv".to_string()];
    for &h in &config.step_sizes {
        names.push(format!("oscillator_h{}_series.csv", h_name(h)));
        names.extend(figures::plot_names(h));
    }
    names
}

fn write(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
}

/// Write the oscillator's tables and plots into `dir`.
pub fn write_oscillator(exp: &Experiment, dir: &Path) -> Result<()> {
    write(&dir.join("oscillator_errors.csv"), &errors_csv(exp))?;
    for &h in &exp.config.step_sizes {
        write(
            &dir.join(format!("oscillator_h{}_series.csv", h_name(h))),
            &series_csv(exp, h),
        )?;
        figures::write_plots(exp, h, dir)?;
    }
    Ok(())
}

/// `symlab paper`.
pub fn run(args: &PaperArgs) -> Result<ExitCode> {
    let config = args.config()?;
    if args.cloth_frames > ::cloth::MAX_FRAMES {
        bail!(
            "--cloth-frames must be at most {} (got {}): every frame's statistics stay in memory, and each of the comparison's runs simulates them all",
            ::cloth::MAX_FRAMES,
            args.cloth_frames
        );
    }
    let dir = &args.out;
    std::fs::create_dir_all(dir)
        .with_context(|| format!("--out {}: cannot create the directory", dir.display()))?;

    let exp = experiment(&config)?;
    write_oscillator(&exp, dir)?;
    let cloth = cloth::section(dir, args.cloth_frames)?;

    let mut files = oscillator_files(&config);
    files.extend(cloth.files.iter().cloned());
    files.push("report.md".into());
    write(
        &dir.join("report.md"),
        &report::markdown(&exp, &cloth.markdown, &files),
    )?;

    println!(
        "Oscillator H = ½(p² + k²q²), k = {}, q₀ = {}, p₀ = {}, {} steps: maximum errors over the run",
        config.k, config.q0, config.p0, config.steps
    );
    print!("{}", report::text_table(&exp));
    println!();
    println!("Cloth comparison (figure 5), paper scene at 60 Hz frames:");
    print!("{}", cloth.terminal);
    println!();
    println!("Wrote {} files to {}:", files.len(), dir.display());
    for name in &files {
        println!("  {name}");
    }
    println!("Read {} first.", dir.join("report.md").display());
    Ok(ExitCode::SUCCESS)
}
