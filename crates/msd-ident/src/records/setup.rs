//! What a joint fit is given: the drive, the records with their channels, the options.

use super::model::OutputKind;
use crate::input_noise::NoiseModel;
use crate::plant::Drive;
use crate::residuals::ResidualOptions;
use crate::{
    data::Excitation,
    error::{IdentError, Result},
    params::{KnownParameter, Parameters},
};
use msd_ode::Hold;
use msd_opt::LevenbergMarquardtOptions;
use msd_signal::{Channel, Frame, ResponseQuantity};
use serde::{Deserialize, Serialize};

/// One test run: the drive's samples and the sensors' records.
///
/// Each channel (an [`msd_signal::Channel`] measuring a motion, absolute or relative to
/// the base) has its own offset in each record (the sensor's zero): a velocity or
/// acceleration channel does not see a displacement sensor's offset, and the reverse.
/// Channels of the same name in several records share one noise level.
///
/// ```
/// use msd_ident::{Channel, Excitation, Quantity, Record};
/// // A pluck: no drive, so the excitation only gives the grid (100 samples of 10 ms).
/// let grid = Excitation::from_samples(0.0, 0.01, vec![0.0; 100])?;
/// let samples = (0..100).map(|i| (-0.1 * i as f64).exp() * (0.5 * i as f64).cos()).collect();
/// let record = Record { name: "pluck 1".into(), excitation: grid,
///     channels: vec![Channel::new("laser", Quantity::Displacement, samples)] };
/// assert_eq!(record.channels[0].quantity, Quantity::Displacement);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// The run's name, for the tables and the messages.
    pub name: String,
    /// The drive's samples (force, base acceleration or base displacement) with the
    /// sampling grid; for [`Drive::None`] only its grid is used.
    pub excitation: Excitation,
    /// At least one channel, each measuring the mass's motion.
    pub channels: Vec<Channel>,
}

/// Options of [`fit_records`](crate::records::fit_records).
///
/// ```
/// use msd_ident::{Drive, KnownParameter, RecordsOptions};
/// let options = RecordsOptions { drive: Drive::None, known: KnownParameter::Mass(2.5), ..Default::default() };
/// assert!(options.validate().is_ok());
/// let toml = "drive = \"base_acceleration\"\nknown = { mass = 2.5 }\nhold = \"first\"";
/// let read: RecordsOptions = toml::from_str(toml).expect("valid");
/// assert_eq!(read.drive, Drive::BaseAcceleration);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RecordsOptions {
    /// What drives the plant. By default a force on the mass.
    pub drive: Drive,
    /// A known mass or static stiffness: with a force drive it is held fixed, with the
    /// other drives it turns ωn and ζ into m, c and k. By default nothing is known.
    pub known: KnownParameter,
    /// Refuse a setup that cannot give m, c and k (instead of giving ωn and ζ only).
    /// By default false.
    pub require_physical: bool,
    /// θ₀; with the base drives and free decays only ωn and ζ of it matter. By default
    /// none: ARX poles of each channel (the classroom estimates of a free decay), the
    /// one with the smallest cost.
    pub initial_guess: Option<Parameters>,
    /// Estimate each record's initial state (else each starts at rest). By default true;
    /// a free decay needs it.
    pub estimate_initial_state: bool,
    /// Estimate each channel's offset in each record (else zero). By default true.
    pub estimate_offset: bool,
    /// With two records or more, predict each record by the parameters fitted to the
    /// others. By default true.
    pub leave_one_out: bool,
    /// With a single record, the share of its samples at the end held out and predicted
    /// by the plant refitted to the rest, a check on fresh data (the estimates still use
    /// every sample). 0 for none; by default 0.2.
    pub hold_out: f64,
    /// The residual tests (whiteness, correlation with the drive) of the fit and of
    /// the validation. By default 25 lags at 99 %, as MATLAB's `resid`.
    pub residuals: ResidualOptions,
    /// How the drive is reconstructed between samples. By default cubic.
    #[serde(with = "crate::simulate::hold_serde")]
    pub hold: Hold,
    /// Which noise model sets the intervals: by default `input_noise`, the drive's
    /// noise estimated with the sensors' (see [`NoiseModel`]).
    pub noise_model: NoiseModel,
    /// Most weighted least-squares passes (each re-estimates the channels' noise levels
    /// from the residuals); one suffices with a single sensor. By default 10.
    pub max_passes: usize,
    /// The optimiser of each pass. By default MINPACK's settings.
    #[serde(skip)]
    pub levenberg_marquardt: LevenbergMarquardtOptions,
}

impl Default for RecordsOptions {
    fn default() -> Self {
        Self {
            drive: Drive::Force,
            known: KnownParameter::None,
            require_physical: false,
            initial_guess: None,
            estimate_initial_state: true,
            estimate_offset: true,
            leave_one_out: true,
            hold_out: 0.2,
            residuals: ResidualOptions::default(),
            hold: Hold::Cubic,
            noise_model: NoiseModel::InputNoise,
            max_passes: 10,
            levenberg_marquardt: LevenbergMarquardtOptions::default(),
        }
    }
}

impl RecordsOptions {
    /// Checks the options alone (the records are checked by the fit), naming the first
    /// one out of range or the combination that cannot work.
    pub fn validate(&self) -> Result<()> {
        self.known.validate()?;
        if let Some(guess) = &self.initial_guess {
            guess.validate()?;
        }
        if !(0.0..=0.5).contains(&self.hold_out) {
            return Err(IdentError::InvalidParameter {
                name: "hold_out",
                value: self.hold_out,
                expected: "a share of the record from 0 (none) to 0.5",
            });
        }
        self.residuals.validate()?;
        if self.max_passes == 0 {
            return Err(IdentError::InvalidParameter {
                name: "max_passes",
                value: 0.0,
                expected: "at least 1",
            });
        }
        self.levenberg_marquardt.validate()?;
        self.check_setup()
    }

    fn check_setup(&self) -> Result<()> {
        let setup = self.drive.setup();
        if self.drive == Drive::None && !self.estimate_initial_state {
            return Err(IdentError::Setup {
                setup,
                reason: "nothing moves the mass: a free decay needs its initial state estimated; set `estimate_initial_state = true`".into(),
            });
        }
        if self.require_physical
            && !self.drive.estimates_mass()
            && self.known == KnownParameter::None
        {
            return Err(IdentError::Setup {
                setup,
                reason: "m, c and k are not separately identifiable without a known mass or stiffness (every plant with the same c/m and k/m moves the same way): set `known` to the weighed mass or the static stiffness, or ask for ωn and ζ only".into(),
            });
        }
        Ok(())
    }

    /// How `channel` is computed from the model's state under this drive, or why it
    /// cannot be.
    pub(crate) fn output_kind(&self, record: &str, channel: &Channel) -> Result<OutputKind> {
        use Frame::{Absolute, Relative};
        use ResponseQuantity::{Acceleration, Displacement, Velocity};
        let refuse = |reason: String| IdentError::InvalidRecord {
            record: record.to_string(),
            channel: Some(channel.name.clone()),
            reason,
        };
        let Some(motion) = channel.quantity.motion() else {
            return Err(refuse(format!(
                "it measures {}: a record's channels measure the mass's motion (the drive is the record's excitation)",
                channel.quantity
            )));
        };
        let kind = match (self.drive, channel.frame, motion) {
            (Drive::Force | Drive::None, _, Displacement) => Some(OutputKind::Displacement),
            (Drive::Force | Drive::None, _, Velocity) => Some(OutputKind::Velocity),
            (Drive::Force | Drive::None, _, Acceleration) => Some(OutputKind::Acceleration),
            (Drive::BaseAcceleration, Relative, Displacement) => Some(OutputKind::Displacement),
            (Drive::BaseAcceleration, Relative, Velocity) => Some(OutputKind::Velocity),
            (Drive::BaseAcceleration, Relative, Acceleration) => Some(OutputKind::Acceleration),
            (Drive::BaseAcceleration, Absolute, Acceleration) => {
                Some(OutputKind::AbsoluteAcceleration)
            }
            (Drive::BaseDisplacement, Absolute, Displacement) => Some(OutputKind::Displacement),
            (Drive::BaseDisplacement, Absolute, Velocity) => Some(OutputKind::AbsoluteVelocity),
            (Drive::BaseDisplacement, Relative, Displacement) => {
                Some(OutputKind::RelativeDisplacement)
            }
            _ => None,
        };
        kind.ok_or_else(|| {
            refuse(format!(
                "the {} {} cannot be predicted from a {}: {}",
                channel.frame,
                channel.quantity,
                self.drive.setup(),
                supported(self.drive)
            ))
        })
    }
}

fn supported(drive: Drive) -> &'static str {
    match drive {
        Drive::BaseAcceleration => {
            "it supports relative displacement, velocity and acceleration and absolute acceleration (the absolute displacement and velocity need the base's own, which an accelerometer does not give)"
        }
        Drive::BaseDisplacement => {
            "it supports absolute displacement, absolute velocity and relative displacement (the others need the derivative of the measured base displacement)"
        }
        Drive::Force | Drive::None => "it supports displacement, velocity and acceleration",
    }
}
