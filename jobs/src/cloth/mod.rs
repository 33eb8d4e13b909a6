//! A cloth scene run into files: `energy.csv`, the energy plot, OBJ frames,
//! PNG renderings and a one-screen summary, with the energy guard, the
//! blow-up replay and checkpoints — the one pipeline behind `symlab cloth`
//! and `symlab.cloth.run`.
//!
//! The phases are named, as in the cloth crate:
//! 1. [`Request`]: what the user asked, as they wrote it (a scene file or
//!    text, the method id, frames, substeps or a step size, the output
//!    folder, …). Every field is optional where the scene has a default.
//! 2. [`plan`]: the request checked and resolved against the scene (the
//!    method applies, the schedule fits the run limits, the output folder
//!    can be written), the model built. An error is an [`InputError`]
//!    whose [`Origin`] names the request's field — shown by the command
//!    line as its flag (`--dt 1e-3: …`) and by Python as its keyword — or
//!    the scene file's field (`scene.toml: simulation.method: …`).
//! 3. [`Job::run`]: the run, progress and stop requests through an
//!    [`Observer`]; it returns an [`Outcome`] (finished with its summary,
//!    blown up with what was kept, or stopped with its checkpoint). The
//!    library prints nothing: the front ends print the outcome's text.
//!
//! A run stopped by its observer (a signal, in the command line) writes a
//! checkpoint from which [`resume`] continues it to the same bits and the
//! same files as a run never stopped; the checkpoint holds the request and
//! the scene's text, so the run goes on even if the scene file changed.
//!
//! ```
//! use jobs::cloth::{Request, SceneSource, Outcome, Quiet, plan};
//!
//! let scene = "[cloth]\nwidth = 1.0\nheight = 1.0\nnx = 4\nny = 4\n\
//!              [material]\ndensity = 0.1\nstretch = 10.0\n\
//!              [pins]\nedges = [\"top\"]\n\
//!              [simulation]\nsubsteps = 20\nframes = 3\nmethod = \"stormer-verlet\"\n";
//! let out = std::env::temp_dir().join(format!("jobs-cloth-doc-{}", std::process::id()));
//! let request = Request {
//!     out: Some(out.clone()),
//!     render: Some("none".into()),
//!     ..Request::new(SceneSource::Text { name: "sheet.toml".into(), text: scene.into() })
//! };
//! let outcome = plan(&request)?.run(&mut Quiet)?;
//! let Outcome::Finished { summary, .. } = outcome else { panic!("not finished") };
//! assert!(summary.contains("stormer-verlet"));
//! assert!(out.join("energy.csv").exists());
//!
//! // A wrong field is named, for each front end in its own words.
//! let bad = Request { frames: Some(2_000_000), ..request };
//! let Err(err) = plan(&bad) else { panic!("two million frames were accepted") };
//! assert!(err.to_string().starts_with("--frames"), "{err}");
//! assert!(err.keyword_message().starts_with("frames"), "{err}");
//! # std::fs::remove_dir_all(&out).ok();
//! # Ok::<(), jobs::cloth::JobError>(())
//! ```

// Imports go one way, each module from those above it: request →
// observer → checkpoint → plan → summary, energy, render → run; stability
// and equal_stretch (other jobs on the same plan) last.
mod checkpoint;
mod energy;
pub mod equal_stretch;
mod observer;
mod plan;
mod render;
mod request;
mod run;
pub mod stability;
mod summary;

pub use checkpoint::interval;
pub use integrator_core::checkpoint::Every;
pub use observer::{Observer, Outcome, Quiet, Stop};
pub use plan::{Job, plan, resume};
pub use request::{Field, InputError, JobError, Origin, Request, SceneSource};
pub use summary::facts;
