//! The six schemes of the paper's section 5, from the scheme library.

use integrator_core::library::{
    ExplicitEuler, GaussLegendre2, Heun, ImplicitMidpoint, PaperDirk2, SymplecticEulerA,
};
use integrator_core::problems::Oscillator;
use integrator_core::{Info, Scheme, Step, energy, integrate};

/// The schemes of the paper's section 5, from the scheme library.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    ExplicitEuler,
    Heun,
    /// The implicit midpoint rule, the paper's "Euler midpoint" (its eq. 20).
    ImplicitMidpoint,
    /// The paper's 2-stage semi-implicit symplectic RK (its figure 2).
    PaperDirk2,
    /// 2-stage Gauss–Legendre (the paper's eq. 21).
    GaussLegendre2,
    /// Symplectic Euler, kick then drift (`p` first).
    SymplecticEuler,
}

impl Method {
    pub const ALL: [Method; 6] = [
        Method::ExplicitEuler,
        Method::Heun,
        Method::ImplicitMidpoint,
        Method::PaperDirk2,
        Method::GaussLegendre2,
        Method::SymplecticEuler,
    ];

    /// The scheme's id in the catalogue (`symlab check --builtin ID`).
    pub fn id(self) -> &'static str {
        match self {
            Method::ExplicitEuler => "euler",
            Method::Heun => "heun",
            Method::ImplicitMidpoint => "midpoint",
            Method::PaperDirk2 => "paper-dirk2",
            Method::GaussLegendre2 => "gauss2",
            Method::SymplecticEuler => "symplectic-euler-a",
        }
    }

    /// A short name for tables and legends.
    pub fn label(self) -> &'static str {
        match self {
            Method::ExplicitEuler => "explicit Euler",
            Method::Heun => "Heun",
            Method::ImplicitMidpoint => "implicit midpoint",
            Method::PaperDirk2 => "paper DIRK2",
            Method::GaussLegendre2 => "Gauss–Legendre 2",
            Method::SymplecticEuler => "symplectic Euler",
        }
    }

    /// What `butcher!` proved about the scheme's table.
    pub fn info(self) -> Info {
        match self {
            Method::ExplicitEuler => ExplicitEuler::INFO,
            Method::Heun => Heun::INFO,
            Method::ImplicitMidpoint => ImplicitMidpoint::INFO,
            Method::PaperDirk2 => PaperDirk2::INFO,
            Method::GaussLegendre2 => GaussLegendre2::INFO,
            Method::SymplecticEuler => SymplecticEulerA::INFO,
        }
    }

    /// The states `z₀, …, z_n` of a run of `n` steps of size `h`, and why
    /// it stopped early if it did (a divergence or a failed stage solve:
    /// the states up to the last good step are kept, so the run is
    /// reported, not dropped).
    pub(crate) fn states(
        self,
        osc: &Oscillator,
        z0: [f64; 2],
        h: f64,
        n: usize,
    ) -> (Vec<[f64; 2]>, Option<String>) {
        fn run<M: Step<Oscillator>>(
            m: &M,
            osc: &Oscillator,
            z0: [f64; 2],
            h: f64,
            n: usize,
        ) -> (Vec<[f64; 2]>, Option<String>) {
            let mut z = z0.to_vec();
            let mut out = Vec::with_capacity(n + 1);
            let failure = integrate(m, osc, &mut z, 0.0, h, n, |_, _, z| out.push([z[0], z[1]]))
                .err()
                .map(|e| e.to_string());
            // An energy that overflows is a divergence too, even while the
            // state is finite.
            let bad = out.iter().position(|z| !energy(osc, z).is_finite());
            if let Some(k) = bad {
                out.truncate(k);
                return (
                    out,
                    Some(format!("diverged at step {k}: the energy is not finite")),
                );
            }
            (out, failure)
        }
        match self {
            Method::ExplicitEuler => run(&ExplicitEuler, osc, z0, h, n),
            Method::Heun => run(&Heun, osc, z0, h, n),
            Method::ImplicitMidpoint => run(&ImplicitMidpoint, osc, z0, h, n),
            Method::PaperDirk2 => run(&PaperDirk2, osc, z0, h, n),
            Method::GaussLegendre2 => run(&GaussLegendre2, osc, z0, h, n),
            Method::SymplecticEuler => run(&SymplecticEulerA, osc, z0, h, n),
        }
    }
}
