//! The mass-spring cloth as a separable Hamiltonian `H = ½ pᵀM⁻¹p + V(q)`.
//!
//! The state holds only the free particles: pinned particles are removed
//! from the unknowns and enter the forces as constant positions. Springs are
//! precomputed into two flat lists, free–free and free–pinned, ordered so
//! that consecutive springs rarely share a particle (no store-to-load
//! dependency between them), which the Jacobians, the energy and the
//! implicit methods walk; the explicit force runs as stencil loops over the
//! grid instead (`stencil.rs`). No force evaluation allocates.

//!
//! By stage: `build.rs` makes the model of a scene (particles and pins,
//! springs, colliders, the check of the initial state), `springs.rs` lays out
//! the grid's springs, `colliders.rs` holds the penalty, `forces.rs` the
//! energy and the forces, `stencil.rs` the explicit force kernel (`bands.rs`: by bands of rows, for
//! the banded stepper), `jacobian.rs` the sparse force Jacobian;
//! `avf.rs`, `discrete_gradient.rs` and `stability.rs` serve the methods that
//! need more than the force.

use std::sync::OnceLock;

use nalgebra::Vector3;

mod avf;
mod bands;
mod bending;
mod build;
mod colliders;
pub(crate) mod constraints;
mod discrete_gradient;
mod forces;
mod jacobian;
mod springs;
mod stability;
mod stencil;

pub use crate::scene::DEFAULT_BENDING;
pub use bending::{BENDING_POWER_ITERATIONS, BendingRate};
use colliders::Penalty;
pub use constraints::CONSTRAINT_TOLERANCE;
use jacobian::{JacobianLayout, spring_block};
pub(crate) use springs::{PinSpring, Spring};
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
    /// The isometric bending energy of an inextensible sheet
    /// (`material.bending`; 0 without it), J.
    pub bending: f64,
}

impl Energy {
    pub fn potential(&self) -> f64 {
        self.springs + self.gravity + self.colliders + self.bending
    }
    pub fn total(&self) -> f64 {
        self.kinetic + self.potential()
    }
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
    /// The same springs as stencil loops over the grid: the explicit
    /// force kernel ([`stencil`]).
    stencil: stencil::Stencil,
    family_counts: [usize; 3],
    colliders: Vec<Penalty>,
    /// Built on first use ([`ClothModel::jac`]).
    jac: OnceLock<JacobianLayout>,
    /// The warp and weft length constraints of an inextensible scene
    /// (`None`: the spring model).
    constraints: Option<std::sync::Arc<constraints::EdgeConstraints>>,
    /// The isometric bending energy (`material.bending > 0`; only on an
    /// inextensible sheet, whose motion is the isometric one it assumes).
    bending: Option<bending::Bending>,
}

const PINNED: u32 = u32::MAX;

impl ClothModel {
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
    /// Springs with a free end: those that pull on a particle of the state.
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
            bending: self.bending_energy(q),
        }
    }

    #[inline]
    fn chunks<'a>(&self, x: &'a [f64]) -> &'a [[f64; 3]] {
        &x.as_chunks::<3>().0[..self.free_count()]
    }

    /// Whether the scene has colliders.
    pub fn has_colliders(&self) -> bool {
        !self.colliders.is_empty()
    }

    /// The weight `m·g` of one particle (N).
    pub fn weight(&self) -> Vector3<f64> {
        Vector3::from(self.weight)
    }
}
