//! The Wisdom–Holman parts of up to eight planets in eight lanes (one
//! planet a lane, lane `l` body `l + 1`), on either implementation of
//! [`F8`]: the Kepler flows of all planets in one pass, the interaction
//! kicks (plain, lazy and exact modified) with every pair of planets at
//! once (below), no allocation and no
//! branch on the number of planets beyond the masks built once.
//!
//! # The pairs
//!
//! The mutual forces of `p` planets are taken in `⌊p/2⌋` rotations: in
//! rotation `k`, lane `l` meets planet `(l + k) mod p`. Each lane adds the
//! force its partner exerts on it, and the equal and opposite force is
//! rotated back by `k` lanes and added to the partner; for even `p` the last
//! rotation (`k = p/2`) meets every pair twice, so only its first `p/2`
//! lanes count. Every pair once, with `⌊p/2⌋` vector square roots and
//! divisions (two for five planets, against ten scalar ones).
//!
//! The sums run in a fixed order of their own (not the scalar kernels'
//! body by body), the same on both implementations: see
//! [`crate::simd`].

// Lane loops index several arrays at once.
#![allow(clippy::needless_range_loop)]

use crate::kepler::KeplerSolver;
use crate::simd::{F8, Kernel, W, first};

/// The lanes' constants for `p ≤ 8` planets: lane `l` is body `l + 1`.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Lanes {
    /// Planets (used lanes).
    pub p: usize,
    /// The mask of the used lanes.
    pub used: u8,
    /// The planets' masses (0 in unused lanes).
    pub m: [f64; W],
    /// `GM` of each planet's Kepler problem (unused lanes repeat lane 0).
    pub gm: [f64; W],
    /// The mass that turns momentum into velocity in the Kepler flow
    /// (unused lanes repeat lane 0).
    pub mv: [f64; W],
    /// The rotations that meet every pair of planets once.
    pub rotations: Vec<Rotation>,
}

/// One rotation of the pairs (see the [module documentation](self)).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Rotation {
    /// Lane `l`'s partner.
    pub to: [u64; W],
    /// The lane whose partner lane `l` is.
    pub back: [u64; W],
    /// The lanes that count.
    pub mask: u8,
    /// The partner's mass.
    pub m_to: [f64; W],
    /// Lane `l`'s mass times its partner's.
    pub mm: [f64; W],
}

impl Lanes {
    /// Lane constants for the planets `1 … n − 1` of `masses` (`None` for
    /// more than eight planets); `gm(i)`, `mv(i)` for body `i`.
    pub fn new(
        masses: &[f64],
        gm: impl Fn(usize) -> f64,
        mv: impl Fn(usize) -> f64,
    ) -> Option<Self> {
        let p = masses.len().checked_sub(1)?;
        if p == 0 || p > W {
            return None;
        }
        let lane = |f: &dyn Fn(usize) -> f64, pad: bool| {
            let mut out = [0.0; W];
            for l in 0..W {
                out[l] = if l < p {
                    f(l + 1)
                } else if pad {
                    f(1)
                } else {
                    0.0
                };
            }
            out
        };
        let m = lane(&|i| masses[i], false);
        let mut rotations = Vec::new();
        for k in 1..=p / 2 {
            let mut to = [0u64; W];
            let mut back = [0u64; W];
            for l in 0..W {
                (to[l], back[l]) = if l < p {
                    (((l + k) % p) as u64, ((l + p - k) % p) as u64)
                } else {
                    (l as u64, l as u64)
                };
            }
            let mask = if 2 * k == p { first(k) } else { first(p) };
            let m_to = to.map(|j| m[j as usize]);
            let mut mm = [0.0; W];
            for l in 0..W {
                mm[l] = m[l] * m_to[l];
            }
            rotations.push(Rotation {
                to,
                back,
                mask,
                m_to,
                mm,
            });
        }
        Some(Self {
            p,
            used: first(p),
            m,
            gm: lane(&gm, true),
            mv: lane(&mv, true),
            rotations,
        })
    }

    /// The Kepler flow of the planets over `h`, `q`, `pm` their positions
    /// and momenta (`3p` numbers each), written for the lanes whose result
    /// is the scalar drift's (see [`KeplerSolver::quick8`]); returns their
    /// mask. The other planets are left as they were, for the caller to
    /// drift one way or another (a planet whose step leaves the short-step
    /// path of the scalar solve, while the others stay on it).
    #[inline(always)]
    pub fn kepler<V: F8>(
        &self,
        solver: &KeplerSolver,
        h: f64,
        q: &mut [f64],
        pm: &mut [f64],
    ) -> u8 {
        let x = V::load3(q, self.p);
        let pp = V::load3(pm, self.p);
        let (xo, po, ok) = self.kepler_regs(solver, h, &x, &pp);
        if ok == 0 {
            return 0;
        }
        V::store3(&xo, q, self.p);
        V::store3(&po, pm, self.p);
        ok
    }

    /// [`kepler`](Self::kepler) on positions and momenta in lanes (unused
    /// lanes 0, as [`F8::load3`] leaves them): the new ones, a lane not
    /// done keeping its own numbers bit for bit, and the mask of the lanes
    /// done.
    #[inline(always)]
    pub fn kepler_regs<V: F8>(
        &self,
        solver: &KeplerSolver,
        h: f64,
        x: &[V; 3],
        pp: &[V; 3],
    ) -> ([V; 3], [V; 3], u8) {
        let zero = [0u64; W];
        let mv = V::from_array(self.mv);
        let mut xs = *x;
        // Divided by m, not multiplied by a rounded 1/m: that rounding
        // would be the same at every step, and `(p·(1/m))·m` a bias of the
        // momentum of the same sign every step (measured: the error of
        // wh:whckl-c17 at h = 2 days over 10⁵ days 37 times larger,
        // examples/wh_error.rs).
        let mut v = pp.map(|c| c.div(mv));
        // Unused lanes repeat lane 0, so that they compute harmlessly.
        for k in 0..3 {
            xs[k] = V::select(self.used, xs[k], xs[k].permute(&zero));
            v[k] = V::select(self.used, v[k], v[k].permute(&zero));
        }
        let (xn, vn, ok) = solver.quick8(V::from_array(self.gm), h, &xs, &v);
        let ok = ok & self.used;
        // A lane not done keeps its own numbers, bit for bit.
        let mut xo = *x;
        let mut po = *pp;
        for k in 0..3 {
            xo[k] = V::select(ok, xn[k], x[k]);
            po[k] = V::select(ok, vn[k].mul(mv), pp[k]);
        }
        (xo, po, ok)
    }

    /// The planets' mutual accelerations at positions `x` (all lanes):
    /// lane `l` gets `Σ_j G mⱼ (xⱼ − xₗ)/|xⱼ − xₗ|³` over the other
    /// planets, added to `a`.
    #[inline(always)]
    pub fn mutual<V: F8>(&self, g: f64, x: &[V; 3], a: &mut [V; 3]) {
        let zero = V::splat(0.0);
        let m = V::from_array(self.m);
        for rot in &self.rotations {
            let mut d = *x;
            for k in 0..3 {
                d[k] = x[k].permute(&rot.to).sub(x[k]);
            }
            let r2 = d[0].mul(d[0]).add(d[1].mul(d[1])).add(d[2].mul(d[2]));
            let s = V::splat(g).div(r2.mul(r2.sqrt()));
            let s = V::select(rot.mask, s, zero);
            let (si, sj) = (s.mul(V::from_array(rot.m_to)), s.mul(m));
            for k in 0..3 {
                a[k] = a[k].add(si.mul(d[k]));
                a[k] = a[k].sub(sj.mul(d[k]).permute(&rot.back));
            }
        }
    }

    /// The democratic heliocentric kick `Pᵢ += h·G Σⱼ mᵢmⱼ (Qⱼ − Qᵢ)/|Qⱼ − Qᵢ|³`
    /// on the lanes `p` from positions `x`.
    #[inline(always)]
    pub fn mutual_kick<V: F8>(&self, hg: f64, x: &[V; 3], p: &mut [V; 3]) {
        let zero = V::splat(0.0);
        for rot in &self.rotations {
            let mut d = *x;
            for k in 0..3 {
                d[k] = x[k].permute(&rot.to).sub(x[k]);
            }
            let r2 = d[0].mul(d[0]).add(d[1].mul(d[1])).add(d[2].mul(d[2]));
            let s = V::splat(hg)
                .mul(V::from_array(rot.mm))
                .div(r2.mul(r2.sqrt()));
            let s = V::select(rot.mask, s, zero);
            for k in 0..3 {
                let f = s.mul(d[k]);
                p[k] = p[k].add(f);
                p[k] = p[k].sub(f.permute(&rot.back));
            }
        }
    }

    /// Up to `n` democratic heliocentric steps in lanes, the state kept in
    /// registers from step to step: step `k` is `I K I J` — the
    /// interaction kick over `hg/G`, the Kepler flow over `h`, the kick
    /// again, and the jump of every position by `f·ΣPᵢ` (`f` = the jump's
    /// time over the central mass; `f_last` for the last step), the step of
    /// [`DemocraticHeliocentric::integrate`](super::DemocraticHeliocentric::integrate)
    /// after its first half jump. It stops before a step whose kick or jump
    /// is not finite or whose Kepler flow leaves a lane to the scalar
    /// solve, with the state as that step found it, and returns the steps
    /// done: each the same operations as the flows one by one
    /// ([`MutualKick`], [`Lanes::kepler`], the jump's sum in body order),
    /// so the same bits.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn democratic_run<V: F8>(
        &self,
        hg: f64,
        h: f64,
        f: f64,
        f_last: f64,
        n: usize,
        q: &mut [f64],
        pm: &mut [f64],
    ) -> usize {
        let p = self.p;
        let used = self.used;
        let solver = KeplerSolver::default();
        let finite = |v: &[V; 3]| v[0].finite() & v[1].finite() & v[2].finite();
        let mut x = V::load3(q, p);
        let mut pv = V::load3(pm, p);
        let mut done = 0;
        while done < n {
            let f = if done + 1 < n { f } else { f_last };
            let mut kicked = pv;
            self.mutual_kick(hg, &x, &mut kicked);
            if finite(&kicked) != 0xff {
                break;
            }
            let (xn, mut pn, ok) = self.kepler_regs(&solver, h, &x, &kicked);
            if ok != used {
                break;
            }
            self.mutual_kick(hg, &xn, &mut pn);
            if finite(&pn) != 0xff {
                break;
            }
            // The jump: ΣPᵢ summed body by body from 0, as the flow sums it.
            let mut sum = [0.0; 3];
            for k in 0..3 {
                let lanes = pn[k].to_array();
                for l in 0..p {
                    sum[k] += lanes[l];
                }
            }
            let d = sum.map(|c| c * f);
            if !d.iter().all(|c| c.is_finite()) {
                break;
            }
            for k in 0..3 {
                x[k] = V::select(used, xn[k].add(V::splat(d[k])), xn[k]);
            }
            pv = pn;
            done += 1;
        }
        V::store3(&x, q, p);
        V::store3(&pv, pm, p);
        done
    }

    /// The derivative of [`mutual`](Self::mutual)'s accelerations along
    /// the displacement `dx` of the positions `x`: lane `l` gets
    /// `Σ_j mⱼ G (δd/r³ − 3(d·δd) d/r⁵)` over the other planets (`d = xⱼ −
    /// xₗ`, `δd = δxⱼ − δxₗ`), each pair's tidal term once, added to `da`.
    #[inline(always)]
    pub fn mutual_tidal<V: F8>(&self, g: f64, x: &[V; 3], dx: &[V; 3], da: &mut [V; 3]) {
        let zero = V::splat(0.0);
        let three = V::splat(3.0);
        let m = V::from_array(self.m);
        for rot in &self.rotations {
            let (mut d, mut dd) = (*x, *dx);
            for k in 0..3 {
                d[k] = x[k].permute(&rot.to).sub(x[k]);
                dd[k] = dx[k].permute(&rot.to).sub(dx[k]);
            }
            let r2 = dot(&d, &d);
            // Lanes that do not count (a lane its own partner: 0/0) to 0.
            let s = V::select(rot.mask, V::splat(g).div(r2.mul(r2.sqrt())), zero);
            let t = V::select(rot.mask, three.mul(dot(&d, &dd)).div(r2), zero);
            let m_to = V::from_array(rot.m_to);
            for k in 0..3 {
                let tidal = s.mul(dd[k].sub(t.mul(d[k])));
                da[k] = da[k].add(m_to.mul(tidal));
                da[k] = da[k].sub(m.mul(tidal).permute(&rot.back));
            }
        }
    }
}

#[inline(always)]
fn dot<V: F8>(a: &[V; 3], b: &[V; 3]) -> V {
    a[0].mul(b[0]).add(a[1].mul(b[1])).add(a[2].mul(b[2]))
}

/// Which kick the Jacobi lanes take.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum LaneKick {
    /// `Pᵢ += h·m'ᵢQ̈ᵢ`.
    Plain,
    /// The lazy implementer's modified kick: the accelerations taken at
    /// `Q + δ·Q̈(Q)` (the weight `δ`).
    Lazy(f64),
    /// The exact modified kick `Pᵢ += h·m'ᵢQ̈ᵢ + 2γ·m'ᵢ·DQ̈ᵢ[Q̈]` (the
    /// weight `γ`).
    Exact(f64),
}

/// The Jacobi split's own lane constants.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct JacobiLanes {
    pub lanes: Lanes,
    /// `mᵢ/Mᵢ` (0 in unused lanes).
    pub f: [f64; W],
    /// `1/M_{i−1}`.
    pub inv_prev: [f64; W],
    /// `m'ᵢ` (0 in unused lanes).
    pub reduced: [f64; W],
    /// `m₀`.
    pub m0: f64,
    /// `G`.
    pub g: f64,
}

impl JacobiLanes {
    /// The inertial positions relative to the barycentre of the Jacobi
    /// positions `q` (lanes): the planets' `xᵢ = Qᵢ − Σ_{k≥i} fₖQₖ` and the
    /// Sun's `x₀ = −Σ_{k≥1} fₖQₖ` in every lane. Linear in `q`, so also the
    /// inertial displacement of a Jacobi one.
    #[inline(always)]
    fn inertial<V: F8>(&self, q: &[V; 3]) -> ([V; 3], [V; 3]) {
        let zero = V::splat(0.0);
        let all0 = [0u64; W];
        let f = V::from_array(self.f);
        let mut x = *q;
        let mut x0 = [zero; 3];
        for k in 0..3 {
            let s = f.mul(q[k]).suffix_sum();
            x[k] = q[k].sub(s);
            x0[k] = s.permute(&all0).neg();
        }
        (x, x0)
    }

    /// The Jacobi accelerations of the interaction, `Q̈ᵢ = aᵢ − Σ_{j<i}
    /// mⱼaⱼ/M_{i−1} + G Mᵢ Qᵢ/|Qᵢ|³ = aᵢ + Σ_{j≥i} mⱼaⱼ/M_{i−1} + G Mᵢ Qᵢ/|Qᵢ|³`, at Jacobi positions `q` (lanes).
    #[inline(always)]
    pub fn accelerations<V: F8>(&self, q: &[V; 3]) -> [V; 3] {
        self.accelerations_x(q).0
    }

    /// [`accelerations`](Self::accelerations), with the inertial positions
    /// it took them at ([`inertial`](Self::inertial)).
    #[allow(clippy::type_complexity)]
    #[inline(always)]
    fn accelerations_x<V: F8>(&self, q: &[V; 3]) -> ([V; 3], [V; 3], [V; 3]) {
        let l = &self.lanes;
        let zero = V::splat(0.0);
        let g = V::splat(self.g);
        let m = V::from_array(l.m);
        let (x, x0) = self.inertial(q);
        // The Sun and each planet.
        let mut d = x;
        for k in 0..3 {
            d[k] = x[k].sub(x0[k]);
        }
        let r2 = d[0].mul(d[0]).add(d[1].mul(d[1])).add(d[2].mul(d[2]));
        let s = V::select(l.used, g.div(r2.mul(r2.sqrt())), zero);
        let s0 = s.mul(V::splat(self.m0));
        let mut a = [zero; 3];
        for k in 0..3 {
            a[k] = s0.mul(d[k]).neg();
        }
        // The planets with each other.
        l.mutual(self.g, &x, &mut a);
        // Jacobi: minus the interior bodies' weighted mean, plus the Kepler
        // term's. The forces are pairwise, so `Σ_{j<i} mⱼaⱼ = −Σ_{j≥i}
        // mⱼaⱼ` (the Sun's acceleration is not needed): a suffix sum over
        // the planets, no longer than the prefix sum from the Sun's.
        let inv = V::from_array(self.inv_prev);
        let r2 = q[0].mul(q[0]).add(q[1].mul(q[1])).add(q[2].mul(q[2]));
        let kep = V::from_array(l.gm).div(r2.mul(r2.sqrt()));
        let mut qdd = a;
        for k in 0..3 {
            let acc = m.mul(a[k]).suffix_sum();
            qdd[k] = a[k].add(acc.mul(inv)).add(kep.mul(q[k]));
            // Unused lanes (Q = 0, so 0·∞ there) to 0: the gradient kick
            // sums the shifted positions across the lanes.
            qdd[k] = V::select(l.used, qdd[k], zero);
        }
        (qdd, x, x0)
    }

    /// The exact modified kick `Pᵢ += h·m'ᵢQ̈ᵢ + 2γ·m'ᵢ·DQ̈ᵢ[Q̈]` on
    /// positions and momenta in lanes, the lanes' form of
    /// [`Jacobi::interaction_kick_modified`](super::Jacobi::interaction_kick_modified):
    /// the inertial displacement `δx` of `w = Q̈`, the Sun's and every
    /// pair's tidal term `G mⱼ (δd/r³ − 3(d·δd) d/r⁵)`, the Jacobi
    /// combination (a suffix sum, as in [`accelerations`](Self::accelerations):
    /// the tidal terms are pairwise too) and the Kepler term's derivative
    /// `G Mᵢ (wᵢ/|Qᵢ|³ − 3(Qᵢ·wᵢ) Qᵢ/|Qᵢ|⁵)`. The mask of the lanes whose
    /// new momentum is finite.
    #[inline(always)]
    pub fn modified_regs<V: F8>(&self, h: f64, gamma: f64, q: &[V; 3], pv: &mut [V; 3]) -> u8 {
        let l = &self.lanes;
        let zero = V::splat(0.0);
        let three = V::splat(3.0);
        let (w, x, x0) = self.accelerations_x(q);
        let (dx, dx0) = self.inertial(&w);
        // The Sun with each planet (`d = xᵢ − x₀`): planet i gets
        // `−m₀·tidal`.
        let (mut d, mut dd) = (x, dx);
        for k in 0..3 {
            d[k] = x[k].sub(x0[k]);
            dd[k] = dx[k].sub(dx0[k]);
        }
        let r2 = dot(&d, &d);
        let s = V::select(l.used, V::splat(self.g).div(r2.mul(r2.sqrt())), zero);
        let t = V::select(l.used, three.mul(dot(&d, &dd)).div(r2), zero);
        let m0 = V::splat(self.m0);
        let mut da = [zero; 3];
        for k in 0..3 {
            da[k] = m0.mul(s.mul(dd[k].sub(t.mul(d[k])))).neg();
        }
        l.mutual_tidal(self.g, &x, &dx, &mut da);
        let m = V::from_array(l.m);
        let inv = V::from_array(self.inv_prev);
        let r2 = dot(q, q);
        let kep = V::from_array(l.gm).div(r2.mul(r2.sqrt()));
        let tq = three.mul(dot(q, &w)).div(r2);
        let reduced = V::from_array(self.reduced);
        let hm = V::splat(h).mul(reduced);
        let gm = V::splat(2.0 * gamma).mul(reduced);
        let mut ok = 0xff;
        for k in 0..3 {
            let acc = m.mul(da[k]).suffix_sum();
            let dq = da[k].add(acc.mul(inv)).add(kep.mul(w[k].sub(tq.mul(q[k]))));
            // Unused lanes (Q = 0: 0/0 there) to 0.
            let dq = V::select(l.used, dq, zero);
            pv[k] = pv[k].add(hm.mul(w[k]).add(gm.mul(dq)));
            ok &= pv[k].finite();
        }
        ok
    }

    /// The kick `kind` over `h` (`Pᵢ += h·m'ᵢQ̈ᵢ`, the accelerations taken
    /// at `Q + δ·Q̈(Q)` for the lazy implementer's modified kick, or the
    /// exact modified kick); `q`, `pm` the planets' positions and momenta.
    /// The mask of the lanes whose new momentum is finite.
    #[inline(always)]
    pub fn kick<V: F8>(&self, h: f64, kind: LaneKick, q: &[f64], pm: &mut [f64]) -> u8 {
        let p = self.lanes.p;
        let qv = V::load3(q, p);
        let mut pv = V::load3(pm, p);
        let ok = self.kick_regs(h, kind, &qv, &mut pv);
        V::store3(&pv, pm, p);
        ok
    }

    /// [`kick`](Self::kick) on positions and momenta in lanes.
    #[inline(always)]
    pub fn kick_regs<V: F8>(&self, h: f64, kind: LaneKick, qv: &[V; 3], pv: &mut [V; 3]) -> u8 {
        let delta = match kind {
            LaneKick::Exact(gamma) => return self.modified_regs(h, gamma, qv, pv),
            LaneKick::Lazy(delta) => Some(delta),
            LaneKick::Plain => None,
        };
        let mut qdd = self.accelerations(qv);
        if let Some(delta) = delta {
            let dv = V::splat(delta);
            let mut shifted = *qv;
            for k in 0..3 {
                shifted[k] = qv[k].add(dv.mul(qdd[k]));
            }
            qdd = self.accelerations(&shifted);
        }
        let hm = V::splat(h).mul(V::from_array(self.reduced));
        let mut ok = 0xff;
        for k in 0..3 {
            pv[k] = pv[k].add(hm.mul(qdd[k]));
            ok &= pv[k].finite();
        }
        ok
    }

    /// Up to `n` Wisdom–Holman steps of kick then drift in lanes, the state
    /// kept in registers from step to step: step `k` takes the kick `kind`
    /// over `kick` and drifts the
    /// planets by `drift`, the last by `drift_last`. It stops before a step
    /// whose kick is not finite or whose drift leaves a lane to the scalar
    /// solve, with the state as that step found it, and returns the steps
    /// done: each the same operations as [`kick`](Self::kick) and
    /// [`Lanes::kepler`], so the same bits as those steps one flow at a
    /// time.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn run<V: F8>(
        &self,
        kick: f64,
        kind: LaneKick,
        drift: f64,
        drift_last: f64,
        n: usize,
        q: &mut [f64],
        pm: &mut [f64],
    ) -> usize {
        let p = self.lanes.p;
        let used = self.lanes.used;
        let solver = KeplerSolver::default();
        let mut x = V::load3(q, p);
        let mut pv = V::load3(pm, p);
        let mut done = 0;
        while done < n {
            let d = if done + 1 < n { drift } else { drift_last };
            let mut kicked = pv;
            if self.kick_regs(kick, kind, &x, &mut kicked) != 0xff {
                break;
            }
            let (xn, pn, ok) = self.lanes.kepler_regs(&solver, d, &x, &kicked);
            if ok != used {
                break;
            }
            x = xn;
            pv = pn;
            done += 1;
        }
        V::store3(&x, q, p);
        V::store3(&pv, pm, p);
        done
    }
}

/// [`Lanes::kepler`] as a [`Kernel`].
pub(super) struct KeplerKernel<'a> {
    pub lanes: &'a Lanes,
    pub h: f64,
    pub q: &'a mut [f64],
    pub p: &'a mut [f64],
}

impl Kernel for KeplerKernel<'_> {
    type Out = u8;
    #[inline(always)]
    fn run<V: F8>(self) -> u8 {
        self.lanes
            .kepler::<V>(&KeplerSolver::default(), self.h, self.q, self.p)
    }
}

/// [`JacobiLanes::kick`] as a [`Kernel`].
pub(super) struct JacobiKick<'a> {
    pub lanes: &'a JacobiLanes,
    pub h: f64,
    pub kind: LaneKick,
    pub q: &'a [f64],
    pub p: &'a mut [f64],
}

impl Kernel for JacobiKick<'_> {
    type Out = u8;
    #[inline(always)]
    fn run<V: F8>(self) -> u8 {
        self.lanes.kick::<V>(self.h, self.kind, self.q, self.p)
    }
}

/// [`Lanes::mutual_kick`] on the planets' positions `q` and momenta `p`,
/// as a [`Kernel`]: the mask of the lanes whose new momentum is finite.
pub(super) struct MutualKick<'a> {
    pub lanes: &'a Lanes,
    pub hg: f64,
    pub q: &'a [f64],
    pub p: &'a mut [f64],
}

impl Kernel for MutualKick<'_> {
    type Out = u8;
    #[inline(always)]
    fn run<V: F8>(self) -> u8 {
        let n = self.lanes.p;
        let x = V::load3(self.q, n);
        let mut pv = V::load3(self.p, n);
        self.lanes.mutual_kick(self.hg, &x, &mut pv);
        V::store3(&pv, self.p, n);
        pv[0].finite() & pv[1].finite() & pv[2].finite()
    }
}

/// [`JacobiLanes::run`] as a [`Kernel`].
pub(super) struct JacobiRun<'a> {
    pub lanes: &'a JacobiLanes,
    pub kick: f64,
    pub kind: LaneKick,
    pub drift: f64,
    pub drift_last: f64,
    pub n: usize,
    pub q: &'a mut [f64],
    pub p: &'a mut [f64],
}

impl Kernel for JacobiRun<'_> {
    type Out = usize;
    #[inline(always)]
    fn run<V: F8>(self) -> usize {
        self.lanes.run::<V>(
            self.kick,
            self.kind,
            self.drift,
            self.drift_last,
            self.n,
            self.q,
            self.p,
        )
    }
}

/// [`Lanes::democratic_run`] as a [`Kernel`].
pub(super) struct DemocraticRun<'a> {
    pub lanes: &'a Lanes,
    pub hg: f64,
    pub h: f64,
    pub f: f64,
    pub f_last: f64,
    pub n: usize,
    pub q: &'a mut [f64],
    pub p: &'a mut [f64],
}

impl Kernel for DemocraticRun<'_> {
    type Out = usize;
    #[inline(always)]
    fn run<V: F8>(self) -> usize {
        self.lanes
            .democratic_run::<V>(self.hg, self.h, self.f, self.f_last, self.n, self.q, self.p)
    }
}
