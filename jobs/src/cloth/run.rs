//! Phase 3: a [`Job`] run into its folder — OBJ frames as they come, the
//! frames to render kept, checkpoints — and then the output of a finished
//! run and its summary, of a run that blew up (what was good, and how the
//! energy grew), or of a run its observer stopped.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use cloth::{FrameStats, RunError, Vec3};

use super::checkpoint::{Collected, Control};
use super::observer::{Observer, Outcome, Stop};
use super::plan::Job;
use super::request::JobError;
use super::summary::{Summary, energy_growth};
use super::{energy, render};

impl Job {
    /// Run the job to its outcome, telling `observer` of each frame and
    /// asking it after each whether to stop. Errors are those of the output
    /// (a file that cannot be written) or of a run that failed other than
    /// by blowing up; a blow-up is an [`Outcome::BlownUp`].
    pub fn run(mut self, observer: &mut dyn Observer) -> Result<Outcome, JobError> {
        let clock = Instant::now();
        let triangles = self.sim.model.triangles();
        let ckpt_path = self.dir.join(cloth::checkpoint::FILE_NAME);
        let resumed = self.resumed.take();
        if resumed.is_none() {
            clear_stale(&self.dir)?;
            // A new run in this folder supersedes an older run's checkpoint.
            integrator_core::checkpoint::remove(&ckpt_path)?;
        }
        let frames_dir = self.dir.join("frames");
        let every = self.request.obj_every;
        if every > 0 {
            std::fs::create_dir_all(&frames_dir)
                .map_err(|e| JobError::io(&frames_dir, "cannot create the directory", e))?;
        }
        let opts = self.settings.options;
        let (col, state, wall_before) = match resumed {
            Some(r) => {
                let col = Collected {
                    stats: r.state.frames.clone(),
                    objs: r.objs,
                    kept: r.kept,
                };
                (col, Some(r.state), r.wall)
            }
            None => {
                let col = Collected {
                    stats: Vec::with_capacity(opts.frames.min(1 << 16) + 1),
                    objs: 0,
                    kept: BTreeMap::new(),
                };
                (col, None, 0.0)
            }
        };
        observer.start(opts.frames, state.as_ref().map_or(0, |s| s.frame));
        let col = RefCell::new(col);
        let observer = RefCell::new(observer);
        let (result, note, saved_frame, stopped_by) = {
            let mut control = Control::new(
                &self.request,
                &self.scene_text,
                self.every,
                &observer,
                &ckpt_path,
                &col,
                wall_before,
            );
            let result = self.sim.run_controlled(
                &self.method,
                &self.settings,
                state.as_ref(),
                &mut control,
                |frame| {
                    let mut col = col.borrow_mut();
                    let k = frame.stats.frame;
                    col.stats.push(frame.stats);
                    if every > 0 && (k % every == 0 || k == opts.frames) {
                        let path = frames_dir.join(format!("frame_{k:04}.obj"));
                        cloth::write_obj(&path, &frame.positions(), &triangles)?;
                        col.objs += 1;
                    }
                    if self.renders.binary_search(&k).is_ok() {
                        col.kept.insert(k, (frame.stats.time, frame.positions()));
                    }
                    observer.borrow_mut().frame(frame);
                    Ok(())
                },
            );
            (
                result,
                control.note(),
                control.saved_frame,
                control.stopped_by.take(),
            )
        };
        observer.into_inner().finish();
        let wall = wall_before + clock.elapsed().as_secs_f64();
        let mut col = col.into_inner();
        let mut notes: Vec<String> = note.into_iter().collect();
        // The model checks that the initial state is finite, so frame 0
        // always reaches the callback; should it not, that is an error
        // about the scene, not a panic.
        let Some(&good) = col.stats.last() else {
            let why = match &result {
                Err(e) => e.to_string(),
                Ok(_) => "no frame was recorded".to_string(),
            };
            return Err(JobError::Scene(format!(
                "{}: the initial state cannot be simulated: {why}",
                self.scene.name
            )));
        };
        match result {
            Ok(report) => {
                let e_ref = self.e_ref();
                let mut written = vec!["energy.csv".to_string(), "energy.svg".to_string()];
                cloth::write_energy_csv(self.dir.join("energy.csv"), &report.frames, e_ref)?;
                energy::plot(
                    &self.dir.join("energy.svg"),
                    &report.frames,
                    e_ref,
                    &self.title(report.method),
                )?;
                let (names, render_note) = self.render_kept(&triangles, &col.kept)?;
                written.extend(names);
                notes.extend(render_note);
                let summary = Summary {
                    scene: &self.scene,
                    model: &self.sim.model,
                    method: &self.method,
                    report: &report,
                    opts: &self.settings.options,
                    wall,
                    e_ref,
                    note: self.note.as_deref(),
                    dir: &self.dir,
                    objs: col.objs,
                    written: &written,
                }
                .render();
                // The run is complete: nothing is left to resume.
                integrator_core::checkpoint::remove(&ckpt_path)?;
                Ok(Outcome::Finished {
                    summary,
                    report,
                    notes,
                })
            }
            Err(RunError::Stopped { frame, time }) => {
                let stop = stopped_by.unwrap_or_else(|| Stop {
                    reason: "the observer".into(),
                });
                let mut written = self.energy_files(&col.stats)?;
                if col.objs > 0 {
                    written.push(format!("{} OBJ in frames/", col.objs));
                }
                let checkpoint = (saved_frame == Some(frame)).then(|| ckpt_path.clone());
                let text = stopped_text(
                    &self,
                    &stop,
                    &written,
                    checkpoint.as_deref(),
                    frame,
                    time,
                    wall,
                );
                Ok(Outcome::Stopped {
                    text,
                    stop,
                    checkpoint,
                    notes,
                })
            }
            Err(err) if err.is_blowup() => {
                let (lines, render_note) =
                    self.blown_up(good, &triangles, &frames_dir, &mut col)?;
                notes.extend(render_note);
                Ok(Outcome::BlownUp {
                    error: err.to_string(),
                    lines,
                    notes,
                })
            }
            Err(err) => Err(JobError::Run(err.to_string())),
        }
    }

    /// `E_ref` of the energy guard.
    fn e_ref(&self) -> f64 {
        self.settings.guard.map_or(1.0, |g| g.e_ref)
    }

    /// The energy plot's title.
    fn title(&self, name: &str) -> String {
        format!(
            "{} — {name}, h = {:.3e} s",
            self.scene.name,
            self.settings.options.step_size()
        )
    }

    /// What a run that stopped early keeps of its energy: `energy.csv`,
    /// and with two frames or more the plot; the names written.
    fn energy_files(&self, stats: &[FrameStats]) -> Result<Vec<String>, JobError> {
        let e_ref = self.e_ref();
        cloth::write_energy_csv(self.dir.join("energy.csv"), stats, e_ref)?;
        let mut written = vec!["energy.csv".to_string()];
        if stats.len() >= 2 {
            energy::plot(
                &self.dir.join("energy.svg"),
                stats,
                e_ref,
                &self.title(self.method.name()),
            )?;
            written.push("energy.svg".into());
        }
        Ok(written)
    }

    /// A run that blew up (a non-finite state, a failed solve, or the
    /// energy guard; the simulation is at the last good frame): keep what
    /// was good — energy.csv, the plot, the last good frame as OBJ and PNG
    /// — and say how the energy grew before. The lines to print after the
    /// error, and a note on the renderings.
    fn blown_up(
        &self,
        good: FrameStats,
        triangles: &[[usize; 3]],
        frames_dir: &Path,
        col: &mut Collected,
    ) -> Result<(Vec<String>, Option<String>), JobError> {
        let e_ref = self.e_ref();
        let sim = &self.sim;
        let mut written = self.energy_files(&col.stats)?;
        let positions = sim.model.positions(&sim.state[..sim.state.len() / 2]);
        if self.request.obj_every > 0 {
            let path = frames_dir.join(format!("frame_{:04}.obj", good.frame));
            if !path.exists() {
                cloth::write_obj(&path, &positions, triangles)?;
                col.objs += 1;
            }
        }
        if self.render_failure {
            col.kept.insert(good.frame, (good.time, positions));
        }
        let (names, render_note) = self.render_kept(triangles, &col.kept)?;
        written.extend(names);
        if col.objs > 0 {
            written.push(format!("{} OBJ in frames/", col.objs));
        }
        let growth = energy_growth(&col.stats, e_ref);
        let mut lines = vec![format!("  energy up to the last good frame: {growth}")];
        if growth.exponential() {
            lines.push(
                "  the energy was growing exponentially before the run stopped (see energy.svg): the method is unstable at this step, whatever the solver".into(),
            );
        }
        lines.push(format!(
            "  output up to the last good frame, {} (t = {:.4} s), was written to {}: {}; nothing after it",
            good.frame,
            good.time,
            self.dir.display(),
            written.join(", ")
        ));
        Ok((lines, render_note))
    }

    /// Render the kept frames with one camera fitted to all of them; the
    /// names written, and a note when a picture had to be simplified (see
    /// [`cloth::render::Picture::simplified`]).
    fn render_kept(
        &self,
        triangles: &[[usize; 3]],
        kept: &BTreeMap<usize, (f64, Vec<Vec3>)>,
    ) -> Result<(Vec<String>, Option<String>), JobError> {
        if kept.is_empty() {
            return Ok((Vec::new(), None));
        }
        let scene = &self.scene;
        let all: Vec<Vec3> = kept.values().flat_map(|(_, p)| p.iter().copied()).collect();
        let stage =
            cloth::render::Stage::for_grid(scene.colliders.clone(), triangles, scene.cloth.nx);
        let camera = cloth::render::Camera::fit(&all, &scene.colliders);
        drop(all);
        let mut names = Vec::new();
        let mut notes = Vec::new();
        for (k, (t, positions)) in kept {
            let name = format!("render_{k:04}.png");
            let caption = format!(
                "{} · {} · frame {k} · t = {t:.3} s",
                scene.name,
                self.method.id()
            );
            if let Some(n) =
                render::png_noted(&self.dir.join(&name), &stage, &camera, positions, &caption)?
            {
                notes.push(format!("{name}: {n}"));
            }
            names.push(name);
        }
        Ok((names, (!notes.is_empty()).then(|| notes.join("; "))))
    }
}

/// Remove what an earlier run left that this one may not overwrite:
/// `frames/frame_*.obj` and `render_*.png`.
fn clear_stale(dir: &Path) -> Result<(), JobError> {
    let remove = |d: &Path, prefix: &str, ext: &str| -> Result<(), JobError> {
        let Ok(entries) = std::fs::read_dir(d) else {
            return Ok(());
        };
        for entry in entries.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if name.starts_with(prefix) && name.ends_with(ext) && entry.path().is_file() {
                std::fs::remove_file(entry.path())
                    .map_err(|e| JobError::io(entry.path(), "cannot remove the old file", e))?;
            }
        }
        Ok(())
    };
    remove(&dir.join("frames"), "frame_", ".obj")?;
    remove(dir, "render_", ".png")
}

/// The text of a run stopped after `frame`: what ran, what was written,
/// and how to continue.
#[allow(clippy::too_many_arguments)] // one line each, all of them printed
fn stopped_text(
    job: &Job,
    stop: &Stop,
    written: &[String],
    checkpoint: Option<&Path>,
    frame: usize,
    time: f64,
    wall: f64,
) -> String {
    let dir = &job.dir;
    let total = job.settings.options.frames;
    let mut s = format!(
        "cloth: {} — {} stopped by {} after frame {frame} of {total} (t = {time:.4} s), {wall:.1} s of wall time\n",
        job.scene.name,
        job.method.id(),
        stop.reason
    );
    s += &format!(
        "  written      {}: {} (up to frame {frame})\n",
        dir.display(),
        written.join(", ")
    );
    match checkpoint {
        Some(path) => {
            s += &format!(
                "  checkpoint   {} — continue with: symlab resume {}\n",
                path.display(),
                dir.display()
            )
        }
        None => s += "  checkpoint   none: this run cannot be resumed\n",
    }
    s
}
