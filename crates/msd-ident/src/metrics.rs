//! Goodness-of-fit measures of a model output against a measurement.

use serde::{Deserialize, Serialize};

/// How well a model output matches a measurement.
///
/// ```
/// use msd_ident::FitMetrics;
/// let measured = [1.0, 2.0, 3.0, 4.0];
/// let model = [1.1, 1.9, 3.1, 3.9];
/// let fit = FitMetrics::new(&measured, &model);
/// assert!((fit.r_squared - (1.0 - 0.04 / 5.0)).abs() < 1e-12);
/// assert!((fit.residual_rms - 0.1).abs() < 1e-12);
/// assert_eq!(fit.to_string(), "R² = 0.99200, fit = 91.06 %, RMS error = 1.0000e-1 (4 samples)");
/// assert_eq!(serde_json::to_value(fit)?["samples"], 4);
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FitMetrics {
    /// Coefficient of determination R² = 1 − SSE/SST, SST about the measurement's mean.
    /// Serialized as `r2` (the toolkit's results.json key).
    #[serde(rename = "r2", alias = "r_squared")]
    pub r_squared: f64,
    /// MATLAB's `compare` fit: 100·(1 − ‖y − ŷ‖/‖y − ȳ‖), in percent.
    pub fit_percent: f64,
    /// Root mean square of the residuals y − ŷ.
    pub residual_rms: f64,
    /// Sum of squared residuals.
    pub sse: f64,
    /// Number of samples.
    pub samples: usize,
}

impl std::fmt::Display for FitMetrics {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "R² = {:.5}, fit = {:.2} %, RMS error = {:.4e} ({} samples)",
            self.r_squared, self.fit_percent, self.residual_rms, self.samples
        )
    }
}

impl FitMetrics {
    /// Computes the metrics of `model` against `measured` (equal lengths, non-empty).
    /// For a constant measurement R² and fit % are 1 and 100 for an exact match, else 0.
    pub fn new(measured: &[f64], model: &[f64]) -> Self {
        debug_assert_eq!(measured.len(), model.len());
        let n = measured.len();
        let mean = measured.iter().sum::<f64>() / n as f64;
        let sst: f64 = measured.iter().map(|y| (y - mean).powi(2)).sum();
        let sse: f64 = measured
            .iter()
            .zip(model)
            .map(|(y, m)| (y - m).powi(2))
            .sum();
        // A constant measurement (SST = 0) has no variance to explain: as scikit-learn's
        // r2_score, R² = 1 (fit 100 %) for an exact match and 0 otherwise, never 0/0.
        let (r_squared, fit_percent) = if sst > 0.0 {
            (1.0 - sse / sst, 100.0 * (1.0 - (sse / sst).sqrt()))
        } else if sse == 0.0 {
            (1.0, 100.0)
        } else {
            (0.0, 0.0)
        };
        Self {
            r_squared,
            fit_percent,
            residual_rms: (sse / n as f64).sqrt(),
            sse,
            samples: n,
        }
    }
}
