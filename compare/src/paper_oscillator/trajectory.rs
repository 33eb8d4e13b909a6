//! One run of one method at one step size: the numerical and the exact
//! solution at every step, and what they say (errors, phase, amplitude,
//! the energy error's growth).

use super::Method;

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
