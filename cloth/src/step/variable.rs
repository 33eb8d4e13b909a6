//! The reversible variable step of RATTLE: per frame a whole number `N` of
//! equal steps `h = 1/(frame_rate·N)`, so that frames land on
//! `1/frame_rate`, with `N` chosen by a rule that is the same forwards and
//! backwards in time.
//!
//! **The measure.** A frame of `N` steps visits the positions
//! `q_0, …, q_N`. At an interior node `q_j` (`0 < j < N`) the steps carry
//! the unprojected momentum, so the position solve of step `j + 1` finds
//! the whole constraint impulse at `q_j` (the velocity projection's half of
//! step `j` and the position solve's half of step `j + 1`), and RATTLE
//! measures from it the transverse-wave number `h·ω = 4·√(½ΣΛ)` (divided by
//! √2 for the two half-steps; [`RattleStepper`](super::RattleStepper),
//! `last_wave_number`). That impulse is
//! `M(q_{j+1} − 2q_j + q_{j−1})/h² − F(q_j)` along `G(q_j)ᵀ`: a function of
//! three consecutive nodes that does not change when they are taken in the
//! reverse order. The frame's measure `W_N` is the largest of these over its
//! interior nodes; the two end nodes are left out, because there the
//! impulse also holds a half from the neighbouring frame, whose step may
//! differ (they are interior to no frame, but each lies one step `h` from
//! an interior node of both frames beside it). `N ≥ 2`, so that a frame has
//! an interior node. A step whose position solve fails, or that leaves a
//! non-finite value, makes `W_N = ∞`.
//!
//! **The rule.** `N(z) = min{N ≥ N_floor : W_N(z) ≤ target}`, `z` the
//! state at the frame's start, `N_floor` the run's steps per frame
//! (`simulation.substeps`, or what `substeps = "auto"` chose) and `target`
//! [`VariableStep::wave_number`]. While the floor's frames stay below the
//! target the run's states are those of the fixed step at the floor, to
//! the bit (its frame times are `k/frame_rate` where the fixed step's are
//! sums of steps).
//!
//! **Why it is reversible.** RATTLE is symmetric: the frame map `Φ_N` of
//! `N` steps satisfies `R∘Φ_N∘R∘Φ_N = id` with `R` the flip of the momenta,
//! and the flipped run of `N` steps from `z' = R·Φ_N(z)` visits the same
//! nodes in the reverse order, so `W_N(z') = W_N(z)` (to round-off; the
//! position solve stops at its round-off, [`CONSTRAINT_TOLERANCE`]).
//! Backwards, the rule accepts `N` again; it also rejects every `M < N`
//! again, because the flipped run of `M` steps from `z'` samples the same
//! times `t₀ + kT/M` of the same motion as the forward run of `M` steps from
//! `z` and differs from it only by the difference of the frame maps `Φ_M`
//! and `Φ_N`, a global error of `O(h²)` over one frame. So the backward run
//! chooses the same `N` unless a rejected `W_M` lies within that
//! difference of the target (a tie, which the continuous step-size rules of
//! Hairer & Söderlind settle by a fixed point but an integer count cannot),
//! or `W` is not monotone in `N` across the target (the search below
//! assumes it is: it stops at an accepted `N` whose `N − 1` was rejected).
//! The choice does not depend on history: the previous frame's `N` is only
//! where the search starts ([`Controller`]), and the acceptance test alone
//! decides — a frame accepted at `N > N_floor` is accepted only after
//! `N − 1` was tried from the same start and rejected, which costs a
//! second integration of that frame (reported as redone frames and extra
//! steps in [`VariableStats`]). That check stops at the first interior
//! node whose `h·ω` passes the target ([`Search::is_check`]): one node
//! rejects `N − 1`, and the search then ends with `N` whatever the
//! others would show, so the rule and the chosen counts are those of the
//! whole integration. The constraints stay at round-off at every
//! frame: every step solves them, and the frame's end is projected as in
//! the fixed step.
//!
//! [`CONSTRAINT_TOLERANCE`]: crate::model::CONSTRAINT_TOLERANCE

use std::collections::BTreeMap;

use integrator_core::checkpoint::{CheckpointError, Decoder, Encoder};

/// The settings, read from the scene's `[simulation]` table (they live in
/// the scene module, which knows the fields).
pub use crate::scene::VariableStep;

/// What the variable step did over a run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VariableStats {
    /// The floor `N_floor` (steps per frame) and the target `h·ω`.
    pub floor: usize,
    pub target: f64,
    /// Frames stepped, and how many steps each took: steps per frame →
    /// frames.
    pub frames: usize,
    pub histogram: BTreeMap<usize, usize>,
    /// Integrations of a frame in all (at least one per frame), the frames
    /// integrated more than once, and the steps of integrations not kept.
    pub attempts: usize,
    pub redone: usize,
    pub discarded_steps: usize,
    /// Integrations stopped by a failed position solve or a non-finite
    /// state (counted as `W_N = ∞`).
    pub failed: usize,
    /// The largest interior `h·ω` of an accepted frame, and the largest
    /// seen in a rejected integration (the check of `N − 1` below an
    /// accepted `N` stops at its first interior node past the target, so
    /// there it is that node's).
    pub max_accepted: f64,
    pub max_rejected: f64,
}

impl VariableStats {
    /// The fewest, the mean and the most steps of a frame (0s before the
    /// first frame).
    pub fn min_mean_max(&self) -> (usize, f64, usize) {
        let min = self.histogram.keys().next().copied().unwrap_or(0);
        let max = self.histogram.keys().next_back().copied().unwrap_or(0);
        let steps: usize = self.histogram.iter().map(|(n, k)| n * k).sum();
        (min, steps as f64 / self.frames.max(1) as f64, max)
    }

    /// The steps kept, in all.
    pub fn steps(&self) -> usize {
        self.histogram.iter().map(|(n, k)| n * k).sum()
    }

    fn encode(&self, e: &mut Encoder) {
        e.usize(self.floor)
            .f64(self.target)
            .usize(self.frames)
            .usize(self.histogram.len());
        for (n, k) in &self.histogram {
            e.usize(*n).usize(*k);
        }
        e.usize(self.attempts)
            .usize(self.redone)
            .usize(self.discarded_steps)
            .usize(self.failed)
            .f64(self.max_accepted)
            .f64(self.max_rejected);
    }

    fn decode(d: &mut Decoder<'_>) -> Result<VariableStats, CheckpointError> {
        let floor = d.usize("variable.floor")?;
        let target = d.f64("variable.target")?;
        let frames = d.usize("variable.frames")?;
        let bins = d.usize("variable.histogram")?;
        let mut histogram = BTreeMap::new();
        for _ in 0..bins {
            let n = d.usize("variable.histogram")?;
            let k = d.usize("variable.histogram")?;
            histogram.insert(n, k);
        }
        Ok(VariableStats {
            floor,
            target,
            frames,
            histogram,
            attempts: d.usize("variable.attempts")?,
            redone: d.usize("variable.redone")?,
            discarded_steps: d.usize("variable.discarded_steps")?,
            failed: d.usize("variable.failed")?,
            max_accepted: d.f64("variable.max_accepted")?,
            max_rejected: d.f64("variable.max_rejected")?,
        })
    }
}

/// The outcome of integrating a frame with `N` steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Attempt {
    /// It ran; the largest interior `h·ω`.
    Ran(f64),
    /// A step failed or left a non-finite value (`W_N = ∞`).
    Failed,
}

/// What the search does next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Next {
    /// Integrate the frame again from its start with this many steps.
    Try(usize),
    /// The frame is done with this many steps (the last accepted
    /// integration; `latest`: it is the one just made, else it was kept).
    Done { steps: usize, latest: bool },
    /// No count up to the cap is accepted.
    Exhausted { tried: usize },
}

/// The search of one frame: the largest count known rejected and the
/// smallest known accepted, from the same start state.
#[derive(Clone, Copy, Debug)]
pub struct Search {
    floor: usize,
    cap: usize,
    target: f64,
    /// The largest rejected count (`floor − 1` before any).
    lo: usize,
    /// The smallest accepted count.
    hi: Option<usize>,
    attempts: usize,
}

impl Search {
    /// Where to start: the previous frame's count, within `[floor, cap]`.
    pub fn first(&self, guess: usize) -> usize {
        guess.clamp(self.floor, self.cap)
    }

    /// Record the integration with `n` steps and say what to do next. A
    /// count `n·W/target` (rounded up) is the prediction for `W ∝ 1/N`.
    pub fn record(&mut self, n: usize, attempt: Attempt) -> Next {
        self.attempts += 1;
        let predicted = |w: f64| {
            let p = (n as f64 * w / self.target).ceil();
            if p.is_finite() && p < self.cap as f64 {
                p as usize
            } else {
                self.cap
            }
        };
        match attempt {
            Attempt::Ran(w) if w <= self.target => {
                self.hi = Some(n);
                if n <= self.lo + 1 {
                    return Next::Done {
                        steps: n,
                        latest: true,
                    };
                }
                Next::Try(predicted(w).clamp(self.lo + 1, n - 1))
            }
            rejected => {
                self.lo = self.lo.max(n);
                let up = match rejected {
                    Attempt::Ran(w) => predicted(w),
                    Attempt::Failed => n.saturating_mul(2),
                };
                let mut next = up.max(n + 1);
                if let Some(hi) = self.hi {
                    if hi <= n + 1 {
                        return Next::Done {
                            steps: hi,
                            latest: false,
                        };
                    }
                    next = next.min(hi - 1);
                }
                if next > self.cap {
                    if n >= self.cap {
                        return Next::Exhausted { tried: n };
                    }
                    next = self.cap;
                }
                Next::Try(next)
            }
        }
    }

    /// Whether the integration with `n` steps is the check below an
    /// accepted count (`n + 1` accepted): rejected, whatever its `h·ω`, it
    /// ends the search with that count ([`record`](Self::record) uses the
    /// rejected `W` only to predict the next count up), so it may stop at
    /// the first interior node past the target. The decision is the one
    /// the whole integration would give.
    pub fn is_check(&self, n: usize) -> bool {
        self.hi.is_some_and(|hi| hi <= n + 1)
    }

    /// Integrations of this frame so far.
    pub fn attempts(&self) -> usize {
        self.attempts
    }
}

/// The variable step's state between frames: where the next frame's search
/// starts (the last frame's count; it decides nothing, see the module
/// documentation) and the statistics. Saved in a checkpoint.
#[derive(Clone, Debug, PartialEq)]
pub struct Controller {
    pub settings: VariableStep,
    /// The floor: at least 2.
    pub floor: usize,
    pub guess: usize,
    pub stats: VariableStats,
}

impl Controller {
    /// The controller of a run whose steps per frame are `substeps` (the
    /// floor, raised to 2 for an interior node).
    pub fn new(settings: VariableStep, substeps: usize) -> Controller {
        let floor = substeps.max(2);
        Controller {
            settings,
            floor,
            guess: floor,
            stats: VariableStats {
                floor,
                target: settings.wave_number,
                ..Default::default()
            },
        }
    }

    /// A search for the next frame.
    pub fn search(&self) -> Search {
        Search {
            floor: self.floor,
            cap: self.settings.max_substeps.max(self.floor),
            target: self.settings.wave_number,
            lo: self.floor - 1,
            hi: None,
            attempts: 0,
        }
    }

    /// Record a finished frame.
    pub fn finish(&mut self, steps: usize, search: &Search, tried_steps: usize, w: f64) {
        self.guess = steps;
        let s = &mut self.stats;
        s.frames += 1;
        *s.histogram.entry(steps).or_insert(0) += 1;
        s.attempts += search.attempts();
        s.redone += usize::from(search.attempts() > 1);
        s.discarded_steps += tried_steps - steps;
        s.max_accepted = s.max_accepted.max(w);
    }

    /// Record a rejected or failed integration.
    pub fn rejected(&mut self, attempt: Attempt) {
        match attempt {
            Attempt::Ran(w) => self.stats.max_rejected = self.stats.max_rejected.max(w),
            Attempt::Failed => self.stats.failed += 1,
        }
    }

    /// The marker before the controller in a checkpoint's stepper data.
    const MARK: &'static str = "variable-step";

    /// Append the controller to a checkpoint's stepper data.
    pub fn save(&self, e: &mut Encoder) {
        e.str(Controller::MARK).usize(self.guess);
        self.stats.encode(e);
    }

    /// Take back what [`save`](Self::save) wrote.
    pub fn restore(&mut self, d: &mut Decoder<'_>) -> Result<(), CheckpointError> {
        let mark = d.str("variable")?;
        if mark != Controller::MARK {
            return Err(d.error(format!(
                "expected the variable step's state (simulation.step = \"variable\"), found \"{mark}\""
            )));
        }
        self.guess = d.usize("variable.guess")?;
        self.stats = VariableStats::decode(d)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn search(floor: usize, cap: usize) -> Search {
        Controller::new(
            VariableStep {
                wave_number: 1.0,
                max_substeps: cap,
            },
            floor,
        )
        .search()
    }

    #[test]
    fn accepted_at_the_floor_is_done() {
        let mut s = search(4, 100);
        assert_eq!(
            s.record(4, Attempt::Ran(0.3)),
            Next::Done {
                steps: 4,
                latest: true
            }
        );
    }

    #[test]
    fn accepted_above_the_floor_checks_the_count_below() {
        let mut s = search(4, 100);
        // W ∝ 1/N: 10 steps at 0.95 predicts 10 at the target; the count
        // below must still be tried.
        assert_eq!(s.record(10, Attempt::Ran(0.95)), Next::Try(9));
        assert_eq!(
            s.record(9, Attempt::Ran(1.05)),
            Next::Done {
                steps: 10,
                latest: false
            }
        );
    }

    #[test]
    fn rejected_jumps_by_the_prediction_and_failures_double() {
        let mut s = search(4, 100);
        assert_eq!(s.record(4, Attempt::Ran(2.5)), Next::Try(10));
        assert_eq!(s.record(10, Attempt::Failed), Next::Try(20));
        assert_eq!(s.record(20, Attempt::Ran(0.5)), Next::Try(11));
        assert_eq!(
            s.record(11, Attempt::Ran(0.9)),
            Next::Done {
                steps: 11,
                latest: true
            }
        );
    }

    #[test]
    fn only_the_count_below_an_accepted_one_is_a_check() {
        let mut s = search(4, 100);
        assert!(!s.is_check(4));
        assert_eq!(s.record(4, Attempt::Ran(2.5)), Next::Try(10));
        assert!(!s.is_check(10));
        assert_eq!(s.record(10, Attempt::Ran(0.95)), Next::Try(9));
        // 10 accepted: 9 is the check, and its rejection ends the search
        // at 10 whatever its h·ω.
        assert!(s.is_check(9));
        let mut t = s;
        assert_eq!(
            s.record(9, Attempt::Ran(1.01)),
            Next::Done {
                steps: 10,
                latest: false
            }
        );
        assert_eq!(
            t.record(9, Attempt::Ran(7.0)),
            Next::Done {
                steps: 10,
                latest: false
            }
        );
    }

    #[test]
    fn the_cap_stops_the_search() {
        let mut s = search(4, 8);
        assert_eq!(s.record(4, Attempt::Failed), Next::Try(8));
        assert_eq!(s.record(8, Attempt::Failed), Next::Exhausted { tried: 8 });
    }
}
