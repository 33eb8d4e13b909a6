//! Checkpoints of `symlab cloth` runs and their resumption: when to write
//! one (`--checkpoint-every`, a signal), what goes in it beside the
//! library's [`RunState`] (the command's arguments, the scene's text, the
//! frames kept for rendering, the OBJ count, the wall time so far), and
//! the output of a run a signal stopped.
//!
//! The arguments and the scene's text are saved, not the file's name
//! alone, so that `symlab resume` plans exactly the run that was stopped
//! even when the scene file has changed or moved since.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

use anyhow::{Result, anyhow, bail};
use clap::Parser;
use cloth::checkpoint::{
    Action, CheckpointError, Decoder, Encoder, Kind, RunControl, RunState, resumable,
};
use cloth::{FrameStats, Method, Vec3};

use super::{ClothArgs, Collected, Plan, energy_files};

pub use integrator_core::checkpoint::{DEFAULT_EVERY, Every, parse_every};

/// The interval of a run of `method`: the flag's, or the default where
/// the method's runs can be resumed. A flag asking for checkpoints of a
/// method that cannot save its stepper is refused rather than ignored.
pub fn interval(flag: Option<Every>, method: &Method) -> Result<Option<Duration>> {
    match flag {
        Some(Every::Off) => Ok(None),
        Some(Every::After(d)) if resumable(method) => Ok(Some(d)),
        Some(Every::After(_)) => bail!(
            "--checkpoint-every: {} runs cannot be checkpointed yet (RATTLE runs of inextensible scenes can); use --checkpoint-every off",
            method.id()
        ),
        None => Ok(resumable(method).then_some(DEFAULT_EVERY)),
    }
}

/// The output folder is writable (checked before a run starts).
pub fn check_writable(dir: &Path) -> Result<()> {
    Ok(integrator_core::checkpoint::check_writable(dir)?)
}

/// Remove a checkpoint (none there is not an error).
pub fn remove(path: &Path) -> Result<()> {
    Ok(integrator_core::checkpoint::remove(path)?)
}

/// What every checkpoint of a run repeats.
pub struct Saving {
    /// The arguments after `symlab cloth`.
    pub argv: Vec<String>,
    /// The scene file's name as given, and its text.
    pub scene_file: String,
    pub scene_text: String,
    /// `None`: only when a signal stops the run.
    pub every: Option<Duration>,
}

/// A run read back from a checkpoint.
pub struct Resumed {
    pub argv: Vec<String>,
    pub scene_file: String,
    pub scene_text: String,
    /// Wall time of the run before it stopped (s).
    pub wall: f64,
    pub objs: usize,
    pub kept: BTreeMap<usize, (f64, Vec<Vec3>)>,
    pub state: RunState,
}

fn encode(saving: &Saving, wall: f64, col: &Collected, state: &RunState) -> Vec<u8> {
    let mut e = Encoder::new();
    e.usize(saving.argv.len());
    for a in &saving.argv {
        e.str(a);
    }
    e.str(&saving.scene_file)
        .str(&saving.scene_text)
        .f64(wall)
        .usize(col.objs)
        .usize(col.kept.len());
    for (k, (t, positions)) in &col.kept {
        let flat: Vec<f64> = positions.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
        e.usize(*k).f64(*t).f64s(&flat);
    }
    state.encode(&mut e);
    e.finish()
}

fn decode(path: &Path, payload: &[u8]) -> Result<Resumed, CheckpointError> {
    let mut d = Decoder::new(path, payload);
    let n = d.usize("arguments")?;
    if n > 1000 {
        return Err(d.error(format!("arguments: {n} of them")));
    }
    let argv = (0..n)
        .map(|_| d.str("arguments").map(str::to_string))
        .collect::<Result<Vec<_>, _>>()?;
    let scene_file = d.str("scene file")?.to_string();
    let scene_text = d.str("scene text")?.to_string();
    let wall = d.f64("wall time")?;
    let objs = d.usize("OBJ count")?;
    let nk = d.usize("kept frames")?;
    let mut kept = BTreeMap::new();
    for _ in 0..nk {
        let k = d.usize("kept frame")?;
        let t = d.f64("kept frame time")?;
        let flat = d.f64s("kept frame positions")?;
        if flat.len() % 3 != 0 {
            return Err(d.error("kept frame positions: not a list of 3-vectors"));
        }
        let positions = flat
            .chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect();
        kept.insert(k, (t, positions));
    }
    let state = RunState::decode(&mut d)?;
    d.end()?;
    Ok(Resumed {
        argv,
        scene_file,
        scene_text,
        wall,
        objs,
        kept,
        state,
    })
}

/// The arguments of `symlab cloth`, for reading a checkpoint's back.
#[derive(Parser)]
#[command(name = "symlab cloth")]
struct Stored {
    #[command(flatten)]
    args: ClothArgs,
}

/// `symlab resume DIR` of a cloth run: `payload` read from `path` in `dir`.
pub fn resume(dir: &Path, path: &Path, payload: &[u8]) -> Result<ExitCode> {
    let resumed = decode(path, payload)?;
    let argv = resumed.argv.clone();
    let mut args = Stored::try_parse_from(
        std::iter::once("symlab cloth".to_string()).chain(argv.iter().cloned()),
    )
    .map_err(|e| {
        anyhow!(
            "{}: the saved arguments `symlab cloth {}` do not parse: {}",
            path.display(),
            argv.join(" "),
            e.to_string().trim()
        )
    })?
    .args;
    // The folder may have moved since: the run goes on where its
    // checkpoint is.
    args.out = Some(dir.to_path_buf());
    super::run_or_resume(&args, &argv, Some(resumed))
}

/// The [`RunControl`] of a `symlab cloth` run.
pub struct Control<'a> {
    saving: &'a Saving,
    path: PathBuf,
    col: &'a RefCell<Collected>,
    wall_before: f64,
    started: Instant,
    last: Instant,
    /// The signal that stopped the run.
    pub stopped_by: Option<i32>,
    /// Whether a stop found a stepper that cannot be saved.
    unsaved: bool,
    /// The frame of the last checkpoint written, its size and write time.
    pub saved_frame: Option<usize>,
    written: usize,
    bytes: usize,
    seconds: f64,
}

impl<'a> Control<'a> {
    pub fn new(
        saving: &'a Saving,
        path: &Path,
        col: &'a RefCell<Collected>,
        wall_before: f64,
    ) -> Control<'a> {
        let now = Instant::now();
        Control {
            saving,
            path: path.to_path_buf(),
            col,
            wall_before,
            started: now,
            last: now,
            stopped_by: None,
            unsaved: false,
            saved_frame: None,
            written: 0,
            bytes: 0,
            seconds: 0.0,
        }
    }

    /// A line about the checkpoints for a stopped run.
    pub fn note(&self) -> Option<String> {
        self.stopped_by?;
        if self.unsaved {
            return Some(
                "no checkpoint: this method's runs cannot be resumed yet (RATTLE runs can)".into(),
            );
        }
        (self.written > 0).then(|| {
            format!(
                "{} checkpoint{} written, the last {:.1} KiB in {:.1} ms",
                self.written,
                if self.written == 1 { "" } else { "s" },
                self.bytes as f64 / 1024.0,
                1e3 * self.seconds
            )
        })
    }
}

impl RunControl for Control<'_> {
    fn after_frame(&mut self, _stats: &FrameStats) -> Action {
        if let Some(sig) = crate::signals::requested() {
            self.stopped_by = Some(sig);
            return Action::Stop;
        }
        match self.saving.every {
            Some(d) if self.last.elapsed() >= d => Action::Checkpoint,
            _ => Action::Continue,
        }
    }

    fn checkpoint(&mut self, state: &RunState) -> Result<(), cloth::CallbackError> {
        if !state.resumable() {
            self.unsaved = true;
            return Ok(());
        }
        let t = Instant::now();
        let wall = self.wall_before + self.started.elapsed().as_secs_f64();
        let payload = encode(self.saving, wall, &self.col.borrow(), state);
        cloth::checkpoint::write(&self.path, Kind::Cloth, &payload)?;
        self.seconds = t.elapsed().as_secs_f64();
        self.bytes = payload.len();
        self.written += 1;
        self.saved_frame = Some(state.frame);
        self.last = Instant::now();
        Ok(())
    }
}

/// A run a signal stopped after `frame`: energy.csv and the plot of the
/// frames so far, what ran, and how to continue; exit 128 + the signal.
pub fn stopped(
    plan: &Plan<'_>,
    col: &Collected,
    control_saved: Option<usize>,
    path: &Path,
    frame: usize,
    time: f64,
    wall: f64,
) -> Result<ExitCode> {
    let sig = crate::signals::requested().unwrap_or(15);
    let dir = plan.dir;
    let mut written = energy_files(plan, &col.stats)?;
    if col.objs > 0 {
        written.push(format!("{} OBJ in frames/", col.objs));
    }
    let total = plan.settings.options.frames;
    println!(
        "cloth: {} — {} stopped by {} after frame {frame} of {total} (t = {time:.4} s), {wall:.1} s of wall time",
        plan.scene.name,
        plan.method.id(),
        crate::signals::name(sig)
    );
    println!(
        "  written      {}: {} (up to frame {frame})",
        dir.display(),
        written.join(", ")
    );
    if control_saved == Some(frame) {
        println!(
            "  checkpoint   {} — continue with: symlab resume {}",
            path.display(),
            dir.display()
        );
    } else {
        println!("  checkpoint   none: this run cannot be resumed");
    }
    Ok(ExitCode::from(crate::signals::exit_status(sig)))
}
