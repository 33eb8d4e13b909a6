//! The bands' worker threads, started once with the stepper and kept hot
//! between frames.
//!
//! Why not a thread per frame (`std::thread::scope`, as this stepper
//! started) or a rayon pool: both leave the second core asleep between
//! frames, and on the virtual machines this project runs on, waking a
//! halted core takes tens of microseconds — measured on a Zen 5 at 64²
//! (AVX2 cap, frames of 64 steps), the first band waited 70–140 µs at the
//! frame's first barrier for its partner, 5–9 % of a 1.4 ms frame. A
//! [`Crew`] member that has finished a job keeps looking for the next one
//! for [`HOT`] before it sleeps, so the frames of a run (a few hundred
//! microseconds apart: the run loop's energy and output) find it awake;
//! after a longer pause it sleeps on a condition variable and costs
//! nothing.

use std::cell::UnsafeCell;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How long an idle member looks for the next job before it sleeps.
const HOT: Duration = Duration::from_micros(2000);

/// Spins between two looks at the clock while hot, and of the caller
/// waiting for the members before it yields its core.
const SPINS: u32 = 1 << 8;

/// A job as the members see it: the caller's closure with its lifetime
/// erased ([`Crew::run`] does not return before every member is done
/// with it).
type Job = *const (dyn Fn(usize) + Sync + 'static);

struct Shared {
    /// Bumped once per job, and once more to stop.
    generation: AtomicU64,
    /// The job of the current generation: written by the caller before it
    /// bumps `generation` (release), read by members after they see the
    /// bump (acquire), and not written again before all have counted
    /// themselves in `done`.
    job: UnsafeCell<Option<Job>>,
    /// Members done with the current job.
    done: AtomicUsize,
    /// A member's job panicked (the caller panics in its turn).
    panicked: AtomicBool,
    stop: AtomicBool,
    /// Where sleeping members wait for the next generation.
    sleep: Mutex<()>,
    wake: Condvar,
}

// SAFETY: `job` is written only by the caller while no member reads it
// (before the generation bump that publishes it, after every member has
// counted itself done), as the module's protocol says.
unsafe impl Sync for Shared {}
// SAFETY: the raw job pointer is only dereferenced under the same protocol.
unsafe impl Send for Shared {}

/// Members `1..n` of a team whose member 0 is the calling thread.
pub(super) struct Crew {
    shared: Arc<Shared>,
    members: Vec<JoinHandle<()>>,
}

impl Crew {
    /// A crew of `n − 1` threads besides the caller, or the error of the
    /// thread that could not be started (the ones started are stopped).
    pub(super) fn new(n: usize) -> std::io::Result<Crew> {
        let shared = Arc::new(Shared {
            generation: AtomicU64::new(0),
            job: UnsafeCell::new(None),
            done: AtomicUsize::new(0),
            panicked: AtomicBool::new(false),
            stop: AtomicBool::new(false),
            sleep: Mutex::new(()),
            wake: Condvar::new(),
        });
        let mut crew = Crew {
            shared,
            members: Vec::with_capacity(n.saturating_sub(1)),
        };
        for index in 1..n {
            let shared = Arc::clone(&crew.shared);
            let member = std::thread::Builder::new()
                .name(format!("cloth-band-{index}"))
                .spawn(move || serve(&shared, index))?;
            crew.members.push(member);
        }
        Ok(crew)
    }

    /// A crew of the caller alone (no thread to start).
    pub(super) fn alone() -> Crew {
        Crew::new(1).expect("a crew of one starts no thread")
    }

    /// `f(0)` on the calling thread and `f(i)` on member `i`, all at once;
    /// returns what `f(0)` returns when every member is done. A member's
    /// panic is the caller's panic, after all are done.
    pub(super) fn run<R>(&self, f: &(dyn Fn(usize) -> R + Sync)) -> R {
        let s = &*self.shared;
        if self.members.is_empty() {
            return f(0);
        }
        let members = move |i: usize| {
            f(i);
        };
        let job: &(dyn Fn(usize) + Sync) = &members;
        // SAFETY: the lifetime is erased only for the members' use, which
        // ends before this function returns or unwinds (`AllDone`).
        let job: Job = unsafe { std::mem::transmute::<&(dyn Fn(usize) + Sync), Job>(job) };
        s.done.store(0, Ordering::Relaxed);
        // SAFETY: no member reads the job now (all counted themselves done
        // with the last one, or none ran yet).
        unsafe { *s.job.get() = Some(job) };
        s.generation.fetch_add(1, Ordering::Release);
        {
            // Under the lock, so a member about to sleep either sees the
            // new generation or is waiting when the notice comes.
            let _lock = s.sleep.lock().unwrap_or_else(|e| e.into_inner());
            s.wake.notify_all();
        }
        let wait = AllDone {
            shared: s,
            n: self.members.len(),
        };
        let out = f(0);
        drop(wait);
        if s.panicked.swap(false, Ordering::AcqRel) {
            panic!("a banded worker panicked");
        }
        out
    }
}

/// Waits, also while the caller unwinds, until every member is done with
/// the job, so that no member uses the caller's borrows after `run`.
struct AllDone<'a> {
    shared: &'a Shared,
    n: usize,
}

impl Drop for AllDone<'_> {
    fn drop(&mut self) {
        let mut spins = 0u32;
        while self.shared.done.load(Ordering::Acquire) < self.n {
            if spins < SPINS {
                spins += 1;
                std::hint::spin_loop();
            } else {
                std::thread::yield_now();
            }
        }
    }
}

impl Drop for Crew {
    fn drop(&mut self) {
        let s = &*self.shared;
        s.stop.store(true, Ordering::Release);
        s.generation.fetch_add(1, Ordering::Release);
        {
            let _lock = s.sleep.lock().unwrap_or_else(|e| e.into_inner());
            s.wake.notify_all();
        }
        for member in self.members.drain(..) {
            // A member never panics outside a job (caught there).
            let _ = member.join();
        }
    }
}

/// A member's life: wait for a generation, run its share of the job,
/// count itself done; until the crew stops.
fn serve(s: &Shared, index: usize) {
    let mut seen = 0u64;
    loop {
        seen = next_generation(s, seen);
        if s.stop.load(Ordering::Acquire) {
            return;
        }
        // SAFETY: published before the generation this member saw, and
        // live until it counts itself done (`Crew::run`).
        let job = unsafe { (*s.job.get()).expect("a job is published with its generation") };
        // SAFETY: as above.
        let job = unsafe { &*job };
        if catch_unwind(AssertUnwindSafe(|| job(index))).is_err() {
            s.panicked.store(true, Ordering::Release);
        }
        s.done.fetch_add(1, Ordering::AcqRel);
    }
}

/// The first generation after `seen`: looked for hot for [`HOT`], then
/// waited for asleep.
fn next_generation(s: &Shared, seen: u64) -> u64 {
    let since = Instant::now();
    loop {
        for _ in 0..SPINS {
            let g = s.generation.load(Ordering::Acquire);
            if g != seen {
                return g;
            }
            std::hint::spin_loop();
        }
        if since.elapsed() > HOT {
            break;
        }
    }
    let mut lock = s.sleep.lock().unwrap_or_else(|e| e.into_inner());
    loop {
        let g = s.generation.load(Ordering::Acquire);
        if g != seen {
            return g;
        }
        lock = s.wake.wait(lock).unwrap_or_else(|e| e.into_inner());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every member runs its share of every job, once, and the caller
    /// sees all their writes when `run` returns; also after the members
    /// have slept.
    #[test]
    fn every_member_runs_every_job() {
        let crew = Crew::new(3).unwrap();
        let counts: Vec<AtomicUsize> = (0..3).map(|_| AtomicUsize::new(0)).collect();
        for round in 1..=300usize {
            let r = crew.run(&|i| {
                counts[i].fetch_add(1, Ordering::Relaxed);
                i
            });
            assert_eq!(r, 0);
            for c in &counts {
                assert_eq!(c.load(Ordering::Relaxed), round);
            }
            if round % 100 == 0 {
                std::thread::sleep(HOT * 3);
            }
        }
    }

    /// A member's panic reaches the caller, and the crew still works after.
    #[test]
    fn a_member_panic_is_the_callers() {
        let crew = Crew::new(2).unwrap();
        let out = catch_unwind(AssertUnwindSafe(|| {
            crew.run(&|i| {
                if i == 1 {
                    panic!("a bug in one band");
                }
            })
        }));
        assert!(out.is_err());
        let hits = AtomicUsize::new(0);
        crew.run(&|_| {
            hits.fetch_add(1, Ordering::Relaxed);
        });
        assert_eq!(hits.load(Ordering::Relaxed), 2);
    }
}
