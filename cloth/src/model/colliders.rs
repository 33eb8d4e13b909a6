//! Colliders as penalties: a C² ramp of the signed distance to a plane or a
//! sphere, with its force and Jacobian.

use nalgebra::{Matrix3, Vector3};

use crate::scene::Collider;

#[derive(Clone, Copy, Debug)]
pub(super) enum Shape {
    /// Signed distance `n·x − c`.
    Plane { normal: Vector3<f64>, c: f64 },
    /// Signed distance `|x − center| − radius`.
    Sphere { center: Vector3<f64>, radius: f64 },
}

/// A penalty collider with its per-particle stiffness `κ = m·stiffness`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Penalty {
    shape: Shape,
    kappa: f64,
    skin: f64,
}

impl Penalty {
    /// `κ = m·stiffness`, the penalty's curvature deep in contact (N/m).
    pub(super) fn kappa(&self) -> f64 {
        self.kappa
    }

    /// `(φ(δ), φ'(δ), φ''(δ))` of the C² ramp, times `κ`.
    #[inline]
    pub(super) fn ramp(&self, delta: f64) -> (f64, f64, f64) {
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
    pub(super) fn distance(&self, x: &Vector3<f64>) -> Option<(f64, Vector3<f64>, f64)> {
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
    pub(super) fn energy(&self, x: &Vector3<f64>) -> f64 {
        self.distance(x).map_or(0.0, |(d, _, _)| self.ramp(-d).0)
    }

    #[inline]
    pub(super) fn force(&self, x: &Vector3<f64>) -> Vector3<f64> {
        match self.distance(x) {
            Some((d, n, _)) if d < 0.0 => n * self.ramp(-d).1,
            _ => Vector3::zeros(),
        }
    }

    /// `∂F/∂x` (symmetric).
    #[inline]
    pub(super) fn force_jacobian(&self, x: &Vector3<f64>) -> Matrix3<f64> {
        self.force_jacobian_projected(x, false)
    }

    /// `∂F/∂x`; `project`: without a sphere's tangential term
    /// `(I − n̂n̂ᵀ)·φ'/r`, the only part of `−∂F/∂x` that can be negative, so
    /// that `−∂F/∂x` is positive semidefinite (its projection onto the PSD
    /// cone: the term is a multiple of the tangential projector).
    #[inline]
    pub(super) fn force_jacobian_projected(&self, x: &Vector3<f64>, project: bool) -> Matrix3<f64> {
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

/// The scene's colliders as penalties on particles of mass `mass`
/// (`κ = m·stiffness`).
pub(super) fn penalties(colliders: &[Collider], mass: f64) -> Vec<Penalty> {
    colliders
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
        .collect()
}
