//! Building the model of a scene, step by step: the particles and pins, the
//! springs, the colliders, then the check of the initial state.

use std::sync::{Arc, OnceLock};

use nalgebra::Vector3;

use super::bending::Bending;
use super::colliders::penalties;
use super::constraints::{self, Gram};
use super::springs::{directions, grid_springs};
use super::stencil::Stencil;
use super::{ClothModel, Family, PINNED, PinSpring, Spring};
use crate::scene::{Scene, SceneError};

/// The springs of a scene's grid, sorted into the lists the model keeps.
struct GridSprings {
    ff: Vec<Spring>,
    fp: Vec<PinSpring>,
    /// The largest `|ℓ − L|/L` among springs between two pinned particles.
    pp_strain: f64,
    family_counts: [usize; 3],
    /// The first spring whose ends start at the same point (rounding).
    collapsed: Option<(usize, usize)>,
}

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
        let start = start_positions(scene, dx, dy);
        let (free_index, free_ids) = free_lists(scene);
        let mass = scene.material.density * c.width * c.height / n as f64;
        let springs = sort_springs(scene, dx, dy, &start, &free_index);
        if let Some((a, b)) = springs.collapsed {
            return Err(SceneError::Field {
                file: scene.name.clone(),
                field: "cloth.origin".to_string(),
                message: format!(
                    "particles {:?} and {:?} start at the same point {:?}: the grid spacing is lost to rounding there",
                    (a % nx, a / nx),
                    (b % nx, b / nx),
                    start[a].as_slice()
                ),
            });
        }
        let stencil = Stencil::new(nx, ny, &directions(dx, dy, scene.spring_families()), |f| {
            stiffness(scene, f)
        });
        let constraints = if scene.material.inextensible {
            Some(Arc::new(constraints::build(
                scene,
                dx,
                dy,
                &start,
                &free_index,
            )?))
        } else {
            None
        };
        let bending = if scene.material.inextensible {
            Bending::new(nx, ny, dx, dy, scene.material.bending, &start, &free_index)
        } else {
            None
        };
        let colliders = penalties(&scene.colliders, mass);
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
            ff: springs.ff,
            fp: springs.fp,
            pp_strain: springs.pp_strain,
            stencil,
            family_counts: springs.family_counts,
            colliders,
            jac: OnceLock::new(),
            constraints,
            bending,
        };
        model.check_initial_state(scene)?;
        model.check_constraints_independent(scene)?;
        Ok(model)
    }

    /// The constraints' Gram matrix `G·Gᵀ` must be positive definite at the
    /// start, or no step can solve for the multipliers: it is singular when
    /// a straight line of edges is held taut between two pins (their
    /// gradients are parallel), a sheet that would need infinite tension.
    fn check_constraints_independent(&self, scene: &Scene) -> Result<(), SceneError> {
        let Some(c) = &self.constraints else {
            return Ok(());
        };
        let z = self.initial_state();
        let mut d = vec![[0.0; 3]; c.len()];
        c.edge_vectors(&z[..3 * self.free_count()], &mut d, false);
        Gram::new(c.clone(), false)
            .factorize(&d)
            .map_err(|_| SceneError::Field {
                file: scene.name.clone(),
                field: "pins".to_string(),
                message: "the length constraints are dependent at the start (their Gram matrix G·Gᵀ is not positive definite): a straight line of inextensible edges is held taut between two pins, which would need infinite tension".to_string(),
            })
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
        let bending = self.bending_energy(q);
        if !bending.is_finite() {
            return Err(field_err(
                "material.bending".into(),
                format!(
                    "the bending energy at the initial positions is {bending:e} J: not finite (the rigidity over the grid's cell area overflows)"
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
}

/// The initial positions of all particles, by particle id `j·nx + i`: the
/// grid of spacing `dx`, `dy` on the cloth's plane (its rows arcs where the
/// scene sags, [`ClothSpec::sag`](crate::scene::ClothSpec::sag)), scaled
/// by the prestretch, placed at the origin.
fn start_positions(scene: &Scene, dx: f64, dy: f64) -> Vec<Vector3<f64>> {
    let c = &scene.cloth;
    let (nx, ny) = (c.nx, c.ny);
    let n = nx * ny;
    let (u, v) = c.plane.axes();
    let (u, v) = (Vector3::from(u), Vector3::from(v));
    let bow = u.cross(&v);
    let origin = Vector3::from(c.origin);
    // Along `u` and along the bow, particle `i` of every row.
    let row: Vec<(f64, f64)> = if c.sag > 0.0 {
        let half = crate::scene::arc_half_angle(nx, dx, c.sag);
        let r = crate::scene::arc_radius(nx, dx, half);
        let step = 2.0 * half / (nx - 1) as f64;
        (0..nx)
            .map(|i| {
                // The angles from the first particle and to the last (φ =
                // −Θ + from): R(sin φ + sin Θ) and R(cos φ − cos Θ) as
                // products, so that both ends sit at a bow of exactly 0.
                let (from, to) = (i as f64 * step, (nx - 1 - i) as f64 * step);
                let along = 2.0 * r * (from / 2.0).sin() * (half - from / 2.0).cos();
                let down = 2.0 * r * (from / 2.0).sin() * (to / 2.0).sin();
                (along, down)
            })
            .collect()
    } else {
        (0..nx).map(|i| (i as f64 * dx, 0.0)).collect()
    };
    (0..n)
        .map(|id| {
            let (i, j) = (id % nx, id / nx);
            let (along, down) = row[i];
            origin + (u * along + bow * down + v * (j as f64 * dy)) * c.prestretch
        })
        .collect()
}

/// Particle id → index into the free list (`PINNED` for a pin), and free
/// index → particle id.
fn free_lists(scene: &Scene) -> (Vec<u32>, Vec<u32>) {
    let nx = scene.cloth.nx;
    let n = nx * scene.cloth.ny;
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
    (free_index, free_ids)
}

/// The stiffness `k` of a spring family (N per unit strain; 0 where the
/// scene has none of that family).
fn stiffness(scene: &Scene, family: Family) -> f64 {
    let m = &scene.material;
    match family {
        Family::Stretch => m.stretch,
        Family::Shear => m.shear,
        Family::Bend => m.bend,
    }
    .unwrap_or(0.0)
}

/// The grid's springs into free–free and free–pinned lists (springs between
/// two pins only count towards `pp_strain` and the family counts).
fn sort_springs(
    scene: &Scene,
    dx: f64,
    dy: f64,
    start: &[Vector3<f64>],
    free_index: &[u32],
) -> GridSprings {
    let (nx, ny) = (scene.cloth.nx, scene.cloth.ny);
    let mut ff = Vec::with_capacity(scene.spring_count());
    let mut fp = Vec::new();
    let mut pp_strain: f64 = 0.0;
    let mut family_counts = [0usize; 3];
    let mut collapsed = None;
    grid_springs(
        nx,
        ny,
        dx,
        dy,
        scene.spring_families(),
        |a, b, family, rest| {
            let k = stiffness(scene, family);
            family_counts[family as usize] += 1;
            let kl = k / rest;
            let apart = (start[b] - start[a]).norm();
            if collapsed.is_none() && (apart.is_nan() || apart <= 0.0) {
                collapsed = Some((a, b));
            }
            match (free_index[a], free_index[b]) {
                (PINNED, PINNED) => {
                    pp_strain = pp_strain.max(((start[b] - start[a]).norm() - rest).abs() / rest);
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
    GridSprings {
        ff,
        fp,
        pp_strain,
        family_counts,
        collapsed,
    }
}
