//! The time-domain fit of the records a frequency response was estimated from, beside
//! the frequency-domain fit: the same plant identified twice from the same data.
//!
//! The records (force and response, one pair per record) are fitted jointly by
//! msd-ident's [`fit_records`](msd_ident::fit_records) with a force drive: m, c and k
//! shared, each record's initial state and offset its own, started from the
//! frequency-domain estimate. Each quantity is compared in units of the combined
//! standard error, d = (q̂_f − q̂_t)/√(SE_f² + SE_t²). Both estimates come from the same
//! noise, so they are positively correlated: when the time-domain fit is efficient (it
//! is the maximum-likelihood fit of white output noise), Cov(q̂_f, q̂_t) = Var(q̂_t)
//! (Hausman 1978), Var(q̂_f − q̂_t) = SE_f² − SE_t² ≤ SE_f² + SE_t², and |d| ≤ 1.96 is a
//! conservative test of agreement at 95 %.
//!
//! A chain of several masses, or several modes fitted, has no single-mode time model:
//! the comparison is skipped and says why.
//!
//! ```
//! use msd_experiment::{RunOptions, config::{Config, Spec}, frf::{self, TimeDomain}};
//! let text = r#"
//!     name = "shaker"
//!     [frequency_response.plant]
//!     masses = [2.5]
//!     springs = [120.0]
//!     dampers = [1.8]
//!     [frequency_response.shaker]
//!     records = 2
//!     sample_rate = 50.0
//!     duration = 20.0
//!     settle = 40.0
//!     force = { kind = "multisine", base_frequency = 0.05, f_min = 0.05, f_max = 4.95, rms = 2.0 }
//!     [frequency_response.estimator]
//!     welch = { window = "rectangular" }
//! "#;
//! let config = Config::from_toml_str(text, "shaker.toml")?;
//! let outcome = frf::run(Spec::new(config)?, &RunOptions::default())?;
//! let Some(TimeDomain::Compared(fit)) = &outcome.time_domain else { panic!("compared") };
//! assert_eq!(fit.records, 2);
//! assert_eq!(fit.comparison[0].quantity, "mass");
//! assert!(fit.estimate.stiffness.expect("a force drive gives k").contains(120.0));
//! assert!(fit.comparison.iter().all(|d| d.difference_se.abs() <= 1.96), "{fit:?}");
//! # Ok::<(), msd_experiment::ExperimentError>(())
//! ```

use super::{FrfFit, Truth};
use crate::fmt::sig;
use msd_ident::Hold;
use msd_ident::{
    Channel, Drive, Excitation, IdentError, Interval, OneModeFit, Record, RecordsOptions,
    ResponseQuantity, fit_records,
    records::{ChannelNoise, PlantIntervals},
};
use msd_signal::FrfKind;
use serde::Serialize;
use std::fmt::Write;

/// The time records behind a frequency response: `[force, response]` per record.
#[derive(Debug, Clone)]
pub(crate) struct TimeRecords {
    pub channels: Vec<[Vec<f64>; 2]>,
    pub sample_rate: f64,
    /// The response's quantity.
    pub kind: FrfKind,
    /// How the force is held between samples in the fit: `First` where the records were
    /// simulated that way (no model error), `Cubic` for measured records.
    pub hold: Hold,
}

/// The time-domain fit and the comparison, or why there is none.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum TimeDomain {
    /// The records fitted in the time domain, compared quantity by quantity.
    Compared(Box<TimeFit>),
    /// Not compared.
    Skipped {
        /// Why, in words.
        reason: String,
    },
}

/// The joint time-domain fit of the records.
#[derive(Debug, Clone, Serialize)]
pub struct TimeFit {
    /// m, c, k, fn and ζ with 95 % intervals.
    pub estimate: PlantIntervals,
    /// Records fitted.
    pub records: usize,
    /// Samples of all records.
    pub samples: usize,
    /// The force between samples: `"first"` (linear) or `"cubic"`.
    pub hold: &'static str,
    /// σ̂ of the response channel.
    pub noise: Vec<ChannelNoise>,
    /// Levenberg–Marquardt iterations over all passes.
    pub iterations: usize,
    /// What the fit reports (unconverged passes).
    pub notes: Vec<String>,
    /// Each quantity in both domains.
    pub comparison: Vec<Difference>,
}

/// One quantity estimated in both domains.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Difference {
    /// `mass`, `damping`, `stiffness`, `natural_frequency_hz` or `damping_ratio`.
    pub quantity: &'static str,
    /// From the frequency response.
    pub frequency_domain: Interval,
    /// From the time records.
    pub time_domain: Interval,
    /// The true value of a synthetic plant.
    pub truth: Option<f64>,
    /// (frequency − time)/√(SE_f² + SE_t²) (a quantity whose two standard errors are
    /// both 0, from noise-free records, is not compared).
    pub difference_se: f64,
}

/// The comparison for `fit` of the records; `scale_known` = whether m, c, k are compared.
pub(crate) fn compare(
    records: &TimeRecords,
    fit: &FrfFit,
    truth: Option<&Truth>,
    scale_known: bool,
) -> TimeDomain {
    let skipped = |reason: String| TimeDomain::Skipped { reason };
    let one = match fit {
        FrfFit::OneMode(one) => one,
        FrfFit::Modes(_) | FrfFit::Set(_) => {
            return skipped(format!(
                "{} modes were fitted; the time-domain model is one mass on a spring and a damper (a single mode), so it does not apply",
                fit.poles().len()
            ));
        }
    };
    if let Some(t) = truth.filter(|t| t.plant.len() > 1) {
        return skipped(format!(
            "the plant is a chain of {} masses; the time-domain model is one mass on a spring and a damper (a single mode), so it does not apply",
            t.plant.len()
        ));
    }
    match fit_time(records, one) {
        Ok(td) => TimeDomain::Compared(Box::new(TimeFit {
            comparison: differences(one, &td.plant, truth, scale_known),
            estimate: td.plant,
            records: records.channels.len(),
            samples: records.channels.iter().map(|[f, _]| f.len()).sum(),
            hold: hold_name(records.hold),
            noise: td.noise,
            iterations: td.iterations,
            notes: td.notes,
        })),
        Err(e) => skipped(format!("the time-domain fit failed: {e}")),
    }
}

fn hold_name(hold: Hold) -> &'static str {
    match hold {
        Hold::Zero => "zero",
        Hold::First => "first",
        Hold::Cubic => "cubic",
    }
}

/// The joint force-drive fit of the records, started from the frequency-domain m, c, k.
fn fit_time(records: &TimeRecords, one: &OneModeFit) -> Result<msd_ident::RecordsFit, IdentError> {
    let quantity = match records.kind {
        FrfKind::Receptance => ResponseQuantity::Displacement,
        FrfKind::Mobility => ResponseQuantity::Velocity,
        FrfKind::Accelerance => ResponseQuantity::Acceleration,
    };
    let dt = 1.0 / records.sample_rate;
    let fitted = records
        .channels
        .iter()
        .enumerate()
        .map(|(i, [force, response])| {
            Ok(Record {
                name: format!("record {}", i + 1),
                excitation: Excitation::from_samples(0.0, dt, force.clone())?,
                channels: vec![Channel::new("response", quantity.into(), response.clone())],
            })
        })
        .collect::<Result<Vec<_>, IdentError>>()?;
    let options = RecordsOptions {
        drive: Drive::Force,
        initial_guess: one.parameters.validate().is_ok().then_some(one.parameters),
        leave_one_out: false,
        hold_out: 0.0,
        hold: records.hold,
        ..RecordsOptions::default()
    };
    fit_records(&fitted, &options)
}

/// The quantities both fits give, with the truth of a one-mass plant.
fn differences(
    one: &OneModeFit,
    td: &PlantIntervals,
    truth: Option<&Truth>,
    scale_known: bool,
) -> Vec<Difference> {
    let u = &one.uncertainty;
    let plant = truth.map(|t| &t.plant);
    let mode = truth.and_then(|t| t.modes.first());
    let mut pairs = Vec::new();
    if scale_known {
        pairs.push(("mass", u.mass, td.mass, plant.map(|p| p.masses[0])));
        pairs.push((
            "damping",
            u.damping,
            td.damping,
            plant.map(|p| p.dampers[0]),
        ));
        pairs.push((
            "stiffness",
            u.stiffness,
            td.stiffness,
            plant.map(|p| p.springs[0]),
        ));
    }
    pairs.push((
        "natural_frequency_hz",
        u.natural_frequency_hz,
        Some(td.natural_frequency_hz),
        mode.map(|m| m.natural_frequency_hz),
    ));
    pairs.push((
        "damping_ratio",
        u.damping_ratio,
        Some(td.damping_ratio),
        mode.map(|m| m.damping_ratio),
    ));
    pairs
        .into_iter()
        .filter_map(|(quantity, f, t, truth)| {
            let t = t?;
            let combined = f.standard_error.hypot(t.standard_error);
            // Noise-free records give both standard errors 0: a difference has no scale.
            if !(combined.is_finite() && combined > 0.0) {
                return None;
            }
            Some(Difference {
                quantity,
                frequency_domain: f,
                time_domain: t,
                truth,
                difference_se: (f.value - t.value) / combined,
            })
        })
        .collect()
}

impl TimeFit {
    /// The comparison with the largest |difference|.
    pub fn largest(&self) -> Option<&Difference> {
        self.comparison
            .iter()
            .max_by(|a, b| a.difference_se.abs().total_cmp(&b.difference_se.abs()))
    }
}

impl std::fmt::Display for TimeDomain {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TimeDomain::Compared(t) => {
                write!(f, "time domain ({} records):", t.records)?;
                match t.largest() {
                    Some(d) => write!(
                        f,
                        " largest difference {:.2} combined SE ({})",
                        d.difference_se, d.quantity
                    ),
                    None => write!(f, " nothing to compare"),
                }
            }
            TimeDomain::Skipped { reason } => write!(f, "time domain: not compared: {reason}"),
        }
    }
}

/// The report's section.
pub(crate) fn markdown(w: &mut String, td: &TimeDomain) -> std::fmt::Result {
    writeln!(w, "## Frequency domain and time domain\n")?;
    let t = match td {
        TimeDomain::Compared(t) => t,
        TimeDomain::Skipped { reason } => {
            writeln!(w, "Not compared: {reason}.\n")?;
            return Ok(());
        }
    };
    writeln!(
        w,
        "The same {} records ({} samples) fitted in the time domain: msd-ident's `fit_records` with a force drive, each record's initial state and offset estimated, the force {} between samples, started from the frequency-domain estimate ({} iterations, σ̂ = {}).\n",
        t.records,
        t.samples,
        if t.hold == "first" {
            "linear (as simulated)"
        } else {
            "cubic"
        },
        t.iterations,
        t.noise.first().map_or("—".into(), |n| sig(n.sigma, 3)),
    )?;
    writeln!(
        w,
        "| quantity | frequency domain ± 95 % | time domain ± 95 % | truth | difference / combined SE |\n|---|---|---|---|---|"
    )?;
    for d in &t.comparison {
        writeln!(
            w,
            "| {} | {} | {} | {} | {:.2} |",
            label(d.quantity),
            plus_minus(&d.frequency_domain),
            plus_minus(&d.time_domain),
            d.truth.map_or("—".into(), |v| sig(v, 6)),
            d.difference_se
        )?;
    }
    writeln!(
        w,
        "\nThe difference is in units of √(SE_f² + SE_t²). Both fits use the same records, so their errors are positively correlated and |difference| ≤ 1.96 is a conservative test of agreement at 95 %.\n"
    )?;
    for note in &t.notes {
        writeln!(w, "Note: {note}.\n")?;
    }
    Ok(())
}

fn label(quantity: &str) -> &str {
    match quantity {
        "mass" => "m [kg]",
        "damping" => "c [N·s/m]",
        "stiffness" => "k [N/m]",
        "natural_frequency_hz" => "fn [Hz]",
        "damping_ratio" => "ζ [-]",
        other => other,
    }
}

fn plus_minus(i: &Interval) -> String {
    format!(
        "{} ± {}",
        sig(i.value, 6),
        sig(0.5 * (i.ci95[1] - i.ci95[0]), 3)
    )
}
