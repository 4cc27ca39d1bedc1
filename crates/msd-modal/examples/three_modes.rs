//! Three modes (10, 23 and 41 Hz; ζ 1 %, 2 %, 0.5 %) in a frequency response of 2000
//! lines with 1 % noise: the stabilization diagram, the automatic selection, the polished
//! modes with 95 % intervals, and the MAC of the fit's modal constants.
//!
//! `cargo run -p msd-modal --example three_modes`

use msd_modal::{ModalOptions, ModalParameters, fit_modes, synthetic_frequency_response};

fn main() -> Result<(), msd_modal::ModalError> {
    let truth = [(10.0, 0.01, 1.0), (23.0, 0.02, -0.6), (41.0, 0.005, 0.4)].map(|(f, z, a)| {
        ModalParameters {
            natural_frequency_hz: f,
            damping_ratio: z,
            modal_constant: a,
            modal_constant_imaginary: 0.0,
        }
    });
    let f: Vec<f64> = (1..=2000).map(|i| 0.025 * i as f64).collect();
    let frf =
        synthetic_frequency_response(&f, 0.01, 1, |f| truth.iter().map(|m| m.receptance(f)).sum())?;
    let fit = fit_modes(&frf, &ModalOptions::default())?;
    println!("{fit}");
    for (mode, true_mode) in fit.modes.iter().zip(&truth) {
        println!(
            "{:.3} Hz: true fn inside its interval: {}, true ζ inside: {}",
            true_mode.natural_frequency_hz,
            mode.natural_frequency_hz
                .contains(true_mode.natural_frequency_hz),
            mode.damping_ratio.contains(true_mode.damping_ratio)
        );
    }
    Ok(())
}
