//! The linear half of the variable projection: each record's Gram matrix of W·G (the
//! free responses to a unit initial displacement and velocity, and one indicator per
//! channel for its offset), β̂, and the projection of a vector off the span of W·G.
//!
//! Every sum runs over one channel's contiguous rows, so the Gram matrix of a record is
//! built from per-channel sums Σ g·gᵀ, Σ g and the count, each weighted by w².

use super::problem::{Joint, RecordRows};
use nalgebra::{Cholesky, DMatrix, DVector, Dyn};

impl Joint<'_> {
    /// The rows of channel `ch` of a record.
    pub(crate) fn rows_of(rec: &RecordRows<'_>, ch: usize) -> std::ops::Range<usize> {
        let first = rec.start + ch * rec.len;
        first..first + rec.len
    }

    /// The Gram matrix (W·G)ᵀ(W·G) of a record: per channel, Σ g·gᵀ, Σ g and the count
    /// weighted by w².
    pub(crate) fn gram(&self, rec: &RecordRows<'_>) -> DMatrix<f64> {
        let q = self.linear_count(rec.maps.len());
        let first = 2 * usize::from(self.state);
        let mut gram = DMatrix::zeros(q, q);
        for (ch, &w) in rec.weights.iter().enumerate() {
            let w2 = w * w;
            let (mut s00, mut s01, mut s11, mut s0, mut s1) = (0.0, 0.0, 0.0, 0.0, 0.0);
            for g in &self.basis[Self::rows_of(rec, ch)] {
                s00 += g[0] * g[0];
                s01 += g[0] * g[1];
                s11 += g[1] * g[1];
                s0 += g[0];
                s1 += g[1];
            }
            if self.state {
                gram[(0, 0)] += w2 * s00;
                gram[(0, 1)] += w2 * s01;
                gram[(1, 0)] += w2 * s01;
                gram[(1, 1)] += w2 * s11;
            }
            if self.offset {
                let o = first + ch;
                gram[(o, o)] = w2 * rec.len as f64;
                if self.state {
                    [gram[(0, o)], gram[(1, o)]] = [w2 * s0, w2 * s1];
                    [gram[(o, 0)], gram[(o, 1)]] = [w2 * s0, w2 * s1];
                }
            }
        }
        gram
    }

    /// (W·G)ᵀ·v for a record, `v(ch)` giving channel ch's rows of a vector already
    /// weighted by w.
    pub(crate) fn moments<'v>(
        &self,
        rec: &RecordRows<'_>,
        v: impl Fn(usize) -> &'v [f64],
    ) -> DVector<f64> {
        let first = 2 * usize::from(self.state);
        let mut rhs = DVector::zeros(self.linear_count(rec.maps.len()));
        for (ch, &w) in rec.weights.iter().enumerate() {
            let (mut a, mut b, mut sum) = (0.0, 0.0, 0.0);
            for (g, v) in self.basis[Self::rows_of(rec, ch)].iter().zip(v(ch)) {
                a += g[0] * v;
                b += g[1] * v;
                sum += v;
            }
            if self.state {
                rhs[0] += w * a;
                rhs[1] += w * b;
            }
            if self.offset {
                rhs[first + ch] = w * sum;
            }
        }
        rhs
    }

    /// The fitted part of channel `ch`, G·β (unweighted), as (state coefficients, offset).
    pub(crate) fn fitted(&self, beta: &[f64], ch: usize) -> ([f64; 2], f64) {
        let first = 2 * usize::from(self.state);
        let state = if self.state {
            [beta[0], beta[1]]
        } else {
            [0.0; 2]
        };
        let offset = if self.offset { beta[first + ch] } else { 0.0 };
        (state, offset)
    }

    /// β̂ of every record from the data (after [`prepare`](Self::prepare)).
    pub(crate) fn solve_linear(&mut self) {
        let mut weighted = vec![0.0; self.records.iter().map(|r| r.len).max().unwrap_or(0)];
        let mut records = std::mem::take(&mut self.records);
        for rec in &mut records {
            let Some(linear) = &rec.linear else {
                rec.beta.clear();
                continue;
            };
            let channels = rec.record.channels.len();
            let mut rhs = DVector::zeros(self.linear_count(channels));
            for ch in 0..channels {
                let w = rec.weights[ch];
                let rows = Self::rows_of(rec, ch);
                for ((out, y), f) in weighted
                    .iter_mut()
                    .zip(&rec.record.channels[ch].samples)
                    .zip(&self.forced[rows])
                {
                    *out = w * (y - f);
                }
                rhs += self.moments_of_channel(rec, ch, &weighted[..rec.len]);
            }
            rec.beta = linear.solve(&rhs).iter().copied().collect();
        }
        self.records = records;
    }

    /// [`moments`](Self::moments) of one channel's weighted rows `v` (zero elsewhere).
    pub(crate) fn moments_of_channel(
        &self,
        rec: &RecordRows<'_>,
        ch: usize,
        v: &[f64],
    ) -> DVector<f64> {
        let empty: &[f64] = &[];
        self.moments(rec, |c| if c == ch { v } else { empty })
    }

    /// Removes from the record's rows of `v` their projection on the span of W·G.
    pub(crate) fn project(&self, rec: &RecordRows<'_>, v: &mut [f64]) {
        let Some(linear) = &rec.linear else {
            return;
        };
        let coef = linear.solve(&self.moments(rec, |ch| &v[Self::rows_of(rec, ch)]));
        let coef: Vec<f64> = coef.iter().copied().collect();
        for ch in 0..rec.maps.len() {
            let w = rec.weights[ch];
            let (state, offset) = self.fitted(&coef, ch);
            let rows = Self::rows_of(rec, ch);
            for (v, g) in v[rows.clone()].iter_mut().zip(&self.basis[rows]) {
                *v -= w * (g[0] * state[0] + g[1] * state[1] + offset);
            }
        }
    }
}

/// A Gram matrix factorised with its diagonal scaled to 1 (so the units of the columns
/// do not matter).
pub(crate) struct LinearSolve {
    cholesky: Cholesky<f64, Dyn>,
    scale: DVector<f64>,
}

impl LinearSolve {
    pub(crate) fn new(gram: DMatrix<f64>) -> Option<Self> {
        let q = gram.nrows();
        let scale = DVector::from_fn(q, |i, _| 1.0 / gram[(i, i)].sqrt());
        if !scale.iter().all(|s| s.is_finite()) {
            return None;
        }
        let scaled = DMatrix::from_fn(q, q, |r, c| gram[(r, c)] * scale[r] * scale[c]);
        Some(Self {
            cholesky: scaled.cholesky()?,
            scale,
        })
    }

    pub(crate) fn solve(&self, rhs: &DVector<f64>) -> DVector<f64> {
        let scaled = rhs.component_mul(&self.scale);
        self.cholesky.solve(&scaled).component_mul(&self.scale)
    }
}
