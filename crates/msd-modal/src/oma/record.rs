//! An output-only record: channels sampled together, each with what it measures and
//! where, and the reference channels.

use serde::{Deserialize, Serialize};

use msd_modal_core::error::{ModalError, Result};
use msd_modal_core::mode::Dof;
use msd_signal::{Channel, Quantity, Recording};

/// The power of λ that turns a displacement into a channel's quantity (0, 1, 2): shapes
/// are reported as displacement shapes, a velocity channel's entry divided by the pole
/// λ, an acceleration's by λ². [`OutputRecord::check`] refuses a force channel.
pub(crate) fn order(quantity: Quantity) -> i32 {
    match quantity {
        Quantity::Displacement | Quantity::Force => 0,
        Quantity::Velocity => 1,
        Quantity::Acceleration => 2,
    }
}

/// The DOF a channel's shape entry is reported at ([`OutputRecord::check`] refuses a
/// channel without one).
pub(crate) fn dof(channel: &Channel) -> Dof {
    channel.dof.unwrap_or_default()
}

/// An accelerometer's channel at `dof` (most ambient records are accelerometers').
///
/// ```
/// use msd_modal::{Dof, accelerometer};
/// let c = accelerometer("a1", Dof { node: 1, direction: 3 }, vec![0.0, 1.0]);
/// assert_eq!((c.unit.as_str(), c.dof), ("m/s²", Some(Dof { node: 1, direction: 3 })));
/// ```
pub fn accelerometer(name: impl Into<String>, dof: Dof, samples: Vec<f64>) -> Channel {
    Channel::new(name, Quantity::Acceleration, samples).at(dof)
}

/// The unit vector of a measuring direction given as azimuth and elevation in degrees
/// (azimuth from +x towards +y in the horizontal plane, elevation up from it).
///
/// ```
/// let [x, y, z] = msd_modal::direction_from_angles(90.0, 0.0);
/// assert!(x.abs() < 1e-12 && (y - 1.0).abs() < 1e-12 && z.abs() < 1e-12);
/// ```
pub fn direction_from_angles(azimuth_deg: f64, elevation_deg: f64) -> [f64; 3] {
    let (az, el) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
    [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()]
}

/// Channels sampled together with no measured input (an ambient or operational record),
/// each at its DOF, and which of them are the references.
///
/// ```
/// use msd_modal::{Dof, OutputRecord, accelerometer};
/// let channel = |i: u32| accelerometer(format!("a{i}"), Dof { node: i, direction: 1 },
///     (0..100).map(|t| ((t * (i as usize + 3)) as f64).sin()).collect());
/// let record = OutputRecord::new(100.0, vec![channel(1), channel(2)]).with_references(vec![1]);
/// assert!(record.check().is_ok());
/// assert_eq!(record.sample_rate_hz(), 100.0);
/// let bad = OutputRecord { references: vec![2], ..record };
/// assert!(bad.check().unwrap_err().to_string().contains("references"));
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OutputRecord {
    /// The channels (no measured input), each with as many samples, on one grid.
    pub recording: Recording,
    /// The reference channels' indices into the recording's channels; empty = every
    /// channel.
    pub references: Vec<usize>,
}

impl OutputRecord {
    /// `channels` sampled at `sample_rate_hz` from t = 0, every channel a reference.
    pub fn new(sample_rate_hz: f64, channels: Vec<Channel>) -> Self {
        Self {
            recording: Recording {
                channels,
                ..Recording::new("output-only record", 0.0, sample_rate_hz.recip())
            },
            references: Vec::new(),
        }
    }

    /// With the reference channels `references` (indices into the channels).
    pub fn with_references(self, references: Vec<usize>) -> Self {
        Self { references, ..self }
    }

    /// Samples per second, Hz.
    pub fn sample_rate_hz(&self) -> f64 {
        self.recording.dt.recip()
    }

    /// The channels.
    pub fn channels(&self) -> &[Channel] {
        &self.recording.channels
    }

    /// A band's lower edge below the record's Nyquist frequency.
    pub(crate) fn check_band(&self, band_hz: Option<[f64; 2]>) -> Result<()> {
        match band_hz {
            Some([low, _]) if low >= 0.5 * self.sample_rate_hz() => {
                Err(ModalError::InvalidParameter {
                    name: "band_hz[0]",
                    value: low,
                    expected: "a frequency below the Nyquist frequency (half the sample rate)",
                })
            }
            _ => Ok(()),
        }
    }

    /// Each channel less its mean, divided by the root mean square deviation of the
    /// channels of its quantity (channels of one quantity keep their relative sizes, so
    /// that a structure's modes stay orthogonal; quantities of different units become
    /// comparable); and those divisors.
    pub(crate) fn standardised_by_quantity(&self) -> (Vec<Vec<f64>>, Vec<f64>) {
        let (centred, sds) = self.standardised();
        let common: Vec<f64> = self
            .channels()
            .iter()
            .map(|c| {
                let (sum, count) = self
                    .channels()
                    .iter()
                    .zip(&sds)
                    .filter(|(d, _)| d.quantity == c.quantity)
                    .fold((0.0, 0.0), |(s, n), (_, sd)| (s + sd * sd, n + 1.0));
                (sum / count).sqrt()
            })
            .collect();
        let scaled = centred
            .iter()
            .zip(sds.iter().zip(&common))
            .map(|(x, (sd, c))| x.iter().map(|v| v * sd / c).collect())
            .collect();
        (scaled, common)
    }

    /// Each channel less its mean, divided by its standard deviation; and those
    /// deviations.
    pub(crate) fn standardised(&self) -> (Vec<Vec<f64>>, Vec<f64>) {
        self.channels()
            .iter()
            .map(|c| {
                let n = c.samples.len() as f64;
                let mean = c.samples.iter().sum::<f64>() / n;
                let sd = (c.samples.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
                (c.samples.iter().map(|v| (v - mean) / sd).collect(), sd)
            })
            .unzip()
    }

    /// Samples per channel.
    pub fn len(&self) -> usize {
        self.recording.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The references' indices (every channel where none are named).
    pub fn reference_indices(&self) -> Vec<usize> {
        if self.references.is_empty() {
            (0..self.channels().len()).collect()
        } else {
            self.references.clone()
        }
    }

    /// Checks the rate, the channels' lengths and values and the references, naming the
    /// first channel or value that is wrong.
    pub fn check(&self) -> Result<()> {
        if !(self.sample_rate_hz().is_finite() && self.sample_rate_hz() > 0.0) {
            return Err(invalid(
                "sample_rate_hz",
                self.sample_rate_hz(),
                "a positive rate",
            ));
        }
        if self.channels().len() < 2 {
            return Err(invalid(
                "channels",
                self.channels().len() as f64,
                "at least two channels (one channel has no shape and no references to spare)",
            ));
        }
        let n = self.len();
        for c in self.channels() {
            if c.samples.len() != n {
                return Err(ModalError::LengthMismatch {
                    what: "a channel of the record",
                    expected: n,
                    got: c.samples.len(),
                });
            }
            check_channel(c)?;
        }
        if let Some(input) = self.recording.inputs.first() {
            return Err(ModalError::BadChannel {
                channel: input.name.clone(),
                reason: "a measured input: an output-only record has none (fit FRFs instead)"
                    .into(),
            });
        }
        for &r in &self.references {
            if r >= self.channels().len() {
                return Err(invalid(
                    "references",
                    r as f64,
                    "the index of a channel of the record",
                ));
            }
        }
        Ok(())
    }
}

/// A motion channel at a DOF whose values are all finite and not all equal.
fn check_channel(c: &Channel) -> Result<()> {
    let bad = |reason: String| ModalError::BadChannel {
        channel: c.name.clone(),
        reason,
    };
    if c.quantity == Quantity::Force {
        return Err(bad("it measures a force: an output-only analysis reads motions (displacement, velocity, acceleration)".into()));
    }
    if c.dof.is_none() {
        return Err(bad(
            "it has no DOF: an output-only analysis reports its shapes at DOFs".into(),
        ));
    }
    if let Some(t) = c.samples.iter().position(|v| !v.is_finite()) {
        return Err(ModalError::BadChannel {
            channel: c.name.clone(),
            reason: format!("sample {t} is {}", c.samples[t]),
        });
    }
    let first = c.samples.first().copied().unwrap_or(0.0);
    if c.samples.iter().all(|&v| v == first) {
        return Err(ModalError::BadChannel {
            channel: c.name.clone(),
            reason: format!("it is constant ({first}) throughout: a dead sensor"),
        });
    }
    Ok(())
}

fn invalid(name: &'static str, value: f64, expected: &'static str) -> ModalError {
    ModalError::InvalidParameter {
        name,
        value,
        expected,
    }
}
