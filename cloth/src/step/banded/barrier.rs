//! A spinning barrier for the few long-lived workers of a banded frame.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Spins of a waiting worker before it starts yielding its core
/// ([`std::thread::yield_now`]) between looks: the bands' shares of a phase
/// differ by microseconds, so on an idle machine the partner arrives within
/// these (about 10–40 µs of `pause`), and yielding on an idle core returns
/// at once; on an oversubscribed one (a CI runner, the other core busy)
/// yielding soon lets the partner run instead of burning its time slice.
const SPINS: u32 = 1 << 10;

/// `n` workers wait until all have arrived; reusable (a generation counter,
/// so a fast worker that arrives at the next barrier cannot be confused
/// with the last one). Arriving releases what the worker wrote before it to
/// every worker that leaves after it (acquire/release). A worker that
/// panics poisons it ([`PoisonOnPanic`]), and whoever waits at it then
/// panics too, so that a bug in one band is a panic of the frame, never a
/// partner spinning forever.
#[derive(Debug)]
pub(super) struct SpinBarrier {
    n: usize,
    arrived: AtomicUsize,
    generation: AtomicUsize,
    poisoned: AtomicBool,
}

/// Held by a worker for its whole frame: poisons the barrier if the worker
/// unwinds.
pub(super) struct PoisonOnPanic<'a>(pub &'a SpinBarrier);

impl Drop for PoisonOnPanic<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.poisoned.store(true, Ordering::Release);
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
            // by whoever sees the new generation).
            self.arrived.store(0, Ordering::Relaxed);
            self.generation.fetch_add(1, Ordering::Release);
            return;
        }
        let mut spins = 0u32;
        while self.generation.load(Ordering::Acquire) == generation {
            if self.poisoned.load(Ordering::Acquire) {
                panic!("a banded worker panicked, so its partner stops waiting for it");
            }
            if spins < SPINS {
                spins += 1;
                std::hint::spin_loop();
            } else {
                std::thread::yield_now();
            }
        }
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
