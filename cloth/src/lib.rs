//! Undamped mass-spring cloth as a separable Hamiltonian, after the cloth
//! experiments of Tan et al. (section 5 of the paper): scenes, the model and
//! its force Jacobian, runs with any scheme that steps it, and frame output.
//!
//! One way to run a scene: parse a [`Method`], give [`RunSettings`], and
//! [`Simulation::run`] it. Every method that `symlab list` lists and that
//! steps cloth goes through the same loop — explicit schemes, the implicit
//! tables through the sparse stage solver, the midpoint family and the
//! energy-conserving schemes as minimisations:
//!
//! ```
//! use cloth::{Method, RunSettings, Scene, Simulation};
//!
//! let scene = Scene::from_toml(r#"
//!     [cloth]
//!     width = 1.0
//!     height = 1.0
//!     nx = 4
//!     ny = 4
//!     [material]
//!     density = 0.1
//!     stretch = 10.0
//!     [pins]
//!     edges = ["top"]
//!     [simulation]
//!     substeps = 20
//!     frames = 3
//!     method = "gauss2"
//! "#, "inline.toml")?;
//! let method = Method::parse(&scene.simulation.method)?;
//! assert_eq!((method.kind(), method.order()), ("implicit", 4));
//! let mut sim = Simulation::new(&scene)?;
//! let report = sim.run(&method, &RunSettings::from_scene(&scene), |_frame| Ok(()))?;
//! assert_eq!(report.frames.len(), 4); // the initial state and 3 frames
//! // The same scene with an explicit scheme: the same call.
//! let mut sim = Simulation::new(&scene)?;
//! let report = sim.run(&Method::parse("stormer-verlet")?, &RunSettings::from_scene(&scene), |_| Ok(()))?;
//! assert_eq!(report.steps, 60);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The studies are library code too ([`study`]): the largest step at which a
//! method keeps the energy error of a scene within a tolerance
//! ([`study::stability::largest_stable_step`], the bracketing shared with
//! `compare --hard`), the growth of the energy error over a run
//! ([`study::growth::fit`]), the reference energy and the guard
//! ([`study::energy`], [`EnergyGuard`]). `symlab cloth --stability` and
//! `symlab paper` format what these return:
//!
//! ```
//! use cloth::study::stability::{StabilitySettings, Status, largest_stable_step};
//! use cloth::{Method, Scene};
//!
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
//!     substeps = 20
//!     frames = 3
//!     method = "stormer-verlet"
//! "#, "inline.toml")?;
//! let settings = StabilitySettings { duration: 0.2, ..Default::default() };
//! let found = largest_stable_step(&scene, &Method::parse("stormer-verlet")?, &settings)?;
//! assert_eq!(found.status, Status::Bracketed);
//! // Störmer–Verlet's linear limit is h·ω_max = 2; on the nonlinear sheet the
//! // search lands near it.
//! let ratio = found.h.unwrap() / found.h_linear;
//! assert!(0.5 < ratio && ratio < 2.0, "h/h_linear = {ratio}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Conventions
//!
//! * **Units**: SI throughout (m, kg, s, N, J). The y axis points up.
//! * **Grid**: particle `(i, j)`, `0 ≤ i < nx` along the width (`u`),
//!   `0 ≤ j < ny` along the height (`v`), has id `j·nx + i`; it starts at
//!   `origin + prestretch·(i·Δx·u + j·Δy·v)`, `Δx = width/(nx − 1)`,
//!   `Δy = height/(ny − 1)`. `plane = "horizontal"`: `u = +x`, `v = +z`;
//!   `"vertical"`: `u = +x`, `v = −y` (row `j = 0` on top). With
//!   `sag > 0` every row starts instead as one circular arc of chords `Δx`
//!   bowing by `sag` along `u × v` (down for a horizontal sheet), so that
//!   its ends are closer than `width`: a sheet pinned along its left and
//!   right edges then hangs between them like a hammock.
//! * **Springs**: stretch (structural) between `(i, j)` and `(i+1, j)`,
//!   `(i, j+1)`; shear between `(i, j)` and `(i+1, j+1)`, and `(i+1, j)` and
//!   `(i, j+1)`; bend between `(i, j)` and `(i+2, j)`, `(i, j+2)`. Rest
//!   lengths are those of the grid at `prestretch = 1`. A family whose
//!   stiffness is absent (or 0) has no springs and costs nothing.
//! * **Stiffness is per unit strain** (N): a spring of rest length `L`
//!   stretched to length `ℓ` pulls its ends together with force
//!   `k·(ℓ − L)/L` and stores `½·k·(ℓ − L)²/L`; as a linear spring its
//!   constant is `k/L` (N/m). `k` is the force that would double the
//!   spring's length, like the `EA` of a rod: a chain keeps its stiffness
//!   when refined, and the same `k` means the same material at every
//!   resolution along a line of springs.
//! * **Mass**: lumped and uniform, `m = density·width·height/(nx·ny)` per
//!   particle (no corner or edge weighting), so the mass matrix is `m·I`.
//! * **Pins**: pinned particles are removed from the unknowns; the state
//!   `z = [q; p]` holds the free particles only (`q, p ∈ R^{3·free}`, in
//!   particle-id order), and pinned positions are constants in the springs.
//! * **Colliders** are penalty potentials, conservative and C²: a particle
//!   penetrating a plane or sphere by `δ` has potential
//!   `m·stiffness·φ(δ)` with `φ(δ) = δ³/(6s)` for `δ < s` and
//!   `δ²/2 − sδ/2 + s²/6` beyond, `s` the `skin` (default 1 mm; `s = 0`
//!   gives `½δ²`). Collider stiffness is per unit mass (s⁻²): deep in
//!   contact a particle oscillates at `√stiffness` rad/s whatever the
//!   resolution.
//! * **Energy**: `H = ½pᵀM⁻¹p + V`, `V` = springs + gravity (`−Σ m g·x`) +
//!   colliders, over terms that depend on the free particles. No damping.
//!   The length constraints of an inextensible scene store no energy.
//!
//! # Scene files
//!
//! ```toml
//! name = "paper"                 # optional; default: the file stem
//! description = "…"              # optional
//! gravity = [0.0, -9.81, 0.0]    # optional (m/s²); absent: no gravity
//!
//! [cloth]
//! width = 1.0                    # m
//! height = 1.0                   # m
//! nx = 25                        # particles along the width, ≥ 2
//! ny = 25                        # particles along the height, ≥ 2
//! origin = [0.0, 0.0, 0.0]       # optional; position of particle (0, 0)
//! plane = "horizontal"           # optional; "horizontal" or "vertical"
//! prestretch = 1.0               # optional; initial scale of the grid about origin
//! sag = 0.0                      # optional; rows start as arcs sagging this much (m), ≤ a half circle
//!
//! [material]
//! density = 0.01378              # kg/m²
//! stretch = 50.75                # N per unit strain, or "inextensible"; each family optional
//! shear = 50.75
//! bend = 1.0
//! bending = 3.0e-6               # N·m, inextensible only: isometric bending (default 3e-6, 0: none)
//!
//! [pins]                         # optional; all three lists optional
//! edges = ["top"]                # "top" (j = 0), "bottom", "left" (i = 0), "right"
//! corners = ["top-left"]         # "top-left" (0, 0), "top-right", "bottom-left", "bottom-right"
//! points = [[3, 4]]              # (i, j)
//!
//! [[colliders]]                  # optional, any number
//! type = "sphere"                # or "plane" with point = [..], normal = [..]
//! center = [0.5, -0.4, 0.5]
//! radius = 0.3
//! stiffness = 1e5                # s⁻² (per unit mass)
//! skin = 0.001                   # optional (m)
//!
//! [simulation]
//! frame_rate = 60.0              # optional, Hz
//! substeps = 100                 # steps per frame, or "auto" (the default of an inextensible scene)
//! step = "fixed"                 # optional; "variable" (inextensible only, its default) or "fixed"
//! # wave_number = 1.0            # variable step only: the largest h·ω of a frame's interior steps, in (0, 2)
//! # max_substeps = 1024          # variable step only: the most steps per frame before the run stops
//! frames = 300
//! method = "symplectic-euler-a"  # any id of Method::all() (symlab list, avf, discrete-gradient, rattle)
//! ```
//!
//! `stretch = "inextensible"` makes the warp and weft edges holonomic
//! length constraints `|x_a − x_b|² = L²` instead of springs (shear and bend
//! stay springs); such a scene is stepped by `rattle` (RATTLE: the
//! constrained Störmer–Verlet step, [`step::rattle`]) and only by it. It must
//! start on its constraints (`prestretch = 1`), no two pins of one edge may
//! be apart by other than its length, and no straight line of edges may be
//! held taut between two pins (`sag` gives the rows of a sheet pinned at
//! both ends the slack to hang); each is an error naming the field. It
//! bends with the isometric bending energy `½·B·∫(κ₁ + κ₂)² dA`
//! (`bending = B` in N·m, [`DEFAULT_BENDING`] when left out, a light cotton
//! fabric; refused on a spring scene), without `substeps` chooses its
//! step from its stability limits ([`schedule::auto_step`]), and by default
//! takes RATTLE's reversible variable step (`step = "variable"`,
//! [`step::variable`]): each frame the fewest steps, at least `substeps`,
//! whose transverse-wave numbers `h·ω` stay at or below `wave_number`
//! (default 1), as `h·ω ∝ 1/N` from the counts integrated (`step =
//! "fixed"` takes `substeps` every frame).
//!
//! Unknown keys, missing fields, non-positive sizes or density, negative
//! stiffness, a resolution below 2, a pin outside the grid, an unknown
//! method, or a grid with no spring are errors that name the file and the
//! field. So are fields that are finite on their own but make the model's
//! derived quantities (spacing, rest lengths, particle mass and its inverse,
//! `k/L`, `k·L`, weights, collider stiffness per particle) or its initial
//! energy and forces non-finite, and scenes beyond the limits:
//! [`MAX_PARTICLES`] particles, [`MAX_FRAMES`] frames, [`MAX_STEPS`] steps
//! in a run, a step `1/(frame_rate·substeps)` that is not a positive normal
//! number. Implicit methods take at most
//! [`step::stage::MAX_FREE_PARTICLES`] free particles.
//!
//! # For a command-line front end
//!
//! * [`Scene::load`] → [`Scene`] (its fields are public: override
//!   `simulation.method`, `substeps`, `frames` as needed; [`scene::regrid`]
//!   changes the resolution).
//! * [`Method::parse`] → [`Method`]: the one registry of what steps cloth,
//!   with each method's facts (kind, [`Mechanism`], order, symplectic,
//!   [`Conserves`]); [`Method::all`] lists them.
//! * [`Simulation::new`] → model and initial state; [`Simulation::run`]
//!   (a [`Method`], [`RunSettings`], a frame callback) or
//!   [`Simulation::run_scheme`] (any `S: Step<ClothModel> + Scheme`; a
//!   table that `butcher!` found to be a composition of midpoint steps,
//!   `Info::midpoint_weights`, a user's included, steps as minimisations);
//!   [`run_scene`] does all three.
//! * [`RunSettings`]: frames, substeps, frame rate ([`RunOptions`]), the
//!   solvers ([`SolverSettings`]: [`MinimiseSettings`], [`StageSettings`])
//!   and an optional [`EnergyGuard`] (`E_ref` from
//!   [`study::energy::reference_energy`]); a guarded run that passes its
//!   limit stops with [`RunError::Blowup`], a [`Blowup`] that says where.
//! * The callback gets a [`Frame`]: statistics, the model and the state;
//!   [`Frame::positions`] and [`ClothModel::triangles`] feed [`write_obj`].
//!   [`RunReport::frames`] feeds [`write_energy_csv`]; [`RunReport::solver`]
//!   says what the solver did.
//! * [`ClothModel::stability`] estimates `ω_max` and `2/ω_max` at the initial
//!   state (power iteration on `M⁻¹K`, plus a Gershgorin upper bound).
//!
//! # Layout
//!
//! Imports run one way: [`method`] → [`scene`] → model → [`step`] (one
//! [`step::ClothStepper`] per mechanism, no frame loop) → run (the one
//! loop, the guard, the blow-up replay) → [`study`] → output.
//!
//! # For an implicit solver
//!
//! The model is a [`Separable`](integrator_core::Separable) system with
//! mass matrix `m·I` ([`ClothModel::inverse_mass`]).
//! [`ClothModel::force_jacobian_pattern`] gives the nonzeros of
//! `∂F/∂q = −∇²V` once, each entry once, in compressed-column order, and
//! [`ClothModel::force_jacobian_values`] fills the values in that order
//! without allocating, so a CSC matrix can be built once and refreshed in
//! place. The Jacobian of `z' = [M⁻¹p; F(q)]` is `[[0, M⁻¹], [∂F/∂q, 0]]`.

pub mod checkpoint;
mod frame;
pub mod method;
mod model;
mod output;
pub mod render;
mod run;
pub mod scene;
pub mod schedule;
pub mod step;
pub mod study;

pub use method::{
    AVERAGE_VECTOR_FIELD, Conserves, DISCRETE_GRADIENT, Mechanism, Method, MethodError, Minimised,
    RATTLE,
};
pub use model::{
    BENDING_POWER_ITERATIONS, BendingRate, CONSTRAINT_TOLERANCE, ClothModel, DEFAULT_BENDING,
    Energy, Family, STABILITY_WORK, Stability,
};
pub use output::{
    ENERGY_CSV_HEADER, OutputError, write_energy_csv, write_energy_csv_to, write_obj, write_obj_to,
};
pub use run::{
    Blowup, CallbackError, EnergyGuard, Frame, FrameStats, Located, RunError, RunOptions,
    RunReport, RunSettings, Simulation, SolverSettings,
};
pub use scene::{
    ClothSpec, Collider, MAX_FRAMES, MAX_PARTICLES, MAX_STEPS, Material, Plane, Scene, SceneError,
    SimulationSpec,
};
pub use schedule::run_scene;
pub use step::{
    MinimiseSettings, RattleSettings, Solver, SolverStats, StageSettings, VariableStats,
    VariableStep,
};

/// Nalgebra's 3-vector of `f64`, as used for positions and momenta.
pub type Vec3 = nalgebra::Vector3<f64>;

/// The guide's cloth chapter (`guide/src/cloth.md`), compiled and run as
/// doctests like the other chapters (whose hooks are in the `compare`
/// crate, which does not depend on this one).
#[cfg(doctest)]
#[doc = include_str!("../../guide/src/cloth.md")]
pub struct GuideCloth;
