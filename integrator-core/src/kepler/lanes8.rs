//! Eight Kepler drifts over the same `h` in one pass, on either
//! implementation of [`F8`] (AVX-512 or the portable arrays):
//! [`KeplerSolver::drift_lanes8`], and the kernel the Wisdom–Holman splits
//! call on their own lanes.
//!
//! The same one-evaluation path as [`drift_lanes`](KeplerSolver::drift_lanes)
//! (see `lanes.rs`): the scalar solve's operations in the scalar solve's
//! order, each lane checking the scalar solve's own stopping tests, every
//! choice a select instead of a branch; a lane that would take another path
//! is redone by the scalar [`KeplerSolver::drift`]. So every lane is the
//! scalar drift bit for bit, on either implementation.

use super::stumpff::{C2, C2_1_LO, C3, C3_0_LO, C3_1_LO, SERIES_LIMIT, SERIES_MID, SERIES_SHORT};
use super::{KeplerError, KeplerSolver, SHORT_STEP};
use crate::simd::{F8, Kernel, Simd, W, dispatch};

/// `(c₂, c₃)` of the Stumpff series in every lane by Horner's rule with `N`
/// terms, a lane with fewer terms (`m7`: lanes with 7 or more, `m10`: lanes
/// with 10) starting from zero coefficients, as `lanes.rs`'s `series`.
#[inline(always)]
fn series<V: F8, const N: usize>(m: V, m7: u8, m10: u8) -> (V, V) {
    let zero = V::splat(0.0);
    // Lanes that sum term k (k < 5: all; 5, 6: seven or more; 7…9: ten).
    let has = |k: usize| -> u8 {
        if k < 5 {
            0xff
        } else if k < 7 {
            m7
        } else {
            m10
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
    /// The scalar solve's one-evaluation path in eight lanes (`lanes.rs`'s
    /// `quick`, operation for operation), and the mask of the lanes for
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
        let short = pu.abs().lt(short_step)
            & bu2.abs().lt(short_step)
            & gm.mul(u).mul(u).mul(ir0).lt(short_step);
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

        // Stumpff's c₂, c₃ with the scalar code's term count per lane.
        let s2 = s.mul(s);
        let z = beta.mul(s2);
        let az = z.abs();
        ok &= az.lt(V::splat(SERIES_LIMIT));
        let m7 = !az.lt(V::splat(SERIES_SHORT));
        let m10 = !az.lt(V::splat(SERIES_MID));
        let m = z.neg();
        let (c2, c3) = if ok & m10 != 0 {
            series::<V, 10>(m, m7, m10)
        } else if ok & m7 != 0 {
            series::<V, 7>(m, m7, m10)
        } else {
            series::<V, 5>(m, m7, m10)
        };

        // `Orbit::evaluate`, the stopping tests and `Orbit::at_root`.
        let one = V::splat(1.0);
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
        let two = V::splat(2.0);
        let halley = V::select(
            fpp.finite(),
            two.mul(f).mul(fp).div(two.mul(fp).mul(fp).sub(f.mul(fpp))),
            newton,
        );
        let d = V::select(rounding, newton, halley);
        // A non-finite correction takes the scalar code's other exit;
        // leave it to the scalar code. A zero one (the starter already the
        // root to rounding, common for the outer planets) leaves the `Gₖ`
        // as they are, as `Orbit::at_root` does.
        ok &= (rounding | d.abs().le(V::splat(self.tolerance).mul(s.abs()))) & d.finite();
        let keep = d.eq(zero);
        let e = V::splat(0.5).mul(d).mul(d);
        let n1 = V::select(keep, g1, g1.sub(d.mul(g0)).sub(e.mul(beta).mul(g1)));
        let n2 = V::select(keep, g2, g2.sub(d.mul(g1)).add(e.mul(g0)));
        let n3 = V::select(keep, g3, g3.sub(d.mul(g2)).add(e.mul(g1)));
        let r = r0.add(eta.mul(n1)).add(zeta.mul(n2));
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
