//! The line that reports how the energy error of a run grew
//! ([`cloth::study::growth`] fits it), on success and on failure alike.

use cloth::study::growth::{Growth, MIN_FRAMES, Trend};

/// One line for the run's summary.
pub fn describe(growth: &Growth) -> String {
    match *growth {
        Growth::TooShort { frames } => {
            format!("{frames} frames: too few to fit a growth (at least {MIN_FRAMES} are needed)")
        }
        Growth::Fitted {
            envelope,
            power,
            e_folding,
            trend,
        } => {
            let env = format!(
                "max |H − H₀|/E_ref per quarter of the run {:.2e}, {:.2e}, {:.2e}, {:.2e}",
                envelope[0], envelope[1], envelope[2], envelope[3]
            );
            let verdict = match trend {
                Trend::Exponential => format!(
                    "grows exponentially, ×e every {e_folding:.3} s (×10 every {:.3} s): not energy-stable at this step",
                    e_folding * std::f64::consts::LN_10
                ),
                Trend::Bounded => format!("bounded, no drift (fitted t^{power:.2})"),
                Trend::Power => format!("grows like t^{power:.2}"),
            };
            format!("{env}: {verdict}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cloth::study::growth::fit;

    /// `f` sampled at 60 Hz over `n` frames: (times, values).
    fn series(n: usize, f: impl Fn(f64) -> f64) -> (Vec<f64>, Vec<f64>) {
        (0..=n).map(|k| k as f64 / 60.0).map(|t| (t, f(t))).unzip()
    }

    #[test]
    fn an_oscillating_error_of_constant_amplitude_is_bounded() {
        let (t, e) = series(600, |t| 1e-3 * (40.0 * t).sin());
        let g = fit(&t, &e);
        assert!(describe(&g).contains("bounded"), "{}", describe(&g));
    }

    #[test]
    fn a_linear_drift_has_power_one() {
        let (t, e) = series(600, |t| 1e-4 * t);
        assert!(describe(&fit(&t, &e)).contains("t^1.00"));
    }

    #[test]
    fn exponential_growth_gives_its_e_folding_time() {
        let (t, e) = series(120, |t| 1e-6 * (t / 0.1).exp());
        let g = fit(&t, &e);
        assert!(describe(&g).contains("not energy-stable"));
    }

    #[test]
    fn a_transient_then_a_plateau_is_not_exponential() {
        let (t, e) = series(120, |t| {
            if t < 0.6 {
                1e-7
            } else {
                1e-3 * (1.0 + 0.1 * t)
            }
        });
        let g = fit(&t, &e);
        assert!(describe(&g).contains("grows like t^"), "{}", describe(&g));
    }

    #[test]
    fn short_and_exact_runs_are_said_so() {
        let (t, e) = series(5, |t| t);
        assert!(describe(&fit(&t, &e)).contains("too few"));
        let (t, e) = series(100, |_| 0.0);
        let g = fit(&t, &e);
        assert!(describe(&g).contains("bounded"), "{}", describe(&g));
    }
}
