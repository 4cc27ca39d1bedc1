//! [`Recording`]: one test run as every engine reads it — a uniform time grid, the
//! measured inputs and the response channels, each named, with its quantity, unit,
//! scale and measurement point ([`Dof`]).
//!
//! Readers (CSV, MATLAB, TDMS, UFF) and simulators produce it; the time-domain fits (a
//! chain of masses, one mass with any drive) and the frequency-response estimates take
//! it or a view of it.

use serde::{Deserialize, Serialize};

use crate::error::{Result, SignalError};
use crate::quantity::ResponseQuantity;

/// A measurement point and direction (as UFF numbers them: direction 1, 2, 3 = +X, +Y,
/// +Z, negative for the opposite sense). Displays as `node:direction`, e.g. `3:+2`.
///
/// ```
/// use msd_signal::Dof;
/// assert_eq!(Dof { node: 3, direction: -2 }.to_string(), "3:-2");
/// ```
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize,
)]
pub struct Dof {
    /// The node (point) number.
    pub node: u32,
    /// The direction: ±1, ±2, ±3 (translations), ±4, ±5, ±6 (rotations).
    pub direction: i32,
}

impl Dof {
    /// Whether the direction is one UFF numbers: ±1 … ±6.
    ///
    /// ```
    /// use msd_signal::Dof;
    /// assert!(Dof { node: 3, direction: -3 }.is_valid());
    /// assert!(!Dof { node: 3, direction: 0 }.is_valid());
    /// assert!(!Dof { node: 3, direction: 7 }.is_valid());
    /// ```
    pub fn is_valid(&self) -> bool {
        (1..=6).contains(&self.direction.unsigned_abs())
    }
}

impl std::fmt::Display for Dof {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{:+}", self.node, self.direction)
    }
}

/// What a channel measures: a force, or a motion ([`ResponseQuantity`]).
///
/// ```
/// use msd_signal::{Quantity, ResponseQuantity};
/// assert_eq!(Quantity::from(ResponseQuantity::Acceleration).si_unit(), "m/s²");
/// assert_eq!(Quantity::Force.motion(), None);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// A force (a load cell, an impact hammer), N.
    #[default]
    Force,
    /// A displacement, m.
    Displacement,
    /// A velocity, m/s.
    Velocity,
    /// An acceleration, m/s².
    Acceleration,
}

impl Quantity {
    /// The SI unit the samples are in.
    pub fn si_unit(self) -> &'static str {
        match self {
            Self::Force => "N",
            Self::Displacement => "m",
            Self::Velocity => "m/s",
            Self::Acceleration => "m/s²",
        }
    }

    /// The motion measured, or `None` for a force.
    pub fn motion(self) -> Option<ResponseQuantity> {
        match self {
            Self::Force => None,
            Self::Displacement => Some(ResponseQuantity::Displacement),
            Self::Velocity => Some(ResponseQuantity::Velocity),
            Self::Acceleration => Some(ResponseQuantity::Acceleration),
        }
    }
}

/// The quantity's name as configs spell it: `force`, `displacement`, ….
///
/// ```
/// assert_eq!(msd_signal::Quantity::Velocity.to_string(), "velocity");
/// ```
impl std::fmt::Display for Quantity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Force => "force",
            Self::Displacement => "displacement",
            Self::Velocity => "velocity",
            Self::Acceleration => "acceleration",
        })
    }
}

impl From<ResponseQuantity> for Quantity {
    fn from(q: ResponseQuantity) -> Self {
        match q {
            ResponseQuantity::Displacement => Self::Displacement,
            ResponseQuantity::Velocity => Self::Velocity,
            ResponseQuantity::Acceleration => Self::Acceleration,
        }
    }
}

/// Whether a motion channel measures the mass's motion itself or its motion relative to
/// the base. With a fixed base the two are the same. By default [`Frame::Absolute`].
///
/// ```
/// use msd_signal::Frame;
/// assert_eq!(serde_json::to_value(Frame::Relative)?, "relative");
/// assert_eq!((Frame::default(), Frame::Relative.to_string()), (Frame::Absolute, "relative".to_string()));
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Frame {
    /// The mass's motion x (an accelerometer on the mass, a laser from the ground).
    #[default]
    Absolute,
    /// The motion relative to the base, y = x − z (an LVDT between base and mass).
    Relative,
}

impl Frame {
    /// Whether this is [`Frame::Absolute`] (the default, left out of serialized channels).
    pub fn is_absolute(&self) -> bool {
        *self == Self::Absolute
    }
}

/// The frame's name as configs spell it: `absolute` or `relative`.
impl std::fmt::Display for Frame {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Absolute => "absolute",
            Self::Relative => "relative",
        })
    }
}

/// One named channel of a [`Recording`]: its samples in SI units.
///
/// ```
/// use msd_signal::{Channel, Quantity};
/// let c = Channel::new("load cell", Quantity::Force, vec![0.0, 1.5]);
/// assert_eq!((c.unit.as_str(), c.scale, c.dof), ("N", 1.0, None));
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Channel {
    /// The channel's name, for tables and messages.
    pub name: String,
    /// What it measures.
    pub quantity: Quantity,
    /// The unit of `samples` (the quantity's SI unit unless said otherwise).
    pub unit: String,
    /// The factor that took the file's numbers to `samples` (a sensitivity, a g in
    /// m/s²); 1 when they were read as they are.
    pub scale: f64,
    /// Where it measures, when the test names its points.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dof: Option<Dof>,
    /// Its measuring direction as a unit vector in the test geometry's axes (x, y, z)
    /// where it is oblique; `None` means along `dof`'s direction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<[f64; 3]>,
    /// For a motion, whether it is the mass's own or relative to the base.
    #[serde(default, skip_serializing_if = "Frame::is_absolute")]
    pub frame: Frame,
    /// One sample per grid instant.
    pub samples: Vec<f64>,
}

impl Channel {
    /// A channel in the quantity's SI unit, scale 1, at no named point.
    pub fn new(name: impl Into<String>, quantity: Quantity, samples: Vec<f64>) -> Self {
        Self {
            name: name.into(),
            quantity,
            unit: quantity.si_unit().into(),
            scale: 1.0,
            dof: None,
            direction: None,
            frame: Frame::Absolute,
            samples,
        }
    }

    /// The same channel in `frame` (a relative sensor, such as an LVDT between base and
    /// mass, is [`Frame::Relative`]).
    ///
    /// ```
    /// use msd_signal::{Channel, Frame, Quantity};
    /// let lvdt = Channel::new("lvdt", Quantity::Displacement, vec![0.0, 1e-3]).in_frame(Frame::Relative);
    /// assert_eq!(serde_json::to_value(&lvdt)?["frame"], "relative");
    /// # Ok::<(), serde_json::Error>(())
    /// ```
    pub fn in_frame(self, frame: Frame) -> Self {
        Self { frame, ..self }
    }

    /// The same channel at `dof`.
    pub fn at(self, dof: Dof) -> Self {
        Self {
            dof: Some(dof),
            ..self
        }
    }
}

/// One test run on a uniform grid tᵢ = t₀ + i·dt: the measured inputs (a force, a base
/// motion; none for a free decay or an output-only test) and the response channels,
/// all of one length.
///
/// ```
/// use msd_signal::{Channel, Quantity, Recording};
/// let run = Recording::new("run 1", 0.0, 1e-3)
///     .with_input(Channel::new("force", Quantity::Force, vec![0.0, 1.0, 0.5]))
///     .with_channel(Channel::new("laser", Quantity::Displacement, vec![0.0, 0.0, 1e-4]));
/// run.validate()?;
/// assert_eq!((run.len(), run.input(), run.time(2)), (3, &[0.0, 1.0, 0.5][..], 2e-3));
/// assert_eq!(run.prefix(2).channels[0].samples, [0.0, 0.0]);
/// let short = run.clone().with_channel(Channel::new("accelerometer", Quantity::Acceleration, vec![0.0]));
/// assert_eq!(short.validate().unwrap_err().to_string(),
///     "recording `run 1`: channel `accelerometer` has 1 samples, `force` has 3");
/// # Ok::<(), msd_signal::SignalError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Recording {
    /// The run's name, for tables and messages.
    pub name: String,
    /// Time of the first sample, s.
    pub t0: f64,
    /// Sampling interval, s.
    pub dt: f64,
    /// The measured inputs, in the order the engine reads them.
    #[serde(default)]
    pub inputs: Vec<Channel>,
    /// The response channels, in the order the engine reads them.
    #[serde(default)]
    pub channels: Vec<Channel>,
}

impl Recording {
    /// An empty recording on the grid `t0 + i·dt`.
    pub fn new(name: impl Into<String>, t0: f64, dt: f64) -> Self {
        Self {
            name: name.into(),
            t0,
            dt,
            ..Self::default()
        }
    }

    /// With one more measured input.
    pub fn with_input(mut self, input: Channel) -> Self {
        self.inputs.push(input);
        self
    }

    /// With one more response channel.
    pub fn with_channel(mut self, channel: Channel) -> Self {
        self.channels.push(channel);
        self
    }

    /// Every channel, the inputs first.
    pub fn all_channels(&self) -> impl Iterator<Item = &Channel> {
        self.inputs.iter().chain(&self.channels)
    }

    /// Every channel, mutably, the inputs first.
    pub fn all_channels_mut(&mut self) -> impl Iterator<Item = &mut Channel> {
        self.inputs.iter_mut().chain(&mut self.channels)
    }

    /// The number of samples (of the first channel; 0 without any).
    pub fn len(&self) -> usize {
        self.all_channels().next().map_or(0, |c| c.samples.len())
    }

    /// Whether it holds no sample.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The first measured input's samples (empty without one).
    pub fn input(&self) -> &[f64] {
        self.inputs.first().map_or(&[], |c| &c.samples)
    }

    /// Response channel `channel` against the first measured input: the pair the
    /// frequency-response estimates take ([`frf_estimate`](crate::frf_estimate)); `None`
    /// without an input or without that channel.
    ///
    /// ```
    /// use msd_signal::{Channel, FrfOptions, Quantity, Recording, frf_estimate};
    /// let force: Vec<f64> = (0..200).map(|i| if (5..8).contains(&i) { 10.0 } else { 0.0 }).collect();
    /// let gain: Vec<f64> = force.iter().map(|f| 2.0 * f).collect();
    /// let hit = Recording::new("hit 1", 0.0, 0.01)
    ///     .with_input(Channel::new("hammer", Quantity::Force, force.clone()))
    ///     .with_channel(Channel::new("response", Quantity::Displacement, gain));
    /// let pair = hit.pair(0).expect("an input and a channel");
    /// assert_eq!((pair.input, pair.output[6]), (&force[..], 20.0));
    /// assert!(hit.pair(1).is_none());
    /// let frf = frf_estimate(&[pair], 1.0 / hit.dt, &FrfOptions::default())?;
    /// assert!(frf.h.iter().all(|h| h.norm() == 0.0 || (h.re - 2.0).abs() < 1e-9));
    /// # Ok::<(), msd_signal::SignalError>(())
    /// ```
    pub fn pair(&self, channel: usize) -> Option<crate::frf::Record<'_>> {
        Some(crate::frf::Record {
            input: &self.inputs.first()?.samples,
            output: &self.channels.get(channel)?.samples,
        })
    }

    /// The responses' samples, in order.
    pub fn responses(&self) -> impl ExactSizeIterator<Item = &[f64]> {
        self.channels.iter().map(|c| c.samples.as_slice())
    }

    /// The time of sample `i`, s.
    pub fn time(&self, i: usize) -> f64 {
        self.t0 + self.dt * i as f64
    }

    /// The time of every sample, s: the grid's [`time`](Self::time)s.
    ///
    /// ```
    /// let run = msd_signal::Recording::new("run", 1.0, 0.5)
    ///     .with_channel(msd_signal::Channel::new("x", msd_signal::Quantity::Displacement, vec![0.0; 3]));
    /// assert_eq!(run.times(), [1.0, 1.5, 2.0]);
    /// ```
    pub fn times(&self) -> Vec<f64> {
        (0..self.len()).map(|i| self.time(i)).collect()
    }

    /// Samples `[a, b)` of every channel (clamped to the record), the grid starting at
    /// sample `a`.
    pub fn slice(&self, a: usize, b: usize) -> Self {
        let b = b.min(self.len());
        let a = a.min(b);
        let part = |c: &Channel| Channel {
            samples: c.samples[a..b].to_vec(),
            ..c.clone()
        };
        Self {
            name: self.name.clone(),
            t0: self.time(a),
            dt: self.dt,
            inputs: self.inputs.iter().map(part).collect(),
            channels: self.channels.iter().map(part).collect(),
        }
    }

    /// The first `n` samples.
    pub fn prefix(&self, n: usize) -> Self {
        self.slice(0, n)
    }

    /// Checks the grid (t₀ finite, dt finite and positive) and the channels (one
    /// length, finite samples, a positive finite scale).
    pub fn validate(&self) -> Result<()> {
        let bad = |what: String, value: f64, expected| {
            Err(SignalError::InvalidRecording {
                recording: self.name.clone(),
                what,
                value,
                expected,
            })
        };
        if !self.t0.is_finite() {
            return bad("t0".into(), self.t0, "a finite time, s");
        }
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return bad("dt".into(), self.dt, "a finite sampling interval > 0, s");
        }
        let Some(first) = self.all_channels().next() else {
            return Ok(());
        };
        for c in self.all_channels() {
            if c.samples.len() != first.samples.len() {
                return Err(SignalError::ChannelLength {
                    recording: self.name.clone(),
                    channel: c.name.clone(),
                    len: c.samples.len(),
                    first: first.name.clone(),
                    expected: first.samples.len(),
                });
            }
            if !(c.scale.is_finite() && c.scale > 0.0) {
                return bad(
                    format!("channel `{}` scale", c.name),
                    c.scale,
                    "a finite factor > 0",
                );
            }
            if let Some(i) = c.samples.iter().position(|v| !v.is_finite()) {
                return bad(
                    format!("channel `{}` sample {i}", c.name),
                    c.samples[i],
                    "a finite value",
                );
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run() -> Recording {
        Recording::new("run", 0.5, 0.01)
            .with_input(Channel::new("force", Quantity::Force, vec![1.0; 5]))
            .with_channel(
                Channel::new("laser", Quantity::Displacement, vec![0.0; 5]).at(Dof {
                    node: 2,
                    direction: 3,
                }),
            )
    }

    #[test]
    fn bad_grids_samples_and_scales_are_refused_naming_what() {
        let message = |r: Recording| r.validate().unwrap_err().to_string();
        let mut r = run();
        r.dt = 0.0;
        assert!(
            message(r)
                .contains("recording `run`: dt = 0: expected a finite sampling interval > 0, s")
        );
        let mut r = run();
        r.channels[0].samples[3] = f64::NAN;
        assert!(
            message(r).contains(
                "recording `run`: channel `laser` sample 3 = NaN: expected a finite value"
            )
        );
        let mut r = run();
        r.inputs[0].scale = -9.81;
        assert!(message(r).contains("channel `force` scale = -9.81"));
        assert!(Recording::new("empty", 0.0, 1.0).validate().is_ok());
    }

    #[test]
    fn slices_keep_the_grid_and_the_channels() {
        let r = run();
        let part = r.slice(2, 99);
        assert_eq!(
            (part.len(), part.t0, part.time(0)),
            (3, r.time(2), r.time(2))
        );
        assert_eq!(
            part.channels[0].dof,
            Some(Dof {
                node: 2,
                direction: 3
            })
        );
        assert_eq!(r.slice(4, 2).len(), 0);
        let text = serde_json::to_string(&r).unwrap();
        assert_eq!(serde_json::from_str::<Recording>(&text).unwrap(), r);
    }
}
