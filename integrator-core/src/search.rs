//! The search for the largest step that passes a test: expand until the
//! verdict changes, then bisect until the bracket is narrow enough.
//!
//! Why one function: the largest stable step is searched for in two
//! places, `compare`'s hard cases (in step counts over a fixed end time)
//! and `cloth`'s stability study (in step sizes), and both had written the
//! same expand-then-bisect loop. The loop is written here once;
//! what differs — how a candidate grows, shrinks and splits a bracket, and
//! where it stops — is a [`Ladder`]: [`Geometric`] for step sizes,
//! [`StepCounts`] for whole numbers of steps over a fixed time.
//!
//! The search assumes a single threshold. Where passing is not monotone in
//! the step (resonances), it finds *a* threshold: the step it returns as
//! passing always passed, and the one it returns as failing always failed.
//!
//! ```
//! use integrator_core::search::{Geometric, largest_passing};
//!
//! // Steps up to 0.3 pass; search from 0.01 between 1e-6 and 10, to 1 %.
//! let ladder = Geometric { floor: 1e-6, cap: 10.0, resolution: 1.01 };
//! let b = largest_passing(&ladder, 0.01, |h| if h <= 0.3 { Ok(()) } else { Err(h) });
//! let (lo, ()) = b.passed.unwrap();
//! let (hi, _) = b.failed.unwrap();
//! assert!(lo <= 0.3 && 0.3 < hi && hi / lo <= 1.01);
//! ```

/// The candidates of a search and how to move between them. A candidate
/// "up" is a larger step, "down" a smaller one, whatever the encoding (a
/// step count goes down when the step goes up).
pub trait Ladder {
    /// A candidate step (a size, a count, …).
    type Step: Copy;
    /// The next larger step after `x` (about twice as large), or `None` when
    /// `x` is at the largest step the search may try.
    fn up(&self, x: Self::Step) -> Option<Self::Step>;
    /// The next smaller step after `x` (about half), or `None` when `x` is
    /// at the smallest step the search may try.
    fn down(&self, x: Self::Step) -> Option<Self::Step>;
    /// A step strictly between `passed` (smaller) and `failed` (larger), or
    /// `None` when the bracket is as narrow as asked.
    fn between(&self, passed: Self::Step, failed: Self::Step) -> Option<Self::Step>;
}

/// Step sizes `h > 0`, doubled and halved, between `floor` and `cap`, and
/// bisected geometrically (`√(lo·hi)`) until `hi/lo ≤ resolution`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Geometric {
    /// The smallest step tried.
    pub floor: f64,
    /// The largest step tried.
    pub cap: f64,
    /// The widest bracket `hi/lo` accepted (e.g. 1.01 for 1 %); above 1.
    pub resolution: f64,
}

impl Ladder for Geometric {
    type Step = f64;
    fn up(&self, x: f64) -> Option<f64> {
        let h = (x * 2.0).min(self.cap);
        (h > x).then_some(h)
    }
    fn down(&self, x: f64) -> Option<f64> {
        let h = (x / 2.0).max(self.floor);
        (h < x).then_some(h)
    }
    fn between(&self, passed: f64, failed: f64) -> Option<f64> {
        (failed / passed > self.resolution).then(|| (passed * failed).sqrt())
    }
}

/// Whole numbers of steps `n ≥ 1` over a fixed time `T` (step `T/n`): a
/// larger step is a smaller count (`⌈n/2⌉`, down to one step), a smaller
/// step a larger count (`2n`, up to `max`), and a bracket is split at the
/// geometric mean of the counts until their ratio is at most
/// `1 + tolerance` or they are adjacent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepCounts {
    /// The most steps tried (the smallest step).
    pub max: u64,
    /// Stop when `n_passed/n_failed ≤ 1 + tolerance`.
    pub tolerance: f64,
}

impl Ladder for StepCounts {
    type Step = u64;
    fn up(&self, n: u64) -> Option<u64> {
        (n > 1).then(|| n.div_ceil(2))
    }
    fn down(&self, n: u64) -> Option<u64> {
        (n < self.max).then(|| n.saturating_mul(2).min(self.max))
    }
    fn between(&self, passed: u64, failed: u64) -> Option<u64> {
        // `passed` has more steps than `failed`.
        if (passed as f64) / (failed as f64) > 1.0 + self.tolerance && passed > failed + 1 {
            let mid = ((passed as f64) * (failed as f64)).sqrt().round() as u64;
            Some(mid.clamp(failed + 1, passed - 1))
        } else {
            None
        }
    }
}

/// What a search found: the largest step that passed and the smallest that
/// failed, each with what its probe returned, and how many probes it made.
///
/// Both present: the threshold lies between them. Only `passed`: every
/// step up to the largest allowed passed. Only `failed`: every step down to
/// the smallest allowed failed.
#[derive(Clone, Debug, PartialEq)]
pub struct Bracket<S, P, F> {
    /// The largest step that passed, with its probe's result.
    pub passed: Option<(S, P)>,
    /// The smallest step that failed (above `passed`), with why.
    pub failed: Option<(S, F)>,
    /// Probes made.
    pub probes: usize,
}

/// Probe `start`; if it passes, go up until a probe fails (or the ladder
/// ends), else down until one passes (or the ladder ends); then split the
/// bracket until the ladder says it is narrow enough. `probe` returns
/// `Ok` for a passing step and `Err` for a failing one, each with whatever
/// the caller wants to keep (an error measured, a reason).
pub fn largest_passing<L: Ladder, P, F>(
    ladder: &L,
    start: L::Step,
    mut probe: impl FnMut(L::Step) -> Result<P, F>,
) -> Bracket<L::Step, P, F> {
    let mut probes = 0;
    let mut test = |x| {
        probes += 1;
        probe(x)
    };
    let mut passed = None;
    let mut failed = None;
    let mut x = start;
    match test(start) {
        Ok(p) => {
            passed = Some((start, p));
            while let Some(next) = ladder.up(x) {
                x = next;
                match test(x) {
                    Ok(p) => passed = Some((x, p)),
                    Err(f) => {
                        failed = Some((x, f));
                        break;
                    }
                }
            }
        }
        Err(f) => {
            failed = Some((start, f));
            while let Some(next) = ladder.down(x) {
                x = next;
                match test(x) {
                    Ok(p) => {
                        passed = Some((x, p));
                        break;
                    }
                    Err(f) => failed = Some((x, f)),
                }
            }
        }
    }
    if let (Some(lo), Some(hi)) = (&mut passed, &mut failed) {
        while let Some(mid) = ladder.between(lo.0, hi.0) {
            match test(mid) {
                Ok(p) => *lo = (mid, p),
                Err(f) => *hi = (mid, f),
            }
        }
    }
    Bracket {
        passed,
        failed,
        probes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn threshold(t: f64) -> impl FnMut(f64) -> Result<(), ()> {
        move |h| if h <= t { Ok(()) } else { Err(()) }
    }

    #[test]
    fn a_threshold_is_bracketed_to_the_resolution_from_either_side() {
        let ladder = Geometric {
            floor: 1e-9,
            cap: 1e3,
            resolution: 1.01,
        };
        for start in [1e-5, 0.3, 0.7, 50.0] {
            let b = largest_passing(&ladder, start, threshold(0.3));
            let (lo, hi) = (b.passed.unwrap().0, b.failed.unwrap().0);
            assert!(
                lo <= 0.3 && hi > 0.3 && hi / lo <= 1.01,
                "{start}: {lo} {hi}"
            );
        }
    }

    #[test]
    fn the_ends_of_the_ladder_are_reported() {
        let ladder = Geometric {
            floor: 0.1,
            cap: 1.0,
            resolution: 1.01,
        };
        let all = largest_passing(&ladder, 0.5, threshold(f64::INFINITY));
        assert_eq!((all.passed.map(|p| p.0), all.failed), (Some(1.0), None));
        let none = largest_passing(&ladder, 0.5, threshold(0.0));
        assert_eq!(none.passed, None);
        assert_eq!(none.failed.map(|f| f.0), Some(0.1));
        assert_eq!(none.probes, 4); // 0.5, 0.25, 0.125, 0.1
    }

    #[test]
    fn step_counts_bracket_to_adjacent_counts() {
        // Passing: at least 37 steps.
        let ladder = StepCounts {
            max: 1000,
            tolerance: 1e-6,
        };
        let b = largest_passing(&ladder, 4, |n| if n >= 37 { Ok(n) } else { Err(n) });
        assert_eq!(b.passed.map(|p| p.0), Some(37));
        assert_eq!(b.failed.map(|f| f.0), Some(36));
        let one = largest_passing(&ladder, 8, |_| Ok::<_, ()>(()));
        assert_eq!(one.passed.map(|p| p.0), Some(1));
        let never = largest_passing(&ladder, 8, |_| Err::<(), _>(()));
        assert_eq!(never.failed.map(|f| f.0), Some(1000));
    }
}
