//! The checkpoint of a paper run: the request (without its folder: a run
//! resumes where its checkpoint is found) and the figure-5 cloth runs
//! finished so far, every double's bits exactly. The oscillator part takes
//! a second and is computed again on resumption (the same bits: it is
//! deterministic); the cloth runs, the long part, are not.

use std::path::Path;

use cloth::checkpoint::{CheckpointError, Decoder, Encoder, Kind, read_any};
use cloth::study::figure5::{ClothRun, decode_run, encode_run};
use compare::paper_oscillator::Config;

use super::request::Request;

/// Write the checkpoint of `request` after `runs` (atomically: a torn
/// write leaves the previous checkpoint).
pub(super) fn write(
    path: &Path,
    request: &Request,
    runs: &[ClothRun],
) -> Result<(), CheckpointError> {
    let mut e = Encoder::new();
    let c = &request.oscillator;
    e.f64(c.k)
        .f64(c.q0)
        .f64(c.p0)
        .usize(c.steps)
        .f64s(&c.step_sizes)
        .usize(request.cloth_frames)
        .usize(runs.len());
    for r in runs {
        encode_run(&mut e, r);
    }
    cloth::checkpoint::write(path, Kind::Paper, &e.finish())
}

/// The request (its `out` left at the default: the caller sets the folder)
/// and the runs of a paper checkpoint's payload.
pub(super) fn decode(
    path: &Path,
    payload: &[u8],
) -> Result<(Request, Vec<ClothRun>), CheckpointError> {
    let mut d = Decoder::new(path, payload);
    let oscillator = Config {
        k: d.f64("k")?,
        q0: d.f64("q0")?,
        p0: d.f64("p0")?,
        steps: d.usize("steps")?,
        step_sizes: d.f64s("step_sizes")?,
    };
    let cloth_frames = d.usize("cloth_frames")?;
    let n = d.usize("runs")?;
    let mut runs = Vec::new();
    for _ in 0..n {
        runs.push(decode_run(&mut d)?);
    }
    d.end()?;
    let request = Request {
        oscillator,
        cloth_frames,
        ..Request::default()
    };
    Ok((request, runs))
}

/// How many cloth runs the checkpoint at `path` keeps.
pub(super) fn runs_in(path: &Path) -> Result<usize, CheckpointError> {
    let (kind, payload) = read_any(path)?;
    if kind != Kind::Paper {
        return Err(Decoder::new(path, &payload).error("not a paper run's checkpoint"));
    }
    Ok(decode(path, &payload)?.1.len())
}
