//! The paper's setup (no `[setup]`: a force on the mass, one displacement channel):
//! [`msd_ident::predicted_uncertainty`] and msd-ident's `estimate` for the check.

use super::search::{Widths, draws, duration_needed, longest_record, standard_deviations};
use super::{Correlation, NAMES, Plan, PlanOptions, PlannedQuantity, PlannedTest};
use crate::config::{Config, TimeGrid};
use crate::{ExperimentError, Result};
use msd_ident::{Interval, Uncertainty, estimate, predicted_uncertainty};
use std::path::Path;

/// The plan of a config without `[setup]`.
pub(super) fn plan(config: &Config, config_path: &Path, options: &PlanOptions) -> Result<Plan> {
    let (sigma, time) = match (&config.plant, &config.noise, config.time) {
        (Some(_), Some(noise), Some(time)) if noise.sigma > 0.0 => (noise.sigma, time),
        _ => {
            return Err(ExperimentError::config(
                config_path,
                "plan needs a synthetic config: [plant] (the prior guess of the plant), [time], [identification.input] and [noise] with sigma > 0",
            ));
        }
    };
    let (uncertainty, record) = predict(config, config_path)?;
    let now = widths(&uncertainty);
    let verified = verify(config, config_path, options)?;
    let mut search = Widths::new(
        |duration| {
            let longer = with_duration(config, time, duration);
            Ok(widths(&predict(&longer, config_path)?.0).to_vec())
        },
        options.progress,
    );
    let longest = longest_record(time.duration, 2.0 * time.samples() as f64);
    let mut quantities = Vec::new();
    for (q, iv) in intervals(&uncertainty).into_iter().enumerate() {
        let longer = |duration| search.width(duration, q);
        quantities.push(PlannedQuantity {
            name: NAMES[q],
            value: iv.value,
            standard_error: iv.standard_error,
            relative_half_width: now[q],
            amplitude_factor: Some(now[q] / options.target),
            duration_needed_s: duration_needed(
                time.duration,
                now[q],
                options.target,
                longest,
                longer,
            )?,
            repeats_needed: None,
            simulated_standard_deviation: verified.as_ref().map(|v| v[q]),
        });
    }
    let samples = record.excitation.samples();
    Ok(Plan {
        name: config.name.clone(),
        test: PlannedTest {
            excitation: "force",
            records: 1,
            samples: record.len(),
            duration_s: record.excitation.dt() * (record.len() - 1) as f64,
            drive: "force",
            peak_drive: samples.iter().fold(0.0, |m, f| m.max(f.abs())),
            drive_unit: "N",
            repeats: "records",
            repeats_planned: 1,
            channels: vec![("displacement".into(), sigma, "m")],
        },
        target: options.target,
        quantities,
        correlation: Correlation {
            names: NAMES[..3].to_vec(),
            matrix: (0..3)
                .map(|r| (0..3).map(|c| uncertainty.correlation[(r, c)]).collect())
                .collect(),
        },
        notes: uncertainty.warnings.clone(),
        verified_with: options.verify,
    })
}

/// The prediction at the config's prior, and the identification record.
fn predict(config: &Config, config_path: &Path) -> Result<(Uncertainty, msd_ident::DataSet)> {
    let (Some(plant), Some(noise)) = (&config.plant, &config.noise) else {
        return Err(ExperimentError::config(
            config_path,
            "plant: missing section",
        ));
    };
    let data = crate::data::load(config, config_path, config.seed)?;
    let u = predicted_uncertainty(
        &plant.parameters(),
        &data.identification.excitation,
        noise.sigma,
        &config.estimation,
    )
    .map_err(|e| ExperimentError::config(config_path, format!("the planned experiment: {e}")))?;
    Ok((u, data.identification))
}

/// The config with its record `duration` s long.
fn with_duration(config: &Config, time: TimeGrid, duration: f64) -> Config {
    let mut c = config.clone();
    c.time = Some(TimeGrid { duration, ..time });
    c
}

fn intervals(u: &Uncertainty) -> [Interval; 5] {
    [
        u.mass,
        u.damping,
        u.stiffness,
        u.natural_frequency_hz,
        u.damping_ratio,
    ]
}

fn widths(u: &Uncertainty) -> [f64; 5] {
    intervals(u).map(|iv| (iv.ci95[1] - iv.value) / iv.value.abs())
}

/// The standard deviations of m, c, k, fn and ζ over `seeds` simulated experiments
/// (seeds 0, 1, …), estimated as the config says.
fn verify(config: &Config, config_path: &Path, options: &PlanOptions) -> Result<Option<Vec<f64>>> {
    if options.verify == 0 {
        return Ok(None);
    }
    let draws = draws(options.verify, "plan --verify", options.progress, |seed| {
        let data = crate::data::load(config, config_path, seed)?;
        let fit = estimate(&data.identification, &config.estimation)
            .map_err(|e| ExperimentError::run("plan --verify", e))?;
        Ok(intervals(&fit.uncertainty).map(|iv| iv.value).to_vec())
    })?;
    Ok(Some(standard_deviations(&draws)))
}
