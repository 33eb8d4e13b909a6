//! The exact flow of the two-body problem `ẍ = −GM x/|x|³`: the Kepler
//! drift `(x, v) ← φ_h(x, v)` of the Wisdom–Holman methods, exact up to
//! rounding for every conic (circular to `e → 1`, parabolic, hyperbolic),
//! for any `h` (negative `h` runs backwards, steps of many orbits are
//! reduced by whole periods).
//!
//! # Method
//!
//! Universal variables (Stumpff; Danby, *Fundamentals of Celestial
//! Mechanics* §6.9; the form used by WHFast, Rein & Tamayo 2015). With
//! `r₀ = |x|`, `η₀ = x·v`, `β = 2GM/r₀ − |v|²` (positive for bound orbits)
//! and `ζ₀ = GM − βr₀`, the functions `Gₖ(s) = sᵏ cₖ(βs²)`
//! ([Stumpff's `cₖ`](stumpff)) give the universal Kepler equation
//!
//! ```text
//! F(s) = r₀ s + η₀ G₂(s) + ζ₀ G₃(s) − h = 0,   F'(s) = r(s) > 0,
//! ```
//!
//! one equation for every conic, monotone in `s`. Its root is found by
//! Halley's method from a starter (a fourth-order series in `h` for short
//! steps, close enough that the first Halley step usually ends the solve;
//! Kepler's equation in the eccentric or hyperbolic anomaly with Danby's
//! starter for long ones) inside a bracket that every iterate
//! tightens; a Halley step that leaves the bracket is replaced by
//! bisection, so the solve cannot wander or cycle. It stops when the
//! correction is below [`KeplerSolver::tolerance`]·|s|, or when `|F(s)|`
//! is already below the rounding error of its own terms (near the
//! pericentre of an orbit with `e → 1`, where `r` is small, the correction
//! cannot get below the noise of `F` divided by `r`). A solve that does
//! neither within [`KeplerSolver::max_iterations`] is a
//! [`KeplerError::NotConverged`] with the iteration count and residual.
//!
//! A short step (`|η₀h/2r₀²|` below ½, `|βh²/r₀²|` and `GM h²/r₀³` below
//! 2.5) is at most about a quarter of a period: its root has the sign of
//! `h`, the initial bracket is `(0, ±∞)`. Otherwise,
//! for a bound orbit (`β > 0`), `h` is first reduced by whole periods
//! `P = 2πGM/β^{3/2}` (towards zero, so the reduction is odd in `h`); the
//! root then lies in `|s| < 2π/√β` (less than one turn of the eccentric
//! anomaly), the initial bracket. For `β ≤ 0` the bracket is grown by
//! doubling from the starter.
//!
//! The new state is formed with Gauss's `f` and `g` functions in the forms
//! that keep their small parts small (Rein & Tamayo 2015):
//!
//! ```text
//! f − 1 = −GM G₂/r₀,   g = h − GM G₃,   ḟ = −GM G₁/(r₀ r),   ġ − 1 = −GM G₂/r,
//! x ← x + ((f − 1) x + g v),   v ← v + (ḟ x + (ġ − 1) v),
//! ```
//!
//! so that the increments, not the whole state, carry the rounding of the
//! coefficients: a short step changes `x` by a rounding error of the
//! increment, as a drift should. One of `f`, `ġ` is then taken from the
//! identity `f ġ − ḟ g = 1` (see `update`): computed independently, the
//! four coefficients miss it by roundings whose mean is not zero, a bias
//! that made the energy of a long run drift linearly.
//!
//! A caller that drifts the same orbit over the same `h` again and again
//! may keep a [`WarmStart`] and call [`KeplerSolver::drift_warm`]: a long
//! solve then starts from the previous root (measured: more evaluations
//! than the cold starter for nearly circular orbits, about the same time;
//! off by default in the Wisdom–Holman runs, see
//! [`KEPLER_WARM_START_DEFAULT`](crate::problems::wisdom_holman::KEPLER_WARM_START_DEFAULT)).
//! Short steps are the same bits either way.
//!
//! Several orbits over the same `h` (the planets of a Wisdom–Holman step)
//! are drifted side by side, bit for bit as one by one, by
//! [`KeplerSolver::drift_lanes`] (four at a time) and
//! [`KeplerSolver::drift_lanes8`] (eight, in one AVX-512 register where the
//! processor has it).
//!
//! # Example
//!
//! ```
//! use integrator_core::kepler::drift;
//!
//! // A circular orbit of radius 1 with GM = 1 (period 2π): a quarter turn.
//! let (mut x, mut v) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
//! drift(1.0, std::f64::consts::FRAC_PI_2, &mut x, &mut v).unwrap();
//! assert!((x[0]).abs() < 1e-15 && (x[1] - 1.0).abs() < 1e-15);
//! assert!((v[0] + 1.0).abs() < 1e-15 && v[1].abs() < 1e-15);
//! ```

mod error;
mod lanes;
mod lanes8;
mod stumpff;

pub use error::KeplerError;
pub use lanes::LANES;
pub use stumpff::stumpff;

use std::f64::consts::PI;

/// The settings of the universal Kepler solve. [`Default`] gives
/// [`KeplerSolver::DEFAULT_TOLERANCE`] and
/// [`KeplerSolver::DEFAULT_MAX_ITERATIONS`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KeplerSolver {
    /// The solve stops when the proposed correction of `s` is at most
    /// `tolerance·|s|` (or when the residual is at rounding level), and
    /// applies that correction to second order. Above ~1e-6 the neglected
    /// third-order terms reach rounding level.
    pub tolerance: f64,
    /// The most Halley or bisection steps (and bracket doublings) one solve
    /// may take before it is a [`KeplerError::NotConverged`].
    pub max_iterations: usize,
}

impl KeplerSolver {
    /// Halley's method converges cubically: after a correction of
    /// `1e-7·|s|` the next would be about `1e-21·|s|`, far below rounding,
    /// so the solve stops there and carries the correction into the
    /// `Gₖ` by their Taylor series instead of evaluating them again.
    pub const DEFAULT_TOLERANCE: f64 = 1e-7;
    /// Room for the worst case: bisection on a bracket that a poor starter
    /// left wide needs about 60 steps to reach a relative width of 1e-16,
    /// and doubling a hyperbolic bracket up as many again. Measured on the
    /// 543 solves of `tests/kepler_flow.rs` (e = 0 … 0.999 and hyperbolae,
    /// steps 10⁻⁴ P … 10 P; its ignored test `evaluation_counts`): one
    /// evaluation for 49 %, 1 to 3 for 95 %, at most 12 (e = 0.9, a step
    /// of three periods).
    pub const DEFAULT_MAX_ITERATIONS: usize = 200;

    /// [`drift`] with these settings.
    pub fn drift(
        &self,
        gm: f64,
        h: f64,
        x: &mut [f64; 3],
        v: &mut [f64; 3],
    ) -> Result<(), KeplerError> {
        self.drift_from(gm, h, x, v, None)
    }

    /// [`drift`](Self::drift) with a [`WarmStart`]: where the step is long
    /// (not the short-step series' case) and `warm` holds a root for the
    /// same `h` inside the solve's bracket, Halley's method starts from
    /// that root instead of the long-step starters; afterwards `warm`
    /// holds this solve's root (long steps only; a short step leaves it as
    /// it was). A short step is exactly [`drift`](Self::drift), so that
    /// the lanes, which take only short steps, give the same bits with or
    /// without the history, on every SIMD level.
    ///
    /// The result is the root to the solve's tolerance either way, but
    /// the last bits may depend on where the iteration started: a run that
    /// warm-starts is a function of its own history, which a checkpoint of
    /// such a run must save ([`WarmStart::h`], [`WarmStart::s`]).
    pub fn drift_warm(
        &self,
        gm: f64,
        h: f64,
        x: &mut [f64; 3],
        v: &mut [f64; 3],
        warm: &mut WarmStart,
    ) -> Result<(), KeplerError> {
        self.drift_from(gm, h, x, v, Some(warm))
    }

    #[inline(always)]
    fn drift_from(
        &self,
        gm: f64,
        h: f64,
        x: &mut [f64; 3],
        v: &mut [f64; 3],
        warm: Option<&mut WarmStart>,
    ) -> Result<(), KeplerError> {
        if !(gm.is_finite() && gm > 0.0) {
            return Err(KeplerError::BadGm { gm });
        }
        if !h.is_finite() {
            return Err(KeplerError::BadStep { h });
        }
        for (what, a) in [("x", &*x), ("v", &*v)] {
            if let Some(i) = a.iter().position(|c| !c.is_finite()) {
                return Err(KeplerError::NonFinite {
                    what,
                    index: i,
                    value: a[i],
                });
            }
        }
        let r0 = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
        if r0 == 0.0 {
            return Err(KeplerError::ZeroPosition);
        }
        if h == 0.0 {
            return Ok(());
        }
        let v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        let eta = x[0] * v[0] + x[1] * v[1] + x[2] * v[2];
        let beta = 2.0 * gm / r0 - v2;
        let zeta = gm - beta * r0;
        let ir0 = 1.0 / r0;
        let orbit = Orbit {
            gm,
            r0,
            ir0,
            eta,
            beta,
            zeta,
        };
        let guess = warm.as_ref().and_then(|w| w.guess(h));
        let (root, g, r, long) = self.solve(&orbit, h, guess)?;

        let (xn, vn) = update(gm, g[4], ir0, r, g[1], g[2], g[3], x, v);
        if xn.iter().chain(&vn).any(|c| !c.is_finite()) {
            return Err(KeplerError::Overflow { h, beta });
        }
        *x = xn;
        *v = vn;
        if let Some(w) = warm
            && long
        {
            *w = WarmStart { h, s: root };
        }
        Ok(())
    }

    /// The root `s` of the universal Kepler equation for a step `h`, with
    /// `[G₀, G₁, G₂, G₃, h']` at it (`h'` the step after the reduction by
    /// whole periods), `r = F'(s)` and whether the step was long (not the
    /// series starter's case: the root a [`WarmStart`] keeps). `warm`, a
    /// previous root for the same `h`, replaces the long-step starters
    /// where it lies inside the bracket.
    #[inline(always)]
    fn solve(
        &self,
        o: &Orbit,
        h: f64,
        warm: Option<f64>,
    ) -> Result<(f64, [f64; 5], f64, bool), KeplerError> {
        let series = o.series_guess(h);
        let (s, g, r) = self.solve_from(o, h, series, warm)?;
        Ok((s, g, r, series.is_none()))
    }

    /// [`solve`](Self::solve) with the series starter already formed.
    // The bracket tests are written `!(lo < s && s < hi)` so that a NaN
    // iterate fails them too.
    #[allow(clippy::nonminimal_bool)]
    fn solve_from(
        &self,
        o: &Orbit,
        h: f64,
        series: Option<f64>,
        warm: Option<f64>,
    ) -> Result<(f64, [f64; 5], f64), KeplerError> {
        let mut ht = h;
        // The bracket [lo, hi] of the root; F(lo) ≤ 0 ≤ F(hi).
        let (mut lo, mut hi);
        let mut s;
        if let Some(guess) = series {
            // A short step (the Wisdom–Holman regime): well under a period,
            // so no reduction, and the root has the sign of h (F is
            // increasing, F(0) = −h). The series is close enough that the
            // first Halley step usually ends the solve; the half-open
            // bracket still catches an iterate that strays.
            (lo, hi) = if h >= 0.0 {
                (0.0, f64::INFINITY)
            } else {
                (f64::NEG_INFINITY, 0.0)
            };
            s = guess;
        } else if o.beta > 0.0 {
            let sb = o.beta.sqrt();
            let period = 2.0 * PI * o.gm / (o.beta * sb);
            if ht.abs() >= period {
                ht -= period * (ht / period).trunc();
                if ht == 0.0 {
                    // Whole periods: home again.
                    return Ok((0.0, [1.0, 0.0, 0.0, 0.0, 0.0], o.r0));
                }
            }
            // |h'| < P: less than one turn of the eccentric anomaly; the
            // margin covers a reduced step that rounding left just above P.
            let turn = 2.0 * PI / sb * (1.0 + 1e-9);
            (lo, hi) = if ht >= 0.0 { (0.0, turn) } else { (-turn, 0.0) };
            s = match warm {
                Some(w) if w > lo && w < hi => w,
                _ => o
                    .short_step_guess(ht)
                    .unwrap_or_else(|| o.elliptic_guess(ht)),
            };
        } else {
            (lo, hi) = if ht >= 0.0 {
                (0.0, f64::INFINITY)
            } else {
                (f64::NEG_INFINITY, 0.0)
            };
            s = match warm {
                Some(w) if w > lo && w < hi => w,
                _ => o
                    .short_step_guess(ht)
                    .or_else(|| o.hyperbolic_guess(ht))
                    .unwrap_or_else(|| o.parabolic_guess(ht)),
            };
        }
        if !(s > lo && s < hi) {
            s = o.parabolic_guess(ht).clamp(lo, hi);
            if !(s > lo && s < hi) || !s.is_finite() {
                s = if hi.is_finite() && lo.is_finite() {
                    0.5 * (lo + hi)
                } else {
                    ht / o.r0
                };
            }
        }

        let mut correction = f64::NAN;
        let mut residual = f64::NAN;
        for _ in 0..self.max_iterations {
            let (g, f, fp, fpp, scale) = o.evaluate(s, ht);
            residual = f;
            if f == 0.0 || f.abs() <= 2.0 * f64::EPSILON * scale {
                return Ok(o.at_root(s, g, f / fp));
            }
            if f < 0.0 {
                lo = s;
            } else if f > 0.0 {
                hi = s;
            } else if s > 0.0 {
                // F overflowed (a hyperbolic s too far out): the root is nearer 0.
                hi = s;
            } else {
                lo = s;
            }
            // Halley: s − 2F F'/(2F'² − F F''); Newton where F'' overflowed
            // (G₀ = cosh of a hyperbolic anomaly near the end of f64).
            let ds = if fpp.is_finite() {
                2.0 * f * fp / (2.0 * fp * fp - f * fpp)
            } else {
                f / fp
            };
            correction = ds;
            if ds.abs() <= self.tolerance * s.abs() {
                return Ok(o.at_root(s, g, ds));
            }
            let mut next = s - ds;
            if !(next > lo && next < hi) || !next.is_finite() {
                next = match (lo.is_finite(), hi.is_finite()) {
                    // Bisect, geometrically where the bracket spans orders
                    // of magnitude (a hyperbolic starter far off).
                    (true, true) if lo > 0.0 && hi > 8.0 * lo => (lo * hi).sqrt(),
                    (true, true) if hi < 0.0 && lo < 8.0 * hi => -(lo * hi).sqrt(),
                    (true, true) => 0.5 * (lo + hi),
                    // An unbounded side (β ≤ 0): step out by doubling.
                    (true, false) => 2.0 * lo.max(s).max(f64::MIN_POSITIVE),
                    (false, true) => 2.0 * hi.min(s).min(-f64::MIN_POSITIVE),
                    (false, false) => unreachable!("one end of the bracket is 0"),
                };
            }
            if next == s {
                return Ok(o.at_root(s, g, ds));
            }
            s = next;
        }
        Err(KeplerError::NotConverged {
            iterations: self.max_iterations,
            residual,
            correction,
            s,
            h,
            gm: o.gm,
            beta: o.beta,
        })
    }
}

/// The new state from the `Gₖ` at the root: Gauss's `f`, `g`, `ḟ`, `ġ` in
/// the increment forms of the [module documentation](self), with `1/r₀` and
/// `1/r` formed once, and one of `f`, `ġ` replaced by its value from the
/// identity `f ġ − ḟ g = 1` (the Wronskian of the flow, which scales the
/// angular momentum: `x' × v' = (f ġ − ḟ g) x × v`).
///
/// Why: the four coefficients computed independently each round once, but
/// their Wronskian then misses 1 by a few ulps whose mean is not zero
/// (measured, with the Stumpff series' coefficient roundings already
/// compensated: +0.002 to +0.004 ulp of energy per step at h = P/16 for
/// e = 0.3 to 0.7); through the identity the Wronskian is 1 up to the
/// rounding of one division, of either sign. Where `|ḟ g| ≤ 2` and the
/// larger of `|f|`, `|ġ|` is at least ½ (every step well under a period,
/// where both are near 1), the smaller is solved from the larger,
/// `ġ − 1 = (ḟ g − (f − 1))/f` or `f − 1 = (ḟ g − (ġ − 1))/ġ`: a divisor of
/// at least ½ and a numerator of a few terms of size at most ~3, so the
/// result keeps the relative accuracy of the direct form to a small
/// factor. Elsewhere (long steps, where `f` and `ġ` may both pass near
/// zero) the direct forms are kept.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn update(
    gm: f64,
    h: f64,
    ir0: f64,
    r: f64,
    g1: f64,
    g2: f64,
    g3: f64,
    x: &[f64; 3],
    v: &[f64; 3],
) -> ([f64; 3], [f64; 3]) {
    // The identity's quotient is written over `r` (`a = −ḟ g r`), so that
    // its division runs beside `1/r` instead of after it, and the choices
    // are selects, not branches (which of |f|, |ġ| is larger changes from
    // step to step, and a mispredicted branch costs more than the
    // arithmetic of both sides).
    let ir = 1.0 / r;
    let gm_g2 = gm * g2;
    let fm1_direct = -gm_g2 * ir0;
    let gg = h - gm * g3;
    let a = gm * g1 * ir0 * gg;
    let fd = -gm * g1 * ir0 * ir;
    let gdm1_direct = -gm_g2 * ir;
    // f·r and ġ·r.
    let f_r = (1.0 + fm1_direct) * r;
    let gd_r = r - gm_g2;
    let identity = a.abs() <= 2.0 * r && f_r.abs().max(gd_r.abs()) >= 0.5 * r;
    let big_f = f_r.abs() >= gd_r.abs();
    // ġ − 1 = −(a + (f − 1) r)/(f r), or f − 1 = (GM G₂ − a)/(ġ r).
    let num = if big_f {
        -(a + fm1_direct * r)
    } else {
        gm_g2 - a
    };
    let den = if big_f { f_r } else { gd_r };
    let q = num / den;
    let fm1 = if identity && !big_f { q } else { fm1_direct };
    let gdm1 = if identity && big_f { q } else { gdm1_direct };
    let mut xn = [0.0; 3];
    let mut vn = [0.0; 3];
    for k in 0..3 {
        xn[k] = x[k] + (fm1 * x[k] + gg * v[k]);
        vn[k] = v[k] + (fd * x[k] + gdm1 * v[k]);
    }
    (xn, vn)
}

/// The bound on `|η₀h/2r₀²|` below which a step is short (with
/// [`SHORT_TURN`]): the series of `s(h)` ([`Orbit::series_guess`]) is then
/// a correction of the linear `h/r₀`, not a guess.
const SHORT_STEP: f64 = 0.5;

/// The bound on `|βh²/r₀²|` and `GM h²/r₀³` (about `(nh)²`, `n` the mean
/// motion, for a nearly circular orbit) below which a step is short: up to
/// about a quarter of a period. The fourth-order series of `s(h)` is exact
/// for a circular orbit and off by `O(e·(nh)⁵)` otherwise, from which
/// Halley's method converges in one to three evaluations: the outer
/// planets at every step a Wisdom–Holman integration uses (Jupiter to
/// h ≈ 1100 days) stay on this path, which the lanes run
/// ([`KeplerSolver::drift_lanes8`]).
const SHORT_TURN: f64 = 2.5;

/// The history of one orbit's Kepler solves that a warm start needs
/// ([`KeplerSolver::drift_warm`]): the step `h` of its last long solve and
/// that solve's root `s` (after the reduction by whole periods), or none.
///
/// Why the previous root: the drifts of a Wisdom–Holman run repeat the
/// same few steps `h` on orbits that change little from one step to the
/// next, so the root of the last solve with the same `h` is a starter that
/// costs nothing, where the long-step starter costs an `atan2`, a `hypot`
/// and three `sin_cos` (Danby's starter refined by two Newton steps). It is
/// a guess only: the solve keeps its bracket and stopping tests, and a
/// guess for another `h` or outside the bracket is not used.
///
/// Why a value the caller keeps rather than state inside the solver: the
/// drift stays a pure function of its arguments for every caller without
/// history, and a run that warm-starts owns its history (and can save it
/// in a checkpoint: [`h`](Self::h) and [`s`](Self::s) as bits, restored
/// by [`new`](Self::new)), so two runs from the same start give the same
/// bits whatever ran before them in the same process.
///
/// Two are equal where their bits are (so that no history equals itself).
#[derive(Clone, Copy, Debug)]
pub struct WarmStart {
    h: f64,
    s: f64,
}

impl WarmStart {
    /// No history: the next solve uses the cold starters.
    pub const NONE: Self = Self {
        h: f64::NAN,
        s: f64::NAN,
    };

    /// A history of a root `s` for the step `h` (as [`h`](Self::h) and
    /// [`s`](Self::s) gave them, e.g. from a checkpoint).
    pub fn new(h: f64, s: f64) -> Self {
        Self { h, s }
    }

    /// The step of the remembered solve (NaN for none).
    pub fn h(&self) -> f64 {
        self.h
    }

    /// The remembered root (NaN for none).
    pub fn s(&self) -> f64 {
        self.s
    }

    /// The guess for a solve over `h`: the root, where it was for the same
    /// `h` bit for bit and is finite.
    fn guess(&self, h: f64) -> Option<f64> {
        (self.h.to_bits() == h.to_bits() && self.s.is_finite()).then_some(self.s)
    }
}

impl PartialEq for WarmStart {
    fn eq(&self, o: &Self) -> bool {
        self.h.to_bits() == o.h.to_bits() && self.s.to_bits() == o.s.to_bits()
    }
}

impl Eq for WarmStart {}

impl Default for WarmStart {
    fn default() -> Self {
        Self::NONE
    }
}

impl Default for KeplerSolver {
    fn default() -> Self {
        Self {
            tolerance: Self::DEFAULT_TOLERANCE,
            max_iterations: Self::DEFAULT_MAX_ITERATIONS,
        }
    }
}

/// `(x, v) ← φ_h(x, v)`, the exact flow of `ẍ = −GM x/|x|³` over time `h`
/// (any sign, any length), with the default [`KeplerSolver`]. See the
/// [module documentation](self) for the method.
///
/// Errors: `GM` not finite and positive, `h` or the state not finite, `x =
/// 0`, a solve that does not converge, a result beyond the range of f64.
/// On error `x` and `v` are left as they were.
pub fn drift(gm: f64, h: f64, x: &mut [f64; 3], v: &mut [f64; 3]) -> Result<(), KeplerError> {
    KeplerSolver::default().drift(gm, h, x, v)
}

/// The constants of one orbit that the universal Kepler equation needs.
struct Orbit {
    gm: f64,
    r0: f64,
    /// `1/r₀`, formed once.
    ir0: f64,
    eta: f64,
    beta: f64,
    zeta: f64,
}

impl Orbit {
    /// `[G₀ … G₃, h]`, `F(s)`, `F'(s) = r`, `F''(s)` and the size of `F`'s
    /// terms (its rounding scale).
    #[inline]
    fn evaluate(&self, s: f64, h: f64) -> ([f64; 5], f64, f64, f64, f64) {
        let s2 = s * s;
        let [c0, c1, c2, c3] = stumpff(self.beta * s2);
        let g1 = s * c1;
        let g2 = s2 * c2;
        let g3 = s2 * s * c3;
        let (a, b, c) = (self.r0 * s, self.eta * g2, self.zeta * g3);
        let f = a + b + c - h;
        let fp = self.r0 + self.eta * g1 + self.zeta * g2;
        let fpp = self.eta * c0 + self.zeta * g1;
        let scale = a.abs() + b.abs() + c.abs() + h.abs();
        ([c0, g1, g2, g3, h], f, fp, fpp, scale)
    }

    /// The last correction `δ` (Halley's, or Newton's `F/F'` where the
    /// residual is at rounding level) carried into the `Gₖ` by their Taylor
    /// series to second order, `Gₖ(s − δ) = Gₖ − δ·Gₖ' + δ²/2·Gₖ''` (with
    /// `Gₖ' = G_{k−1}`, `G₀' = −βG₁`), instead of another evaluation; with
    /// `|δ| ≤ 1e-7·|s|` the cubic term is below 1e-21 of `s`. Stopping at
    /// `s` itself would leave the root always on the side Halley's method
    /// approaches it from, a bias that makes `f ġ − g ḟ` differ from 1 by
    /// the same sign at every step and the energy drift linearly in time.
    #[inline]
    fn at_root(&self, s: f64, g: [f64; 5], d: f64) -> (f64, [f64; 5], f64) {
        let [g0, g1, g2, g3, h] = g;
        if !d.is_finite() || d == 0.0 {
            let r = self.r0 + self.eta * g1 + self.zeta * g2;
            return (s, g, r);
        }
        let b = self.beta;
        let e = 0.5 * d * d;
        let n1 = g1 - d * g0 - e * b * g1;
        let n2 = g2 - d * g1 + e * g0;
        let n3 = g3 - d * g2 + e * g1;
        let n0 = g0 + d * b * g1 - e * b * g0;
        let r = self.r0 + self.eta * n1 + self.zeta * n2;
        (s - d, [n0, n1, n2, n3, h], r)
    }

    /// The series of the root `s(h)` to fourth order in `u = h/r₀`: with
    /// `F(s)/r₀ = s + p s² + q s³ + t s⁴ + …` (`p = η₀/2r₀`, `q = ζ₀/6r₀`,
    /// `t = −βη₀/24r₀`),
    /// `s = u − p u² + (2p² − q) u³ + (5p(q − p²) − t) u⁴`.
    /// `None` where the step is not short (see [`SHORT_STEP`] and
    /// [`SHORT_TURN`]).
    #[inline]
    fn series_guess(&self, h: f64) -> Option<f64> {
        let ir0 = self.ir0;
        let u = h * ir0;
        let p = 0.5 * self.eta * ir0;
        let pu = p * u;
        let bu2 = self.beta * u * u;
        let short =
            pu.abs() < SHORT_STEP && bu2.abs() < SHORT_TURN && self.gm * u * u * ir0 < SHORT_TURN;
        if !short {
            return None;
        }
        let q = self.zeta * ir0 * (1.0 / 6.0);
        let t = -self.beta * self.eta * ir0 * (1.0 / 24.0);
        let c3 = 2.0 * p * p - q;
        let c4 = 5.0 * p * (q - p * p) - t;
        Some(u * (1.0 + u * (-p + u * (c3 + u * c4))))
    }

    /// `s ≈ h/r₀ − η₀h²/(2r₀³)` (the series of `s(h)` to second order),
    /// used where it is a good start: when `β s²` (the squared change of
    /// the anomaly, for bound orbits) is small.
    fn short_step_guess(&self, h: f64) -> Option<f64> {
        let u = h / self.r0;
        let s = u * (1.0 - 0.5 * u * self.eta / self.r0);
        // The second-order term must be a correction, not the answer.
        let small = (0.5 * u * self.eta / self.r0).abs() < 0.25
            && (self.beta * s * s).abs() < 0.25
            && (self.gm * u * u / self.r0) < 0.25;
        small.then_some(s)
    }

    /// `s` from Kepler's equation `E − e sin E = M` with Danby's starter
    /// `E ≈ M + 0.85 e sign(sin M)`, as a change of eccentric anomaly
    /// `ΔE/√β` (bound orbits).
    fn elliptic_guess(&self, h: f64) -> f64 {
        let sb = self.beta.sqrt();
        let ecos = 1.0 - self.r0 * self.beta / self.gm;
        let esin = self.eta * sb / self.gm;
        let e = ecos.hypot(esin);
        let e0 = esin.atan2(ecos);
        let m0 = e0 - esin;
        let n = self.beta * sb / self.gm;
        let m1 = m0 + n * h;
        // Reduce to (−π, π] keeping count of the turns.
        let turns = ((m1 + PI) / (2.0 * PI)).floor();
        let m = m1 - 2.0 * PI * turns;
        let sign = if m.sin() >= 0.0 { 1.0 } else { -1.0 };
        let mut ea = m + 0.85 * e * sign;
        // Two Newton steps on Kepler's equation refine the starter cheaply.
        for _ in 0..2 {
            let (sn, cs) = ea.sin_cos();
            ea -= (ea - e * sn - m) / (1.0 - e * cs);
        }
        (ea + 2.0 * PI * turns - e0) / sb
    }

    /// `s` from the hyperbolic Kepler equation `e sinh H − H = M` with the
    /// starter `H ≈ sign(M) ln(2|M|/e + 1.8)`, as `ΔH/√(−β)` (β < 0).
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // a NaN e² is no hyperbola either
    fn hyperbolic_guess(&self, h: f64) -> Option<f64> {
        if self.beta >= 0.0 {
            return None;
        }
        let alpha = -self.beta;
        let sa = alpha.sqrt();
        let ecosh = 1.0 + self.r0 * alpha / self.gm;
        let esinh = self.eta * sa / self.gm;
        let e2 = ecosh * ecosh - esinh * esinh;
        if !(e2 > 1.0) {
            return None;
        }
        let e = e2.sqrt();
        let h0 = (esinh / e).asinh();
        let m0 = esinh - h0;
        let n = alpha * sa / self.gm;
        let m = m0 + n * h;
        let hh = if m.is_finite() {
            let mut hh = m.signum() * (2.0 * m.abs() / e + 1.8).ln();
            for _ in 0..2 {
                let (sn, cs) = (hh.sinh(), hh.cosh());
                let next = hh - (e * sn - hh - m) / (e * cs - 1.0);
                if next.is_finite() {
                    hh = next;
                }
            }
            hh
        } else {
            // |M| beyond f64: the starter's logarithm taken by parts.
            h.signum() * ((2.0 / e).ln() + n.ln() + h.abs().ln())
        };
        let s = (hh - h0) / sa;
        s.is_finite().then_some(s)
    }

    /// `s` from the cubic of a parabola through the same point,
    /// `r₀s + GM s³/6 = h` (one Newton-free estimate: the smaller of the
    /// linear and the cubic term's solutions).
    fn parabolic_guess(&self, h: f64) -> f64 {
        let lin = h / self.r0;
        let cub = (6.0 * h / self.gm).cbrt();
        if lin.abs() < cub.abs() { lin } else { cub }
    }
}
