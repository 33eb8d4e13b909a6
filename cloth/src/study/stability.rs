//! The largest stable step of a method on a scene, found by bisection on
//! `h`, to set beside the linear estimate `2/ω_max`.
//!
//! A trial runs the scene for a fixed simulated time at one step size, with
//! frames at about 60 Hz (whole steps per frame); it is **stable** when it
//! finishes — no NaN or infinity, every solve converged — and the relative
//! energy error `|H − H₀|/E_ref` stays within the tolerance at every frame
//! (the energy guard cuts a trial short as soon as it does not). The
//! search ([`integrator_core::search::largest_passing`], the one `compare
//! --hard` uses) starts at `2/ω_max`, doubles or halves until it brackets
//! the threshold, then bisects in `log h` until the bracket is within the
//! resolution (1 %); it gives up below a floor (too many steps for a trial)
//! or above a cap (a few steps over the whole run). Stability need not be
//! monotone in `h` (resonances): this finds a threshold, the largest one
//! only if there is one. Every number is returned as data ([`Found`],
//! [`Outcome`]); `symlab cloth --stability` formats them.
//!
//! ```
//! use cloth::{Method, Scene};
//! use cloth::study::stability::{StabilitySettings, Status, largest_stable_step};
//!
//! // A small sheet hanging from its top edge: 4 × 4 particles, stiff springs.
//! let scene = Scene::from_toml(r#"
//!     gravity = [0.0, -9.81, 0.0]
//!     [cloth]
//!     width = 1.0
//!     height = 1.0
//!     nx = 4
//!     ny = 4
//!     [material]
//!     density = 0.1
//!     stretch = 1000.0
//!     [pins]
//!     edges = ["top"]
//!     [simulation]
//!     substeps = 10
//!     frames = 3
//!     method = "stormer-verlet"
//! "#, "inline.toml")?;
//! let settings = StabilitySettings { duration: 0.2, ..StabilitySettings::default() };
//! let found = largest_stable_step(&scene, &Method::parse("stormer-verlet")?, &settings)?;
//! assert_eq!(found.status, Status::Bracketed);
//! let h = found.h.expect("a stable step");
//! // Within 1 % of the threshold, near the linear limit 2/ω_max ≈ 1.6 ms.
//! assert!(h / found.h_linear > 0.5 && h / found.h_linear < 2.0);
//! assert!(found.max_error <= settings.tolerance);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use integrator_core::search::{Geometric, largest_passing};

use crate::method::Method;
use crate::run::{EnergyGuard, RunError, RunOptions, RunSettings, Simulation};
use crate::scene::{Scene, SceneError};
use crate::step::MinimiseSettings;
use crate::study::energy::{ReferenceEnergyError, reference_energy, worst_relative_error};

/// What a search does, with the defaults `symlab cloth --stability` uses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StabilitySettings {
    /// Simulated seconds per trial (default 1).
    pub duration: f64,
    /// The largest `|H − H₀|/E_ref` a stable trial may show (default 0.1).
    pub tolerance: f64,
    /// Bisect until `h_unstable/h_stable` is at most this (default 1.01).
    pub resolution: f64,
    /// The search stops expanding at `duration / min_steps` (default 8):
    /// a trial of fewer steps says little about the method.
    pub min_steps: f64,
    /// The most steps of an explicit method's trial (default 400 000): the
    /// floor of its search is `duration / max_steps_explicit`.
    pub max_steps_explicit: f64,
    /// The most steps of an implicit method's trial (default 20 000), each
    /// a solve.
    pub max_steps_implicit: f64,
    /// The minimisation solver of the midpoint family, `avf` and
    /// `discrete-gradient`.
    pub minimise: MinimiseSettings,
}

impl Default for StabilitySettings {
    fn default() -> Self {
        StabilitySettings {
            duration: 1.0,
            tolerance: 0.1,
            resolution: 1.01,
            min_steps: 8.0,
            max_steps_explicit: 400_000.0,
            max_steps_implicit: 20_000.0,
            minimise: MinimiseSettings::default(),
        }
    }
}

impl StabilitySettings {
    /// The smallest tolerance: a relative energy error below 1e-12 is
    /// round-off, which no step size can beat; the search would only halve
    /// down to its floor.
    pub const MIN_TOLERANCE: f64 = 1e-12;
    /// Shortest and longest trial (s). Below, the trial's step floor
    /// `duration/max_steps_explicit` approaches the smallest normal numbers
    /// and the search means nothing; above, a trial would be all frames.
    pub const DURATION_RANGE: (f64, f64) = (1e-6, 1e6);

    /// Each field finite and in its range, or an error naming it: a zero
    /// resolution or an infinite duration would never end.
    pub fn check(&self) -> Result<(), StabilityError> {
        let bad =
            |field: &'static str, message: String| Err(StabilityError::Setting { field, message });
        let (lo, hi) = Self::DURATION_RANGE;
        if !(self.duration >= lo && self.duration <= hi) {
            return bad(
                "duration",
                format!(
                    "must be between {lo:e} s and {hi:e} s (got {:e})",
                    self.duration
                ),
            );
        }
        if !(self.tolerance >= Self::MIN_TOLERANCE && self.tolerance.is_finite()) {
            return bad(
                "tolerance",
                format!(
                    "must be at least {:e} and finite (got {:e}): below that, round-off alone exceeds it",
                    Self::MIN_TOLERANCE,
                    self.tolerance
                ),
            );
        }
        let blowup = EnergyGuard::DEFAULT_LIMIT;
        if self.tolerance > blowup {
            return bad(
                "tolerance",
                format!(
                    "must be at most {blowup} (got {:e}): a run whose relative energy error passes {blowup} has blown up whatever the tolerance",
                    self.tolerance
                ),
            );
        }
        if !(self.resolution.is_finite() && self.resolution > 1.0) {
            return bad(
                "resolution",
                format!("must be finite and above 1, got {}", self.resolution),
            );
        }
        if !(self.min_steps.is_finite() && self.min_steps >= 1.0) {
            return bad(
                "min_steps",
                format!("must be at least 1, got {}", self.min_steps),
            );
        }
        for (field, max) in [
            ("max_steps_explicit", self.max_steps_explicit),
            ("max_steps_implicit", self.max_steps_implicit),
        ] {
            if !(max.is_finite() && max >= self.min_steps) {
                return bad(
                    field,
                    format!(
                        "must be finite and at least min_steps = {}, got {max}",
                        self.min_steps
                    ),
                );
            }
        }
        Ok(())
    }

    /// The smallest step tried for `method`: `duration / max_steps`.
    pub fn floor(&self, method: &Method) -> f64 {
        let max = if method.explicit() {
            self.max_steps_explicit
        } else {
            self.max_steps_implicit
        };
        self.duration / max
    }

    /// The largest step tried: `duration / min_steps`.
    pub fn cap(&self) -> f64 {
        self.duration / self.min_steps
    }
}

/// Why a search could not start.
#[derive(Debug, thiserror::Error)]
pub enum StabilityError {
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The scene has no energy scale to measure the tolerance against.
    #[error(transparent)]
    Energy(#[from] ReferenceEnergyError),
    #[error("{field}: {message}")]
    Setting {
        field: &'static str,
        message: String,
    },
}

/// The scales of a scene that every method's search shares: computed once
/// by [`Scales::of`], passed to [`search`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scales {
    /// The energy that errors are relative to
    /// ([`reference_energy`]).
    pub e_ref: f64,
    /// The linear estimate `2/ω_max` at the initial state, where the search
    /// starts; infinite when `M⁻¹K` has no positive eigenvalue (the search
    /// then starts at its cap).
    pub h_linear: f64,
}

impl Scales {
    pub fn of(scene: &Scene) -> Result<Scales, StabilityError> {
        let sim = Simulation::new(scene)?;
        Ok(Scales {
            e_ref: reference_energy(scene, &sim)?,
            h_linear: sim.model.stability().h_max,
        })
    }
}

/// How one trial ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// It finished within the tolerance; its largest `|H − H₀|/E_ref`.
    Stable { max_error: f64 },
    /// The energy error passed the tolerance (or stopped being a number)
    /// at `time` (s).
    Energy { error: f64, time: f64 },
    /// A non-finite state at `step`.
    Blowup { step: usize, time: f64 },
    /// A solve (stage equations or minimisation) failed at `step`.
    Newton { step: usize, time: f64 },
    /// Anything else (the message): the scene or the options were refused.
    Other(String),
}

impl Outcome {
    pub fn stable(&self) -> bool {
        matches!(self, Outcome::Stable { .. })
    }
}

/// One trial: how it ended and the seconds spent stepping (0 unless
/// stable).
#[derive(Clone, Debug, PartialEq)]
pub struct Trial {
    pub outcome: Outcome,
    pub stepping_seconds: f64,
}

/// Run options with step exactly `h`, about 60 frames per simulated second
/// (a frame no longer than the duration), covering at least `duration`.
/// The steps of a frame are bounded by the steps of the whole trial (and by
/// `max_steps`), so a tiny duration cannot ask for 1/(60·h) steps (a hang
/// at a duration of 1e-300).
pub fn run_options(h: f64, duration: f64, max_steps: f64) -> RunOptions {
    let per_frame = (1.0 / 60.0 / h).round().min((duration / h).ceil());
    let substeps = (per_frame.min(max_steps) as usize).max(1);
    let frame = substeps as f64 * h;
    RunOptions {
        frames: ((duration / frame).ceil() as usize).max(1),
        substeps,
        frame_rate: 1.0 / frame,
    }
}

/// The run options of a trial at `h` ([`run_options`] with the settings'
/// duration; the steps per frame bounded by the larger of the two step
/// limits).
pub fn trial_options(h: f64, settings: &StabilitySettings) -> RunOptions {
    let max = settings.max_steps_explicit.max(settings.max_steps_implicit);
    run_options(h, settings.duration, max)
}

/// One trial of `method` at step `h`, its energy measured against `e_ref`.
pub fn trial(
    scene: &Scene,
    method: &Method,
    h: f64,
    e_ref: f64,
    settings: &StabilitySettings,
) -> Trial {
    let other = |e: &dyn std::fmt::Display| Trial {
        outcome: Outcome::Other(e.to_string()),
        stepping_seconds: 0.0,
    };
    let mut sim = match Simulation::new(scene) {
        Ok(s) => s,
        Err(e) => return other(&e),
    };
    // The guard at the tolerance, without the replay: a trial only needs
    // to know that it failed, and when.
    let guard = EnergyGuard::new(e_ref)
        .with_limit(settings.tolerance)
        .without_replay();
    let run = RunSettings::new(trial_options(h, settings))
        .with_minimise(settings.minimise)
        .with_guard(guard);
    let failed = |outcome| Trial {
        outcome,
        stepping_seconds: 0.0,
    };
    match sim.run(method, &run, |_| Ok(())) {
        Ok(report) => Trial {
            outcome: Outcome::Stable {
                max_error: worst_relative_error(&report.frames, e_ref).0,
            },
            stepping_seconds: report.stepping_seconds,
        },
        Err(RunError::Blowup(b)) => failed(Outcome::Energy {
            error: b.relative_error,
            time: b.time,
        }),
        Err(RunError::Diverged { step, time, .. }) => failed(Outcome::Blowup { step, time }),
        Err(RunError::Solve { step, time, .. } | RunError::Minimise { step, time, .. }) => {
            failed(Outcome::Newton { step, time })
        }
        Err(e) => other(&e),
    }
}

/// Where the search ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// A stable step and an unstable one within the resolution.
    Bracketed,
    /// Stable at every step up to the cap ([`StabilitySettings::cap`]).
    AtCap,
    /// Unstable at every step down to the floor
    /// ([`StabilitySettings::floor`]).
    BelowFloor,
}

/// What the search found for one method.
#[derive(Clone, Debug, PartialEq)]
pub struct Found {
    pub method: Method,
    pub status: Status,
    /// The largest step found stable, if any.
    pub h: Option<f64>,
    /// The largest `|H − H₀|/E_ref` of the trial at `h` (NaN without one).
    pub max_error: f64,
    /// How the trial just above `h` failed ([`Status::Bracketed`]), or the
    /// one at the floor ([`Status::BelowFloor`]); `None` at the cap.
    pub beyond: Option<Outcome>,
    /// Trials run.
    pub trials: usize,
    /// Where the search started: `2/ω_max` ([`Scales::h_linear`]).
    pub h_linear: f64,
    /// The smallest and the largest step the search could try.
    pub floor: f64,
    pub cap: f64,
}

/// The largest stable step of `method` on `scene`: [`Scales::of`] the
/// scene, then [`search`]. For several methods, compute the scales once and
/// call [`search`] for each (in parallel if you like: a search holds no
/// shared state).
pub fn largest_stable_step(
    scene: &Scene,
    method: &Method,
    settings: &StabilitySettings,
) -> Result<Found, StabilityError> {
    settings.check()?;
    let scales = Scales::of(scene)?;
    Ok(search(scene, method, &scales, settings))
}

/// The search for one method, from `scales.h_linear` clamped to the floor
/// and cap. `settings` should pass [`StabilitySettings::check`].
pub fn search(
    scene: &Scene,
    method: &Method,
    scales: &Scales,
    settings: &StabilitySettings,
) -> Found {
    let (floor, cap) = (settings.floor(method), settings.cap());
    let ladder = Geometric {
        floor,
        cap,
        resolution: settings.resolution,
    };
    let start = scales.h_linear.clamp(floor, cap);
    let bracket = largest_passing(&ladder, start, |h| {
        match trial(scene, method, h, scales.e_ref, settings).outcome {
            Outcome::Stable { max_error } => Ok(max_error),
            failed => Err(failed),
        }
    });
    let status = match (&bracket.passed, &bracket.failed) {
        (Some(_), Some(_)) => Status::Bracketed,
        (Some(_), None) => Status::AtCap,
        (None, _) => Status::BelowFloor,
    };
    Found {
        method: *method,
        status,
        h: bracket.passed.as_ref().map(|p| p.0),
        max_error: bracket.passed.map_or(f64::NAN, |p| p.1),
        beyond: bracket.failed.map(|f| f.1),
        trials: bracket.probes,
        h_linear: scales.h_linear,
        floor,
        cap,
    }
}

/// The stepping time per simulated second of `method` at `h` (s), from one
/// more trial; `None` if that trial is not stable. Run it alone (not beside
/// other searches) for a time that means something.
pub fn seconds_per_simulated_second(
    scene: &Scene,
    method: &Method,
    h: f64,
    e_ref: f64,
    settings: &StabilitySettings,
) -> Option<f64> {
    let t = trial(scene, method, h, e_ref, settings);
    t.outcome.stable().then(|| {
        let opts = trial_options(h, settings);
        t.stepping_seconds / (opts.frames as f64 * opts.substeps as f64 * h)
    })
}

/// The methods a search covers by default: the explicit symplectic ones,
/// explicit Euler, RK4, and the implicit Gauss–Legendre 2, midpoint and
/// implicit Euler.
pub fn default_methods() -> Vec<Method> {
    let mut out: Vec<Method> = Method::all()
        .iter()
        .filter(|m| m.explicit() && m.symplectic())
        .copied()
        .collect();
    out.extend(
        ["euler", "rk4", "gauss2", "midpoint", "implicit-euler"]
            .into_iter()
            .filter_map(|id| Method::parse(id).ok()),
    );
    out
}
