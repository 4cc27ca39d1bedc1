//! Joint fits of the setups a vibration lab runs: one or several records of one rig,
//! each with one or several sensors, the plant driven by a force on the mass, by the
//! base's acceleration or displacement, or by nothing (free decays).
//!
//! [`fit_records`] documents the model and the method; `problem.rs` the variable
//! projection, `model.rs` the equations of each drive.

mod check;
mod generate;
mod guess;
mod intervals;
mod linear;
mod loo;
mod model;
mod noise;
mod noise_model;
mod plan;
mod problem;
mod recording;
mod result;
mod setup;
mod spectra;
mod validate;
mod weighted;

pub use crate::input_noise::{NoiseModel, NoiseModelFit, ResidualSpectrum, ResidualWhiteness};
pub use generate::simulate_channels;
pub use intervals::PlantIntervals;
pub use plan::{PlannedChannel, PlannedRecord, predicted_records_uncertainty, simulate_response};
pub use result::{ChannelFit, ChannelNoise, LeftOut, RecordFit, RecordsFit};
pub use setup::{Record, RecordsOptions};
pub use validate::{RecordsValidation, validate_records};

use crate::plant::{Drive, Plant};
use crate::{
    error::{IdentError, Result},
    free_decay::ClassroomEstimates,
    params::{InitialState, KnownParameter},
};
use check::check_records;
use loo::leave_one_out;
use msd_opt::levenberg_marquardt;
use noise::{initial_sigmas, noise_levels, residual_sigmas};
use problem::{Joint, RecordRows};
use std::time::Instant;

/// Fits one plant to `records` jointly.
///
/// ## The model
/// Every drive is one linear model of the plant ([`Drive`] gives the equations); each
/// channel is the displacement, velocity or acceleration of the mass, absolute or
/// relative to the base ([`Frame`](crate::Frame)), plus its own offset. What each setup identifies:
/// a force drive m, c and k; the base drives and free decays ωn and ζ only (scaling m, c
/// and k together leaves those records unchanged), and m, c, k with a known mass or
/// static stiffness. A velocity or acceleration channel does not see a displacement
/// sensor's offset: each channel of each record has its own.
///
/// ## The algorithm
/// Maximum likelihood with each sensor's noise level unknown: weighted least squares
/// with weights 1/σ̂², σ̂ re-estimated from the residuals between passes until it
/// settles. Each pass is Levenberg–Marquardt in ln m, ln c, ln k with the exact
/// sensitivities, each record's initial state and offsets eliminated by linear least
/// squares (variable projection, see `problem.rs`). The covariance is the weighted
/// Gauss–Newton one, which accounts for the eliminated quantities exactly; intervals use
/// Student's t and, for derived quantities, the delta method.
///
/// ```
/// use msd_ident::{fit_records, Channel, Drive, Excitation, Frame, InitialState, Parameters, Quantity, Record, RecordsOptions, ResponseQuantity, records::simulate_response};
/// use msd_signal::{gaussian_noise, paper_identification_input};
/// // The paper's plant and input, an accelerometer on the mass (σ = 0.05 m/s², seed 1).
/// let p = Parameters::PAPER;
/// let force = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
/// let a = simulate_response(&p, Drive::Force, &force, InitialState::REST,
///     ResponseQuantity::Acceleration, Frame::Absolute)?;
/// let noise = gaussian_noise(1, "accelerometer", 0.05, a.len())?;
/// let samples = a.iter().zip(&noise).map(|(a, n)| a + n).collect();
/// let channel = Channel::new("accelerometer", Quantity::Acceleration, samples);
/// let record = Record { name: "run 1".into(), excitation: force, channels: vec![channel] };
/// let fit = fit_records(&[record], &RecordsOptions::default())?;
/// assert_eq!(fit.plant.identifiable.len(), 5);
/// assert!(fit.plant.stiffness.unwrap().contains(p.stiffness), "{fit}");
/// assert!((fit.noise[0].sigma / 0.05 - 1.0).abs() < 0.05, "{fit}");
/// println!("{fit}");
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
///
/// Refused, naming the record and the channel: no records, a record without channels,
/// records of different sampling intervals, a channel whose length differs from its
/// excitation's, a non-finite or constant channel, a quantity the drive cannot predict;
/// a setup that cannot give what `options` asks; a free decay that does not ring down.
pub fn fit_records(records: &[Record], options: &RecordsOptions) -> Result<RecordsFit> {
    let started = Instant::now();
    options.validate()?;
    let kinds = check_records(records, options)?;
    let refs: Vec<&Record> = records.iter().collect();
    let fixed = fixed_parameters(options);
    let mut problem = Joint::new(&refs, &kinds, options, fixed);
    let dof = degrees_of_freedom(&problem)?;
    let mut sigma = initial_sigmas(&problem);
    problem.set_sigmas(by_name(&problem.group_names.clone(), &sigma));
    let theta0 = guess::initial_theta(&problem, options)?;
    let mut notes = Vec::new();
    let (x, passes, iterations) =
        solve(&mut problem, theta0, options, dof, &mut sigma, &mut notes)?;
    let output_error = problem.theta(&x);
    let treated = noise_model::covariance(
        &mut problem,
        output_error,
        options.noise_model,
        &options.residuals,
    )?;
    let theta = treated.theta;
    // The validation's starting point: the weighted estimate when it replaced x̂.
    let x = if theta == output_error {
        x
    } else {
        problem.pack(theta)
    };
    // Under the drive's noise model the standard errors rest on estimated variances:
    // Satterthwaite's degrees of freedom (never more than the samples').
    let t_dof = |nu: Option<f64>| match nu {
        Some(nu) if nu.is_finite() => (nu.floor() as usize).clamp(1, dof),
        _ => dof,
    };
    let intervals_at =
        |theta, cov, dof| intervals::plant_intervals(options.drive, options.known, theta, cov, dof);
    let plant = intervals_at(
        theta,
        &treated.reported,
        t_dof(treated.fit.degrees_of_freedom),
    );
    let output_error_plant = (treated.output_error.as_ref())
        .map(|(cov, nu)| intervals_at(output_error, cov, t_dof(*nu)));
    let white_noise_plant =
        (treated.fit.treatment != "white").then(|| intervals_at(output_error, &treated.white, dof));
    if options.drive == Drive::None && plant.damping_ratio.ci95[0] <= 0.0 {
        return Err(IdentError::Setup {
            setup: options.drive.setup(),
            reason: format!(
                "the records do not decay: ζ = {:.3e} and its 95 % interval reaches 0; a free decay must ring down",
                plant.damping_ratio.value
            ),
        });
    }
    let records_fit: Vec<RecordFit> = problem
        .records
        .iter()
        .map(|rec| record_fit(&problem, rec, theta))
        .collect();
    notes.extend(poor_fits(&records_fit));
    notes.extend(crate::input_noise::notes(
        &treated.fit,
        &treated.whiteness,
        "white_noise_plant",
        options.drive != Drive::None,
    ));
    let shows = (treated.fit.p_value).is_some_and(|p| p < crate::input_noise::WHITENESS_LEVEL);
    if shows && treated.output_error.is_none() && treated.whiteness.iter().any(|c| !c.passed) {
        notes.push("the estimate is the output-error one, not weighted by the drive's noise: the residuals are not white under the noise model, so it cannot be trusted to weigh the frequency lines".into());
    }
    let names = problem.group_names.clone();
    let leave_one_out = (options.leave_one_out && records.len() >= 2).then(|| {
        let x = x.clone();
        leave_one_out(
            records,
            &kinds,
            options,
            &x,
            by_name(&names, &sigma),
            &mut notes,
        )
    });
    let validation = (records.len() == 1 && options.hold_out > 0.0)
        .then(|| {
            let held =
                validate::hold_out(&records[0], &kinds[0], options, &x, by_name(&names, &sigma));
            held.map_err(|e| notes.push(format!("no validation on held-out data: {e}")))
                .ok()
        })
        .flatten();
    let sigma_of = by_name(&names, &sigma);
    let predictions =
        (validation.iter().flat_map(|v| &v.predictions)).chain(leave_one_out.iter().flatten());
    notes.extend(validate::notes(predictions, sigma_of));
    Ok(RecordsFit {
        drive: options.drive,
        plant,
        noise: noise_levels(&problem, &sigma),
        noise_model: treated.fit,
        white_noise_plant,
        output_error_plant,
        whiteness: treated.whiteness,
        records: records_fit,
        leave_one_out,
        validation,
        passes,
        iterations,
        evaluations: problem.evaluations,
        notes,
        wall_time: started.elapsed(),
        theta,
    })
}

/// m, c, k held fixed: the mass at 1 unless a force drives (c, k are then per unit
/// mass), and a known one with a force drive.
pub(super) fn fixed_parameters(options: &RecordsOptions) -> [Option<f64>; 3] {
    match (options.drive.estimates_mass(), options.known) {
        (false, _) => [Some(1.0), None, None],
        (true, KnownParameter::Mass(m)) => [Some(m), None, None],
        (true, KnownParameter::Stiffness(k)) => [None, None, Some(k)],
        (true, KnownParameter::None) => [None; 3],
    }
}

/// Samples minus estimated quantities (plant, initial states, offsets).
fn degrees_of_freedom(problem: &Joint<'_>) -> Result<usize> {
    let linear: usize = problem
        .records
        .iter()
        .map(|r| problem.linear_count(r.maps.len()))
        .sum();
    let estimated = problem.free.len() + linear;
    if problem.rows <= estimated + 1 {
        return Err(IdentError::TooFewSamples {
            got: problem.rows,
            needed: estimated + 2,
            why: "a joint fit needs more samples than estimated quantities",
        });
    }
    Ok(problem.rows - estimated)
}

/// σ of each group by name, for [`Joint::set_sigmas`].
fn by_name<'s>(names: &'s [String], sigma: &'s [f64]) -> impl Fn(&str) -> f64 + Copy + 's {
    move |name| {
        let g = names.iter().position(|n| n == name);
        g.map_or(1.0, |g| sigma[g])
    }
}

/// Weighted passes until the noise levels settle: returns x̂, the passes and the
/// iterations; leaves `problem` prepared at x̂ with the final weights.
fn solve(
    problem: &mut Joint<'_>,
    theta0: [f64; 3],
    options: &RecordsOptions,
    dof: usize,
    sigma: &mut Vec<f64>,
    notes: &mut Vec<String>,
) -> Result<(Vec<f64>, usize, usize)> {
    let mut x = problem.pack(theta0);
    let (mut iterations, mut passes) = (0, 0);
    let names = problem.group_names.clone();
    loop {
        let lm = levenberg_marquardt(problem, &x, &options.levenberg_marquardt)?;
        passes += 1;
        iterations += lm.iterations;
        x = lm.x;
        if !lm.exit.is_success() {
            notes.push(format!(
                "pass {passes}: Levenberg–Marquardt stopped without converging ({})",
                lm.exit
            ));
        }
        if !problem.prepare(problem.theta(&x)) {
            return Err(IdentError::EstimationFailed {
                reason: "the model cannot be simulated at the estimate".into(),
            });
        }
        problem.solve_linear();
        let new = residual_sigmas(problem, dof);
        let change = new
            .iter()
            .zip(sigma.iter())
            .map(|(a, b)| (a / b - 1.0).abs())
            .fold(0.0, f64::max);
        *sigma = new;
        problem.set_sigmas(by_name(&names, sigma));
        // The Gram matrices depend on the weights: prepare again.
        problem.prepare(problem.theta(&x));
        problem.solve_linear();
        if names.len() == 1 || change < 1e-3 {
            return Ok((x, passes, iterations));
        }
        if passes == options.max_passes {
            notes.push(format!(
                "the noise levels did not settle in {passes} passes (last relative change {change:.1e}): the weights, and so the intervals, are approximate"
            ));
            return Ok((x, passes, iterations));
        }
    }
}

/// A note for each channel the model does not explain (R² < 0.5): a wrong drive,
/// quantity, frame or unit fits, but explains nothing.
fn poor_fits(records: &[RecordFit]) -> Vec<String> {
    let channels = records
        .iter()
        .flat_map(|r| r.channels.iter().map(move |c| (r, c)));
    channels
        .filter(|(_, c)| c.fit.r_squared < 0.5)
        .map(|(r, c)| {
            format!(
                "record `{}`, channel `{}`: R² = {:.3}, the model does not explain this channel; check the drive, the quantity, the frame and the units",
                r.name, c.channel, c.fit.r_squared
            )
        })
        .collect()
}

/// The initial state, offsets and channel fits of one record (the problem prepared).
fn record_fit(problem: &Joint<'_>, rec: &RecordRows<'_>, theta: [f64; 3]) -> RecordFit {
    let s = problem.initial_state(rec);
    let u0 = match problem.drive {
        Drive::None => 0.0,
        _ => rec.record.excitation.samples()[0],
    };
    let plant = Plant {
        theta,
        drive: problem.drive,
    };
    RecordFit {
        name: rec.record.name.clone(),
        initial_state: InitialState {
            displacement: s[0],
            velocity: plant.velocity(s, u0),
        },
        channels: channel_fits(problem, rec),
        classroom: (problem.drive == Drive::None)
            .then(|| {
                let dt = rec.record.excitation.dt();
                ClassroomEstimates::from_record(dt, &rec.record.channels[0].samples).ok()
            })
            .flatten(),
    }
}

pub(super) fn channel_fits(problem: &Joint<'_>, rec: &RecordRows<'_>) -> Vec<ChannelFit> {
    let offsets = problem.offsets(rec);
    rec.record
        .channels
        .iter()
        .enumerate()
        .map(|(ch, channel)| {
            let model: Vec<f64> = (0..rec.len).map(|i| problem.model(rec, ch, i)).collect();
            ChannelFit {
                channel: channel.name.clone(),
                offset: offsets[ch],
                fit: crate::metrics::FitMetrics::new(&channel.samples, &model),
                model,
            }
        })
        .collect()
}
