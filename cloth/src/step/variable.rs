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
//! **The rule.** A frame integrated with `N` steps *asks for*
//! `F_N(z) = ⌈N·W_N(z)/target⌉` within `[N_floor, cap]`: the fewest steps
//! whose `h·ω` would stay at or below the target if `h·ω` went as `1/N`
//! (as it does while the step resolves the wave: `ω` is the sheet's), `z`
//! the state at the frame's start, `N_floor` the run's steps per frame
//! (`simulation.substeps`, or what `substeps = "auto"` chose), `target`
//! [`VariableStep::wave_number`] and `cap` `max_substeps`. `N` asks for
//! itself when its `h·ω` stay at or below the target (`W_N ≤ target`) and
//! `N − 1` steps would pass it (`N·W_N/target > N − 1`), or `N` is the
//! floor. The frame takes the fewest counts that ask for themselves. While
//! the floor's frames stay below the target the run's states are those of
//! the fixed step at the floor, to the bit (its frame times are
//! `k/frame_rate` where the fixed step's are sums of steps).
//!
//! **The search** ([`Search`]) starts at the last frame's continuous count
//! `N·W_N/target`, rounded up ([`Controller`]), integrates, and goes to the
//! count asked for (twice the count after a failed solve) until a count
//! asks for itself; a frame whose `h·ω` moves slowly is integrated once. An
//! integration stops at its first interior node past the target: that node
//! alone rejects the count, whatever the others would show (it then asks
//! for at least one step more). A count `N` that asks for itself is taken
//! unless its continuous count lies within [`TIE_BAND`] (½) of `N − 1`;
//! then `N − 1` is integrated too, and taken if it asks for itself (and so
//! on down). When the count asked for was integrated already (at a tie `N`
//! can ask for `N + 1` and `N + 1` for `N`), the frame takes the fewest
//! steps found within the target; with none within it, the count above the
//! largest tried, up to the cap. Every try starts from the frame's start as
//! the first did, the stepper's carried data included (RATTLE's kept
//! factor, warm start and carried momentum: `ClothStepper::mark` and
//! `rewind`), so the frame's end is a function of its start and its count
//! alone, and a further try costs no fresh factorisation.
//!
//! This replaced a search that proved `N` by integrating `N − 1` for every
//! frame above the floor, which on the 64² sheet over 600 frames threw
//! away 41 % of the steps kept (27 % now, with the same steps per frame
//! in every frame).
//!
//! **Why it is reversible.** RATTLE is symmetric: the frame map `Φ_N` of
//! `N` steps satisfies `R∘Φ_N∘R∘Φ_N = id` with `R` the flip of the momenta,
//! and the flipped run of `N` steps from `z' = R·Φ_N(z)` visits the same
//! nodes in the reverse order, so `W_N(z') = W_N(z)` (to round-off; the
//! position solve stops at its round-off, [`CONSTRAINT_TOLERANCE`]), and
//! `N` asks for itself backwards too. The flipped run of `M ≠ N` steps from
//! `z'` samples the same motion as the forward run of `M` steps from `z`,
//! so it asks for the same count unless `M·W_M/target` lies within the
//! frame's `O(h²)` difference of a whole number. The backward search
//! starts from another guess (the forward run's next frame), so it must
//! not matter where the search starts: it does not as long as the counts
//! that ask for themselves are found from any start, which the tie band
//! ensures when the continuous counts of neighbouring counts differ by
//! less than it (a property test runs the search from every start on
//! frames whose continuous counts wander by up to ½ between neighbours,
//! `the_count_taken_does_not_depend_on_the_guess`). `W` is a largest value over the nodes a count samples, so
//! they differ: over 600 frames of the 64² sheet, every frame above the
//! floor integrated with `N − 1`, `N` and `N + 1` steps, by 0.005 in the
//! median, by less than 0.13 in 90 % of frames and by 0.91 at most; four
//! searches started from four different guesses (the last count, the last
//! continuous count, its linear extrapolation, the floor) chose the same
//! steps in every frame with the band, and differed in a few frames
//! without it. What remains — neighbours that differ by more than the band,
//! a tie that round-off settles differently backwards — the continuous
//! step-size rules of Hairer & Söderlind settle by a fixed point but an
//! integer count cannot. The constraints stay at round-off at every frame:
//! every step solves them, and the frame's end is projected as in the
//! fixed step.
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
    /// seen in a rejected integration (which stops at its first interior
    /// node past the target, so it is that node's).
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
    /// The frame is done with this many steps (`latest`: the integration
    /// just made, else the one kept, [`Search::keep`]).
    Done { steps: usize, latest: bool },
    /// No count up to the cap is accepted.
    Exhausted { tried: usize },
}

/// The count a frame integrated with `n` steps asks for: `⌈n·w/target⌉`
/// within `[floor, cap]`, the fewest steps whose `h·ω` would stay at or
/// below the target if `h·ω` went as `1/N` (as it does while `h` resolves
/// the wave: `ω` is the sheet's, not the step's).
fn asked(n: usize, w: f64, target: f64, floor: usize, cap: usize) -> usize {
    let p = (n as f64 * w / target).ceil();
    if p.is_finite() && p < cap as f64 {
        (p as usize).max(floor)
    } else {
        cap
    }
}

/// The search of one frame, from the same start state each time: the
/// counts integrated so far, the fewest found to ask for themselves, and
/// the fewest that kept `h·ω` at or below the target.
#[derive(Clone, Debug)]
pub struct Search {
    floor: usize,
    cap: usize,
    target: f64,
    /// How close to `N − 1` a count `N` that asks for itself may put its
    /// continuous count `N·W_N/target` before `N − 1` is tried as well
    /// ([`TIE_BAND`]).
    band: f64,
    /// The counts integrated, in order (a handful: each is new).
    visited: Vec<usize>,
    /// The fewest steps found to ask for themselves, and their `h·ω`.
    found: Option<(usize, f64)>,
    /// The fewest steps found within the target, and their `h·ω`.
    safe: Option<(usize, f64)>,
    /// Whether the integration just recorded is the one to keep.
    keep: bool,
}

/// The tie band: a count `N` that asks for itself with `N·W_N/target`
/// within this of `N − 1` has `N − 1` tried too, and the frame takes the
/// fewest counts that ask for themselves. `W` is a largest value over the
/// nodes a count samples, so `N·W_N/target` is not quite the same for
/// `N − 1` and `N`: on the 64² sheet (600 frames, every frame above the
/// floor integrated with `N − 1`, `N` and `N + 1` steps) the differences
/// had a median of 0.005, 90 % below 0.13 and the largest 0.91; 12 of 416
/// frames had a neighbouring count that asked for itself too, the found
/// one within 0.42 of it. Without the band, which of two such counts a
/// frame takes would depend on where the search started, which is not the
/// same forwards and backwards.
pub const TIE_BAND: f64 = 0.5;

impl Search {
    /// Where to start: the guess, within `[floor, cap]`.
    pub fn first(&self, guess: usize) -> usize {
        guess.clamp(self.floor, self.cap)
    }

    /// Record the integration with `n` steps and say what to do next.
    ///
    /// `n` *asks for itself* when [`asked`] gives `n`: its `h·ω` stay within
    /// the target and `n − 1` would not, by `W ∝ 1/N` (at the floor, the
    /// first alone). The frame takes the fewest counts that ask for
    /// themselves: a count that does is done unless its continuous count
    /// lies within [`TIE_BAND`] of `n − 1`, when `n − 1` is tried as well
    /// (and so on down). A count that does not goes to the one it asks for
    /// (twice itself after a failure). When that count was integrated
    /// already (the two counts either side of a tie can ask for each
    /// other), the frame takes the fewest steps found within the target;
    /// with none, the count above the largest integrated.
    pub fn record(&mut self, n: usize, attempt: Attempt) -> Next {
        self.visited.push(n);
        self.keep = false;
        let next = match attempt {
            Attempt::Ran(w) => {
                let p = asked(n, w, self.target, self.floor, self.cap);
                if w <= self.target && self.safe.is_none_or(|(s, _)| n < s) {
                    self.safe = Some((n, w));
                    self.keep = self.found.is_none();
                }
                if w <= self.target && p == n {
                    self.found = Some((n, w));
                    self.keep = true;
                    let c = n as f64 * w / self.target;
                    let below = n - 1;
                    if n > self.floor
                        && c < below as f64 + self.band
                        && !self.visited.contains(&below)
                    {
                        return Next::Try(below);
                    }
                    return Next::Done {
                        steps: n,
                        latest: true,
                    };
                }
                p
            }
            Attempt::Failed => n.saturating_mul(2).min(self.cap),
        };
        if let Some((f, _)) = self.found {
            // The count below one that asks for itself does not.
            return Next::Done {
                steps: f,
                latest: false,
            };
        }
        if !self.visited.contains(&next) {
            return Next::Try(next);
        }
        match self.safe {
            Some((s, _)) => Next::Done {
                steps: s,
                latest: s == n,
            },
            None => {
                let up = self.visited.iter().max().map_or(self.floor, |m| m + 1);
                if up > self.cap {
                    Next::Exhausted { tried: n }
                } else {
                    Next::Try(up)
                }
            }
        }
    }

    /// Whether the end state of the integration just recorded is the one
    /// to keep while another count is tried (the fewest that asks for
    /// itself, or before any does, the fewest within the target).
    pub fn keep(&self) -> bool {
        self.keep
    }

    /// The `h·ω` of the count the frame takes: the fewest that asks for
    /// itself, or before any does, the fewest within the target.
    pub fn taken(&self) -> Option<f64> {
        self.found.or(self.safe).map(|(_, w)| w)
    }

    /// Integrations of this frame so far.
    pub fn attempts(&self) -> usize {
        self.visited.len()
    }
}

/// The variable step's state between frames: where the next frame's search
/// starts (it decides nothing, see the module documentation) and the
/// statistics. Saved in a checkpoint.
#[derive(Clone, Debug, PartialEq)]
pub struct Controller {
    pub settings: VariableStep,
    /// The floor: at least 2.
    pub floor: usize,
    /// The last frame's continuous count `N·W_N/target` (the floor before
    /// any): the next frame's search starts there, rounded up, which is the
    /// count the frame asks for while `h·ω` moves slowly from frame to
    /// frame, so that most frames are integrated once. (A linear
    /// extrapolation of the last two did worse on the 64² sheet: 1572
    /// steps thrown away against 1360 over 600 frames.)
    pub last: f64,
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
            last: floor as f64,
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
            band: TIE_BAND,
            visited: Vec::new(),
            found: None,
            safe: None,
            keep: false,
        }
    }

    /// Where the next frame's search starts: the last frame's continuous
    /// count, rounded up (within the floor and the cap, [`Search::first`]).
    pub fn guess(&self) -> usize {
        let next = self.last.ceil();
        if next.is_finite() && next >= 1.0 {
            next.min(usize::MAX as f64) as usize
        } else {
            1
        }
    }

    /// Record a finished frame: `steps` taken, their largest interior `h·ω`
    /// `w`, `tried_steps` integrated in all.
    pub fn finish(&mut self, steps: usize, search: &Search, tried_steps: usize, w: f64) {
        self.last = steps as f64 * w / self.settings.wave_number;
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
        e.str(Controller::MARK).f64(self.last);
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
        self.last = d.f64("variable.last")?;
        self.stats = VariableStats::decode(d)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn controller(floor: usize, cap: usize) -> Controller {
        Controller::new(
            VariableStep {
                wave_number: 1.0,
                max_substeps: cap,
            },
            floor,
        )
    }

    fn search(floor: usize, cap: usize) -> Search {
        controller(floor, cap).search()
    }

    fn done(steps: usize, latest: bool) -> Next {
        Next::Done { steps, latest }
    }

    #[test]
    fn accepted_at_the_floor_is_done() {
        let mut s = search(4, 100);
        assert_eq!(s.record(4, Attempt::Ran(0.3)), done(4, true));
        assert_eq!(s.attempts(), 1);
    }

    #[test]
    fn a_count_that_asks_for_itself_away_from_a_tie_is_done_at_once() {
        let mut s = search(4, 100);
        // 10 steps at 0.95: ⌈9.5⌉ = 10, 9 would be at 1.06 by W ∝ 1/N, and
        // 9.5 is not within the tie band of 9.
        assert_eq!(s.record(10, Attempt::Ran(0.95)), done(10, true));
        assert_eq!(s.attempts(), 1);
        assert_eq!(s.taken(), Some(0.95));
        // 10 steps at 0.85 ask for 9 (9 would be at 0.94).
        let mut s = search(4, 100);
        assert_eq!(s.record(10, Attempt::Ran(0.85)), Next::Try(9));
        assert!(s.keep(), "10 is the fewest within the target so far");
        assert_eq!(s.record(9, Attempt::Ran(0.96)), done(9, true));
    }

    #[test]
    fn near_a_tie_the_count_below_is_tried_and_the_fewest_that_ask_for_themselves_is_taken() {
        // 10 steps at 0.92 (9.2, within the band of 9): 9 is tried.
        let mut s = search(4, 100);
        assert_eq!(s.record(10, Attempt::Ran(0.92)), Next::Try(9));
        assert!(s.keep());
        // 9 at 1.03 is past the target: the frame takes 10, kept.
        assert_eq!(s.record(9, Attempt::Ran(1.03)), done(10, false));
        assert_eq!(s.taken(), Some(0.92));
        // 9 at 0.96 asks for itself too (8.64, not within the band of 8):
        // the frame takes 9.
        let mut s = search(4, 100);
        assert_eq!(s.record(10, Attempt::Ran(0.92)), Next::Try(9));
        assert_eq!(s.record(9, Attempt::Ran(0.96)), done(9, true));
        // 9 at 0.85 asks for 8 (7.65): it is within the target but does
        // not ask for itself, and the frame takes 10, not 9.
        let mut s = search(4, 100);
        assert_eq!(s.record(10, Attempt::Ran(0.92)), Next::Try(9));
        assert_eq!(s.record(9, Attempt::Ran(0.85)), done(10, false));
        assert!(!s.keep(), "the kept state stays 10's");
        assert_eq!(s.taken(), Some(0.92));
    }

    #[test]
    fn the_same_pair_gives_the_same_count_whichever_is_tried_first() {
        // Forwards and backwards the search starts from different guesses;
        // 9 at 0.98 (8.82) and 10 at 0.91 (9.1) both ask for themselves.
        let mut up = search(4, 100);
        assert_eq!(up.record(9, Attempt::Ran(0.98)), done(9, true));
        let mut down = search(4, 100);
        assert_eq!(down.record(10, Attempt::Ran(0.91)), Next::Try(9));
        assert_eq!(down.record(9, Attempt::Ran(0.98)), done(9, true));
        // 9 at 1.02 asks for 10, 10 at 0.89 for 9 (8.9, within the band):
        // 10 either way.
        let mut up = search(4, 100);
        assert_eq!(up.record(9, Attempt::Ran(1.02)), Next::Try(10));
        assert_eq!(up.record(10, Attempt::Ran(0.89)), done(10, true));
        let mut down = search(4, 100);
        assert_eq!(down.record(10, Attempt::Ran(0.89)), Next::Try(9));
        assert_eq!(down.record(9, Attempt::Ran(1.02)), done(10, false));
    }

    #[test]
    fn rejected_jumps_by_the_prediction_and_failures_double() {
        let mut s = search(4, 100);
        assert_eq!(s.record(4, Attempt::Ran(2.5)), Next::Try(10));
        assert_eq!(s.record(10, Attempt::Failed), Next::Try(20));
        assert_eq!(s.record(20, Attempt::Ran(0.55)), Next::Try(11));
        assert_eq!(s.attempts(), 3);
    }

    #[test]
    fn a_prediction_back_to_a_count_tried_takes_the_fewest_within_the_target() {
        let mut s = search(4, 100);
        assert_eq!(s.record(4, Attempt::Ran(2.5)), Next::Try(10));
        assert_eq!(s.record(10, Attempt::Failed), Next::Try(20));
        // 20 at 0.3 asks for 6; 6 past the target asks for 10, which failed:
        // the fewest within the target is 20.
        assert_eq!(s.record(20, Attempt::Ran(0.3)), Next::Try(6));
        assert_eq!(s.record(6, Attempt::Ran(1.6)), done(20, false));
    }

    #[test]
    fn the_cap_stops_the_search() {
        let mut s = search(4, 8);
        assert_eq!(s.record(4, Attempt::Failed), Next::Try(8));
        assert_eq!(s.record(8, Attempt::Failed), Next::Exhausted { tried: 8 });
        let mut s = search(4, 8);
        assert_eq!(s.record(4, Attempt::Ran(3.0)), Next::Try(8));
        assert_eq!(s.record(8, Attempt::Ran(1.2)), Next::Exhausted { tried: 8 });
    }

    #[test]
    fn the_search_starts_at_the_last_continuous_count() {
        let mut c = controller(4, 100);
        assert_eq!(c.search().first(c.guess()), 4);
        let s = c.search();
        // 11 steps at 0.95: 10.45, so the next frame starts at 11.
        c.finish(11, &s, 11, 0.95);
        assert_eq!(c.guess(), 11);
        // Falling below the floor, the search starts at the floor.
        c.finish(4, &s, 4, 0.2);
        assert_eq!(c.search().first(c.guess()), 4);
    }

    #[test]
    fn the_controller_is_saved_and_restored() {
        let mut c = controller(4, 100);
        let s = c.search();
        c.finish(10, &s, 19, 0.95);
        c.rejected(Attempt::Ran(1.3));
        let mut e = Encoder::default();
        c.save(&mut e);
        let bytes = e.finish();
        let mut d = Decoder::new(std::path::Path::new("c.ckpt"), &bytes);
        let mut back = controller(4, 100);
        back.restore(&mut d).unwrap();
        assert_eq!(back, c);
    }

    /// Run a search from `guess` on a frame whose counts `N` measure
    /// `W_N = target·c_N/N` (`target` 1): the count taken.
    fn taken(floor: usize, cap: usize, guess: usize, c: &dyn Fn(usize) -> f64) -> Option<usize> {
        let mut s = search(floor, cap);
        let mut n = s.first(guess);
        for _ in 0..=cap {
            match s.record(n, Attempt::Ran(c(n) / n as f64)) {
                Next::Try(next) => n = next,
                Next::Done { steps, .. } => return Some(steps),
                Next::Exhausted { .. } => return None,
            }
        }
        panic!("the search did not end");
    }

    proptest::proptest! {
        /// Where the search starts does not change the count it takes, as
        /// long as the continuous counts `N·W_N/target` of neighbouring
        /// counts differ by less than the tie band: here they are
        /// `c + j(N)` with `|j| ≤ ¼`, so they differ by at most ½. The
        /// count taken is then the fewest that asks for itself (at a tie
        /// where none does, the fewest within the target), whatever the
        /// guess (the forward and backward runs' guesses differ).
        #[test]
        fn the_count_taken_does_not_depend_on_the_guess(
            c in 2.0f64..40.0,
            amplitude in 0.0f64..0.2499,
            k in 0.1f64..3.0,
            phase in 0.0f64..6.3,
            floor in 2usize..8,
        ) {
            let cap = 64;
            let cn = |n: usize| c + amplitude * (k * n as f64 + phase).sin();
            // The fewest that asks for itself; at a tie where none does
            // (N asks for N + 1, N + 1 for N), the fewest within the target.
            let asks_itself = |n: usize| cn(n) <= n as f64 && (n == floor || cn(n) > (n - 1) as f64);
            let fewest = (floor..=cap)
                .find(|&n| asks_itself(n))
                .or_else(|| (floor..=cap).find(|&n| cn(n) <= n as f64));
            for guess in floor..=cap {
                proptest::prop_assert_eq!(taken(floor, cap, guess, &cn), fewest, "guess {}", guess);
            }
        }
    }
}
