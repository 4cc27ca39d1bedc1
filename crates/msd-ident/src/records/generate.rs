//! Noise-free records of a lab setup on the physical plant (m, c, k): every channel of
//! one exact simulation, for synthetic tests.

use crate::plant::{Drive, Plant};
use crate::{
    data::Excitation,
    error::{IdentError, Result},
    params::{InitialState, Parameters},
};
use msd_ode::{ExactSimulator, Hold, SVector, SampledInput};
use msd_signal::Frame;
use msd_signal::ResponseQuantity;

/// The noise-free channels (`quantity`, `frame`) of `plant` under `drive`, released from
/// `initial` at the first of `samples` instants `dt` apart: one exact simulation (the
/// matrix exponential, balanced, with a cubic hold of the drive's samples), each channel
/// a combination of the state and the drive.
///
/// The state is (x, x′) under a force or a free decay (no `input`: the drive is zero);
/// (y, y′) relative to a base driven by z″; (x, w = x′ − (c/m)·z) with a base driven by
/// z, so that no derivative of z appears. Acceleration channels are the equation of
/// motion's value; a base displacement is measured as a displacement (absolute or
/// relative) only.
///
/// This is the synthetic tests' generator on the physical parameters; the model that
/// [`fit_records`](crate::records::fit_records) fits is [`simulate_response`](crate::records::simulate_response)
/// (the same system, its own rounding).
///
/// ```
/// use msd_ident::{Drive, Frame, InitialState, Parameters, ResponseQuantity, records::simulate_channels};
/// let released = InitialState { displacement: 0.01, velocity: 0.0 };
/// let channels = [(ResponseQuantity::Displacement, Frame::Absolute),
///     (ResponseQuantity::Acceleration, Frame::Absolute)];
/// let out = simulate_channels(&Parameters::PAPER, released, Drive::None, None, 1000, 0.002, &channels)?;
/// let (m, k) = (Parameters::PAPER.mass, Parameters::PAPER.stiffness);
/// assert_eq!(out[0][0], 0.01);
/// assert!((out[1][0] + k / m * 0.01).abs() < 1e-12); // x″ = −(k/m)·x at rest
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn simulate_channels(
    plant: &Parameters,
    initial: InitialState,
    drive: Drive,
    input: Option<&Excitation>,
    samples: usize,
    dt: f64,
    channels: &[(ResponseQuantity, Frame)],
) -> Result<Vec<Vec<f64>>> {
    plant.validate()?;
    if drive == Drive::BaseDisplacement
        && let Some((q, _)) = channels
            .iter()
            .find(|(q, _)| *q != ResponseQuantity::Displacement)
    {
        return Err(IdentError::Setup {
            setup: drive.setup(),
            reason: format!(
                "a {q:?} channel: a base displacement drive is measured by displacement channels only"
            ),
        });
    }
    let zeros = vec![0.0; samples];
    let (values, breakpoints) = match input {
        Some(x) if x.len() == samples => (x.samples(), x.breakpoints()),
        Some(x) => {
            return Err(IdentError::Setup {
                setup: drive.setup(),
                reason: format!("{} drive samples for {samples} instants", x.len()),
            });
        }
        None => (zeros.as_slice(), &[][..]),
    };
    let (m, c, k) = (plant.mass, plant.damping, plant.stiffness);
    let model = Plant {
        theta: [m, c, k],
        drive,
    }
    .model();
    let sim = ExactSimulator::new(&model, dt, Hold::Cubic)?;
    let x0 = match (drive, values.first()) {
        (Drive::BaseDisplacement, Some(&z0)) => {
            SVector::<f64, 2>::new(initial.displacement, initial.velocity - c / m * z0)
        }
        _ => SVector::<f64, 2>::new(initial.displacement, initial.velocity),
    };
    let mut out = vec![vec![0.0; samples]; channels.len()];
    sim.simulate_with(
        &x0,
        &SampledInput {
            values,
            breakpoints,
        },
        |i, s| {
            let u = values[i];
            for (column, &(quantity, frame)) in out.iter_mut().zip(channels) {
                column[i] = channel_value(plant, drive, quantity, frame, [s[0], s[1]], u);
            }
        },
    )?;
    Ok(out)
}

/// One channel's value from the state `s` and the drive `u` (see [`simulate_channels`]
/// for what the state is).
fn channel_value(
    plant: &Parameters,
    drive: Drive,
    quantity: ResponseQuantity,
    frame: Frame,
    s: [f64; 2],
    u: f64,
) -> f64 {
    let (m, c, k) = (plant.mass, plant.damping, plant.stiffness);
    let [s0, s1] = s;
    match (drive, quantity, frame) {
        (Drive::BaseAcceleration, q, frame) => {
            // Relative motion y: y″ = −z″ − (c·y′ + k·y)/m; absolute x″ = y″ + z″.
            let relative_acc = -u - (c * s1 + k * s0) / m;
            match (q, frame) {
                (ResponseQuantity::Displacement, _) => s0,
                (ResponseQuantity::Velocity, _) => s1,
                (_, Frame::Relative) => relative_acc,
                _ => relative_acc + u,
            }
        }
        (Drive::BaseDisplacement, _, Frame::Absolute) => s0,
        (Drive::BaseDisplacement, _, Frame::Relative) => s0 - u,
        (_, ResponseQuantity::Displacement, _) => s0,
        (_, ResponseQuantity::Velocity, _) => s1,
        (_, ResponseQuantity::Acceleration, _) => (u - c * s1 - k * s0) / m,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Under a base acceleration the absolute acceleration is the relative one plus the
    /// base's, and a free decay's velocity is the derivative of its displacement.
    #[test]
    fn channels_are_consistent_with_each_other() {
        let p = Parameters::PAPER;
        let dt = 1e-3;
        let base =
            Excitation::from_samples(0.0, dt, (0..500).map(|i| (i as f64 * dt).sin()).collect())
                .expect("an excitation");
        let channels = [
            (ResponseQuantity::Acceleration, Frame::Relative),
            (ResponseQuantity::Acceleration, Frame::Absolute),
        ];
        let out = simulate_channels(
            &p,
            InitialState::REST,
            Drive::BaseAcceleration,
            Some(&base),
            500,
            dt,
            &channels,
        )
        .expect("simulates");
        for ((absolute, relative), z) in out[1].iter().zip(&out[0]).zip(base.samples()) {
            let expected = relative + z;
            assert!((absolute - expected).abs() <= 1e-15 * expected.abs().max(1.0));
        }
        let released = InitialState {
            displacement: 0.01,
            velocity: 0.0,
        };
        let both = [
            (ResponseQuantity::Displacement, Frame::Absolute),
            (ResponseQuantity::Velocity, Frame::Absolute),
        ];
        let out =
            simulate_channels(&p, released, Drive::None, None, 500, dt, &both).expect("simulates");
        for i in 1..499 {
            // Central difference: error (dt²/6)·x‴ ≤ (dt²/6)·ωn³·|x0| ≈ 5.5e-7 m/s.
            let derivative = (out[0][i + 1] - out[0][i - 1]) / (2.0 * dt);
            assert!(
                (derivative - out[1][i]).abs() < 6e-7,
                "{i}: {derivative} vs {}",
                out[1][i]
            );
        }
    }

    #[test]
    fn a_base_displacement_with_an_acceleration_channel_is_refused() {
        let channels = [(ResponseQuantity::Acceleration, Frame::Absolute)];
        let err = simulate_channels(
            &Parameters::PAPER,
            InitialState::REST,
            Drive::BaseDisplacement,
            None,
            10,
            0.01,
            &channels,
        )
        .expect_err("refused");
        assert!(
            err.to_string().contains("displacement channels only"),
            "{err}"
        );
    }
}
