//! One test condition of a dynamometer record, and its checks.

use super::recording::{machine_recording, stroke_and_force};
use crate::error::{IdentError, Result};
use msd_signal::Recording;
use serde::{Deserialize, Serialize};

/// Fewest whole stroke cycles a condition must hold: one cycle gives a loop, a second
/// lets its harmonic fit average and its noise be estimated.
///
/// ```
/// assert_eq!(msd_ident::dynamometer::MIN_CYCLES, 2);
/// ```
pub const MIN_CYCLES: usize = 2;

/// One test condition of a damper test machine: a recording of the imposed stroke and
/// the measured force (see [`machine_recording`]) and the stroke's frequency.
///
/// ```
/// use msd_ident::dynamometer::Condition;
/// let dt = 1e-3;
/// let x: Vec<f64> = (0..1000).map(|i| 0.01 * (2.0 * std::f64::consts::PI * 4.0 * i as f64 * dt).sin()).collect();
/// let force = x.iter().map(|x| 5000.0 * x).collect();
/// let c = Condition::new("4 Hz", dt, x, force).at_frequency(4.0);
/// assert!(c.validate(5).is_ok());
/// assert_eq!((c.name(), c.displacement().len(), c.force()[0]), ("4 Hz", 1000, 0.0));
/// ```
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Condition {
    /// The stroke x (m, the input) and the force F (N, the force the machine applies to
    /// the specimen), named after the condition (e.g. `"2 Hz, 25 mm"`).
    pub recording: Recording,
    /// The imposed stroke frequency, Hz; `None`: estimated from the stroke (IEEE 1057
    /// four-parameter sine fit).
    #[serde(default)]
    pub frequency_hz: Option<f64>,
}

impl Condition {
    /// The condition `name`: the stroke x (m) and the force F (N) sampled every `dt`
    /// seconds, its frequency to be estimated from the stroke.
    pub fn new(name: impl Into<String>, dt: f64, displacement: Vec<f64>, force: Vec<f64>) -> Self {
        Self {
            recording: machine_recording(name, dt, displacement, force),
            frequency_hz: None,
        }
    }

    /// The same condition at the imposed stroke frequency `f`, Hz.
    pub fn at_frequency(self, f: f64) -> Self {
        Self {
            frequency_hz: Some(f),
            ..self
        }
    }

    /// Its name in the tables and messages.
    pub fn name(&self) -> &str {
        &self.recording.name
    }

    /// Sampling interval, s.
    pub fn dt(&self) -> f64 {
        self.recording.dt
    }

    /// The measured stroke x, m (empty when the recording has no stroke input).
    pub fn displacement(&self) -> &[f64] {
        stroke_and_force(&self.recording).map_or(&[], |(x, _)| x)
    }

    /// The measured force F, N (empty when the recording has no force channel).
    pub fn force(&self) -> &[f64] {
        stroke_and_force(&self.recording).map_or(&[], |(_, f)| f)
    }

    /// Checks that the condition can be analysed with `harmonics` harmonics: `dt` and the
    /// frequency finite and > 0, displacement and force of equal length, finite and not
    /// constant, at least [`MIN_CYCLES`] whole cycles (when the frequency is given), and
    /// the highest harmonic below the Nyquist frequency.
    pub fn validate(&self, harmonics: usize) -> Result<()> {
        let (displacement, force) = stroke_and_force(&self.recording)?;
        let (n, dt) = (displacement.len(), self.dt());
        if !(dt.is_finite() && dt > 0.0) {
            return Err(self.invalid("dt", format!("{dt} s"), "a finite number > 0"));
        }
        if force.len() != n {
            return Err(self.invalid(
                "force",
                format!("{} samples", force.len()),
                format!("{n} samples, as many as the displacement"),
            ));
        }
        for (field, samples) in [("displacement", displacement), ("force", force)] {
            self.check_samples(field, samples)?;
        }
        if let Some(f) = self.frequency_hz {
            self.check_frequency(f, harmonics)?;
        }
        Ok(())
    }

    /// Finite, at least 2, not all equal.
    fn check_samples(&self, field: &'static str, samples: &[f64]) -> Result<()> {
        if samples.len() < 2 {
            let found = format!("{} samples", samples.len());
            return Err(self.invalid(field, found, "a record of whole stroke cycles"));
        }
        if let Some((i, v)) = samples.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(self.invalid(field, format!("sample {i} is {v}"), "a finite number"));
        }
        let first = samples[0];
        if samples.iter().all(|&v| v == first) {
            let expected = match field {
                "displacement" => "an imposed stroke that moves",
                _ => "a force that varies with the stroke",
            };
            return Err(self.invalid(field, format!("constant (every sample {first})"), expected));
        }
        Ok(())
    }

    /// The frequency itself, the whole cycles it gives and its highest harmonic.
    pub(crate) fn check_frequency(&self, f: f64, harmonics: usize) -> Result<()> {
        if !(f.is_finite() && f > 0.0) {
            return Err(self.invalid("frequency_hz", format!("{f} Hz"), "a finite number > 0"));
        }
        let (n, dt) = (self.displacement().len(), self.dt());
        let cycles = n as f64 * dt * f;
        if cycles < MIN_CYCLES as f64 - 1e-9 {
            return Err(self.invalid(
                "displacement",
                format!("{cycles:.2} cycles of {f} Hz ({n} samples of {dt} s)"),
                format!("at least {MIN_CYCLES} whole cycles"),
            ));
        }
        let nyquist = 0.5 / dt;
        if harmonics as f64 * f >= nyquist {
            return Err(self.invalid(
                "frequency_hz",
                format!(
                    "{harmonics} harmonics of {f} Hz reach {} Hz",
                    harmonics as f64 * f
                ),
                format!("below the Nyquist frequency {nyquist} Hz (a finer dt or fewer harmonics)"),
            ));
        }
        Ok(())
    }

    /// The located error of `field`.
    pub(crate) fn invalid(
        &self,
        field: &'static str,
        found: String,
        expected: impl Into<String>,
    ) -> IdentError {
        IdentError::InvalidCondition {
            condition: self.name().to_string(),
            field,
            found,
            expected: expected.into(),
        }
    }

    /// The samples spanning the whole cycles of `f` Hz from the start: (cycles, n).
    pub(crate) fn whole_cycles(&self, f: f64) -> (usize, usize) {
        let (n, dt) = (self.displacement().len(), self.dt());
        let cycles = (n as f64 * dt * f + 1e-9).floor() as usize;
        let used = ((cycles as f64 / (f * dt)).round() as usize).min(n);
        (cycles, used)
    }
}
