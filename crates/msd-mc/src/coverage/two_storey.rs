//! The study's chain: `configs/two-storey.toml` with a noisy load cell.

use super::{CoverageOptions, SeedFit};
use crate::error::Result;
use msd_ident::chain::{
    ChainOptions, ChainParameters, ChainSensor, ChainSetup, fit_chain, simulate_chain,
};
use msd_ident::{IdentError, ResponseQuantity};
use msd_signal::{Multisine, MultisineSpec, PhaseScheme, Signal, gaussian_noise};

/// The sampling interval, s, and the record's length.
const DT: f64 = 2e-3;
const SAMPLES: usize = 5000;
/// The force's rms, N, and each accelerometer's noise, m/s².
const FORCE_RMS: f64 = 2.0;
const SENSOR_SIGMA: f64 = 0.02;

fn setup() -> ChainSetup {
    let accelerometer = |at| ChainSensor {
        at,
        quantity: ResponseQuantity::Acceleration,
        ..ChainSensor::default()
    };
    ChainSetup {
        masses: 2,
        force_at: 2,
        sensors: vec![accelerometer(1), accelerometer(2)],
        ..ChainSetup::default()
    }
}

/// The chain's truth.
pub(super) fn truth() -> ChainParameters {
    ChainParameters {
        masses: vec![2.0, 1.5],
        dampers: vec![3.0, 2.0],
        springs: vec![8000.0, 6000.0],
        ..ChainParameters::default()
    }
}

/// One seed: the record simulated and fitted from the config's guess.
pub(super) fn fit_seed(options: &CoverageOptions, seed: u64) -> Result<SeedFit> {
    let setup = setup();
    let truth = truth();
    let spec = MultisineSpec {
        base_frequency: 0.1,
        f_min: 0.1,
        f_max: 40.0,
        rms: FORCE_RMS,
        phases: PhaseScheme::Random,
        seed,
        ..MultisineSpec::default()
    };
    let signal = Signal::Multisine(Multisine::new(spec).map_err(IdentError::from)?);
    let exact = signal.sample(0.0, DT, SAMPLES);
    let clean = simulate_chain(&setup, &truth, &exact, DT)?;
    let mut outputs = Vec::new();
    for (i, y) in clean.iter().enumerate() {
        let noise = gaussian_noise(seed, &format!("floor {}", i + 1), SENSOR_SIGMA, SAMPLES)
            .map_err(IdentError::from)?;
        outputs.push(y.iter().zip(&noise).map(|(y, e)| y + e).collect());
    }
    let drive_noise = gaussian_noise(seed, "force", options.drive_noise * FORCE_RMS, SAMPLES)
        .map_err(IdentError::from)?;
    let input = exact.iter().zip(&drive_noise).map(|(u, e)| u + e).collect();
    let record = setup.recording(format!("seed {seed}"), DT, input, outputs);
    let guess = ChainParameters {
        masses: vec![2.5, 1.2],
        dampers: vec![2.0, 3.0],
        springs: vec![10000.0, 5000.0],
        ..ChainParameters::default()
    };
    let fit_options = ChainOptions {
        noise_model: options.noise_model,
        ..ChainOptions::default()
    };
    let fit = fit_chain(&setup, &record, &guess, &fit_options)?;
    let mut quantities = Vec::new();
    if let Some(iv) = &fit.uncertainty.intervals {
        for (family, values, truths) in [
            ("m", &iv.masses, &truth.masses),
            ("c", &iv.dampers, &truth.dampers),
            ("k", &iv.springs, &truth.springs),
        ] {
            for (i, (iv, t)) in values.iter().zip(truths).enumerate() {
                quantities.push((format!("{family}{}", i + 1), *t, *iv));
            }
        }
    }
    for (i, (mode, true_mode)) in fit.uncertainty.modes.iter().zip(truth.modes()).enumerate() {
        let (f, z) = (&true_mode.natural_frequency_hz, &true_mode.damping_ratio);
        quantities.push((format!("fn{}", i + 1), f.value, mode.natural_frequency_hz));
        quantities.push((format!("zeta{}", i + 1), z.value, mode.damping_ratio));
    }
    Ok(SeedFit {
        quantities,
        noise_model: fit.noise_model,
        whiteness: fit.whiteness,
    })
}
