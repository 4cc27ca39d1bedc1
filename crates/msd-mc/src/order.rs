//! The order in which a band simulates its samples: similar responses side by side.
//!
//! A column's percentiles depend only on the multiset of its values, so the samples may
//! be simulated in any order without changing a bit of the result. The order matters
//! for speed: the percentile trackers look first at each block of [`LANES`] samples as
//! a whole (its smallest and largest value at that time, its *envelope*) and skip the
//! blocks lying wholly below or above the window they search. Blocks of samples with
//! similar responses have narrow envelopes, so most of them can be skipped.
//!
//! Similar parameters give similar responses. The samples are sorted by natural
//! frequency ωn, which sets the phase of the ringing (responses that ring at different
//! frequencies drift apart); then, within runs of four blocks, by damping ratio ζ, which
//! sets the height of the resonance; then, within runs of two blocks, by stiffness k,
//! which sets the static gain. On the paper's band (N = 1000, ±10 %) a level's exact
//! window cuts about 11 (5th and 95th percentiles) and 19 (median) of the 125 blocks
//! per time, against 44 and 124 in draw order.

use crate::engine::LANES;
use msd_ident::Parameters;

/// The permutation that puts similar draws next to each other (see the module
/// documentation): position s of the run simulates draw `order[s]`. Draws that are
/// `None` come last. Deterministic: stable sorts of the draws' own values.
pub(crate) fn similarity_order(draws: &[Option<Parameters>]) -> Vec<usize> {
    // Each key computed once (a sort compares each draw ~2·log₂N times).
    let keys = |f: fn(&Parameters) -> f64| -> Vec<f64> {
        let key = |d: &Option<Parameters>| d.as_ref().map_or(f64::INFINITY, f);
        draws.iter().map(key).collect()
    };
    let (omega, zeta, k) = (
        keys(Parameters::natural_frequency),
        keys(Parameters::damping_ratio),
        keys(|p| p.stiffness),
    );
    let by = |key: &[f64], run: &mut [usize]| run.sort_by(|&a, &b| key[a].total_cmp(&key[b]));
    let mut order: Vec<usize> = (0..draws.len()).collect();
    by(&omega, &mut order);
    for run in order.chunks_mut(4 * LANES) {
        by(&zeta, run);
        for pair in run.chunks_mut(2 * LANES) {
            by(&k, pair);
        }
    }
    order
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_permutation_with_failed_draws_last_and_similar_draws_together() {
        let draws: Vec<Option<Parameters>> = (0..200)
            .map(|i| {
                // Natural frequencies in a scrambled order; every seventh draw failed.
                let k = 100.0 + ((i * 37) % 200) as f64;
                (i % 7 != 3).then(|| Parameters::new(2.5, 1.8, k).unwrap())
            })
            .collect();
        let order = similarity_order(&draws);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..200).collect::<Vec<_>>());
        let failed = draws.iter().filter(|d| d.is_none()).count();
        assert!(order[200 - failed..].iter().all(|&i| draws[i].is_none()));
        // Equal m and c: each run of four blocks holds the next 32 natural frequencies.
        let wn = |i: usize| draws[i].unwrap().natural_frequency();
        for (a, b) in order[..200 - failed]
            .chunks(4 * LANES)
            .zip(order[4 * LANES..].chunks(4 * LANES))
        {
            let top = a.iter().map(|&i| wn(i)).fold(0.0, f64::max);
            assert!(
                b.iter()
                    .filter(|&&i| draws[i].is_some())
                    .all(|&i| wn(i) >= top)
            );
        }
        assert_eq!(similarity_order(&draws), order);
    }

    /// The keys computed once give the permutation that comparing the draws' own values
    /// gives: random draws, ties, failed draws.
    #[test]
    fn equals_sorting_by_the_draws_own_values() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let draws: Vec<Option<Parameters>> = (0..1000)
            .map(|i| {
                let mut v = || (rng.random_range(0..40) as f64) / 8.0 + 1.0; // many ties
                let p = Parameters::new(v(), v(), 100.0 * v()).unwrap();
                (i % 13 != 4).then_some(p)
            })
            .collect();
        let d = &draws;
        let by = |f: fn(&Parameters) -> f64| {
            move |a: &usize, b: &usize| {
                let key = |i: usize| d[i].as_ref().map_or(f64::INFINITY, f);
                key(*a).total_cmp(&key(*b))
            }
        };
        let mut expected: Vec<usize> = (0..draws.len()).collect();
        expected.sort_by(by(Parameters::natural_frequency));
        for run in expected.chunks_mut(4 * LANES) {
            run.sort_by(by(Parameters::damping_ratio));
            for pair in run.chunks_mut(2 * LANES) {
                pair.sort_by(by(|p| p.stiffness));
            }
        }
        assert_eq!(similarity_order(&draws), expected);
    }
}
