//! Checking a scene: each field's range, then the quantities the model
//! derives from them (`check_scales`), so that a scene built in code gets the
//! same errors as one read from a file.

use std::collections::BTreeSet;

use super::read::Reader;
use super::{Collider, Scene, SceneError, grid_too_large, run_length_problem};
use crate::method::Method;

impl Scene {
    /// Check the invariants that loading guarantees, for a scene built or
    /// edited in code (errors name the scene by its `name`).
    pub fn validate(&self) -> Result<(), SceneError> {
        let r = Reader { file: &self.name };
        self.check_cloth(&r)?;
        self.check_material(&r)?;
        self.check_pins(&r)?;
        finite3(&r, &self.gravity, "gravity")?;
        self.check_colliders(&r)?;
        self.check_simulation(&r)?;
        self.check_has_springs(&r)?;
        self.check_scales()
    }

    /// The cloth's sizes, prestretch, origin and grid.
    fn check_cloth(&self, r: &Reader) -> Result<(), SceneError> {
        let c = &self.cloth;
        positive(r, c.width, "cloth.width")?;
        positive(r, c.height, "cloth.height")?;
        positive(r, c.prestretch, "cloth.prestretch")?;
        finite3(r, &c.origin, "cloth.origin")?;
        for (n, field) in [(c.nx, "cloth.nx"), (c.ny, "cloth.ny")] {
            if n < 2 {
                return Err(r.err(field, format!("must be at least 2 (got {n})")));
            }
        }
        if let Some((which, message)) = grid_too_large(c.nx, c.ny) {
            return Err(r.err(&format!("cloth.{which}"), message));
        }
        non_negative(r, c.sag, "cloth.sag")?;
        let most = super::max_sag(c.nx, c.width / (c.nx - 1) as f64);
        if c.sag > most {
            return Err(r.err(
                "cloth.sag",
                format!(
                    "{} m is more than a row of width {} m can sag: at most {most} m, a half circle",
                    c.sag, c.width
                ),
            ));
        }
        Ok(())
    }

    /// The density and each spring family's stiffness.
    fn check_material(&self, r: &Reader) -> Result<(), SceneError> {
        let m = &self.material;
        positive(r, m.density, "material.density")?;
        for (k, field) in [
            (m.stretch, "material.stretch"),
            (m.shear, "material.shear"),
            (m.bend, "material.bend"),
        ] {
            if let Some(k) = k {
                non_negative(r, k, field)?;
            }
        }
        if m.inextensible && m.stretch.is_some() {
            return Err(r.err(
                "material.stretch",
                "an inextensible material has no stretch springs: give a stiffness or \"inextensible\", not both",
            ));
        }
        non_negative(r, m.bending, "material.bending")?;
        if m.bending > 0.0 && !m.inextensible {
            return Err(r.err(
                "material.bending",
                "the isometric bending energy is for an inextensible sheet (material.stretch = \"inextensible\"), whose motion is the isometric one it assumes; a spring cloth bends with `bend` springs",
            ));
        }
        Ok(())
    }

    /// Pins inside the grid, and not every particle pinned.
    fn check_pins(&self, r: &Reader) -> Result<(), SceneError> {
        let c = &self.cloth;
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
        Ok(())
    }

    /// Each collider's own fields (their products: `check_collider_scales`).
    fn check_colliders(&self, r: &Reader) -> Result<(), SceneError> {
        for (k, col) in self.colliders.iter().enumerate() {
            let f = |key: &str| format!("colliders[{k}].{key}");
            match col {
                Collider::Plane {
                    point,
                    normal,
                    stiffness,
                    skin,
                } => {
                    finite3(r, point, &f("point"))?;
                    finite3(r, normal, &f("normal"))?;
                    let len = normal.iter().map(|x| x * x).sum::<f64>().sqrt();
                    if (len - 1.0).abs() > 1e-9 {
                        return Err(r.err(
                            &f("normal"),
                            format!("must be a unit vector (length {len})"),
                        ));
                    }
                    positive(r, *stiffness, &f("stiffness"))?;
                    non_negative(r, *skin, &f("skin"))?;
                }
                Collider::Sphere {
                    center,
                    radius,
                    stiffness,
                    skin,
                } => {
                    finite3(r, center, &f("center"))?;
                    positive(r, *radius, &f("radius"))?;
                    positive(r, *stiffness, &f("stiffness"))?;
                    non_negative(r, *skin, &f("skin"))?;
                }
            }
        }
        Ok(())
    }

    /// The frame rate, the run's length and the method's name.
    fn check_simulation(&self, r: &Reader) -> Result<(), SceneError> {
        let s = &self.simulation;
        positive(r, s.frame_rate, "simulation.frame_rate")?;
        if let Some((what, message)) = run_length_problem(s.frames, s.substeps, s.frame_rate) {
            return Err(r.err(&format!("simulation.{what}"), message));
        }
        let method = Method::parse(&s.method).map_err(|e| r.err("simulation.method", e))?;
        if let Some(why) = method_mismatch(&method, self.material.inextensible) {
            return Err(r.err("simulation.method", why));
        }
        Ok(())
    }

    /// At least one spring on the grid: something holds the cloth together.
    fn check_has_springs(&self, r: &Reader) -> Result<(), SceneError> {
        let c = &self.cloth;
        // Inextensible: the warp and weft constraints hold it (a grid of
        // at least 2 × 2 has them).
        if self.spring_count() == 0 && !self.material.inextensible {
            return Err(r.err(
                "material",
                format!(
                    "a {} × {} grid has no spring of the families given (stretch, shear, bend): nothing holds the cloth together",
                    c.nx, c.ny
                ),
            ));
        }
        Ok(())
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
        let (dx, dy) = (grid_spacing(c.width, c.nx), grid_spacing(c.height, c.ny));
        let origin = c.origin.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        self.check_spacing(&r, dx, dy, origin)?;
        let mass = self.check_mass(&r)?;
        let n = (c.nx * c.ny) as f64;
        self.check_springs(&r, dx, dy, mass, n)?;
        self.check_fall(&r, mass, n, origin)?;
        self.check_collider_scales(&r, mass)
    }

    /// The grid spacings `dx`, `dy` and their doubles (the bend springs'
    /// rest lengths), then the initial grid: spacing and extent scaled by
    /// the prestretch, placed at the origin (`origin`: its largest
    /// coordinate in magnitude).
    fn check_spacing(&self, r: &Reader, dx: f64, dy: f64, origin: f64) -> Result<(), SceneError> {
        let c = &self.cloth;
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
        Ok(())
    }

    /// The area and the particle mass `density·width·height/(nx·ny)` and its
    /// inverse; returns the mass.
    fn check_mass(&self, r: &Reader) -> Result<f64, SceneError> {
        let c = &self.cloth;
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
        Ok(mass)
    }

    /// Per spring family and rest length: `k/L`, `k·L`, the rate
    /// `k/(L·m)` and the energy the prestretch stores (`n` particles of
    /// mass `mass`).
    fn check_springs(
        &self,
        r: &Reader,
        dx: f64,
        dy: f64,
        mass: f64,
        n: f64,
    ) -> Result<(), SceneError> {
        let c = &self.cloth;
        let m = &self.material;
        let diag = dx.hypot(dy);
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
        Ok(())
    }

    /// The weight `m·g` and the potential energy `M·|g|·ℓ` of the cloth
    /// (`n` particles of mass `mass`) falling by its size and origin.
    fn check_fall(&self, r: &Reader, mass: f64, n: f64, origin: f64) -> Result<(), SceneError> {
        let c = &self.cloth;
        let m = &self.material;
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
        Ok(())
    }

    /// Each collider's extent (squared distances stay finite) and its
    /// penalty scale `stiffness·m` on particles of mass `mass`.
    fn check_collider_scales(&self, r: &Reader, mass: f64) -> Result<(), SceneError> {
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

fn finite3(r: &Reader, v: &[f64; 3], field: &str) -> Result<(), SceneError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(r.err(field, format!("must be finite (got {v:?})")))
    }
}

fn positive(r: &Reader, x: f64, field: &str) -> Result<(), SceneError> {
    if x > 0.0 && x.is_finite() {
        Ok(())
    } else {
        Err(r.err(field, format!("must be positive and finite (got {x})")))
    }
}

fn non_negative(r: &Reader, x: f64, field: &str) -> Result<(), SceneError> {
    if x >= 0.0 && x.is_finite() {
        Ok(())
    } else {
        Err(r.err(field, format!("must be non-negative and finite (got {x})")))
    }
}

/// Not a positive normal number (zero, subnormal, infinite, NaN or negative).
fn bad(x: f64) -> bool {
    !(x.is_normal() && x > 0.0)
}

/// Lengths enter the model squared (a distance is the square root of a sum
/// of squares, a spring's energy has (ℓ − L)²): a spacing whose square
/// underflows (below about 1e-154 m) would put neighbours "at the same
/// point", an extent whose square overflows would make every distance
/// infinite.
fn square_bad(x: f64) -> bool {
    bad(x * x)
}

/// The spacing of `n` grid points over `len`.
fn grid_spacing(len: f64, n: usize) -> f64 {
    len / (n - 1) as f64
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

/// Why `method` cannot step a cloth whose warp and weft are (`inextensible`)
/// or are not length constraints: only `rattle` steps the constrained model,
/// and it steps nothing else. `None` when it can.
pub fn method_mismatch(method: &Method, inextensible: bool) -> Option<String> {
    let constrained = method.mechanism() == crate::method::Mechanism::Constrained;
    match (inextensible, constrained) {
        (true, false) => Some(format!(
            "{} steps the spring model; an inextensible material (material.stretch = \"inextensible\") is stepped by {}",
            method.id(),
            crate::method::RATTLE
        )),
        (false, true) => Some(format!(
            "{} steps an inextensible material (material.stretch = \"inextensible\"); this scene's warp and weft are springs",
            method.id()
        )),
        _ => None,
    }
}
