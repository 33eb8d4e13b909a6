//! A spinning barrier for the few long-lived workers of a banded frame.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex};

/// Spins of a waiting worker before it sleeps until the last one arrives:
/// the bands' shares of a phase differ by microseconds, so on an idle
/// machine the partner arrives within these (about 10–40 µs of `pause`).
/// Sleeping, not yielding, after them: a yield on a core that another
/// process shares (a build beside the run, however low its priority) hands
/// that process a whole time slice, milliseconds, before the worker looks
/// again (measured: a 16² frame of 64 steps took 7.8 ms instead of 0.2 on
/// a Zen 5 with builds on the other core); a sleeper is woken by the last
/// arrival at once and, being the busier task, runs ahead of the other
/// process. On an oversubscribed machine (both workers on one core) the
/// spinner gives its core up after the spins as well.
const SPINS: u32 = 1 << 10;

/// `n` workers wait until all have arrived; reusable (a generation counter,
/// so a fast worker that arrives at the next barrier cannot be confused
/// with the last one). Arriving releases what the worker wrote before it to
/// every worker that leaves after it (acquire/release). A worker that
/// panics poisons it ([`PoisonOnPanic`]), and whoever waits at it then
/// panics too, so that a bug in one band is a panic of the frame, never a
/// partner waiting forever.
#[derive(Debug)]
pub(super) struct SpinBarrier {
    n: usize,
    arrived: AtomicUsize,
    generation: AtomicUsize,
    poisoned: AtomicBool,
    /// Workers asleep (or about to be) at the current generation.
    sleepers: AtomicUsize,
    /// Where they sleep: the generation is looked at again under the lock,
    /// and the last arrival notifies under it, so no wake-up is lost.
    lock: Mutex<()>,
    wake: Condvar,
}

/// Held by a worker for its whole frame: poisons the barrier if the worker
/// unwinds.
pub(super) struct PoisonOnPanic<'a>(pub &'a SpinBarrier);

impl Drop for PoisonOnPanic<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.poisoned.store(true, Ordering::SeqCst);
            self.0.wake_sleepers();
        }
    }
}

impl SpinBarrier {
    pub(super) fn new(n: usize) -> SpinBarrier {
        SpinBarrier {
            n,
            arrived: AtomicUsize::new(0),
            generation: AtomicUsize::new(0),
            poisoned: AtomicBool::new(false),
            sleepers: AtomicUsize::new(0),
            lock: Mutex::new(()),
            wake: Condvar::new(),
        }
    }

    /// Wait for the other workers.
    pub(super) fn wait(&self) {
        if self.n <= 1 {
            return;
        }
        let generation = self.generation.load(Ordering::Acquire);
        if self.arrived.fetch_add(1, Ordering::AcqRel) + 1 == self.n {
            // The last one: reset the count, then open (the reset is seen
            // by whoever sees the new generation), then wake the sleepers.
            self.arrived.store(0, Ordering::Relaxed);
            self.generation.fetch_add(1, Ordering::SeqCst);
            if self.sleepers.load(Ordering::SeqCst) > 0 {
                self.wake_sleepers();
            }
            return;
        }
        for _ in 0..SPINS {
            if self.generation.load(Ordering::Acquire) != generation {
                return;
            }
            std::hint::spin_loop();
        }
        // Asleep until the generation changes. Counted before the look
        // under the lock (sequentially consistent with the last arrival's
        // bump and its look at the count): either it sees this sleeper and
        // notifies, or this sleeper sees its new generation.
        self.sleepers.fetch_add(1, Ordering::SeqCst);
        let mut guard = self.lock.lock().unwrap_or_else(|e| e.into_inner());
        while self.generation.load(Ordering::SeqCst) == generation {
            if self.poisoned.load(Ordering::SeqCst) {
                drop(guard);
                self.sleepers.fetch_sub(1, Ordering::SeqCst);
                panic!("a banded worker panicked, so its partner stops waiting for it");
            }
            guard = self.wake.wait(guard).unwrap_or_else(|e| e.into_inner());
        }
        drop(guard);
        self.sleepers.fetch_sub(1, Ordering::SeqCst);
    }

    /// Wake every sleeper (under the lock, so that none is between its
    /// look at the generation and its wait).
    fn wake_sleepers(&self) {
        let _guard = self.lock.lock().unwrap_or_else(|e| e.into_inner());
        self.wake.notify_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicU64;

    /// Every worker sees all the others' increments of a phase once it is
    /// past the phase's barrier.
    #[test]
    fn phases_do_not_overlap() {
        let barrier = SpinBarrier::new(3);
        let counter = AtomicU64::new(0);
        std::thread::scope(|s| {
            for _ in 0..3 {
                s.spawn(|| {
                    for phase in 1..=200u64 {
                        counter.fetch_add(1, Ordering::Relaxed);
                        barrier.wait();
                        assert_eq!(counter.load(Ordering::Relaxed), 3 * phase);
                        barrier.wait();
                    }
                });
            }
        });
        assert_eq!(counter.load(Ordering::Relaxed), 600);
    }

    /// A worker that panics mid-frame makes its partner's wait panic
    /// instead of spinning forever; the scope then reports the panic.
    #[test]
    fn a_panicking_worker_does_not_leave_its_partner_waiting() {
        let barrier = SpinBarrier::new(2);
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            std::thread::scope(|s| {
                s.spawn(|| {
                    let _guard = PoisonOnPanic(&barrier);
                    barrier.wait();
                    barrier.wait();
                });
                s.spawn(|| {
                    let _guard = PoisonOnPanic(&barrier);
                    barrier.wait();
                    panic!("a bug in one band");
                });
            });
        }));
        assert!(outcome.is_err());
    }
}
