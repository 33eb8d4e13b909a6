//! The mass-spring cloth as a separable Hamiltonian `H = ½ pᵀM⁻¹p + V(q)`.
//!
//! The state holds only the free particles: pinned particles are removed
//! from the unknowns and enter the forces as constant positions. Springs are
//! precomputed into two flat lists, free–free and free–pinned, ordered so
//! that consecutive springs rarely share a particle (no store-to-load
//! dependency between them), and the force loop allocates nothing.

use std::sync::OnceLock;

use nalgebra::{Matrix3, Vector3};

use crate::scene::{Collider, Scene, SceneError};

mod avf;
mod discrete_gradient;
mod stability;

pub use stability::{STABILITY_WORK, Stability};

/// The three spring families.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Family {
    /// Structural springs between grid neighbours.
    Stretch,
    /// Diagonal springs across each cell.
    Shear,
    /// Springs between second neighbours along rows and columns.
    Bend,
}

impl Family {
    pub const ALL: [Family; 3] = [Family::Stretch, Family::Shear, Family::Bend];
    pub fn name(self) -> &'static str {
        match self {
            Family::Stretch => "stretch",
            Family::Shear => "shear",
            Family::Bend => "bend",
        }
    }
}

/// A spring between two free particles (indices into the free list).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Spring {
    pub(crate) a: u32,
    pub(crate) b: u32,
    /// `k/L` (N/m).
    pub(crate) kl: f64,
    /// Rest length `L` (m).
    pub(crate) rest: f64,
}

/// A spring between a free particle and a pinned one.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PinSpring {
    pub(crate) a: u32,
    pub(crate) pin: [f64; 3],
    pub(crate) kl: f64,
    pub(crate) rest: f64,
}

#[derive(Clone, Copy, Debug)]
enum Shape {
    /// Signed distance `n·x − c`.
    Plane { normal: Vector3<f64>, c: f64 },
    /// Signed distance `|x − center| − radius`.
    Sphere { center: Vector3<f64>, radius: f64 },
}

/// A penalty collider with its per-particle stiffness `κ = m·stiffness`.
#[derive(Clone, Copy, Debug)]
struct Penalty {
    shape: Shape,
    kappa: f64,
    skin: f64,
}

impl Penalty {
    /// `(φ(δ), φ'(δ), φ''(δ))` of the C² ramp, times `κ`.
    #[inline]
    fn ramp(&self, delta: f64) -> (f64, f64, f64) {
        let (k, s) = (self.kappa, self.skin);
        if delta <= 0.0 {
            (0.0, 0.0, 0.0)
        } else if delta < s {
            (
                k * delta * delta * delta / (6.0 * s),
                k * delta * delta / (2.0 * s),
                k * delta / s,
            )
        } else {
            (
                k * (0.5 * delta * delta - 0.5 * s * delta + s * s / 6.0),
                k * (delta - 0.5 * s),
                k,
            )
        }
    }

    /// Signed distance and outward unit normal at `x` (`None` at a sphere's centre).
    #[inline]
    fn distance(&self, x: &Vector3<f64>) -> Option<(f64, Vector3<f64>, f64)> {
        match self.shape {
            Shape::Plane { normal, c } => Some((normal.dot(x) - c, normal, f64::INFINITY)),
            Shape::Sphere { center, radius } => {
                let r = x - center;
                let len = r.norm();
                (len > 0.0).then(|| (len - radius, r / len, len))
            }
        }
    }

    #[inline]
    fn energy(&self, x: &Vector3<f64>) -> f64 {
        self.distance(x).map_or(0.0, |(d, _, _)| self.ramp(-d).0)
    }

    #[inline]
    fn force(&self, x: &Vector3<f64>) -> Vector3<f64> {
        match self.distance(x) {
            Some((d, n, _)) if d < 0.0 => n * self.ramp(-d).1,
            _ => Vector3::zeros(),
        }
    }

    /// `∂F/∂x` (symmetric).
    #[inline]
    fn force_jacobian(&self, x: &Vector3<f64>) -> Matrix3<f64> {
        self.force_jacobian_projected(x, false)
    }

    /// `∂F/∂x`; `project`: without a sphere's tangential term
    /// `(I − n̂n̂ᵀ)·φ'/r`, the only part of `−∂F/∂x` that can be negative, so
    /// that `−∂F/∂x` is positive semidefinite (its projection onto the PSD
    /// cone: the term is a multiple of the tangential projector).
    #[inline]
    fn force_jacobian_projected(&self, x: &Vector3<f64>, project: bool) -> Matrix3<f64> {
        match self.distance(x) {
            Some((d, n, r)) if d < 0.0 => {
                let (_, d1, d2) = self.ramp(-d);
                let nn = n * n.transpose();
                let mut j = -d2 * nn;
                if r.is_finite() && !project {
                    j += (Matrix3::identity() - nn) * (d1 / r);
                }
                j
            }
            _ => Matrix3::zeros(),
        }
    }
}

/// The springs of a grid, as `(particle a, particle b, family, rest length)`
/// with particle ids `j·nx + i`, handed to `each` in the order the model
/// stores them: family by family and direction by direction, row by row,
/// and within a row of horizontal springs alternating blocks so that
/// consecutive springs share no particle. A callback rather than a list:
/// on a 2048 × 2048 grid the list alone would be 24 million entries.
fn grid_springs(
    nx: usize,
    ny: usize,
    dx: f64,
    dy: f64,
    families: [bool; 3],
    mut each: impl FnMut(usize, usize, Family, f64),
) {
    let diag = dx.hypot(dy);
    let mut dirs: Vec<(isize, isize, Family, f64)> = Vec::new();
    if families[0] {
        dirs.extend([(1, 0, Family::Stretch, dx), (0, 1, Family::Stretch, dy)]);
    }
    if families[1] {
        dirs.extend([(1, 1, Family::Shear, diag), (-1, 1, Family::Shear, diag)]);
    }
    if families[2] {
        dirs.extend([
            (2, 0, Family::Bend, 2.0 * dx),
            (0, 2, Family::Bend, 2.0 * dy),
        ]);
    }
    let id = |i: usize, j: usize| j * nx + i;
    for (di, dj, family, rest) in dirs {
        let is: Vec<usize> = (0..nx)
            .filter(|&i| {
                let ib = i as isize + di;
                ib >= 0 && (ib as usize) < nx
            })
            .collect();
        // Horizontal springs: blocks of `di` starting points alternate so
        // that consecutive springs are disjoint.
        let order: Vec<usize> = if dj == 0 {
            let l = di.unsigned_abs();
            let first = is.iter().copied().filter(|i| (i / l) % 2 == 0);
            let second = is.iter().copied().filter(|i| (i / l) % 2 == 1);
            first.chain(second).collect()
        } else {
            is
        };
        for j in 0..ny.saturating_sub(dj as usize) {
            for &i in &order {
                let ib = (i as isize + di) as usize;
                each(id(i, j), id(ib, j + dj as usize), family, rest);
            }
        }
    }
}

/// The energy of a state, by term. Terms that do not depend on the free
/// particles (springs between two pinned particles, the weight of pinned
/// particles) are left out.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energy {
    /// `½ pᵀM⁻¹p` (J).
    pub kinetic: f64,
    /// `Σ ½ k (ℓ − L)²/L` over springs with a free end (J).
    pub springs: f64,
    /// `−Σ m g·x` over free particles (J).
    pub gravity: f64,
    /// Penalty energy of the colliders (J).
    pub colliders: f64,
}

impl Energy {
    pub fn potential(&self) -> f64 {
        self.springs + self.gravity + self.colliders
    }
    pub fn total(&self) -> f64 {
        self.kinetic + self.potential()
    }
}

/// Where the Jacobian blocks of each term go in the value array: a block
/// `(r, c)` is stored column by column, entry `(rr, cc)` at
/// `base + cc·stride + rr`.
#[derive(Clone, Debug, Default)]
struct JacobianLayout {
    pattern: Vec<(usize, usize)>,
    /// Blocks `aa, ab, ba, bb` as `(base, stride)` pairs.
    ff: Vec<[u32; 8]>,
    fp: Vec<[u32; 2]>,
    /// Diagonal blocks of all free particles (only with colliders).
    diag: Vec<[u32; 2]>,
}

impl JacobianLayout {
    fn new(n_free: usize, ff: &[Spring], fp: &[PinSpring], with_diag: bool) -> JacobianLayout {
        // Block coordinates as (column, row).
        let mut blocks: Vec<(u32, u32)> = Vec::with_capacity(4 * ff.len() + fp.len() + n_free);
        for s in ff {
            blocks.extend([(s.a, s.a), (s.b, s.a), (s.a, s.b), (s.b, s.b)]);
        }
        blocks.extend(fp.iter().map(|s| (s.a, s.a)));
        if with_diag {
            blocks.extend((0..n_free as u32).map(|a| (a, a)));
        }
        blocks.sort_unstable();
        blocks.dedup();
        // Rows of each block column, and the scalar offset where it starts.
        let mut col_ptr = vec![0usize; n_free + 1];
        for &(c, _) in &blocks {
            col_ptr[c as usize + 1] += 1;
        }
        for c in 0..n_free {
            col_ptr[c + 1] += col_ptr[c];
        }
        let rows: Vec<u32> = blocks.iter().map(|&(_, r)| r).collect();
        let mut pattern = Vec::with_capacity(9 * blocks.len());
        for c in 0..n_free {
            let col_rows = &rows[col_ptr[c]..col_ptr[c + 1]];
            for cc in 0..3 {
                for &r in col_rows {
                    for rr in 0..3 {
                        pattern.push((3 * r as usize + rr, 3 * c + cc));
                    }
                }
            }
        }
        let locate = |r: u32, c: u32| -> [u32; 2] {
            let (lo, hi) = (col_ptr[c as usize], col_ptr[c as usize + 1]);
            let pos = rows[lo..hi].binary_search(&r).unwrap_or(0);
            [(9 * lo + 3 * pos) as u32, (3 * (hi - lo)) as u32]
        };
        let ff = ff
            .iter()
            .map(|s| {
                let [aa, ab, ba, bb] = [
                    locate(s.a, s.a),
                    locate(s.a, s.b),
                    locate(s.b, s.a),
                    locate(s.b, s.b),
                ];
                [aa[0], aa[1], ab[0], ab[1], ba[0], ba[1], bb[0], bb[1]]
            })
            .collect();
        let fp = fp.iter().map(|s| locate(s.a, s.a)).collect();
        let diag = if with_diag {
            (0..n_free as u32).map(|a| locate(a, a)).collect()
        } else {
            Vec::new()
        };
        JacobianLayout {
            pattern,
            ff,
            fp,
            diag,
        }
    }
}

#[inline]
fn add_block(values: &mut [f64], [base, stride]: [u32; 2], m: &Matrix3<f64>, sign: f64) {
    let (base, stride) = (base as usize, stride as usize);
    for cc in 0..3 {
        let col = &mut values[base + cc * stride..base + cc * stride + 3];
        for rr in 0..3 {
            col[rr] += sign * m[(rr, cc)];
        }
    }
}

/// `∂F_a/∂x_b` of a spring with `d = x_b − x_a`: `(k/L)[(1 − L/ℓ) I + (L/ℓ) d̂d̂ᵀ]`;
/// `definite`: with `1 − L/ℓ` clamped at 0 (see
/// [`ClothModel::force_jacobian_values_definite`]).
#[inline]
fn spring_block(d: &Vector3<f64>, kl: f64, rest: f64, definite: bool) -> Matrix3<f64> {
    let l = d.norm();
    let dh = d / l;
    let transverse = 1.0 - rest / l;
    let transverse = if definite {
        transverse.max(0.0)
    } else {
        transverse
    };
    Matrix3::from_diagonal_element(kl * transverse) + (dh * dh.transpose()) * (kl * rest / l)
}

/// The cloth of a scene as a [`Separable`](integrator_core::Separable)
/// Hamiltonian on the free particles.
#[derive(Clone, Debug)]
pub struct ClothModel {
    name: String,
    nx: usize,
    ny: usize,
    mass: f64,
    inv_mass: f64,
    gravity: Vector3<f64>,
    /// `m·g`, the weight of one particle (N).
    weight: [f64; 3],
    /// Particle id → index into the free list, or `u32::MAX` when pinned.
    free_index: Vec<u32>,
    /// Free index → particle id.
    free_ids: Vec<u32>,
    /// Positions of all particles at the start (pinned ones stay there).
    start: Vec<Vector3<f64>>,
    ff: Vec<Spring>,
    fp: Vec<PinSpring>,
    /// The largest `|ℓ − L|/L` among springs between two pinned particles.
    pp_strain: f64,
    family_counts: [usize; 3],
    colliders: Vec<Penalty>,
    /// Built on first use ([`ClothModel::jac`]).
    jac: OnceLock<JacobianLayout>,
}

const PINNED: u32 = u32::MAX;

impl ClothModel {
    /// Build the model of a scene. Fails (naming the field) only when the
    /// scene breaks an invariant that [`Scene::load`] checks, e.g. after
    /// editing its fields by hand.
    pub fn new(scene: &Scene) -> Result<ClothModel, SceneError> {
        scene.validate()?;
        let c = &scene.cloth;
        let (nx, ny) = (c.nx, c.ny);
        let n = nx * ny;
        let dx = c.width / (nx - 1) as f64;
        let dy = c.height / (ny - 1) as f64;
        let (u, v) = c.plane.axes();
        let (u, v) = (Vector3::from(u), Vector3::from(v));
        let origin = Vector3::from(c.origin);
        let start: Vec<Vector3<f64>> = (0..n)
            .map(|id| {
                let (i, j) = (id % nx, id / nx);
                origin + (u * (i as f64 * dx) + v * (j as f64 * dy)) * c.prestretch
            })
            .collect();
        let mut free_index = vec![0u32; n];
        for &(i, j) in &scene.pins {
            free_index[j * nx + i] = PINNED;
        }
        let mut free_ids = Vec::with_capacity(n - scene.pins.len());
        for (id, slot) in free_index.iter_mut().enumerate() {
            if *slot != PINNED {
                *slot = free_ids.len() as u32;
                free_ids.push(id as u32);
            }
        }
        let mass = scene.material.density * c.width * c.height / n as f64;
        let m = &scene.material;
        let stiffness = |f: Family| match f {
            Family::Stretch => m.stretch,
            Family::Shear => m.shear,
            Family::Bend => m.bend,
        };
        let mut ff = Vec::with_capacity(scene.spring_count());
        let mut fp = Vec::new();
        let mut pp_strain: f64 = 0.0;
        let mut family_counts = [0usize; 3];
        // The first spring whose ends start at the same point (rounding).
        let mut collapsed = None;
        grid_springs(
            nx,
            ny,
            dx,
            dy,
            scene.spring_families(),
            |a, b, family, rest| {
                let k = stiffness(family).unwrap_or(0.0);
                family_counts[family as usize] += 1;
                let kl = k / rest;
                let apart = (start[b] - start[a]).norm();
                if collapsed.is_none() && (apart.is_nan() || apart <= 0.0) {
                    collapsed = Some((a, b));
                }
                match (free_index[a], free_index[b]) {
                    (PINNED, PINNED) => {
                        pp_strain =
                            pp_strain.max(((start[b] - start[a]).norm() - rest).abs() / rest);
                    }
                    (PINNED, fb) => fp.push(PinSpring {
                        a: fb,
                        pin: start[a].into(),
                        kl,
                        rest,
                    }),
                    (fa, PINNED) => fp.push(PinSpring {
                        a: fa,
                        pin: start[b].into(),
                        kl,
                        rest,
                    }),
                    (fa, fb) => ff.push(Spring {
                        a: fa,
                        b: fb,
                        kl,
                        rest,
                    }),
                }
            },
        );
        ff.shrink_to_fit();
        let field_err = |field: &str, message: String| SceneError::Field {
            file: scene.name.clone(),
            field: field.to_string(),
            message,
        };
        if let Some((a, b)) = collapsed {
            return Err(field_err(
                "cloth.origin",
                format!(
                    "particles {:?} and {:?} start at the same point {:?}: the grid spacing is lost to rounding there",
                    (a % nx, a / nx),
                    (b % nx, b / nx),
                    start[a].as_slice()
                ),
            ));
        }
        let colliders: Vec<Penalty> = scene
            .colliders
            .iter()
            .map(|col| match *col {
                Collider::Plane {
                    point,
                    normal,
                    stiffness,
                    skin,
                } => {
                    let normal = Vector3::from(normal);
                    Penalty {
                        shape: Shape::Plane {
                            normal,
                            c: normal.dot(&Vector3::from(point)),
                        },
                        kappa: stiffness * mass,
                        skin,
                    }
                }
                Collider::Sphere {
                    center,
                    radius,
                    stiffness,
                    skin,
                } => Penalty {
                    shape: Shape::Sphere {
                        center: Vector3::from(center),
                        radius,
                    },
                    kappa: stiffness * mass,
                    skin,
                },
            })
            .collect();
        let gravity = Vector3::from(scene.gravity);
        let model = ClothModel {
            name: scene.name.clone(),
            nx,
            ny,
            mass,
            inv_mass: 1.0 / mass,
            gravity,
            weight: (gravity * mass).into(),
            free_index,
            free_ids,
            start,
            ff,
            fp,
            pp_strain,
            family_counts,
            colliders,
            jac: OnceLock::new(),
        };
        model.check_initial_state(scene)?;
        Ok(model)
    }

    /// The initial state must have a finite energy, term by term, and
    /// finite forces: a scene whose fields are each finite can still start
    /// from infinities (a sphere so large that the cloth starts 1e154 m deep
    /// inside it, a spring energy that overflows). Such a run could never
    /// mean anything, and its relative energy error would be NaN from the
    /// first frame; it is refused here, naming the field.
    fn check_initial_state(&self, scene: &Scene) -> Result<(), SceneError> {
        let field_err = |field: String, message: String| SceneError::Field {
            file: scene.name.clone(),
            field,
            message,
        };
        let z = self.initial_state();
        let q = &z[..3 * self.free_count()];
        let (springs, gravity, _) = self.potential_terms(q);
        if !springs.is_finite() {
            return Err(field_err(
                "material".into(),
                format!("the spring energy at the initial positions is {springs:e} J: not finite"),
            ));
        }
        if !gravity.is_finite() {
            return Err(field_err(
                "gravity".into(),
                format!(
                    "the gravitational energy at the initial positions is {gravity:e} J: not finite"
                ),
            ));
        }
        let q3 = self.chunks(q);
        for (k, c) in self.colliders.iter().enumerate() {
            let e: f64 = q3.iter().map(|x| c.energy(&Vector3::from(*x))).sum();
            if !e.is_finite() {
                let deepest = q3
                    .iter()
                    .filter_map(|x| c.distance(&Vector3::from(*x)))
                    .map(|(d, _, _)| -d)
                    .fold(0.0f64, f64::max);
                return Err(field_err(
                    format!("colliders[{k}]"),
                    format!(
                        "its penalty energy at the initial positions is {e:e} J, not finite: the cloth starts {deepest:e} m deep inside it"
                    ),
                ));
            }
        }
        let mut force = vec![0.0; q.len()];
        integrator_core::Separable::force(self, q, &mut force);
        if let Some(index) = force.iter().position(|f| !f.is_finite()) {
            let (i, j) = self.particle_of_component(index).unwrap_or((0, 0));
            return Err(field_err(
                "material".into(),
                format!(
                    "the force on particle ({i}, {j}) at the initial positions is {}: not finite",
                    force[index]
                ),
            ));
        }
        Ok(())
    }

    /// The sparse layout of the force Jacobian, built on first use: only
    /// implicit methods (and tests) need it, and it costs about 50 times the
    /// memory of the springs (on a 2048 × 2048 grid, about 8 GB), so an
    /// explicit run never builds it.
    fn jac(&self) -> &JacobianLayout {
        self.jac.get_or_init(|| {
            JacobianLayout::new(
                self.free_ids.len(),
                &self.ff,
                &self.fp,
                !self.colliders.is_empty(),
            )
        })
    }

    /// Whether the sparse Jacobian layout has been built: only once an
    /// implicit method (or a caller of
    /// [`force_jacobian_pattern`](Self::force_jacobian_pattern) and its
    /// kin) asked for it. An explicit run never does.
    pub fn jacobian_built(&self) -> bool {
        self.jac.get().is_some()
    }

    /// The elastic energy the springs with a free end store when every one
    /// of them is stretched by the relative amount `strain`:
    /// `Σ ½·k·L·strain²` (J). An energy scale of the material alone, for
    /// measuring energy errors of a scene that has no other (no gravity,
    /// starting at rest).
    pub fn elastic_energy_scale(&self, strain: f64) -> f64 {
        let kl2 = |kl: f64, rest: f64| kl * rest * rest;
        let sum: f64 = self.ff.iter().map(|s| kl2(s.kl, s.rest)).sum::<f64>()
            + self.fp.iter().map(|s| kl2(s.kl, s.rest)).sum::<f64>();
        0.5 * sum * strain * strain
    }

    /// The scene's name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Grid size `(nx, ny)`.
    pub fn grid(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }
    /// All particles, free and pinned.
    pub fn particle_count(&self) -> usize {
        self.nx * self.ny
    }
    /// Particles in the state.
    pub fn free_count(&self) -> usize {
        self.free_ids.len()
    }
    pub fn pinned_count(&self) -> usize {
        self.particle_count() - self.free_count()
    }
    /// The lumped mass of every particle (kg).
    pub fn particle_mass(&self) -> f64 {
        self.mass
    }
    /// `1/m`: the mass matrix is `m·I`.
    pub fn inverse_mass(&self) -> f64 {
        self.inv_mass
    }
    pub fn gravity(&self) -> Vector3<f64> {
        self.gravity
    }
    /// Springs of each family in the grid (free or not), in the order of [`Family::ALL`].
    pub fn family_counts(&self) -> [usize; 3] {
        self.family_counts
    }
    /// All springs of the grid.
    pub fn spring_count(&self) -> usize {
        self.family_counts.iter().sum()
    }
    /// Springs that the force loop visits (those with a free end).
    pub fn active_spring_count(&self) -> usize {
        self.ff.len() + self.fp.len()
    }
    /// The grid position `(i, j)` of a particle id `j·nx + i`.
    pub fn grid_index(&self, id: usize) -> (usize, usize) {
        (id % self.nx, id / self.nx)
    }
    /// The index of particle `(i, j)` in the free list (its position is
    /// `q[3k..3k + 3]`), or `None` when it is pinned or outside the grid.
    pub fn free_index(&self, i: usize, j: usize) -> Option<usize> {
        if i >= self.nx || j >= self.ny {
            return None;
        }
        let k = self.free_index[j * self.nx + i];
        (k != PINNED).then_some(k as usize)
    }
    /// The particle id of the `k`-th free particle.
    pub fn free_particle(&self, k: usize) -> usize {
        self.free_ids[k] as usize
    }
    /// The grid position of the particle a state component belongs to
    /// (`q` or `p`, any of x, y, z), if the index is in range.
    pub fn particle_of_component(&self, index: usize) -> Option<(usize, usize)> {
        let k = (index % (3 * self.free_count()).max(1)) / 3;
        self.free_ids.get(k).map(|&id| self.grid_index(id as usize))
    }

    /// The initial state `z = [q; p]`: the scene's initial positions at rest (`p = 0`).
    pub fn initial_state(&self) -> Vec<f64> {
        let n = 3 * self.free_count();
        let mut z = vec![0.0; 2 * n];
        for (k, &id) in self.free_ids.iter().enumerate() {
            z[3 * k..3 * k + 3].copy_from_slice(self.start[id as usize].as_slice());
        }
        z
    }

    /// Positions of all particles (free ones from `q`, pinned ones fixed),
    /// indexed by particle id `j·nx + i`.
    pub fn positions(&self, q: &[f64]) -> Vec<Vector3<f64>> {
        let mut out = Vec::new();
        self.positions_into(q, &mut out);
        out
    }

    /// [`positions`](Self::positions) into a reused buffer.
    pub fn positions_into(&self, q: &[f64], out: &mut Vec<Vector3<f64>>) {
        out.clear();
        out.extend_from_slice(&self.start);
        for (k, &id) in self.free_ids.iter().enumerate() {
            out[id as usize] = Vector3::new(q[3 * k], q[3 * k + 1], q[3 * k + 2]);
        }
    }

    /// The triangles of the grid (particle ids, counter-clockwise seen from
    /// `u × v`), two per cell, for OBJ output.
    pub fn triangles(&self) -> Vec<[usize; 3]> {
        let nx = self.nx;
        let mut out = Vec::with_capacity(2 * (self.nx - 1) * (self.ny - 1));
        for j in 0..self.ny - 1 {
            for i in 0..nx - 1 {
                let a = j * nx + i;
                let (b, c, d) = (a + 1, a + nx, a + nx + 1);
                out.push([a, b, d]);
                out.push([a, d, c]);
            }
        }
        out
    }

    /// The largest relative elongation or compression `|ℓ − L|/L` over all springs.
    pub fn max_strain(&self, q: &[f64]) -> f64 {
        let q3 = self.chunks(q);
        let mut m = self.pp_strain;
        for s in &self.ff {
            let d = Vector3::from(q3[s.b as usize]) - Vector3::from(q3[s.a as usize]);
            m = m.max((d.norm() - s.rest).abs() / s.rest);
        }
        for s in &self.fp {
            let d = Vector3::from(s.pin) - Vector3::from(q3[s.a as usize]);
            m = m.max((d.norm() - s.rest).abs() / s.rest);
        }
        m
    }

    /// Total momentum `Σ p` of the free particles (kg·m/s).
    pub fn momentum(&self, p: &[f64]) -> Vector3<f64> {
        self.chunks(p)
            .iter()
            .fold(Vector3::zeros(), |acc, x| acc + Vector3::from(*x))
    }

    /// The energy of `z = [q; p]` by term.
    pub fn energy(&self, z: &[f64]) -> Energy {
        let (q, p) = z.split_at(3 * self.free_count());
        let (springs, gravity, colliders) = self.potential_terms(q);
        Energy {
            kinetic: integrator_core::Separable::kinetic(self, p),
            springs,
            gravity,
            colliders,
        }
    }

    /// Springs, gravity and collider potential at `q`.
    pub(crate) fn potential_terms(&self, q: &[f64]) -> (f64, f64, f64) {
        let q3 = self.chunks(q);
        let mut springs = 0.0;
        for s in &self.ff {
            let d = Vector3::from(q3[s.b as usize]) - Vector3::from(q3[s.a as usize]);
            let e = d.norm() - s.rest;
            springs += 0.5 * s.kl * e * e;
        }
        for s in &self.fp {
            let d = Vector3::from(s.pin) - Vector3::from(q3[s.a as usize]);
            let e = d.norm() - s.rest;
            springs += 0.5 * s.kl * e * e;
        }
        let mut gravity = 0.0;
        let mut colliders = 0.0;
        let w = Vector3::from(self.weight);
        for x in q3 {
            let x = Vector3::from(*x);
            gravity -= w.dot(&x);
            for c in &self.colliders {
                colliders += c.energy(&x);
            }
        }
        (springs, gravity, colliders)
    }

    #[inline]
    fn chunks<'a>(&self, x: &'a [f64]) -> &'a [[f64; 3]] {
        &x.as_chunks::<3>().0[..self.free_count()]
    }

    /// The positions (row, column) of the nonzero entries of the force
    /// Jacobian `∂F/∂q = −∇²V` (`3·free × 3·free`), each once, sorted by
    /// column and then row: the order of a compressed-sparse-column matrix's
    /// values, so a CSC matrix built from this pattern (e.g. faer's
    /// `SparseColMat::try_new_from_triplets`) can take
    /// [`force_jacobian_values`](Self::force_jacobian_values) into its value
    /// array as it is. The structure does not depend on the state; the
    /// blocks are 3×3, one per pair of particles coupled by a spring and one
    /// on the diagonal of every particle with a spring or (when the scene has
    /// colliders) any particle.
    pub fn force_jacobian_pattern(&self) -> Vec<(usize, usize)> {
        self.jac().pattern.clone()
    }

    /// The number of entries of [`force_jacobian_pattern`](Self::force_jacobian_pattern).
    pub fn force_jacobian_nnz(&self) -> usize {
        self.jac().pattern.len()
    }

    /// The values of `∂F/∂q` at `q`, in the order of
    /// [`force_jacobian_pattern`](Self::force_jacobian_pattern). Allocates nothing.
    ///
    /// # Panics
    /// If `values` is not exactly as long as the pattern or `q` shorter than `3·free`.
    pub fn force_jacobian_values(&self, q: &[f64], values: &mut [f64]) {
        self.jacobian_into(q, values, false, false);
    }

    /// [`force_jacobian_values`](Self::force_jacobian_values) with the
    /// transverse term `(k/L)(1 − L/ℓ)` of every compressed spring (`ℓ < L`)
    /// clamped to 0, so that `K = −∂F/∂q` is positive semidefinite (the
    /// springs and gravity; colliders as they are). This is the matrix the
    /// implicit stage solver factorises: a compressed spring makes the exact
    /// `K` indefinite, and then `I + h²M⁻¹K` can be nearly singular at large
    /// `h`, which sends Newton's corrections far off. Newton's method only
    /// needs an approximate Jacobian, so the converged steps are the same;
    /// only the iteration is better behaved (the clamp of Choi and Ko, 2002).
    pub fn force_jacobian_values_definite(&self, q: &[f64], values: &mut [f64]) {
        self.jacobian_into(q, values, true, false);
    }

    /// `−∇²V` projected so that `∇²V` is positive semidefinite, block by
    /// block, in the order of
    /// [`force_jacobian_pattern`](Self::force_jacobian_pattern): each
    /// spring's 3×3 block `(k/L)[(1 − L/ℓ)I + (L/ℓ)d̂d̂ᵀ]` has the
    /// eigenvalues `k/L` (along the spring) and `(k/L)(1 − L/ℓ)` (twice,
    /// across it), and the latter is clamped at 0 — exactly the projection
    /// of the block onto the PSD cone; a sphere collider's tangential term
    /// (negative curvature of `V`) is dropped, the normal term kept; plane
    /// colliders and gravity need nothing. The Hessian of the minimisation
    /// solvers ([`crate::step::minimise`]). Allocates nothing.
    pub fn force_jacobian_values_projected(&self, q: &[f64], values: &mut [f64]) {
        self.jacobian_into(q, values, true, true);
    }

    fn jacobian_into(&self, q: &[f64], values: &mut [f64], definite: bool, project: bool) {
        let jac = self.jac();
        assert_eq!(
            values.len(),
            jac.pattern.len(),
            "values must match the Jacobian pattern"
        );
        values.fill(0.0);
        let q3 = self.chunks(q);
        for (s, loc) in self.ff.iter().zip(&jac.ff) {
            let d = Vector3::from(q3[s.b as usize]) - Vector3::from(q3[s.a as usize]);
            let k = spring_block(&d, s.kl, s.rest, definite);
            add_block(values, [loc[0], loc[1]], &k, -1.0);
            add_block(values, [loc[2], loc[3]], &k, 1.0);
            add_block(values, [loc[4], loc[5]], &k, 1.0);
            add_block(values, [loc[6], loc[7]], &k, -1.0);
        }
        for (s, &loc) in self.fp.iter().zip(&jac.fp) {
            let d = Vector3::from(s.pin) - Vector3::from(q3[s.a as usize]);
            add_block(values, loc, &spring_block(&d, s.kl, s.rest, definite), -1.0);
        }
        for (x, &loc) in q3.iter().zip(&jac.diag) {
            let x = Vector3::from(*x);
            for c in &self.colliders {
                add_block(values, loc, &c.force_jacobian_projected(&x, project), 1.0);
            }
        }
    }

    /// The springs with a free end: free–free and free–pinned.
    pub(crate) fn springs(&self) -> (&[Spring], &[PinSpring]) {
        (&self.ff, &self.fp)
    }

    /// Whether the scene has colliders.
    pub fn has_colliders(&self) -> bool {
        !self.colliders.is_empty()
    }

    /// The weight `m·g` of one particle (N).
    pub fn weight(&self) -> Vector3<f64> {
        Vector3::from(self.weight)
    }

    /// The force `F(q) = −∇V` into `out` (as
    /// [`Separable::force`](integrator_core::Separable::force)), and the
    /// force scale at `q`: the size of the terms whose round-off `F` carries.
    /// That is the largest of a particle's weight, a spring's tension
    /// `(k/L)|ℓ − L|`, a collider's push, and `κ·‖q‖_∞` with `κ` the largest
    /// spring constant `k/L`: positions are known to an ulp of `‖q‖_∞`, and
    /// an ulp of position moves a force by `κ` times it, so no `F` computed
    /// in `f64` is more accurate than a few `ε·κ·‖q‖_∞`. A gradient measured
    /// against this scale can be asked to vanish down to a small multiple of
    /// `ε` whatever the net forces are (a hanging sheet's net forces are tiny
    /// beside the tensions that balance them).
    pub fn force_and_scale(&self, q: &[f64], out: &mut [f64]) -> f64 {
        let n = self.free_count();
        let q3 = &q.as_chunks::<3>().0[..n];
        let f3 = &mut out.as_chunks_mut::<3>().0[..n];
        f3.fill(self.weight);
        let mut scale = Vector3::from(self.weight).norm();
        let mut kappa: f64 = 0.0;
        for s in &self.ff {
            let (a, b) = (s.a as usize, s.b as usize);
            let d = Vector3::from(q3[b]) - Vector3::from(q3[a]);
            let l = d.norm();
            let fd = d * (s.kl - s.kl * s.rest / l);
            kappa = kappa.max(s.kl);
            scale = scale.max((s.kl * (l - s.rest)).abs());
            f3[a] = (Vector3::from(f3[a]) + fd).into();
            f3[b] = (Vector3::from(f3[b]) - fd).into();
        }
        for s in &self.fp {
            let a = s.a as usize;
            let d = Vector3::from(s.pin) - Vector3::from(q3[a]);
            let l = d.norm();
            kappa = kappa.max(s.kl);
            scale = scale.max((s.kl * (l - s.rest)).abs());
            f3[a] = (Vector3::from(f3[a]) + d * (s.kl - s.kl * s.rest / l)).into();
        }
        for c in &self.colliders {
            for (f, x) in f3.iter_mut().zip(q3) {
                let push = c.force(&Vector3::from(*x));
                scale = scale.max(push.norm());
                *f = (Vector3::from(*f) + push).into();
            }
        }
        let q_max = q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        scale.max(kappa * q_max)
    }
}

impl integrator_core::Separable for ClothModel {
    fn dof(&self) -> usize {
        3 * self.free_ids.len()
    }

    fn kinetic(&self, p: &[f64]) -> f64 {
        0.5 * self.inv_mass * p.iter().map(|x| x * x).sum::<f64>()
    }

    fn potential(&self, q: &[f64]) -> f64 {
        let (springs, gravity, colliders) = self.potential_terms(q);
        springs + gravity + colliders
    }

    fn velocity(&self, p: &[f64], out: &mut [f64]) {
        let n = self.dof();
        let inv = self.inv_mass;
        for (o, x) in out[..n].iter_mut().zip(&p[..n]) {
            *o = inv * x;
        }
    }

    fn force(&self, q: &[f64], out: &mut [f64]) {
        let n = self.free_count();
        let q3 = &q.as_chunks::<3>().0[..n];
        let f3 = &mut out.as_chunks_mut::<3>().0[..n];
        f3.fill(self.weight);
        for s in &self.ff {
            let (a, b) = (s.a as usize, s.b as usize);
            let d = Vector3::from(q3[b]) - Vector3::from(q3[a]);
            let l = d.norm();
            let fd = d * (s.kl - s.kl * s.rest / l);
            f3[a] = (Vector3::from(f3[a]) + fd).into();
            f3[b] = (Vector3::from(f3[b]) - fd).into();
        }
        for s in &self.fp {
            let a = s.a as usize;
            let d = Vector3::from(s.pin) - Vector3::from(q3[a]);
            let l = d.norm();
            f3[a] = (Vector3::from(f3[a]) + d * (s.kl - s.kl * s.rest / l)).into();
        }
        for c in &self.colliders {
            for (f, x) in f3.iter_mut().zip(q3) {
                *f = (Vector3::from(*f) + c.force(&Vector3::from(*x))).into();
            }
        }
    }
}
