//! The experiment's CSV files: the errors of every run, and every step of
//! every run at one step size. Numbers are written in Rust's shortest
//! round-trip scientific form, so a reader gets back the exact values.

use super::{Experiment, Trajectory};
use crate::output::csv_field;

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
            csv_field(r.method.id()),
            csv_field(r.method.label()),
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
            csv_field(&r.status()),
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
