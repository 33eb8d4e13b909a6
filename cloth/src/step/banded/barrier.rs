//! A spinning barrier for the few long-lived workers of a banded frame.

use std::sync::atomic::{AtomicUsize, Ordering};

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
/// every worker that leaves after it (acquire/release).
#[derive(Debug)]
pub(super) struct SpinBarrier {
    n: usize,
    arrived: AtomicUsize,
    generation: AtomicUsize,
}

impl SpinBarrier {
    pub(super) fn new(n: usize) -> SpinBarrier {
        SpinBarrier {
            n,
            arrived: AtomicUsize::new(0),
            generation: AtomicUsize::new(0),
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
}
