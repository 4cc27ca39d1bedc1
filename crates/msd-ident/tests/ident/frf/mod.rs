//! Fitting frequency responses as the one-mass plant: one mode from a noisy stepped sine
//! (intervals and their coverage), an impact test with an exponential window. The modal
//! fits are tested in msd-modal.

mod impact;
mod noisy_peak;
mod one_mode;

use msd_signal::{Complex64, FrequencyResponseEstimate};

/// A measured table of `h` at `frequency` (Hz).
pub fn table(frequency: &[f64], h: Vec<Complex64>) -> FrequencyResponseEstimate {
    FrequencyResponseEstimate::new(frequency.to_vec(), h).expect("valid table")
}
