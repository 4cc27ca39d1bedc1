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

/// Does a model explain the data significantly better than their mean? The regression
/// F-test: F = (R²/p) / ((1 − R²)/(n − p − 1)) with p estimated quantities, against
/// Fisher–Snedecor's F(p, n − p − 1). White residuals alone do not make a model adequate:
/// the residuals of a model that explains nothing are the data, white if the noise is.
///
/// ```
/// use msd_ident::FitMetrics;
/// let y = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
/// let good = FitMetrics::new(&y, &[1.1, 1.9, 3.0, 4.1, 4.9, 6.0]).f_test(2);
/// assert!(good.significant, "{good:?}");
/// // F(2, d) has the closed-form tail (1 + 2F/d)^(−d/2).
/// let exact = (1.0 + 2.0 * good.statistic / 3.0).powf(-1.5);
/// assert!((good.p_value / exact - 1.0).abs() < 1e-9, "{} vs {exact}", good.p_value);
/// let none = FitMetrics::new(&y, &[3.4, 3.6, 3.5, 3.4, 3.6, 3.5]).f_test(2);
/// assert!(!none.significant, "{none:?}");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FTest {
    /// F.
    pub statistic: f64,
    /// Degrees of freedom (p, n − p − 1).
    pub degrees_of_freedom: [usize; 2],
    /// P(F(p, n − p − 1) ≥ F).
    pub p_value: f64,
    /// p-value below 0.05.
    pub significant: bool,
}

impl FitMetrics {
    /// The regression F-test of this fit with `estimated` quantities (see [`FTest`]).
    pub fn f_test(&self, estimated: usize) -> FTest {
        use statrs::distribution::{ContinuousCDF, FisherSnedecor};
        let p = estimated.max(1);
        let dof = self.samples.saturating_sub(p + 1).max(1);
        let r2 = self.r_squared.clamp(0.0, 1.0);
        // An exact fit (R² = 1) has F = ∞: the largest finite number stands for it.
        let statistic = if r2 >= 1.0 {
            f64::MAX
        } else {
            (r2 / p as f64) / ((1.0 - r2) / dof as f64)
        };
        let p_value = match FisherSnedecor::new(p as f64, dof as f64) {
            Ok(_) if r2 >= 1.0 => 0.0,
            Ok(f) => f.sf(statistic),
            Err(_) => 1.0,
        };
        FTest {
            statistic,
            degrees_of_freedom: [p, dof],
            p_value,
            significant: p_value < 0.05,
        }
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

/// The residuals measured − model, sample by sample.
pub(crate) fn residuals(measured: &[f64], model: &[f64]) -> Vec<f64> {
    debug_assert_eq!(measured.len(), model.len());
    measured.iter().zip(model).map(|(y, m)| y - m).collect()
}
