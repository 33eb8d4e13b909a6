//! "What this run measured": the table of every run, the runs that stopped,
//! the energy of each method, and the position and phase at the largest
//! step size.

use std::fmt::Write as _;

use compare::format::{self, MISSING};
use compare::paper_oscillator::{
    ENERGY_FLOOR, Experiment, Findings, Method, h_name, relative_difference, value_at,
};

use super::{growth_with_h, markdown_table, sci2};

pub(super) fn write(w: &mut String, exp: &Experiment, f: &Findings) {
    let _ = writeln!(w, "## What this run measured\n");
    runs(w, exp);
    let _ = writeln!(w, "### Energy\n");
    euler_energy(w, exp, f);
    heun_energy(w, exp, f);
    round_off_energy(w, f);
    symplectic_euler_energy(w, exp, f);
    phase(w, exp, f);
}

/// The table of every run, and the runs that stopped early.
fn runs(w: &mut String, exp: &Experiment) {
    let n = exp.config.steps;
    let _ = writeln!(
        w,
        "Maximum errors over the {n} steps (and the errors at the last step):\n"
    );
    let _ = writeln!(w, "{}", markdown_table(exp));
    let stopped: Vec<_> = exp.runs.iter().filter(|r| r.failure.is_some()).collect();
    if !stopped.is_empty() {
        let _ = writeln!(
            w,
            "Runs that stopped before step {n} (their rows are over the steps they took; \
             figures that need a later step read {MISSING}):\n"
        );
        for r in stopped {
            let _ = writeln!(
                w,
                "- {} at h = {}: {}",
                r.method.label(),
                h_name(r.h),
                r.failure.as_deref().unwrap_or_default()
            );
        }
        let _ = writeln!(w);
    }
}

/// `max |ΔH|/H₀` of `m` at every step size, as "x at h = …, …".
fn by_h(exp: &Experiment, m: Method) -> String {
    let parts: Vec<String> = exp
        .config
        .step_sizes
        .iter()
        .map(|&h| format!("{} at h = {h}", sci2(exp.max_rel_energy(m, h))))
        .collect();
    parts.join(", ")
}

fn euler_energy(w: &mut String, exp: &Experiment, f: &Findings) {
    let (h_max, n) = (f.h_max, exp.config.steps);
    let _ = writeln!(
        w,
        "- **Explicit Euler** gains energy at every step: max |ΔH|/H₀ = {}; the error grows {} \
         (the paper's \"large error with the increasing of time-step\"). Within the run at h = {h_max} \
         |ΔH| grows from {} after {} steps to {} after {n} ({}; linear growth would give {}): exponential \
         growth, within a relative {} of the prediction H₀((1 + h²k²)ⁿ − 1) = {} from its stability function \
         R(z) = 1 + z, |R(ih)|² = 1 + h²k².",
        by_h(exp, Method::ExplicitEuler),
        growth_with_h(&f.sorted_step_sizes, |h| exp
            .max_rel_energy(Method::ExplicitEuler, h)),
        sci2(f.euler_early),
        n / 10,
        sci2(f.euler_final),
        format::times(f.euler_final, f.euler_early),
        format::times(n as f64, (n / 10) as f64),
        sci2(relative_difference(f.euler_final, f.euler_predicted)),
        sci2(f.euler_predicted),
    );
}

fn heun_energy(w: &mut String, exp: &Experiment, f: &Findings) {
    let (h_max, n) = (f.h_max, exp.config.steps);
    let _ = writeln!(
        w,
        "- **Heun** drifts: max |ΔH|/H₀ = {}. At h = {h_max} |ΔH| grows at every step ({} steps where it did \
         not), from {} after {} steps to {} after {n} ({}: linear growth, a drift), within a relative {} of the \
         prediction H₀((1 + (hk)⁴/4)ⁿ − 1) = {} (|R(ih)|² = 1 + (hk)⁴/4 for R(z) = 1 + z + z²/2). With h it grows \
         {} (the h⁴ of the prediction).",
        by_h(exp, Method::Heun),
        f.heun_decreases,
        sci2(f.heun_early),
        n / 10,
        sci2(f.heun_final),
        format::times(f.heun_final, f.heun_early),
        sci2(relative_difference(f.heun_final, f.heun_predicted)),
        sci2(f.heun_predicted),
        growth_with_h(&f.sorted_step_sizes, |h| exp
            .max_rel_energy(Method::Heun, h)),
    );
}

fn round_off_energy(w: &mut String, f: &Findings) {
    let round_off: Vec<String> = f
        .round_off_worst
        .iter()
        .map(|&(m, worst)| format!("{} {}", m.label(), sci2(worst)))
        .collect();
    let _ = writeln!(
        w,
        "- **Implicit midpoint, paper DIRK2, Gauss–Legendre 2** keep the energy to round-off at every step size: \
         largest max |ΔH|/H₀ over all h: {}. In the energy plots their |ΔH| is drawn as max(|ΔH|, {ENERGY_FLOOR:e}) \
         because it is exactly 0 at some steps and a log axis cannot show 0.",
        round_off.join(", ")
    );
}

fn symplectic_euler_energy(w: &mut String, exp: &Experiment, f: &Findings) {
    let h_max = f.h_max;
    let se = exp.run(Method::SymplecticEuler, h_max).summary();
    let _ = writeln!(
        w,
        "- **Symplectic Euler**'s energy error is neither round-off nor growing: it oscillates with an amplitude \
         proportional to h (max |ΔH|/H₀ = {}; {}). At h = {h_max} its largest |ΔH| is {} over the first half of the \
         run and {} over the second ({}), and ΔH changes sign {} times. It conserves the modified energy \
         H̃ = H − (hk²/2)·qp exactly (largest drift of H̃ over all runs: {} of H₀), so ΔH = (hk²/2)(qp − q₀p₀) \
         is bounded by the orbit.\n",
        by_h(exp, Method::SymplecticEuler),
        growth_with_h(&f.sorted_step_sizes, |h| exp
            .max_rel_energy(Method::SymplecticEuler, h)),
        sci2(se.energy_error_first_half),
        sci2(se.energy_error_second_half),
        format::times(se.energy_error_second_half, se.energy_error_first_half),
        se.energy_sign_changes,
        sci2(f.symplectic_euler_modified_drift),
    );
}

/// Position and phase at the largest step size: a table, then the
/// midpoint rule's and symplectic Euler's rotation against the prediction.
fn phase(w: &mut String, exp: &Experiment, f: &Findings) {
    let (h_max, n) = (f.h_max, exp.config.steps);
    let _ = writeln!(
        w,
        "### Position and phase at h = {h_max} after {n} steps (t = {})\n",
        h_max * n as f64
    );
    let _ = writeln!(
        w,
        "| method | final \\|Δq\\| | max \\|Δq\\| | phase error after {} steps | after {n} steps | amplitude error r/r₀ − 1 |",
        n / 2
    );
    let _ = writeln!(w, "|---|---|---|---|---|---|");
    for r in exp.at(h_max) {
        let m = r.summary();
        let phase = r.phase_error();
        let _ = writeln!(
            w,
            "| {} | {} | {} | {} | {} | {} |",
            r.method.label(),
            sci2(m.final_err_q.abs()),
            sci2(m.max_err_q),
            format::signed_sci(value_at(&phase, n / 2), 3),
            format::signed_sci(value_at(&phase, n), 3),
            if r.failure.is_some() {
                MISSING.to_string()
            } else {
                format::signed_sci(m.final_amplitude_error, 2)
            }
        );
    }
    midpoint_rotation(w, f, n);
    symplectic_euler_rotation(w, f, n);
}

fn midpoint_rotation(w: &mut String, f: &Findings, n: usize) {
    let linear_expected = n as f64 / (n / 2) as f64;
    let mid_ratio = f.midpoint_phase_final / f.midpoint_phase_half;
    let linear = if (mid_ratio / linear_expected - 1.0).abs() < 0.05 {
        "i.e. it grows linearly in time"
    } else {
        "not the linear growth expected"
    };
    let _ = writeln!(
        w,
        "\nThe implicit midpoint rule rotates by 2·atan(hk/2) per step instead of hk: predicted phase error \
         −n·(hk − 2·atan(hk/2)) = {:+.6e}, measured {:+.6e}; the phase error after {n} steps is {} that \
         after {} steps, {linear}.",
        f.midpoint_phase_predicted,
        f.midpoint_phase_final,
        format::times(f.midpoint_phase_final, f.midpoint_phase_half),
        n / 2,
    );
}

fn symplectic_euler_rotation(w: &mut String, f: &Findings, n: usize) {
    let h_max = f.h_max;
    if f.symplectic_euler_phase_predicted.is_finite() {
        let _ = writeln!(
            w,
            "Symplectic Euler's step matrix has trace 2 − (hk)², so it rotates by acos(1 − (hk)²/2) per step, \
             faster than hk: a secular phase drift of {:+.3e} after {n} steps. Its measured angle error ({:+.3e} \
             after {} steps, {:+.3e} after {n}) also contains an O(h) oscillation, because its orbit is the \
             ellipse H̃ = const, not the circle H = H₀.\n",
            f.symplectic_euler_phase_predicted,
            f.symplectic_euler_phase_half,
            n / 2,
            f.symplectic_euler_phase_final,
        );
    } else {
        let _ = writeln!(
            w,
            "At h = {h_max}, hk > 2 lies outside symplectic Euler's stability interval: its step matrix has real \
             eigenvalues and the solution does not rotate.\n"
        );
    }
}
