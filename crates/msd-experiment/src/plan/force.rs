//! The paper's setup (no `[setup]`: a force on the mass, one displacement channel):
//! [`msd_ident::predicted_uncertainty`] and msd-ident's `estimate` for the check.

use super::search::{Widths, draws, duration_needed, longest_record, standard_deviations};
use super::{Correlation, NAMES, Plan, PlanOptions, PlannedQuantity, PlannedTest};
use crate::config::{Config, TimeGrid};
use crate::error::{ExperimentError, Result};
use msd_ident::{Excitation, Interval, PlannedInformation, Uncertainty, estimate};
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
    let (information, excitation) = predict(config, config_path)?;
    let uncertainty = information
        .uncertainty(sigma)
        .map_err(|e| planned(config_path, e))?;
    let now = widths(&uncertainty);
    let verified = verify(config, config_path, options)?;
    // Only a search for a longer record needs to know how the information grows.
    let steady = match now.iter().any(|w| *w > options.target) {
        true => steady_growth(config, config_path, time, (&information, &excitation))?,
        false => None,
    };
    let mut search = Widths::new(
        |duration| {
            let longer = with_duration(config, time, duration);
            let information = match &steady {
                Some(later) => {
                    let samples = longer.time.map_or(0, |t| t.samples());
                    information.extrapolated(later, samples)
                }
                None => predict(&longer, config_path)?.0,
            };
            let u = information
                .uncertainty(sigma)
                .map_err(|e| planned(config_path, e))?;
            Ok(widths(&u).to_vec())
        },
        options.progress,
    );
    // Extrapolated lengths hold nothing in memory: only the planned record's 64× bounds
    // them.
    let longest = match steady {
        Some(_) => 64.0 * time.duration,
        None => longest_record(time.duration, 2.0 * time.samples() as f64),
    };
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
            coverage: None,
        });
    }
    let samples = excitation.samples();
    Ok(Plan {
        name: config.name.clone(),
        test: PlannedTest {
            excitation: "force",
            records: 1,
            samples: excitation.len(),
            duration_s: excitation.dt() * (excitation.len() - 1) as f64,
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

/// The information of the identification record at the config's prior, and its input.
fn predict(config: &Config, config_path: &Path) -> Result<(PlannedInformation, Excitation)> {
    let Some(plant) = &config.plant else {
        return Err(ExperimentError::config(
            config_path,
            "plant: missing section",
        ));
    };
    let excitation = crate::data::identification_excitation(config, config_path)?;
    let information = PlannedInformation::new(&plant.parameters(), &excitation, &config.estimation)
        .map_err(|e| planned(config_path, e))?;
    Ok((information, excitation))
}

/// The information of the record lengthened by a quarter and by half. Where the input
/// does not depend on the record's length (its samples on the record lengthened by half
/// begin with the record's own), both come from one simulation of the longer (the
/// quarter its first rows: it differs from its own record only by the input's
/// interpolation at the end, far below [`STEADY`] on records long enough to need it);
/// otherwise each is simulated.
fn lengthened(
    config: &Config,
    config_path: &Path,
    time: TimeGrid,
    excitation: &Excitation,
) -> Result<[PlannedInformation; 2]> {
    let longer = |factor: f64| with_duration(config, time, factor * time.duration);
    let samples = |factor: f64| longer(factor).time.map_or(0, |t| t.samples());
    let (quarter, half) = (samples(1.25), samples(1.5));
    let longest = crate::data::identification_excitation(&longer(1.5), config_path)?;
    let n = excitation.len();
    let repeats_the_record = longest.t0() == excitation.t0()
        && longest.dt() == excitation.dt()
        && quarter > n
        && longest.len() == half
        && longest.samples()[..n] == *excitation.samples();
    match (&config.plant, repeats_the_record) {
        (Some(plant), true) => PlannedInformation::prefixes(
            &plant.parameters(),
            &longest,
            &config.estimation,
            [quarter, half],
        )
        .map_err(|e| planned(config_path, e)),
        _ => Ok([
            predict(&longer(1.25), config_path)?.0,
            predict(&longer(1.5), config_path)?.0,
        ]),
    }
}

/// A prediction's error, as the config's.
fn planned(config_path: &Path, e: msd_ident::IdentError) -> ExperimentError {
    ExperimentError::config(config_path, format!("the planned experiment: {e}"))
}

/// The information of the record lengthened by half, when what a longer record adds
/// grows in proportion to its length: the information added by the first quarter is
/// half that of the first half, sample for sample, to [`STEADY`] (the input repeats itself
/// beyond the record, periodic or constant, and the response is in steady state).
/// Longer records then follow from it without simulating them
/// ([`PlannedInformation::extrapolated`]); otherwise `None`, and each is simulated.
fn steady_growth(
    config: &Config,
    config_path: &Path,
    time: TimeGrid,
    (information, excitation): (&PlannedInformation, &Excitation),
) -> Result<Option<PlannedInformation>> {
    let [quarter, half] = lengthened(config, config_path, time, excitation)?;
    let rate = |later: &PlannedInformation| {
        let added = (later.samples - information.samples) as f64;
        (&later.normal - &information.normal) / added
    };
    let (early, whole) = (rate(&quarter), rate(&half));
    // On the scale of the record's own information per sample (a quantity the added
    // stretch says nothing more about, such as m under a constant force, has rate 0).
    let per_sample = &information.normal / information.samples as f64;
    let p = whole.nrows();
    let steady = (0..p).all(|i| {
        (0..p).all(|j| {
            let scale = (per_sample[(i, i)] * per_sample[(j, j)]).sqrt();
            (early[(i, j)] - whole[(i, j)]).abs() <= STEADY * scale
        })
    });
    Ok(steady.then_some(half))
}

/// How far the rates of information over the added quarter and the added half may
/// differ, relative to the record's own rate, for the growth to count as steady: the
/// extrapolated information is then within 1e-4 of the truth at any length, a standard
/// error within 5e-5. It passes the stretches' partial periods (the paper's 1.4 Hz sine
/// over 500 s stretches: 1.4e-6) and fails a transient or a sweep that has not ended.
const STEADY: f64 = 1e-4;

/// The config with its record `duration` s long.
pub(super) fn with_duration(config: &Config, time: TimeGrid, duration: f64) -> Config {
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
