//! Wisdom–Holman in Jacobi coordinates: [`Jacobi`].

// Loops over bodies index several per-body arrays (masses, positions,
// momenta) at once; an index reads clearer than zipped iterators.
#![allow(clippy::needless_range_loop)]

use super::lanes::{JacobiKick, JacobiLanes, JacobiRun, KeplerKernel, LaneKick, Lanes};
use super::warm::KeplerHistory;
use super::{Bodies, WhError, get3, set3, with_scratch};
use crate::kepler::{KeplerSolver, LANES, WarmStart};
use crate::simd::{Level, Simd, W, dispatch};

/// Wisdom–Holman in Jacobi coordinates (Wisdom & Holman 1991; the form of
/// WHFast, Rein & Tamayo 2015).
///
/// With `Mᵢ = m₀ + … + mᵢ` and `Rᵢ` the centre of mass of bodies `0 … i`,
/// the Jacobi coordinates are `Q₀ = R_{N−1}` (the barycentre) and
/// `Qᵢ = xᵢ − R_{i−1}`, with masses `m'ᵢ = mᵢM_{i−1}/Mᵢ` and conjugate
/// momenta `Pᵢ = m'ᵢQ̇ᵢ` (`P₀` the total momentum). The Hamiltonian splits as
///
/// ```text
/// H_Kepler      = |P₀|²/(2M_{N−1}) + Σᵢ₌₁ [ |Pᵢ|²/(2m'ᵢ) − G m'ᵢMᵢ/|Qᵢ| ],
/// H_interaction = Σᵢ₌₁ G m'ᵢMᵢ/|Qᵢ| − Σ_{i<j} G mᵢmⱼ/|xᵢ − xⱼ|,
/// ```
///
/// so that `H_Kepler` is N − 1 independent Kepler problems (`GM = G·Mᵢ`)
/// plus the free barycentre, and `H_interaction`, a function of the
/// positions alone, is small (the planets' mutual pull and the difference
/// between the Sun's pull and the Kepler term's, both of the order of the
/// planetary masses). Its flow is a kick `Pᵢ += h m'ᵢ Q̈ᵢ` with the Jacobi
/// acceleration `Q̈ᵢ = aᵢ − Σ_{j<i} mⱼaⱼ/M_{i−1} + G Mᵢ Qᵢ/|Qᵢ|³` from the
/// inertial accelerations `aₖ` (`m'ᵢQ̈ᵢ = −∂H_interaction/∂Qᵢ`).
#[derive(Clone, Debug, PartialEq)]
pub struct Jacobi {
    bodies: Bodies,
    /// `Mᵢ = m₀ + … + mᵢ`.
    interior: Vec<f64>,
    /// `m'ᵢ` (`m'₀ = M_{N−1}`).
    reduced: Vec<f64>,
    /// Up to eight planets: their constants in eight lanes, for the Kepler
    /// flow and the kicks in one pass ([`crate::simd`]).
    lanes: Option<JacobiLanes>,
    /// Which implementation of the lanes runs.
    simd: Simd,
    /// How [`Split::flow_b_gradient`](crate::split::Split::flow_b_gradient)
    /// takes a gradient kick.
    gradient: GradientKick,
    /// Whether a [`WarmJacobi`](super::WarmJacobi) run warm-starts its long Kepler solves
    /// ([`Jacobi::with_kepler_warm_start`]).
    warm_start: bool,
}

/// The environment variable that sets [`Jacobi::kepler_warm_start`]'s
/// default: `1` on, `0` off; unset (or anything else) gives
/// [`KEPLER_WARM_START_DEFAULT`]. For measuring both ways with the same
/// binary (`symlab compare`'s `wh:` rows).
pub const KEPLER_WARM_START_ENV: &str = "SYMLAB_KEPLER_WARM";

/// Whether a [`WarmJacobi`](super::WarmJacobi) run warm-starts its long Kepler solves unless
/// told otherwise: off, as measured (AMD EPYC Zen 5, one run at a time
/// beside one busy core of another process).
///
/// - Evaluations: from the previous root a planet's long solve (e ≤ 0.1,
///   0.3 … 0.9 P) takes 2–3 evaluations where the cold starter ends in
///   one (390 against 180 over 60 solves; `tests/kepler_warm.rs`): the
///   previous root is off by about `e·nh`, the cold starter (Danby's and
///   two Newton steps on Kepler's equation) is nearly the root.
/// - Time: the starter's `atan2`, `hypot` and three `sin_cos` that it
///   saves about pay for that. 100 merged leapfrog steps
///   (`benches/kepler.rs`, `wisdom_holman_warm`): at 500 and 1000 days
///   the same code (every drift short); at 1500 and 2000 days 2–4 %
///   faster (AVX2: 89.8 → 87.0 µs and 93.4 → 91.7 µs; AVX-512: 63.5 →
///   62.4 µs and 66.6 → 64.2 µs). compare's outer-solar sweep at h = 200
///   … 2000 days (21 timed runs a point, twice, against the tree before
///   the warm start): at 1124 and 2000 days wh:leapfrog 0.92–0.98 of the
///   cold time, wh:whckl-c17 0.97–1.02, wh:aba-10-6-4 0.98–1.02; below,
///   where every drift is short, the warm run's history costs up to 2 %
///   (wh:aba-10-6-4 on AVX-512); the errors at 1124 days and beyond are
///   6e-4 and worse, outside the accuracies the sweep is about.
/// - And a warm-started run's last bits depend on its history, which a
///   checkpoint of a run in progress would have to hold.
///
/// A gain of a few per cent at steps nobody takes does not pay for that.
/// The cost at those steps is elsewhere: Jupiter's long drift takes the
/// whole step out of the lanes' loop (100 steps: 16.7 µs at 1000 days,
/// 66.6 µs at 2000 on AVX-512).
pub const KEPLER_WARM_START_DEFAULT: bool = false;

/// How the Jacobi split takes a gradient (modified) kick
/// `exp(h·B + γ·[B,[A,B]])`, the kick `Pᵢ += h·m'ᵢQ̈ᵢ + 2γ·m'ᵢ·DQ̈ᵢ[Q̈]`
/// (`DQ̈[w]` the derivative of the interaction's Jacobi accelerations in
/// the direction `w`): Wisdom, Holman & Touma's two kernels, REBOUND's
/// WHCKL and WHCKM.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum GradientKick {
    /// The lazy implementer's kick
    /// ([`Jacobi::interaction_kick_gradient`]): the accelerations taken at
    /// `Q + (2γ/h)·Q̈`, two force evaluations, the modified kick up to
    /// terms of the third power of the interaction (WHCKL).
    #[default]
    Lazy,
    /// The modified kick itself ([`Jacobi::interaction_kick_modified`]):
    /// `DQ̈[Q̈]` from the pairs' tidal terms, exact to rounding, so the
    /// kick is the exact flow of a potential and symplectic (WHCKM).
    Exact,
}

impl Jacobi {
    /// `G` and the masses (body 0 the central one), optionally the bodies'
    /// names for messages. A mass that is zero, negative or not finite is
    /// an error naming the body.
    pub fn new(g: f64, masses: &[f64], names: Option<&[&str]>) -> Result<Self, WhError> {
        let bodies = Bodies::new(g, masses, names)?;
        let mut interior = Vec::with_capacity(masses.len());
        let mut acc = 0.0;
        for &m in masses {
            acc += m;
            interior.push(acc);
        }
        let mut reduced = vec![acc; masses.len()];
        for i in 1..masses.len() {
            reduced[i] = masses[i] * interior[i - 1] / interior[i];
        }
        let lanes = Lanes::new(masses, |i| g * interior[i], |i| reduced[i]).map(|lanes| {
            let lane = |f: &dyn Fn(usize) -> f64| {
                let mut out = [0.0; W];
                for l in 0..lanes.p {
                    out[l] = f(l + 1);
                }
                out
            };
            JacobiLanes {
                f: lane(&|i| masses[i] / interior[i]),
                inv_prev: lane(&|i| 1.0 / interior[i - 1]),
                reduced: lane(&|i| reduced[i]),
                m0: masses[0],
                g,
                lanes,
            }
        });
        Ok(Self {
            bodies,
            interior,
            reduced,
            lanes,
            simd: Simd::Auto,
            gradient: GradientKick::Lazy,
            warm_start: kepler_warm_start_from_env(),
        })
    }

    /// The same split with the Kepler solver's warm start on or off (the
    /// default [`KEPLER_WARM_START_DEFAULT`], or `SYMLAB_KEPLER_WARM`,
    /// [`KEPLER_WARM_START_ENV`]). It takes effect in the runs that carry
    /// a history, [`WarmJacobi`](super::WarmJacobi) (compare's `wh:` rows step one): a long
    /// drift (not the short-step series' case: Jupiter beyond about a
    /// quarter of its period) then starts Halley's method from the body's
    /// previous root for the same `h`
    /// ([`KeplerSolver::drift_warm`]). The plain flows
    /// ([`kepler_flow`](Self::kepler_flow), [`step`](Self::step),
    /// [`integrate`](Self::integrate)) have no history and never
    /// warm-start.
    pub fn with_kepler_warm_start(mut self, on: bool) -> Self {
        self.warm_start = on;
        self
    }

    /// Whether [`WarmJacobi`](super::WarmJacobi) runs warm-start
    /// ([`Jacobi::with_kepler_warm_start`]).
    pub fn kepler_warm_start(&self) -> bool {
        self.warm_start
    }

    /// The same split taking gradient kicks as `kick` (the default
    /// [`GradientKick::Lazy`]).
    pub fn with_gradient_kick(mut self, kick: GradientKick) -> Self {
        self.gradient = kick;
        self
    }

    /// How this split takes gradient kicks ([`Jacobi::with_gradient_kick`]).
    pub fn gradient_kick(&self) -> GradientKick {
        self.gradient
    }

    /// The same split with the eight-lane kernels of up to eight planets on
    /// the implementation `simd` (the default [`Simd::Auto`]: the best the
    /// processor has, under the cap of `SYMLAB_SIMD`). All give the same
    /// bits.
    pub fn with_simd(mut self, simd: Simd) -> Self {
        self.simd = simd;
        self
    }

    /// The implementation of the eight-lane kernels ([`Jacobi::with_simd`]).
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
        self.bodies.check_len("the Jacobi state", w)?;
        let n = self.bodies.n();
        let m = &self.bodies.m;
        let (x, p) = z.split_at(3 * n);
        let (q, pj) = w.split_at_mut(3 * n);
        let mut sx = get3(x, 0).map(|c| c * m[0]);
        let mut sp = get3(p, 0);
        for i in 1..n {
            let (xi, pi) = (get3(x, i), get3(p, i));
            let (mi, mprev, mcur) = (m[i], self.interior[i - 1], self.interior[i]);
            set3(q, i, [0, 1, 2].map(|k| xi[k] - sx[k] / mprev));
            set3(
                pj,
                i,
                [0, 1, 2].map(|k| (mprev * pi[k] - mi * sp[k]) / mcur),
            );
            for k in 0..3 {
                sx[k] += mi * xi[k];
                sp[k] += pi[k];
            }
        }
        let mt = self.interior[n - 1];
        set3(q, 0, sx.map(|c| c / mt));
        set3(pj, 0, sp);
        Ok(())
    }

    /// The inertial `z = [x; p]` from `w = [Q; P]`.
    pub fn to_inertial(&self, w: &[f64], z: &mut [f64]) -> Result<(), WhError> {
        self.bodies.check_state("the Jacobi state", w)?;
        self.bodies.check_len("the inertial state", z)?;
        let n = self.bodies.n();
        let m = &self.bodies.m;
        let (q, pj) = w.split_at(3 * n);
        let (x, p) = z.split_at_mut(3 * n);
        // R_{i−1} = Rᵢ − (mᵢ/Mᵢ)Qᵢ, xᵢ = R_{i−1} + Qᵢ; S_{i−1} = (M_{i−1}/Mᵢ)Sᵢ − Pᵢ,
        // pᵢ = Pᵢ + (mᵢ/Mᵢ)Sᵢ (S the total momentum of bodies 0 … i).
        let mut r = get3(q, 0);
        let mut s = get3(pj, 0);
        for i in (1..n).rev() {
            let (qi, pi) = (get3(q, i), get3(pj, i));
            let f = m[i] / self.interior[i];
            let g = self.interior[i - 1] / self.interior[i];
            r = [0, 1, 2].map(|k| r[k] - f * qi[k]);
            set3(x, i, [0, 1, 2].map(|k| r[k] + qi[k]));
            set3(p, i, [0, 1, 2].map(|k| pi[k] + f * s[k]));
            s = [0, 1, 2].map(|k| g * s[k] - pi[k]);
        }
        set3(x, 0, r);
        set3(p, 0, s);
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
        self.bodies.round_trip("Jacobi", z, &back)
    }

    /// The flow of `H_Kepler` over `h`: the barycentre moves freely, each
    /// `(Qᵢ, Pᵢ/m'ᵢ)` by the exact [Kepler drift](crate::kepler::drift)
    /// with `GM = G·Mᵢ`.
    pub fn kepler_flow(&self, h: f64, w: &mut [f64]) -> Result<(), WhError> {
        self.kepler_flow_from(h, w, None)
    }

    /// [`kepler_flow`](Self::kepler_flow) with the warm starts of
    /// `history` ([`KeplerSolver::drift_warm`]): each long solve starts
    /// from the body's root for the same `h` where `history` has one, and
    /// leaves its root there. Short solves are `kepler_flow`'s bits.
    pub fn kepler_flow_warm(
        &self,
        h: f64,
        w: &mut [f64],
        history: &mut KeplerHistory,
    ) -> Result<(), WhError> {
        self.kepler_flow_from(h, w, Some(history))
    }

    // Inlined into both entries, so that `kepler_flow` (no history) is
    // compiled as it was before the warm start existed.
    #[inline(always)]
    fn kepler_flow_from(
        &self,
        h: f64,
        w: &mut [f64],
        mut history: Option<&mut KeplerHistory>,
    ) -> Result<(), WhError> {
        self.bodies.check_len("the Jacobi state", w)?;
        if let Some(hist) = &history
            && hist.bodies() != self.bodies.n()
        {
            return Err(WhError::History {
                expected: self.bodies.n(),
                found: hist.bodies(),
            });
        }
        let n = self.bodies.n();
        let (q, p) = w.split_at_mut(3 * n);
        let v0 = 1.0 / self.reduced[0];
        for k in 0..3 {
            q[k] += h * p[k] * v0;
        }
        // Up to eight planets in one pass on AVX-512 or AVX2, each lane
        // written where it is the scalar drift's (the same bits as below);
        // the planets it leaves go through the groups of four below. On the
        // portable level only the groups of four run: on the portable eight
        // lanes they are the faster of the two
        // (docs/results/outer-solar-wisdom-holman.md), with the same bits.
        let mut lane_done = 0u8;
        if self.simd.level() >= Level::Avx2
            && let Some(jl) = &self.lanes
        {
            let k = KeplerKernel {
                lanes: &jl.lanes,
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
            let mut gm = [1.0; LANES];
            let mut x = [[0.0; 3]; LANES];
            let mut v = [[0.0; 3]; LANES];
            for l in 0..used {
                let i = body[l];
                let mr = self.reduced[i];
                gm[l] = self.bodies.g * self.interior[i];
                x[l] = get3(q, i);
                v[l] = get3(p, i).map(|c| c / mr);
            }
            let done = match history.as_deref_mut() {
                Some(hist) => {
                    let mut warm: [WarmStart; LANES] = std::array::from_fn(|l| {
                        if l < used {
                            hist.get(body[l], h)
                        } else {
                            WarmStart::NONE
                        }
                    });
                    let before = warm;
                    let done = solver.drift_lanes_warm(&gm, h, &mut x, &mut v, used, &mut warm);
                    // Only a long solve writes its root.
                    for l in 0..used {
                        if warm[l] != before[l] {
                            hist.put(body[l], warm[l]);
                        }
                    }
                    done
                }
                None => solver.drift_lanes(&gm, h, &mut x, &mut v, used),
            };
            // Lanes before a failing one have been drifted: store them, so
            // that the state is what drifting body by body would leave.
            let stored = match &done {
                Ok(()) => used,
                Err((l, _)) => *l,
            };
            for l in 0..stored {
                let i = body[l];
                let mr = self.reduced[i];
                set3(q, i, x[l]);
                set3(p, i, v[l].map(|c| c * mr));
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

    /// The flow of `H_interaction` over `h`: the kick
    /// `Pᵢ += h·m'ᵢQ̈ᵢ` (see the [type documentation](Jacobi)).
    pub fn interaction_kick(&self, h: f64, w: &mut [f64]) -> Result<(), WhError> {
        self.bodies.check_len("the Jacobi state", w)?;
        let n = self.bodies.n();
        if let Some(jl) = &self.lanes {
            return self.kick_lanes(jl, h, LaneKick::Plain, w);
        }
        with_scratch(6 * n, |scratch| {
            let (q, p) = w.split_at_mut(3 * n);
            self.kick_at(h, q, p, scratch)
        })
    }

    /// The gradient kick `exp(h·B + γ·[B,[A,B]])` of the interaction
    /// ([`Split::flow_b_gradient`](crate::split::Split::flow_b_gradient)),
    /// as Wisdom, Holman & Touma's "lazy implementer's" modified kick (the
    /// kernel of REBOUND's WHCKL): the Jacobi positions are moved by
    /// `δ·Q̈ᵢ` with `δ = 2γ/h` (`Q̈` the interaction's Jacobi accelerations,
    /// `M⁻¹F` for the Jacobi masses of the Kepler part), the kick
    /// `Pᵢ += h·m'ᵢQ̈ᵢ` is taken with the accelerations there, and the
    /// positions are put back. With `F(Q + δM⁻¹F) = F + δ·(∂F/∂Q)M⁻¹F +
    /// O(δ²)` this is the exact modified kick `h·F + 2γ·(∂F/∂Q)M⁻¹F` up to
    /// terms `O(γ²/h)` with three powers of the interaction, which every
    /// claimed order of the catalogue's gradient kernels leaves alone. Two
    /// force evaluations.
    pub fn interaction_kick_gradient(
        &self,
        h: f64,
        gamma: f64,
        w: &mut [f64],
    ) -> Result<(), WhError> {
        self.bodies.check_len("the Jacobi state", w)?;
        let n = self.bodies.n();
        if h == 0.0 || !h.is_finite() || !gamma.is_finite() {
            return Err(WhError::GradientKick { h, gamma });
        }
        let delta = 2.0 * gamma / h;
        if let Some(jl) = &self.lanes {
            return self.kick_lanes(jl, h, LaneKick::Lazy(delta), w);
        }
        with_scratch(9 * n, |scratch| {
            let (shifted, scratch) = scratch.split_at_mut(3 * n);
            let (q, p) = w.split_at_mut(3 * n);
            // Q̈ at Q (the barycentre Q₀ does not enter the interaction).
            let (x, a) = scratch.split_at_mut(3 * n);
            self.accelerations(q, x, a);
            shifted.copy_from_slice(q);
            let mut acc = get3(a, 0).map(|c| c * self.bodies.m[0]);
            for i in 1..n {
                let qdd = self.jacobi_acceleration(q, a, i, &mut acc);
                for k in 0..3 {
                    shifted[3 * i + k] += delta * qdd[k];
                }
            }
            scratch.fill(0.0);
            self.kick_at(h, shifted, p, scratch)
        })
    }

    /// The modified kick itself, `Pᵢ += h·m'ᵢQ̈ᵢ + 2γ·m'ᵢ·DQ̈ᵢ[Q̈]`, the
    /// exact flow of `h·B + γ·[B,[A,B]]` (for this split's `A`, whose
    /// kinetic part is `Σ|Pᵢ|²/2m'ᵢ`, `[B,[A,B]] = −Σ|∂B/∂Qᵢ|²/m'ᵢ`):
    /// Wisdom, Holman & Touma's modified kick, REBOUND's WHCKM kernel. The
    /// derivative of the accelerations along `w = Q̈` is taken analytically:
    /// the inertial displacement `δx` of `w` (the same linear map as the
    /// positions), each pair's tidal term `G mⱼ (δd/r³ − 3(d·δd) d/r⁵)`, and
    /// the Kepler term's `G Mᵢ (wᵢ/|Qᵢ|³ − 3(Qᵢ·wᵢ) Qᵢ/|Qᵢ|⁵)`. One force
    /// evaluation and one of the tidal terms, the cost of two; where
    /// [`interaction_kick_gradient`](Self::interaction_kick_gradient) is
    /// the same to second order in `γ`, this one is exact, so the kick is
    /// symplectic to rounding. Up to eight planets take it in the lanes
    /// (the same terms, summed in the lanes' order: see
    /// `JacobiLanes::modified_regs`). Errors: `h` or `γ` not finite, or a
    /// momentum that is not finite (naming the body).
    pub fn interaction_kick_modified(
        &self,
        h: f64,
        gamma: f64,
        w: &mut [f64],
    ) -> Result<(), WhError> {
        self.bodies.check_len("the Jacobi state", w)?;
        if !h.is_finite() || !gamma.is_finite() {
            return Err(WhError::GradientKick { h, gamma });
        }
        if let Some(jl) = &self.lanes {
            return self.kick_lanes(jl, h, LaneKick::Exact(gamma), w);
        }
        let n = self.bodies.n();
        let g = self.bodies.g;
        let m = &self.bodies.m;
        with_scratch(15 * n, |scratch| {
            let (q, p) = w.split_at_mut(3 * n);
            let (x, rest) = scratch.split_at_mut(3 * n);
            let (a, rest) = rest.split_at_mut(3 * n);
            let (qdd, rest) = rest.split_at_mut(3 * n);
            let (dx, da) = rest.split_at_mut(3 * n);
            self.accelerations(q, x, a);
            let mut acc = get3(a, 0).map(|c| c * m[0]);
            for i in 1..n {
                set3(qdd, i, self.jacobi_acceleration(q, a, i, &mut acc));
            }
            // δx of the direction Q̈ (Q̈₀ = 0: the barycentre is not kicked).
            self.barycentric(qdd, dx);
            // δa: every pair's tidal term once.
            for i in 0..n {
                let (xi, dxi) = (get3(x, i), get3(dx, i));
                for j in i + 1..n {
                    let (xj, dxj) = (get3(x, j), get3(dx, j));
                    let d = [0, 1, 2].map(|k| xj[k] - xi[k]);
                    let dd = [0, 1, 2].map(|k| dxj[k] - dxi[k]);
                    let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                    let s = g / (r2 * r2.sqrt());
                    let t = 3.0 * (d[0] * dd[0] + d[1] * dd[1] + d[2] * dd[2]) / r2;
                    let tidal = [0, 1, 2].map(|k| s * (dd[k] - t * d[k]));
                    for k in 0..3 {
                        da[3 * i + k] += m[j] * tidal[k];
                        da[3 * j + k] -= m[i] * tidal[k];
                    }
                }
            }
            // DQ̈ᵢ = δaᵢ − Σ_{j<i} mⱼδaⱼ/M_{i−1} + the Kepler term's derivative.
            let mut dacc = get3(da, 0).map(|c| c * m[0]);
            for i in 1..n {
                let (qi, wi, dai) = (get3(q, i), get3(qdd, i), get3(da, i));
                let r2 = qi[0] * qi[0] + qi[1] * qi[1] + qi[2] * qi[2];
                let kep = g * self.interior[i] / (r2 * r2.sqrt());
                let t = 3.0 * (qi[0] * wi[0] + qi[1] * wi[1] + qi[2] * wi[2]) / r2;
                let inv = 1.0 / self.interior[i - 1];
                let (hm, gm) = (h * self.reduced[i], 2.0 * gamma * self.reduced[i]);
                for k in 0..3 {
                    let dq = dai[k] - dacc[k] * inv + kep * (wi[k] - t * qi[k]);
                    dacc[k] += m[i] * dai[k];
                    p[3 * i + k] += hm * wi[k] + gm * dq;
                }
                self.bodies.check_kicked(p, i)?;
            }
            Ok(())
        })
    }

    /// The kick `kind` of up to eight planets in lanes; an error names the
    /// first body whose momentum is not finite.
    fn kick_lanes(
        &self,
        jl: &JacobiLanes,
        h: f64,
        kind: LaneKick,
        w: &mut [f64],
    ) -> Result<(), WhError> {
        let n = self.bodies.n();
        let (q, p) = w.split_at_mut(3 * n);
        let k = JacobiKick {
            lanes: jl,
            h,
            kind,
            q: &q[3..],
            p: &mut p[3..],
        };
        let ok = dispatch(self.simd, k);
        if ok & jl.lanes.used != jl.lanes.used {
            for i in 1..n {
                self.bodies.check_kicked(p, i)?;
            }
        }
        Ok(())
    }

    /// The inertial positions relative to the barycentre of the Jacobi
    /// positions `q`, into `x` (linear in `q`, so also the inertial
    /// displacement of a Jacobi one): `Q₀` drops out of every difference,
    /// so it is left out.
    #[inline(always)]
    fn barycentric(&self, q: &[f64], x: &mut [f64]) {
        let m = &self.bodies.m;
        let mut r = [0.0; 3];
        for i in (1..self.bodies.n()).rev() {
            let qi = get3(q, i);
            let f = m[i] / self.interior[i];
            r = [0, 1, 2].map(|k| r[k] - f * qi[k]);
            set3(x, i, [0, 1, 2].map(|k| r[k] + qi[k]));
        }
        set3(x, 0, r);
    }

    /// The inertial accelerations of the interaction at Jacobi positions
    /// `q`, into `a` (zeroed), with the inertial positions relative to the
    /// barycentre in `x`: every pair once.
    #[inline(always)]
    fn accelerations(&self, q: &[f64], x: &mut [f64], a: &mut [f64]) {
        let n = self.bodies.n();
        let g = self.bodies.g;
        let m = &self.bodies.m;
        self.barycentric(q, x);
        for i in 0..n {
            let xi = get3(x, i);
            for j in i + 1..n {
                let xj = get3(x, j);
                let d = [xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]];
                let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                let s = g / (r2 * r2.sqrt());
                let (si, sj) = (s * m[j], s * m[i]);
                for k in 0..3 {
                    a[3 * i + k] += si * d[k];
                    a[3 * j + k] -= sj * d[k];
                }
            }
        }
    }

    /// Body `i`'s Jacobi acceleration from the inertial ones `a`, minus the
    /// Kepler part's; `acc` carries `Σ_{j<i} mⱼaⱼ` (start it at `m₀a₀`).
    #[inline(always)]
    fn jacobi_acceleration(&self, q: &[f64], a: &[f64], i: usize, acc: &mut [f64; 3]) -> [f64; 3] {
        let m = &self.bodies.m;
        let ai = get3(a, i);
        let qi = get3(q, i);
        let r2 = qi[0] * qi[0] + qi[1] * qi[1] + qi[2] * qi[2];
        let kep = self.bodies.g * self.interior[i] / (r2 * r2.sqrt());
        let inv = 1.0 / self.interior[i - 1];
        let mut qdd = [0.0; 3];
        for k in 0..3 {
            qdd[k] = ai[k] - acc[k] * inv + kep * qi[k];
            acc[k] += m[i] * ai[k];
        }
        qdd
    }

    /// `Pᵢ += h·m'ᵢQ̈ᵢ(q)` for every planet, with `6n` zeroed scratch
    /// numbers; an error names the first body whose momentum is not finite.
    #[inline(always)]
    fn kick_at(
        &self,
        h: f64,
        q: &[f64],
        p: &mut [f64],
        scratch: &mut [f64],
    ) -> Result<(), WhError> {
        let n = self.bodies.n();
        let (x, a) = scratch.split_at_mut(3 * n);
        self.accelerations(q, x, a);
        let mut acc = get3(a, 0).map(|c| c * self.bodies.m[0]);
        for i in 1..n {
            let qdd = self.jacobi_acceleration(q, a, i, &mut acc);
            let hm = h * self.reduced[i];
            for k in 0..3 {
                p[3 * i + k] += hm * qdd[k];
            }
            self.bodies.check_kicked(p, i)?;
        }
        Ok(())
    }

    /// Up to `n` steps of the interaction kick over `kick` (the gradient
    /// kick with weight `gamma` where it is nonzero, as
    /// [`interaction_kick_gradient`](Self::interaction_kick_gradient) or
    /// [`interaction_kick_modified`](Self::interaction_kick_modified), as
    /// [`gradient_kick`](Self::gradient_kick) says), then the Kepler flow
    /// over `drift` (`drift_last` for the last): the loop of a
    /// Wisdom–Holman integration between outputs, its drifts merged. Up to
    /// eight planets run in the lanes with the state in registers from
    /// step to step, on AVX2 and AVX-512 ([`Simd`]), the same operations as the
    /// flows one by one (so the same bits: `tests/simd_lanes.rs`) without
    /// storing and reloading the state between them. Returns the steps
    /// taken; it stops, with `w` as that step found it, before a step whose
    /// kick is not finite or whose drift leaves a lane to the scalar solve
    /// (and takes none on the portable level or for more than eight
    /// planets): the caller takes that step flow by flow.
    pub fn kick_drift_run(
        &self,
        kick: f64,
        gamma: f64,
        drift: f64,
        drift_last: f64,
        n: usize,
        w: &mut [f64],
    ) -> usize {
        let nb = self.bodies.n();
        let Some(jl) = &self.lanes else { return 0 };
        // On the portable level the flows one by one (their Kepler drifts
        // in groups of four) are faster than the loop on the portable
        // eight lanes: measured 100 steps at h = 10 days in 746 µs in the
        // loop, the democratic split's flows in 439 µs
        // (docs/results/simd-lanes.md).
        if n == 0 || self.simd.level() < Level::Avx2 || w.len() != 6 * nb {
            return 0;
        }
        // The refusals of the kicks one by one: the caller's flows report
        // them.
        let kind = if gamma == 0.0 {
            LaneKick::Plain
        } else if !kick.is_finite() || !gamma.is_finite() {
            return 0;
        } else if self.gradient == GradientKick::Exact {
            LaneKick::Exact(gamma)
        } else if kick == 0.0 {
            return 0;
        } else {
            LaneKick::Lazy(2.0 * gamma / kick)
        };
        let (q, p) = w.split_at_mut(3 * nb);
        // The barycentre must stay finite over the whole run (the flows
        // one by one would stop at the step where it did not).
        let v0 = 1.0 / self.reduced[0];
        let reach = drift.abs().max(drift_last.abs()) * n as f64;
        if (0..3).any(|k| !(q[k].abs() + reach * (p[k] * v0).abs()).is_finite()) {
            return 0;
        }
        let done = dispatch(
            self.simd,
            JacobiRun {
                lanes: jl,
                kick,
                kind,
                drift,
                drift_last,
                n,
                q: &mut q[3..],
                p: &mut p[3..],
            },
        );
        // The barycentre's free drift, step by step as `kepler_flow` takes it.
        for step in 0..done {
            let d = if step + 1 < n { drift } else { drift_last };
            for k in 0..3 {
                q[k] += d * p[k] * v0;
            }
        }
        done
    }

    /// One Wisdom–Holman step `A(h/2) B(h) A(h/2)` (A the Kepler flow, B
    /// the interaction kick): symmetric, symplectic, order 2.
    pub fn step(&self, h: f64, w: &mut [f64]) -> Result<(), WhError> {
        self.kepler_flow(0.5 * h, w)?;
        self.interaction_kick(h, w)?;
        self.kepler_flow(0.5 * h, w)
    }

    /// `n` steps of [`step`](Self::step), the half Kepler flows of
    /// consecutive steps merged into one (`A(h/2) [B(h) A(h)]ⁿ⁻¹ B(h)
    /// A(h/2)`, the same map up to rounding, one Kepler solve per body
    /// per step). Errors name the step (numbered from 0).
    pub fn integrate(&self, h: f64, n: usize, w: &mut [f64]) -> Result<(), WhError> {
        if n == 0 {
            return Ok(());
        }
        self.kepler_flow(0.5 * h, w).map_err(|e| e.at_step(0))?;
        let mut k = 0;
        while k < n {
            k += self.kick_drift_run(h, 0.0, h, 0.5 * h, n - k, w);
            if k == n {
                break;
            }
            self.interaction_kick(h, w).map_err(|e| e.at_step(k))?;
            let last = if k + 1 == n { 0.5 * h } else { h };
            self.kepler_flow(last, w).map_err(|e| e.at_step(k))?;
            k += 1;
        }
        Ok(())
    }
}

/// [`KEPLER_WARM_START_ENV`] read once: `1` on, `0` off, unset the
/// default. Any other value is refused aloud, as `SYMLAB_SIMD`'s are: one
/// line on standard error naming the variable and the value, and the
/// default — never silently taken for either.
fn kepler_warm_start_from_env() -> bool {
    static WARM: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *WARM.get_or_init(|| match std::env::var_os(KEPLER_WARM_START_ENV) {
        None => KEPLER_WARM_START_DEFAULT,
        Some(v) if v == "1" => true,
        Some(v) if v == "0" => false,
        Some(v) => {
            eprintln!(
                "{KEPLER_WARM_START_ENV}={v:?} is neither 1 nor 0: ignored, the Kepler warm start stays {}",
                if KEPLER_WARM_START_DEFAULT { "on" } else { "off" }
            );
            KEPLER_WARM_START_DEFAULT
        }
    })
}
