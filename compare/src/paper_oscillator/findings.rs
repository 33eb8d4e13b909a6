//! What the runs say about the paper's claims: numbers derived from the
//! runs beyond the per-run summaries, the closed-form predictions they are
//! checked against, and the yes/no answers a report states. A report only
//! formats these.

use super::{Experiment, Method, Trajectory, paper_closed_form_deviation};

/// An energy error at most this fraction of `H₀` is round-off.
const ROUND_OFF: f64 = 1e-13;

/// A bounded energy error: over the second half of a run at most this many
/// times its largest over the first half.
const BOUNDED_GROWTH: f64 = 1.5;

/// Numbers derived from the runs, beyond the per-run summaries.
#[derive(Clone, Debug)]
pub struct Findings {
    /// The largest and smallest step sizes of the set-up.
    pub h_max: f64,
    pub h_min: f64,
    /// The step sizes in increasing order.
    pub sorted_step_sizes: Vec<f64>,
    /// Explicit Euler at `h_max`: `|ΔH|` after `n/10` steps and at the end.
    pub euler_early: f64,
    pub euler_final: f64,
    /// The prediction `H₀((1 + h²k²)ⁿ − 1)` for explicit Euler at `h_max`.
    pub euler_predicted: f64,
    /// Heun at `h_max`: `|ΔH|` after `n/10` steps and at the end, and the
    /// steps at which it did not grow.
    pub heun_early: f64,
    pub heun_final: f64,
    pub heun_decreases: usize,
    /// The prediction `H₀((1 + (hk)⁴/4)ⁿ − 1)` for Heun at `h_max`.
    pub heun_predicted: f64,
    /// Symplectic Euler: the largest drift of its modified energy
    /// `H̃ = H − (hk²/2)·qp`, relative to `H₀`, over all step sizes.
    pub symplectic_euler_modified_drift: f64,
    /// The implicit midpoint rule at `h_max`: the phase error after `n/2`
    /// and `n` steps, and the prediction `−n·(hk − 2·atan(hk/2))`.
    pub midpoint_phase_half: f64,
    pub midpoint_phase_final: f64,
    pub midpoint_phase_predicted: f64,
    /// Symplectic Euler at `h_max`: the phase error after `n/2` and `n` steps.
    pub symplectic_euler_phase_half: f64,
    pub symplectic_euler_phase_final: f64,
    /// Its secular part, `n·(acos(1 − (hk)²/2) − hk)`.
    pub symplectic_euler_phase_predicted: f64,
    /// The paper's printed closed form against the exact flow used here.
    pub closed_form_deviation: f64,
    /// The symplectic Runge–Kutta methods (midpoint, DIRK2, Gauss–Legendre
    /// 2) with their largest `max |ΔH|/H₀` over all step sizes.
    pub round_off_worst: Vec<(Method, f64)>,
    /// Every symplectic run's energy error is bounded (second half at most
    /// 1.5× the first) or round-off.
    pub symplectic_energy_bounded: bool,
    /// The same at `h_max` alone.
    pub symplectic_energy_bounded_at_h_max: bool,
    /// Every non-symplectic run's `|ΔH|` grows at every step.
    pub non_symplectic_energy_grows: bool,
    /// Explicit Euler's `max |ΔH|` grows with `h`.
    pub euler_grows_with_h: bool,
    /// At `h_max` every symplectic method's largest `|Δq|` is below
    /// explicit Euler's.
    pub euler_worst_at_h_max: bool,
    /// The paper DIRK2 at `h = 0.05` (its figure 2), where the set-up has
    /// that step size: the largest amplitude error `|r/r₀ − 1|` of the run.
    pub dirk2_amplitude_at_0_05: Option<f64>,
    /// At `h_max`, the symplectic methods whose largest `|Δq|` is above
    /// Heun's, and those at or below it, with that error.
    pub worse_than_heun: Vec<(Method, f64)>,
    pub better_than_heun: Vec<(Method, f64)>,
    /// Heun's final `|ΔH|/H₀` at `h_max`.
    pub heun_energy_drift: f64,
    /// Where symplectic Euler's energy error exceeds Heun's at `h_max`: the
    /// step after which Heun's growing error would pass symplectic Euler's
    /// bounded one, `ln(1 + max|ΔH|/H₀) / ln(1 + (hk)⁴/4)`.
    pub heun_passes_symplectic_euler_after: Option<f64>,
    /// Gauss–Legendre 2 has the smallest largest `|Δq|` of the symplectic
    /// RK methods at every step size.
    pub higher_order_better: bool,
    /// At `h_min`, the two largest `max |ΔH|/H₀` and the two largest
    /// `max |Δq|`, largest first.
    pub largest_energy_errors_at_h_min: Vec<(f64, Method)>,
    pub largest_position_errors_at_h_min: Vec<(f64, Method)>,
    /// The methods of those two lists are all of order 1.
    pub first_order_lead_at_h_min: bool,
    /// Every run of the symplectic RK methods keeps the energy to round-off.
    pub rk_round_off: bool,
}

/// `v[i]`, or NaN for a run that stopped before step `i` (a report prints
/// it as missing and lists the runs that stopped and why).
pub fn value_at(v: &[f64], i: usize) -> f64 {
    v.get(i).copied().unwrap_or(f64::NAN)
}

/// The relative difference `|measured − predicted| / |predicted|`.
pub fn relative_difference(measured: f64, predicted: f64) -> f64 {
    ((measured - predicted) / predicted).abs()
}

/// Bounded (at most 1.5× over the second half) or round-off.
fn energy_bounded(r: &Trajectory) -> bool {
    let (a, b) = r.energy_error_halves();
    b <= BOUNDED_GROWTH * a || r.max_energy_error() <= ROUND_OFF * r.energy0
}

/// The symplectic Runge–Kutta methods of the set: they conserve quadratic
/// invariants exactly.
const SYMPLECTIC_RK: [Method; 3] = [
    Method::ImplicitMidpoint,
    Method::PaperDirk2,
    Method::GaussLegendre2,
];

impl Findings {
    pub fn of(exp: &Experiment) -> Findings {
        let c = &exp.config;
        let (h_max, h_min) = c.h_range();
        let n = c.steps;
        let (k, e0) = (c.k, c.energy0());
        let euler = exp.run(Method::ExplicitEuler, h_max);
        let heun = exp.run(Method::Heun, h_max);
        let mid = exp.run(Method::ImplicitMidpoint, h_max);
        let se = exp.run(Method::SymplecticEuler, h_max);
        let hk = h_max * k;
        let symplectic_euler_modified_drift = c
            .step_sizes
            .iter()
            .map(|&h| {
                let r = exp.run(Method::SymplecticEuler, h);
                let modified = |i: usize| {
                    r.energy_error[i] - 0.5 * h * k * k * (r.q[i] * r.p[i] - r.q[0] * r.p[0])
                };
                (0..r.t.len())
                    .map(modified)
                    .fold(0.0f64, |m, x| m.max(x.abs()))
                    / e0
            })
            .fold(0.0, f64::max);
        let (mid_phase, se_phase) = (mid.phase_error(), se.phase_error());
        let mut sorted_step_sizes = c.step_sizes.clone();
        sorted_step_sizes.sort_by(f64::total_cmp);
        let symplectic_at_h_max = || exp.at(h_max).filter(|r| r.method.info().symplectic);
        let heun_summary = heun.summary();
        let se_summary = se.summary();
        let split_by_heun = |worse: bool| -> Vec<(Method, f64)> {
            symplectic_at_h_max()
                .filter(|r| (r.max_err_q() > heun_summary.max_err_q) == worse)
                .map(|r| (r.method, r.max_err_q()))
                .collect()
        };
        let ranked = |key: &dyn Fn(&Trajectory) -> f64| {
            let mut v: Vec<(f64, Method)> = exp.at(h_min).map(|r| (key(r), r.method)).collect();
            v.sort_by(|a, b| b.0.total_cmp(&a.0));
            v.truncate(2);
            v
        };
        let largest_energy_errors_at_h_min =
            ranked(&|r: &Trajectory| r.max_energy_error() / r.energy0);
        let largest_position_errors_at_h_min = ranked(&|r: &Trajectory| r.max_err_q());
        let first_order_lead_at_h_min = largest_energy_errors_at_h_min
            .iter()
            .chain(&largest_position_errors_at_h_min)
            .all(|(_, m)| m.info().order == 1);
        Findings {
            h_max,
            h_min,
            euler_early: value_at(&euler.energy_error, n / 10).abs(),
            euler_final: value_at(&euler.energy_error, n).abs(),
            euler_predicted: e0 * ((1.0 + hk * hk).powi(n as i32) - 1.0),
            heun_early: value_at(&heun.energy_error, n / 10).abs(),
            heun_final: value_at(&heun.energy_error, n).abs(),
            heun_decreases: heun.energy_error_decreases(),
            heun_predicted: e0 * ((1.0 + hk.powi(4) / 4.0).powi(n as i32) - 1.0),
            symplectic_euler_modified_drift,
            midpoint_phase_half: value_at(&mid_phase, n / 2),
            midpoint_phase_final: value_at(&mid_phase, n),
            midpoint_phase_predicted: -(n as f64) * (hk - 2.0 * (hk / 2.0).atan()),
            symplectic_euler_phase_half: value_at(&se_phase, n / 2),
            symplectic_euler_phase_final: value_at(&se_phase, n),
            symplectic_euler_phase_predicted: n as f64 * ((1.0 - hk * hk / 2.0).acos() - hk),
            closed_form_deviation: paper_closed_form_deviation(euler, c),
            round_off_worst: SYMPLECTIC_RK
                .iter()
                .map(|&m| {
                    let worst = c
                        .step_sizes
                        .iter()
                        .map(|&h| exp.max_rel_energy(m, h))
                        .fold(0.0, f64::max);
                    (m, worst)
                })
                .collect(),
            symplectic_energy_bounded: exp
                .runs
                .iter()
                .filter(|r| r.method.info().symplectic)
                .all(energy_bounded),
            symplectic_energy_bounded_at_h_max: symplectic_at_h_max().all(energy_bounded),
            non_symplectic_energy_grows: exp
                .runs
                .iter()
                .filter(|r| !r.method.info().symplectic)
                .all(|r| r.energy_error_decreases() == 0),
            euler_grows_with_h: sorted_step_sizes.windows(2).all(|p| {
                exp.max_rel_energy(Method::ExplicitEuler, p[1])
                    > exp.max_rel_energy(Method::ExplicitEuler, p[0])
            }),
            euler_worst_at_h_max: symplectic_at_h_max().all(|r| r.max_err_q() < euler.max_err_q()),
            dirk2_amplitude_at_0_05: exp.get(Method::PaperDirk2, 0.05).map(|r| {
                r.amplitude_error()
                    .iter()
                    .fold(0.0f64, |m, x| m.max(x.abs()))
            }),
            worse_than_heun: split_by_heun(true),
            better_than_heun: split_by_heun(false),
            heun_energy_drift: heun_summary.final_energy_error.abs() / e0,
            heun_passes_symplectic_euler_after: (se_summary.max_energy_error
                > heun_summary.max_energy_error)
                .then(|| se_summary.max_rel_energy_error.ln_1p() / (hk.powi(4) / 4.0).ln_1p()),
            higher_order_better: c.step_sizes.iter().all(|&h| {
                let gl = exp.run(Method::GaussLegendre2, h).max_err_q();
                gl < exp.run(Method::ImplicitMidpoint, h).max_err_q()
                    && gl < exp.run(Method::PaperDirk2, h).max_err_q()
            }),
            largest_energy_errors_at_h_min,
            largest_position_errors_at_h_min,
            first_order_lead_at_h_min,
            rk_round_off: exp
                .runs
                .iter()
                .filter(|r| SYMPLECTIC_RK.contains(&r.method))
                .all(|r| r.max_energy_error() <= ROUND_OFF * r.energy0),
            sorted_step_sizes,
        }
    }
}
