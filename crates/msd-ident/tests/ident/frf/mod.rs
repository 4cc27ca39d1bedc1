//! Fitting frequency responses: one mode from a noisy stepped sine (intervals and their
//! coverage), an impact test with an exponential window, several modes.

mod beam;
mod impact;
mod modes;
mod one_mode;
mod real_hammer;

use msd_signal::{Complex64, FrequencyResponseEstimate};

/// A measured table of `h` at `frequency` (Hz).
pub fn table(frequency: &[f64], h: Vec<Complex64>) -> FrequencyResponseEstimate {
    FrequencyResponseEstimate::new(frequency.to_vec(), h).expect("valid table")
}
