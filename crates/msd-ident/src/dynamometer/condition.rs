//! One test condition of a dynamometer record, and its checks.

use crate::error::{IdentError, Result};
use serde::{Deserialize, Serialize};

/// Fewest whole stroke cycles a condition must hold: one cycle gives a loop, a second
/// lets its harmonic fit average and its noise be estimated.
///
/// ```
/// assert_eq!(msd_ident::dynamometer::MIN_CYCLES, 2);
/// ```
pub const MIN_CYCLES: usize = 2;

/// One test condition of a damper test machine: the imposed stroke and the measured
/// force, sampled together every `dt` seconds.
///
/// ```
/// use msd_ident::dynamometer::Condition;
/// let dt = 1e-3;
/// let x: Vec<f64> = (0..1000).map(|i| 0.01 * (2.0 * std::f64::consts::PI * 4.0 * i as f64 * dt).sin()).collect();
/// let force = x.iter().map(|x| 5000.0 * x).collect();
/// let c = Condition { name: "4 Hz".into(), dt, displacement: x, force, frequency_hz: Some(4.0) };
/// assert!(c.validate(5).is_ok());
/// ```
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Condition {
    /// Its name in the tables and messages (e.g. `"2 Hz, 25 mm"`).
    pub name: String,
    /// Sampling interval, s.
    pub dt: f64,
    /// The measured stroke x, m.
    pub displacement: Vec<f64>,
    /// The measured force F, N (the force the machine applies to the specimen).
    pub force: Vec<f64>,
    /// The imposed stroke frequency, Hz; `None`: estimated from the stroke (IEEE 1057
    /// four-parameter sine fit).
    #[serde(default)]
    pub frequency_hz: Option<f64>,
}

impl Condition {
    /// Checks that the condition can be analysed with `harmonics` harmonics: `dt` and the
    /// frequency finite and > 0, displacement and force of equal length, finite and not
    /// constant, at least [`MIN_CYCLES`] whole cycles (when the frequency is given), and
    /// the highest harmonic below the Nyquist frequency.
    pub fn validate(&self, harmonics: usize) -> Result<()> {
        let n = self.displacement.len();
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(self.invalid("dt", format!("{} s", self.dt), "a finite number > 0"));
        }
        if self.force.len() != n {
            return Err(self.invalid(
                "force",
                format!("{} samples", self.force.len()),
                format!("{n} samples, as many as the displacement"),
            ));
        }
        for (field, samples) in [("displacement", &self.displacement), ("force", &self.force)] {
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
        let n = self.displacement.len();
        let cycles = n as f64 * self.dt * f;
        if cycles < MIN_CYCLES as f64 - 1e-9 {
            return Err(self.invalid(
                "displacement",
                format!(
                    "{cycles:.2} cycles of {f} Hz ({n} samples of {} s)",
                    self.dt
                ),
                format!("at least {MIN_CYCLES} whole cycles"),
            ));
        }
        let nyquist = 0.5 / self.dt;
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
            condition: self.name.clone(),
            field,
            found,
            expected: expected.into(),
        }
    }

    /// The samples spanning the whole cycles of `f` Hz from the start: (cycles, n).
    pub(crate) fn whole_cycles(&self, f: f64) -> (usize, usize) {
        let n = self.displacement.len();
        let cycles = (n as f64 * self.dt * f + 1e-9).floor() as usize;
        let used = ((cycles as f64 / (f * self.dt)).round() as usize).min(n);
        (cycles, used)
    }
}
