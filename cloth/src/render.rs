//! A small software rasteriser for cloth frames: a fixed oblique
//! perspective camera fitted to what is drawn, z-buffered triangles with
//! smooth two-sided Lambert shading (a directional light plus a headlight),
//! the quads' edges drawn faintly where they are large enough to see,
//! colliders ray-cast (spheres shaded, planes as a grid floor; a floor grid
//! below the cloth when the scene has no plane), 2× supersampled.
//!
//! It returns an [`Image`] (RGB bytes) and says, as data, when the picture
//! had to be simplified; encoding it (PNG, a caption) is the caller's, so
//! the crate needs no image or plotting library.
//!
//! ```
//! use cloth::render::{Camera, Stage, HEIGHT, WIDTH, rasterise};
//! use cloth::Vec3;
//!
//! // One square of cloth, two triangles, seen from the default camera.
//! let positions = [
//!     Vec3::new(0.0, 0.0, 0.0),
//!     Vec3::new(1.0, 0.0, 0.0),
//!     Vec3::new(0.0, 0.0, 1.0),
//!     Vec3::new(1.0, 0.0, 1.0),
//! ];
//! let stage = Stage { colliders: vec![], triangles: vec![[0, 1, 3], [0, 3, 2]], nx: 2 };
//! let camera = Camera::fit(&positions, &stage.colliders);
//! let picture = rasterise(&stage, &camera, &positions);
//! assert_eq!(picture.image.rgb.len(), (WIDTH * HEIGHT * 3) as usize);
//! assert_eq!(picture.simplified, None);
//! ```

use crate::{Collider, Vec3};

/// Image size (pixels).
pub const WIDTH: u32 = 640;
pub const HEIGHT: u32 = 480;
/// Supersampling factor per axis.
const SS: usize = 2;
/// Vertical field of view (radians).
const FOV: f64 = 0.6;

/// What a picture shows besides the cloth.
pub struct Stage {
    pub colliders: Vec<Collider>,
    /// The cloth's triangles (particle ids, counter-clockwise seen from the
    /// front, `u × v`).
    pub triangles: Vec<[usize; 3]>,
    /// Particles per grid row: an edge between particles that share a row
    /// or a column is a quad edge (drawn), any other a cell's diagonal.
    pub nx: usize,
}

/// The finest mesh a picture draws: at most this many cells along a side.
/// A 640 × 480 picture cannot show more; a finer grid is drawn through
/// every k-th particle of each row and column (always including the last),
/// so drawing costs the same on a 2048 × 2048 cloth as on 512 × 512, and a
/// degenerate 100 000 × 2 grid is 512 × 1 cells, not 200 000 slivers.
pub const MAX_CELLS_PER_SIDE: usize = 512;

/// The most pixel tests the triangles of one picture may cost: 40 per
/// (supersampled) pixel. A cloth folded on itself many times, or blown up
/// into triangles that each cover the screen, would otherwise cost
/// triangles × pixels; past the budget the remaining triangles are left
/// out and the picture says so (see [`rasterise`]).
pub const PIXEL_BUDGET_PER_PIXEL: usize = 40;

impl Stage {
    /// The stage of an `nx × ny` grid: its triangles (as
    /// `ClothModel::triangles` numbers them) through every k-th particle
    /// along each side when the grid has more than [`MAX_CELLS_PER_SIDE`]
    /// cells there.
    pub fn for_grid(colliders: Vec<Collider>, triangles: &[[usize; 3]], nx: usize) -> Stage {
        let ny = if nx > 1 {
            triangles.len() / (2 * (nx - 1)) + 1
        } else {
            1
        };
        if nx <= MAX_CELLS_PER_SIDE + 1 && ny <= MAX_CELLS_PER_SIDE + 1 {
            return Stage {
                colliders,
                triangles: triangles.to_vec(),
                nx,
            };
        }
        let samples = |n: usize| -> Vec<usize> {
            let stride = (n - 1).div_ceil(MAX_CELLS_PER_SIDE).max(1);
            let mut v: Vec<usize> = (0..n).step_by(stride).collect();
            if v.last() != Some(&(n - 1)) {
                v.push(n - 1);
            }
            v
        };
        let (is, js) = (samples(nx), samples(ny));
        let mut out = Vec::with_capacity(2 * (is.len() - 1) * (js.len() - 1));
        for jj in js.windows(2) {
            for ii in is.windows(2) {
                let a = jj[0] * nx + ii[0];
                let b = jj[0] * nx + ii[1];
                let c = jj[1] * nx + ii[0];
                let d = jj[1] * nx + ii[1];
                out.push([a, b, d]);
                out.push([a, d, c]);
            }
        }
        Stage {
            colliders,
            triangles: out,
            nx,
        }
    }
}

/// A fixed camera, the same for every frame of a run.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    eye: Vec3,
    right: Vec3,
    up: Vec3,
    forward: Vec3,
    /// Pixels per unit of `x/z` at the supersampled resolution.
    focal: f64,
    /// The floor drawn when the scene has no plane collider: `y = floor`.
    floor: f64,
    /// Grid spacing of floors (m).
    spacing: f64,
    /// Size of the scene (m), for fading the floor with distance.
    radius: f64,
}

impl Camera {
    /// A camera looking down at 25° from the front-right (azimuth 35°) at
    /// the centre of the bounding box of `points` (all frames to be drawn)
    /// and of the colliders' extents, far enough for the bounding sphere to
    /// fit.
    pub fn fit(points: &[Vec3], colliders: &[Collider]) -> Camera {
        let finite = |x: &Vec3| x.iter().all(|v| v.is_finite());
        let bounds = |pts: &mut dyn Iterator<Item = Vec3>| {
            pts.filter(finite).fold(
                (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY)),
                |(lo, hi), x| (lo.inf(&x), hi.sup(&x)),
            )
        };
        let (cloth_lo, _) = bounds(&mut points.iter().copied());
        let extents = colliders.iter().filter_map(|c| match c {
            Collider::Sphere { center, radius, .. } => Some([
                Vec3::from(*center) - Vec3::repeat(*radius),
                Vec3::from(*center) + Vec3::repeat(*radius),
            ]),
            _ => None,
        });
        let (mut lo, mut hi) = bounds(&mut points.iter().copied().chain(extents.flatten()));
        if !(finite(&lo) && finite(&hi)) {
            lo = Vec3::zeros();
            hi = Vec3::repeat(1.0);
        }
        let center = (lo + hi) / 2.0;
        let radius = ((hi - lo).norm() / 2.0).max(1e-3);
        let (az, el): (f64, f64) = (35f64.to_radians(), 25f64.to_radians());
        // From the target towards the eye: in front (+z), to the right (+x), above.
        let back = Vec3::new(el.cos() * az.sin(), el.sin(), el.cos() * az.cos());
        let forward = -back;
        let right = forward.cross(&Vec3::y()).normalize();
        let up = right.cross(&forward);
        // Back off until every corner of the box is inside the picture, with
        // a margin: a corner at offset o needs |o·right| ≤ T·(d + o·forward).
        let tv = (FOV / 2.0).tan() * 0.9;
        let th = tv * WIDTH as f64 / HEIGHT as f64;
        let mut dist: f64 = 0.0;
        for k in 0..8 {
            let corner = Vec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            let o = corner - center;
            let depth = o.dot(&forward);
            dist = dist
                .max(o.dot(&right).abs() / th - depth)
                .max(o.dot(&up).abs() / tv - depth)
                .max(0.1 * radius - depth);
        }
        let eye = center + back * dist;
        let focal = (HEIGHT as usize * SS) as f64 / 2.0 / (FOV / 2.0).tan();
        // Below the cloth and the spheres.
        let floor_y = if cloth_lo.y.is_finite() {
            cloth_lo.y.min(lo.y)
        } else {
            lo.y
        };
        Camera {
            eye,
            right,
            up,
            forward,
            focal,
            floor: floor_y - 0.15 * radius,
            spacing: nice_spacing(radius),
            radius,
        }
    }
}

/// A round grid spacing, about a tenth of the scene's radius.
fn nice_spacing(radius: f64) -> f64 {
    let raw = radius / 5.0;
    let p = 10f64.powf(raw.log10().floor());
    let m = raw / p;
    p * if m < 2.0 {
        1.0
    } else if m < 5.0 {
        2.0
    } else {
        5.0
    }
}

#[derive(Clone, Copy)]
struct Rgb([f64; 3]);

impl Rgb {
    fn scale(self, s: f64) -> Rgb {
        Rgb(self.0.map(|c| c * s))
    }
    fn mix(self, o: Rgb, t: f64) -> Rgb {
        Rgb([0, 1, 2].map(|k| self.0[k] * (1.0 - t) + o.0[k] * t))
    }
}

const FRONT: Rgb = Rgb([0.80, 0.30, 0.22]);
const BACK: Rgb = Rgb([0.93, 0.74, 0.32]);
const SPHERE: Rgb = Rgb([0.45, 0.55, 0.70]);
const FLOOR: Rgb = Rgb([0.86, 0.86, 0.84]);
const LINE: Rgb = Rgb([0.55, 0.55, 0.55]);
const SKY_TOP: Rgb = Rgb([0.80, 0.86, 0.93]);
const SKY_BOTTOM: Rgb = Rgb([0.97, 0.97, 0.98]);

struct Canvas {
    w: usize,
    h: usize,
    color: Vec<Rgb>,
    depth: Vec<f64>,
}

/// A plane `n·x = d` drawn as a gridded floor.
struct Floor {
    normal: Vec3,
    d: f64,
    /// Tangent axes for the grid.
    a: Vec3,
    b: Vec3,
}

impl Floor {
    fn new(normal: Vec3, point: Vec3) -> Floor {
        let n = normal.normalize();
        let helper = if n.x.abs() < 0.9 {
            Vec3::x()
        } else {
            Vec3::z()
        };
        let a = n.cross(&helper).normalize();
        let b = n.cross(&a);
        Floor {
            normal: n,
            d: n.dot(&point),
            a,
            b,
        }
    }
}

/// An RGB picture, rows top to bottom, three bytes a pixel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    /// `width · height · 3` bytes, gamma 2.2.
    pub rgb: Vec<u8>,
}

/// Why a picture is not the whole cloth: triangles were left out when its
/// pixel budget ([`PIXEL_BUDGET_PER_PIXEL`]) ran out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Simplified {
    /// Triangles not drawn.
    pub not_drawn: usize,
    /// Triangles of the stage.
    pub triangles: usize,
    /// The budget that ran out, in pixel tests per pixel.
    pub budget_per_pixel: usize,
}

/// The sentence a caption or a note shows.
impl std::fmt::Display for Simplified {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} of {} triangles not drawn: the picture's budget of {} pixel tests per pixel ran out",
            self.not_drawn, self.triangles, self.budget_per_pixel
        )
    }
}

/// A rasterised frame: the image, and whether it had to be simplified.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Picture {
    pub image: Image,
    pub simplified: Option<Simplified>,
}

impl Picture {
    /// `caption` with, in parentheses, what a simplified picture left out:
    /// the line to print on it.
    pub fn caption(&self, caption: &str) -> String {
        match &self.simplified {
            Some(s) => format!("{caption} ({s})"),
            None => caption.to_string(),
        }
    }
}

/// The cloth at `positions` (all particles, by id) on `stage`, seen by
/// `camera`: a [`WIDTH`] × [`HEIGHT`] picture. Its cost is bounded by the
/// image, not by the mesh: the sky and colliders once per pixel, the
/// triangles at most [`PIXEL_BUDGET_PER_PIXEL`] pixel tests per pixel in all
/// (plus a constant per triangle); past that the remaining triangles are
/// left out and [`Picture::simplified`] says how many.
pub fn rasterise(stage: &Stage, camera: &Camera, positions: &[Vec3]) -> Picture {
    let (w, h) = (WIDTH as usize * SS, HEIGHT as usize * SS);
    let mut canvas = Canvas {
        w,
        h,
        color: vec![Rgb([0.0; 3]); w * h],
        depth: vec![f64::INFINITY; w * h],
    };
    let light = (camera.up * 1.0 - camera.right * 0.5 - camera.forward * 0.6).normalize();
    let mut floors: Vec<Floor> = stage
        .colliders
        .iter()
        .filter_map(|c| match c {
            Collider::Plane { point, normal, .. } => {
                Some(Floor::new(Vec3::from(*normal), Vec3::from(*point)))
            }
            _ => None,
        })
        .collect();
    if floors.is_empty() {
        floors.push(Floor::new(Vec3::y(), Vec3::new(0.0, camera.floor, 0.0)));
    }
    background(&mut canvas, camera, &floors, &stage.colliders, light);
    let skipped = cloth(
        &mut canvas,
        camera,
        positions,
        &stage.triangles,
        stage.nx.max(1),
        light,
        true,
    );
    Picture {
        image: Image {
            width: WIDTH,
            height: HEIGHT,
            rgb: downsample(&canvas),
        },
        simplified: (skipped > 0).then_some(Simplified {
            not_drawn: skipped,
            triangles: stage.triangles.len(),
            budget_per_pixel: PIXEL_BUDGET_PER_PIXEL,
        }),
    }
}

fn ray(camera: &Camera, px: f64, py: f64, w: usize, h: usize) -> Vec3 {
    let sx = (px - w as f64 / 2.0) / camera.focal;
    let sy = -(py - h as f64 / 2.0) / camera.focal;
    camera.forward + camera.right * sx + camera.up * sy
}

/// Sky, floors and spheres, ray-cast per pixel; depths are the distance
/// along the view axis, as for the triangles.
fn background(
    canvas: &mut Canvas,
    camera: &Camera,
    floors: &[Floor],
    colliders: &[Collider],
    light: Vec3,
) {
    let (w, h) = (canvas.w, canvas.h);
    for py in 0..h {
        let sky = SKY_TOP.mix(SKY_BOTTOM, py as f64 / h as f64);
        for px in 0..w {
            let d = ray(camera, px as f64 + 0.5, py as f64 + 0.5, w, h);
            let mut best = f64::INFINITY;
            let mut color = sky;
            for f in floors {
                let denom = f.normal.dot(&d);
                if denom.abs() < 1e-12 {
                    continue;
                }
                let t = (f.d - f.normal.dot(&camera.eye)) / denom;
                // Only the side of the plane the camera is on.
                if t > 0.0 && t < best && f.normal.dot(&camera.eye) > f.d {
                    best = t;
                    let x = camera.eye + d * t;
                    let (u, v) = (f.a.dot(&x) / camera.spacing, f.b.dot(&x) / camera.spacing);
                    // Grid lines about a pixel wide: scale by the footprint.
                    let fw = (t / camera.focal) / camera.spacing * 1.2;
                    let du = (u - u.round()).abs();
                    let dv = (v - v.round()).abs();
                    let line = (1.0 - (du.min(dv) / fw).min(1.0)).max(0.0);
                    let base = FLOOR.mix(LINE, 0.8 * line);
                    // Fade into the sky far away.
                    let fade = ((t - 3.0 * camera.radius) / (6.0 * camera.radius)).clamp(0.0, 1.0);
                    color = base.mix(sky, fade);
                }
            }
            for c in colliders {
                if let Collider::Sphere { center, radius, .. } = c {
                    let oc = camera.eye - Vec3::from(*center);
                    let a = d.dot(&d);
                    let b = 2.0 * oc.dot(&d);
                    let cc = oc.dot(&oc) - radius * radius;
                    let disc = b * b - 4.0 * a * cc;
                    if disc >= 0.0 {
                        let t = (-b - disc.sqrt()) / (2.0 * a);
                        if t > 0.0 && t < best {
                            best = t;
                            let x = camera.eye + d * t;
                            let n = (x - Vec3::from(*center)).normalize();
                            let view = -d.normalize();
                            color = SPHERE.scale(shade(n, light, view));
                        }
                    }
                }
            }
            let i = py * w + px;
            canvas.color[i] = color;
            canvas.depth[i] = best;
        }
    }
}

/// Ambient, a directional light and a headlight.
fn shade(n: Vec3, light: Vec3, view: Vec3) -> f64 {
    0.18 + 0.55 * n.dot(&light).max(0.0) + 0.32 * n.dot(&view).max(0.0)
}

/// Draw the triangles; returns how many were left out when the pixel
/// budget ran out. `narrow`: visit only each row's span of the triangle
/// (always, but for the test that checks it against the whole bounding box).
#[allow(clippy::too_many_arguments)]
fn cloth(
    canvas: &mut Canvas,
    camera: &Camera,
    positions: &[Vec3],
    triangles: &[[usize; 3]],
    nx: usize,
    light: Vec3,
    narrow: bool,
) -> usize {
    let (w, h) = (canvas.w, canvas.h);
    let mut budget = PIXEL_BUDGET_PER_PIXEL * w * h;
    let mesh = Mesh::new(camera, positions, triangles, nx, light, (w, h));
    for (done, t) in triangles.iter().enumerate() {
        if budget == 0 {
            return triangles.len() - done;
        }
        let Some(tri) = mesh.triangle(t, (w, h)) else {
            continue;
        };
        for py in tri.y0..=tri.y1 {
            let span = tri.span(py, narrow);
            budget = budget.saturating_sub(1);
            let Some((px0, px1)) = span else {
                continue;
            };
            budget = budget.saturating_sub(px1 + 1 - px0);
            for px in px0..=px1 {
                mesh.pixel(canvas, &tri, px, py);
            }
        }
    }
    0
}

/// The cloth as the camera sees it: smooth normals, camera coordinates and
/// screen positions of every particle.
struct Mesh<'a> {
    camera: &'a Camera,
    positions: &'a [Vec3],
    normals: Vec<Vec3>,
    cam: Vec<Vec3>,
    screen: Vec<(f64, f64)>,
    nx: usize,
    light: Vec3,
}

impl<'a> Mesh<'a> {
    fn new(
        camera: &'a Camera,
        positions: &'a [Vec3],
        triangles: &[[usize; 3]],
        nx: usize,
        light: Vec3,
        (w, h): (usize, usize),
    ) -> Self {
        let cam: Vec<Vec3> = positions
            .iter()
            .map(|p| {
                let r = p - camera.eye;
                Vec3::new(
                    r.dot(&camera.right),
                    r.dot(&camera.up),
                    r.dot(&camera.forward),
                )
            })
            .collect();
        let screen = cam
            .iter()
            .map(|c| {
                (
                    w as f64 / 2.0 + c.x / c.z * camera.focal,
                    h as f64 / 2.0 - c.y / c.z * camera.focal,
                )
            })
            .collect();
        Mesh {
            camera,
            positions,
            normals: smooth_normals(positions, triangles),
            cam,
            screen,
            nx,
            light,
        }
    }

    /// What drawing triangle `t` needs, or `None` when nothing of it is
    /// drawn (behind the near plane, not finite, degenerate, off screen).
    fn triangle(&self, t: &[usize; 3], (w, h): (usize, usize)) -> Option<Triangle> {
        let near = 1e-3 * self.camera.radius;
        let z = t.map(|k| self.cam[k].z);
        if z.iter().any(|&z| !(z > near && z.is_finite())) {
            return None;
        }
        let s = t.map(|k| self.screen[k]);
        let area = (s[1].0 - s[0].0) * (s[2].1 - s[0].1) - (s[2].0 - s[0].0) * (s[1].1 - s[0].1);
        if area.abs() < 1e-12 || !area.is_finite() {
            return None;
        }
        // Which side faces the camera: the face normal against the view ray.
        let [a, b, c] = t.map(|k| self.positions[k]);
        let face = (b - a).cross(&(c - a));
        let front = face.dot(&(self.camera.eye - a)) > 0.0;
        let (base, sign) = if front { (FRONT, 1.0) } else { (BACK, -1.0) };
        // Quad edges (not the cell's diagonal) drawn faintly when they are
        // at least 10 (supersampled) pixels long. Edge k is opposite vertex k.
        let len =
            |i: usize, j: usize| ((s[i].0 - s[j].0).powi(2) + (s[i].1 - s[j].1).powi(2)).sqrt();
        let nx = self.nx;
        let quad = |i: usize, j: usize| {
            let (p, q) = (t[i], t[j]);
            p % nx == q % nx || p / nx == q / nx
        };
        let edges = [(1, 2), (2, 0), (0, 1)].map(|(i, j)| (quad(i, j), len(i, j)));
        let lines = edges.iter().filter(|e| e.0).all(|e| e.1 >= 10.0);
        let xs = s.map(|p| p.0);
        let ys = s.map(|p| p.1);
        let least = |v: [f64; 3]| v.iter().copied().fold(f64::INFINITY, f64::min);
        let most = |v: [f64; 3]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let x0 = least(xs).floor().max(0.0) as usize;
        let x1 = most(xs).ceil().min(w as f64 - 1.0);
        let y0 = least(ys).floor().max(0.0) as usize;
        let y1 = most(ys).ceil().min(h as f64 - 1.0);
        if x1 < 0.0 || y1 < 0.0 {
            return None;
        }
        Some(Triangle {
            corners: [a, b, c],
            s,
            z,
            normals: t.map(|k| self.normals[k]),
            area,
            base,
            sign,
            edges,
            lines,
            x0,
            x1: x1 as usize,
            y0,
            y1: y1 as usize,
        })
    }

    /// Shade pixel `(px, py)` if the triangle covers it and is nearest.
    fn pixel(&self, canvas: &mut Canvas, tri: &Triangle, px: usize, py: usize) {
        let (s, z, n, area) = (&tri.s, &tri.z, &tri.normals, tri.area);
        let [a, b, c] = tri.corners;
        let (x, y) = (px as f64 + 0.5, py as f64 + 0.5);
        let edge = |i: usize, j: usize| {
            (s[j].0 - s[i].0) * (y - s[i].1) - (s[j].1 - s[i].1) * (x - s[i].0)
        };
        let l0 = edge(1, 2) / area;
        let l1 = edge(2, 0) / area;
        let l2 = edge(0, 1) / area;
        if l0 < 0.0 || l1 < 0.0 || l2 < 0.0 {
            return;
        }
        // Perspective-correct depth and normal.
        let inv = l0 / z[0] + l1 / z[1] + l2 / z[2];
        let depth = 1.0 / inv;
        let i = py * canvas.w + px;
        if depth >= canvas.depth[i] {
            return;
        }
        let mut normal =
            (n[0] * (l0 / z[0]) + n[1] * (l1 / z[1]) + n[2] * (l2 / z[2])) * depth * tri.sign;
        let view = (self.camera.eye - (a * l0 + b * l1 + c * l2)).normalize();
        if normal.norm() > 0.0 {
            normal = normal.normalize();
        }
        // Keep interpolated normals on the visible side.
        if normal.dot(&view) < 0.0 {
            normal -= view * (1.01 * normal.dot(&view));
            normal = normal.normalize();
        }
        let mut color = tri.base.scale(shade(normal, self.light, view));
        if tri.lines {
            let d = [l0, l1, l2]
                .iter()
                .zip(&tri.edges)
                .filter(|(_, e)| e.0)
                .map(|(l, e)| l * area.abs() / e.1)
                .fold(f64::INFINITY, f64::min);
            color = color.scale(1.0 - 0.35 * (1.0 - (d / 1.5).min(1.0)));
        }
        canvas.color[i] = color;
        canvas.depth[i] = depth;
    }
}

/// Smooth normals: area-weighted sums of the faces' (front-side) normals.
fn smooth_normals(positions: &[Vec3], triangles: &[[usize; 3]]) -> Vec<Vec3> {
    let mut normals = vec![Vec3::zeros(); positions.len()];
    for t in triangles {
        let [a, b, c] = t.map(|k| positions[k]);
        let n = (b - a).cross(&(c - a));
        if n.iter().all(|v| v.is_finite()) {
            for &k in t {
                normals[k] += n;
            }
        }
    }
    for n in &mut normals {
        let len = n.norm();
        if len > 0.0 {
            *n /= len;
        }
    }
    normals
}

/// One triangle on screen, ready to fill.
struct Triangle {
    /// The corners in space.
    corners: [Vec3; 3],
    /// The corners on screen (supersampled pixels).
    s: [(f64, f64); 3],
    /// The corners' depths along the view axis.
    z: [f64; 3],
    normals: [Vec3; 3],
    /// Twice the signed screen area.
    area: f64,
    base: Rgb,
    /// +1 seen from the front, −1 from the back.
    sign: f64,
    /// Per edge (opposite vertex k): whether it is a quad edge, its length.
    edges: [(bool, f64); 3],
    /// Whether the quad edges are drawn.
    lines: bool,
    /// The screen bounding box, clipped.
    x0: usize,
    x1: usize,
    y0: usize,
    y1: usize,
}

impl Triangle {
    /// The pixels of row `py` the triangle can cover: each edge function is
    /// linear in x along the row, so its sign condition is a half-line;
    /// their intersection (widened by a pixel, the pixel test is exact) is
    /// all that is visited. Without `narrow`, the whole bounding box.
    fn span(&self, py: usize, narrow: bool) -> Option<(usize, usize)> {
        let s = &self.s;
        let sigma = self.area.signum();
        let yc = py as f64 + 0.5;
        let (mut lo, mut hi) = (self.x0 as f64, self.x1 as f64 + 1.0);
        for (i, j) in [(1, 2), (2, 0), (0, 1)].into_iter().filter(|_| narrow) {
            let c = (s[j].0 - s[i].0) * (yc - s[i].1);
            let d = (s[j].1 - s[i].1) * sigma;
            if d > 0.0 {
                hi = hi.min(s[i].0 + sigma * c / d + 1.0);
            } else if d < 0.0 {
                lo = lo.max(s[i].0 + sigma * c / d - 1.0);
            } else if sigma * c < -1e-9 * (1.0 + c.abs()) {
                hi = lo - 1.0;
            }
        }
        if hi.is_nan() || lo.is_nan() || hi < lo {
            return None;
        }
        let px0 = (lo - 0.5).floor().max(self.x0 as f64) as usize;
        let px1 = (hi - 0.5).ceil().min(self.x1 as f64);
        if px1 < px0 as f64 {
            return None;
        }
        Some((px0, px1 as usize))
    }
}

fn downsample(canvas: &Canvas) -> Vec<u8> {
    let (w, h) = (WIDTH as usize, HEIGHT as usize);
    let mut out = Vec::with_capacity(w * h * 3);
    for y in 0..h {
        for x in 0..w {
            let mut acc = [0.0; 3];
            for dy in 0..SS {
                for dx in 0..SS {
                    let c = canvas.color[(y * SS + dy) * canvas.w + x * SS + dx];
                    for (a, v) in acc.iter_mut().zip(c.0) {
                        *a += v;
                    }
                }
            }
            for a in acc {
                let v = (a / (SS * SS) as f64).clamp(0.0, 1.0);
                // Gamma 2.2 for a less flat look.
                out.push((v.powf(1.0 / 2.2) * 255.0).round() as u8);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sheet(n: usize, y: f64) -> (Vec<Vec3>, Vec<[usize; 3]>) {
        let mut pts = Vec::new();
        for j in 0..n {
            for i in 0..n {
                pts.push(Vec3::new(
                    i as f64 / (n - 1) as f64,
                    y,
                    j as f64 / (n - 1) as f64,
                ));
            }
        }
        let mut tris = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let a = j * n + i;
                tris.push([a, a + 1, a + n + 1]);
                tris.push([a, a + n + 1, a + n]);
            }
        }
        (pts, tris)
    }

    #[test]
    fn the_cloth_covers_the_middle_of_the_picture() {
        let (pts, triangles) = sheet(6, 0.0);
        let stage = Stage {
            colliders: vec![],
            triangles,
            nx: 6,
        };
        let camera = Camera::fit(&pts, &stage.colliders);
        let Picture { image, simplified } = rasterise(&stage, &camera, &pts);
        let img = image.rgb;
        assert_eq!(simplified, None);
        assert_eq!(img.len(), (WIDTH * HEIGHT * 3) as usize);
        let px = |x: u32, y: u32| {
            let i = ((y * WIDTH + x) * 3) as usize;
            [img[i], img[i + 1], img[i + 2]]
        };
        // The centre pixel is cloth (red or gold, whichever side is up).
        let c = px(WIDTH / 2, HEIGHT / 2);
        assert!(c[0] > c[2] + 40, "centre pixel {c:?}");
        // A corner is background (bluish-grey sky or floor).
        let k = px(2, 2);
        assert!(k[2] >= k[0], "corner pixel {k:?}");
    }

    /// A crumpled sheet: pseudo-random heights, so triangles of every
    /// slope and orientation, both sides, overlapping.
    fn crumpled(n: usize) -> (Vec<Vec3>, Vec<[usize; 3]>) {
        let (mut pts, tris) = sheet(n, 0.0);
        let mut seed: u64 = 0x2545_F491_4F6C_DD1D;
        for p in &mut pts {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let r = (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            p.y = 0.6 * r;
            p.x += 0.1 * r;
        }
        (pts, tris)
    }

    fn draw(stage: &Stage, camera: &Camera, pts: &[Vec3], narrow: bool) -> (Vec<u8>, usize) {
        let (w, h) = (WIDTH as usize * SS, HEIGHT as usize * SS);
        let mut canvas = Canvas {
            w,
            h,
            color: vec![Rgb([0.0; 3]); w * h],
            depth: vec![f64::INFINITY; w * h],
        };
        let light = (camera.up - camera.right * 0.5 - camera.forward * 0.6).normalize();
        let skipped = cloth(
            &mut canvas,
            camera,
            pts,
            &stage.triangles,
            stage.nx,
            light,
            narrow,
        );
        (downsample(&canvas), skipped)
    }

    #[test]
    fn row_spans_draw_exactly_the_pixels_of_the_bounding_box_test() {
        let (pts, triangles) = crumpled(12);
        let stage = Stage {
            colliders: vec![],
            triangles,
            nx: 12,
        };
        let camera = Camera::fit(&pts, &stage.colliders);
        let (fast, a) = draw(&stage, &camera, &pts, true);
        let (slow, b) = draw(&stage, &camera, &pts, false);
        assert_eq!((a, b), (0, 0));
        assert!(fast.iter().any(|&v| v > 0), "something is drawn");
        assert!(fast == slow, "the row spans changed the picture");
    }

    #[test]
    fn a_picture_costs_a_bounded_number_of_pixel_tests() {
        // 20 000 triangles that each cover a large part of the picture (a
        // cloth folded on itself, or blown up): without the budget, some
        // 20 000 × 500 000 pixel tests.
        let (pts, _) = sheet(2, 0.0);
        let big = [[0, 1, 3], [0, 3, 2]];
        let stage = Stage {
            colliders: vec![],
            triangles: big.iter().copied().cycle().take(20_000).collect(),
            nx: 2,
        };
        let camera = Camera::fit(&pts, &[]);
        let clock = std::time::Instant::now();
        let picture = rasterise(&stage, &camera, &pts);
        assert_eq!(picture.image.rgb.len(), (WIDTH * HEIGHT * 3) as usize);
        let note = picture.simplified.as_ref().expect("the budget ran out");
        assert!(note.not_drawn > 0 && note.not_drawn < 20_000, "{note:?}");
        assert_eq!(note.triangles, 20_000);
        assert!(clock.elapsed().as_secs_f64() < 20.0);
        // And the picture says what it left out, in its note and caption.
        assert!(note.to_string().contains("not drawn"), "{note}");
        assert!(picture.caption("test").contains("not drawn"));
    }

    #[test]
    fn a_huge_grid_is_drawn_through_a_coarser_mesh() {
        let nx = 100_000; // × 2
        let mut tris = Vec::new();
        for i in 0..nx - 1 {
            let (a, b, c, d) = (i, i + 1, nx + i, nx + i + 1);
            tris.push([a, b, d]);
            tris.push([a, d, c]);
        }
        let stage = Stage::for_grid(vec![], &tris, nx);
        let cells = stage.triangles.len() / 2;
        assert!(
            (MAX_CELLS_PER_SIDE / 2..=MAX_CELLS_PER_SIDE).contains(&cells),
            "{cells} cells"
        );
        // Every corner of the grid is still a vertex.
        for corner in [0, nx - 1, nx, 2 * nx - 1] {
            assert!(stage.triangles.iter().any(|t| t.contains(&corner)));
        }
        // A small grid is left alone.
        let (_, small) = sheet(5, 0.0);
        assert_eq!(Stage::for_grid(vec![], &small, 5).triangles, small);
    }

    #[test]
    fn a_sphere_is_drawn() {
        let (pts, triangles) = sheet(4, 1.0);
        let stage = Stage {
            colliders: vec![Collider::Sphere {
                center: [0.5, 0.0, 0.5],
                radius: 0.3,
                stiffness: 1.0,
                skin: 0.0,
            }],
            triangles,
            nx: 4,
        };
        let camera = Camera::fit(&pts, &stage.colliders);
        let Picture { image, simplified } = rasterise(&stage, &camera, &pts);
        let img = image.rgb;
        assert_eq!(simplified, None);
        // Some pixels have the sphere's blue.
        let blue = img
            .chunks(3)
            .filter(|p| p[2] as i32 > p[0] as i32 + 30)
            .count();
        assert!(blue > 100, "{blue} bluish pixels");
    }
}
