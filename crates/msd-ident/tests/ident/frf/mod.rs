//! Fitting frequency responses: one mode from a noisy stepped sine (intervals and their
//! coverage), an impact test with an exponential window, several modes.

mod impact;
mod modes;
mod one_mode;

use msd_signal::{Complex64, FrequencyResponseEstimate, gaussian_noise};

/// `h` with complex Gaussian noise of relative size `relative` (E|e|² = relative²·|H|²:
/// each part has std relative·|H|/√2), from `seed`.
pub fn with_noise(h: &[Complex64], relative: f64, seed: u64) -> Vec<Complex64> {
    let n = h.len();
    let s = relative / std::f64::consts::SQRT_2;
    let re = gaussian_noise(seed, "frf.noise.re", s, n).expect("valid");
    let im = gaussian_noise(seed, "frf.noise.im", s, n).expect("valid");
    h.iter()
        .zip(re.iter().zip(&im))
        .map(|(h, (a, b))| h + h.norm() * Complex64::new(*a, *b))
        .collect()
}

/// A measured table of `h` at `frequency` (Hz).
pub fn table(frequency: &[f64], h: Vec<Complex64>) -> FrequencyResponseEstimate {
    FrequencyResponseEstimate::new(frequency.to_vec(), h).expect("valid table")
}
