//! A `[chain]` config: every m, c, k, mode and estimated delay of the chain predicted by
//! [`msd_ident::chain::predict_chain`] at the config's chain (the Cramér–Rao bound of the fit's
//! own linearisation), what reaches the target (a stronger drive, a longer record, repeats),
//! and with `verify` the spread and the coverage of that many simulated records, each
//! fitted as the run fits it.

use super::force::with_duration;
use super::search::{
    Widths, draws, duration_needed, longest_record, repeats_needed, standard_deviations,
};
use super::{Correlation, Plan, PlanOptions, PlannedQuantity, PlannedTest};
use crate::config::{ChainSection, Config};
use crate::error::{ExperimentError, Result};
use msd_ident::{
    Interval, ResponseQuantity,
    chain::{ChainDrive, ChainUncertainty, predict_chain},
};
use std::path::Path;

const M: [&str; 8] = ["m1", "m2", "m3", "m4", "m5", "m6", "m7", "m8"];
const C: [&str; 8] = ["c1", "c2", "c3", "c4", "c5", "c6", "c7", "c8"];
const K: [&str; 8] = ["k1", "k2", "k3", "k4", "k5", "k6", "k7", "k8"];
const CG: [&str; 8] = ["cg1", "cg2", "cg3", "cg4", "cg5", "cg6", "cg7", "cg8"];
const KG: [&str; 8] = ["kg1", "kg2", "kg3", "kg4", "kg5", "kg6", "kg7", "kg8"];
const FN: [&str; 8] = ["fn1", "fn2", "fn3", "fn4", "fn5", "fn6", "fn7", "fn8"];
const ZETA: [&str; 8] = [
    "zeta1", "zeta2", "zeta3", "zeta4", "zeta5", "zeta6", "zeta7", "zeta8",
];
const CUTOFF: [&str; 8] = [
    "cutoff1", "cutoff2", "cutoff3", "cutoff4", "cutoff5", "cutoff6", "cutoff7", "cutoff8",
];
const DELAY: [&str; 8] = [
    "delay1", "delay2", "delay3", "delay4", "delay5", "delay6", "delay7", "delay8",
];

/// Where a planned quantity sits in a [`ChainUncertainty`].
#[derive(Debug, Clone, Copy)]
enum Slot {
    Mass(usize),
    Damper(usize),
    Spring(usize),
    GroundDamper(usize),
    GroundSpring(usize),
    Frequency(usize),
    Damping(usize),
    Cutoff(usize),
    Delay(usize),
}

impl Slot {
    fn name(self) -> &'static str {
        let at = |names: &[&'static str; 8], i: usize| names.get(i).copied().unwrap_or("…");
        match self {
            Slot::Mass(i) => at(&M, i),
            Slot::Damper(i) => at(&C, i),
            Slot::Spring(i) => at(&K, i),
            Slot::GroundDamper(i) => at(&CG, i),
            Slot::GroundSpring(i) => at(&KG, i),
            Slot::Frequency(i) => at(&FN, i),
            Slot::Damping(i) => at(&ZETA, i),
            Slot::Cutoff(i) => at(&CUTOFF, i),
            Slot::Delay(i) => at(&DELAY, i),
        }
    }

    fn interval(self, u: &ChainUncertainty) -> Option<Interval> {
        let iv = u.intervals.as_ref();
        match self {
            Slot::Mass(i) => iv.map(|v| v.masses[i]),
            Slot::Damper(i) => iv.map(|v| v.dampers[i]),
            Slot::Spring(i) => iv.map(|v| v.springs[i]),
            Slot::GroundDamper(i) => iv.and_then(|v| v.ground_dampers.get(i).copied()),
            Slot::GroundSpring(i) => iv.and_then(|v| v.ground_springs.get(i).copied()),
            Slot::Frequency(i) => u.modes.get(i).map(|m| m.natural_frequency_hz),
            Slot::Damping(i) => u.modes.get(i).map(|m| m.damping_ratio),
            Slot::Cutoff(i) => u.cutoffs.get(i).copied().flatten(),
            Slot::Delay(i) => u.delays.get(i).copied().flatten(),
        }
    }
}

/// The quantities of a chain's plan: each free m, c, k (and connection to the ground)
/// when all are identified, each
/// mode's fn and ζ, each estimated filter cut-off and delay.
fn slots(chain: &ChainSection, u: &ChainUncertainty) -> Vec<Slot> {
    let mut out = Vec::new();
    if u.intervals.is_some() {
        for i in 0..chain.size() {
            if !chain.known_masses.contains(&(i + 1)) {
                out.push(Slot::Mass(i));
            }
            out.extend([Slot::Damper(i), Slot::Spring(i)]);
            if chain.guess.ground_dampers.get(i).is_some_and(|v| *v > 0.0) {
                out.push(Slot::GroundDamper(i));
            }
            if chain.guess.ground_springs.get(i).is_some_and(|v| *v > 0.0) {
                out.push(Slot::GroundSpring(i));
            }
        }
    }
    for i in 0..u.modes.len() {
        out.extend([Slot::Frequency(i), Slot::Damping(i)]);
    }
    for (i, cutoff) in u.cutoffs.iter().enumerate() {
        if cutoff.is_some() {
            out.push(Slot::Cutoff(i));
        }
    }
    for (i, delay) in u.delays.iter().enumerate() {
        if delay.is_some() {
            out.push(Slot::Delay(i));
        }
    }
    out
}

fn width(u: &ChainUncertainty, slot: Slot) -> f64 {
    slot.interval(u)
        .map_or(f64::INFINITY, |iv| (iv.ci95[1] - iv.value) / iv.value.abs())
}

/// The plan of a `[chain]` config.
pub(super) fn plan(config: &Config, path: &Path, options: &PlanOptions) -> Result<Plan> {
    let (Some(chain), Some(time)) = (config.chain.as_ref(), config.time) else {
        return Err(ExperimentError::config(
            path,
            "a chain plan needs [chain] and [time]",
        ));
    };
    let Some(plant) = chain.plant.as_ref() else {
        return Err(ExperimentError::config(
            path,
            "chain.plant: missing: a plan predicts a test of a known chain (a config with measured [data] has none to plan)",
        ));
    };
    if let Some(i) = chain.sensors.iter().position(|s| s.sigma <= 0.0) {
        return Err(ExperimentError::config(
            path,
            format!("chain.sensors[{i}].sigma = 0: a plan needs each channel's noise level (> 0)"),
        ));
    }
    let predict = |config: &Config| -> Result<ChainUncertainty> {
        let input = crate::data::synthetic_input(config, path)?
            .ok_or_else(|| ExperimentError::config(path, "identification.input: missing"))?;
        let noise: Vec<f64> = chain.sensors.iter().map(|s| s.sigma).collect();
        let options = crate::chain::fit_options(chain);
        predict_chain(
            &chain.planned(),
            plant,
            input.samples(),
            input.dt(),
            &noise,
            &options,
        )
        .map_err(|e| ExperimentError::config(path, format!("the planned experiment: {e}")))
    };
    let now = predict(config)?;
    let slots = slots(chain, &now);
    let verified = verify(config, chain, &slots, &now, options)?;
    let mut search = Widths::new(
        |duration| {
            let u = predict(&with_duration(config, time, duration))?;
            Ok(slots.iter().map(|&s| width(&u, s)).collect::<Vec<_>>())
        },
        options.progress,
    );
    let samples = crate::budget::samples_per_experiment(config);
    let longest = longest_record(time.duration, samples);
    let mut quantities = Vec::with_capacity(slots.len());
    for (q, &slot) in slots.iter().enumerate() {
        let iv = slot.interval(&now).unwrap_or(Interval {
            value: 0.0,
            standard_error: 0.0,
            ci95: [0.0, 0.0],
        });
        let w = width(&now, slot);
        quantities.push(PlannedQuantity {
            name: slot.name(),
            value: iv.value,
            standard_error: iv.standard_error,
            relative_half_width: w,
            amplitude_factor: Some(w / options.target),
            duration_needed_s: duration_needed(time.duration, w, options.target, longest, |d| {
                search.width(d, q)
            })?,
            repeats_needed: repeats_needed(1, w, options.target),
            simulated_standard_deviation: verified.as_ref().map(|v| v.0[q]),
            coverage: verified.as_ref().map(|v| v.1[q]),
        });
    }
    drop(search);
    Ok(Plan {
        name: config.name.clone(),
        test: test(config, chain),
        target: options.target,
        quantities,
        correlation: Correlation {
            names: now.names.iter().map(|n| static_name(n)).collect(),
            matrix: now.correlation.clone(),
        },
        notes: now.unidentifiable.clone(),
        verified_with: options.verify,
    })
}

/// The static name of a fitted column's name ("m2", "delay1").
fn static_name(name: &str) -> &'static str {
    [M, C, K, CG, KG, CUTOFF, DELAY]
        .iter()
        .flat_map(|names| names.iter())
        .find(|n| **n == name)
        .copied()
        .unwrap_or("…")
}

/// The planned test as the plan shows it.
fn test(config: &Config, chain: &ChainSection) -> PlannedTest {
    let samples = config.time.map_or(0, |t| t.samples());
    let dt = config.time.map_or(0.0, |t| t.dt);
    let (drive, unit) = match chain.drive {
        ChainDrive::Force => ("force", "N"),
        ChainDrive::BaseAcceleration => ("base acceleration", "m/s²"),
    };
    let peak = crate::data::synthetic_input(config, Path::new(""))
        .ok()
        .flatten()
        .map_or(0.0, |x| {
            x.samples().iter().fold(0.0, |m: f64, v| m.max(v.abs()))
        });
    PlannedTest {
        excitation: drive,
        records: 1,
        samples,
        duration_s: dt * samples.saturating_sub(1) as f64,
        drive,
        peak_drive: peak,
        drive_unit: unit,
        repeats: "records",
        repeats_planned: 1,
        channels: chain
            .sensors
            .iter()
            .map(|s| {
                let (q, unit) = match s.quantity {
                    ResponseQuantity::Displacement => ("displacement", "m"),
                    ResponseQuantity::Velocity => ("velocity", "m/s"),
                    ResponseQuantity::Acceleration => ("acceleration", "m/s²"),
                };
                (format!("{q} of mass {}", s.at), s.sigma, unit)
            })
            .collect(),
    }
}

/// Over `options.verify` simulated records (seeds 0 …), each fitted as the run fits it:
/// each quantity's standard deviation and the fraction of 95 % intervals that hold the
/// prior value.
fn verify(
    config: &Config,
    chain: &ChainSection,
    slots: &[Slot],
    prior: &ChainUncertainty,
    options: &PlanOptions,
) -> Result<Option<(Vec<f64>, Vec<f64>)>> {
    if options.verify == 0 {
        return Ok(None);
    }
    let draws = draws(options.verify, "plan --verify", options.progress, |seed| {
        let record = crate::chain::record(config, chain, seed)?;
        let fit = crate::chain::fit(chain, &record)?;
        slots
            .iter()
            .map(|&slot| {
                let iv = slot.interval(&fit.uncertainty).ok_or_else(|| {
                    ExperimentError::run(
                        "plan --verify",
                        format!("seed {seed}: the fit does not identify {}", slot.name()),
                    )
                })?;
                let truth = slot.interval(prior).map_or(f64::NAN, |p| p.value);
                Ok((iv.value, iv.contains(truth)))
            })
            .collect::<Result<Vec<_>>>()
    })?;
    let values: Vec<Vec<f64>> = draws
        .iter()
        .map(|d| d.iter().map(|v| v.0).collect())
        .collect();
    let coverage = (0..slots.len())
        .map(|q| draws.iter().filter(|d| d[q].1).count() as f64 / draws.len() as f64)
        .collect();
    Ok(Some((standard_deviations(&values), coverage)))
}
