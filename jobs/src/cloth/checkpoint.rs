//! Checkpoints of cloth jobs and their resumption: when to write one (the
//! request's interval, or the observer's stop), what goes in it beside the
//! cloth crate's [`RunState`] (the request, the scene's text, the frames
//! kept for rendering, the OBJ count, the wall time so far), and the text
//! of a run that was stopped.
//!
//! The request and the scene's text are saved, not the file's name alone,
//! so that [`resume`] plans exactly the run that was stopped even when the
//! scene file has changed or moved since — whichever front end started it.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use cloth::checkpoint::{
    Action, CheckpointError, Decoder, Encoder, Kind, RunControl, RunState, resumable,
};
use cloth::{FrameStats, Method, Vec3};
use integrator_core::checkpoint::{DEFAULT_EVERY, Every};

use super::observer::{Observer, Stop};
use super::request::{Field, InputError, Request, SceneSource};

/// What a run collects as it goes, beside the simulation's state, and a
/// checkpoint keeps: the statistics of every frame, the OBJ count, and
/// the positions of the frames still to render.
pub(crate) struct Collected {
    pub stats: Vec<FrameStats>,
    pub objs: usize,
    /// Positions of the frames to render, with their time.
    pub kept: BTreeMap<usize, (f64, Vec<Vec3>)>,
}

/// The interval of a run of `method`: the request's, or the default where
/// the method's runs can be resumed. Checkpoints asked of a method that
/// cannot save its stepper are refused rather than ignored.
pub fn interval(asked: Option<Every>, method: &Method) -> Result<Option<Duration>, InputError> {
    match asked {
        Some(Every::Off) => Ok(None),
        Some(Every::After(d)) if resumable(method) => Ok(Some(d)),
        Some(Every::After(_)) => Err(InputError::field(
            Field::CheckpointEvery,
            format!(
                "{} runs cannot be checkpointed yet (RATTLE runs of inextensible scenes can); set it to off",
                method.id()
            ),
        )),
        None => Ok(resumable(method).then_some(DEFAULT_EVERY)),
    }
}

/// A run read back from a checkpoint.
pub(crate) struct Resumed {
    /// Wall time of the run before it stopped (s).
    pub wall: f64,
    pub objs: usize,
    pub kept: BTreeMap<usize, (f64, Vec<Vec3>)>,
    pub state: RunState,
}

fn opt_str(e: &mut Encoder, s: Option<&str>) {
    e.bool(s.is_some());
    if let Some(s) = s {
        e.str(s);
    }
}

fn opt_usize(e: &mut Encoder, n: Option<usize>) {
    e.bool(n.is_some());
    if let Some(n) = n {
        e.usize(n);
    }
}

fn opt_f64(e: &mut Encoder, x: Option<f64>) {
    e.bool(x.is_some());
    if let Some(x) = x {
        e.f64(x);
    }
}

/// The request's fields; the scene as its name (the text follows).
fn encode_request(e: &mut Encoder, r: &Request) {
    e.str(&r.scene.file_name());
    opt_str(e, r.method.as_deref());
    opt_usize(e, r.frames);
    opt_usize(e, r.substeps);
    opt_f64(e, r.dt);
    opt_str(e, r.grid.as_deref());
    opt_str(e, r.out.as_ref().and_then(|p| p.to_str()));
    e.usize(r.obj_every);
    opt_str(e, r.render.as_deref());
    opt_f64(e, r.tolerance);
    opt_str(e, r.solver.as_deref());
    match r.checkpoint_every {
        None => e.usize(0),
        Some(Every::Off) => e.usize(1),
        Some(Every::After(d)) => e.usize(2).f64(d.as_secs_f64()),
    };
}

fn decode_request(d: &mut Decoder<'_>) -> Result<(String, Request), CheckpointError> {
    fn opt<'a, T>(
        d: &mut Decoder<'a>,
        field: &str,
        read: impl FnOnce(&mut Decoder<'a>, &str) -> Result<T, CheckpointError>,
    ) -> Result<Option<T>, CheckpointError> {
        if d.bool(field)? {
            read(d, field).map(Some)
        } else {
            Ok(None)
        }
    }
    let string = |d: &mut Decoder<'_>, f: &str| d.str(f).map(str::to_string);
    let name = d.str("scene file")?.to_string();
    let mut r = Request::new(SceneSource::Text {
        name: name.clone(),
        text: String::new(),
    });
    r.method = opt(d, "method", string)?;
    r.frames = opt(d, "frames", |d, f| d.usize(f))?;
    r.substeps = opt(d, "substeps", |d, f| d.usize(f))?;
    r.dt = opt(d, "dt", |d, f| d.f64(f))?;
    r.grid = opt(d, "grid", string)?;
    r.out = opt(d, "out", string)?.map(PathBuf::from);
    r.obj_every = d.usize("obj every")?;
    r.render = opt(d, "render", string)?;
    r.tolerance = opt(d, "tolerance", |d, f| d.f64(f))?;
    r.solver = opt(d, "solver", string)?;
    r.checkpoint_every = match d.usize("checkpoint every")? {
        0 => None,
        1 => Some(Every::Off),
        2 => {
            let s = d.f64("checkpoint interval")?;
            Some(Every::After(Duration::try_from_secs_f64(s).map_err(
                |_| d.error(format!("checkpoint interval: {s} s")),
            )?))
        }
        k => return Err(d.error(format!("checkpoint every: tag {k}"))),
    };
    Ok((name, r))
}

fn encode(
    request: &Request,
    scene_text: &str,
    wall: f64,
    col: &Collected,
    state: &RunState,
) -> Vec<u8> {
    let mut e = Encoder::new();
    encode_request(&mut e, request);
    e.str(scene_text)
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

pub(crate) fn decode(
    path: &Path,
    payload: &[u8],
) -> Result<(Request, String, Resumed), CheckpointError> {
    let mut d = Decoder::new(path, payload);
    let (_, request) = decode_request(&mut d)?;
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
    Ok((
        request,
        scene_text,
        Resumed {
            wall,
            objs,
            kept,
            state,
        },
    ))
}

/// The [`RunControl`] of a cloth job: the observer's stop, and the
/// checkpoints.
pub(crate) struct Control<'a, 'o> {
    request: &'a Request,
    scene_text: &'a str,
    every: Option<Duration>,
    observer: &'a RefCell<&'o mut dyn Observer>,
    path: PathBuf,
    col: &'a RefCell<Collected>,
    wall_before: f64,
    started: Instant,
    last: Instant,
    /// Why the run was stopped.
    pub stopped_by: Option<Stop>,
    /// Whether a stop found a stepper that cannot be saved.
    unsaved: bool,
    /// The frame of the last checkpoint written, its size and write time.
    pub saved_frame: Option<usize>,
    written: usize,
    bytes: usize,
    seconds: f64,
}

impl<'a, 'o> Control<'a, 'o> {
    pub fn new(
        request: &'a Request,
        scene_text: &'a str,
        every: Option<Duration>,
        observer: &'a RefCell<&'o mut dyn Observer>,
        path: &Path,
        col: &'a RefCell<Collected>,
        wall_before: f64,
    ) -> Control<'a, 'o> {
        let now = Instant::now();
        Control {
            request,
            scene_text,
            every,
            observer,
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

    /// A line about the checkpoints of a stopped run.
    pub fn note(&self) -> Option<String> {
        self.stopped_by.as_ref()?;
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

impl RunControl for Control<'_, '_> {
    fn after_frame(&mut self, _stats: &FrameStats) -> Action {
        if let Some(stop) = self.observer.borrow_mut().stop_requested() {
            self.stopped_by = Some(stop);
            return Action::Stop;
        }
        match self.every {
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
        let payload = encode(
            self.request,
            self.scene_text,
            wall,
            &self.col.borrow(),
            state,
        );
        cloth::checkpoint::write(&self.path, Kind::Cloth, &payload)?;
        self.seconds = t.elapsed().as_secs_f64();
        self.bytes = payload.len();
        self.written += 1;
        self.saved_frame = Some(state.frame);
        self.last = Instant::now();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn roundtrip(r: &Request) -> Request {
        let mut e = Encoder::new();
        encode_request(&mut e, r);
        let bytes = e.finish();
        let path = Path::new("test.symlab");
        let mut d = Decoder::new(path, &bytes);
        let (name, back) = decode_request(&mut d).unwrap();
        d.end().unwrap();
        assert_eq!(name, r.scene.file_name());
        back
    }

    /// Every field of the request survives the checkpoint, set or not:
    /// `symlab resume` plans the run that was asked.
    #[test]
    fn the_request_survives_the_checkpoint() {
        let full = Request {
            method: Some("rattle".into()),
            frames: Some(240),
            substeps: Some(6),
            dt: Some(2.5e-3),
            grid: Some("10x10".into()),
            out: Some(PathBuf::from("out/x")),
            obj_every: 40,
            render: Some("0,1,120".into()),
            tolerance: Some(1e-10),
            solver: Some("local-global".into()),
            checkpoint_every: Some(Every::After(Duration::from_millis(1500))),
            ..Request::new(SceneSource::File(PathBuf::from("scenes/a b.toml")))
        };
        let back = roundtrip(&full);
        assert_eq!(back.method, full.method);
        assert_eq!(back.frames, full.frames);
        assert_eq!(back.substeps, full.substeps);
        assert_eq!(back.dt.map(f64::to_bits), full.dt.map(f64::to_bits));
        assert_eq!(back.grid, full.grid);
        assert_eq!(back.out, full.out);
        assert_eq!(back.obj_every, full.obj_every);
        assert_eq!(back.render, full.render);
        assert_eq!(back.tolerance, full.tolerance);
        assert_eq!(back.solver, full.solver);
        assert_eq!(back.checkpoint_every, full.checkpoint_every);

        let bare = Request::new(SceneSource::Text {
            name: "<scene>".into(),
            text: "x".into(),
        });
        let back = roundtrip(&bare);
        assert!(back.method.is_none() && back.frames.is_none() && back.dt.is_none());
        assert!(back.out.is_none() && back.render.is_none() && back.checkpoint_every.is_none());
        let off = Request {
            checkpoint_every: Some(Every::Off),
            ..bare
        };
        assert_eq!(roundtrip(&off).checkpoint_every, Some(Every::Off));
    }
}
