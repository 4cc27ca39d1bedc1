//! A [`Record`] read from an msd-signal [`Recording`]: the recording's input is the
//! drive (held between samples as an [`Excitation`]), its channels are the sensors.

use super::setup::Record;
use crate::data::Excitation;
use crate::error::{IdentError, Result};
use crate::plant::Drive;
use msd_signal::{Quantity, Recording};

impl Drive {
    /// What the measured input of a record under this drive measures (`None`: a free
    /// decay has no drive).
    pub fn input_quantity(self) -> Option<Quantity> {
        match self {
            Drive::Force => Some(Quantity::Force),
            Drive::BaseAcceleration => Some(Quantity::Acceleration),
            Drive::BaseDisplacement => Some(Quantity::Displacement),
            Drive::None => None,
        }
    }
}

impl Record {
    /// The record of one test run under `drive`: `recording`'s one measured input is the
    /// drive (a force, the base's acceleration or displacement; none for a free decay),
    /// its channels the sensors. The recording is checked first (grid, lengths, finite
    /// samples); an input of another quantity than the drive's is refused naming it.
    ///
    /// ```
    /// use msd_ident::{Channel, Drive, Quantity, Record};
    /// use msd_signal::Recording;
    /// let run = Recording::new("run 1", 0.0, 1e-3)
    ///     .with_input(Channel::new("load cell", Quantity::Force, vec![0.0, 1.0, 0.5]))
    ///     .with_channel(Channel::new("accelerometer", Quantity::Acceleration, vec![0.0, 0.2, 0.1]));
    /// let record = Record::from_recording(&run, Drive::Force)?;
    /// assert_eq!((record.excitation.samples(), record.channels.len()), (&[0.0, 1.0, 0.5][..], 1));
    /// let err = Record::from_recording(&run, Drive::BaseAcceleration).unwrap_err();
    /// assert_eq!(err.to_string(), "record `run 1`, channel `load cell`: it measures force: expected acceleration, the input of a base acceleration");
    /// # Ok::<(), msd_ident::IdentError>(())
    /// ```
    pub fn from_recording(recording: &Recording, drive: Drive) -> Result<Self> {
        recording.validate()?;
        let refuse = |channel: Option<&str>, reason: String| IdentError::InvalidRecord {
            record: recording.name.clone(),
            channel: channel.map(str::to_string),
            reason,
        };
        let samples = match (drive.input_quantity(), recording.inputs.as_slice()) {
            (None, []) => vec![0.0; recording.len()],
            (Some(q), [input]) if input.quantity == q => input.samples.clone(),
            (None, [input, ..]) => {
                return Err(refuse(
                    Some(&input.name),
                    "a free decay has no drive: expected no measured input".into(),
                ));
            }
            (Some(q), []) => {
                return Err(refuse(
                    None,
                    format!(
                        "no measured input: a {} needs one, measuring {q}",
                        drive.setup()
                    ),
                ));
            }
            (Some(q), [input]) => {
                return Err(refuse(
                    Some(&input.name),
                    format!(
                        "it measures {}: expected {q}, the input of a {}",
                        input.quantity,
                        drive.setup()
                    ),
                ));
            }
            (Some(_), [_, extra, ..]) => {
                return Err(refuse(
                    Some(&extra.name),
                    format!("a second measured input: a {} has one", drive.setup()),
                ));
            }
        };
        Ok(Record {
            name: recording.name.clone(),
            excitation: Excitation::from_samples(recording.t0, recording.dt, samples)?,
            channels: recording.channels.clone(),
        })
    }
}
