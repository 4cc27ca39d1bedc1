//! Before the test: the Cramér–Rao intervals of a joint fit, and the noise-free response
//! of any channel under any drive.

use super::intervals::{PlantIntervals, log_covariance, plant_intervals};
use super::problem::Joint;
use super::setup::{Record, RecordsOptions};
use crate::plant::Drive;
use crate::plant::Plant;
use crate::{
    data::Excitation,
    error::{IdentError, Result},
    params::{InitialState, Parameters},
};
use msd_ode::{SVector, SampledInput};
use msd_signal::{Channel, Frame, ResponseQuantity};

/// A sensor of a planned record: what it will measure and its noise level (see
/// [`predicted_records_uncertainty`] for a plan).
///
/// ```
/// use msd_ident::{ResponseQuantity, records::PlannedChannel};
/// let acc = PlannedChannel { name: "acc".into(), quantity: ResponseQuantity::Acceleration, sigma: 0.05, ..Default::default() };
/// assert_eq!(acc.frame, msd_ident::Frame::Absolute);
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PlannedChannel {
    /// The sensor's name (channels of one name share σ).
    pub name: String,
    /// Displacement, velocity or acceleration.
    pub quantity: ResponseQuantity,
    /// Absolute, or relative to the base.
    pub frame: Frame,
    /// The white noise's standard deviation, in the channel's unit.
    pub sigma: f64,
}

/// A planned record: its drive, its initial state (what rings a free decay) and its
/// sensors (see [`predicted_records_uncertainty`] for a plan).
///
/// ```
/// use msd_ident::{Excitation, InitialState, records::{PlannedChannel, PlannedRecord}};
/// let pluck = PlannedRecord { name: "pluck".into(),
///     excitation: Excitation::from_samples(0.0, 0.002, vec![0.0; 5001])?,
///     initial_state: InitialState { displacement: 0.01, velocity: 0.0 },
///     channels: vec![PlannedChannel { name: "laser".into(), sigma: 2e-4, ..Default::default() }] };
/// assert_eq!(pluck.excitation.len(), 5001);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PlannedRecord {
    /// The run's name.
    pub name: String,
    /// The drive's samples (only the grid for a free decay).
    pub excitation: Excitation,
    /// The state at the first sample (relative to the base under a base acceleration);
    /// at rest when the options do not estimate it.
    pub initial_state: InitialState,
    /// The sensors.
    pub channels: Vec<PlannedChannel>,
}

/// The Cramér–Rao prediction of [`fit_records`](crate::records::fit_records)' intervals: the
/// covariance (JᵀWJ)⁻¹ of the exact sensitivities at `plant`, each record's initial
/// state and offsets estimated as `options` says and accounted for, the 95 % intervals
/// with the fit's Student's t. The values are the plant's own.
///
/// ```
/// use msd_ident::{Excitation, Parameters, RecordsOptions, ResponseQuantity, records::{predicted_records_uncertainty, PlannedChannel, PlannedRecord}};
/// use msd_signal::paper_identification_input;
/// let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
/// let accelerometer = PlannedChannel { name: "acc".into(), quantity: ResponseQuantity::Acceleration,
///     sigma: 0.05, ..Default::default() };
/// let run = |name: &str| PlannedRecord { name: name.into(), excitation: input.clone(),
///     initial_state: Default::default(), channels: vec![accelerometer.clone()] };
/// let options = RecordsOptions::default();
/// let one = predicted_records_uncertainty(&Parameters::PAPER, &[run("1")], &options)?;
/// let four = predicted_records_uncertainty(&Parameters::PAPER, &[run("1"), run("2"), run("3"), run("4")], &options)?;
/// // Four identical runs halve the standard errors.
/// let (se1, se4) = (one.stiffness.unwrap().standard_error, four.stiffness.unwrap().standard_error);
/// assert!((se4 / se1 - 0.5).abs() < 1e-3, "{se1} {se4}");
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn predicted_records_uncertainty(
    plant: &Parameters,
    records: &[PlannedRecord],
    options: &RecordsOptions,
) -> Result<PlantIntervals> {
    plant.validate()?;
    options.validate()?;
    let stand_ins = stand_in_records(records, options)?;
    let kinds = stand_ins
        .iter()
        .map(|r| {
            r.channels
                .iter()
                .map(|c| options.output_kind(&r.name, c))
                .collect()
        })
        .collect::<Result<Vec<_>>>()?;
    let refs: Vec<&Record> = stand_ins.iter().collect();
    let fixed = super::fixed_parameters(options);
    let theta = model_theta(plant, options.drive);
    let mut problem = Joint::new(&refs, &kinds, options, fixed);
    let dof = super::degrees_of_freedom(&problem)?;
    let sigma = |name: &str| {
        let channels = records.iter().flat_map(|r| &r.channels);
        channels
            .filter(|c| c.name == name)
            .map(|c| c.sigma)
            .next()
            .unwrap_or(1.0)
    };
    problem.set_sigmas(sigma);
    if !problem.prepare(theta) {
        return Err(IdentError::NotIdentifiable {
            reason: "the planned records' free responses cannot tell the initial states and offsets apart".into(),
        });
    }
    let plant_model = Plant {
        theta,
        drive: options.drive,
    };
    for (rec, planned) in problem.records.iter_mut().zip(records) {
        let q = 2 * usize::from(options.estimate_initial_state)
            + rec.maps.len() * usize::from(options.estimate_offset);
        rec.beta = vec![0.0; q];
        if options.estimate_initial_state {
            let s = state(&plant_model, planned.initial_state, &planned.excitation);
            [rec.beta[0], rec.beta[1]] = s;
        }
    }
    let cov = log_covariance(&problem, theta)?;
    Ok(plant_intervals(
        options.drive,
        options.known,
        theta,
        &cov,
        dof,
    ))
}

/// Records without data standing in for the plan (checked: names, σ, sampling).
fn stand_in_records(records: &[PlannedRecord], options: &RecordsOptions) -> Result<Vec<Record>> {
    if records.is_empty() {
        return Err(IdentError::Setup {
            setup: options.drive.setup(),
            reason: "no records to plan: give at least one record".into(),
        });
    }
    let dt0 = records[0].excitation.dt();
    records
        .iter()
        .map(|r| {
            let fail = |channel: Option<&str>, reason: String| IdentError::InvalidRecord {
                record: r.name.clone(),
                channel: channel.map(str::to_string),
                reason,
            };
            if (r.excitation.dt() - dt0).abs() > 1e-9 * dt0 {
                return Err(fail(
                    None,
                    "its sampling interval differs from the first record's".into(),
                ));
            }
            if r.channels.is_empty() {
                return Err(fail(None, "no channels: give at least one sensor".into()));
            }
            if let Some(c) = r
                .channels
                .iter()
                .find(|c| !(c.sigma.is_finite() && c.sigma > 0.0))
            {
                return Err(fail(
                    Some(&c.name),
                    format!("σ = {}: expected a finite noise level > 0", c.sigma),
                ));
            }
            let channels = r
                .channels
                .iter()
                .map(|c| {
                    Channel::new(c.name.clone(), c.quantity.into(), Vec::new()).in_frame(c.frame)
                })
                .collect();
            Ok(Record {
                name: r.name.clone(),
                excitation: r.excitation.clone(),
                channels,
            })
        })
        .collect()
}

/// The model's θ of a plant: (m, c, k), or (1, c/m, k/m) when the drive cannot fix m.
fn model_theta(plant: &Parameters, drive: Drive) -> [f64; 3] {
    let [m, c, k] = plant.to_array();
    if drive.estimates_mass() {
        [m, c, k]
    } else {
        [1.0, c / m, k / m]
    }
}

/// The model's state of a physical initial state (x′ − (c/m)·z under a base
/// displacement).
fn state(plant: &Plant, initial: InitialState, excitation: &Excitation) -> [f64; 2] {
    let u0 = if plant.drive == Drive::None {
        0.0
    } else {
        excitation.samples()[0]
    };
    let offset = plant.velocity([0.0, 0.0], u0);
    [initial.displacement, initial.velocity - offset]
}

/// The noise-free response of a `quantity` sensor in `frame` on `plant` under `drive`,
/// released from `initial` (relative to the base under a base acceleration) at the
/// first sample: the model [`fit_records`](crate::records::fit_records) fits, for synthetic
/// records. A free decay ignores the excitation's samples.
///
/// ```
/// use msd_ident::{simulate, Backend, Drive, Excitation, Frame, InitialState, Parameters, ResponseQuantity, records::simulate_response};
/// use msd_signal::paper_identification_input;
/// let force = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
/// let p = Parameters::PAPER;
/// let x = simulate_response(&p, Drive::Force, &force, InitialState::REST,
///     ResponseQuantity::Displacement, Frame::Absolute)?;
/// let reference = simulate(&p, &force, InitialState::REST, &Backend::EXACT)?;
/// assert!(x.iter().zip(&reference).all(|(a, b)| (a - b).abs() < 1e-12));
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn simulate_response(
    plant: &Parameters,
    drive: Drive,
    excitation: &Excitation,
    initial: InitialState,
    quantity: ResponseQuantity,
    frame: Frame,
) -> Result<Vec<f64>> {
    plant.validate()?;
    let options = RecordsOptions {
        drive,
        ..RecordsOptions::default()
    };
    let channel = Channel::new("response", quantity.into(), Vec::new()).in_frame(frame);
    let map = Plant {
        theta: model_theta(plant, drive),
        drive,
    };
    let output = map.output(options.output_kind("simulated", &channel)?);
    let zeros;
    let input = if drive == Drive::None {
        zeros = vec![0.0; excitation.len()];
        SampledInput::smooth(&zeros)
    } else {
        SampledInput {
            values: excitation.samples(),
            breakpoints: excitation.breakpoints(),
        }
    };
    let s0 = state(&map, initial, excitation);
    let sim = map.response(excitation.dt(), options.hold)?;
    let mut y = vec![0.0; excitation.len()];
    sim.simulate_with(&SVector::<f64, 2>::new(s0[0], s0[1]), &input, |i, s| {
        y[i] = output.value([s[0], s[1]], input.values[i]);
    })?;
    Ok(y)
}
