//! Wisdom–Holman in democratic heliocentric coordinates: [`DemocraticHeliocentric`].

// Loops over bodies index several per-body arrays (masses, positions,
// momenta) at once; an index reads clearer than zipped iterators.
#![allow(clippy::needless_range_loop)]

use super::lanes::{DemocraticRun, KeplerKernel, Lanes, MutualKick};
use super::{Bodies, WhError, get3, set3};
use crate::kepler::{KeplerSolver, LANES};
use crate::simd::{Level, Simd, W, dispatch};

/// Wisdom–Holman in democratic heliocentric coordinates (Duncan, Levison &
/// Lee 1998, the coordinates of SyMBA).
///
/// Positions relative to the central body, momenta relative to the
/// barycentre: `Q₀ = Σmₖxₖ/M` (the barycentre), `Qᵢ = xᵢ − x₀`, `P₀ = Σpₖ`,
/// `Pᵢ = pᵢ − (mᵢ/M)P₀` (`M` the total mass), a canonical change of
/// variables in which the Hamiltonian splits into three parts,
///
/// ```text
/// H_Kepler      = |P₀|²/(2M) + Σᵢ₌₁ [ |Pᵢ|²/(2mᵢ) − G m₀mᵢ/|Qᵢ| ],
/// H_interaction = −Σ_{1≤i<j} G mᵢmⱼ/|Qᵢ − Qⱼ|,
/// H_jump        = |Σᵢ₌₁ Pᵢ|²/(2m₀),
/// ```
///
/// each with an exact flow: N − 1 Kepler problems about the central mass
/// (`GM = G·m₀`) and a free barycentre; a kick of the momenta by the
/// planets' mutual forces; and a "jump" of every heliocentric position by
/// the same `h·ΣPᵢ/m₀` (the central body's motion about the barycentre,
/// felt by all). The step composes them as Duncan, Levison & Lee do,
/// symmetrically:
///
/// ```text
/// J(h/2) I(h/2) K(h) I(h/2) J(h/2)
/// ```
///
/// (J jump, I interaction, K Kepler): symplectic, symmetric, order 2. The
/// interaction and the jump are both of the order of the planetary masses;
/// any symmetric arrangement of the three flows is order 2 as well, and the
/// three parts stay available on their own for other compositions. None of them
/// commute, so a two-part scheme that treats `J·K·J` as one part gets at
/// most order 2 from it.
#[derive(Clone, Debug, PartialEq)]
pub struct DemocraticHeliocentric {
    bodies: Bodies,
    total: f64,
    /// Up to eight planets: their constants in eight lanes, for the Kepler
    /// flow and the kick in one pass ([`crate::simd`]).
    lanes: Option<Lanes>,
    /// Which implementation of the lanes runs.
    simd: Simd,
}

impl DemocraticHeliocentric {
    /// `G` and the masses (body 0 the central one), optionally the bodies'
    /// names for messages. A mass that is zero, negative or not finite is
    /// an error naming the body.
    pub fn new(g: f64, masses: &[f64], names: Option<&[&str]>) -> Result<Self, WhError> {
        let bodies = Bodies::new(g, masses, names)?;
        let total = masses.iter().sum();
        let lanes = Lanes::new(masses, |_| g * masses[0], |i| masses[i]);
        Ok(Self {
            bodies,
            total,
            lanes,
            simd: Simd::Auto,
        })
    }

    /// The same split with the eight-lane kernels of up to eight planets on
    /// the implementation `simd` (the default [`Simd::Auto`]: the best the
    /// processor has, under the cap of `SYMLAB_SIMD`). All give the same
    /// bits.
    pub fn with_simd(mut self, simd: Simd) -> Self {
        self.simd = simd;
        self
    }

    /// The implementation of the eight-lane kernels
    /// ([`DemocraticHeliocentric::with_simd`]).
    pub fn simd(&self) -> Simd {
        self.simd
    }

    /// The outer solar system of [`crate::problems::outer_solar`], with its
    /// names.
    pub fn outer_solar() -> Self {
        use crate::problems::outer_solar::{G, MASSES, NAMES};
        Self::new(G, &MASSES, Some(&NAMES)).expect("the published masses are positive")
    }

    /// The number of bodies.
    pub fn bodies(&self) -> usize {
        self.bodies.n()
    }

    /// The total energy of an inertial state `z = [x; p]`.
    pub fn energy(&self, z: &[f64]) -> f64 {
        self.bodies.energy(z)
    }

    /// `w = [Q; P]` from the inertial `z = [x; p]`.
    pub fn from_inertial(&self, z: &[f64], w: &mut [f64]) -> Result<(), WhError> {
        self.bodies.check_state("the inertial state", z)?;
        self.bodies
            .check_len("the democratic heliocentric state", w)?;
        let n = self.bodies.n();
        let m = &self.bodies.m;
        let (x, p) = z.split_at(3 * n);
        let (q, pd) = w.split_at_mut(3 * n);
        let x0 = get3(x, 0);
        let mut sx = [0.0; 3];
        let mut sp = [0.0; 3];
        for i in 0..n {
            let (xi, pi) = (get3(x, i), get3(p, i));
            for k in 0..3 {
                sx[k] += m[i] * xi[k];
                sp[k] += pi[k];
            }
        }
        for i in 1..n {
            let (xi, pi) = (get3(x, i), get3(p, i));
            let f = m[i] / self.total;
            set3(q, i, [0, 1, 2].map(|k| xi[k] - x0[k]));
            set3(pd, i, [0, 1, 2].map(|k| pi[k] - f * sp[k]));
        }
        set3(q, 0, sx.map(|c| c / self.total));
        set3(pd, 0, sp);
        Ok(())
    }

    /// The inertial `z = [x; p]` from `w = [Q; P]`.
    pub fn to_inertial(&self, w: &[f64], z: &mut [f64]) -> Result<(), WhError> {
        self.bodies
            .check_state("the democratic heliocentric state", w)?;
        self.bodies.check_len("the inertial state", z)?;
        let n = self.bodies.n();
        let m = &self.bodies.m;
        let (q, pd) = w.split_at(3 * n);
        let (x, p) = z.split_at_mut(3 * n);
        // x₀ = Q₀ − Σ mᵢQᵢ/M; p₀ = (m₀/M)P₀ − Σ Pᵢ.
        let mut sq = [0.0; 3];
        let mut sp = [0.0; 3];
        for i in 1..n {
            let (qi, pi) = (get3(q, i), get3(pd, i));
            for k in 0..3 {
                sq[k] += m[i] * qi[k];
                sp[k] += pi[k];
            }
        }
        let (q0, p0) = (get3(q, 0), get3(pd, 0));
        let x0 = [0, 1, 2].map(|k| q0[k] - sq[k] / self.total);
        set3(x, 0, x0);
        set3(p, 0, [0, 1, 2].map(|k| m[0] / self.total * p0[k] - sp[k]));
        for i in 1..n {
            let (qi, pi) = (get3(q, i), get3(pd, i));
            let f = m[i] / self.total;
            set3(x, i, [0, 1, 2].map(|k| qi[k] + x0[k]));
            set3(p, i, [0, 1, 2].map(|k| pi[k] + f * p0[k]));
        }
        Ok(())
    }

    /// [`from_inertial`](Self::from_inertial), then back, and an error
    /// naming the first body whose inertial state does not come back within
    /// [`ROUND_TRIP_ULPS`](super::ROUND_TRIP_ULPS)`·N·ε` of the largest coordinate,
    /// position (momentum).
    pub fn from_inertial_checked(&self, z: &[f64], w: &mut [f64]) -> Result<(), WhError> {
        self.from_inertial(z, w)?;
        let mut back = vec![0.0; z.len()];
        self.to_inertial(w, &mut back)?;
        self.bodies.round_trip("democratic heliocentric", z, &back)
    }

    /// The flow of `H_Kepler` over `h`: the barycentre moves freely, each
    /// `(Qᵢ, Pᵢ/mᵢ)` by the exact [Kepler drift](crate::kepler::drift)
    /// about the central mass (`GM = G·m₀`).
    pub fn kepler_flow(&self, h: f64, w: &mut [f64]) -> Result<(), WhError> {
        self.bodies
            .check_len("the democratic heliocentric state", w)?;
        let n = self.bodies.n();
        let m = &self.bodies.m;
        let gm = self.bodies.g * m[0];
        let (q, p) = w.split_at_mut(3 * n);
        let v0 = h / self.total;
        for k in 0..3 {
            q[k] += p[k] * v0;
        }
        // Up to eight planets in one pass on AVX-512 or AVX2, each lane
        // written where it is the scalar drift's (the same bits as below);
        // the planets it leaves go through the groups of four below. On the
        // portable level only the groups of four run: on the portable eight
        // lanes they are the faster of the two
        // (docs/results/outer-solar-wisdom-holman.md), with the same bits.
        let mut lane_done = 0u8;
        if self.simd.level() >= Level::Avx2
            && let Some(lanes) = &self.lanes
        {
            let k = KeplerKernel {
                lanes,
                h,
                q: &mut q[3..],
                p: &mut p[3..],
            };
            lane_done = dispatch(self.simd, k);
        }
        // Planet i was drifted in lane i − 1.
        let in_lanes = |i: usize| i <= W && lane_done >> (i - 1) & 1 == 1;
        // The planets in groups of LANES, drifted side by side (the same
        // bits as one by one, see `KeplerSolver::drift_lanes`).
        let solver = KeplerSolver::default();
        let gms = [gm; LANES];
        let mut next = 1;
        while next < n {
            // The next LANES planets not drifted yet.
            let mut body = [0usize; LANES];
            let mut used = 0;
            while next < n && used < LANES {
                if !in_lanes(next) {
                    body[used] = next;
                    used += 1;
                }
                next += 1;
            }
            if used == 0 {
                break;
            }
            let mut x = [[0.0; 3]; LANES];
            let mut v = [[0.0; 3]; LANES];
            for l in 0..used {
                let i = body[l];
                x[l] = get3(q, i);
                v[l] = get3(p, i).map(|c| c / m[i]);
            }
            let done = solver.drift_lanes(&gms, h, &mut x, &mut v, used);
            // Lanes before a failing one have been drifted: store them, so
            // that the state is what drifting body by body would leave.
            let stored = match &done {
                Ok(()) => used,
                Err((l, _)) => *l,
            };
            for l in 0..stored {
                let i = body[l];
                set3(q, i, x[l]);
                set3(p, i, v[l].map(|c| c * m[i]));
            }
            if let Err((l, source)) = done {
                let i = body[l];
                return Err(WhError::Kepler {
                    part: "Kepler",
                    body: i,
                    name: self.bodies.name(i),
                    step: None,
                    source: Box::new(source),
                });
            }
        }
        Ok(())
    }

    /// The flow of `H_interaction` over `h`: every pair of non-central
    /// bodies kicks the other's momentum by `h·G mᵢmⱼ (Qⱼ − Qᵢ)/|Qⱼ − Qᵢ|³`.
    pub fn interaction_kick(&self, h: f64, w: &mut [f64]) -> Result<(), WhError> {
        self.bodies
            .check_len("the democratic heliocentric state", w)?;
        let n = self.bodies.n();
        let m = &self.bodies.m;
        let hg = h * self.bodies.g;
        let (q, p) = w.split_at_mut(3 * n);
        if let Some(lanes) = &self.lanes {
            let k = MutualKick {
                lanes,
                hg,
                q: &q[3..],
                p: &mut p[3..],
            };
            if dispatch(self.simd, k) & lanes.used != lanes.used {
                for i in 1..n {
                    self.bodies.check_kicked(p, i)?;
                }
            }
            return Ok(());
        }
        for i in 1..n {
            let qi = get3(q, i);
            for j in i + 1..n {
                let qj = get3(q, j);
                let d = [qj[0] - qi[0], qj[1] - qi[1], qj[2] - qi[2]];
                let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                let s = hg * m[i] * m[j] / (r2 * r2.sqrt());
                for k in 0..3 {
                    p[3 * i + k] += s * d[k];
                    p[3 * j + k] -= s * d[k];
                }
            }
            self.bodies.check_kicked(p, i)?;
        }
        Ok(())
    }

    /// The flow of `H_jump` over `h`: every `Qᵢ` (`i ≥ 1`) moves by
    /// `h·ΣⱼPⱼ/m₀`.
    pub fn jump(&self, h: f64, w: &mut [f64]) -> Result<(), WhError> {
        self.bodies
            .check_len("the democratic heliocentric state", w)?;
        let n = self.bodies.n();
        let (q, p) = w.split_at_mut(3 * n);
        let mut s = [0.0; 3];
        for i in 1..n {
            for k in 0..3 {
                s[k] += p[3 * i + k];
            }
        }
        let f = h / self.bodies.m[0];
        let d = s.map(|c| c * f);
        if !d.iter().all(|c| c.is_finite()) {
            return Err(WhError::NonFinite {
                part: "jump",
                body: 0,
                name: self.bodies.name(0),
                step: None,
            });
        }
        for i in 1..n {
            for k in 0..3 {
                q[3 * i + k] += d[k];
            }
        }
        Ok(())
    }

    /// One step `J(h/2) I(h/2) K(h) I(h/2) J(h/2)` (see the [type
    /// documentation](DemocraticHeliocentric)).
    pub fn step(&self, h: f64, w: &mut [f64]) -> Result<(), WhError> {
        self.jump(0.5 * h, w)?;
        self.interaction_kick(0.5 * h, w)?;
        self.kepler_flow(h, w)?;
        self.interaction_kick(0.5 * h, w)?;
        self.jump(0.5 * h, w)
    }

    /// `n` steps of [`step`](Self::step), the half jumps of consecutive
    /// steps merged into one (the same map up to rounding). Errors name the
    /// step (numbered from 0). Up to eight planets step in the lanes with
    /// the state in registers from step to step on AVX2 and AVX-512
    /// ([`steps_in_lanes`](Self::steps_in_lanes)), the same bits as the
    /// flows one by one, which take the steps the lanes leave.
    pub fn integrate(&self, h: f64, n: usize, w: &mut [f64]) -> Result<(), WhError> {
        if n == 0 {
            return Ok(());
        }
        self.jump(0.5 * h, w).map_err(|e| e.at_step(0))?;
        let mut k = 0;
        while k < n {
            k += self.steps_in_lanes(h, n - k, w);
            if k == n {
                break;
            }
            let at = |e: WhError| e.at_step(k);
            self.interaction_kick(0.5 * h, w).map_err(at)?;
            self.kepler_flow(h, w).map_err(at)?;
            self.interaction_kick(0.5 * h, w).map_err(at)?;
            let last = if k + 1 == n { 0.5 * h } else { h };
            self.jump(last, w).map_err(at)?;
            k += 1;
        }
        Ok(())
    }

    /// Up to `n` steps of [`integrate`](Self::integrate)'s loop (`I(h/2)
    /// K(h) I(h/2) J(h)`, the last jump `J(h/2)`) with up to eight planets
    /// in the lanes, the state in registers from step to step, as the
    /// Jacobi split's [`kick_drift_run`](super::Jacobi::kick_drift_run)
    /// takes its steps. Returns the steps taken; it stops, with `w` as that
    /// step found it, before a step whose kick or jump is not finite or
    /// whose Kepler flow leaves a lane to the scalar solve, and takes none
    /// on the portable level (where the flows one by one are faster, as
    /// for the Jacobi split) or for more than eight planets: the caller
    /// takes that step flow by flow.
    pub fn steps_in_lanes(&self, h: f64, n: usize, w: &mut [f64]) -> usize {
        let nb = self.bodies.n();
        let Some(lanes) = &self.lanes else { return 0 };
        if n == 0 || self.simd.level() < Level::Avx2 || w.len() != 6 * nb {
            return 0;
        }
        let (q, p) = w.split_at_mut(3 * nb);
        // The barycentre must stay finite over the whole run (the flows
        // one by one would stop at the step where it did not).
        let v0 = h / self.total;
        if (0..3).any(|k| !(q[k].abs() + n as f64 * (p[k] * v0).abs()).is_finite()) {
            return 0;
        }
        let m0 = self.bodies.m[0];
        let done = dispatch(
            self.simd,
            DemocraticRun {
                lanes,
                hg: 0.5 * h * self.bodies.g,
                h,
                f: h / m0,
                f_last: 0.5 * h / m0,
                n,
                q: &mut q[3..],
                p: &mut p[3..],
            },
        );
        // The barycentre's free drift, step by step as `kepler_flow` takes
        // it (its momentum `P₀` is no other flow's).
        for _ in 0..done {
            for k in 0..3 {
                q[k] += p[k] * v0;
            }
        }
        done
    }
}
