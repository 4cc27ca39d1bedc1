//! The frequency-domain row: a three-mode fit (issue 21's speed target, ≤ 20 ms).

use super::harness::{Budget, measure};
use super::report::{Row, Target};
use super::rows::fail;
use crate::Result;
use msd_ident::{
    ModalOptions, fit_modes,
    frf::{FrfWeighting, ModalParameters, synthetic_frequency_response},
};

/// Three modes (fn 10, 23, 41 Hz; ζ 1 %, 2 %, 0.5 %) in 2000 lines with 1 % noise:
/// the stabilization diagram over orders 2–40 and the polish of every modal parameter
/// (msd-ident's criterion bench `frf` measures the same).
pub fn frequency_domain(budget: &Budget) -> Result<Vec<Row>> {
    let modes = [(10.0, 0.01, 1.0), (23.0, 0.02, -0.6), (41.0, 0.005, 0.4)].map(|(f, z, a)| {
        ModalParameters {
            natural_frequency_hz: f,
            damping_ratio: z,
            modal_constant: a,
            modal_constant_imaginary: 0.0,
        }
    });
    let f: Vec<f64> = (1..=2000).map(|i| 0.025 * i as f64).collect();
    let frf =
        synthetic_frequency_response(&f, 0.01, 1, |f| modes.iter().map(|m| m.receptance(f)).sum())
            .map_err(fail("bench: frequency response"))?;
    let options = ModalOptions {
        weighting: FrfWeighting::Relative,
        ..ModalOptions::default()
    };
    let fit = fit_modes(&frf, &options).map_err(fail("bench: modal fit"))?;
    let samples = measure(budget, || fit_modes(&frf, &options).ok());
    Ok(vec![
        Row::new(
            "frequency domain",
            "three modes, 2000 lines: stabilization diagram orders 2–40 + polish",
            samples,
        )
        .target(Target::Seconds(20e-3))
        .note(format!(
            "{} modes found, {} iterations",
            fit.modes.len(),
            fit.iterations
        )),
    ])
}
