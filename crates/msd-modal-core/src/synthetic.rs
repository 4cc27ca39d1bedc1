//! Frequency responses with known truth, for tests, benchmarks and teaching.

use msd_signal::{Complex64, FrequencyResponseEstimate, gaussian_noise};

use crate::error::Result;

/// A measured table made up: `response(f)` at each of the `frequency_hz` lines plus
/// complex Gaussian noise of relative size `relative_noise` (E|e|² = relative²·|H|²:
/// each part has standard deviation relative·|H|/√2), from `seed` (msd-signal's streams
/// `frf.noise.re` and `frf.noise.im`); the variances relative²·|H|² are attached (when
/// the noise is not 0).
///
/// Errors on frequencies that are not finite, ≥ 0 and increasing, a negative or
/// non-finite noise level, and a response that is not finite.
///
/// ```
/// use msd_modal_core::synthetic_frequency_response;
/// use msd_signal::Complex64;
/// // The paper's plant (m 2.5 kg, c 1.8 N·s/m, k 120 N/m) measured at 40 frequencies
/// // with 1 % complex noise.
/// let f: Vec<f64> = (0..40).map(|i| 0.25 + 2.25 * i as f64 / 39.0).collect();
/// let sweep = synthetic_frequency_response(&f, 0.01, 1, |f| {
///     let w = std::f64::consts::TAU * f;
///     Complex64::new(1.0, 0.0) / Complex64::new(120.0 - 2.5 * w * w, 1.8 * w)
/// })?;
/// assert_eq!(sweep.h.len(), 40);
/// assert!(sweep.variance.is_some());
/// # Ok::<(), msd_modal_core::ModalError>(())
/// ```
pub fn synthetic_frequency_response(
    frequency_hz: &[f64],
    relative_noise: f64,
    seed: u64,
    response: impl Fn(f64) -> Complex64,
) -> Result<FrequencyResponseEstimate> {
    let n = frequency_hz.len();
    let s = relative_noise / std::f64::consts::SQRT_2;
    let re = gaussian_noise(seed, "frf.noise.re", s, n)?;
    let im = gaussian_noise(seed, "frf.noise.im", s, n)?;
    let exact: Vec<Complex64> = frequency_hz.iter().map(|&f| response(f)).collect();
    let h = exact
        .iter()
        .zip(re.iter().zip(&im))
        .map(|(h, (a, b))| h + h.norm() * Complex64::new(*a, *b))
        .collect();
    let frf = FrequencyResponseEstimate::new(frequency_hz.to_vec(), h)?;
    if relative_noise == 0.0 {
        return Ok(frf);
    }
    let variance = exact
        .iter()
        .map(|h| (relative_noise * h.norm()).powi(2))
        .collect();
    Ok(frf.with_variance(variance)?)
}
