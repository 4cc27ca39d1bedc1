//! First-order and total Sobol indices of any model, with bootstrap confidence intervals.
//!
//! ## The method
//! Saltelli et al. (2010), "Variance based sensitivity analysis of model output. Design
//! and estimator for the total sensitivity index", Comput. Phys. Commun. 181, 259–270:
//! two independent N × d sample matrices A and B, and for each input i the matrix
//! A_B⁽ⁱ⁾ — A with its column i taken from B — so N·(d + 2) model runs. With V the
//! variance of the 2N outputs f(A), f(B) (denominator 2N − 1), Jansen's (1999) estimators
//! (Saltelli 2010, Table 2, (f) and (b)):
//!
//! - first order  Sᵢ  = (V − 1/(2N) Σⱼ (f(B)ⱼ − f(A_B⁽ⁱ⁾)ⱼ)²) / V
//! - total        S_Tᵢ = 1/(2N) Σⱼ (f(A)ⱼ − f(A_B⁽ⁱ⁾)ⱼ)² / V
//!
//! Confidence intervals: R bootstrap resamples of the N rows (with replacement),
//! percentile intervals at the requested confidence, and the standard error as the
//! standard deviation of the replicates. A quantity with V = 0 gets NaN indices.
//!
//! Row j of A and B draws 2d uniforms from [`sample_rng`](crate::draw::sample_rng)(seed, j);
//! bootstrap resample r draws from stream 2⁶³ + r. Inputs come from their distributions
//! by the inverse CDF of uniforms in (0, 1). Rows run in parallel on a local pool and are
//! reduced in row order, so results do not depend on the thread count.

use crate::quantile::percentiles;
use crate::{
    draw::sample_rng,
    error::{McError, Result},
};
use rand::Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, Normal};

/// Stream offset of the bootstrap generators.
const BOOTSTRAP_STREAM: u64 = 1 << 63;

/// The distribution of one model input.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Distribution {
    /// Uniform on [low, high].
    Uniform {
        /// Lower end.
        low: f64,
        /// Upper end (> low).
        high: f64,
    },
    /// Normal with `mean` and standard deviation `std` (> 0).
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation.
        std: f64,
    },
}

impl Distribution {
    /// The value at probability `u` ∈ (0, 1) (inverse CDF).
    pub fn quantile(&self, u: f64) -> f64 {
        match *self {
            Distribution::Uniform { low, high } => low + u * (high - low),
            Distribution::Normal { mean, std } => Normal::new(mean, std)
                .map(|d| d.inverse_cdf(u))
                .unwrap_or(f64::NAN),
        }
    }

    fn validate(&self) -> Result<()> {
        let (name, value, ok, expected) = match *self {
            Distribution::Uniform { low, high } => (
                "uniform width",
                high - low,
                low.is_finite() && high.is_finite() && high > low,
                "finite ends with high > low",
            ),
            Distribution::Normal { mean, std } => (
                "normal standard deviation",
                std,
                mean.is_finite() && std.is_finite() && std > 0.0,
                "a finite mean and a finite std > 0",
            ),
        };
        if ok {
            Ok(())
        } else {
            Err(McError::InvalidOption {
                name,
                value,
                expected,
            })
        }
    }
}

/// Options of [`sobol_indices`].
///
/// By default N = 1000 base samples, 500 bootstrap resamples, 95 % confidence, seed 0,
/// 2 threads.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SobolOptions {
    /// N, rows of A and B (≥ 2); the model runs N·(d + 2) times. By default 1000.
    pub samples: usize,
    /// Bootstrap resamples R (≥ 10). By default 500.
    pub bootstrap: usize,
    /// Confidence level of the intervals, in (0, 1). By default 0.95.
    pub confidence: f64,
    /// Seed. By default 0.
    pub seed: u64,
    /// Worker threads (≥ 1). By default 2.
    pub threads: usize,
}

impl Default for SobolOptions {
    fn default() -> Self {
        Self {
            samples: 1000,
            bootstrap: 500,
            confidence: 0.95,
            seed: 0,
            threads: 2,
        }
    }
}

impl SobolOptions {
    /// Checks every field.
    pub fn validate(&self) -> Result<()> {
        if self.samples == 0 {
            return Err(McError::ZeroSamples);
        }
        if self.threads == 0 {
            return Err(McError::ZeroThreads);
        }
        let checks = [
            (
                "samples",
                self.samples as f64,
                self.samples >= 2,
                "at least 2",
            ),
            (
                "bootstrap",
                self.bootstrap as f64,
                self.bootstrap >= 10,
                "at least 10",
            ),
            (
                "confidence",
                self.confidence,
                self.confidence > 0.0 && self.confidence < 1.0,
                "a number in (0, 1)",
            ),
        ];
        for (name, value, ok, expected) in checks {
            if !ok {
                return Err(McError::InvalidOption {
                    name,
                    value,
                    expected,
                });
            }
        }
        Ok(())
    }
}

/// One index with its uncertainty.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SobolIndex {
    /// The estimate from all N rows.
    pub estimate: f64,
    /// Standard deviation of the bootstrap replicates.
    pub std_error: f64,
    /// Bootstrap percentile interval at the run's confidence.
    pub ci: [f64; 2],
}

/// The indices of one quantity of interest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SobolQuantity {
    /// Its name.
    pub name: String,
    /// Mean over f(A) and f(B).
    pub mean: f64,
    /// Variance V over f(A) and f(B).
    pub variance: f64,
    /// First-order index of each input.
    pub first_order: Vec<SobolIndex>,
    /// Total index of each input.
    pub total: Vec<SobolIndex>,
}

/// Result of [`sobol_indices`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SobolResult {
    /// One entry per quantity of interest.
    pub quantities: Vec<SobolQuantity>,
    /// N.
    pub samples: usize,
    /// Model runs: N·(d + 2).
    pub evaluations: usize,
    /// Bootstrap resamples.
    pub bootstrap: usize,
    /// Confidence of the intervals.
    pub confidence: f64,
    /// Worker threads used.
    pub threads: usize,
}

impl std::fmt::Display for SobolResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "Sobol indices (Saltelli 2010 / Jansen): N = {}, {} runs, {} bootstrap resamples, {:.0} % intervals",
            self.samples,
            self.evaluations,
            self.bootstrap,
            100.0 * self.confidence
        )?;
        for q in &self.quantities {
            write!(
                f,
                "\n  {} (mean {:.6e}, variance {:.6e})",
                q.name, q.mean, q.variance
            )?;
            for (i, (s, t)) in q.first_order.iter().zip(&q.total).enumerate() {
                write!(
                    f,
                    "\n    input {i}: S = {:.4} [{:.4}, {:.4}], ST = {:.4} [{:.4}, {:.4}]",
                    s.estimate, s.ci[0], s.ci[1], t.estimate, t.ci[0], t.ci[1]
                )?;
            }
        }
        Ok(())
    }
}

/// First-order and total Sobol indices of each of the `quantities` (names) returned by
/// `model` (one value per quantity), for independent `inputs`.
///
/// ```
/// use msd_mc::{Distribution, SobolOptions, sobol_indices};
/// // y = x0 + 2·x1 on U(0, 1)²: S = (0.2, 0.8), no interaction.
/// let inputs = [Distribution::Uniform { low: 0.0, high: 1.0 }; 2];
/// let options = SobolOptions { samples: 2000, seed: 1, ..SobolOptions::default() };
/// let result = sobol_indices(|x: &[f64]| vec![x[0] + 2.0 * x[1]], &inputs, &["y"], &options)?;
/// let s = &result.quantities[0].first_order;
/// assert!((s[0].estimate - 0.2).abs() < 0.05 && (s[1].estimate - 0.8).abs() < 0.05);
/// # Ok::<(), msd_mc::McError>(())
/// ```
pub fn sobol_indices<F>(
    model: F,
    inputs: &[Distribution],
    quantities: &[&str],
    options: &SobolOptions,
) -> Result<SobolResult>
where
    F: Fn(&[f64]) -> Vec<f64> + Sync,
{
    options.validate()?;
    if inputs.is_empty() {
        return Err(McError::InvalidOption {
            name: "inputs",
            value: 0.0,
            expected: "at least one input distribution",
        });
    }
    if quantities.is_empty() {
        return Err(McError::InvalidOption {
            name: "quantities",
            value: 0.0,
            expected: "at least one quantity of interest",
        });
    }
    inputs.iter().try_for_each(Distribution::validate)?;
    let (n, d, q) = (options.samples, inputs.len(), quantities.len());
    let runs = d + 2;
    let pool = crate::pool(options.threads)?;
    // outputs[row][run·q + k]: run 0 = A, 1 = B, 2 + i = A_B^(i).
    let outputs: Vec<Result<Vec<f64>>> = pool.install(|| {
        (0..n)
            .into_par_iter()
            .map(|row| {
                // A panic in the caller's model becomes an error, never a torn-down pool.
                let run = || evaluate_row(&model, inputs, q, options.seed, row);
                std::panic::catch_unwind(std::panic::AssertUnwindSafe(run)).unwrap_or_else(
                    |payload| {
                        let message = payload
                            .downcast_ref::<&str>()
                            .map(|s| (*s).to_string())
                            .or_else(|| payload.downcast_ref::<String>().cloned())
                            .unwrap_or_else(|| "non-string panic payload".into());
                        Err(McError::WorkerPanicked { row, message })
                    },
                )
            })
            .collect()
    });
    let outputs: Vec<Vec<f64>> = outputs.into_iter().collect::<Result<_>>()?;

    let all: Vec<usize> = (0..n).collect();
    let estimates = indices(&outputs, &all, d, q);
    let replicates: Vec<Vec<[f64; 4]>> = pool.install(|| {
        (0..options.bootstrap)
            .into_par_iter()
            .map(|r| {
                let mut rng = sample_rng(options.seed, BOOTSTRAP_STREAM + r as u64);
                let rows: Vec<usize> = (0..n).map(|_| rng.random_range(0..n)).collect();
                indices(&outputs, &rows, d, q)
            })
            .collect()
    });
    let alpha = 100.0 * (1.0 - options.confidence) / 2.0;
    let interval = |k: usize, i: usize, which: usize, estimate: f64| {
        let values: Vec<f64> = replicates.iter().map(|rep| rep[k * d + i][which]).collect();
        let r = values.len() as f64;
        let mean = values.iter().sum::<f64>() / r;
        let std_error = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (r - 1.0)).sqrt();
        let mut ci = [0.0; 2];
        if values.iter().all(|v| v.is_finite()) {
            percentiles(&values, &[alpha, 100.0 - alpha], &mut ci);
        } else {
            ci = [f64::NAN; 2];
        }
        SobolIndex {
            estimate,
            std_error,
            ci,
        }
    };
    let quantities = (0..q)
        .map(|k| {
            let e = |i: usize| estimates[k * d + i];
            SobolQuantity {
                name: quantities[k].to_string(),
                mean: e(0)[2],
                variance: e(0)[3],
                first_order: (0..d).map(|i| interval(k, i, 0, e(i)[0])).collect(),
                total: (0..d).map(|i| interval(k, i, 1, e(i)[1])).collect(),
            }
        })
        .collect();
    Ok(SobolResult {
        quantities,
        samples: n,
        evaluations: n * runs,
        bootstrap: options.bootstrap,
        confidence: options.confidence,
        threads: options.threads,
    })
}

/// The d + 2 model runs of one Saltelli row.
fn evaluate_row<F>(
    model: &F,
    inputs: &[Distribution],
    q: usize,
    seed: u64,
    row: usize,
) -> Result<Vec<f64>>
where
    F: Fn(&[f64]) -> Vec<f64>,
{
    let d = inputs.len();
    let mut rng = sample_rng(seed, row as u64);
    let mut open = || ((rng.random::<u64>() >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
    let a: Vec<f64> = inputs.iter().map(|dist| dist.quantile(open())).collect();
    let b: Vec<f64> = inputs.iter().map(|dist| dist.quantile(open())).collect();
    let mut out = Vec::with_capacity((d + 2) * q);
    let mut x = a.clone();
    for run in 0..d + 2 {
        let point: &[f64] = match run {
            0 => &a,
            1 => &b,
            _ => {
                let i = run - 2;
                x.copy_from_slice(&a);
                x[i] = b[i];
                &x
            }
        };
        let y = model(point);
        let evaluation = row * (d + 2) + run;
        if y.len() != q {
            return Err(McError::ModelOutputLength {
                evaluation,
                expected: q,
                got: y.len(),
            });
        }
        if let Some(k) = y.iter().position(|v| !v.is_finite()) {
            return Err(McError::NonFiniteOutput {
                evaluation,
                quantity: k,
                value: y[k],
            });
        }
        out.extend_from_slice(&y);
    }
    Ok(out)
}

/// Jansen's estimators over `rows` (indices into `outputs`, repeats allowed): for each
/// quantity k and input i, `[Sᵢ, S_Tᵢ, mean, V]` at k·d + i.
fn indices(outputs: &[Vec<f64>], rows: &[usize], d: usize, q: usize) -> Vec<[f64; 4]> {
    let n = rows.len() as f64;
    let mut result = Vec::with_capacity(q * d);
    for k in 0..q {
        let value = |row: usize, run: usize| outputs[row][run * q + k];
        let mean = rows.iter().map(|&r| value(r, 0) + value(r, 1)).sum::<f64>() / (2.0 * n);
        let variance = rows
            .iter()
            .map(|&r| (value(r, 0) - mean).powi(2) + (value(r, 1) - mean).powi(2))
            .sum::<f64>()
            / (2.0 * n - 1.0);
        for i in 0..d {
            let (mut first, mut total) = (0.0, 0.0);
            for &r in rows {
                let ab = value(r, 2 + i);
                first += (value(r, 1) - ab).powi(2);
                total += (value(r, 0) - ab).powi(2);
            }
            let (s, st) = if variance > 0.0 {
                (
                    (variance - first / (2.0 * n)) / variance,
                    total / (2.0 * n) / variance,
                )
            } else {
                (f64::NAN, f64::NAN)
            };
            result.push([s, st, mean, variance]);
        }
    }
    result
}
