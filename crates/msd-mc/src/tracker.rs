//! Exact percentiles of successive time columns, one level at a time, each column's
//! search narrowed by the previous columns.
//!
//! ## The algorithm
//! A level needs the r-th and (r+1)-th smallest values of each column. One pass over
//! the column counts the values below a window and collects those inside; if the counts
//! show that the window holds ranks r and r + 1, they are found by a selection among
//! the few collected. The pass looks at each block of [`LANES`] samples first as a
//! whole, by its envelope (its smallest and largest value at that time, written beside
//! the values when the block was simulated): a block wholly below the window counts
//! [`LANES`] at once, a block wholly above counts nothing, and only the blocks the
//! window cuts are looked at value by value. The band simulates similar samples side by
//! side (see [`order`](crate::order)), so the window cuts few blocks.
//!
//! The window is first predicted from the last two columns (the order statistics' last
//! move extrapolated, widened by a margin that follows the recent prediction errors: up
//! at once, down by halves). If the counts refuse it, the second window is proven: order
//! statistics are 1-Lipschitz in the sup norm, so if no sample moved by more than D
//! since the previous column, neither did any order statistic, and the previous values
//! ± D hold them (rounding at the edges would show in the counts). Failing both (the
//! first column), a selection over the whole column. The counts prove every answer, so
//! the result is always exactly the full selection's
//! ([`percentiles_of_keys`](crate::quantile::percentiles_of_keys)).
//!
//! Levels do not depend on each other, so each has its own tracker and they run as
//! parallel tasks; within a level the columns are taken in order.

use crate::engine::{GROUP, LANES};
use crate::quantile::{key, order_statistics, position};

/// Blocks of [`LANES`] samples in a group.
const BLOCKS: usize = GROUP / LANES;

/// A group's row at one time: its envelopes and its values, one cache line per part
/// (rows start on a 64-byte boundary): the group's minimum and maximum (then padding),
/// the blocks' minima, the blocks' maxima, and the [`GROUP`] values, sample after
/// sample. A tracker walking the columns reads every group's rows in order, a stream
/// the hardware prefetches, and most often only the first line of a row.
pub(crate) const ROW: usize = 3 * BLOCKS + GROUP;
const GROUP_MIN: usize = 0;
const GROUP_MAX: usize = 1;
const MINS: usize = BLOCKS;
const MAXS: usize = 2 * BLOCKS;
/// Where a row's values start.
pub(crate) const VALUES: usize = 3 * BLOCKS;

/// A group's rows for a chunk of time columns (see [`ROW`]), 64-byte aligned.
#[derive(Debug)]
pub(crate) struct Region {
    data: Vec<f64>,
    start: usize,
    len: usize,
}

impl Region {
    /// Rows for `width` columns, zeroed.
    pub(crate) fn new(width: usize) -> Self {
        let len = width * ROW;
        let data = vec![0.0; len + 7];
        let address = data.as_ptr() as usize;
        let start = (address.next_multiple_of(64) - address) / size_of::<f64>();
        Self { data, start, len }
    }

    /// The rows.
    pub(crate) fn rows(&self) -> &[f64] {
        &self.data[self.start..self.start + self.len]
    }

    /// The rows, to write.
    pub(crate) fn rows_mut(&mut self) -> &mut [f64] {
        &mut self.data[self.start..self.start + self.len]
    }
}

/// Writes the envelopes of the first `columns` rows of a group's `rows` from the values
/// written there.
pub(crate) fn write_envelopes(rows: &mut [f64], columns: usize) {
    debug_assert!(rows.len() >= columns * ROW);
    // Values are finite or +∞, never NaN.
    for row in rows.chunks_exact_mut(ROW).take(columns) {
        let (envelopes, values) = row.split_at_mut(VALUES);
        let (mut low, mut high) = ([0.0; BLOCKS], [0.0; BLOCKS]);
        for (k, v) in values.chunks_exact(LANES).enumerate() {
            let v: &[f64; LANES] = v.try_into().expect("LANES values");
            (low[k], high[k]) = (smallest(v), largest(v));
        }
        envelopes[MINS..MAXS].copy_from_slice(&low);
        envelopes[MAXS..].copy_from_slice(&high);
        envelopes[GROUP_MIN] = smallest(&low);
        envelopes[GROUP_MAX] = largest(&high);
    }
}

/// The smallest of 8 values that are not NaN (`<` is then min), by halving: vectorises.
#[inline(always)]
fn smallest(v: &[f64; 8]) -> f64 {
    let min = |a: f64, b: f64| if b < a { b } else { a };
    let h: [f64; 4] = std::array::from_fn(|i| min(v[i], v[i + 4]));
    let q: [f64; 2] = std::array::from_fn(|i| min(h[i], h[i + 2]));
    min(q[0], q[1])
}

/// The largest of 8 values that are not NaN, as [`smallest`].
#[inline(always)]
fn largest(v: &[f64; 8]) -> f64 {
    let max = |a: f64, b: f64| if b > a { b } else { a };
    let h: [f64; 4] = std::array::from_fn(|i| max(v[i], v[i + 4]));
    let q: [f64; 2] = std::array::from_fn(|i| max(h[i], h[i + 2]));
    max(q[0], q[1])
}

/// One time column of a chunk whose groups of [`GROUP`] samples are laid out in rows
/// ([`ROW`]): sample g·GROUP + s at column `index` is
/// `groups[g][index·ROW + VALUES + s]`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Column<'a> {
    pub(crate) groups: &'a [&'a [f64]],
    pub(crate) index: usize,
}

impl<'a> Column<'a> {
    /// Group `g`'s row.
    fn row(self, g: usize) -> &'a [f64; ROW] {
        self.groups[g][self.index * ROW..]
            .first_chunk()
            .expect("index < columns")
    }

    /// The values of block `b` (samples b·LANES …).
    fn block(self, b: usize) -> &'a [f64; LANES] {
        let (g, k) = (b / BLOCKS, b % BLOCKS);
        self.row(g)[VALUES + k * LANES..]
            .first_chunk()
            .expect("k < BLOCKS")
    }

    /// The column's values, [`LANES`] at a time.
    fn blocks(self) -> impl Iterator<Item = &'a [f64; LANES]> {
        (0..self.groups.len()).flat_map(move |g| self.row(g)[VALUES..].as_chunks::<LANES>().0)
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
    /// Windows searched (one or two a column, none for a full selection).
    pub(crate) searches: usize,
    /// Blocks looked at value by value (the window cut their envelope), all searches.
    pub(crate) cut_blocks: usize,
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
    /// The last column of the previous chunk: its groups' rows.
    last: Vec<f64>,
    /// Values inside the window, collected (spare slots: collecting writes past the end).
    inside: Vec<f64>,
    /// Their keys.
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
            last: vec![f64::INFINITY; (padded / GROUP) * ROW],
            inside: vec![0.0; padded + LANES],
            candidates: vec![0; padded],
            blocks: vec![0; padded / LANES],
            keys: vec![0; padded],
            counts: TrackerCounts::default(),
        }
    }

    /// The percentiles of the first `out.len()` columns of a chunk (its groups' rows,
    /// envelopes written), the chunk after the one given last, into `out`. Values
    /// finite or +∞ (−0.0 counts as +0.0, as `<` has it).
    pub(crate) fn chunk(&mut self, groups: &[&[f64]], out: &mut [f64]) {
        debug_assert!(groups.len() * GROUP == self.keys.len());
        debug_assert!(groups.iter().all(|g| g.len() >= out.len() * ROW));
        let last = std::mem::take(&mut self.last);
        {
            let previous: Vec<&[f64]> = last.chunks_exact(ROW).collect();
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
        for (to, group) in self.last.chunks_exact_mut(ROW).zip(groups) {
            to.copy_from_slice(&group[final_column * ROW..][..ROW]);
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
        // The envelopes: a group or block wholly below counts its size at once, one
        // wholly above nothing; the blocks the window cuts are listed.
        let mut b = 0;
        let mut listed = 0;
        for g in 0..column.groups.len() {
            let row = column.row(g);
            if row[GROUP_MAX] < lo {
                b += GROUP;
                continue;
            }
            if hi < row[GROUP_MIN] {
                continue;
            }
            for k in 0..BLOCKS {
                let (min, max) = (row[MINS + k], row[MAXS + k]);
                b += LANES * usize::from(max < lo);
                self.blocks[listed] = (g * BLOCKS + k) as u32;
                listed += usize::from((lo <= max) & (min <= hi));
            }
        }
        self.counts.cut_blocks += listed;
        self.counts.searches += 1;
        if b > self.rank {
            return None;
        }
        // The listed blocks value by value: counting below (per lane, in f64, which
        // vectorises), collecting inside (without a branch; keys only for the kept).
        let one_if = |c: bool| if c { 1.0 } else { 0.0 };
        let mut below = [0.0f64; LANES];
        let mut m = 0;
        for &block in &self.blocks[..listed] {
            let values = column.block(block as usize);
            for (count, &v) in below.iter_mut().zip(values) {
                *count += one_if(v < lo);
            }
            for &v in values {
                self.inside[m] = v;
                m += usize::from((lo <= v) & (v <= hi));
            }
        }
        b += below.iter().sum::<f64>() as usize;
        for (k, &v) in self.candidates.iter_mut().zip(&self.inside[..m]) {
            *k = key(v);
        }
        if b > self.rank || self.needed >= b + m {
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
    /// padding; with the samples in a random order or sorted.
    #[test]
    fn trackers_equal_full_selection() {
        for sorted in [false, true] {
            let counts = track_and_compare(sorted);
            for c in &counts {
                assert!(c.predicted > 0 && c.lipschitz > 0 && c.full >= 1, "{c:?}");
            }
            // Both paths taken: some blocks cut, others counted or skipped whole (32
            // blocks a column, 4 of them padding).
            let cut: usize = counts.iter().map(|c| c.cut_blocks).sum();
            let searched: usize = counts.iter().map(|c| 32 * c.searches).sum();
            assert!(cut > 0 && cut < searched / 2, "{counts:?}");
        }
    }

    fn track_and_compare(sorted: bool) -> Vec<TrackerCounts> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let (good, levels) = (253usize, [0.0, 5.0, 50.0, 72.5, 95.0, 100.0]);
        let padded = good.next_multiple_of(GROUP);
        let mut trackers: Vec<_> = levels
            .iter()
            .map(|&l| LevelTracker::new(l, good, padded))
            .collect();
        let mut column: Vec<f64> = (0..good)
            .map(|i| match sorted {
                true => i as f64 / 10.0,
                false => rng.random::<f64>(),
            })
            .collect();
        let (width, chunks) = (37, 9);
        for chunk in 0..chunks {
            // A region of rows per group.
            let mut data = vec![f64::INFINITY; (padded / GROUP) * width * ROW];
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
                    data[((i / GROUP) * width + j) * ROW + VALUES + i % GROUP] = *v;
                }
                let mut row = [0.0; 6];
                percentiles(&column, &levels, &mut row);
                for (k, value) in row.into_iter().enumerate() {
                    expected[k][j] = value;
                }
            }
            for region in data.chunks_exact_mut(width * ROW) {
                write_envelopes(region, width);
            }
            let groups: Vec<&[f64]> = data.chunks_exact(width * ROW).collect();
            for (k, tracker) in trackers.iter_mut().enumerate() {
                // The last chunk is shorter than the buffer.
                let columns = if chunk + 1 == chunks {
                    width - 5
                } else {
                    width
                };
                let mut got = vec![0.0; columns];
                tracker.chunk(&groups, &mut got);
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(
                    bits(&got),
                    bits(&expected[k][..columns]),
                    "sorted {sorted}, chunk {chunk}, level {k}"
                );
            }
        }
        trackers.iter().map(|t| t.counts).collect()
    }
}
