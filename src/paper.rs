//! `symlab paper`: the command-line client of the paper's reproduction
//! ([`jobs::paper`], which checks the set-up, runs the oscillator and the
//! cloth comparison of figure 5, and writes the tables, plots and
//! `report.md`). This module reads the flags into the job's request and
//! prints what the job returns; a refused field reads as its flag.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Result;
use compare::paper_oscillator::Config;
use jobs::paper::{DEFAULT_CLOTH_FRAMES, Observer, PaperError, Reproduced, Request, Stage};

#[derive(clap::Args, Debug)]
pub struct PaperArgs {
    /// The directory to write the tables, plots and report into (created if
    /// missing; files of the same names are overwritten).
    #[arg(long, value_name = "DIR", default_value = "out/paper")]
    pub out: PathBuf,
    /// The frequency k of H = ½(p² + k²q²) (the paper does not state it).
    #[arg(long, default_value_t = Config::default().k, allow_hyphen_values = true)]
    pub k: f64,
    /// The initial position q₀.
    #[arg(long, default_value_t = Config::default().q0, allow_hyphen_values = true)]
    pub q0: f64,
    /// The initial momentum p₀.
    #[arg(long, default_value_t = Config::default().p0, allow_hyphen_values = true)]
    pub p0: f64,
    /// Steps per run (the paper: 200).
    #[arg(long, default_value_t = Config::default().steps, allow_hyphen_values = true)]
    pub steps: usize,
    /// The step sizes, comma-separated (the paper: 0.01, 0.05 and 0.1).
    #[arg(long = "h", value_name = "H,...", value_delimiter = ',', default_values_t = Config::default().step_sizes, allow_hyphen_values = true)]
    pub step_sizes: Vec<f64>,
    /// Frames of the cloth comparison (figure 5), at 60 Hz; 0 skips it; at
    /// most 10⁶.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_CLOTH_FRAMES, allow_hyphen_values = true)]
    pub cloth_frames: usize,
}

impl PaperArgs {
    /// The job's request, as the flags say (the job checks it).
    pub fn request(&self) -> Request {
        Request {
            out: self.out.clone(),
            oscillator: Config {
                k: self.k,
                q0: self.q0,
                p0: self.p0,
                steps: self.steps,
                step_sizes: self.step_sizes.clone(),
            },
            cloth_frames: self.cloth_frames,
        }
    }
}

/// `symlab paper`: run the job (it reports each cloth run on stderr: the
/// oscillator takes a second, the cloth comparison about 30 s in release),
/// then print its summary and the files it wrote. SIGINT or SIGTERM stop
/// it after the cloth run under way, with its checkpoint
/// (`symlab resume DIR` goes on) and exit status 130 or 143.
pub fn run(args: &PaperArgs) -> Result<ExitCode> {
    let request = args.request();
    finish(jobs::paper::run(&request, &mut Front), &request.out)
}

/// `symlab resume DIR` on a paper run's checkpoint.
pub fn resume(dir: &Path, path: &Path, payload: &[u8]) -> Result<ExitCode> {
    println!("resuming the paper run in {}", dir.display());
    finish(jobs::paper::resume(dir, path, payload, &mut Front), dir)
}

/// The command line's observer: each cloth run on stderr, and a stop when
/// a signal came.
struct Front;

impl Observer for Front {
    fn stage(&mut self, stage: Stage) {
        if let Stage::Cloth { .. } = stage {
            crate::signals::install();
        }
    }
    fn cloth_run(&mut self, done: usize, total: usize) {
        eprintln!("cloth comparison: {done} of {total} runs done");
    }
    fn stop(&mut self) -> bool {
        crate::signals::requested().is_some()
    }
}

fn finish(result: Result<Reproduced, PaperError>, dir: &Path) -> Result<ExitCode> {
    let done = match result {
        Ok(done) => done,
        Err(PaperError::Stopped {
            checkpoint,
            done,
            total,
        }) => {
            let sig = crate::signals::requested().unwrap_or(15);
            println!(
                "stopped by {} after {done} of {total} cloth runs",
                crate::signals::name(sig)
            );
            println!(
                "checkpoint {} — continue with: symlab resume {}",
                checkpoint.display(),
                dir.display()
            );
            return Ok(ExitCode::from(crate::signals::exit_status(sig)));
        }
        Err(e) => return Err(e.into()),
    };
    let summary = &done.summary;
    println!("{}", summary.oscillator.heading);
    for line in &summary.oscillator.lines {
        println!("{line}");
    }
    println!();
    println!("{}", summary.cloth.heading);
    if done.cloth.is_some() {
        for line in &summary.cloth.lines {
            println!("{line}");
        }
        println!();
    } else {
        println!("skipped (--cloth-frames 0)");
    }
    println!(
        "Wrote {} files to {}:",
        done.files.len(),
        done.dir.display()
    );
    for name in &done.files {
        println!("  {name}");
    }
    println!("Read {} first.", done.report.display());
    Ok(ExitCode::SUCCESS)
}
