//! How the energy error of a cloth run grows: bounded, a power of `t`, or
//! exponential.
//!
//! Why: a symplectic method keeps the energy error bounded only where
//! backward error analysis applies. Far outside it (the implicit midpoint
//! rule on stiff springs at one step per 60 Hz frame) the error can grow
//! without bound, and a run that ends in a failed solve would otherwise
//! report only the failure. Fitting the growth, on success and on failure
//! alike, reports the growth instead of hiding it.
//!
//! The fit works on the envelope: the largest `|H − H₀|/E_ref` in each
//! quarter of the run, against the time at the end of the quarter. A bounded
//! error gives a flat envelope, a linear drift `e ∝ t` an envelope growing
//! like `1 : 2 : 3 : 4`, an exponential one a straight line in `ln e`.
//!
//! Growth like a power of `t` is not by itself a sign of a non-symplectic
//! method: on the undamped paper scene even symplectic Euler's envelope grows
//! like `t^0.7`–`t^1.2` over 10 s, at 162, 256 and 1024 substeps per frame
//! alike, while its size shrinks with the step (1.0e-2, 5.5e-3, 6.4e-4 of
//! E_ref at 10 s). An exponential envelope is what marks a method unstable at
//! its step.
//!
//! ```
//! use cloth::study::growth::{fit, Trend};
//!
//! // An energy error that doubles every 0.1 s, sampled at 60 Hz for 2 s.
//! let times: Vec<f64> = (0..=120).map(|k| k as f64 / 60.0).collect();
//! let rel: Vec<f64> = times.iter().map(|t| 1e-6 * (t / 0.1).exp2()).collect();
//! let growth = fit(&times, &rel);
//! assert!(growth.exponential());
//! assert_eq!(growth.trend(), Some(Trend::Exponential));
//! ```

/// The fitted growth of the energy error over a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Growth {
    /// Fewer frames after the first than [`GrowthSettings::min_frames`]:
    /// nothing to fit.
    TooShort { frames: usize },
    /// The envelope per quarter, and what the fit makes of it.
    Fitted {
        envelope: [f64; 4],
        /// The exponent `p` of `e ∝ tᵖ` fitted to the envelope (log–log).
        power: f64,
        /// The e-folding time `τ` of `e ∝ exp(t/τ)` fitted to the envelope
        /// (`ln e` against `t`), in seconds; infinite for a flat envelope.
        e_folding: f64,
        /// What the thresholds of the fit's settings call this growth.
        trend: Trend,
    },
}

/// What a fitted growth is called.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Trend {
    /// A power below [`GrowthSettings::bounded_power`]: no drift.
    Bounded,
    /// A drift like `tᵖ`, not exponential.
    Power,
    /// Exponential growth: see [`GrowthSettings::exponential_power`].
    Exponential,
}

/// The thresholds of the fit. The defaults are those `symlab cloth` and
/// `symlab paper` report with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrowthSettings {
    /// Frames after the first that a fit needs (default [`MIN_FRAMES`]: two
    /// per quarter).
    pub min_frames: usize,
    /// A power at or above which the growth is called exponential, if the
    /// last quarter still grows that fast (default [`EXPONENTIAL_POWER`]).
    pub exponential_power: f64,
    /// Below this power the error is called bounded (default
    /// [`BOUNDED_POWER`]).
    pub bounded_power: f64,
}

/// Frames after the first that a fit needs by default (two per quarter).
pub const MIN_FRAMES: usize = 8;

/// The default power above which the growth is called exponential: over a
/// run cut in four, `e₄/e₁ = 4ᵖ`, so `p = 3` is a factor of 64 between the
/// first and the last quarter, which no drift of the sizes seen (`p ≤ 1`
/// for a systematic drift, `½` for a random walk) comes near.
pub const EXPONENTIAL_POWER: f64 = 3.0;

/// The default power below which the error is called bounded (no drift).
pub const BOUNDED_POWER: f64 = 0.3;

impl Default for GrowthSettings {
    fn default() -> Self {
        GrowthSettings {
            min_frames: MIN_FRAMES,
            exponential_power: EXPONENTIAL_POWER,
            bounded_power: BOUNDED_POWER,
        }
    }
}

/// Fit the growth of `rel` (the relative energy error of each frame, frame 0
/// first) at `times` (seconds, increasing), with the default settings.
pub fn fit(times: &[f64], rel: &[f64]) -> Growth {
    GrowthSettings::default().fit(times, rel)
}

impl GrowthSettings {
    /// Fit the growth of `rel` (the relative energy error of each frame,
    /// frame 0 first) at `times` (seconds, increasing). A NaN frame is left
    /// out of its quarter's envelope rather than poisoning it.
    pub fn fit(&self, times: &[f64], rel: &[f64]) -> Growth {
        let n = rel.len().min(times.len()).saturating_sub(1);
        // At least one frame per quarter whatever the setting.
        if n < self.min_frames.max(4) {
            return Growth::TooShort { frames: n };
        }
        let t0 = times[0];
        let mut envelope = [0.0f64; 4];
        let mut ends = [0.0f64; 4];
        for (k, (e, t)) in envelope.iter_mut().zip(ends.iter_mut()).enumerate() {
            let (lo, hi) = (1 + k * n / 4, 1 + (k + 1) * n / 4);
            *e = rel[lo..hi]
                .iter()
                .fold(0.0f64, |m, x| if x.is_nan() { m } else { m.max(x.abs()) });
            *t = times[hi - 1] - t0;
        }
        // A quarter with no error at all (an exact run) has no logarithm:
        // then the envelope is flat by any measure.
        let floor = envelope.iter().fold(f64::MAX, |m, &e| m.min(e));
        if floor <= 0.0 || !floor.is_finite() {
            return Growth::Fitted {
                envelope,
                power: 0.0,
                e_folding: f64::INFINITY,
                trend: Trend::Bounded,
            };
        }
        let ln_e = envelope.map(f64::ln);
        let power = slope(&ends.map(f64::ln), &ln_e);
        let rate = slope(&ends, &ln_e);
        Growth::Fitted {
            envelope,
            power,
            e_folding: if rate > 0.0 {
                1.0 / rate
            } else {
                f64::INFINITY
            },
            trend: self.trend(power, &envelope),
        }
    }

    /// Exponential: faster than `tᵖ` (`p` = [`Self::exponential_power`])
    /// over the run and still faster than `tᵖ` in the last quarter
    /// (`e₄/e₃ ≥ (4/3)ᵖ`). The second condition keeps a quiet start followed
    /// by a plateau (a transient, as a released cloth's first swing) from
    /// being called exponential.
    fn trend(&self, power: f64, envelope: &[f64; 4]) -> Trend {
        let p = self.exponential_power;
        if power >= p && envelope[3] >= (4.0f64 / 3.0).powf(p) * envelope[2] {
            Trend::Exponential
        } else if power < self.bounded_power {
            Trend::Bounded
        } else {
            Trend::Power
        }
    }
}

/// The least-squares slope of `y` on `x`.
fn slope(x: &[f64; 4], y: &[f64; 4]) -> f64 {
    let mx = x.iter().sum::<f64>() / 4.0;
    let my = y.iter().sum::<f64>() / 4.0;
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    if sxx > 0.0 { sxy / sxx } else { 0.0 }
}

impl Growth {
    /// What the fit calls the growth; `None` when the run was too short.
    pub fn trend(&self) -> Option<Trend> {
        match self {
            Growth::TooShort { .. } => None,
            Growth::Fitted { trend, .. } => Some(*trend),
        }
    }

    /// Whether the fit says the error grows exponentially (see
    /// [`GrowthSettings::exponential_power`]).
    pub fn exponential(&self) -> bool {
        self.trend() == Some(Trend::Exponential)
    }
}

/// The line a run's summary gives the fit, on success and on failure alike:
/// the envelope per quarter and the verdict.
impl std::fmt::Display for Growth {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Growth::TooShort { frames } => write!(
                f,
                "{frames} frames: too few to fit a growth (at least {MIN_FRAMES} are needed)"
            ),
            Growth::Fitted {
                envelope,
                power,
                e_folding,
                trend,
            } => {
                write!(
                    f,
                    "max |H − H₀|/E_ref per quarter of the run {:.2e}, {:.2e}, {:.2e}, {:.2e}: ",
                    envelope[0], envelope[1], envelope[2], envelope[3]
                )?;
                match trend {
                    Trend::Exponential => write!(
                        f,
                        "grows exponentially, ×e every {e_folding:.3} s (×10 every {:.3} s): not energy-stable at this step",
                        e_folding * std::f64::consts::LN_10
                    ),
                    Trend::Bounded => write!(f, "bounded, no drift (fitted t^{power:.2})"),
                    Trend::Power => write!(f, "grows like t^{power:.2}"),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series(n: usize, f: impl Fn(f64) -> f64) -> (Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..=n).map(|k| k as f64 / 60.0).collect();
        let e = t.iter().map(|&t| f(t)).collect();
        (t, e)
    }

    #[test]
    fn an_oscillating_error_of_constant_amplitude_is_bounded() {
        let (t, e) = series(600, |t| 1e-3 * (40.0 * t).sin());
        let g = fit(&t, &e);
        let Growth::Fitted { power, .. } = g else {
            panic!("{g:?}")
        };
        assert!(power.abs() < BOUNDED_POWER, "{g:?}");
        assert_eq!(g.trend(), Some(Trend::Bounded));
        assert!(g.to_string().contains("bounded, no drift"), "{g}");
    }

    #[test]
    fn a_linear_drift_has_power_one() {
        let (t, e) = series(600, |t| 1e-4 * t);
        let Growth::Fitted { power, .. } = fit(&t, &e) else {
            panic!()
        };
        assert!((power - 1.0).abs() < 1e-9, "{power}");
        assert_eq!(fit(&t, &e).trend(), Some(Trend::Power));
        assert!(fit(&t, &e).to_string().contains("grows like t^1.00"));
    }

    #[test]
    fn exponential_growth_gives_its_e_folding_time() {
        let (t, e) = series(120, |t| 1e-6 * (t / 0.1).exp());
        let g = fit(&t, &e);
        assert!(g.exponential(), "{g:?}");
        let Growth::Fitted { e_folding, .. } = g else {
            panic!()
        };
        assert!((e_folding - 0.1).abs() < 1e-9, "{e_folding}");
        assert!(g.to_string().contains("not energy-stable"), "{g}");
    }

    #[test]
    fn a_transient_then_a_plateau_is_not_exponential() {
        // Quiet for the first quarter, then a jump to a level that stays.
        let (t, e) = series(120, |t| {
            if t < 0.6 {
                1e-7
            } else {
                1e-3 * (1.0 + 0.1 * t)
            }
        });
        let g = fit(&t, &e);
        let Growth::Fitted { power, .. } = g else {
            panic!()
        };
        assert!(power >= EXPONENTIAL_POWER, "{power}");
        assert!(!g.exponential(), "{g:?}");
        assert_eq!(g.trend(), Some(Trend::Power));
        assert!(g.to_string().contains("grows like t^"), "{g}");
    }

    #[test]
    fn short_and_exact_runs_are_said_so() {
        let (t, e) = series(5, |t| t);
        assert_eq!(fit(&t, &e), Growth::TooShort { frames: 5 });
        assert!(fit(&t, &e).to_string().contains("too few"));
        let (t, e) = series(100, |_| 0.0);
        let g = fit(&t, &e);
        assert!(!g.exponential());
        assert_eq!(g.trend(), Some(Trend::Bounded));
        assert!(g.to_string().contains("bounded"), "{g}");
    }

    #[test]
    fn a_nan_frame_does_not_poison_the_envelope() {
        let (t, mut e) = series(100, |t| 1e-3 * (1.0 + t));
        e[50] = f64::NAN;
        let Growth::Fitted { power, .. } = fit(&t, &e) else {
            panic!()
        };
        assert!(power.is_finite());
    }

    #[test]
    fn the_thresholds_are_settings() {
        // A linear drift is bounded for a lenient setting, exponential for
        // a strict one.
        let (t, e) = series(600, |t| 1e-4 * t);
        let lenient = GrowthSettings {
            bounded_power: 1.5,
            ..GrowthSettings::default()
        };
        assert_eq!(lenient.fit(&t, &e).trend(), Some(Trend::Bounded));
        let strict = GrowthSettings {
            exponential_power: 0.5,
            ..GrowthSettings::default()
        };
        assert!(strict.fit(&t, &e).exponential());
        let (t, e) = series(20, |t| t);
        let long = GrowthSettings {
            min_frames: 30,
            ..GrowthSettings::default()
        };
        assert_eq!(long.fit(&t, &e), Growth::TooShort { frames: 20 });
    }
}
