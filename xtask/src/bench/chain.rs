//! The rows of chains of masses (issue 33: a 3-mass chain, 3 channels × 10,000 samples,
//! fitted in ≤ 50 ms).

use super::harness::{Budget, measure};
use super::report::{Row, Target};
use super::rows::fail;
use crate::Result;
use msd_ident::{
    ResponseQuantity,
    chain::{ChainOptions, ChainParameters, ChainSensor, ChainSetup, fit_chain, simulate_chain},
    records::NoiseModel,
};
use msd_signal::{Recording, gaussian_noise};

/// A 3-mass chain, force on the top mass, accelerometers on all three.
fn three_masses() -> Result<(ChainSetup, Recording, ChainParameters)> {
    let setup = ChainSetup {
        masses: 3,
        force_at: 3,
        sensors: (1..=3)
            .map(|at| ChainSensor {
                at,
                quantity: ResponseQuantity::Acceleration,
                ..ChainSensor::default()
            })
            .collect(),
        ..ChainSetup::default()
    };
    let truth = ChainParameters {
        masses: vec![3.0, 2.0, 1.0],
        dampers: vec![6.0, 4.0, 2.0],
        springs: vec![3e4, 2e4, 1e4],
        ..ChainParameters::default()
    };
    let n = 10_000;
    let input = gaussian_noise(1, "chain/force", 1.0, n)
        .map_err(fail::<msd_signal::SignalError>("bench: chain force"))?;
    let clean = simulate_chain(&setup, &truth, &input, 2e-3).map_err(fail("bench: chain"))?;
    let mut outputs = Vec::new();
    for (j, y) in clean.iter().enumerate() {
        let e = gaussian_noise(1, &format!("chain/{j}"), 0.02, n).map_err(fail::<
            msd_signal::SignalError,
        >(
            "bench: noise"
        ))?;
        outputs.push(y.iter().zip(e).map(|(a, b)| a + b).collect());
    }
    let guess = ChainParameters {
        masses: vec![3.3, 1.8, 1.1],
        dampers: vec![5.0, 5.0, 2.5],
        springs: vec![3.3e4, 1.8e4, 1.1e4],
        ..ChainParameters::default()
    };
    let record = setup.recording("three masses", 2e-3, input, outputs);
    Ok((setup, record, guess))
}

/// The fit and one simulation of the 3-mass chain.
pub fn chain_rows(budget: &Budget) -> Result<Vec<Row>> {
    let (setup, record, guess) = three_masses()?;
    let options = ChainOptions::default();
    let fit = fit_chain(&setup, &record, &guess, &options).map_err(fail("bench: chain fit"))?;
    let white = ChainOptions {
        noise_model: NoiseModel::White,
        ..options.clone()
    };
    let treated = measure(budget, || fit_chain(&setup, &record, &guess, &options).ok());
    let white_fit = measure(budget, || fit_chain(&setup, &record, &guess, &white).ok());
    let ratio = treated.median() / white_fit.median();
    Ok(vec![
        Row::new(
            "chain",
            "3-mass chain: fit of m, c, k (9) from 3 accelerometers × 10,000 samples, the drive's noise model",
            treated,
        )
        .target(Target::Seconds(50e-3))
        .note(format!(
            "{} model evaluations; {ratio:.2}× the white-noise fit (issue 42: ≤ 3×)",
            fit.evaluations
        )),
        Row::new(
            "chain",
            "3-mass chain: the same fit, white-noise model (the drive taken as exact)",
            white_fit,
        )
        .target(Target::Seconds(50e-3)),
        Row::new(
            "chain",
            "3-mass chain: one exact simulation, 3 channels × 10,000 samples",
            measure(budget, || {
                simulate_chain(&setup, &fit.parameters, record.input(), record.dt).ok()
            }),
        ),
    ])
}
