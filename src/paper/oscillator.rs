//! The oscillator experiment of the paper's section 5 (its figures 2–4):
//! `H = ½(p² + k²q²)` integrated by six schemes at several step sizes, every
//! step compared with the closed-form solution.
//!
//! Everything the report and the tests say is computed here, from the runs:
//! nothing is hard-coded but the set-up.

use anyhow::{Context, Result, bail};
use integrator_core::library::{
    ExplicitEuler, GaussLegendre2, Heun, ImplicitMidpoint, PaperDirk2, SymplecticEulerA,
};
use integrator_core::problems::{ExactFlow, Oscillator};
use integrator_core::{Info, Scheme, Step, energy, integrate};

/// Energy errors below this are drawn at this value on the log axis
/// (schemes that conserve the quadratic energy can be exactly 0).
pub const ENERGY_FLOOR: f64 = 1e-17;

/// Energy errors above this are drawn at this value (an unstable run can
/// reach the end of the f64 range, which no axis can span).
pub const ENERGY_CEILING: f64 = 1e100;

/// The most steps per run: every step is written to the series CSV and
/// drawn in the plots.
pub const MAX_STEPS: usize = 20_000;

/// The set-up of the experiment.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    /// The frequency `k` of `H = ½(p² + k²q²)`.
    pub k: f64,
    pub q0: f64,
    pub p0: f64,
    /// Steps per run.
    pub steps: usize,
    /// The step sizes, one run of every method per step size.
    pub step_sizes: Vec<f64>,
}

impl Default for Config {
    /// The paper's set-up where it states one (h = 0.01, 0.05, 0.1 and 200
    /// steps), and k = 1, q₀ = 1, p₀ = 0 where it does not.
    fn default() -> Self {
        Config {
            k: 1.0,
            q0: 1.0,
            p0: 0.0,
            steps: 200,
            step_sizes: vec![0.01, 0.05, 0.1],
        }
    }
}

impl Config {
    /// Refuse a set-up the experiment cannot measure, naming the argument.
    pub fn validate(&self) -> Result<()> {
        if !(self.k.is_finite() && self.k > 0.0) {
            bail!("--k must be a finite positive number (got {})", self.k);
        }
        if !(self.q0.is_finite() && self.p0.is_finite()) {
            bail!(
                "--q0 and --p0 must be finite (got q0 = {}, p0 = {})",
                self.q0,
                self.p0
            );
        }
        if self.q0 == 0.0 && self.p0 == 0.0 {
            bail!(
                "--q0 and --p0 are both 0: the oscillator would rest at its equilibrium with zero energy"
            );
        }
        if self.steps < 20 {
            bail!(
                "--steps must be at least 20 (got {}): the claims compare the run's halves and its first 20 steps",
                self.steps
            );
        }
        if self.steps > MAX_STEPS {
            bail!(
                "--steps must be at most {MAX_STEPS} (got {}): every step is plotted and written",
                self.steps
            );
        }
        let e0 = self.energy0();
        if !(e0.is_finite() && e0 >= f64::MIN_POSITIVE) {
            bail!(
                "--k {:e}, --q0 {:e}, --p0 {:e}: the energy H(q0, p0) = {e0:e} is not a normal positive f64, \
                 so relative energy errors |H − H0|/H0 would be meaningless; choose values whose \
                 energy lies between 1e-300 and 1e300",
                self.k,
                self.q0,
                self.p0
            );
        }
        if self.step_sizes.is_empty() {
            bail!("--h needs at least one step size");
        }
        for &h in &self.step_sizes {
            if !(h.is_finite() && h > 0.0) {
                bail!("--h: every step size must be a finite positive number (got {h})");
            }
        }
        for (i, &h) in self.step_sizes.iter().enumerate() {
            if self.step_sizes[..i].contains(&h) {
                bail!("--h: step size {h} is given twice");
            }
        }
        Ok(())
    }

    pub fn oscillator(&self) -> Oscillator {
        Oscillator { k: self.k }
    }

    pub fn z0(&self) -> [f64; 2] {
        [self.q0, self.p0]
    }

    /// `H(q₀, p₀)`.
    pub fn energy0(&self) -> f64 {
        energy(&self.oscillator(), &self.z0())
    }
}

/// A step size as it appears in file names: as written where that is short
/// (`0.01`), in scientific notation otherwise (`1e-300`, not 300 digits).
pub fn h_name(h: f64) -> String {
    let plain = format!("{h}");
    if plain.len() <= 10 {
        plain
    } else {
        format!("{h:e}")
    }
}

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

    /// The states `z₀, …, z_n` of `n` steps of size `h`.
    /// The states of a run of `n` steps, and why it stopped early if it
    /// did (a divergence or a failed stage solve: the states up to the last
    /// good step are kept, so the run is reported, not dropped).
    fn states(
        self,
        osc: &Oscillator,
        z0: [f64; 2],
        h: f64,
        n: usize,
    ) -> Result<(Vec<[f64; 2]>, Option<String>)> {
        fn run<M: Step<Oscillator>>(
            m: &M,
            osc: &Oscillator,
            z0: [f64; 2],
            h: f64,
            n: usize,
        ) -> Result<(Vec<[f64; 2]>, Option<String>)> {
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
                return Ok((
                    out,
                    Some(format!("diverged at step {k}: the energy is not finite")),
                ));
            }
            Ok((out, failure))
        }
        let result = match self {
            Method::ExplicitEuler => run(&ExplicitEuler, osc, z0, h, n),
            Method::Heun => run(&Heun, osc, z0, h, n),
            Method::ImplicitMidpoint => run(&ImplicitMidpoint, osc, z0, h, n),
            Method::PaperDirk2 => run(&PaperDirk2, osc, z0, h, n),
            Method::GaussLegendre2 => run(&GaussLegendre2, osc, z0, h, n),
            Method::SymplecticEuler => run(&SymplecticEulerA, osc, z0, h, n),
        };
        result.with_context(|| format!("{} with h = {h}", self.label()))
    }
}

/// One run: the numerical and the exact solution at every step.
#[derive(Clone, Debug)]
pub struct Trajectory {
    pub method: Method,
    pub h: f64,
    pub k: f64,
    /// `H(z₀)`.
    pub energy0: f64,
    pub t: Vec<f64>,
    pub q: Vec<f64>,
    pub p: Vec<f64>,
    pub q_exact: Vec<f64>,
    pub p_exact: Vec<f64>,
    /// `H(zₙ) − H(z₀)`, signed.
    pub energy_error: Vec<f64>,
    /// Why the run stopped before its last step (a divergence, a failed
    /// stage solve); the vectors then end at the last good step.
    pub failure: Option<String>,
}

/// `atan2` angles made continuous (jumps of 2π removed).
fn unwrap_angles(angles: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for a in angles {
        match out.last() {
            None => out.push(a),
            Some(&prev) => {
                let tau = std::f64::consts::TAU;
                let d = (a - prev).rem_euclid(tau);
                let d = if d > std::f64::consts::PI { d - tau } else { d };
                out.push(prev + d);
            }
        }
    }
    out
}

impl Trajectory {
    /// `ok`, or why the run stopped early.
    pub fn status(&self) -> String {
        self.failure.clone().unwrap_or_else(|| "ok".into())
    }

    /// Steps taken.
    pub fn steps(&self) -> usize {
        self.t.len() - 1
    }

    pub fn err_q(&self, n: usize) -> f64 {
        self.q[n] - self.q_exact[n]
    }

    pub fn err_p(&self, n: usize) -> f64 {
        self.p[n] - self.p_exact[n]
    }

    fn max_abs(v: impl Iterator<Item = f64>) -> f64 {
        v.fold(0.0, |m, x| m.max(x.abs()))
    }

    pub fn max_err_q(&self) -> f64 {
        Self::max_abs((0..self.t.len()).map(|n| self.err_q(n)))
    }

    pub fn max_err_p(&self) -> f64 {
        Self::max_abs((0..self.t.len()).map(|n| self.err_p(n)))
    }

    pub fn max_energy_error(&self) -> f64 {
        Self::max_abs(self.energy_error.iter().copied())
    }

    /// The largest `|H − H₀|` over steps `range`.
    pub fn max_energy_error_over(&self, range: std::ops::Range<usize>) -> f64 {
        Self::max_abs(self.energy_error[range].iter().copied())
    }

    /// The largest `|H − H₀|` over the first and over the second half of the
    /// run (steps 1..=n/2 and n/2+1..=n).
    pub fn energy_error_halves(&self) -> (f64, f64) {
        let half = self.steps() / 2;
        (
            self.max_energy_error_over(1..half + 1),
            self.max_energy_error_over(half + 1..self.t.len()),
        )
    }

    /// How often the signed energy error changes sign over the run (exact
    /// zeros skipped).
    pub fn energy_sign_changes(&self) -> usize {
        let signs: Vec<bool> = self
            .energy_error
            .iter()
            .filter(|e| **e != 0.0)
            .map(|e| *e > 0.0)
            .collect();
        signs.windows(2).filter(|w| w[0] != w[1]).count()
    }

    /// Steps at which `|H − H₀|` did not grow.
    pub fn energy_error_decreases(&self) -> usize {
        self.energy_error
            .windows(2)
            .filter(|w| w[1].abs() <= w[0].abs())
            .count()
    }

    /// The phase of the numerical solution minus the exact phase at every
    /// step, from the angle of `(q, −p/k)` (continuous, radians). Positive:
    /// the numerical solution runs ahead.
    pub fn phase_error(&self) -> Vec<f64> {
        let k = self.k;
        let num = unwrap_angles(self.q.iter().zip(&self.p).map(|(&q, &p)| (-p / k).atan2(q)));
        let ex = unwrap_angles(
            self.q_exact
                .iter()
                .zip(&self.p_exact)
                .map(|(&q, &p)| (-p / k).atan2(q)),
        );
        num.iter().zip(&ex).map(|(a, b)| a - b).collect()
    }

    /// `r/r₀ − 1` at every step, with `r = √(q² + (p/k)²)` (the exact
    /// solution keeps `r` constant).
    pub fn amplitude_error(&self) -> Vec<f64> {
        let k = self.k;
        let r = |q: f64, p: f64| q.hypot(p / k);
        let r0 = r(self.q_exact[0], self.p_exact[0]);
        self.q
            .iter()
            .zip(&self.p)
            .map(|(&q, &p)| r(q, p) / r0 - 1.0)
            .collect()
    }

    pub fn summary(&self) -> Summary {
        let n = self.steps();
        let (first_half, second_half) = self.energy_error_halves();
        Summary {
            method: self.method,
            h: self.h,
            steps: n,
            max_err_q: self.max_err_q(),
            max_err_p: self.max_err_p(),
            max_energy_error: self.max_energy_error(),
            max_rel_energy_error: self.max_energy_error() / self.energy0,
            final_err_q: self.err_q(n),
            final_err_p: self.err_p(n),
            final_energy_error: self.energy_error[n],
            final_phase_error: self.phase_error()[n],
            final_amplitude_error: self.amplitude_error()[n],
            energy_error_first_half: first_half,
            energy_error_second_half: second_half,
            energy_sign_changes: self.energy_sign_changes(),
        }
    }
}

/// What one run measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Summary {
    pub method: Method,
    pub h: f64,
    pub steps: usize,
    pub max_err_q: f64,
    pub max_err_p: f64,
    /// `max |H − H₀|`.
    pub max_energy_error: f64,
    /// `max |H − H₀| / H₀`.
    pub max_rel_energy_error: f64,
    pub final_err_q: f64,
    pub final_err_p: f64,
    pub final_energy_error: f64,
    pub final_phase_error: f64,
    pub final_amplitude_error: f64,
    pub energy_error_first_half: f64,
    pub energy_error_second_half: f64,
    pub energy_sign_changes: usize,
}

/// One method at one step size.
pub fn simulate(config: &Config, method: Method, h: f64) -> Result<Trajectory> {
    config.validate()?;
    let osc = config.oscillator();
    let z0 = config.z0();
    let n = config.steps;
    let (states, failure) = method.states(&osc, z0, h, n)?;
    let energy0 = config.energy0();
    let mut traj = Trajectory {
        method,
        h,
        k: config.k,
        energy0,
        t: Vec::with_capacity(n + 1),
        q: Vec::with_capacity(n + 1),
        p: Vec::with_capacity(n + 1),
        q_exact: Vec::with_capacity(n + 1),
        p_exact: Vec::with_capacity(n + 1),
        energy_error: Vec::with_capacity(n + 1),
        failure,
    };
    for (i, z) in states.iter().enumerate() {
        let t = i as f64 * h;
        let exact = osc
            .flow(&z0, t)
            .context("the oscillator's exact flow is defined for every state")?;
        traj.t.push(t);
        traj.q.push(z[0]);
        traj.p.push(z[1]);
        traj.q_exact.push(exact[0]);
        traj.p_exact.push(exact[1]);
        traj.energy_error.push(energy(&osc, z) - energy0);
    }
    Ok(traj)
}

/// Every method at every step size of the set-up.
#[derive(Clone, Debug)]
pub struct Experiment {
    pub config: Config,
    /// By step size (in the set-up's order), then method (in [`Method::ALL`] order).
    pub runs: Vec<Trajectory>,
}

impl Experiment {
    /// The run of `method` at step size `h` (one of the set-up's).
    pub fn get(&self, method: Method, h: f64) -> Option<&Trajectory> {
        self.runs.iter().find(|r| r.method == method && r.h == h)
    }

    /// The runs at step size `h`, in [`Method::ALL`] order.
    pub fn at(&self, h: f64) -> impl Iterator<Item = &Trajectory> {
        self.runs.iter().filter(move |r| r.h == h)
    }
}

/// Run the whole oscillator experiment.
pub fn oscillator_experiment(config: &Config) -> Result<Experiment> {
    config.validate()?;
    let mut runs = Vec::new();
    for &h in &config.step_sizes {
        for method in Method::ALL {
            runs.push(simulate(config, method, h)?);
        }
    }
    Ok(Experiment {
        config: config.clone(),
        runs,
    })
}

/// The paper's closed form, `q(t) = √(q₀² + p₀²/k²)·cos(kt − arctg(p₀/(kq₀)))`,
/// as printed (section 5).
pub fn paper_closed_form_q(k: f64, q0: f64, p0: f64, t: f64) -> f64 {
    (q0 * q0 + p0 * p0 / (k * k)).sqrt() * (k * t - (p0 / (k * q0)).atan()).cos()
}

/// The largest difference between the paper's closed form and the exact flow
/// used here, over the times of a run.
pub fn paper_closed_form_deviation(traj: &Trajectory, config: &Config) -> f64 {
    traj.t
        .iter()
        .zip(&traj.q_exact)
        .map(|(&t, &q)| (paper_closed_form_q(config.k, config.q0, config.p0, t) - q).abs())
        .fold(0.0, f64::max)
}

/// `oscillator_errors.csv`: one row per (h, method).
pub fn errors_csv(exp: &Experiment) -> String {
    let mut s = String::from(
        "h,method,label,order,symplectic,steps,t_end,max_err_q,max_err_p,max_energy_error,max_rel_energy_error,\
         final_err_q,final_err_p,final_energy_error,final_phase_error,final_amplitude_error,\
         energy_error_first_half,energy_error_second_half,energy_sign_changes,status\n",
    );
    for r in &exp.runs {
        let m = r.summary();
        let info = r.method.info();
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{},{}\n",
            r.h,
            compare::output::csv_field(r.method.id()),
            compare::output::csv_field(r.method.label()),
            info.order,
            info.symplectic,
            m.steps,
            r.t[m.steps],
            m.max_err_q,
            m.max_err_p,
            m.max_energy_error,
            m.max_rel_energy_error,
            m.final_err_q,
            m.final_err_p,
            m.final_energy_error,
            m.final_phase_error,
            m.final_amplitude_error,
            m.energy_error_first_half,
            m.energy_error_second_half,
            m.energy_sign_changes,
            // Quoted as RFC 4180 says where a comma, quote or newline
            // would split it.
            compare::output::csv_field(&r.status()),
        ));
    }
    s
}

/// `oscillator_h{h}_series.csv`: every step of every method at one step
/// size, with the exact solution: `step,t,q_exact,p_exact`, then
/// `{id}_q,{id}_p,{id}_dH` per method (`dH = H − H₀`, signed).
pub fn series_csv(exp: &Experiment, h: f64) -> String {
    let runs: Vec<&Trajectory> = exp.at(h).collect();
    let mut s = String::from("step,t,q_exact,p_exact");
    for r in &runs {
        let id = r.method.id();
        s.push_str(&format!(",{id}_q,{id}_p,{id}_dH"));
    }
    s.push('\n');
    // The longest run carries the exact solution; a run that stopped early
    // leaves its cells empty after its last good step.
    let Some(first) = runs.iter().max_by_key(|r| r.t.len()) else {
        return s;
    };
    for n in 0..first.t.len() {
        s.push_str(&format!(
            "{},{},{:e},{:e}",
            n, first.t[n], first.q_exact[n], first.p_exact[n]
        ));
        for r in &runs {
            if n < r.t.len() {
                s.push_str(&format!(
                    ",{:e},{:e},{:e}",
                    r.q[n], r.p[n], r.energy_error[n]
                ));
            } else {
                s.push_str(",,,");
            }
        }
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    //! The paper's qualitative claims, on the numbers this module computes.
    use super::*;

    fn run_h01() -> Experiment {
        let config = Config {
            step_sizes: vec![0.1],
            ..Config::default()
        };
        oscillator_experiment(&config).unwrap()
    }

    #[test]
    fn gauss_methods_conserve_the_quadratic_energy_to_round_off() {
        let exp = run_h01();
        for m in [
            Method::GaussLegendre2,
            Method::ImplicitMidpoint,
            Method::PaperDirk2,
        ] {
            let r = exp.get(m, 0.1).unwrap();
            let rel = r.max_energy_error() / r.energy0;
            assert!(rel <= 1e-13, "{}: relative energy error {rel:e}", m.label());
        }
    }

    #[test]
    fn symplectic_euler_energy_error_is_bounded_and_oscillates() {
        let exp = run_h01();
        let r = exp.get(Method::SymplecticEuler, 0.1).unwrap();
        let (first, second) = r.energy_error_halves();
        assert!(
            second <= 1.5 * first,
            "first half {first:e}, second half {second:e}"
        );
        assert!(
            r.energy_sign_changes() >= 2,
            "sign changes: {}",
            r.energy_sign_changes()
        );
        // Not round-off: an O(h) oscillation.
        assert!(r.max_energy_error() / r.energy0 > 1e-3);
    }

    #[test]
    fn explicit_euler_energy_error_grows_by_more_than_ten() {
        let exp = run_h01();
        let r = exp.get(Method::ExplicitEuler, 0.1).unwrap();
        let n = r.steps();
        assert!(r.energy_error[n].abs() > 10.0 * r.energy_error[n / 10].abs());
        assert_eq!(r.energy_error_decreases(), 0);
    }

    #[test]
    fn heun_energy_drifts_monotonically_and_linearly() {
        let exp = run_h01();
        let r = exp.get(Method::Heun, 0.1).unwrap();
        assert_eq!(
            r.energy_error_decreases(),
            0,
            "|H − H₀| grows at every step"
        );
        let ratio = r.energy_error[200].abs() / r.energy_error[20].abs();
        assert!((9.0..11.0).contains(&ratio), "step 200 / step 20 = {ratio}");
        assert!(
            r.energy_error[200] > 0.0,
            "Heun gains energy on the oscillator"
        );
    }

    #[test]
    fn symplectic_methods_have_a_phase_error_growing_linearly() {
        let exp = run_h01();
        let r = exp.get(Method::ImplicitMidpoint, 0.1).unwrap();
        let phase = r.phase_error();
        let ratio = phase[200] / phase[100];
        assert!((1.9..2.1).contains(&ratio), "phase error 200/100 = {ratio}");
        // The midpoint rule rotates by 2·atan(hk/2) per step, slower than hk.
        let predicted = -200.0 * (0.1 - 2.0 * (0.05f64).atan());
        assert!((phase[200] - predicted).abs() < 1e-10 * predicted.abs().max(1.0) + 1e-12);
    }

    #[test]
    fn the_papers_closed_form_agrees_with_the_exact_flow() {
        let config = Config::default();
        let exp = run_h01();
        let r = exp.get(Method::Heun, 0.1).unwrap();
        assert!(paper_closed_form_deviation(r, &config) < 1e-14);
    }

    #[test]
    fn bad_set_ups_are_refused_with_the_argument_named() {
        let bad = [
            Config {
                k: -1.0,
                ..Config::default()
            },
            Config {
                k: f64::NAN,
                ..Config::default()
            },
            Config {
                q0: 0.0,
                p0: 0.0,
                ..Config::default()
            },
            Config {
                steps: 3,
                ..Config::default()
            },
            Config {
                step_sizes: vec![],
                ..Config::default()
            },
            Config {
                step_sizes: vec![0.1, 0.0],
                ..Config::default()
            },
            Config {
                step_sizes: vec![0.1, 0.1],
                ..Config::default()
            },
        ];
        for c in bad {
            let e = oscillator_experiment(&c).unwrap_err().to_string();
            assert!(e.starts_with("--"), "{e}");
        }
    }

    #[test]
    fn csv_has_a_row_per_run() {
        let exp = run_h01();
        let csv = errors_csv(&exp);
        assert_eq!(csv.lines().count(), 1 + Method::ALL.len());
        let series = series_csv(&exp, 0.1);
        assert_eq!(series.lines().count(), 1 + 201);
        assert_eq!(
            series.lines().next().unwrap().split(',').count(),
            4 + 3 * Method::ALL.len()
        );
    }
}
