//! The average vector field (AVF) discrete gradient of the cloth's potential,
//! and the potential it is the gradient of, for an energy–momentum
//! conserving step solved as a minimisation.
//!
//! # Why a minimisation
//!
//! The AVF step (Quispel and McLaren 2008; for `M q̈ = −∇V`)
//!
//! ```text
//! q₁ = q + h(v + v₁)/2,   M(v₁ − v) = h·F̄(q, q₁),   F̄(q, q₁) = −∫₀¹ ∇V(q + ξ(q₁ − q)) dξ
//! ```
//!
//! conserves the energy exactly: `V(q₁) − V(q) = −F̄·(q₁ − q)` (the
//! fundamental theorem of calculus along the segment), and
//! `½v₁ᵀMv₁ − ½vᵀMv = ½(v₁ + v)ᵀM(v₁ − v) = (q₁ − q)ᵀF̄`. It keeps linear
//! momentum because `V` is translation invariant (each spring's two forces
//! are equal and opposite). Unlike Gonzalez's discrete gradient
//! ([`ClothModel::discrete_gradient_force`]) it is a gradient in `q₁`:
//! `∂(−F̄)/∂q₁ = ∫₀¹ ξ ∇²V(q + ξ(q₁ − q)) dξ` is symmetric, and
//! `−F̄ = ∇_{q₁} U` with
//!
//! ```text
//! U(q₁) = ∫₀¹ (V(q + ξ(q₁ − q)) − V(q))/ξ dξ.
//! ```
//!
//! Eliminating `v₁`, the step is `M(q₁ − q − hv) = (h²/2)F̄(q, q₁)`, the
//! stationarity condition of
//!
//! ```text
//! Ψ(q₁) = (1/h²)(q₁ − q − hv)ᵀM(q₁ − q − hv) + U(q₁)
//! ```
//!
//! (in the form of `integrator_core::minimise::Objective`: `base = q + hv`,
//! `c = 2/h²`). So the same Newton/line-search machinery as the midpoint
//! family's applies, with a coercive objective whose value the line search
//! can judge ([`ClothModel::avf_potential`]), where the Gonzalez scheme's
//! Newton has no objective to globalise with.
//!
//! It is not symplectic, and it does not keep angular momentum: a spring's
//! AVF force is `(k/L)[D − L·W]` with `D` the mean of the two spring vectors
//! and `W = ∫₀¹ r̂ dξ` (below), which is in general not parallel to `D`
//! (it is when `I₀ = 2/(ℓ₀ + ℓ₁)`, which is exactly Gonzalez's choice), so
//! the pair of forces has a torque. With gravity and pins the cloth keeps no
//! angular momentum anyway.
//!
//! # One spring
//!
//! `ψ(d) = (k/2L)(|d| − L)²` with `d = x_b − x_a` (a pinned spring:
//! `d = pin − x_a`), `∇ψ(r) = (k/L)(r − L·r/|r|)`; the force on `a` is
//! `+∇ψ`, on `b` `−∇ψ` (as in [`ClothModel::force_and_scale`]). With
//! `d₁` the spring at `q₁`, `δ = d₁ − d = a·δ̂` (`a = |δ|`),
//! `r(ξ) = d + ξδ`, `ℓ(ξ) = |r(ξ)|`, `ℓ₀ = |d|`, `ℓ₁ = |d₁|`:
//!
//! ```text
//! ∫₀¹ ∇ψ(r) dξ = (k/L)[D − L·W],   D = (d + d₁)/2,
//! W = ∫₀¹ r/|r| dξ = A·δ̂ + I₀·p,
//! A = (ℓ₁ − ℓ₀)/a = (s₀ + s₁)/(ℓ₀ + ℓ₁),   s₀ = d·δ̂, s₁ = d₁·δ̂,
//! p = d − s₀δ̂ = d₁ − s₁δ̂ (the part of either end across δ, |p| = η),
//! I₀ = ∫₀¹ dξ/ℓ(ξ) = (1/a)·ln((s₁ + ℓ₁)/(s₀ + ℓ₀)).
//! ```
//!
//! `A` is exact because `dℓ/dξ = r̂·δ`, and `ℓ₁² − ℓ₀² = a(s₀ + s₁)`. Then
//! `W·δ = ℓ₁ − ℓ₀` whatever `I₀` is (`p ⊥ δ`), so
//! `∇̄ψ·δ = (k/L)[(ℓ₁² − ℓ₀²)/2 − L(ℓ₁ − ℓ₀)] = ψ(ℓ₁) − ψ(ℓ₀)` holds to
//! round-off by construction; `I₀` only decides the direction across `δ`.
//! (`I₀ = 2/(ℓ₀ + ℓ₁)` would give Gonzalez's `(k/L)(1 − 2L/(ℓ₀ + ℓ₁))D`.)
//! `I₀` without cancellation: orient so that `s₀ + s₁ ≥ 0` (else swap and
//! negate the ends: `(s₀, ℓ₀, s₁, ℓ₁) → (−s₁, ℓ₁, −s₀, ℓ₀)`, the integral
//! is the same), put `R₀ = s₀ + ℓ₀`, or `η²/(ℓ₀ − s₀)` when `s₀ < 0`, and
//!
//! ```text
//! x = (R₁ − R₀)/R₀ = a·c,   c = (ℓ₀ + ℓ₁ + |s₀ + s₁|)/((ℓ₀ + ℓ₁)·R₀),
//! I₀ = c·log1p(x)/x  (x < 1; → c = 1/ℓ₀ as a → 0),   log1p(x)/a  (x ≥ 1).
//! ```
//!
//! `η` is computed from the shorter end (its round-off is then relative to
//! the shorter length). `δ = 0` exactly gives `∇ψ(d)`, the force at `q`.
//! When the segment passes through `0` (`η = 0`, the ends on opposite
//! sides), `I₀ = ∞` but `I₀·p = 0`: the integrand `r/|r|` is bounded and
//! the AVF force is finite even there, where `∇ψ` itself is undefined.
//!
//! The potential: `ψ(ℓ) − ψ(ℓ₀) = (k/2L)(ℓ² − ℓ₀²) − k(ℓ − ℓ₀)`, and
//! `∫₀¹ (ℓ(ξ)² − ℓ₀²)/ξ dξ = 2d·δ + a²/2` exactly, so
//!
//! ```text
//! U_spring = (k/2L)(2d·δ + a²/2) − k·J,   J = ∫₀¹ (ℓ(ξ) − ℓ₀)/ξ dξ
//!          = ∫₀¹ (2d·δ + ξa²)/(ℓ(ξ) + ℓ₀) dξ.
//! ```
//!
//! `J` in closed form (from `√Q/ξ = (√Q)' + (d·δ)/√Q + ℓ₀²/(ξ√Q)`,
//! `Q(ξ) = ℓ(ξ)²`):
//!
//! ```text
//! J = (ℓ₁ − ℓ₀) + (d·δ)·I₀ − ℓ₀·ln(P/(2ℓ₀²)),   P = ℓ₀ℓ₁ + d·d₁.
//! ```
//!
//! Evaluated as follows. For `a ≤ ℓ₀/2`, by `n`-point Gauss–Legendre on
//! the second integrand (analytic; its nearest singularity, a zero of `Q`,
//! is at `|ξ| = ℓ₀/a`, at least `z = ℓ₀/a − 1` from `[0, 1]`, so the rule's
//! relative error is about `ρ⁻²ⁿ`, `ρ = 2z + 1 + √((2z + 1)² − 1)`; no
//! cancellation as `a → 0`): `n = 4` for `a ≤ ℓ₀/32` (`126⁻⁸ ≈ 2e-17`),
//! 6 for `a ≤ ℓ₀/8` (`30⁻¹² ≈ 2e-18`), 8 for `a ≤ ℓ₀/4` (`13.9⁻¹⁶ ≈ 5e-19`),
//! 12 for `a ≤ ℓ₀/2` (`5.83⁻²⁴ ≈ 4e-19`). Otherwise in closed form: for
//! `s₀ ≥ 0` as written (all terms well conditioned, the last as
//! `ℓ₀·log1p((ℓ₀(ℓ₁ − ℓ₀) + d·δ)/(2ℓ₀²))`); for `s₀ < 0`, with
//! `s₀ = −ℓ₀ + R₀`, as `J = (ℓ₁ − ℓ₀) − ℓ₀·ln(R₁P/(2ℓ₀²R₀)) + R₀·a·I₀`,
//! where `R₁P/R₀` is formed without cancellation: `R₀ = η²/(ℓ₀ − s₀)`;
//! `R₁ = η²/(ℓ₁ − s₁)` when `s₁ < 0`; `P = a²η²/(ℓ₀ℓ₁ − d·d₁)` when
//! `d·d₁ < 0` (Lagrange: `|d × d₁|² = a²η²`), so that `η²` cancels
//! analytically in both cases; in the remaining case (`s₀ < 0 ≤ s₁`,
//! `d·d₁ ≥ 0`) the shorter end is within `√2·η` of the origin, and `η` from
//! it is accurate. The divergent parts of `(d·δ)·I₀` and of the last term
//! (both infinite when the segment passes through `0`) thus cancel
//! analytically, and a segment through `0` gets the finite limit
//! `J = ℓ₁ − ℓ₀ − 2ℓ₀ ln(a/ℓ₀)`.
//!
//! Gravity `−Σ m g·x` is linear: its AVF force is the weight and its `U` is
//! `−Σ m g·(x₁ − x)`, exactly.
//!
//! Colliders are not included: their penalty ramp along a segment has no
//! closed form worth the trouble for the sphere (the plane's would), so the
//! AVF methods here are the AVF of the springs and gravity, and callers
//! refuse scenes with colliders ([`ClothModel::has_colliders`]), as for the
//! Gonzalez scheme.
//!
//! # The Jacobian
//!
//! `∂(−F̄)/∂q₁` is, per spring, the block `B = ∫₀¹ ξ·H(r(ξ)) dξ` with
//! `H(r) = (k/L)[I − (L/|r|)(I − r̂r̂ᵀ)]` (the Hessian of `ψ`, as
//! `spring_block`), approximated by a composite 4-point Gauss–Legendre
//! rule: `B ≈ (k/L)[(½ − C)I + S]`, `C = L·Σ wᵢξᵢ/ℓᵢ`,
//! `S = L·Σ (wᵢξᵢ/ℓᵢ) r̂ᵢr̂ᵢᵀ` (`Σ wᵢξᵢ = ½`). The integrand is analytic
//! except near where `r(ξ)` comes closest to `0`, `ξ* = −d·δ/a²`, at the
//! complex distance `η/a` from the real axis; the rule's panels are graded
//! from `ξ*` (clamped into `[0, 1]`) outwards, `[0, w]`, `[w, 2w]`,
//! `[2w, 4w]`, … with `w` the distance from there to that singularity, so
//! that every panel is about its own width or more away from it and the
//! rule's relative error is below about 1e-5 (at most about 5e-6 on the first
//! panel, 8e-7 on the doubling ones) however close the segment comes to zero
//! length; when the singularity is a whole side away (the common case: the
//! spring does not come near zero length) a side is one panel, 4 points.
//! (A fixed 4-point rule errs by order one where a segment passes within a
//! small fraction of its length of zero length.) Newton needs only a good
//! positive-semidefinite matrix, not the exact one (the converged step does
//! not depend on it); but where springs are compressed the projection drops
//! curvature the objective has, and Newton then converges only linearly:
//! on the test's small cloth at one step per 60 Hz frame, 38.6 iterations
//! per step with the projected matrix against 13.6 with the unprojected one
//! ([`ClothModel::avf_jacobian_values`]) wherever `c·M` plus it is positive
//! definite (`tests/avf.rs`, a dense Newton). `S` lives in the plane of
//! `d` and `δ`, so `B`'s eigenvectors are the normal `n` of that plane
//! (eigenvalue `(k/L)(½ − C)`) and the two of a 2×2 symmetric matrix in
//! it; where one of the three eigenvalues is negative, `B` is rebuilt from
//! the nonnegative eigenpairs (`Σ_{λ>0} λvvᵀ`): the projection of `B` onto
//! the PSD cone. Otherwise `B` is used as summed.

use nalgebra::{Matrix3, Vector3};

use super::{ClothModel, spring_block};

/// Gauss–Legendre on `[0, 1]`: the nodes below `½` (the others are
/// `1 − ξ`) and their weights, 12 points.
const GL12: [(f64, f64); 6] = [
    (0.009_219_682_876_640_375, 0.023_587_668_193_255_914),
    (0.047_941_371_814_762_57, 0.053_469_662_997_659_21),
    (0.115_048_662_902_847_66, 0.080_039_164_271_673_11),
    (0.206_341_022_856_691_3, 0.101_583_713_361_532_96),
    (0.316_084_250_500_909_9, 0.116_746_268_269_177_4),
    (0.437_383_295_744_265_5, 0.124_573_522_906_701_39),
];

/// Gauss–Legendre on `[0, 1]`, 8 points (as [`GL12`]).
const GL8: [(f64, f64); 4] = [
    (0.019855071751231884, 0.05061426814518813),
    (0.10166676129318664, 0.11119051722668724),
    (0.2372337950418355, 0.15685332293894363),
    (0.4082826787521751, 0.181341891689181),
];

/// Gauss–Legendre on `[0, 1]`, 6 points (as [`GL12`]).
const GL6: [(f64, f64); 3] = [
    (0.03376524289842399, 0.08566224618958518),
    (0.16939530676686773, 0.1803807865240693),
    (0.38069040695840156, 0.23395696728634552),
];

/// Gauss–Legendre on `[0, 1]`, 4 points (as [`GL12`]).
const GL4: [(f64, f64); 2] = [
    (0.069_431_844_202_973_71, 0.173_927_422_568_726_93),
    (0.330_009_478_207_571_87, 0.326_072_577_431_273_07),
];

/// The pieces of one spring's segment from `d` to `d₁` that the force and
/// the potential share (`a > 0`).
struct Segment {
    d: Vector3<f64>,
    d1: Vector3<f64>,
    /// `δ̂`.
    dh: Vector3<f64>,
    a: f64,
    l0: f64,
    l1: f64,
    s0: f64,
    s1: f64,
    /// The part of the ends across `δ`, and its length `η`.
    p: Vector3<f64>,
    eta: f64,
}

impl Segment {
    /// `None` when `δ = 0` (or `|δ|` underflows).
    #[inline]
    fn new(d: Vector3<f64>, d1: Vector3<f64>) -> Option<Segment> {
        let delta = d1 - d;
        let a = delta.norm();
        if a.is_nan() || a <= 0.0 {
            return None;
        }
        let dh = delta / a;
        let (l0, l1) = (d.norm(), d1.norm());
        let (s0, s1) = (d.dot(&dh), d1.dot(&dh));
        let p = if l0 <= l1 { d - dh * s0 } else { d1 - dh * s1 };
        let eta = p.norm();
        Some(Segment {
            d,
            d1,
            dh,
            a,
            l0,
            l1,
            s0,
            s1,
            p,
            eta,
        })
    }

    /// `I₀ = ∫₀¹ dξ/ℓ(ξ)` (`∞` when the segment passes through 0).
    #[inline]
    fn inverse_length_integral(&self) -> f64 {
        inverse_length_integral(self.a, self.l0, self.l1, self.s0, self.s1, self.eta)
    }

    /// `W = ∫₀¹ r/|r| dξ = A·δ̂ + I₀·p`.
    #[inline]
    fn mean_direction(&self) -> Vector3<f64> {
        let along = self.dh * ((self.s0 + self.s1) / (self.l0 + self.l1));
        let i0 = self.inverse_length_integral();
        if self.eta > 0.0 && i0.is_finite() {
            along + self.p * i0
        } else {
            along
        }
    }

    /// `J = ∫₀¹ (ℓ(ξ) − ℓ₀)/ξ dξ` (module documentation).
    fn length_integral(&self) -> f64 {
        let Segment {
            d,
            a,
            l0,
            l1,
            s0,
            s1,
            eta,
            ..
        } = *self;
        if l1 == 0.0 {
            return -l0;
        }
        if l0 == 0.0 {
            return l1;
        }
        let delta = self.d1 - d;
        let dd = d.dot(&delta);
        if a <= 0.5 * l0 {
            // The fewest points whose error bound (module documentation) is
            // below 1e-16 relatively.
            let rule: &[(f64, f64)] = if a <= l0 / 32.0 {
                &GL4
            } else if a <= 0.125 * l0 {
                &GL6
            } else if a <= 0.25 * l0 {
                &GL8
            } else {
                &GL12
            };
            let mut sum = 0.0;
            for &(x, w) in rule {
                for xi in [x, 1.0 - x] {
                    let l = (d + delta * xi).norm();
                    sum += w * (2.0 * dd + xi * a * a) / (l + l0);
                }
            }
            return sum;
        }
        let dl = a * (s0 + s1) / (l0 + l1);
        let i0 = self.inverse_length_integral();
        let t = if s0 >= 0.0 {
            dd * i0 - l0 * ((l0 * dl + dd) / (2.0 * l0 * l0)).ln_1p()
        } else {
            let dd1 = d.dot(&self.d1);
            let ratio = if s1 < 0.0 {
                // R₁ = η²/(ℓ₁ − s₁), R₀ = η²/(ℓ₀ − s₀): η² cancels.
                (l0 * l1 + dd1) * (l0 - s0) / (2.0 * l0 * l0 * (l1 - s1))
            } else if dd1 < 0.0 {
                // P = a²η²/(ℓ₀ℓ₁ − d·d₁): η² cancels.
                (s1 + l1) * a * a * (l0 - s0) / (2.0 * l0 * l0 * (l0 * l1 - dd1))
            } else if eta > 0.0 {
                (s1 + l1) * (l0 * l1 + dd1) * (l0 - s0) / (2.0 * l0 * l0 * eta * eta)
            } else {
                // Collinear through (or onto) 0: the limit (a/ℓ₀)².
                (a / l0) * (a / l0)
            };
            let r0 = eta * (eta / (l0 - s0));
            let tail = if r0 > 0.0 && i0.is_finite() {
                r0 * a * i0
            } else {
                0.0
            };
            -l0 * ratio.ln() + tail
        };
        dl + t
    }
}

/// `I₀ = ∫₀¹ dξ/|d + ξδ|` without cancellation (module documentation).
#[inline]
fn inverse_length_integral(a: f64, l0: f64, l1: f64, s0: f64, s1: f64, eta: f64) -> f64 {
    let (sigma, sum) = (s0 + s1, l0 + l1);
    // Orient so that s₀ + s₁ ≥ 0: then s₁ > 0 and R₁ = s₁ + ℓ₁ is safe.
    let (s, l) = if sigma >= 0.0 { (s0, l0) } else { (-s1, l1) };
    let r0 = if s >= 0.0 {
        s + l
    } else {
        eta * (eta / (l - s))
    };
    let c = (sum + sigma.abs()) / (sum * r0);
    let x = a * c;
    if x < 1.0 {
        if x > 0.0 { c * (x.ln_1p() / x) } else { c }
    } else {
        x.ln_1p() / a
    }
}

/// `∫₀¹ ∇ψ(d + ξ(d₁ − d)) dξ` of one spring (`k/L = kl`, `L = rest`).
#[inline]
fn spring_avf(d: Vector3<f64>, d1: Vector3<f64>, kl: f64, rest: f64) -> Vector3<f64> {
    match Segment::new(d, d1) {
        None => d * (kl - kl * rest / d.norm()),
        Some(seg) => ((d + d1) * 0.5 - seg.mean_direction() * rest) * kl,
    }
}

/// `(U, |U|ₐ)` of one spring: `(k/2L)(2d·δ + a²/2) − k·J` and the sum of its
/// terms' magnitudes.
#[inline]
fn spring_avf_potential(d: Vector3<f64>, d1: Vector3<f64>, kl: f64, rest: f64) -> (f64, f64) {
    match Segment::new(d, d1) {
        None => (0.0, 0.0),
        Some(seg) => {
            let quad = 0.5 * kl * (2.0 * d.dot(&(d1 - d)) + 0.5 * seg.a * seg.a);
            let lin = kl * rest * seg.length_integral();
            (quad - lin, quad.abs() + lin.abs())
        }
    }
}

/// The first panel on either side of the closest approach in
/// [`graded_rule`] is at least `2⁻³⁰` of its side (so at most about 30
/// panels a side).
const SMALLEST_PANEL: f64 = 1.0 / (1u64 << 30) as f64;

/// Calls `f(ξ, w)` for the nodes and weights of a composite 4-point
/// Gauss–Legendre rule on `[0, 1]` for integrands with a near-singularity
/// where `r(ξ) = d + ξδ` comes closest to `0`: at `ξ* = −s₀/a` (here
/// `s₀/a = d·δ/a²`), `η/a` off the real axis (`eta_a = η/a`). From `ξ*`
/// clamped into `[0, 1]`, panels `[0, w]`, `[w, 2w]`, `[2w, 4w]`, … on each
/// side, `w` the distance from there to the singularity: each panel is
/// about its own width or more from the singularity, so the rule's relative
/// error is below about 1e-5 on every panel, whatever `η/a` (a single
/// panel, 4 points, when the singularity is at least a side's length away:
/// the common case). Allocates nothing.
#[inline]
fn graded_rule(s0_a: f64, eta_a: f64, mut f: impl FnMut(f64, f64)) {
    let raw = -s0_a;
    let star = raw.clamp(0.0, 1.0);
    let w = (eta_a * eta_a + (raw - star) * (raw - star)).sqrt();
    for (dir, len) in [(1.0, 1.0 - star), (-1.0, star)] {
        if len.is_nan() || len <= 0.0 {
            continue;
        }
        let mut lo = 0.0;
        let mut width = w.max(len * SMALLEST_PANEL);
        loop {
            let hi = if lo + 1.5 * width >= len {
                len
            } else {
                lo + width
            };
            for &(x, weight) in &GL4 {
                for u in [x, 1.0 - x] {
                    f(star + dir * (lo + (hi - lo) * u), weight * (hi - lo));
                }
            }
            if hi >= len {
                break;
            }
            lo = hi;
            width = hi;
        }
    }
}

/// The graded 4-point Gauss–Legendre approximation of
/// `∫₀¹ ξ·H(d + ξδ) dξ` (module documentation), `H` as [`spring_block`];
/// `project`: its projection onto the PSD cone.
#[inline]
fn spring_avf_block(
    d: Vector3<f64>,
    d1: Vector3<f64>,
    kl: f64,
    rest: f64,
    project: bool,
) -> Matrix3<f64> {
    let delta = d1 - d;
    let a = delta.norm();
    if a.is_nan() || a <= 0.0 {
        return spring_block(&d, kl, rest, project) * 0.5;
    }
    let dh = delta / a;
    // An orthonormal basis (e₁ = δ̂, e₂) of a plane holding every r(ξ).
    let (l0, l1) = (d.norm_squared(), d1.norm_squared());
    let (far, near) = if l0 >= l1 { (d, d1) } else { (d1, d) };
    let across = far - dh * far.dot(&dh);
    let across_len = across.norm();
    let e2 = if across_len > 1e-8 * l0.max(l1).sqrt() {
        across / across_len
    } else {
        // (Nearly) collinear: any unit vector across δ̂.
        let pick = if dh.x.abs() <= dh.y.abs() && dh.x.abs() <= dh.z.abs() {
            Vector3::x()
        } else if dh.y.abs() <= dh.z.abs() {
            Vector3::y()
        } else {
            Vector3::z()
        };
        (pick - dh * pick.dot(&dh)).normalize()
    };
    let mut c = 0.0;
    let mut s = Matrix3::zeros();
    let (mut sa, mut sb, mut sc) = (0.0, 0.0, 0.0);
    // η from the nearer end (its round-off relative to the shorter length).
    let eta = (near - dh * near.dot(&dh)).norm();
    graded_rule(d.dot(&dh) / a, eta / a, |xi, w| {
        let r = d + delta * xi;
        let l = r.norm();
        if l.is_nan() || l <= 0.0 {
            return;
        }
        let wl = w * xi * rest / l;
        let rh = r / l;
        c += wl;
        s += (rh * rh.transpose()) * wl;
        let (u, v) = (rh.dot(&dh), rh.dot(&e2));
        sa += wl * u * u;
        sb += wl * u * v;
        sc += wl * v * v;
    });
    let base = 0.5 - c;
    // Eigenpairs of B/(k/L): the plane's normal with ½ − C, and those of
    // the 2×2 [[sa, sb], [sb, sc]] shifted by ½ − C.
    let mean = 0.5 * (sa + sc);
    let radius = (0.25 * (sa - sc) * (sa - sc) + sb * sb).sqrt();
    let (lambda_plus, lambda_minus) = (base + mean + radius, base + mean - radius);
    if !project || (base >= 0.0 && lambda_minus >= 0.0) {
        // Nothing to project (or not asked to): B as summed.
        return (Matrix3::from_diagonal_element(base) + s) * kl;
    }
    // Rebuilt from the nonnegative eigenpairs: subtracting a large negative
    // part instead would leave its round-off, which can be negative.
    let theta = 0.5 * (2.0 * sb).atan2(sa - sc);
    let (cs, sn) = (theta.cos(), theta.sin());
    let n = dh.cross(&e2);
    let v_plus = dh * cs + e2 * sn;
    let v_minus = e2 * cs - dh * sn;
    let mut b = Matrix3::zeros();
    for (lambda, v) in [(base, n), (lambda_plus, v_plus), (lambda_minus, v_minus)] {
        if lambda > 0.0 {
            b += (v * v.transpose()) * (kl * lambda);
        }
    }
    b
}

impl ClothModel {
    /// The average vector field discrete gradient `F̄(q, q₁) =
    /// −∫₀¹ ∇V(q + ξ(q₁ − q)) dξ` of the springs and gravity into `out`, in
    /// closed form (module `model::avf`'s documentation gives the
    /// formulas): `V(q₁) − V(q) = −F̄·(q₁ − q)` to round-off by
    /// construction, so the AVF step keeps the energy exactly, and each
    /// spring pulls its two ends equally and oppositely, so it keeps linear
    /// momentum. `q₁ = q` gives the force `F(q)`. Finite even where a
    /// spring's segment passes through zero length. Colliders are not
    /// included: callers refuse scenes with colliders
    /// ([`has_colliders`](Self::has_colliders)). Returns the force scale as
    /// [`force_and_scale`](Self::force_and_scale) does (the largest weight,
    /// spring force `|F̄ₛ|`, and `κ·max(‖q‖_∞, ‖q₁‖_∞)`), for a gradient test
    /// relative to it. Allocates nothing.
    pub fn avf_force(&self, q: &[f64], q1: &[f64], out: &mut [f64]) -> f64 {
        let n = self.free_count();
        let (scale, kappa) = self.two_configuration_force(q, q1, out, spring_avf);
        let q_max = q[..3 * n]
            .iter()
            .chain(&q1[..3 * n])
            .fold(0.0f64, |m, x| m.max(x.abs()));
        scale.max(kappa * q_max)
    }

    /// `U(q₁) = ∫₀¹ (V(q + ξ(q₁ − q)) − V(q))/ξ dξ` for the springs and
    /// gravity: the potential whose gradient in `q₁` is
    /// `−`[`avf_force`](Self::avf_force), so that the AVF step is the
    /// minimiser of `(1/h²)(q₁ − q − hv)ᵀM(q₁ − q − hv) + U(q₁)`, and the value
    /// a line search on that objective needs. Each spring's `U` is
    /// `(k/2L)(2d·δ + |δ|²/2) − k·J` with `J` by 4- to 12-point
    /// Gauss–Legendre for `|δ| ≤ ℓ₀/2` and in closed form otherwise (module documentation);
    /// gravity's is `−Σ m g·(x₁ − x)`. Accurate to round-off of its terms
    /// ([`avf_potential_and_magnitude`](Self::avf_potential_and_magnitude)).
    /// Colliders are not included (as [`avf_force`](Self::avf_force)).
    /// Allocates nothing.
    pub fn avf_potential(&self, q: &[f64], q1: &[f64]) -> f64 {
        self.avf_potential_and_magnitude(q, q1).0
    }

    /// `(U(q₁), |U|ₐ)`: [`avf_potential`](Self::avf_potential) and the sum
    /// of the magnitudes of the terms it is summed from (per spring
    /// `|(k/2L)(2d·δ + |δ|²/2)| + |k·J|`, per particle `|m g·(x₁ − x)|`),
    /// what its round-off is relative to (the `value` of
    /// `integrator_core::minimise::Objective`). Allocates nothing.
    pub fn avf_potential_and_magnitude(&self, q: &[f64], q1: &[f64]) -> (f64, f64) {
        let n = self.free_count();
        let q3 = &q.as_chunks::<3>().0[..n];
        let p3 = &q1.as_chunks::<3>().0[..n];
        let (mut u, mut mag) = (0.0, 0.0);
        for s in &self.ff {
            let (a, b) = (s.a as usize, s.b as usize);
            let d = Vector3::from(q3[b]) - Vector3::from(q3[a]);
            let d1 = Vector3::from(p3[b]) - Vector3::from(p3[a]);
            let (v, m) = spring_avf_potential(d, d1, s.kl, s.rest);
            u += v;
            mag += m;
        }
        for s in &self.fp {
            let pin = Vector3::from(s.pin);
            let d = pin - Vector3::from(q3[s.a as usize]);
            let d1 = pin - Vector3::from(p3[s.a as usize]);
            let (v, m) = spring_avf_potential(d, d1, s.kl, s.rest);
            u += v;
            mag += m;
        }
        let w = Vector3::from(self.weight);
        for (x, x1) in q3.iter().zip(p3) {
            let work = w.dot(&(Vector3::from(*x1) - Vector3::from(*x)));
            u -= work;
            mag += work.abs();
        }
        (u, mag)
    }

    /// A positive semidefinite approximation of `∂(−F̄)/∂q₁ =
    /// ∫₀¹ ξ ∇²V(q + ξ(q₁ − q)) dξ` (the Hessian of
    /// [`avf_potential`](Self::avf_potential)) for Newton's method on the
    /// AVF step, stored as
    /// [`force_jacobian_values_projected`](Self::force_jacobian_values_projected)
    /// stores `−∇²V`: negated, in the order of
    /// [`force_jacobian_pattern`](Self::force_jacobian_pattern). Each
    /// spring's 3×3 block is a composite 4-point Gauss–Legendre rule in `ξ`,
    /// graded towards the spring's closest approach to zero length (relative
    /// error below about 1e-5 whatever the step; 4 points where the spring
    /// stays well away from zero length; see the module documentation), and
    /// then projected onto the PSD cone exactly (its eigenvectors are known
    /// in closed form); gravity adds nothing; colliders are not included (as
    /// [`avf_force`](Self::avf_force)). Allocates nothing.
    ///
    /// # Panics
    /// If `values` is not exactly as long as the pattern.
    pub fn avf_jacobian_values_projected(&self, q: &[f64], q1: &[f64], values: &mut [f64]) {
        self.avf_jacobian_into(q, q1, values, true);
    }

    /// [`avf_jacobian_values_projected`](Self::avf_jacobian_values_projected)
    /// without the projection: the same quadrature of
    /// `∂F̄/∂q₁ = −∫₀¹ ξ ∇²V dξ`, symmetric but indefinite where springs are
    /// compressed. Where `c·M` plus it is still positive definite, Newton's
    /// method converges nearly quadratically with it (the quadrature's
    /// relative error, below about 1e-5, bounds the rate), and only linearly
    /// with the projected matrix (the projection drops curvature the
    /// objective has);
    /// a solver may try its Cholesky factorisation first and fall back to the
    /// projected one. Allocates nothing.
    ///
    /// # Panics
    /// If `values` is not exactly as long as the pattern.
    pub fn avf_jacobian_values(&self, q: &[f64], q1: &[f64], values: &mut [f64]) {
        self.avf_jacobian_into(q, q1, values, false);
    }

    fn avf_jacobian_into(&self, q: &[f64], q1: &[f64], values: &mut [f64], project: bool) {
        self.add_spring_blocks(q, q1, values, |d, d1, kl, rest| {
            spring_avf_block(d, d1, kl, rest, project)
        });
    }
}
