//! Compare your own scheme with the library's best and with DOP853, on
//! Kepler and on a problem of your own — the workflow symlab exists for:
//! declare a scheme, let `butcher!` prove its claims, measure it.
//!
//! ```sh
//! cargo run --release --example my_scheme
//! ```
//!
//! The scheme is Suzuki's fourth-order fractal, five Störmer–Verlet steps
//! with fractions p, p, 1 − 4p, p, p where p = 1/(4 − 4^(1/3)) (M. Suzuki,
//! "Fractal decomposition of exponential operators with applications to
//! many-body theories and Monte Carlo simulations", Phys. Lett. A 146
//! (1990) 319–323). The library does not have it. Its fractions are exact
//! (a cube root), so `butcher!` proves its order 4 exactly at compile time.
//!
//! The second problem is written here: a quartic double well with a
//! coupling, H = (p₁² + p₂²)/2 + (q₁² − 1)²/4 + q₂²/2 + ε q₁² q₂² (ε = 0.1),
//! with no closed-form flow, so its reference is a converged run of the
//! library's order-10 composition.
//!
//! Both comparisons write what `symlab compare` writes — `runs.csv`, the
//! work–precision plots and `report.md` — to `out/my_scheme/<problem>/`.

use std::path::Path;

use compare::{
    AsSeparable, Defaults, Method, Problem, Setup, StackSizes, SweepSettings, work_precision,
};
use integrator_core::problems::{Kepler, reference_solution};
use integrator_core::{Separable, butcher};

butcher! {
    /// Suzuki's fractal: five Störmer–Verlet steps, order 4.
    pub Suzuki4 {
        let p = 1/(4 - cbrt(4));
        claims: [symplectic, symmetric, order = 4],
        compose: [p, p, 1 - 4*p, p, p],
    }
}

/// A coupled double well (see the module documentation).
#[derive(Clone)]
struct DoubleWell {
    eps: f64,
}

impl Separable for DoubleWell {
    fn dof(&self) -> usize {
        2
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        0.5 * (p[0] * p[0] + p[1] * p[1])
    }
    fn potential(&self, q: &[f64]) -> f64 {
        let w = q[0] * q[0] - 1.0;
        0.25 * w * w + 0.5 * q[1] * q[1] + self.eps * q[0] * q[0] * q[1] * q[1]
    }
    fn velocity(&self, p: &[f64], v: &mut [f64]) {
        v.copy_from_slice(p);
    }
    fn force(&self, q: &[f64], f: &mut [f64]) {
        let (x, y) = (q[0], q[1]);
        f[0] = -(x * (x * x - 1.0) + 2.0 * self.eps * x * y * y);
        f[1] = -(y + 2.0 * self.eps * x * x * y);
    }
}

impl Problem for DoubleWell {
    type Kind = AsSeparable;
    /// The state has 4 entries: timed runs step a `[f64; 4]` in registers,
    /// as the built-in problems do (the default steps slices, and compiles
    /// faster).
    const STACK_SIZES: StackSizes = StackSizes::only(4);
    fn name(&self) -> String {
        "double-well".into()
    }
    fn description(&self) -> String {
        format!("coupled double well (ε = {})", self.eps)
    }
    fn energy(&self, z: &[f64]) -> f64 {
        integrator_core::energy(self, z)
    }
    /// Above the barrier: the particle crosses between the wells.
    fn start(&self) -> Vec<f64> {
        vec![1.0, 0.5, 0.5, 0.0]
    }
    fn reference(&self, z0: &[f64], t_end: f64) -> Result<Vec<f64>, String> {
        Ok(reference_solution(self, z0, t_end, 2000.0))
    }
    fn defaults(&self) -> Defaults {
        Defaults {
            t_end: 20.0,
            h_min: 2e-3,
            h_max: 0.2,
        }
    }
}

/// Our scheme, the library's order-4 and best schemes by id, and DOP853.
fn methods<P: Problem<Kind = AsSeparable> + Separable>(sys: &P) -> compare::Result<Vec<Method<P>>> {
    let mut v = vec![Method::scheme("suzuki4", Suzuki4)];
    for id in ["forest-ruth", "pefrl", "kahan-li8", "dop853"] {
        v.push(Method::by_id(id, sys)?);
    }
    Ok(v)
}

fn compare_on<P: Problem<Kind = AsSeparable> + Separable>(sys: P) -> compare::Result<()> {
    let defaults = sys.defaults();
    let setup = Setup::new(sys.clone(), defaults.t_end)?;
    let settings = SweepSettings {
        points: 8,
        tolerances: compare::sweep::tolerance_range(8, 4, 18),
        ..SweepSettings::new(defaults, defaults.t_end)
    };
    let result = work_precision(&setup, &methods(&sys)?, &settings)?;
    let dir = Path::new("out").join("my_scheme").join(&setup.name);
    let files = result.write(&dir)?;
    println!("\n== {} ==", setup.description);
    print!("{}", result.summary());
    for f in files {
        println!("wrote {}", f.display());
    }
    Ok(())
}

fn main() -> compare::Result<()> {
    compare_on(Kepler { e: 0.6 })?;
    compare_on(DoubleWell { eps: 0.1 })?;
    Ok(())
}
