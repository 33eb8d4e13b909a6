//! Scenes: a cloth rectangle, its material, pins, gravity, colliders and the
//! run settings, read from a TOML file and checked field by field.
//!
//! Every error names the file and the field (`material.density`,
//! `pins.points[2]`, `colliders[0].radius`, …); nothing here panics on bad
//! input. See the crate documentation for the file format and the units.

use std::collections::BTreeSet;
use std::fmt;
use std::path::Path;

use toml::{Table, Value};

mod regrid;

pub use regrid::{GridError, parse_grid, regrid};

use crate::method::Method;

/// Why a scene could not be loaded. Every variant names the file; field
/// errors also name the field, as a dotted path (`cloth.nx`,
/// `colliders[1].radius`).
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("{file}: cannot read the scene: {source}")]
    Io {
        file: String,
        #[source]
        source: std::io::Error,
    },
    #[error("{file}: not valid TOML: {message}")]
    Syntax { file: String, message: String },
    #[error("{file}: {field}: {message}")]
    Field {
        file: String,
        field: String,
        message: String,
    },
}

impl SceneError {
    /// The file (or name) the scene came from.
    pub fn file(&self) -> &str {
        match self {
            SceneError::Io { file, .. }
            | SceneError::Syntax { file, .. }
            | SceneError::Field { file, .. } => file,
        }
    }
    /// The field the error is about, if it is about one.
    pub fn field(&self) -> Option<&str> {
        match self {
            SceneError::Field { field, .. } => Some(field),
            _ => None,
        }
    }
}

/// How the grid is laid out in space. Particle `(i, j)` starts at
/// `origin + prestretch · (i·Δx·u + j·Δy·v)` with `Δx = width/(nx − 1)`,
/// `Δy = height/(ny − 1)`. The y axis points up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Plane {
    /// `u = +x`, `v = +z`: a sheet lying flat at height `origin.y`.
    Horizontal,
    /// `u = +x`, `v = −y`: a sheet hanging down from row `j = 0`.
    Vertical,
}

impl Plane {
    /// The name used in scene files.
    pub fn name(self) -> &'static str {
        match self {
            Plane::Horizontal => "horizontal",
            Plane::Vertical => "vertical",
        }
    }
    /// The unit vectors `(u, v)` along which `i` and `j` grow.
    pub fn axes(self) -> ([f64; 3], [f64; 3]) {
        match self {
            Plane::Horizontal => ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
            Plane::Vertical => ([1.0, 0.0, 0.0], [0.0, -1.0, 0.0]),
        }
    }
}

/// The cloth rectangle.
#[derive(Clone, Debug, PartialEq)]
pub struct ClothSpec {
    /// Extent along `u` (m), between particle columns `i = 0` and `i = nx − 1`.
    pub width: f64,
    /// Extent along `v` (m), between rows `j = 0` and `j = ny − 1`.
    pub height: f64,
    /// Particles along the width (at least 2).
    pub nx: usize,
    /// Particles along the height (at least 2).
    pub ny: usize,
    /// Position of particle `(0, 0)` (m).
    pub origin: [f64; 3],
    pub plane: Plane,
    /// Initial positions are the rest grid scaled by this factor about
    /// `origin` (1 = at rest; 1.1 = stretched by 10 %).
    pub prestretch: f64,
}

/// Areal density and the stiffness of each spring family (see the crate
/// documentation for the convention). `None` (or 0): the family is absent.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Areal density (kg/m²).
    pub density: f64,
    /// Structural springs between neighbours `(i, j)–(i±1, j)`, `(i, j)–(i, j±1)` (N per unit strain).
    pub stretch: Option<f64>,
    /// Diagonal springs `(i, j)–(i+1, j±1)` (N per unit strain).
    pub shear: Option<f64>,
    /// Second-neighbour springs `(i, j)–(i±2, j)`, `(i, j)–(i, j±2)` (N per unit strain).
    pub bend: Option<f64>,
}

/// A smooth conservative penalty obstacle. A particle at signed distance
/// `d` from the surface (positive outside) penetrates by `δ = max(0, −d)`
/// and has potential `m·stiffness·φ(δ)` with `φ` the C² ramp
/// `δ³/(6s)` for `δ < s`, `δ²/2 − sδ/2 + s²/6` beyond (`s` = `skin`;
/// `s = 0` gives `δ²/2`).
#[derive(Clone, Debug, PartialEq)]
pub enum Collider {
    /// The half-space below the plane through `point` with outward `normal` (normalised on load).
    Plane {
        point: [f64; 3],
        normal: [f64; 3],
        stiffness: f64,
        skin: f64,
    },
    /// A solid ball.
    Sphere {
        center: [f64; 3],
        radius: f64,
        stiffness: f64,
        skin: f64,
    },
}

/// The default smoothing width of a collider's penalty ramp (m).
pub const DEFAULT_SKIN: f64 = 1e-3;

/// Frames, substeps and method.
#[derive(Clone, Debug, PartialEq)]
pub struct SimulationSpec {
    /// Frames per second (Hz), default 60.
    pub frame_rate: f64,
    /// Steps per frame: the step size is `1/(frame_rate·substeps)`.
    pub substeps: usize,
    /// Frames to simulate after the initial one.
    pub frames: usize,
    /// A method id that [`Method::parse`] accepts (every method of
    /// [`Method::all`]).
    pub method: String,
}

impl SimulationSpec {
    /// The step size `1/(frame_rate·substeps)` (s).
    pub fn step_size(&self) -> f64 {
        1.0 / (self.frame_rate * self.substeps as f64)
    }
}

/// A checked scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// From the `name` key, else the file stem.
    pub name: String,
    pub description: Option<String>,
    pub cloth: ClothSpec,
    pub material: Material,
    /// Pinned particles `(i, j)`, sorted and without repeats.
    pub pins: Vec<(usize, usize)>,
    /// Gravitational acceleration (m/s²); zero when the file gives none.
    pub gravity: [f64; 3],
    pub colliders: Vec<Collider>,
    pub simulation: SimulationSpec,
}

/// The largest grid a scene may ask for: 2²² = 4 194 304 particles (2048 ×
/// 2048). An explicit run needs memory in proportion to the springs (about
/// 4 to 6 per particle at 24 bytes each) and to the state and its copies
/// (the state, the last good frame, the frames kept for rendering: some
/// 300 bytes per particle in all): at this size under 2 GB, so a run fits
/// in 4 GB. The limit is checked before anything is built, so a typo such
/// as `ny = 100000000000` is an error at once instead of a machine that
/// runs out of memory.
pub const MAX_PARTICLES: usize = 1 << 22;

/// The largest scene file read: 16 MiB (the shipped scenes are about 2 KB;
/// a scene with thousands of colliders is well under a megabyte).
pub const MAX_SCENE_BYTES: u64 = 16 << 20;

/// The most frames a run may ask for (after the initial one): 10⁶, about
/// 4.6 hours at 60 Hz. Every frame keeps its statistics in memory (about
/// 100 bytes) and a row of `energy.csv`.
pub const MAX_FRAMES: usize = 1_000_000;

/// The most steps a run may take in all (frames × substeps): 10⁹. A small
/// grid steps at about 10⁷ per second and the paper's 25 × 25 at about 10⁵,
/// so this is hours, not the centuries that `u64::MAX` steps would be; it is
/// checked before the run.
pub const MAX_STEPS: u64 = 1_000_000_000;

/// Why a grid size is refused, and which of `nx`, `ny` to blame: `None`
/// when `nx × ny` is within [`MAX_PARTICLES`]. The larger of the two is
/// blamed (a huge `ny` is `ny`'s fault).
pub fn grid_too_large(nx: usize, ny: usize) -> Option<(&'static str, String)> {
    if nx.checked_mul(ny).is_some_and(|n| n <= MAX_PARTICLES) {
        return None;
    }
    let which = if ny > nx { "ny" } else { "nx" };
    Some((
        which,
        format!(
            "a {nx} × {ny} grid has more than the limit of {MAX_PARTICLES} particles (2^22, e.g. 2048 × 2048)"
        ),
    ))
}

/// Why `frames` frames of `substeps` steps at `frame_rate` Hz cannot be run,
/// as `(what, message)` with `what` one of `"frames"`, `"substeps"`,
/// `"frame_rate"` (the input to blame); `None` when they can. Refused:
/// more than [`MAX_FRAMES`] frames, more than [`MAX_STEPS`] steps in all,
/// and a step `h = 1/(frame_rate·substeps)` that is not a positive normal
/// number (`h = 0` after rounding, e.g. `frame_rate = 1e308`, would run and
/// move nothing).
pub fn run_length_problem(
    frames: usize,
    substeps: usize,
    frame_rate: f64,
) -> Option<(&'static str, String)> {
    if substeps == 0 {
        return Some(("substeps", "must be at least 1 (got 0)".into()));
    }
    if !(frame_rate > 0.0 && frame_rate.is_finite()) {
        return Some((
            "frame_rate",
            format!("must be positive and finite (got {frame_rate})"),
        ));
    }
    if frames > MAX_FRAMES {
        return Some((
            "frames",
            format!("{frames} frames is more than the limit of {MAX_FRAMES}"),
        ));
    }
    let steps = (frames as u128) * (substeps as u128);
    if substeps as u128 > MAX_STEPS as u128 || steps > MAX_STEPS as u128 {
        let what = if frames > substeps {
            "frames"
        } else {
            "substeps"
        };
        return Some((
            what,
            format!(
                "{frames} frames × {substeps} steps per frame = {steps} steps is more than the limit of {MAX_STEPS} steps in a run"
            ),
        ));
    }
    let h = 1.0 / (frame_rate * substeps as f64);
    if !h.is_normal() {
        let what = if frame_rate > substeps as f64 {
            "frame_rate"
        } else {
            "substeps"
        };
        return Some((
            what,
            format!(
                "the step 1/(frame_rate·substeps) = 1/({frame_rate:e} Hz × {substeps}) = {h:e} s is not a positive normal number: the run would not move"
            ),
        ));
    }
    None
}

impl Scene {
    /// Which spring families the material has: stretch, shear, bend.
    pub fn spring_families(&self) -> [bool; 3] {
        let m = &self.material;
        [m.stretch.is_some(), m.shear.is_some(), m.bend.is_some()]
    }

    /// The number of springs the grid has (free or not).
    pub fn spring_count(&self) -> usize {
        let (nx, ny) = (self.cloth.nx, self.cloth.ny);
        let [st, sh, be] = self.spring_families();
        let mut n = 0;
        if st {
            n += (nx - 1) * ny + nx * (ny - 1);
        }
        if sh {
            n += 2 * (nx - 1) * (ny - 1);
        }
        if be {
            n += nx.saturating_sub(2) * ny + nx * ny.saturating_sub(2);
        }
        n
    }

    /// Read and check a scene file.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let io = |source| SceneError::Io {
            file: file.clone(),
            source,
        };
        // Read at most MAX_SCENE_BYTES (+1 to tell a file of exactly that
        // size from a longer one): `symlab cloth /dev/zero` must not read
        // until memory runs out.
        let mut text = String::new();
        std::fs::File::open(path)
            .and_then(|f| {
                use std::io::Read;
                f.take(MAX_SCENE_BYTES + 1).read_to_string(&mut text)
            })
            .map_err(io)?;
        if text.len() as u64 > MAX_SCENE_BYTES {
            return Err(SceneError::Io {
                file,
                source: std::io::Error::other(format!(
                    "larger than the limit of {} MiB for a scene file",
                    MAX_SCENE_BYTES >> 20
                )),
            });
        }
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        Scene::parse(&text, &file, &stem)
    }

    /// Check a scene given as text; `file` names it in errors and is the
    /// default name.
    pub fn from_toml(text: &str, file: &str) -> Result<Scene, SceneError> {
        let stem = Path::new(file)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| file.to_string());
        Scene::parse(text, file, &stem)
    }

    fn parse(text: &str, file: &str, stem: &str) -> Result<Scene, SceneError> {
        let root: Table = text
            .parse()
            .map_err(|e: toml::de::Error| SceneError::Syntax {
                file: file.to_string(),
                message: e.to_string().trim_end().to_string(),
            })?;
        let r = Reader { file };
        r.keys(
            &root,
            "",
            &[
                "name",
                "description",
                "gravity",
                "cloth",
                "material",
                "pins",
                "colliders",
                "simulation",
            ],
        )?;
        let name = r
            .opt_string(&root, "", "name")?
            .unwrap_or_else(|| stem.to_string());
        let description = r.opt_string(&root, "", "description")?;
        let gravity = r.opt_vec3(&root, "", "gravity")?.unwrap_or([0.0; 3]);

        let cloth = r.cloth(r.req_table(&root, "", "cloth")?)?;
        let material = r.material(r.req_table(&root, "", "material")?)?;
        let pins = match root.get("pins") {
            None => Vec::new(),
            Some(_) => r.pins(r.req_table(&root, "", "pins")?, &cloth)?,
        };
        if pins.len() == cloth.nx * cloth.ny {
            return Err(r.err("pins", "every particle is pinned: nothing can move"));
        }
        let colliders = match root.get("colliders") {
            None => Vec::new(),
            Some(Value::Array(items)) => {
                let mut out = Vec::with_capacity(items.len());
                for (k, item) in items.iter().enumerate() {
                    let path = format!("colliders[{k}]");
                    match item {
                        Value::Table(t) => out.push(r.collider(t, &path)?),
                        other => {
                            return Err(
                                r.err(&path, format!("expected a table, found {}", kind(other)))
                            );
                        }
                    }
                }
                out
            }
            Some(other) => {
                return Err(r.err(
                    "colliders",
                    format!(
                        "expected an array of tables ([[colliders]]), found {}",
                        kind(other)
                    ),
                ));
            }
        };
        let simulation = r.simulation(r.req_table(&root, "", "simulation")?)?;
        let scene_name = name;
        let scene = Scene {
            name: String::new(),
            description,
            cloth,
            material,
            pins,
            gravity,
            colliders,
            simulation,
        };
        // The cross-field checks (springs present), reported under the file's name.
        let named = Scene {
            name: file.to_string(),
            ..scene
        };
        named.validate()?;
        let scene = Scene {
            name: scene_name,
            ..named
        };
        Ok(scene)
    }
}

impl Scene {
    /// Check the invariants that loading guarantees, for a scene built or
    /// edited in code (errors name the scene by its `name`).
    pub fn validate(&self) -> Result<(), SceneError> {
        let r = Reader { file: &self.name };
        let finite3 = |v: &[f64; 3], field: &str| {
            if v.iter().all(|x| x.is_finite()) {
                Ok(())
            } else {
                Err(r.err(field, format!("must be finite (got {v:?})")))
            }
        };
        let positive = |x: f64, field: &str| {
            if x > 0.0 && x.is_finite() {
                Ok(())
            } else {
                Err(r.err(field, format!("must be positive and finite (got {x})")))
            }
        };
        let non_negative = |x: f64, field: &str| {
            if x >= 0.0 && x.is_finite() {
                Ok(())
            } else {
                Err(r.err(field, format!("must be non-negative and finite (got {x})")))
            }
        };
        let c = &self.cloth;
        positive(c.width, "cloth.width")?;
        positive(c.height, "cloth.height")?;
        positive(c.prestretch, "cloth.prestretch")?;
        finite3(&c.origin, "cloth.origin")?;
        for (n, field) in [(c.nx, "cloth.nx"), (c.ny, "cloth.ny")] {
            if n < 2 {
                return Err(r.err(field, format!("must be at least 2 (got {n})")));
            }
        }
        if let Some((which, message)) = grid_too_large(c.nx, c.ny) {
            return Err(r.err(&format!("cloth.{which}"), message));
        }
        let m = &self.material;
        positive(m.density, "material.density")?;
        for (k, field) in [
            (m.stretch, "material.stretch"),
            (m.shear, "material.shear"),
            (m.bend, "material.bend"),
        ] {
            if let Some(k) = k {
                non_negative(k, field)?;
            }
        }
        let mut seen = BTreeSet::new();
        for (k, &(i, j)) in self.pins.iter().enumerate() {
            if i >= c.nx || j >= c.ny {
                return Err(r.err(
                    &format!("pins[{k}]"),
                    format!("({i}, {j}) is outside the {} × {} grid", c.nx, c.ny),
                ));
            }
            seen.insert((i, j));
        }
        if seen.len() == c.nx * c.ny {
            return Err(r.err("pins", "every particle is pinned: nothing can move"));
        }
        finite3(&self.gravity, "gravity")?;
        for (k, col) in self.colliders.iter().enumerate() {
            let f = |key: &str| format!("colliders[{k}].{key}");
            match col {
                Collider::Plane {
                    point,
                    normal,
                    stiffness,
                    skin,
                } => {
                    finite3(point, &f("point"))?;
                    finite3(normal, &f("normal"))?;
                    let len = normal.iter().map(|x| x * x).sum::<f64>().sqrt();
                    if (len - 1.0).abs() > 1e-9 {
                        return Err(r.err(
                            &f("normal"),
                            format!("must be a unit vector (length {len})"),
                        ));
                    }
                    positive(*stiffness, &f("stiffness"))?;
                    non_negative(*skin, &f("skin"))?;
                }
                Collider::Sphere {
                    center,
                    radius,
                    stiffness,
                    skin,
                } => {
                    finite3(center, &f("center"))?;
                    positive(*radius, &f("radius"))?;
                    positive(*stiffness, &f("stiffness"))?;
                    non_negative(*skin, &f("skin"))?;
                }
            }
        }
        let s = &self.simulation;
        positive(s.frame_rate, "simulation.frame_rate")?;
        if let Some((what, message)) = run_length_problem(s.frames, s.substeps, s.frame_rate) {
            return Err(r.err(&format!("simulation.{what}"), message));
        }
        Method::parse(&s.method).map_err(|e| r.err("simulation.method", e))?;
        if self.spring_count() == 0 {
            return Err(r.err(
                "material",
                format!(
                    "a {} × {} grid has no spring of the families given (stretch, shear, bend): nothing holds the cloth together",
                    c.nx, c.ny
                ),
            ));
        }
        self.check_scales()
    }

    /// The quantities the model derives from the fields must be finite,
    /// positive numbers a simulation can work with: grid spacings, rest
    /// lengths, the particle mass and its inverse, each spring's `k/L` and
    /// energy scale `k·L`, the weight `m·g` and the energy `M·|g|·ℓ` of the
    /// cloth falling by its size, each collider's `m·stiffness`. Each field
    /// can be finite on its own while a product overflows (`width = 1e308`:
    /// the diagonal's rest length) or underflows (`width = height = 1e-300`:
    /// the particle mass is 0 and its inverse infinite); such a scene would
    /// start from a non-finite state. The error names the field that makes
    /// the product extreme.
    fn check_scales(&self) -> Result<(), SceneError> {
        let r = Reader { file: &self.name };
        let c = &self.cloth;
        let bad = |x: f64| !(x.is_normal() && x > 0.0);
        let spacing = |len: f64, n: usize| len / (n - 1) as f64;
        let (dx, dy) = (spacing(c.width, c.nx), spacing(c.height, c.ny));
        let origin = c.origin.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        // Lengths enter the model squared (a distance is the square root of
        // a sum of squares, a spring's energy has (ℓ − L)²): a spacing whose
        // square underflows (below about 1e-154 m) would put neighbours "at
        // the same point", an extent whose square overflows would make every
        // distance infinite.
        let square_bad = |x: f64| bad(x * x);
        for (d, len, field) in [(dx, c.width, "cloth.width"), (dy, c.height, "cloth.height")] {
            if bad(d) || bad(2.0 * d) || square_bad(d) || square_bad(2.0 * d) {
                return Err(r.err(
                    field,
                    format!(
                        "{len:e} m gives a grid spacing of {d:e} m: not a positive length whose double and square are normal numbers (about 1e-154 to 1e154 m)"
                    ),
                ));
            }
            // The initial grid: spacing and extent scaled by prestretch,
            // placed at the origin. Blame the more extreme factor.
            let span = len * c.prestretch;
            let spacing = d * c.prestretch;
            let reach = origin + span;
            if bad(span) || square_bad(spacing) || square_bad(reach) {
                let field = if c.prestretch.ln().abs() > len.ln().abs() {
                    "cloth.prestretch"
                } else {
                    field
                };
                let field = if origin > 0.0
                    && origin.ln().abs() > span.ln().abs().max(spacing.ln().abs())
                {
                    "cloth.origin"
                } else {
                    field
                };
                return Err(r.err(
                    field,
                    format!(
                        "{len:e} m scaled by prestretch {:e} gives an initial extent of {span:e} m and spacing {spacing:e} m from an origin at distance {origin:e} m: not lengths whose squares are normal numbers (about 1e-154 to 1e154 m)",
                        c.prestretch,
                    ),
                ));
            }
            // Positions origin + i·Δ must stay apart after rounding.
            if origin > 0.0 && spacing <= origin * 1e-12 {
                // An origin far out, or a spacing made tiny by the size or
                // the prestretch: blame the more extreme.
                let field = if origin.ln().abs() >= spacing.ln().abs() {
                    "cloth.origin"
                } else if c.prestretch.ln().abs() > len.ln().abs() {
                    "cloth.prestretch"
                } else {
                    field
                };
                return Err(r.err(
                    field,
                    format!(
                        "an origin {origin:e} m from zero leaves the grid spacing {spacing:e} m to rounding (less than 1e-12 of it): particles would start at the same point",
                    ),
                ));
            }
        }
        let diag = dx.hypot(dy);
        let area = c.width * c.height;
        if bad(area) {
            let field = if c.width.ln().abs() >= c.height.ln().abs() {
                "cloth.width"
            } else {
                "cloth.height"
            };
            return Err(r.err(
                field,
                format!(
                    "the area width × height = {:e} × {:e} m² = {area:e} m² is not a positive finite number",
                    c.width, c.height
                ),
            ));
        }
        let n = (c.nx * c.ny) as f64;
        let m = &self.material;
        let mass = m.density * area / n;
        if bad(mass) || bad(1.0 / mass) {
            return Err(r.err(
                "material.density",
                format!(
                    "the particle mass density·width·height/(nx·ny) = {:e} × {area:e} / {n} = {mass:e} kg (inverse {:e}) is not a positive finite number",
                    m.density,
                    1.0 / mass
                ),
            ));
        }
        // The side a rest length comes from (the diagonal: the longer side).
        let longer = if c.width >= c.height {
            "cloth.width"
        } else {
            "cloth.height"
        };
        for (k, rests, field) in [
            (
                m.stretch,
                [(dx, "cloth.width"), (dy, "cloth.height")],
                "material.stretch",
            ),
            (m.shear, [(diag, longer), (diag, longer)], "material.shear"),
            (
                m.bend,
                [(2.0 * dx, "cloth.width"), (2.0 * dy, "cloth.height")],
                "material.bend",
            ),
        ] {
            let Some(k) = k else { continue };
            for (rest, side) in rests {
                let (kl, kappa) = (k / rest, k * rest);
                // The spring's rate k/L per particle mass is ω²: finite, or
                // the first step overflows.
                let omega2 = kl / mass;
                if kl.is_finite() && kappa.is_finite() && !omega2.is_finite() {
                    let field =
                        most_extreme(&[(k, field), (m.density, "material.density"), (rest, side)]);
                    return Err(r.err(
                        field,
                        format!(
                            "springs of stiffness {k:e} N and rest length {rest:e} m on particles of mass {mass:e} kg have k/(L·m) = ω² = {omega2:e} s⁻²: not finite"
                        ),
                    ));
                }
                // The elastic energy of the prestretch: ½·k·L·(s − 1)² per
                // spring, at most 4 springs of a family per particle.
                let strain = c.prestretch - 1.0;
                let stored = 0.5 * kappa * strain * strain * 4.0 * n;
                if kl.is_finite() && kappa.is_finite() && !stored.is_finite() {
                    let field = most_extreme(&[
                        (c.prestretch, "cloth.prestretch"),
                        (k, field),
                        (rest, side),
                    ]);
                    return Err(r.err(
                        field,
                        format!(
                            "springs of stiffness {k:e} N and rest length {rest:e} m prestretched by {:e} store about {stored:e} J in all: not finite",
                            c.prestretch
                        ),
                    ));
                }
                if !(kl.is_finite() && kappa.is_finite()) {
                    // Blame the more extreme of the two factors.
                    let field = if k.ln().abs() >= rest.ln().abs() {
                        field
                    } else {
                        side
                    };
                    return Err(r.err(
                        field,
                        format!(
                            "springs of stiffness {k:e} N and rest length {rest:e} m have k/L = {kl:e} N/m and an energy scale k·L = {kappa:e} J: not finite"
                        ),
                    ));
                }
            }
        }
        // |g| without overflowing the squares (gravity = [0, -1e200, 0]).
        let g = self.gravity.iter().fold(0.0f64, |a, x| a.hypot(*x));
        let size = c.width.max(c.height) * c.prestretch;
        let fall = mass * n * g * (size + origin);
        if !(g.is_finite() && (mass * g).is_finite() && fall.is_finite()) {
            // The factor that makes the product extreme: the density, |g|,
            // the size (width, height, prestretch) or the origin.
            let side = if c.width >= c.height {
                (c.width, "cloth.width")
            } else {
                (c.height, "cloth.height")
            };
            let field = most_extreme(&[
                (g, "gravity"),
                (m.density, "material.density"),
                side,
                (c.prestretch, "cloth.prestretch"),
                (origin, "cloth.origin"),
            ]);
            return Err(r.err(
                field,
                format!(
                    "|g| = {g:e} m/s² on a cloth of mass {:e} kg and size {size:e} m gives a potential energy of {fall:e} J: not finite",
                    mass * n
                ),
            ));
        }
        for (k, col) in self.colliders.iter().enumerate() {
            let stiffness = match col {
                Collider::Plane {
                    stiffness, point, ..
                } => {
                    if !point.iter().map(|x| x.abs()).sum::<f64>().is_finite() {
                        return Err(r.err(
                            &format!("colliders[{k}].point"),
                            format!("{point:?} is too far out: its distance from the origin is not finite"),
                        ));
                    }
                    *stiffness
                }
                Collider::Sphere {
                    stiffness,
                    center,
                    radius,
                    ..
                } => {
                    let far = center.iter().map(|x| x.abs()).sum::<f64>() + radius;
                    if !(far * far).is_finite() {
                        return Err(r.err(
                            &format!("colliders[{k}].radius"),
                            format!(
                                "a sphere of radius {radius:e} m at {center:?} is too large: (|center| + radius)² = {:e} m² is not finite",
                                far * far
                            ),
                        ));
                    }
                    *stiffness
                }
            };
            let kappa = stiffness * mass;
            if !kappa.is_finite() {
                return Err(r.err(
                    &format!("colliders[{k}].stiffness"),
                    format!("{stiffness:e} s⁻² times the particle mass {mass:e} kg is not finite"),
                ));
            }
        }
        Ok(())
    }
}

/// The field whose value is farthest from 1 in magnitude (|ln x| largest):
/// the one that makes a product of them overflow or underflow. Zero values
/// (an origin at 0) are skipped; the first field wins ties.
fn most_extreme<'a>(factors: &[(f64, &'a str)]) -> &'a str {
    let mut best = factors[0].1;
    let mut score = -1.0;
    for &(x, field) in factors {
        if x == 0.0 {
            continue;
        }
        let s = x.abs().ln().abs();
        if s > score {
            best = field;
            score = s;
        }
    }
    best
}

fn kind(v: &Value) -> &'static str {
    match v {
        Value::String(_) => "a string",
        Value::Integer(_) => "an integer",
        Value::Float(_) => "a float",
        Value::Boolean(_) => "a boolean",
        Value::Datetime(_) => "a date",
        Value::Array(_) => "an array",
        Value::Table(_) => "a table",
    }
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

/// Reads fields out of TOML tables, naming the file and field in errors.
struct Reader<'a> {
    file: &'a str,
}

impl Reader<'_> {
    fn err(&self, field: &str, message: impl fmt::Display) -> SceneError {
        SceneError::Field {
            file: self.file.to_string(),
            field: field.to_string(),
            message: message.to_string(),
        }
    }

    /// Refuse keys outside `allowed`.
    fn keys(&self, t: &Table, path: &str, allowed: &[&str]) -> Result<(), SceneError> {
        for key in t.keys() {
            if !allowed.contains(&key.as_str()) {
                let place = if path.is_empty() {
                    "at the top level".to_string()
                } else {
                    format!("in [{path}]")
                };
                return Err(self.err(
                    &join(path, key),
                    format!(
                        "unknown key `{key}` {place} (expected one of: {})",
                        allowed.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    fn req<'t>(&self, t: &'t Table, path: &str, key: &str) -> Result<&'t Value, SceneError> {
        t.get(key).ok_or_else(|| {
            let place = if path.is_empty() {
                "the scene".to_string()
            } else {
                format!("[{path}]")
            };
            self.err(&join(path, key), format!("missing (required in {place})"))
        })
    }

    fn req_table<'t>(&self, t: &'t Table, path: &str, key: &str) -> Result<&'t Table, SceneError> {
        match self.req(t, path, key)? {
            Value::Table(v) => Ok(v),
            other => Err(self.err(
                &join(path, key),
                format!("expected a table, found {}", kind(other)),
            )),
        }
    }

    fn number(&self, v: &Value, field: &str) -> Result<f64, SceneError> {
        let x = match v {
            Value::Float(x) => *x,
            Value::Integer(i) => *i as f64,
            other => {
                return Err(self.err(field, format!("expected a number, found {}", kind(other))));
            }
        };
        if !x.is_finite() {
            return Err(self.err(field, format!("must be finite (got {x})")));
        }
        Ok(x)
    }

    fn opt_f64(&self, t: &Table, path: &str, key: &str) -> Result<Option<f64>, SceneError> {
        t.get(key)
            .map(|v| self.number(v, &join(path, key)))
            .transpose()
    }

    fn req_f64(&self, t: &Table, path: &str, key: &str) -> Result<f64, SceneError> {
        self.number(self.req(t, path, key)?, &join(path, key))
    }

    fn positive(&self, x: f64, field: &str) -> Result<f64, SceneError> {
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(field, format!("must be positive (got {x})")))
        }
    }

    fn non_negative(&self, x: f64, field: &str) -> Result<f64, SceneError> {
        if x >= 0.0 {
            Ok(x)
        } else {
            Err(self.err(field, format!("must not be negative (got {x})")))
        }
    }

    fn integer(&self, v: &Value, field: &str) -> Result<i64, SceneError> {
        match v {
            Value::Integer(i) => Ok(*i),
            other => Err(self.err(field, format!("expected an integer, found {}", kind(other)))),
        }
    }

    fn count(&self, t: &Table, path: &str, key: &str, min: usize) -> Result<usize, SceneError> {
        let field = join(path, key);
        let i = self.integer(self.req(t, path, key)?, &field)?;
        if i < min as i64 {
            return Err(self.err(&field, format!("must be at least {min} (got {i})")));
        }
        usize::try_from(i).map_err(|_| self.err(&field, format!("too large (got {i})")))
    }

    fn opt_string(&self, t: &Table, path: &str, key: &str) -> Result<Option<String>, SceneError> {
        match t.get(key) {
            None => Ok(None),
            Some(Value::String(s)) => Ok(Some(s.clone())),
            Some(other) => Err(self.err(
                &join(path, key),
                format!("expected a string, found {}", kind(other)),
            )),
        }
    }

    fn string_value<'v>(&self, v: &'v Value, field: &str) -> Result<&'v str, SceneError> {
        match v {
            Value::String(s) => Ok(s),
            other => Err(self.err(field, format!("expected a string, found {}", kind(other)))),
        }
    }

    fn vec3(&self, v: &Value, field: &str) -> Result<[f64; 3], SceneError> {
        match v {
            Value::Array(items) if items.len() == 3 => {
                let mut out = [0.0; 3];
                for (k, x) in items.iter().enumerate() {
                    out[k] = self.number(x, &format!("{field}[{k}]"))?;
                }
                Ok(out)
            }
            Value::Array(items) => Err(self.err(
                field,
                format!("expected 3 numbers [x, y, z], found {}", items.len()),
            )),
            other => Err(self.err(
                field,
                format!("expected an array [x, y, z], found {}", kind(other)),
            )),
        }
    }

    fn opt_vec3(&self, t: &Table, path: &str, key: &str) -> Result<Option<[f64; 3]>, SceneError> {
        t.get(key)
            .map(|v| self.vec3(v, &join(path, key)))
            .transpose()
    }

    fn req_vec3(&self, t: &Table, path: &str, key: &str) -> Result<[f64; 3], SceneError> {
        self.vec3(self.req(t, path, key)?, &join(path, key))
    }

    fn str_array<'v>(
        &self,
        t: &'v Table,
        path: &str,
        key: &str,
    ) -> Result<Vec<(String, &'v str)>, SceneError> {
        let field = join(path, key);
        match t.get(key) {
            None => Ok(Vec::new()),
            Some(Value::Array(items)) => items
                .iter()
                .enumerate()
                .map(|(k, v)| {
                    let f = format!("{field}[{k}]");
                    self.string_value(v, &f).map(|s| (f, s))
                })
                .collect(),
            Some(other) => Err(self.err(
                &field,
                format!("expected an array of strings, found {}", kind(other)),
            )),
        }
    }

    fn cloth(&self, t: &Table) -> Result<ClothSpec, SceneError> {
        let p = "cloth";
        self.keys(
            t,
            p,
            &[
                "width",
                "height",
                "nx",
                "ny",
                "origin",
                "plane",
                "prestretch",
            ],
        )?;
        let width = self.positive(self.req_f64(t, p, "width")?, "cloth.width")?;
        let height = self.positive(self.req_f64(t, p, "height")?, "cloth.height")?;
        let nx = self.count(t, p, "nx", 2)?;
        let ny = self.count(t, p, "ny", 2)?;
        if let Some((which, message)) = grid_too_large(nx, ny) {
            return Err(self.err(&format!("cloth.{which}"), message));
        }
        let origin = self.opt_vec3(t, p, "origin")?.unwrap_or([0.0; 3]);
        let plane = match t.get("plane") {
            None => Plane::Horizontal,
            Some(v) => {
                match self.string_value(v, "cloth.plane")? {
                    "horizontal" => Plane::Horizontal,
                    "vertical" => Plane::Vertical,
                    other => {
                        return Err(self.err(
                        "cloth.plane",
                        format!("unknown plane \"{other}\" (expected \"horizontal\" or \"vertical\")"),
                    ));
                    }
                }
            }
        };
        let prestretch = match self.opt_f64(t, p, "prestretch")? {
            None => 1.0,
            Some(s) => self.positive(s, "cloth.prestretch")?,
        };
        Ok(ClothSpec {
            width,
            height,
            nx,
            ny,
            origin,
            plane,
            prestretch,
        })
    }

    fn material(&self, t: &Table) -> Result<Material, SceneError> {
        let p = "material";
        self.keys(t, p, &["density", "stretch", "shear", "bend"])?;
        let density = self.positive(self.req_f64(t, p, "density")?, "material.density")?;
        let family = |key: &str| -> Result<Option<f64>, SceneError> {
            match self.opt_f64(t, p, key)? {
                None => Ok(None),
                Some(k) => {
                    let k = self.non_negative(k, &join(p, key))?;
                    Ok((k > 0.0).then_some(k))
                }
            }
        };
        Ok(Material {
            density,
            stretch: family("stretch")?,
            shear: family("shear")?,
            bend: family("bend")?,
        })
    }

    fn pins(&self, t: &Table, cloth: &ClothSpec) -> Result<Vec<(usize, usize)>, SceneError> {
        let p = "pins";
        self.keys(t, p, &["edges", "corners", "points"])?;
        let (nx, ny) = (cloth.nx, cloth.ny);
        let mut set = BTreeSet::new();
        for (field, edge) in self.str_array(t, p, "edges")? {
            match edge {
                "top" => set.extend((0..nx).map(|i| (i, 0))),
                "bottom" => set.extend((0..nx).map(|i| (i, ny - 1))),
                "left" => set.extend((0..ny).map(|j| (0, j))),
                "right" => set.extend((0..ny).map(|j| (nx - 1, j))),
                other => {
                    return Err(self.err(
                        &field,
                        format!("unknown edge \"{other}\" (expected \"top\" (j = 0), \"bottom\" (j = ny − 1), \"left\" (i = 0) or \"right\" (i = nx − 1))"),
                    ));
                }
            }
        }
        for (field, corner) in self.str_array(t, p, "corners")? {
            set.insert(match corner {
                "top-left" => (0, 0),
                "top-right" => (nx - 1, 0),
                "bottom-left" => (0, ny - 1),
                "bottom-right" => (nx - 1, ny - 1),
                other => {
                    return Err(self.err(
                        &field,
                        format!("unknown corner \"{other}\" (expected \"top-left\", \"top-right\", \"bottom-left\" or \"bottom-right\")"),
                    ));
                }
            });
        }
        match t.get("points") {
            None => {}
            Some(Value::Array(items)) => {
                for (k, v) in items.iter().enumerate() {
                    let field = format!("pins.points[{k}]");
                    let ij = match v {
                        Value::Array(pair) if pair.len() == 2 => [
                            self.integer(&pair[0], &format!("{field}[0]"))?,
                            self.integer(&pair[1], &format!("{field}[1]"))?,
                        ],
                        _ => return Err(self.err(&field, "expected a pair of integers [i, j]")),
                    };
                    if ij[0] < 0 || ij[1] < 0 || ij[0] >= nx as i64 || ij[1] >= ny as i64 {
                        return Err(self.err(
                            &field,
                            format!(
                                "({}, {}) is outside the {nx} × {ny} grid (0 ≤ i < {nx}, 0 ≤ j < {ny})",
                                ij[0], ij[1]
                            ),
                        ));
                    }
                    set.insert((ij[0] as usize, ij[1] as usize));
                }
            }
            Some(other) => {
                return Err(self.err(
                    "pins.points",
                    format!("expected an array of [i, j] pairs, found {}", kind(other)),
                ));
            }
        }
        Ok(set.into_iter().collect())
    }

    fn collider(&self, t: &Table, path: &str) -> Result<Collider, SceneError> {
        let ty = self.string_value(self.req(t, path, "type")?, &join(path, "type"))?;
        let stiffness =
            |r: &Self| r.positive(r.req_f64(t, path, "stiffness")?, &join(path, "stiffness"));
        let skin = |r: &Self| -> Result<f64, SceneError> {
            match r.opt_f64(t, path, "skin")? {
                None => Ok(DEFAULT_SKIN),
                Some(s) => r.non_negative(s, &join(path, "skin")),
            }
        };
        match ty {
            "plane" => {
                self.keys(t, path, &["type", "point", "normal", "stiffness", "skin"])?;
                let point = self.req_vec3(t, path, "point")?;
                let n = self.req_vec3(t, path, "normal")?;
                let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                if !(len > 0.0 && len.is_finite()) {
                    return Err(self.err(&join(path, "normal"), "must be a nonzero vector"));
                }
                Ok(Collider::Plane {
                    point,
                    normal: [n[0] / len, n[1] / len, n[2] / len],
                    stiffness: stiffness(self)?,
                    skin: skin(self)?,
                })
            }
            "sphere" => {
                self.keys(t, path, &["type", "center", "radius", "stiffness", "skin"])?;
                let center = self.req_vec3(t, path, "center")?;
                let radius =
                    self.positive(self.req_f64(t, path, "radius")?, &join(path, "radius"))?;
                Ok(Collider::Sphere {
                    center,
                    radius,
                    stiffness: stiffness(self)?,
                    skin: skin(self)?,
                })
            }
            other => Err(self.err(
                &join(path, "type"),
                format!("unknown collider type \"{other}\" (expected \"plane\" or \"sphere\")"),
            )),
        }
    }

    fn simulation(&self, t: &Table) -> Result<SimulationSpec, SceneError> {
        let p = "simulation";
        self.keys(t, p, &["frame_rate", "substeps", "frames", "method"])?;
        let frame_rate = match self.opt_f64(t, p, "frame_rate")? {
            None => 60.0,
            Some(r) => self.positive(r, "simulation.frame_rate")?,
        };
        let substeps = self.count(t, p, "substeps", 1)?;
        let frames = self.count(t, p, "frames", 0)?;
        let method = self.string_value(self.req(t, p, "method")?, "simulation.method")?;
        Method::parse(method).map_err(|e| self.err("simulation.method", e))?;
        Ok(SimulationSpec {
            frame_rate,
            substeps,
            frames,
            method: method.to_string(),
        })
    }
}
