//! The problems of `symlab compare`, their default sweeps, and the methods
//! that apply to each.

use anyhow::{Result, bail};
use integrator_core::library::{REGISTRY, info};
use integrator_core::linear::{self, LinearHamiltonian};
use integrator_core::problems::{ExactFlow, Fpu, HenonHeiles, Kepler, Oscillator, Pendulum};
use integrator_core::{OdeSystem, Separable};

use super::runner::{
    PropagatorStepper, RK_IDS, SEPARABLE_IDS, Stepper, System, linear_stepper, propagator_tables,
    separable_stepper,
};

/// `--problem`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ProblemId {
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
}

impl ProblemId {
    pub fn name(self) -> &'static str {
        match self {
            ProblemId::Oscillator => "oscillator",
            ProblemId::Gyroscopic => "gyroscopic",
            ProblemId::Kepler => "kepler",
            ProblemId::KeplerHard => "kepler-hard",
            ProblemId::HenonHeiles => "henon-heiles",
            ProblemId::Fpu => "fpu",
            ProblemId::Pendulum => "pendulum",
        }
    }

    /// The default sweep: `(t_end, h_min, h_max)`, from about 100 to about
    /// 10⁵ steps over the default end time.
    pub fn defaults(self) -> (f64, f64, f64) {
        use std::f64::consts::PI;
        match self {
            ProblemId::Oscillator | ProblemId::Pendulum => (100.0, 1e-3, 1.0),
            ProblemId::Kepler | ProblemId::KeplerHard => {
                (20.0 * PI, 20.0 * PI / 1e5, 20.0 * PI / 100.0)
            }
            ProblemId::HenonHeiles | ProblemId::Fpu | ProblemId::Gyroscopic => (10.0, 1e-4, 0.1),
        }
    }

    /// `(description, H = …)` for the summary and the plot titles.
    pub fn description(self) -> &'static str {
        match self {
            ProblemId::Oscillator => "harmonic oscillator",
            ProblemId::Gyroscopic => "gyroscopic linear system (n = 10, ω ∈ [1, 10])",
            ProblemId::Kepler => "Kepler e = 0.6",
            ProblemId::KeplerHard => "Kepler e = 0.9",
            ProblemId::HenonHeiles => "Hénon–Heiles (chaotic)",
            ProblemId::Fpu => "stiff FPU (ω = 50)",
            ProblemId::Pendulum => "pendulum (amplitude 2)",
        }
    }
}

/// A problem instance with its start, end time and reference end state.
pub struct Setup<P> {
    pub id: ProblemId,
    pub sys: P,
    pub z0: Vec<f64>,
    pub t_end: f64,
    /// The reference state at `t_end` (exact flow, matrix exponential, or
    /// a converged numerical solution).
    pub reference: Vec<f64>,
    /// `E(z0)`.
    pub e0: f64,
}

impl<P: System> Setup<P> {
    fn new(id: ProblemId, sys: P, z0: Vec<f64>, t_end: f64, reference: Vec<f64>) -> Self {
        let e0 = sys.energy_of(&z0);
        Setup {
            id,
            sys,
            z0,
            t_end,
            reference,
            e0,
        }
    }

    /// `|E(z) − E₀| / |E₀|`.
    pub fn energy_error(&self, z: &[f64]) -> f64 {
        (self.sys.energy_of(z) - self.e0).abs() / self.e0.abs().max(f64::MIN_POSITIVE)
    }

    /// `‖z − z_ref‖₂ / ‖z_ref‖₂` at `t_end`.
    pub fn error(&self, z: &[f64]) -> f64 {
        let d: f64 = z
            .iter()
            .zip(&self.reference)
            .map(|(a, b)| (a - b) * (a - b))
            .sum();
        let r: f64 = self.reference.iter().map(|b| b * b).sum();
        (d / r.max(f64::MIN_POSITIVE)).sqrt()
    }
}

/// The kind of a method, for plots split by family.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    ExplicitRk,
    Splitting,
    Implicit,
    Peer,
}

impl Family {
    pub fn name(self) -> &'static str {
        match self {
            Family::ExplicitRk => "explicit-rk",
            Family::Splitting => "splitting",
            Family::Implicit => "implicit",
            Family::Peer => "peer",
        }
    }
}

/// A fixed-step method: facts for the CSV and its stepper.
pub struct Fixed<P: System> {
    pub id: String,
    pub order: usize,
    /// Symplectic for this problem (for separable problems: for separable
    /// Hamiltonians).
    pub symplectic: bool,
    pub family: Family,
    pub stepper: Box<dyn Stepper<P>>,
}

/// A method of a sweep.
pub enum Method<P: System> {
    Fixed(Fixed<P>),
    /// DOP853 from ode_solvers (adaptive; tolerances are swept).
    Dop853,
}

impl<P: System> Method<P> {
    pub fn id(&self) -> &str {
        match self {
            Method::Fixed(f) => &f.id,
            Method::Dop853 => "dop853",
        }
    }
}

/// What each problem type offers.
pub trait Problem: System {
    /// The method with this id, or an error saying why not.
    fn method(id: &str, problem: ProblemId) -> Result<Method<Self>>;
    /// Every method that applies (the default of `--methods`).
    fn all_methods(problem: ProblemId) -> Vec<String>;
    /// DOP853 to `t_end` with `rtol = atol = tol`; `None` where the peer is
    /// not offered.
    fn dop853(_setup: &Setup<Self>, _tol: f64) -> Option<super::peer::PeerOutcome> {
        None
    }
    /// Whether [`dop853`](Problem::dop853) is offered.
    const PEER: bool = false;
}

fn family_of(id: &str) -> Family {
    let i = info(id).expect("a library id");
    if !i.explicit {
        Family::Implicit
    } else if i.form == "rk" {
        Family::ExplicitRk
    } else {
        Family::Splitting
    }
}

fn valid_list(ids: &[String]) -> String {
    ids.join(", ")
}

fn separable_method<P>(id: &str, problem: ProblemId) -> Result<Method<P>>
where
    P: Problem<Counted = super::counting::Counting<P>> + Separable,
{
    if id == "dop853" {
        if P::PEER && cfg!(feature = "peer") {
            return Ok(Method::Dop853);
        }
        if !cfg!(feature = "peer") {
            bail!(
                "method 'dop853' needs the `peer` feature (on by default); this build has it off"
            );
        }
        bail!(
            "method 'dop853' (the ode_solvers peer) is offered for kepler, kepler-hard, oscillator, pendulum, henon-heiles and fpu, not for {}",
            problem.name()
        );
    }
    if id.ends_with("-propagator") && propagator_tables().iter().any(|(p, _, _)| *p == id) {
        bail!(
            "method '{id}' is the exact one-step map of a Gauss table on a linear system z' = Hz + u; it applies to the gyroscopic problem only, not to {}",
            problem.name()
        );
    }
    let Some(stepper) = separable_stepper::<P>(id) else {
        bail!(
            "unknown method '{id}'; valid methods for {}: {}",
            problem.name(),
            valid_list(&P::all_methods(problem))
        );
    };
    let i = info(id).expect("library ids are in the registry");
    Ok(Method::Fixed(Fixed {
        id: id.to_string(),
        order: i.order,
        symplectic: i.symplectic_separable,
        family: family_of(id),
        stepper,
    }))
}

fn separable_all(_problem: ProblemId, peer: bool) -> Vec<String> {
    let mut v: Vec<String> = REGISTRY.iter().map(|(id, _)| id.to_string()).collect();
    if peer && cfg!(feature = "peer") {
        v.push("dop853".into());
    }
    v
}

macro_rules! separable_problem {
    ($ty:ty, $n:literal) => {
        impl Problem for $ty {
            fn method(id: &str, problem: ProblemId) -> Result<Method<Self>> {
                separable_method::<$ty>(id, problem)
            }
            fn all_methods(problem: ProblemId) -> Vec<String> {
                separable_all(problem, Self::PEER)
            }
            #[cfg(feature = "peer")]
            fn dop853(setup: &Setup<Self>, tol: f64) -> Option<super::peer::PeerOutcome> {
                Some(super::peer::dop853::<$ty, $n>(setup, tol))
            }
            const PEER: bool = true;
        }
    };
}

separable_problem!(Oscillator, 2);
separable_problem!(Pendulum, 2);
separable_problem!(Kepler, 4);
separable_problem!(HenonHeiles, 4);
// The stiff chain of `Fpu::stiff()`: m = 3, 12 state components (another
// `m` is refused by the peer with an error status).
separable_problem!(Fpu, 12);

impl Problem for LinearHamiltonian {
    fn method(id: &str, problem: ProblemId) -> Result<Method<Self>> {
        if let Some((pid, p, q)) = propagator_tables()
            .into_iter()
            .find(|(pid, _, _)| *pid == id)
        {
            let base = pid.trim_end_matches("-propagator");
            let i = info(base).expect("gauss tables are in the registry");
            return Ok(Method::Fixed(Fixed {
                id: pid.to_string(),
                order: i.order,
                symplectic: i.symplectic,
                family: Family::Implicit,
                stepper: Box::new(PropagatorStepper { p, q }),
            }));
        }
        if let Some(stepper) = linear_stepper(id) {
            let i = info(id).expect("library ids are in the registry");
            return Ok(Method::Fixed(Fixed {
                id: id.to_string(),
                order: i.order,
                symplectic: i.symplectic,
                family: family_of(id),
                stepper,
            }));
        }
        if SEPARABLE_IDS.contains(&id) {
            let i = info(id).expect("library ids are in the registry");
            let why = if i.form == "prk" && !i.explicit {
                "it is an implicit partitioned pair, which steps Hamiltonian systems H(q, p) given by their gradients"
            } else {
                "it is symplectic only for separable Hamiltonians H = T(p) + V(q) and steps only systems that implement `Separable`"
            };
            bail!(
                "method '{id}' ({}) cannot step the {} problem: {why}; the gyroscopic system z' = Hz + u is an OdeSystem only \
                 (its kinetic energy depends on q through G). Use a Runge–Kutta table (e.g. gauss2) or a gaussN-propagator",
                i.form,
                problem.name()
            );
        }
        if id == "dop853" {
            bail!(
                "method 'dop853' (the ode_solvers peer) is offered for the separable problems, not for gyroscopic"
            );
        }
        bail!(
            "unknown method '{id}'; valid methods for {}: {}",
            problem.name(),
            valid_list(&Self::all_methods(problem))
        );
    }
    fn all_methods(_problem: ProblemId) -> Vec<String> {
        let mut v: Vec<String> = RK_IDS.iter().map(|s| s.to_string()).collect();
        v.extend(
            propagator_tables()
                .into_iter()
                .map(|(id, _, _)| id.to_string()),
        );
        v
    }
}

/// The problem with its default start, at end time `t_end`; the reference
/// end state is computed only when asked for (long runs and stability
/// searches judge by the energy alone).
pub fn oscillator(t_end: f64, with_reference: bool) -> Setup<Oscillator> {
    let sys = Oscillator { k: 1.0 };
    let z0 = vec![1.0, 0.0];
    let reference = if with_reference {
        sys.flow(&z0, t_end).expect("closed form")
    } else {
        vec![]
    };
    Setup::new(ProblemId::Oscillator, sys, z0, t_end, reference)
}

pub fn pendulum(t_end: f64, with_reference: bool) -> Setup<Pendulum> {
    let z0 = Pendulum::at_rest(2.0);
    let reference = if with_reference {
        Pendulum.flow(&z0, t_end).expect("a libration")
    } else {
        vec![]
    };
    Setup::new(ProblemId::Pendulum, Pendulum, z0, t_end, reference)
}

pub fn kepler(id: ProblemId, t_end: f64, with_reference: bool) -> Setup<Kepler> {
    let e = if id == ProblemId::KeplerHard {
        0.9
    } else {
        0.6
    };
    let sys = Kepler { e };
    let z0 = sys.initial_state();
    let reference = if with_reference {
        sys.flow(&z0, t_end).expect("a bound orbit")
    } else {
        vec![]
    };
    Setup::new(id, sys, z0, t_end, reference)
}

pub fn henon_heiles(t_end: f64, with_reference: bool) -> Setup<HenonHeiles> {
    let z0 = HenonHeiles::chaotic_start().to_vec();
    let reference = if with_reference {
        HenonHeiles.reference(&z0, t_end)
    } else {
        vec![]
    };
    Setup::new(ProblemId::HenonHeiles, HenonHeiles, z0, t_end, reference)
}

pub fn fpu(t_end: f64, with_reference: bool) -> Setup<Fpu> {
    let sys = Fpu::stiff();
    let z0 = sys.start();
    let reference = if with_reference {
        sys.reference(&z0, t_end)
    } else {
        vec![]
    };
    Setup::new(ProblemId::Fpu, sys, z0, t_end, reference)
}

/// `gyroscopic(n, seed, spread)` from `q = 0`, `p = (1, …, 1)` (positive
/// kinetic energy, all modes excited).
pub fn gyroscopic(
    n: usize,
    seed: u64,
    spread: f64,
    t_end: f64,
    with_reference: bool,
) -> Result<Setup<LinearHamiltonian>> {
    let sys = linear::gyroscopic(n, seed, spread)?;
    let mut z0 = vec![0.0; 2 * n];
    z0[n..].fill(1.0);
    let reference = if with_reference {
        sys.exact(&z0, t_end)?
    } else {
        vec![]
    };
    Ok(Setup::new(ProblemId::Gyroscopic, sys, z0, t_end, reference))
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
        v = w.iter().map(|x| x / norm).collect();
        if (next - lambda2).abs() <= 1e-12 * next {
            lambda2 = next;
            break;
        }
        lambda2 = next;
    }
    lambda2.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn omega_max_of_the_gyroscopic_system_is_near_the_spread() {
        let sys = linear::gyroscopic(10, 7, 1e4).unwrap();
        let w = omega_max(&sys);
        assert!((0.99e4..=1.0e4 + 0.3).contains(&w), "{w}");
    }

    #[test]
    fn separable_methods_on_the_linear_problem_say_why_not() {
        let err = match LinearHamiltonian::method("leapfrog", ProblemId::Gyroscopic) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("leapfrog cannot step the linear system"),
        };
        assert!(err.contains("separable"), "{err}");
        assert!(LinearHamiltonian::method("gauss2-propagator", ProblemId::Gyroscopic).is_ok());
        assert!(Kepler::method("gauss2-propagator", ProblemId::Kepler).is_err());
        let err = match Kepler::method("nope", ProblemId::Kepler) {
            Err(e) => e.to_string(),
            Ok(_) => panic!(),
        };
        assert!(err.contains("leapfrog") && err.contains("unknown"), "{err}");
    }
}
