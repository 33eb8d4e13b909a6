//! `symlab resume DIR`: continue the interrupted run whose output folder
//! is DIR, from its checkpoint, whatever its kind.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Result, bail};
use integrator_core::checkpoint::{FILE_NAME, Kind, read_any};

/// Arguments of `symlab resume`.
#[derive(clap::Args, Debug)]
pub struct ResumeArgs {
    /// The output folder of the interrupted run (it holds checkpoint.symlab).
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
}

pub fn run(args: &ResumeArgs) -> Result<ExitCode> {
    let dir = &args.dir;
    if !dir.is_dir() {
        bail!("{}: no such directory", dir.display());
    }
    let path = dir.join(FILE_NAME);
    if !path.exists() {
        bail!(
            "{}: no checkpoint ({FILE_NAME}) in this folder: the run finished, was never checkpointed, or wrote its output elsewhere",
            dir.display()
        );
    }
    // A truncated, corrupted or foreign file is refused here, naming it.
    let (kind, payload) = read_any(&path)?;
    match kind {
        Kind::Cloth => crate::cloth_cmd::resume(dir, &path, &payload),
        Kind::Compare => crate::compare::resume(dir, &path, &payload),
        Kind::Paper => crate::paper::resume(dir, &path, &payload),
    }
}
