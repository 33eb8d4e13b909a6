//! The library's test problems as [`Problem`]s, and the eight built-in
//! instances of `symlab compare --problem` ([`Builtin`]).

use integrator_core::OdeSystem;
use integrator_core::linear::{self, LinearHamiltonian};
use integrator_core::problems::{
    ExactFlow, Fpu, HenonHeiles, Kepler, Oscillator, OuterSolarSystem, Pendulum,
};

use crate::counting::{AsOde, AsSeparable};
use crate::error::{CompareError, Result};
use crate::nbody::Bodies;
use crate::problem::{Defaults, Problem, Setup, StackSizes};

use std::f64::consts::PI;

/// Kepler's orbits: 10 orbits of period 2π, 100 to 10⁵ steps.
const KEPLER: Defaults = Defaults {
    t_end: 20.0 * PI,
    h_min: 20.0 * PI / 1e5,
    h_max: 20.0 * PI / 100.0,
};
const SHORT: Defaults = Defaults {
    t_end: 10.0,
    h_min: 1e-4,
    h_max: 0.1,
};
/// The outer solar system over HLW's 10⁵ days, 500 to 5·10⁴ steps.
const OUTER_SOLAR: Defaults = Defaults {
    t_end: 1e5,
    h_min: 2.0,
    h_max: 200.0,
};
/// The step of the outer solar system's reference (days): Sofroniou–
/// Spaletta's order-10 composition at `h = 5` agrees with `h = 2.5` and
/// with Kahan–Li 8 at `h = 2` to 1e-11 over 10⁵ days
/// (`integrator-core/tests/outer_solar.rs`).
pub const OUTER_SOLAR_REFERENCE_STEP: f64 = 5.0;
const PERIODIC: Defaults = Defaults {
    t_end: 100.0,
    h_min: 1e-3,
    h_max: 1.0,
};

fn exact<P: ExactFlow>(
    p: &P,
    z0: &[f64],
    t: f64,
    what: &str,
) -> std::result::Result<Vec<f64>, String> {
    p.flow(z0, t)
        .ok_or_else(|| format!("the exact flow covers {what} only"))
}

impl Problem for Oscillator {
    type Kind = AsSeparable;
    const STACK_SIZES: StackSizes = StackSizes::only(2);
    fn name(&self) -> String {
        "oscillator".into()
    }
    fn description(&self) -> String {
        if self.k == 1.0 {
            "harmonic oscillator".into()
        } else {
            format!("harmonic oscillator (k = {})", self.k)
        }
    }
    fn energy(&self, z: &[f64]) -> f64 {
        integrator_core::energy(self, z)
    }
    fn start(&self) -> Vec<f64> {
        vec![1.0, 0.0]
    }
    fn reference(&self, z0: &[f64], t: f64) -> std::result::Result<Vec<f64>, String> {
        exact(self, z0, t, "states of two components")
    }
    fn defaults(&self) -> Defaults {
        PERIODIC
    }
}

impl Problem for Pendulum {
    type Kind = AsSeparable;
    const STACK_SIZES: StackSizes = StackSizes::only(2);
    fn name(&self) -> String {
        "pendulum".into()
    }
    fn description(&self) -> String {
        "pendulum (amplitude 2)".into()
    }
    fn energy(&self, z: &[f64]) -> f64 {
        integrator_core::energy(self, z)
    }
    fn start(&self) -> Vec<f64> {
        Pendulum::at_rest(2.0)
    }
    fn reference(&self, z0: &[f64], t: f64) -> std::result::Result<Vec<f64>, String> {
        exact(self, z0, t, "librations (|H| < 1)")
    }
    fn defaults(&self) -> Defaults {
        PERIODIC
    }
}

impl Problem for Kepler {
    type Kind = AsSeparable;
    const STACK_SIZES: StackSizes = StackSizes::only(4);
    /// `σ = r`: the inverse distance as step density.
    const STEP_DENSITY: Option<integrator_core::adaptive::DistancePower> =
        Some(integrator_core::adaptive::DistancePower { alpha: 1.0 });
    /// `V = −1/r`: `logh:` applies.
    const NEGATIVE_POTENTIAL: bool = true;
    /// `kepler` (e = 0.6), `kepler-hard` (e = 0.9), else `kepler-e<e>`.
    fn name(&self) -> String {
        if self.e == 0.6 {
            "kepler".into()
        } else if self.e == 0.9 {
            "kepler-hard".into()
        } else {
            format!("kepler-e{}", self.e)
        }
    }
    fn description(&self) -> String {
        format!("Kepler e = {}", self.e)
    }
    fn energy(&self, z: &[f64]) -> f64 {
        integrator_core::energy(self, z)
    }
    fn start(&self) -> Vec<f64> {
        self.initial_state()
    }
    fn reference(&self, z0: &[f64], t: f64) -> std::result::Result<Vec<f64>, String> {
        exact(self, z0, t, "bound orbits")
    }
    fn defaults(&self) -> Defaults {
        KEPLER
    }
    /// An orbit of the normalised problem takes 2π.
    fn period(&self) -> Option<(f64, &'static str)> {
        Some((2.0 * PI, "orbit"))
    }
    /// A massless body about a unit mass at rest, `G = 1`.
    fn rebound_bodies(&self, z: &[f64]) -> Option<std::result::Result<Bodies, String>> {
        Some(Bodies::planar_kepler(z))
    }
}

/// The Sun and the five outer planets (HLW I.2.3), masses relative to the
/// Sun, AU and days; the reference is a converged numerical solution
/// ([`OUTER_SOLAR_REFERENCE_STEP`]).
impl Problem for OuterSolarSystem {
    type Kind = AsSeparable;
    const STACK_SIZES: StackSizes = StackSizes::only(36);
    /// Gravity, `V = −Σ Gmᵢmⱼ/rᵢⱼ`: `logh:` applies.
    const NEGATIVE_POTENTIAL: bool = true;
    fn name(&self) -> String {
        "outer-solar".into()
    }
    fn description(&self) -> String {
        "outer solar system (HLW I.2.3)".into()
    }
    fn energy(&self, z: &[f64]) -> f64 {
        integrator_core::energy(self, z)
    }
    fn start(&self) -> Vec<f64> {
        self.initial_state()
    }
    /// Sofroniou–Spaletta order 10 at 5-day steps.
    fn reference(&self, z0: &[f64], t: f64) -> std::result::Result<Vec<f64>, String> {
        integrator_core::problems::try_reference_solution(
            self,
            z0,
            t,
            1.0 / OUTER_SOLAR_REFERENCE_STEP,
        )
    }
    fn defaults(&self) -> Defaults {
        OUTER_SOLAR
    }
    /// Jupiter's period, about 4332.6 days.
    fn period(&self) -> Option<(f64, &'static str)> {
        Some((4332.59, "Jupiter orbit"))
    }
    /// The Wisdom–Holman (Jacobi) split of the same bodies, masses and `G`
    /// (`wh:ID`: the library's splittings on it).
    fn wisdom_holman(&self) -> Option<integrator_core::problems::wisdom_holman::Jacobi> {
        Some(integrator_core::problems::wisdom_holman::Jacobi::outer_solar())
    }
    /// The six bodies in the same units and frame (not moved to the centre
    /// of mass), velocities `p/m`.
    fn rebound_bodies(&self, z: &[f64]) -> Option<std::result::Result<Bodies, String>> {
        use integrator_core::problems::outer_solar::{G, MASSES, NAMES};
        Some(Bodies::from_momenta(G, &NAMES, &MASSES, z))
    }
}

impl Problem for HenonHeiles {
    type Kind = AsSeparable;
    const STACK_SIZES: StackSizes = StackSizes::only(4);
    fn name(&self) -> String {
        "henon-heiles".into()
    }
    fn description(&self) -> String {
        "Hénon–Heiles (chaotic)".into()
    }
    fn energy(&self, z: &[f64]) -> f64 {
        integrator_core::energy(self, z)
    }
    fn start(&self) -> Vec<f64> {
        HenonHeiles::chaotic_start().to_vec()
    }
    /// Sofroniou–Spaletta order 10 with tiny steps (trustworthy up to
    /// `T ≈ 10`: the motion is chaotic).
    fn reference(&self, z0: &[f64], t: f64) -> std::result::Result<Vec<f64>, String> {
        HenonHeiles::try_reference(self, z0, t)
    }
    fn defaults(&self) -> Defaults {
        SHORT
    }
}

impl Problem for Fpu {
    type Kind = AsSeparable;
    /// The stiff FPU chain of the comparisons has m = 3 (12 entries); another
    /// m steps slices.
    const STACK_SIZES: StackSizes = StackSizes::only(12);
    fn name(&self) -> String {
        "fpu".into()
    }
    fn description(&self) -> String {
        format!("stiff FPU (ω = {})", self.omega)
    }
    fn energy(&self, z: &[f64]) -> f64 {
        integrator_core::energy(self, z)
    }
    fn start(&self) -> Vec<f64> {
        Fpu::start(self)
    }
    fn reference(&self, z0: &[f64], t: f64) -> std::result::Result<Vec<f64>, String> {
        Fpu::try_reference(self, z0, t)
    }
    fn defaults(&self) -> Defaults {
        SHORT
    }
}

/// The linear model `z' = Hz + u` of the paper. Its default instance is the
/// gyroscopic one: `q = 0`, `p = (1, …, 1)` (positive kinetic energy, every
/// mode excited); the reference is the exact flow (matrix exponential).
/// Besides the Runge–Kutta tables it offers the exact one-step maps of the
/// Gauss tables, `gaussN-propagator`.
impl Problem for LinearHamiltonian {
    type Kind = AsOde;
    /// Any size (the gyroscopic problem has 20 entries, a linear problem
    /// file its own): slices.
    const STACK_SIZES: StackSizes = StackSizes::NONE;
    fn name(&self) -> String {
        "gyroscopic".into()
    }
    fn description(&self) -> String {
        format!("linear system z' = Hz + u (n = {})", self.dim() / 2)
    }
    fn energy(&self, z: &[f64]) -> f64 {
        LinearHamiltonian::energy(self, z)
    }
    fn start(&self) -> Vec<f64> {
        let n = self.dim() / 2;
        let mut z0 = vec![0.0; 2 * n];
        z0[n..].fill(1.0);
        z0
    }
    fn reference(&self, z0: &[f64], t: f64) -> std::result::Result<Vec<f64>, String> {
        self.exact(z0, t).map_err(|e| e.to_string())
    }
    fn defaults(&self) -> Defaults {
        SHORT
    }
    /// Linear: the exact one-step maps of the Gauss tables apply.
    fn linear(&self) -> Option<&LinearHamiltonian> {
        Some(self)
    }
}

/// The built-in problems of `symlab compare --problem`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Builtin {
    /// H = ½(p² + q²), q(0) = 1, p(0) = 0; exact flow.
    Oscillator,
    /// Random gyroscopic system Mq̈ + Gq̇ + Kq = f, n = 10, frequencies 1…10
    /// (`gyroscopic(10, 1, 10)`), q(0) = 0, p(0) = 1; matrix exponential.
    Gyroscopic,
    /// Kepler, e = 0.6, from pericentre; exact flow.
    Kepler,
    /// Kepler, e = 0.9, from pericentre; exact flow.
    KeplerHard,
    /// Hénon–Heiles, chaotic start at H = 1/8; numerical reference.
    HenonHeiles,
    /// Stiff FPU chain (m = 3, ω = 50); numerical reference.
    Fpu,
    /// Pendulum H = p²/2 − cos q from rest at q = 2; exact flow.
    Pendulum,
    /// The Sun and five outer planets (HLW I.2.3) over 10⁵ days; numerical
    /// reference.
    OuterSolar,
}

impl Builtin {
    pub const ALL: [Builtin; 8] = [
        Builtin::Oscillator,
        Builtin::Gyroscopic,
        Builtin::Kepler,
        Builtin::KeplerHard,
        Builtin::HenonHeiles,
        Builtin::Fpu,
        Builtin::Pendulum,
        Builtin::OuterSolar,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Builtin::Oscillator => "oscillator",
            Builtin::Gyroscopic => "gyroscopic",
            Builtin::Kepler => "kepler",
            Builtin::KeplerHard => "kepler-hard",
            Builtin::HenonHeiles => "henon-heiles",
            Builtin::Fpu => "fpu",
            Builtin::Pendulum => "pendulum",
            Builtin::OuterSolar => "outer-solar",
        }
    }

    /// The problem named `name`, or an error listing the names.
    pub fn from_name(name: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|b| b.name() == name)
            .ok_or_else(|| {
                CompareError::problem(
                    name,
                    format!(
                        "unknown problem; the built-in problems are {}",
                        Self::ALL.map(Builtin::name).join(", ")
                    ),
                )
            })
    }

    /// The default sweep: `(t_end, h_min, h_max)`.
    pub fn defaults(self) -> Defaults {
        match self {
            Builtin::Oscillator | Builtin::Pendulum => PERIODIC,
            Builtin::Kepler | Builtin::KeplerHard => KEPLER,
            Builtin::HenonHeiles | Builtin::Fpu | Builtin::Gyroscopic => SHORT,
            Builtin::OuterSolar => OUTER_SOLAR,
        }
    }

    /// A line for titles and reports.
    pub fn description(self) -> &'static str {
        match self {
            Builtin::Oscillator => "harmonic oscillator",
            Builtin::Gyroscopic => "gyroscopic linear system (n = 10, ω ∈ [1, 10])",
            Builtin::Kepler => "Kepler e = 0.6",
            Builtin::KeplerHard => "Kepler e = 0.9",
            Builtin::HenonHeiles => "Hénon–Heiles (chaotic)",
            Builtin::Fpu => "stiff FPU (ω = 50)",
            Builtin::Pendulum => "pendulum (amplitude 2)",
            Builtin::OuterSolar => "outer solar system (HLW I.2.3)",
        }
    }
}

/// Renames a setup after the built-in problem it is.
fn built<P: Problem>(id: Builtin, setup: Result<Setup<P>>) -> Result<Setup<P>> {
    Ok(setup?.named(id.name(), id.description()))
}

fn make<P: Problem>(id: Builtin, sys: P, t_end: f64, with_reference: bool) -> Result<Setup<P>> {
    built(
        id,
        if with_reference {
            Setup::new(sys, t_end)
        } else {
            Setup::energy_only(sys, t_end)
        },
    )
}

/// The harmonic oscillator to `t_end`; the reference end state only when
/// asked for (long runs and stability searches judge by the energy alone).
pub fn oscillator(t_end: f64, with_reference: bool) -> Result<Setup<Oscillator>> {
    make(
        Builtin::Oscillator,
        Oscillator { k: 1.0 },
        t_end,
        with_reference,
    )
}

pub fn pendulum(t_end: f64, with_reference: bool) -> Result<Setup<Pendulum>> {
    make(Builtin::Pendulum, Pendulum, t_end, with_reference)
}

/// Kepler with e = 0.6 ([`Builtin::Kepler`]) or e = 0.9
/// ([`Builtin::KeplerHard`]).
pub fn kepler(hard: bool, t_end: f64, with_reference: bool) -> Result<Setup<Kepler>> {
    let (id, e) = if hard {
        (Builtin::KeplerHard, 0.9)
    } else {
        (Builtin::Kepler, 0.6)
    };
    make(id, Kepler { e }, t_end, with_reference)
}

/// The outer solar system ([`Builtin::OuterSolar`]).
pub fn outer_solar(t_end: f64, with_reference: bool) -> Result<Setup<OuterSolarSystem>> {
    make(Builtin::OuterSolar, OuterSolarSystem, t_end, with_reference)
}

pub fn henon_heiles(t_end: f64, with_reference: bool) -> Result<Setup<HenonHeiles>> {
    make(Builtin::HenonHeiles, HenonHeiles, t_end, with_reference)
}

pub fn fpu(t_end: f64, with_reference: bool) -> Result<Setup<Fpu>> {
    make(Builtin::Fpu, Fpu::stiff(), t_end, with_reference)
}

/// `gyroscopic(n, seed, spread)` from `q = 0`, `p = (1, …, 1)`.
pub fn gyroscopic(
    n: usize,
    seed: u64,
    spread: f64,
    t_end: f64,
    with_reference: bool,
) -> Result<Setup<LinearHamiltonian>> {
    let sys = linear::gyroscopic(n, seed, spread)
        .map_err(|e| CompareError::problem("gyroscopic", e.to_string()))?;
    make(Builtin::Gyroscopic, sys, t_end, with_reference)
}

/// The largest frequency of the linear system: `H` has eigenvalues `±iλ`,
/// so `H²` has `−λ²`; power iteration on `H²` (with `Hz = rhs(z) − u`).
pub fn omega_max(sys: &LinearHamiltonian) -> f64 {
    let d = sys.dim();
    let u = sys.offset();
    let apply = |z: &[f64]| {
        let mut out = vec![0.0; d];
        sys.rhs(0.0, z, &mut out);
        for (o, ui) in out.iter_mut().zip(&u) {
            *o -= ui;
        }
        out
    };
    let mut v: Vec<f64> = (0..d).map(|i| 1.0 + 0.1 * (i as f64).sin()).collect();
    let mut lambda2 = 0.0;
    for _ in 0..500 {
        let w = apply(&apply(&v));
        let norm = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        let vnorm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let next = norm / vnorm;
        if !(next.is_finite() && norm > 0.0) {
            break;
        }
        v = w.iter().map(|x| x / norm).collect();
        if (next - lambda2).abs() <= 1e-12 * next {
            lambda2 = next;
            break;
        }
        lambda2 = next;
    }
    lambda2.sqrt()
}
