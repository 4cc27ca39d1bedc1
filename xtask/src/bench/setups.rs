//! The rows of the measurement setups beyond a force and a displacement: free decay,
//! base excitation, and the plan of a test (issue 20's target: each setup's fast
//! identification of 7501 samples ≤ 5 ms).

use super::harness::{Budget, measure};
use super::report::{Row, Target};
use super::rows::fail;
use crate::Result;
use msd_ident::{
    Backend, BaseExcitationOptions, DataSet, EstimationOptions, Excitation, FreeDecayOptions,
    InitialState, KnownParameter, PaperExperiment, Parameters, base_excitation, free_decay,
    predicted_uncertainty, simulate,
};

/// Free decay, base excitation and the Cramér–Rao plan on records of the paper's length.
pub fn setups(budget: &Budget, experiment: &PaperExperiment) -> Result<Vec<Row>> {
    let p = Parameters::PAPER;
    let dt = PaperExperiment::DT;
    // The paper's plant released from 10 mm, 7501 samples, noise from the paper's stream.
    let (s, wd) = (
        p.damping_ratio() * p.natural_frequency(),
        p.natural_frequency() * (1.0 - p.damping_ratio().powi(2)).sqrt(),
    );
    let noise = &experiment.identification.output;
    let clean = &experiment.identification_truth;
    let decay: Vec<f64> = (0..PaperExperiment::SAMPLES)
        .map(|i| {
            let t = i as f64 * dt;
            0.01 * (-s * t).exp() * ((wd * t).cos() + s / wd * (wd * t).sin())
                + 0.1 * (noise[i] - clean[i])
        })
        .collect();
    let options = FreeDecayOptions {
        known: KnownParameter::Mass(p.mass),
        ..FreeDecayOptions::default()
    };
    free_decay(dt, &decay, &options).map_err(fail("bench: free decay"))?;
    // The paper's plant on a table whose acceleration is the paper's input.
    let base = experiment.identification.excitation.clone();
    let force = base.samples().iter().map(|a| -p.mass * a).collect();
    let force = Excitation::from_samples(0.0, dt, force).map_err(fail("bench: base excitation"))?;
    let y = simulate(&p, &force, InitialState::REST, &Backend::EXACT)
        .map_err(fail("bench: base excitation"))?;
    let y: Vec<f64> = y
        .iter()
        .zip(noise)
        .zip(clean)
        .map(|((y, n), c)| y + (n - c))
        .collect();
    let table = DataSet::new("table", base, y).map_err(fail("bench: base excitation"))?;
    let known = BaseExcitationOptions {
        known_mass: Some(p.mass),
        ..BaseExcitationOptions::default()
    };
    base_excitation(&table, &known).map_err(fail("bench: base excitation"))?;
    let input = &experiment.identification.excitation;
    let plan_options = EstimationOptions::default();
    Ok(vec![
        Row::new(
            "setups",
            "free decay (closed form, LM), 7501 samples",
            measure(budget, || free_decay(dt, &decay, &options).ok()),
        )
        .target(Target::Seconds(5e-3)),
        Row::new(
            "setups",
            "base excitation (unit-mass LM + exact), 7501 samples",
            measure(budget, || base_excitation(&table, &known).ok()),
        )
        .target(Target::Seconds(5e-3)),
        Row::new(
            "setups",
            "plan: Cramér–Rao prediction of the paper's record",
            measure(budget, || {
                predicted_uncertainty(&p, input, PaperExperiment::SIGMA, &plan_options).ok()
            }),
        ),
    ])
}
