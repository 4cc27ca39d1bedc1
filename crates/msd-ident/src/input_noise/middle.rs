//! The middle matrix B = Jᵀ·W·Σ·W·J of the sandwich covariance, in the frequency domain.

use super::SpectralModel;
use super::spectral::{padded, real_inverses, spectra};
use nalgebra::DMatrix;
use rustfft::num_complex::Complex64;
use std::ops::Range;

/// One record as the middle matrix sees it: per channel its impulse response (the
/// model's response to one unit drive sample, from rest), its rows of the Jacobian, its
/// weight and its sensor group; `len` samples.
pub(crate) struct MiddleRecord {
    pub len: usize,
    pub impulse: Vec<Vec<f64>>,
    pub rows: Vec<Range<usize>>,
    pub weights: Vec<f64>,
    pub groups: Vec<usize>,
}

/// B's parts, each per unit variance: the drive's (σ²_u) and each sensor group's (σ²_a).
pub(crate) struct Middle {
    pub drive: DMatrix<f64>,
    pub sensors: Vec<DMatrix<f64>>,
}

impl Middle {
    /// B under `model`, its variances scaled by `inflation`.
    pub(crate) fn total(&self, model: &SpectralModel, inflation: f64) -> DMatrix<f64> {
        let mut b = &self.drive * model.input_variance;
        for (part, d) in self.sensors.iter().zip(&model.sensor_variance) {
            b += part * *d;
        }
        b * inflation
    }
}

/// The parts of B = Jᵀ·W·Σ·W·J (p×p) of `jacobian`, per unit variance of the drive and
/// of each of `groups` sensor groups. The drive's noise starts with the record (the plant
/// felt the true drive before it): Σ = σ²_u·Gₐ·G_bᵀ + δ_ab·σ²_a with Gₐ the record's
/// lower-triangular convolution by gₐ, so B's drive part is σ²_u·HᵀH with
/// H = Σₐ Gₐᵀ·Wₐ·Jₐ, each column one zero-padded FFT correlation.
pub(crate) fn middle_matrix(
    records: &[MiddleRecord],
    jacobian: &DMatrix<f64>,
    groups: usize,
) -> Middle {
    let p = jacobian.ncols();
    let mut middle = Middle {
        drive: DMatrix::zeros(p, p),
        sensors: vec![DMatrix::zeros(p, p); groups],
    };
    for rec in records {
        let size = padded(rec.len);
        // Each channel's impulse response, then each column's rows per channel weighted,
        // two to a transform.
        let columns = (0..p).flat_map(|c| {
            (rec.rows.iter().zip(&rec.weights)).map(move |(rows, w)| {
                let column = jacobian.column(c);
                column
                    .rows_range(rows.clone())
                    .iter()
                    .map(|v| v * w)
                    .collect()
            })
        });
        let all: Vec<Vec<f64>> = rec.impulse.iter().cloned().chain(columns).collect();
        let mut transformed = spectra(all.into_iter().map(Vec::into_iter), size, 1.0);
        let x = transformed.split_off(rec.impulse.len());
        let correlations = (0..p).map(|c| {
            let mut sum = vec![Complex64::new(0.0, 0.0); size];
            for (g, x) in transformed.iter().zip(&x[c * rec.rows.len()..]) {
                for ((s, x), g) in sum.iter_mut().zip(x).zip(g) {
                    *s += g.conj() * x;
                }
            }
            sum
        });
        let h: Vec<Vec<f64>> = real_inverses(correlations, size)
            .into_iter()
            .map(|v| v[..rec.len].iter().map(|v| v / size as f64).collect())
            .collect();
        for r in 0..p {
            for c in 0..p {
                middle.drive[(r, c)] += h[r].iter().zip(&h[c]).map(|(a, b)| a * b).sum::<f64>();
                for (ch, &g) in rec.groups.iter().enumerate() {
                    let (x, y) = (jacobian.column(r), jacobian.column(c));
                    let dot: f64 = rec.rows[ch].clone().map(|i| x[i] * y[i]).sum();
                    middle.sensors[g][(r, c)] += rec.weights[ch].powi(2) * dot;
                }
            }
        }
    }
    middle
}
