//! A barrier that spins, then yields, and never sleeps, for workers that meet hundreds
//! of times a second.
//!
//! `std::sync::Barrier` puts waiting threads to sleep on a condition variable. On a
//! virtual machine, waking a sleeping vCPU costs more than a whole time chunk of the
//! band (measured: a second worker that went to sleep between two chunks took no part
//! in the next one at all), so the engine's workers wait here instead: they spin for a
//! short while, then yield the core (so that more workers than cores still progress),
//! and they stop waiting when any worker aborts.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Spins before each yield while waiting.
const SPINS: usize = 256;

/// A reusable barrier for `parties` threads, with an abort flag.
pub(crate) struct SpinBarrier {
    parties: usize,
    arrived: AtomicUsize,
    generation: AtomicUsize,
    aborted: AtomicBool,
}

impl SpinBarrier {
    pub(crate) fn new(parties: usize) -> Self {
        debug_assert!(parties > 0);
        Self {
            parties,
            arrived: AtomicUsize::new(0),
            generation: AtomicUsize::new(0),
            aborted: AtomicBool::new(false),
        }
    }

    /// Waits until all parties have arrived (true), or until one has aborted (false).
    /// Everything a party wrote before arriving is visible to every party after it.
    pub(crate) fn wait(&self) -> bool {
        let generation = self.generation.load(Ordering::Acquire);
        if self.arrived.fetch_add(1, Ordering::AcqRel) + 1 == self.parties {
            self.arrived.store(0, Ordering::Relaxed);
            self.generation.fetch_add(1, Ordering::AcqRel);
            return !self.is_aborted();
        }
        let mut spins = 0;
        while self.generation.load(Ordering::Acquire) == generation {
            if self.is_aborted() {
                return false;
            }
            spins += 1;
            if spins % SPINS == 0 {
                std::thread::yield_now();
            } else {
                std::hint::spin_loop();
            }
        }
        !self.is_aborted()
    }

    /// Releases every waiting party, now and at every later barrier.
    pub(crate) fn abort(&self) {
        self.aborted.store(true, Ordering::Release);
    }

    pub(crate) fn is_aborted(&self) -> bool {
        self.aborted.load(Ordering::Acquire)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicU64;

    /// Four threads (on however many cores) add to a counter in rounds; after each
    /// barrier every thread sees every addition of the round.
    #[test]
    fn every_round_is_complete_after_the_barrier() {
        let (parties, rounds) = (4, 200);
        let barrier = SpinBarrier::new(parties);
        let counter = AtomicU64::new(0);
        std::thread::scope(|s| {
            for _ in 0..parties {
                s.spawn(|| {
                    for round in 1..=rounds {
                        counter.fetch_add(1, Ordering::Relaxed);
                        assert!(barrier.wait());
                        assert_eq!(counter.load(Ordering::Relaxed), round * parties as u64);
                        assert!(barrier.wait()); // nobody adds before everyone has read
                    }
                });
            }
        });
    }

    #[test]
    fn an_abort_releases_the_waiting() {
        let barrier = SpinBarrier::new(3);
        std::thread::scope(|s| {
            let waiting = s.spawn(|| barrier.wait());
            s.spawn(|| barrier.abort());
            assert!(!waiting.join().unwrap());
        });
        assert!(!barrier.wait());
    }
}
