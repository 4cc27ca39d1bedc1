//! Sobol indices of the mass–spring–damper's scalar quantities of interest.

use crate::{
    error::{McError, Result},
    sobol::{Distribution, SobolOptions, SobolResult, sobol_indices},
};
use msd_ident::{Backend, Excitation, InitialState, Parameters, simulate, simulate_into};
use serde::{Deserialize, Serialize};
use std::cell::RefCell;

/// The quantities of [`msd_sobol`], in order: peak |x| and RMS of x over the record,
/// fn = √(k/m)/2π in Hz, ζ = c/(2√(mk)), and x at the chosen time.
pub const MSD_QUANTITIES: [&str; 5] = ["peak |x|", "rms x", "fn (Hz)", "zeta", "x(t)"];

/// Options of [`msd_sobol`].
///
/// By default m, c, k uniform within ±10 % of θ̂ (the paper's Monte Carlo), x(t) at the
/// nominal response's peak, the exact backend from rest, and [`SobolOptions::default`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MsdSobolOptions {
    /// Half-width p of the uniform ranges, in percent (0 < p < 100). By default 10.
    pub percent: f64,
    /// Time of the "x(t)" quantity (on the grid: the nearest sample). By default `None`:
    /// the time of the nominal response's peak |x|.
    pub time: Option<f64>,
    /// Simulation backend. By default [`Backend::EXACT`].
    pub backend: Backend,
    /// Initial state. By default at rest.
    pub initial_state: InitialState,
    /// Sample size, bootstrap, seed and threads.
    pub sobol: SobolOptions,
}

impl Default for MsdSobolOptions {
    fn default() -> Self {
        Self {
            percent: 10.0,
            time: None,
            backend: Backend::EXACT,
            initial_state: InitialState::REST,
            sobol: SobolOptions::default(),
        }
    }
}

thread_local! {
    static SCRATCH: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
}

/// Sobol indices of [`MSD_QUANTITIES`] with respect to (m, c, k), each uniform within
/// ±p % of `nominal`, for the response to `excitation`.
///
/// ```
/// use msd_ident::{Excitation, Parameters};
/// use msd_mc::{MsdSobolOptions, SobolOptions, msd_sobol};
/// let step = Excitation::from_samples(0.0, 0.01, vec![1.0; 300])?;
/// let options = MsdSobolOptions { sobol: SobolOptions { samples: 200, ..SobolOptions::default() }, ..MsdSobolOptions::default() };
/// let result = msd_sobol(&Parameters::PAPER, &step, &options)?;
/// let fnat = &result.quantities[2]; // fn = √(k/m)/2π does not depend on c
/// assert!(fnat.total[1].estimate.abs() < 1e-12);
/// # Ok::<(), msd_mc::McError>(())
/// ```
pub fn msd_sobol(
    nominal: &Parameters,
    excitation: &Excitation,
    options: &MsdSobolOptions,
) -> Result<SobolResult> {
    let p = options.percent;
    if !(p.is_finite() && p > 0.0 && p < 100.0) {
        return Err(McError::InvalidPercent { percent: p });
    }
    nominal.validate()?;
    options.backend.validate()?;
    let (backend, initial) = (&options.backend, options.initial_state);
    let index = match options.time {
        Some(t) => {
            let position = ((t - excitation.t0()) / excitation.dt()).round();
            if !(position >= 0.0 && position < excitation.len() as f64) {
                return Err(McError::InvalidOption {
                    name: "time",
                    value: t,
                    expected: "a time within the excitation's record",
                });
            }
            position as usize
        }
        None => {
            let x = simulate(nominal, excitation, initial, backend)?;
            peak_index(&x)
        }
    };
    let inputs = nominal.to_array().map(|v| Distribution::Uniform {
        low: v * (1.0 - p / 100.0),
        high: v * (1.0 + p / 100.0),
    });
    let model = |theta: &[f64]| -> Vec<f64> {
        let parameters = Parameters::from_array([theta[0], theta[1], theta[2]]);
        SCRATCH.with_borrow_mut(|x| {
            x.resize(excitation.len(), 0.0);
            if simulate_into(&parameters, excitation, initial, backend, x).is_err() {
                return vec![f64::NAN; MSD_QUANTITIES.len()];
            }
            let peak = x[peak_index(x)].abs();
            let rms = (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt();
            vec![
                peak,
                rms,
                parameters.natural_frequency_hz(),
                parameters.damping_ratio(),
                x[index],
            ]
        })
    };
    sobol_indices(model, &inputs, &MSD_QUANTITIES, &options.sobol)
}

/// Index of the largest |x| (the first, on ties).
fn peak_index(x: &[f64]) -> usize {
    x.iter()
        .enumerate()
        .fold((0, -1.0), |best, (i, v)| {
            if v.abs() > best.1 { (i, v.abs()) } else { best }
        })
        .0
}
