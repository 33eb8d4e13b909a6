//! Eight Kepler drifts over the same `h` in one pass, on either
//! implementation of [`F8`] (AVX-512 or the portable arrays):
//! [`KeplerSolver::drift_lanes8`], and the kernel the Wisdom–Holman splits
//! call on their own lanes.
//!
//! The scalar solve's short-step path (the series starter, then Halley's
//! method inside the bracket `(0, ±∞)`), for up to [`LANE_EVALUATIONS`]
//! evaluations where [`drift_lanes`](KeplerSolver::drift_lanes) takes one
//! (see `lanes.rs`): the scalar solve's operations in the scalar solve's
//! order, each lane checking the scalar solve's own stopping tests and
//! keeping its result when it stops while the others step on, every choice
//! a select instead of a branch; a lane that would take another path is
//! redone by the scalar [`KeplerSolver::drift`]. So every lane is the
//! scalar drift bit for bit, on either implementation.

use super::stumpff::{
    C2, C2_1_LO, C3, C3_0_LO, C3_1_LO, SERIES_LIMIT, SERIES_LONG, SERIES_MID, SERIES_SHORT,
};
use super::{KeplerError, KeplerSolver, SHORT_STEP, SHORT_TURN};

/// The most evaluations of the universal Kepler equation the lanes take
/// before leaving a lane to the scalar solve: the starter and Halley's
/// cubic convergence end most short steps after one, the outer planets at
/// the astronomers' step (a twentieth of Jupiter's period) after two.
const LANE_EVALUATIONS: usize = 4;
use crate::simd::{F8, Kernel, Simd, W, dispatch};

/// `(c₂, c₃)` of the Stumpff series in every lane by Horner's rule with `N`
/// terms, a lane with fewer terms (`m7`: lanes with 7 or more, `m10`: lanes
/// with 10 or more, `m12`: lanes with 12) starting from zero coefficients,
/// as `lanes.rs`'s `series`.
#[inline(always)]
fn series<V: F8, const N: usize>(m: V, m7: u8, m10: u8, m12: u8) -> (V, V) {
    let zero = V::splat(0.0);
    // Lanes that sum term k (k < 5: all; 5, 6: seven or more; 7…9: ten or
    // more; 10, 11: twelve).
    let has = |k: usize| -> u8 {
        if k < 5 {
            0xff
        } else if k < 7 {
            m7
        } else if k < 10 {
            m10
        } else {
            m12
        }
    };
    let mut a = V::select(has(N - 1), V::splat(C2[N - 1]), zero);
    let mut b = V::select(has(N - 1), V::splat(C3[N - 1]), zero);
    for k in (2..N - 1).rev() {
        let p = V::select(has(k), V::splat(C2[k]), zero);
        let q = V::select(has(k), V::splat(C3[k]), zero);
        a = a.mul(m).add(p);
        b = b.mul(m).add(q);
    }
    // `series_head`.
    let c2 = V::splat(C2[0]).add(m.mul(V::splat(C2[1]).add(V::splat(C2_1_LO).add(a.mul(m)))));
    let c3 = V::splat(C3[0])
        .add(V::splat(C3_0_LO).add(m.mul(V::splat(C3[1]).add(V::splat(C3_1_LO).add(b.mul(m))))));
    (c2, c3)
}

/// `drift`'s update (`mod.rs`, `update`), lane-wise with selects.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn update<V: F8>(
    gm: V,
    h: V,
    ir0: V,
    r: V,
    g1: V,
    g2: V,
    g3: V,
    x: &[V; 3],
    v: &[V; 3],
) -> ([V; 3], [V; 3]) {
    let one = V::splat(1.0);
    let ir = one.div(r);
    let gm_g2 = gm.mul(g2);
    let fm1_direct = gm_g2.neg().mul(ir0);
    let gg = h.sub(gm.mul(g3));
    let a = gm.mul(g1).mul(ir0).mul(gg);
    let fd = gm.neg().mul(g1).mul(ir0).mul(ir);
    let gdm1_direct = gm_g2.neg().mul(ir);
    let f_r = one.add(fm1_direct).mul(r);
    let gd_r = r.sub(gm_g2);
    let identity =
        a.abs().le(V::splat(2.0).mul(r)) & V::splat(0.5).mul(r).le(f_r.abs().max(gd_r.abs()));
    let big_f = gd_r.abs().le(f_r.abs());
    let num = V::select(big_f, a.add(fm1_direct.mul(r)).neg(), gm_g2.sub(a));
    let den = V::select(big_f, f_r, gd_r);
    let q = num.div(den);
    let fm1 = V::select(identity & !big_f, q, fm1_direct);
    let gdm1 = V::select(identity & big_f, q, gdm1_direct);
    let mut xn = *x;
    let mut vn = *v;
    for k in 0..3 {
        xn[k] = x[k].add(fm1.mul(x[k]).add(gg.mul(v[k])));
        vn[k] = v[k].add(fd.mul(x[k]).add(gdm1.mul(v[k])));
    }
    (xn, vn)
}

#[inline(always)]
fn dot<V: F8>(a: &[V; 3], b: &[V; 3]) -> V {
    a[0].mul(b[0]).add(a[1].mul(b[1])).add(a[2].mul(b[2]))
}

impl KeplerSolver {
    /// The scalar solve's short-step path in eight lanes: the series
    /// starter and up to [`LANE_EVALUATIONS`] Halley steps inside the
    /// bracket, operation for operation, and the mask of the lanes for
    /// which that path is the one the scalar solve takes and ends on. `h`
    /// must be finite and nonzero and `max_iterations` positive (else no
    /// lane is the scalar solve's).
    #[allow(clippy::type_complexity)]
    #[inline(always)]
    pub(crate) fn quick8<V: F8>(
        &self,
        gm: V,
        h: f64,
        x: &[V; 3],
        v: &[V; 3],
    ) -> ([V; 3], [V; 3], u8) {
        if !(h.is_finite() && h != 0.0 && self.max_iterations > 0) {
            return (*x, *v, 0);
        }
        let zero = V::splat(0.0);
        let inf = V::splat(f64::INFINITY);
        let hv = V::splat(h);
        let short_step = V::splat(SHORT_STEP);
        let mut ok = gm.finite() & zero.lt(gm);
        for k in 0..3 {
            ok &= x[k].finite() & v[k].finite();
        }
        let r0 = dot(x, x).sqrt();
        let v2 = dot(v, v);
        let eta = dot(x, v);
        let beta = V::splat(2.0).mul(gm).div(r0).sub(v2);
        let ir0 = V::splat(1.0).div(r0);

        // The series starter.
        let zeta = gm.sub(beta.mul(r0));
        let u = hv.mul(ir0);
        let p = V::splat(0.5).mul(eta).mul(ir0);
        let pu = p.mul(u);
        let bu2 = beta.mul(u).mul(u);
        let short_turn = V::splat(SHORT_TURN);
        let short = pu.abs().lt(short_step)
            & bu2.abs().lt(short_turn)
            & gm.mul(u).mul(u).mul(ir0).lt(short_turn);
        let q = zeta.mul(ir0).mul(V::splat(1.0 / 6.0));
        let t = beta.neg().mul(eta).mul(ir0).mul(V::splat(1.0 / 24.0));
        let c3 = V::splat(2.0).mul(p).mul(p).sub(q);
        let c4 = V::splat(5.0).mul(p).mul(q.sub(p.mul(p))).sub(t);
        let s = u.mul(V::splat(1.0).add(u.mul(p.neg().add(u.mul(c3.add(u.mul(c4)))))));
        let inside = if h >= 0.0 {
            zero.lt(s) & s.lt(inf)
        } else {
            inf.neg().lt(s) & s.lt(zero)
        };
        ok &= !r0.eq(zero) & short & inside;

        // Halley's method as the scalar loop runs it from the series
        // starter, every lane at once: a lane that stops (the residual at
        // rounding level, or a correction below the tolerance) keeps the
        // `Gₖ` carried to its root; the others step on inside their
        // bracket. A lane whose iterate would leave the bracket (where the
        // scalar code bisects), whose `|z|` leaves the series, or that has
        // not stopped after `LANE_EVALUATIONS` is left to the scalar code.
        let one = V::splat(1.0);
        let two = V::splat(2.0);
        let tol = V::splat(self.tolerance);
        let (mut lo, mut hi) = if h >= 0.0 {
            (zero, inf)
        } else {
            (inf.neg(), zero)
        };
        let mut s = s;
        let mut done = 0u8;
        let (mut n1, mut n2, mut n3, mut r) = (zero, zero, zero, zero);
        for _ in 0..LANE_EVALUATIONS.min(self.max_iterations) {
            let active = ok & !done;
            if active == 0 {
                break;
            }
            // Stumpff's c₂, c₃ with the scalar code's term count per lane.
            let s2 = s.mul(s);
            let z = beta.mul(s2);
            let az = z.abs();
            ok &= !active | az.lt(V::splat(SERIES_LIMIT));
            let active = ok & !done;
            let m7 = !az.lt(V::splat(SERIES_SHORT));
            let m10 = !az.lt(V::splat(SERIES_MID));
            let m12 = !az.lt(V::splat(SERIES_LONG));
            let m = z.neg();
            let (c2, c3) = if active & m12 != 0 {
                series::<V, 12>(m, m7, m10, m12)
            } else if active & m10 != 0 {
                series::<V, 10>(m, m7, m10, m12)
            } else if active & m7 != 0 {
                series::<V, 7>(m, m7, m10, m12)
            } else {
                series::<V, 5>(m, m7, m10, m12)
            };

            // `Orbit::evaluate`, the stopping tests and `Orbit::at_root`.
            let c0 = one.sub(z.mul(c2));
            let c1 = one.sub(z.mul(c3));
            let g0 = c0;
            let g1 = s.mul(c1);
            let g2 = s2.mul(c2);
            let g3 = s2.mul(s).mul(c3);
            let (a, b, c) = (r0.mul(s), eta.mul(g2), zeta.mul(g3));
            let f = a.add(b).add(c).sub(hv);
            let fp = r0.add(eta.mul(g1)).add(zeta.mul(g2));
            let fpp = eta.mul(c0).add(zeta.mul(g1));
            let scale = a.abs().add(b.abs()).add(c.abs()).add(hv.abs());
            let rounding = f.eq(zero) | f.abs().le(V::splat(2.0 * f64::EPSILON).mul(scale));
            let newton = f.div(fp);
            let halley = V::select(
                fpp.finite(),
                two.mul(f).mul(fp).div(two.mul(fp).mul(fp).sub(f.mul(fpp))),
                newton,
            );
            let d = V::select(rounding, newton, halley);
            let stop = active & (rounding | d.abs().le(tol.mul(s.abs())));
            // A non-finite correction takes the scalar code's other exit;
            // leave it to the scalar code. A zero one (the starter already
            // the root to rounding, common for the outer planets) leaves
            // the `Gₖ` as they are, as `Orbit::at_root` does.
            ok &= !stop | d.finite();
            let stop = stop & ok;
            if stop != 0 {
                let keep = d.eq(zero);
                let e = V::splat(0.5).mul(d).mul(d);
                let k1 = V::select(keep, g1, g1.sub(d.mul(g0)).sub(e.mul(beta).mul(g1)));
                let k2 = V::select(keep, g2, g2.sub(d.mul(g1)).add(e.mul(g0)));
                let k3 = V::select(keep, g3, g3.sub(d.mul(g2)).add(e.mul(g1)));
                n1 = V::select(stop, k1, n1);
                n2 = V::select(stop, k2, n2);
                n3 = V::select(stop, k3, n3);
                r = V::select(stop, r0.add(eta.mul(k1)).add(zeta.mul(k2)), r);
                done |= stop;
            }
            // The others: the bracket tightened as the scalar loop does
            // (`F < 0`: the root is above `s`), then the Halley step.
            let go = active & !stop;
            if go != 0 {
                lo = V::select(go & f.lt(zero), s, lo);
                hi = V::select(go & zero.lt(f), s, hi);
                let next = s.sub(d);
                ok &= !go | (lo.lt(next) & next.lt(hi) & next.finite());
                s = V::select(go, next, s);
            }
        }
        ok &= done;
        let (xn, vn) = update(gm, hv, ir0, r, n1, n2, n3, x, v);
        for k in 0..3 {
            ok &= xn[k].finite() & vn[k].finite();
        }
        (xn, vn, ok)
    }

    /// [`drift`](Self::drift) of up to eight independent orbits over the
    /// same `h` in one pass, on the chosen implementation of the eight
    /// lanes ([`Simd`]): lane `l < used` has `GM = gm[l]` and state
    /// `(x[l], v[l])`; lanes from `used` on are left alone. Every lane's
    /// result is bit for bit what `drift` gives it, on either
    /// implementation.
    ///
    /// Errors: as [`drift_lanes`](Self::drift_lanes).
    pub fn drift_lanes8(
        &self,
        gm: &[f64; W],
        h: f64,
        x: &mut [[f64; 3]; W],
        v: &mut [[f64; 3]; W],
        used: usize,
        simd: Simd,
    ) -> Result<(), (usize, KeplerError)> {
        let used = used.min(W);
        // Padding lanes repeat lane 0, so that they compute harmlessly.
        let pad = |a: &[f64; W]| {
            let mut o = *a;
            o[used..].fill(a[0]);
            o
        };
        let coord = |a: &[[f64; 3]; W], k: usize| pad(&a.map(|c| c[k]));
        let g = pad(gm);
        let xs = [0, 1, 2].map(|k| coord(x, k));
        let vs = [0, 1, 2].map(|k| coord(v, k));
        let (xn, vn, ok) = dispatch(
            simd,
            Quick8 {
                solver: self,
                gm: g,
                h,
                x: xs,
                v: vs,
            },
        );
        for l in 0..used {
            if ok >> l & 1 == 1 {
                x[l] = [xn[0][l], xn[1][l], xn[2][l]];
                v[l] = [vn[0][l], vn[1][l], vn[2][l]];
            } else {
                self.drift(gm[l], h, &mut x[l], &mut v[l])
                    .map_err(|e| (l, e))?;
            }
        }
        Ok(())
    }
}

type Lanes3 = [[f64; W]; 3];

/// [`KeplerSolver::quick8`] on arrays, as a [`Kernel`].
struct Quick8<'a> {
    solver: &'a KeplerSolver,
    gm: [f64; W],
    h: f64,
    x: Lanes3,
    v: Lanes3,
}

impl Kernel for Quick8<'_> {
    type Out = (Lanes3, Lanes3, u8);
    #[inline(always)]
    fn run<V: F8>(self) -> Self::Out {
        let x = self.x.map(V::from_array);
        let v = self.v.map(V::from_array);
        let (xn, vn, ok) = self.solver.quick8(V::from_array(self.gm), self.h, &x, &v);
        (xn.map(F8::to_array), vn.map(F8::to_array), ok)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::Portable;
    use std::f64::consts::PI;

    /// A test orbit: `(x, v, period)`.
    type Orbit = ([f64; 3], [f64; 3], f64);

    /// Eight planet-like orbits (GM = 1, e from 0 to 0.1, different phases
    /// and radii).
    fn planets() -> Vec<Orbit> {
        (0..W)
            .map(|l| {
                let fl = l as f64;
                let (a, e, th) = (1.0 + 0.15 * fl, 0.0125 * fl, 0.8 * fl);
                // At the pericentre, turned by th.
                let r = a * (1.0 - e);
                let speed = ((1.0 + e) / r).sqrt();
                let x = [r * th.cos(), r * th.sin(), 0.02 * r];
                let v = [-speed * th.sin(), speed * th.cos(), 0.0];
                (x, v, 2.0 * PI * a.powf(1.5))
            })
            .collect()
    }

    #[test]
    fn every_planet_stays_in_its_lane_up_to_a_fifth_of_a_period() {
        // Steps up to P/5 of the innermost orbit take the lanes' Halley
        // steps (two or three evaluations at the long end) in every lane,
        // and give the scalar drift bit for bit.
        let solver = KeplerSolver::default();
        let orbits = planets();
        for frac in [1e-3, 0.02, 0.05, 0.1, 0.15, 0.2, -0.2] {
            let h = frac * orbits[0].2;
            let lanes = |k: usize, f: &dyn Fn(&Orbit) -> [f64; 3]| {
                Portable(std::array::from_fn(|l| f(&orbits[l])[k]))
            };
            let x = [0, 1, 2].map(|k| lanes(k, &|o| o.0));
            let v = [0, 1, 2].map(|k| lanes(k, &|o| o.1));
            let (xn, vn, ok) = solver.quick8(Portable::splat(1.0), h, &x, &v);
            assert_eq!(ok, 0xff, "h = {frac} P: lanes left to the scalar solve");
            for (l, o) in orbits.iter().enumerate() {
                let (mut xs, mut vs) = (o.0, o.1);
                solver.drift(1.0, h, &mut xs, &mut vs).unwrap();
                for k in 0..3 {
                    assert_eq!(
                        xn[k].0[l].to_bits(),
                        xs[k].to_bits(),
                        "h = {frac} P, lane {l}"
                    );
                    assert_eq!(
                        vn[k].0[l].to_bits(),
                        vs[k].to_bits(),
                        "h = {frac} P, lane {l}"
                    );
                }
            }
        }
    }
}
