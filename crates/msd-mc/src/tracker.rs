//! Exact percentiles of successive time columns, one level at a time, each column's
//! search narrowed by the previous columns.
//!
//! ## The algorithm
//! A level needs the r-th and (r+1)-th smallest values of each column. One pass over
//! the column counts the values below a window and collects those inside; if the counts
//! show that the window holds ranks r and r + 1, they are found by a selection among
//! the few collected. The window is first predicted from the last two columns (the
//! order statistics' last move extrapolated, widened by a margin that follows the recent
//! prediction errors: up at once, down by halves). If the counts refuse it, the second
//! window is proven: order statistics are 1-Lipschitz in the sup norm, so if no sample
//! moved by more than D since the previous column, neither did any order statistic, and
//! the previous values ± D hold them (rounding at the edges would show in the counts).
//! Failing both (the first column), a selection over the whole column. The counts prove
//! every answer, so the result is always exactly the full selection's
//! ([`percentiles_of_keys`](crate::quantile::percentiles_of_keys)).
//!
//! Levels do not depend on each other, so each has its own tracker and they run as
//! parallel tasks; within a level the columns are taken in order.

use crate::engine::{GROUP, LANES};
use crate::quantile::{key, order_statistics, position};

/// One time column of a chunk whose groups of [`GROUP`] samples are laid out
/// `groups[g][t·GROUP + s]` (time-major within a group): sample g·GROUP + s at column
/// `index` is `groups[g][index·GROUP + s]`. A column is N/GROUP contiguous runs, which
/// the hardware prefetches.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Column<'a> {
    pub(crate) groups: &'a [&'a [f64]],
    pub(crate) index: usize,
}

impl<'a> Column<'a> {
    /// The values of block `b` (samples b·LANES …).
    fn block(self, b: usize) -> &'a [f64; LANES] {
        let (g, k) = (b / (GROUP / LANES), b % (GROUP / LANES));
        self.groups[g][self.index * GROUP + k * LANES..]
            .first_chunk::<LANES>()
            .expect("b < blocks, index < width")
    }

    /// The column's values, [`LANES`] at a time.
    fn blocks(self) -> impl Iterator<Item = &'a [f64; LANES]> {
        self.groups.iter().flat_map(move |group| {
            let run: &[f64; GROUP] = group[self.index * GROUP..]
                .first_chunk()
                .expect("index < width");
            run.as_chunks::<LANES>().0
        })
    }
}

/// How a tracker found its order statistics, column by column (tests and profiling).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct TrackerCounts {
    /// Inside the window predicted from the two previous columns.
    pub(crate) predicted: usize,
    /// Inside the previous column's window widened by the largest change.
    pub(crate) lipschitz: usize,
    /// By a selection over the whole column.
    pub(crate) full: usize,
    /// Values collected inside accepted windows, all columns.
    pub(crate) candidates: usize,
}

/// The tracker of one percentile level (see the module documentation).
pub(crate) struct LevelTracker {
    rank: usize,
    fraction: f64,
    /// The highest rank needed: `rank`, or `rank + 1` to interpolate.
    needed: usize,
    /// The order statistics (rank, needed) of the last two columns.
    previous: (f64, f64),
    before: (f64, f64),
    margin: f64,
    seen: usize,
    /// The last column of the previous chunk, group after group.
    last: Vec<f64>,
    /// Candidate keys of the current column (one spare slot: collecting writes one past).
    candidates: Vec<i64>,
    /// Blocks of the current column with a value inside the window.
    blocks: Vec<u32>,
    keys: Vec<i64>,
    pub(crate) counts: TrackerCounts,
}

impl LevelTracker {
    /// A tracker of `level` (in [0, 100]) over `good` finite values in columns of
    /// `padded` values (a multiple of [`GROUP`]; the others are +∞).
    pub(crate) fn new(level: f64, good: usize, padded: usize) -> Self {
        debug_assert!(good > 0 && good <= padded && padded.is_multiple_of(GROUP));
        let (rank, fraction) = position(good, level);
        Self {
            rank,
            fraction,
            needed: if fraction > 0.0 { rank + 1 } else { rank },
            previous: (0.0, 0.0),
            before: (0.0, 0.0),
            margin: 0.0,
            seen: 0,
            last: vec![f64::INFINITY; padded],
            candidates: vec![0; padded + 1],
            blocks: vec![0; padded / LANES],
            keys: vec![0; padded],
            counts: TrackerCounts::default(),
        }
    }

    /// The percentiles of the first `out.len()` columns of a chunk (its groups laid out
    /// as [`Column`] says), the chunk after the one given last, into `out`. Values
    /// finite or +∞ (−0.0 counts as +0.0, as `<` has it).
    pub(crate) fn chunk(&mut self, groups: &[&[f64]], out: &mut [f64]) {
        debug_assert!(groups.len() * GROUP == self.keys.len());
        debug_assert!(groups.iter().all(|g| g.len() >= out.len() * GROUP));
        let last = std::mem::take(&mut self.last);
        {
            let previous: Vec<&[f64]> = last.chunks_exact(GROUP).collect();
            for (j, out) in out.iter_mut().enumerate() {
                let column = Column { groups, index: j };
                let previous = match j {
                    0 => Column {
                        groups: &previous,
                        index: 0,
                    },
                    _ => Column {
                        groups,
                        index: j - 1,
                    },
                };
                *out = self.column(column, previous);
            }
        }
        self.last = last;
        let final_column = out.len() - 1;
        for (to, group) in self.last.chunks_exact_mut(GROUP).zip(groups) {
            to.copy_from_slice(&group[final_column * GROUP..(final_column + 1) * GROUP]);
        }
    }

    fn column(&mut self, column: Column<'_>, previous: Column<'_>) -> f64 {
        debug_assert!(column.blocks().flatten().all(|v| !v.is_nan()));
        let mut found = None;
        if self.seen > 0 {
            let (x, next) = self.previous;
            let (dx, dn) = self.drift();
            let window = (
                x.min(x + dx) - self.margin,
                next.max(next + dn) + self.margin,
            );
            found = self.search(column, window);
            if found.is_some() {
                self.counts.predicted += 1;
            } else {
                let change = largest_change(column, previous);
                found = self.search(column, (x - change, next + change));
                self.counts.lipschitz += usize::from(found.is_some());
            }
        }
        let (x, next) = found.unwrap_or_else(|| {
            for (keys, block) in self.keys.chunks_exact_mut(LANES).zip(column.blocks()) {
                for (k, &v) in keys.iter_mut().zip(block) {
                    *k = key(v);
                }
            }
            self.counts.full += 1;
            order_statistics(&mut self.keys, self.rank, self.needed)
        });
        if self.seen > 0 {
            let ((px, pn), (dx, dn)) = (self.previous, self.drift());
            let error = (x - (px + dx)).abs().max((next - (pn + dn)).abs());
            self.margin = (2.0 * error).max(0.5 * self.margin);
        }
        (self.before, self.previous) = (self.previous, (x, next));
        self.seen += 1;
        if self.fraction > 0.0 {
            x + self.fraction * (next - x)
        } else {
            x
        }
    }

    /// The last move of the order statistics (none before two columns).
    fn drift(&self) -> (f64, f64) {
        match self.seen {
            0 | 1 => (0.0, 0.0),
            _ => (
                self.previous.0 - self.before.0,
                self.previous.1 - self.before.1,
            ),
        }
    }

    /// The order statistics (rank, needed) of `column` if `window` holds them.
    fn search(&mut self, column: Column<'_>, (lo, hi): (f64, f64)) -> Option<(f64, f64)> {
        // One pass, written for SIMD: per lane a compare, a mask and an add for the
        // count below; per block the count inside, summed pairwise, and the block's
        // index kept (without a branch) when it is not zero.
        let one_if = |c: bool| if c { 1.0 } else { 0.0 };
        let mut below = [0.0f64; LANES];
        let mut listed = 0;
        for (b, block) in column.blocks().enumerate() {
            let mut inside = [0.0f64; LANES];
            for lane in 0..LANES {
                let v = block[lane];
                below[lane] += one_if(v < lo);
                inside[lane] = one_if((lo <= v) & (v <= hi));
            }
            let [i0, i1, i2, i3, i4, i5, i6, i7] = inside;
            let hits = ((i0 + i4) + (i2 + i6)) + ((i1 + i5) + (i3 + i7));
            self.blocks[listed] = b as u32;
            listed += usize::from(hits > 0.0);
        }
        let b = below.iter().sum::<f64>() as usize;
        if b > self.rank {
            return None;
        }
        // Collecting, from the listed blocks only.
        let mut m = 0;
        for &block in &self.blocks[..listed] {
            let values = column.block(block as usize);
            for &v in values {
                self.candidates[m] = key(v);
                m += usize::from((lo <= v) & (v <= hi));
            }
        }
        if self.needed >= b + m {
            return None;
        }
        self.counts.candidates += m;
        Some(order_statistics(
            &mut self.candidates[..m],
            self.rank - b,
            self.needed - b,
        ))
    }
}

/// The largest change of a sample between two columns (failed samples, +∞ in both,
/// give NaN and are skipped).
fn largest_change(column: Column<'_>, previous: Column<'_>) -> f64 {
    let mut largest = [0.0f64; LANES];
    for (a, b) in column.blocks().zip(previous.blocks()) {
        for lane in 0..LANES {
            let change = (a[lane] - b[lane]).abs();
            if change > largest[lane] {
                largest[lane] = change;
            }
        }
    }
    largest.into_iter().fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quantile::percentiles;
    use rand::{Rng, SeedableRng};

    /// Every level's tracker gives exactly the full selection's results, column after
    /// column and across chunks, whether the columns move slowly (narrow windows), drift
    /// steadily (predicted windows), jump (fallbacks), stand still or tie; with +∞
    /// padding.
    #[test]
    fn trackers_equal_full_selection() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let (good, levels) = (253usize, [0.0, 5.0, 50.0, 72.5, 95.0, 100.0]);
        let padded = good.next_multiple_of(GROUP);
        let mut trackers: Vec<_> = levels
            .iter()
            .map(|&l| LevelTracker::new(l, good, padded))
            .collect();
        let mut column: Vec<f64> = (0..good).map(|_| rng.random::<f64>()).collect();
        let (width, chunks) = (37, 9);
        for chunk in 0..chunks {
            let mut data = vec![f64::INFINITY; padded * width]; // data[group][t][sample]
            let mut expected = vec![vec![0.0; width]; levels.len()];
            for j in 0..width {
                let step = chunk * width + j;
                let scale = match step % 50 {
                    0 => 10.0, // a jump
                    1 => 0.0,  // no change at all
                    _ => 1e-3,
                };
                for (i, v) in column.iter_mut().enumerate() {
                    *v += scale * (rng.random::<f64>() - 0.5) + 1e-3 * (i % 7) as f64;
                    if step % 97 == 3 {
                        *v = (*v * 4.0).round() / 4.0; // heavy ties
                    }
                    if step % 89 == 5 && i % 3 == 0 {
                        *v = -0.0; // signed zeros among the values
                    }
                    data[((i / GROUP) * width + j) * GROUP + i % GROUP] = *v;
                }
                let mut row = [0.0; 6];
                percentiles(&column, &levels, &mut row);
                for (k, value) in row.into_iter().enumerate() {
                    expected[k][j] = value;
                }
            }
            let groups: Vec<&[f64]> = data.chunks_exact(width * GROUP).collect();
            for (k, tracker) in trackers.iter_mut().enumerate() {
                let mut got = vec![0.0; width];
                tracker.chunk(&groups, &mut got);
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&got), bits(&expected[k]), "chunk {chunk}, level {k}");
            }
        }
        for tracker in &trackers {
            let c = tracker.counts;
            assert_eq!(c.predicted + c.lipschitz + c.full, width * chunks);
            assert!(c.predicted > 0 && c.lipschitz > 0 && c.full >= 1, "{c:?}");
        }
    }
}
