//! A `[setup]` config (any drive, several channels and records):
//! [`msd_ident::records::predicted_records_uncertainty`] on the records the run would simulate,
//! and for the check the run's own joint fit of simulated records.

use super::search::{
    Widths, draws, duration_needed, longest_record, repeats_needed, standard_deviations,
};
use super::{Correlation, NAMES, Plan, PlanOptions, PlannedQuantity, PlannedTest};
use crate::config::{Config, ExcitationKind, SetupSection, TimeGrid};
use crate::error::{ExperimentError, Result};
use crate::setup::{data, fit};
use msd_ident::{
    Excitation, InitialState, Interval, RecordsOptions, fit_records,
    records::{PlannedChannel, PlannedRecord, PlantIntervals, predicted_records_uncertainty},
};
use std::path::Path;

/// What the plan of a `[setup]` config needs from it.
struct Planned<'a> {
    config: &'a Config,
    path: &'a Path,
    setup: &'a SetupSection,
    plant: msd_ident::Parameters,
    initial_state: InitialState,
    time: TimeGrid,
    channels: Vec<PlannedChannel>,
    options: RecordsOptions,
}

/// The plan of a config with a `[setup]` (not a test machine).
pub(super) fn plan(config: &Config, path: &Path, options: &PlanOptions) -> Result<Plan> {
    let p = Planned::new(config, path)?;
    let now = p.predict(p.time.duration, 1.0)?;
    let names = estimated(&now);
    let widths = |u: &PlantIntervals| names.iter().map(|n| width(u, n)).collect::<Vec<_>>();
    let verified = verify(&p, &names, options)?;
    let mut search = Widths::new(
        |duration| Ok(widths(&p.predict(duration, 1.0)?)),
        options.progress,
    );
    let samples = crate::budget::samples_per_experiment(p.config);
    let longest = longest_record(p.time.duration, samples);
    let mut quantities = Vec::with_capacity(names.len());
    for (q, name) in names.iter().enumerate() {
        let iv = interval(&now, name).unwrap_or(ZERO);
        let w = width(&now, name);
        let longer = |duration| search.width(duration, q);
        quantities.push(PlannedQuantity {
            name,
            value: iv.value,
            standard_error: iv.standard_error,
            relative_half_width: w,
            amplitude_factor: Some(w / options.target),
            duration_needed_s: duration_needed(
                p.time.duration,
                w,
                options.target,
                longest,
                longer,
            )?,
            repeats_needed: repeats_needed(p.setup.records, w, options.target),
            simulated_standard_deviation: verified.as_ref().map(|v| v[q]),
            coverage: None,
        });
    }
    Ok(Plan {
        name: config.name.clone(),
        test: p.test(),
        target: options.target,
        quantities,
        correlation: correlation(&now, &names),
        notes: p.notes(&now),
        verified_with: options.verify,
    })
}

const ZERO: Interval = Interval {
    value: 0.0,
    standard_error: 0.0,
    ci95: [0.0, 0.0],
};

impl<'a> Planned<'a> {
    /// Reads what the plan needs, refusing a measured config and a channel without noise.
    fn new(config: &'a Config, path: &'a Path) -> Result<Self> {
        let missing = |key: &str, what: &str| {
            ExperimentError::config(
                path,
                format!(
                    "{key}: missing: plan needs the synthetic test ({what}); a measured config (with [data]) has no prior to plan from"
                ),
            )
        };
        let setup = config
            .setup
            .as_ref()
            .ok_or_else(|| missing("setup", "[setup]"))?;
        let plant = config
            .plant
            .filter(|_| config.data.is_none())
            .ok_or_else(|| missing("plant", "[plant], the prior guess of the rig"))?;
        let time = config.time.ok_or_else(|| missing("time", "[time]"))?;
        let responses = setup.channels();
        let sigmas = data::channel_sigmas(config, &responses);
        if let Some(i) = sigmas.iter().position(|s| !(s.is_finite() && *s > 0.0)) {
            return Err(ExperimentError::config(
                path,
                format!(
                    "setup.responses[{i}].sigma = {}: plan needs each channel's noise level > 0 (its own sigma or [noise] sigma)",
                    sigmas[i]
                ),
            ));
        }
        let channels = responses
            .iter()
            .zip(&sigmas)
            .map(|(r, &sigma)| PlannedChannel {
                name: r.channel_name(),
                quantity: fit::sensor(r).0,
                frame: r.frame,
                sigma,
            })
            .collect();
        Ok(Self {
            config,
            path,
            setup,
            plant: plant.parameters(),
            initial_state: plant.initial_state,
            time,
            channels,
            options: fit::records_options(config, setup),
        })
    }

    /// The prediction of records `duration` s long, the drive and the initial state
    /// scaled by `amplitude`.
    fn predict(&self, duration: f64, amplitude: f64) -> Result<PlantIntervals> {
        let records = self.records(duration, amplitude)?;
        predicted_records_uncertainty(&self.plant, &records, &self.options)
            .map_err(|e| ExperimentError::config(self.path, format!("the planned experiment: {e}")))
    }

    /// The records the run would simulate (`setup.records` of them), without noise.
    fn records(&self, duration: f64, amplitude: f64) -> Result<Vec<PlannedRecord>> {
        let mut config = self.config.clone();
        let time = TimeGrid {
            duration,
            ..self.time
        };
        config.time = Some(time);
        let drive = match crate::data::synthetic_input(&config, self.path)? {
            Some(x) => x.samples().iter().map(|u| amplitude * u).collect(),
            None => vec![0.0; time.samples()],
        };
        let excitation = Excitation::from_samples(time.start, time.dt, drive)
            .map_err(|e| ExperimentError::config(self.path, format!("time: {e}")))?;
        let s = self.initial_state;
        let record = |r: usize| PlannedRecord {
            name: format!("record-{}", r + 1),
            excitation: excitation.clone(),
            initial_state: InitialState {
                displacement: amplitude * s.displacement,
                velocity: amplitude * s.velocity,
            },
            channels: self.channels.clone(),
        };
        Ok((0..self.setup.records).map(record).collect())
    }
}

/// The estimated quantities (identifiable, not known), in the order shown.
fn estimated(u: &PlantIntervals) -> Vec<&'static str> {
    let known = |name: &str| interval(u, name).is_some_and(|iv| iv.standard_error == 0.0);
    NAMES
        .into_iter()
        .filter(|n| u.identifiable.contains(n) && !known(n))
        .collect()
}

fn interval(u: &PlantIntervals, name: &str) -> Option<Interval> {
    match name {
        "mass" => u.mass,
        "damping" => u.damping,
        "stiffness" => u.stiffness,
        "natural_frequency_hz" => Some(u.natural_frequency_hz),
        "damping_ratio" => Some(u.damping_ratio),
        _ => None,
    }
}

/// The relative 95 % half-width of `name`.
fn width(u: &PlantIntervals, name: &str) -> f64 {
    interval(u, name).map_or(f64::INFINITY, |iv| (iv.ci95[1] - iv.value) / iv.value.abs())
}

/// The correlation of `names`, from the prediction's (in the order of `identifiable`).
fn correlation(u: &PlantIntervals, names: &[&'static str]) -> Correlation {
    let at = |n: &str| u.identifiable.iter().position(|i| *i == n).unwrap_or(0);
    Correlation {
        names: names.to_vec(),
        matrix: names
            .iter()
            .map(|a| names.iter().map(|b| u.correlation[at(a)][at(b)]).collect())
            .collect(),
    }
}

/// The standard deviations of `names` over `seeds` simulated runs (seeds 0, 1, …), each
/// fitted as the run fits it (without its leave-one-record-out validation, which does
/// not change the estimate).
fn verify(p: &Planned<'_>, names: &[&str], plan: &PlanOptions) -> Result<Option<Vec<f64>>> {
    if plan.verify == 0 {
        return Ok(None);
    }
    let options = RecordsOptions {
        leave_one_out: false,
        hold_out: 0.0,
        ..p.options.clone()
    };
    let draws = draws(plan.verify, "plan --verify", plan.progress, |seed| {
        let loaded = data::load(p.config, p.setup, seed)?;
        let records = fit::ident_records(&loaded.records, loaded.setup.excitation)?;
        let fit = fit_records(&records, &options)
            .map_err(|e| ExperimentError::run("plan --verify", format!("seed {seed}: {e}")))?;
        let values = names
            .iter()
            .map(|n| {
                interval(&fit.plant, n).map(|iv| iv.value).ok_or_else(|| {
                    ExperimentError::run(
                        "plan --verify",
                        format!("seed {seed}: {n} was not estimated"),
                    )
                })
            })
            .collect::<Result<Vec<f64>>>()?;
        Ok(values)
    })?;
    Ok(Some(standard_deviations(&draws)))
}

impl Planned<'_> {
    /// The planned test as the plan shows it.
    fn test(&self) -> PlannedTest {
        let n = self.time.samples();
        let s = self.initial_state;
        let peak = |samples: &[f64]| samples.iter().fold(0.0, |m: f64, u| m.max(u.abs()));
        let (drive, unit, peak_drive) = match self.setup.excitation {
            ExcitationKind::None if s.displacement == 0.0 => {
                ("initial state", "m/s", s.velocity.abs())
            }
            ExcitationKind::None => ("initial state", "m", s.displacement.abs()),
            kind => {
                let samples = self.records(self.time.duration, 1.0).ok();
                let first = samples.as_ref().and_then(|r| r.first());
                let label = match kind {
                    ExcitationKind::BaseAcceleration => "base acceleration",
                    ExcitationKind::BaseDisplacement => "base displacement",
                    _ => "force",
                };
                (
                    label,
                    kind.unit(),
                    first.map_or(0.0, |r| peak(r.excitation.samples())),
                )
            }
        };
        PlannedTest {
            excitation: self.setup.excitation.name(),
            records: self.setup.records,
            samples: n,
            duration_s: self.time.dt * (n.max(1) - 1) as f64,
            drive,
            peak_drive,
            drive_unit: unit,
            repeats: "records",
            repeats_planned: self.setup.records,
            channels: self
                .setup
                .channels()
                .iter()
                .zip(&self.channels)
                .map(|(r, c)| (c.name.clone(), c.sigma, r.quantity.si_unit()))
                .collect(),
        }
    }

    /// What the setup cannot identify (in the run's words), what is known, and what the
    /// prediction leaves out.
    fn notes(&self, u: &PlantIntervals) -> Vec<String> {
        let mut notes: Vec<String> = u.note.iter().cloned().collect();
        for (name, key) in [
            ("mass", "setup.known_mass"),
            ("stiffness", "setup.known_stiffness"),
        ] {
            if let Some(iv) = interval(u, name).filter(|iv| iv.standard_error == 0.0) {
                notes.push(format!(
                    "{name} known ({key} = {}): not estimated",
                    iv.value
                ));
            }
        }
        if self.setup.input_sigma > 0.0 {
            notes.push(format!(
                "the drive's noise (setup.input_sigma = {}) is not in the prediction, which takes the drive as exact: the fit estimates that noise and its intervals will be wider (`cargo xtask noise-study` shows by how much)",
                self.setup.input_sigma
            ));
        }
        notes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The amplitude factor is exact: the drive and the initial state doubled, every
    /// standard error halves, for each shipped setup (two channels, base excitation, a
    /// free decay, five records) as shipped and with every record's initial state and
    /// every channel's offset estimated.
    #[test]
    fn errors_scale_as_one_over_the_amplitude() {
        for name in ["accelerometer", "base-excitation", "free-decay", "repeats"] {
            let path = std::path::PathBuf::from(format!("../../configs/{name}.toml"));
            let shipped = Config::load(&path).unwrap();
            let mut estimated_states = shipped.clone();
            estimated_states.estimation.estimate_initial_state = true;
            estimated_states.estimation.estimate_offset = true;
            for config in [shipped, estimated_states] {
                let p = Planned::new(&config, &path).unwrap();
                let (one, two) = (p.predict(2.0, 1.0).unwrap(), p.predict(2.0, 2.0).unwrap());
                for n in estimated(&one) {
                    let (a, b) = (interval(&one, n).unwrap(), interval(&two, n).unwrap());
                    let ratio = b.standard_error / a.standard_error;
                    assert!((ratio - 0.5).abs() < 1e-9, "{name} {n}: {ratio}");
                }
            }
        }
    }
}
