//! A damper test machine (`setup.excitation = "imposed_displacement"`): the
//! coefficients of the prior plant's damping law, predicted by
//! [`msd_ident::dynamometer::predicted_dynamometer`] on the planned strokes; the check runs the
//! machine's analysis on simulated conditions as the run does.

use super::search::{repeats_needed, standard_deviations};
use super::{Correlation, Plan, PlanOptions, PlannedQuantity, PlannedTest};
use crate::config::{Config, Plant, SetupSection};
use crate::error::{ExperimentError, Result};
use crate::setup::{data, fit, machine};
use msd_ident::{
    dynamometer::{
        Condition, DynamometerNoise, DynamometerOptions, PredictedLaw, dynamometer,
        predicted_dynamometer,
    },
    law::DampingLaw,
};
use std::path::Path;

/// The plan of a test machine's config.
pub(super) fn plan(config: &Config, path: &Path, options: &PlanOptions) -> Result<Plan> {
    let (setup, plant) = synthetic(config, path)?;
    let law = plant_law(&plant);
    let machine_options = DynamometerOptions {
        laws: vec![law],
        ..fit::machine_options(setup)
    };
    let noise = noise(config, path, setup)?;
    let conditions = planned_conditions(config, path, setup, &plant, setup.cycles)?;
    let fit = predict(&conditions, &noise, &machine_options, path)?;
    let verified = verify(config, setup, law, &fit.names, options)?;
    let quantities = fit
        .names
        .iter()
        .zip(&fit.coefficients)
        .enumerate()
        .map(|(j, (name, iv))| {
            // The prior plant has no load-cell offset: F₀ = 0 has no relative width.
            let value = if *name == "force_offset" {
                0.0
            } else {
                iv.value
            };
            let w = (iv.ci95[1] - iv.value) / value.abs();
            PlannedQuantity {
                name,
                value,
                standard_error: iv.standard_error,
                relative_half_width: w,
                amplitude_factor: None,
                duration_needed_s: None,
                repeats_needed: repeats_needed(setup.cycles, w, options.target)
                    .map(|n| n.max(msd_ident::dynamometer::MIN_CYCLES)),
                simulated_standard_deviation: verified.as_ref().map(|v| v[j]),
                coverage: None,
            }
        })
        .collect();
    let samples: usize = conditions.iter().map(|c| c.force().len()).sum();
    let mut notes = vec![format!(
        "the {law:?} law of [plant] planned; the run compares it with the other laws by BIC"
    )];
    if plant.cubic_stiffness != 0.0 {
        notes.push("the plant's cubic stiffness is in no damping law: the prediction leaves out the bias it causes".into());
    }
    Ok(Plan {
        name: config.name.clone(),
        test: PlannedTest {
            excitation: setup.excitation.name(),
            records: conditions.len(),
            samples,
            duration_s: samples as f64 * conditions.first().map_or(0.0, Condition::dt),
            drive: "stroke",
            peak_drive: setup.conditions.iter().fold(0.0, |m, c| m.max(c.amplitude)),
            drive_unit: "m",
            repeats: "cycles",
            repeats_planned: setup.cycles,
            channels: vec![
                ("force".into(), noise.force_sigma, "N"),
                ("stroke".into(), noise.stroke_sigma, "m"),
            ],
        },
        target: options.target,
        quantities,
        correlation: correlation(&fit),
        notes,
        verified_with: options.verify,
    })
}

/// The setup and the prior plant, refusing a measured config.
fn synthetic<'a>(config: &'a Config, path: &Path) -> Result<(&'a SetupSection, Plant)> {
    let plant = config.plant.filter(|_| config.data.is_none());
    match (&config.setup, plant) {
        (Some(setup), Some(plant)) => Ok((setup, plant)),
        _ => Err(ExperimentError::config(
            path,
            "plant: missing: plan needs the synthetic test ([plant], the prior guess of the damper, and setup.conditions); a measured config (with [data]) has no prior to plan from",
        )),
    }
}

/// The damping law of the prior plant (its nonlinear model's, as the run simulates it).
fn plant_law(plant: &Plant) -> DampingLaw {
    plant
        .nonlinear()
        .map_or(DampingLaw::Viscous, |n| n.structure.damping)
}

/// The load cell's σ (the response's) and the stroke sensor's (`setup.input_sigma`).
fn noise(config: &Config, path: &Path, setup: &SetupSection) -> Result<DynamometerNoise> {
    let force_sigma = data::channel_sigmas(config, &setup.channels())[0];
    if !(force_sigma.is_finite() && force_sigma > 0.0) {
        return Err(ExperimentError::config(
            path,
            format!(
                "setup.responses[0].sigma = {force_sigma}: plan needs the load cell's noise level > 0"
            ),
        ));
    }
    Ok(DynamometerNoise {
        force_sigma,
        stroke_sigma: setup.input_sigma,
    })
}

/// The noise-free conditions the run would simulate, with `cycles` each.
fn planned_conditions(
    config: &Config,
    path: &Path,
    setup: &SetupSection,
    plant: &Plant,
    cycles: usize,
) -> Result<Vec<Condition>> {
    let dt = config
        .time
        .map(|t| t.dt)
        .ok_or_else(|| ExperimentError::config(path, "time: missing section"))?;
    let mut conditions = Vec::with_capacity(setup.conditions.len());
    for (i, c) in setup.conditions.iter().enumerate() {
        let clean = machine::stroke_record(plant, c, cycles, dt)
            .map_err(|e| ExperimentError::config(path, format!("setup.conditions[{i}]: {e}")))?;
        let stroke = clean.input.unwrap_or_default();
        let force = clean.channels.into_iter().next().unwrap_or_default();
        let name = format!("condition-{}", i + 1);
        conditions.push(Condition::new(name, dt, stroke, force).at_frequency(c.frequency));
    }
    Ok(conditions)
}

/// The law's predicted fit.
fn predict(
    conditions: &[Condition],
    noise: &DynamometerNoise,
    options: &DynamometerOptions,
    path: &Path,
) -> Result<PredictedLaw> {
    let fits = predicted_dynamometer(conditions, noise, options)
        .map_err(|e| ExperimentError::config(path, format!("the planned experiment: {e}")))?;
    fits.into_iter()
        .next()
        .ok_or_else(|| ExperimentError::run("plan", "no damping law was fitted"))
}

fn correlation(fit: &PredictedLaw) -> Correlation {
    let c = fit.correlation();
    Correlation {
        names: fit.names.clone(),
        matrix: c.row_iter().map(|r| r.iter().copied().collect()).collect(),
    }
}

/// The standard deviations of `law`'s coefficients `names` over `seeds` simulated runs
/// (seeds 0, 1, …), each analysed as the run analyses it (every law, the same options).
fn verify(
    config: &Config,
    setup: &SetupSection,
    law: DampingLaw,
    names: &[&str],
    plan: &PlanOptions,
) -> Result<Option<Vec<f64>>> {
    if plan.verify == 0 {
        return Ok(None);
    }
    let options = fit::machine_options(setup);
    let draws = super::search::draws(plan.verify, "plan --verify", plan.progress, |seed| {
        let conditions = fit::machine_conditions(&data::load(config, setup, seed)?);
        let result = dynamometer(&conditions, &options)
            .map_err(|e| ExperimentError::run("plan --verify", format!("seed {seed}: {e}")))?;
        let values = names
            .iter()
            .map(|n| {
                result
                    .law(law)
                    .and_then(|f| f.coefficient(n))
                    .map(|c| c.value)
                    .ok_or_else(|| {
                        ExperimentError::run(
                            "plan --verify",
                            format!("seed {seed}: the {law:?} law's {n} was not estimated"),
                        )
                    })
            })
            .collect::<Result<Vec<f64>>>()?;
        Ok(values)
    })?;
    Ok(Some(standard_deviations(&draws)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whole cycles add information in proportion: twice the cycles, the standard
    /// errors over √2 (exactly when every period is a whole number of samples, as here).
    #[test]
    fn errors_scale_as_one_over_the_root_of_the_cycles() {
        let path = std::path::PathBuf::from("../../configs/damper-test-machine.toml");
        let config = Config::load(&path).unwrap();
        let (setup, plant) = synthetic(&config, &path).unwrap();
        let options = DynamometerOptions {
            laws: vec![plant_law(&plant)],
            ..fit::machine_options(setup)
        };
        let noise = noise(&config, &path, setup).unwrap();
        let at = |cycles| {
            let conditions = planned_conditions(&config, &path, setup, &plant, cycles).unwrap();
            predict(&conditions, &noise, &options, &path).unwrap()
        };
        let (five, ten) = (at(5), at(10));
        for (a, b) in five.coefficients.iter().zip(&ten.coefficients) {
            let ratio = b.standard_error / a.standard_error;
            assert!((ratio * 2f64.sqrt() - 1.0).abs() < 1e-9, "{ratio}");
        }
    }
}
