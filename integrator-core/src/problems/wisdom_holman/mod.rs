//! N-body problems split for Wisdom–Holman methods: `H = H_Kepler +
//! H_interaction` (+ `H_jump`), each part with its exact flow, in Jacobi
//! coordinates ([`Jacobi`]) and in democratic heliocentric coordinates
//! ([`DemocraticHeliocentric`], Duncan, Levison & Lee 1998).
//!
//! The inertial state is the library's `z = [x; p]` (positions, then
//! momenta `pᵢ = mᵢvᵢ`, body-major, 6N numbers, the layout of
//! [`OuterSolarSystem`](crate::problems::OuterSolarSystem)); body 0 is the
//! central mass. A split's own state is `w = [Q; P]` in its canonical
//! coordinates (positions and their conjugate momenta, same layout), so
//! each part's flow is a symplectic map of `w` and any composition of the
//! flows is symplectic. Convert once at the start (`from_inertial`) and at
//! output (`to_inertial`); the conversions are linear, `O(N)`, and
//! round-trip to a few ulps of the largest coordinate (the `_checked`
//! variants verify it and name the body that does not).
//!
//! Each part is an inherent method `part(&self, h, w) -> Result<(), WhError>`
//! that advances `w` by that part's exact flow over time `h` (any sign),
//! allocating nothing for up to [`STACK_BODIES`] bodies. On error the state
//! is partly advanced and must not be used further; the error names the
//! body and part (and the step, from [`Jacobi::integrate`] or
//! [`DemocraticHeliocentric::integrate`]).
//!
//! Up to eight planets run in eight lanes, one planet a lane
//! ([`crate::simd`]): the Kepler flow of all planets in one pass (on
//! AVX-512; bit for bit the scalar drift, which redoes any lane that would
//! leave the short-step path or take more than four evaluations) and the interaction kicks with every pair
//! of planets at once, in one AVX-512 register where the processor has
//! AVX-512F, else in portable arrays that give the same bits
//! (`with_simd` picks; tested in `tests/simd_lanes.rs`). More planets take
//! the scalar kernels.

mod democratic;
mod error;
mod jacobi;
mod lanes;
mod split;
mod warm;

pub use democratic::DemocraticHeliocentric;
pub use error::WhError;
pub use jacobi::{GradientKick, Jacobi, KEPLER_WARM_START_DEFAULT, KEPLER_WARM_START_ENV};
pub use warm::{KeplerHistory, SLOTS, WarmJacobi};

/// The bodies a split kernel's interaction kick handles with scratch on the
/// stack; beyond this it allocates its scratch once per call.
pub const STACK_BODIES: usize = 16;

/// Validated masses and names, shared by both coordinate systems.
#[derive(Clone, Debug, PartialEq)]
struct Bodies {
    g: f64,
    m: Vec<f64>,
    names: Option<Vec<String>>,
}

impl Bodies {
    fn new(g: f64, masses: &[f64], names: Option<&[&str]>) -> Result<Self, WhError> {
        if !(g.is_finite() && g > 0.0) {
            return Err(WhError::BadG { g });
        }
        if masses.len() < 2 {
            return Err(WhError::TooFewBodies { n: masses.len() });
        }
        if let Some(names) = names
            && names.len() != masses.len()
        {
            return Err(WhError::NameCount {
                names: names.len(),
                masses: masses.len(),
            });
        }
        let names: Option<Vec<String>> = names.map(|n| n.iter().map(|s| s.to_string()).collect());
        for (i, &m) in masses.iter().enumerate() {
            if !(m.is_finite() && m > 0.0) {
                return Err(WhError::BadMass {
                    body: i,
                    name: names.as_ref().map(|n| n[i].clone()),
                    mass: m,
                });
            }
        }
        Ok(Self {
            g,
            m: masses.to_vec(),
            names,
        })
    }

    fn n(&self) -> usize {
        self.m.len()
    }

    fn name(&self, i: usize) -> Option<String> {
        self.names.as_ref().map(|n| n[i].clone())
    }

    /// Body `i`'s momentum in `p` after an interaction kick: an error
    /// naming the body and the part where it is not finite.
    #[inline]
    fn check_kicked(&self, p: &[f64], i: usize) -> Result<(), WhError> {
        if p[3 * i].is_finite() && p[3 * i + 1].is_finite() && p[3 * i + 2].is_finite() {
            return Ok(());
        }
        Err(WhError::NonFinite {
            part: "interaction",
            body: i,
            name: self.name(i),
            step: None,
        })
    }

    fn check_len(&self, what: &'static str, z: &[f64]) -> Result<(), WhError> {
        let expected = 6 * self.n();
        if z.len() != expected {
            return Err(WhError::Length {
                what,
                expected,
                got: z.len(),
            });
        }
        Ok(())
    }

    /// The state's length and finiteness, naming the body of the first
    /// non-finite coordinate.
    fn check_state(&self, what: &'static str, z: &[f64]) -> Result<(), WhError> {
        self.check_len(what, z)?;
        let n = self.n();
        if let Some(k) = z.iter().position(|c| !c.is_finite()) {
            let (body, index) = ((k % (3 * n)) / 3, k);
            return Err(WhError::NonFiniteInput {
                what,
                body,
                name: self.name(body),
                index,
                value: z[k],
            });
        }
        Ok(())
    }

    /// `H = Σ |pᵢ|²/(2mᵢ) − Σ_{i<j} G mᵢmⱼ/|xᵢ − xⱼ|` of an inertial state.
    fn energy(&self, z: &[f64]) -> f64 {
        let n = self.n();
        let (x, p) = z.split_at(3 * n);
        let mut t = 0.0;
        let mut u = 0.0;
        for i in 0..n {
            let pi = &p[3 * i..3 * i + 3];
            t += 0.5 * (pi[0] * pi[0] + pi[1] * pi[1] + pi[2] * pi[2]) / self.m[i];
            for j in 0..i {
                let d = [
                    x[3 * i] - x[3 * j],
                    x[3 * i + 1] - x[3 * j + 1],
                    x[3 * i + 2] - x[3 * j + 2],
                ];
                u += self.m[i] * self.m[j] / (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            }
        }
        t - self.g * u
    }

    /// Compare the state `back` that came back from a conversion with `z`,
    /// per body and component: positions to `bound·max|xₖ|`, momenta to
    /// `bound·max|pₖ|`.
    // `!(err <= bound)` so that a NaN error fails the check too.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    fn round_trip(
        &self,
        coordinates: &'static str,
        z: &[f64],
        back: &[f64],
    ) -> Result<(), WhError> {
        let n = self.n();
        // Max-norms: no squares to underflow (or overflow) and hide a
        // difference.
        let norm = |a: &[f64]| a[0].abs().max(a[1].abs()).max(a[2].abs());
        let scale = |off: usize| (0..n).map(|i| norm(&z[off + 3 * i..])).fold(0.0, f64::max);
        let (sx, sp) = (scale(0), scale(3 * n));
        let bound = ROUND_TRIP_ULPS * n as f64 * f64::EPSILON;
        for i in 0..n {
            for (off, s) in [(0, sx), (3 * n, sp)] {
                let k = off + 3 * i;
                let d = [
                    z[k] - back[k],
                    z[k + 1] - back[k + 1],
                    z[k + 2] - back[k + 2],
                ];
                let err = norm(&d);
                if !(err <= bound * s) {
                    return Err(WhError::RoundTrip {
                        coordinates,
                        body: i,
                        name: self.name(i),
                        error: err / s,
                        bound,
                    });
                }
            }
        }
        Ok(())
    }
}

/// The round trip inertial → split → inertial must come back within
/// `ROUND_TRIP_ULPS·N·ε` of the largest position (momentum): each
/// coordinate passes through a running mass-weighted sum of at most N
/// terms each way.
pub const ROUND_TRIP_ULPS: f64 = 4.0;

/// Run `f` on `len` zeroed scratch numbers: on the stack up to
/// `9·STACK_BODIES` (a gradient kick's `9n`), else on the heap.
#[inline]
fn with_scratch<R>(len: usize, f: impl FnOnce(&mut [f64]) -> R) -> R {
    if len <= 9 * STACK_BODIES {
        let mut buf = [0.0f64; 9 * STACK_BODIES];
        f(&mut buf[..len])
    } else {
        let mut buf = vec![0.0f64; len];
        f(&mut buf)
    }
}

/// A 3-vector of a slice.
#[inline]
fn get3(a: &[f64], i: usize) -> [f64; 3] {
    [a[3 * i], a[3 * i + 1], a[3 * i + 2]]
}

#[inline]
fn set3(a: &mut [f64], i: usize, v: [f64; 3]) {
    a[3 * i..3 * i + 3].copy_from_slice(&v);
}
