//! Several Kepler drifts over the same `h` at once:
//! [`KeplerSolver::drift_lanes`].
//!
//! # Why
//!
//! One short-step drift is a single chain of dependent operations (a
//! square root, the starter, the Stumpff series, Halley's division, the
//! divisions of `f` and `g`): its cost is the chain's latency, and the
//! arithmetic units idle. A Wisdom–Holman step drifts every planet over the
//! same `h`, independent orbits; run side by side, in arrays the compiler
//! can keep in vector registers, their chains overlap.
//!
//! # Same bits as [`drift`](super::drift)
//!
//! In the Wisdom–Holman regime (a step well under a period) the scalar
//! solve ends after one evaluation of the universal Kepler equation at the
//! series starter. The lanes perform exactly that path's operations, in the
//! same order (Rust does not reassociate or fuse floating-point operations,
//! so vector and scalar code round alike), and each lane checks the scalar
//! solve's own stopping test. A lane that would take any other path — not
//! a short step, a second iteration, bad input, an overflow — is redone by
//! the scalar [`KeplerSolver::drift`], which also produces its error. So
//! every lane's result is bit for bit the scalar drift's (tested in
//! `tests/kepler_flow.rs`), only cheaper.

use super::stumpff::{C2, C3, SERIES_LIMIT, SERIES_LONG, SERIES_MID, SERIES_SHORT, series_head};
use super::{KeplerError, KeplerSolver, SHORT_STEP, SHORT_TURN, WarmStart, update};

/// The number of orbits [`KeplerSolver::drift_lanes`] takes at once: four
/// doubles fill two SSE2 registers (the baseline x86-64 build) or one AVX
/// register; more lanes would mostly add padding for the few planets of a
/// Wisdom–Holman problem. Measured (`benches/kepler.rs`, baseline build):
/// four drifts at P/400 side by side in 163 ns, one by one in 220 ns.
pub const LANES: usize = 4;

/// The fewest orbits worth the lanes; fewer are drifted one by one.
const MIN_LANES: usize = 3;

type L = [f64; LANES];

/// Lane-wise `f(a[l])`.
#[inline(always)]
fn map(a: L, f: impl Fn(f64) -> f64) -> L {
    let mut out = [0.0; LANES];
    for l in 0..LANES {
        out[l] = f(a[l]);
    }
    out
}

/// Lane-wise `f(a[l], b[l])`.
#[inline(always)]
fn zip(a: L, b: L, f: impl Fn(f64, f64) -> f64) -> L {
    let mut out = [0.0; LANES];
    for l in 0..LANES {
        out[l] = f(a[l], b[l]);
    }
    out
}

/// `(c₂, c₃)` of [`stumpff`](super::stumpff)'s series branch in every
/// lane, by Horner's rule with `N` terms; a lane whose `|z|` the scalar
/// code would sum with fewer terms (`n` of them) gets zero for the leading
/// coefficients beyond `n`, so its sum starts at `C[n−1]` exactly (`0·m +
/// 0 = 0`, then `0·m + C = C`) and is the scalar sum bit for bit.
#[inline(always)]
fn series<const N: usize>(m: L, terms: [usize; LANES]) -> (L, L) {
    let mut c2 = [0.0; LANES];
    let mut c3 = [0.0; LANES];
    for l in 0..LANES {
        let n = terms[l];
        let (mut a, mut b) = if N <= n {
            (C2[N - 1], C3[N - 1])
        } else {
            (0.0, 0.0)
        };
        for k in (2..N - 1).rev() {
            let (p, q) = if k < n { (C2[k], C3[k]) } else { (0.0, 0.0) };
            a = a * m[l] + p;
            b = b * m[l] + q;
        }
        (c2[l], c3[l]) = series_head(m[l], a, b);
    }
    (c2, c3)
}

impl KeplerSolver {
    /// [`drift`](Self::drift) of up to [`LANES`] independent orbits over
    /// the same `h`: lane `l < used` has `GM = gm[l]` and state
    /// `(x[l], v[l])`; lanes from `used` on are ignored and left alone.
    /// Every lane's result is bit for bit what `drift` gives it (see the
    /// [module documentation](self) for why this is cheaper).
    ///
    /// Errors: the first lane (in order) whose drift fails, with `drift`'s
    /// error. The lanes before it have been drifted, it and those after it
    /// are left as they were, as if the lanes had been drifted one by one.
    pub fn drift_lanes(
        &self,
        gm: &[f64; LANES],
        h: f64,
        x: &mut [[f64; 3]; LANES],
        v: &mut [[f64; 3]; LANES],
        used: usize,
    ) -> Result<(), (usize, KeplerError)> {
        self.drift_lanes_from(gm, h, x, v, used, None)
    }

    /// [`drift_lanes`](Self::drift_lanes) with a [`WarmStart`] per lane: a
    /// lane the lanes leave to the scalar solve is drifted by
    /// [`drift_warm`](Self::drift_warm) with `warm[l]`. The lanes take only
    /// short steps, which a warm start leaves exactly as they were, so
    /// every lane is `drift_warm`'s bits.
    pub fn drift_lanes_warm(
        &self,
        gm: &[f64; LANES],
        h: f64,
        x: &mut [[f64; 3]; LANES],
        v: &mut [[f64; 3]; LANES],
        used: usize,
        warm: &mut [WarmStart; LANES],
    ) -> Result<(), (usize, KeplerError)> {
        self.drift_lanes_from(gm, h, x, v, used, Some(warm))
    }

    #[inline(always)]
    fn drift_lanes_from(
        &self,
        gm: &[f64; LANES],
        h: f64,
        x: &mut [[f64; 3]; LANES],
        v: &mut [[f64; 3]; LANES],
        used: usize,
        mut warm: Option<&mut [WarmStart; LANES]>,
    ) -> Result<(), (usize, KeplerError)> {
        let used = used.min(LANES);
        if used == 0 {
            return Ok(());
        }
        // The lanes cost about the same however many are used (measured:
        // four drifts at P/400 in 163 ns side by side, 55 ns each one by
        // one), so one or two orbits are drifted one by one.
        let quick = if used >= MIN_LANES && h.is_finite() && h != 0.0 && self.max_iterations > 0 {
            // Padding lanes repeat lane 0, so that they compute harmlessly.
            let mut g = *gm;
            let (mut xs, mut vs) = ([[0.0; LANES]; 3], [[0.0; LANES]; 3]);
            for l in 0..LANES {
                let s = if l < used { l } else { 0 };
                g[l] = gm[s];
                for k in 0..3 {
                    xs[k][l] = x[s][k];
                    vs[k][l] = v[s][k];
                }
            }
            Some(self.quick_dispatch(g, h, xs, vs))
        } else {
            None
        };
        for l in 0..used {
            match &quick {
                Some((xn, vn, ok)) if ok[l] => {
                    x[l] = [xn[0][l], xn[1][l], xn[2][l]];
                    v[l] = [vn[0][l], vn[1][l], vn[2][l]];
                }
                _ => match warm.as_deref_mut() {
                    Some(w) => self.drift_warm(gm[l], h, &mut x[l], &mut v[l], &mut w[l]),
                    None => self.drift(gm[l], h, &mut x[l], &mut v[l]),
                }
                .map_err(|e| (l, e))?,
            }
        }
        Ok(())
    }

    /// [`quick`](Self::quick) compiled for AVX2 where
    /// [`crate::simd::level`] allows it (one 256-bit register holds the four
    /// lanes; the baseline x86-64 build has only SSE2's two), else as
    /// built. The same operations in the
    /// same order either way — IEEE addition, multiplication, division and
    /// square root round alike at any vector width, and Rust fuses no
    /// multiply–add — so the bits do not depend on the path (the lanes are
    /// tested against the scalar solve on whichever this machine takes).
    #[allow(clippy::type_complexity)]
    #[inline]
    fn quick_dispatch(
        &self,
        gm: L,
        h: f64,
        x: [L; 3],
        v: [L; 3],
    ) -> ([L; 3], [L; 3], [bool; LANES]) {
        #[cfg(target_arch = "x86_64")]
        if crate::simd::level() >= crate::simd::Level::Avx2 {
            // SAFETY: `level` is AVX2 or above only where the processor
            // has AVX2.
            return unsafe { self.quick_avx2(gm, h, x, v) };
        }
        self.quick(gm, h, x, v)
    }

    /// [`quick`](Self::quick), inlined into a function compiled with AVX2.
    #[cfg(target_arch = "x86_64")]
    #[allow(clippy::type_complexity)]
    #[target_feature(enable = "avx2")]
    fn quick_avx2(&self, gm: L, h: f64, x: [L; 3], v: [L; 3]) -> ([L; 3], [L; 3], [bool; LANES]) {
        self.quick(gm, h, x, v)
    }

    /// The scalar solve's one-evaluation path in every lane (see
    /// [`KeplerSolver::drift`], `Orbit::series_guess`, `Orbit::evaluate`
    /// and `Orbit::at_root`, whose operations are repeated here in the same
    /// order), and per lane whether that path is the one the scalar solve
    /// takes and ends on.
    #[allow(clippy::type_complexity)]
    #[inline(always)]
    fn quick(&self, gm: L, h: f64, x: [L; 3], v: [L; 3]) -> ([L; 3], [L; 3], [bool; LANES]) {
        let dot = |a: &[L; 3], b: &[L; 3]| {
            let mut out = [0.0; LANES];
            for l in 0..LANES {
                out[l] = a[0][l] * b[0][l] + a[1][l] * b[1][l] + a[2][l] * b[2][l];
            }
            out
        };
        let mut ok = [true; LANES];
        for l in 0..LANES {
            ok[l] = gm[l].is_finite()
                && gm[l] > 0.0
                && (0..3).all(|k| x[k][l].is_finite() && v[k][l].is_finite());
        }
        let r0 = map(dot(&x, &x), f64::sqrt);
        let v2 = dot(&v, &v);
        let eta = dot(&x, &v);
        let beta = zip(zip(gm, r0, |g, r| 2.0 * g / r), v2, |a, b| a - b);
        let mut zeta = [0.0; LANES];
        let ir0 = map(r0, |r| 1.0 / r);

        // The series starter (`Orbit::series_guess`).
        let mut s = [0.0; LANES];
        for l in 0..LANES {
            zeta[l] = gm[l] - beta[l] * r0[l];
            let u = h * ir0[l];
            let p = 0.5 * eta[l] * ir0[l];
            let pu = p * u;
            let bu2 = beta[l] * u * u;
            let short = pu.abs() < SHORT_STEP
                && bu2.abs() < SHORT_TURN
                && gm[l] * u * u * ir0[l] < SHORT_TURN;
            let q = zeta[l] * ir0[l] * (1.0 / 6.0);
            let t = -beta[l] * eta[l] * ir0[l] * (1.0 / 24.0);
            let c3 = 2.0 * p * p - q;
            let c4 = 5.0 * p * (q - p * p) - t;
            s[l] = u * (1.0 + u * (-p + u * (c3 + u * c4)));
            // The root has the sign of h: the scalar solve's bracket test.
            let inside = if h >= 0.0 {
                s[l] > 0.0 && s[l] < f64::INFINITY
            } else {
                s[l] > f64::NEG_INFINITY && s[l] < 0.0
            };
            ok[l] &= r0[l] != 0.0 && short && inside;
        }

        // Stumpff's c₂, c₃ by their series (`stumpff`), with the term count
        // the scalar code picks for each lane.
        let s2 = zip(s, s, |a, b| a * b);
        let z = zip(beta, s2, |b, s2| b * s2);
        let mut terms = [5usize; LANES];
        let mut most = 5;
        for l in 0..LANES {
            let a = z[l].abs();
            ok[l] &= a < SERIES_LIMIT;
            terms[l] = if a < SERIES_SHORT {
                5
            } else if a < SERIES_MID {
                7
            } else if a < SERIES_LONG {
                10
            } else {
                12
            };
            if ok[l] {
                most = most.max(terms[l]);
            }
        }
        let m = map(z, |z| -z);
        let (c2, c3) = match most {
            5 => series::<5>(m, terms),
            7 => series::<7>(m, terms),
            10 => series::<10>(m, terms),
            _ => series::<12>(m, terms),
        };

        // `Orbit::evaluate`, the stopping tests and `Orbit::at_root`.
        let mut xn = [[0.0; LANES]; 3];
        let mut vn = [[0.0; LANES]; 3];
        for l in 0..LANES {
            let (s, s2, z) = (s[l], s2[l], z[l]);
            let (r0, eta, zeta, beta, gm) = (r0[l], eta[l], zeta[l], beta[l], gm[l]);
            let c0 = 1.0 - z * c2[l];
            let c1 = 1.0 - z * c3[l];
            let g0 = c0;
            let g1 = s * c1;
            let g2 = s2 * c2[l];
            let g3 = s2 * s * c3[l];
            let (a, b, c) = (r0 * s, eta * g2, zeta * g3);
            let f = a + b + c - h;
            let fp = r0 + eta * g1 + zeta * g2;
            let fpp = eta * c0 + zeta * g1;
            let scale = a.abs() + b.abs() + c.abs() + h.abs();
            let rounding = f == 0.0 || f.abs() <= 2.0 * f64::EPSILON * scale;
            let halley = if fpp.is_finite() {
                2.0 * f * fp / (2.0 * fp * fp - f * fpp)
            } else {
                f / fp
            };
            let d = if rounding { f / fp } else { halley };
            // Ends here: at rounding level, or Halley's correction small.
            // A non-finite correction takes the scalar code's other exit;
            // leave it to the scalar code. A zero one (the starter already
            // the root to rounding, common for the outer planets) leaves
            // the `Gₖ` as they are, as `Orbit::at_root` does.
            ok[l] &= (rounding || d.abs() <= self.tolerance * s.abs()) && d.is_finite();
            let keep = d == 0.0;
            let e = 0.5 * d * d;
            let n1 = if keep {
                g1
            } else {
                g1 - d * g0 - e * beta * g1
            };
            let n2 = if keep { g2 } else { g2 - d * g1 + e * g0 };
            let n3 = if keep { g3 } else { g3 - d * g2 + e * g1 };
            let r = r0 + eta * n1 + zeta * n2;

            // `drift`'s update.
            let xl = [x[0][l], x[1][l], x[2][l]];
            let vl = [v[0][l], v[1][l], v[2][l]];
            let (xo, vo) = update(gm, h, ir0[l], r, n1, n2, n3, &xl, &vl);
            for k in 0..3 {
                xn[k][l] = xo[k];
                vn[k][l] = vo[k];
                ok[l] &= xo[k].is_finite() && vo[k].is_finite();
            }
        }
        (xn, vn, ok)
    }
}
