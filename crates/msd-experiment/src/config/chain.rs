//! `[chain]`: a chain of masses tested in the time domain (`crate::chain`).

use msd_ident::{
    ResponseQuantity,
    chain::{ChainDrive, ChainParameters, ChainSensor, ChainSetup, LowPass},
    records::NoiseModel,
};
use serde::{Deserialize, Serialize};

/// A chain of masses, its sensors and the start of the fit.
///
/// ```
/// let config = msd_experiment::config::Config::load("../../configs/two-storey.toml".as_ref())?;
/// let chain = config.chain.expect("a [chain] config");
/// assert_eq!(chain.size(), 2);
/// # Ok::<(), msd_experiment::ExperimentError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChainSection {
    /// What drives the chain: `"force"` (on `force_at`) or `"base_acceleration"`.
    #[serde(default)]
    pub drive: ChainDrive,
    /// The mass the force acts on, from 1 at the ground. By default 1.
    #[serde(default = "first")]
    pub force_at: usize,
    /// The true chain (synthetic records): masses, dampers, springs from the ground out.
    /// Not with measured records (`[data]`), whose chain is what the fit finds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plant: Option<ChainParameters>,
    /// Where the fit starts.
    pub guess: ChainParameters,
    /// Masses (from 1) that are known: held at the guess's value.
    #[serde(default)]
    pub known_masses: Vec<usize>,
    /// The response channels.
    pub sensors: Vec<ChainSensorSection>,
    /// The drive sensor's white noise (a load cell's, N; a base accelerometer's, m/s²)
    /// added to the drive the fit is given; the chain feels the exact drive. By default 0.
    #[serde(default)]
    pub drive_sigma: f64,
    /// Which noise model sets the intervals: `"input_noise"` (the drive's noise
    /// estimated with the sensors') or `"white"` (the drive taken as exact). By default
    /// `"input_noise"` when `drive_sigma` > 0, `"white"` when the drive is exact by
    /// construction.
    #[serde(default)]
    pub noise_model: Option<NoiseModel>,
}

fn first() -> usize {
    1
}

fn one() -> f64 {
    1.0
}

fn is_one(x: &f64) -> bool {
    *x == 1.0
}

/// One sensor of a chain as tested: where, what, its noise, its delay and filter.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChainSensorSection {
    /// The mass it is on, from 1 at the ground.
    pub at: usize,
    /// `"displacement"`, `"velocity"` or `"acceleration"`. By default a displacement.
    #[serde(default)]
    pub quantity: ResponseQuantity,
    /// Noise σ of the synthetic record, in the channel's unit (≥ 0). By default 0.
    #[serde(default)]
    pub sigma: f64,
    /// Measured records (`[data]`): the sensor's column, by header name or 0-based index.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub column: Option<crate::config::Column>,
    /// Measured records: the factor applied to the column on reading (1e-3 for mm, 9.81
    /// for g). By default 1.
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub scale: f64,
    /// The sensor's true delay, s. By default none.
    #[serde(default)]
    pub delay: Option<f64>,
    /// Estimate the delay (the fit starts from 0) instead of taking `delay` as known.
    #[serde(default)]
    pub estimate_delay: bool,
    /// A low-pass filter in the sensor's path (the true one for the synthetic record).
    #[serde(default)]
    pub low_pass: Option<LowPass>,
    /// Estimate the filter's cut-off (the fit starts from `low_pass`'s) instead of
    /// taking it as known.
    #[serde(default)]
    pub estimate_cutoff: bool,
}

impl ChainSection {
    /// The number of masses (the true chain's, or the guess's with measured records).
    pub fn size(&self) -> usize {
        self.plant.as_ref().unwrap_or(&self.guess).masses.len()
    }

    /// What one sample of a chain's fit costs against one of a single mass's, from
    /// the simulation's size: each of the 1 + p simulated columns (the response and
    /// one sensitivity per fitted quantity) steps the state (2 per mass, plus each
    /// filter's order) through a dense matrix, so (1 + p)·states², divided by a single
    /// mass's (1 + 3)·2². Measured (release, one core) against the paper's fit (29 ms for
    /// 10,001 samples of two channels, 1.45 µs a channel's sample): two-storey 42 ms for
    /// 5000 samples (5.8 a sample, here 7), eight masses on one sensor 2.7 s (372, here
    /// 400).
    pub fn work_per_sample(&self) -> f64 {
        let n = self.size();
        let ground = |v: &[f64]| v.iter().filter(|&&x| x > 0.0).count();
        let fitted = (n - self.known_masses.len().min(n))
            + 2 * n
            + ground(&self.guess.ground_springs)
            + ground(&self.guess.ground_dampers)
            + (self.sensors.iter())
                .map(|s| usize::from(s.estimate_delay) + usize::from(s.estimate_cutoff))
                .sum::<usize>();
        let states = 2 * n
            + (self.sensors.iter())
                .filter_map(|s| s.low_pass.map(|f| usize::from(f.order)))
                .sum::<usize>();
        ((1 + fitted) * states * states) as f64 / 16.0
    }

    /// The noise model of the fit: as chosen, or by default the drive's noise model
    /// when the drive has noise, white when it is exact.
    pub fn noise_model(&self) -> NoiseModel {
        match self.noise_model {
            Some(chosen) => chosen,
            None if self.drive_sigma == 0.0 => NoiseModel::White,
            None => NoiseModel::InputNoise,
        }
    }

    /// The chain as tested: the records are simulated through these sensors.
    pub fn tested(&self, masses: usize) -> ChainSetup {
        ChainSetup {
            masses,
            drive: self.drive,
            force_at: self.force_at,
            sensors: self
                .sensors
                .iter()
                .map(|s| ChainSensor {
                    at: s.at,
                    quantity: s.quantity,
                    delay: s.delay,
                    estimate_delay: false,
                    low_pass: s.low_pass,
                    estimate_cutoff: false,
                })
                .collect(),
        }
    }

    /// The chain as planned: the true sensors, each estimated delay marked so (the plan
    /// predicts its interval at its true value).
    pub fn planned(&self) -> ChainSetup {
        let mut setup = self.tested(self.size());
        for (sensor, section) in setup.sensors.iter_mut().zip(&self.sensors) {
            sensor.estimate_delay = section.estimate_delay;
            sensor.estimate_cutoff = section.estimate_cutoff;
        }
        setup
    }

    /// The chain as fitted: an estimated delay starts from 0.
    pub fn fitted(&self) -> ChainSetup {
        let mut setup = self.tested(self.size());
        for (sensor, section) in setup.sensors.iter_mut().zip(&self.sensors) {
            if section.estimate_delay {
                sensor.delay = None;
                sensor.estimate_delay = true;
            }
            sensor.estimate_cutoff = section.estimate_cutoff;
        }
        setup
    }

    /// Checks the section; errors name the key under `chain.`.
    pub(crate) fn validate(&self, duration: f64) -> Result<(), (String, String)> {
        let keyed = |prefix: &str, e: msd_ident::IdentError| {
            let reason = match e {
                msd_ident::IdentError::Setup { reason, .. } => reason,
                other => other.to_string(),
            };
            let split = reason.find(" = ").or_else(|| reason.find(':')).unwrap_or(0);
            (
                format!("chain.{prefix}{}", &reason[..split]),
                reason[split..].to_string(),
            )
        };
        let n = self.size();
        if !(1..=msd_ident::chain::MAX_MASSES).contains(&n) {
            return Err((
                format!(
                    "chain.{}.masses",
                    if self.plant.is_some() {
                        "plant"
                    } else {
                        "guess"
                    }
                ),
                format!(
                    " has {n} values: expected 1 to {} masses",
                    msd_ident::chain::MAX_MASSES
                ),
            ));
        }
        if let Some(plant) = &self.plant {
            plant.validate(n).map_err(|e| keyed("plant.", e))?;
        }
        self.guess.validate(n).map_err(|e| keyed("guess.", e))?;
        self.fitted().validate().map_err(|e| keyed("", e))?;
        if let Some(&m) = self.known_masses.iter().find(|&&m| !(1..=n).contains(&m)) {
            return Err((
                "chain.known_masses".into(),
                format!(" contains {m}: expected masses from 1 to {n}"),
            ));
        }
        if !(self.drive_sigma.is_finite() && self.drive_sigma >= 0.0) {
            return Err((
                "chain.drive_sigma".into(),
                format!(" = {}: expected a finite number ≥ 0", self.drive_sigma),
            ));
        }
        for (i, s) in self.sensors.iter().enumerate() {
            if !(s.sigma.is_finite() && (0.0..=msd_ident::chain::LEVELS[1]).contains(&s.sigma)) {
                return Err((
                    format!("chain.sensors[{i}].sigma"),
                    format!(
                        " = {}: expected a number from 0 to {:e} (beyond, its squares leave double precision)",
                        super::show(s.sigma),
                        msd_ident::chain::LEVELS[1]
                    ),
                ));
            }
            if let Some(delay) = s.delay
                && !(delay.is_finite() && delay >= 0.0)
            {
                return Err((
                    format!("chain.sensors[{i}].delay"),
                    format!(
                        " = {}: expected a finite number of seconds ≥ 0",
                        super::show(delay)
                    ),
                ));
            }
            if let Some(filter) = s.low_pass
                && filter.cutoff_hz * duration < 1.0
            {
                return Err((
                    format!("chain.sensors[{i}].low_pass.cutoff_hz"),
                    format!(
                        " = {}: expected at least 1/duration = {} Hz (below, the sensor shows nothing of the motion but the record's mean)",
                        super::show(filter.cutoff_hz),
                        super::show(1.0 / duration)
                    ),
                ));
            }
            if let Some(delay) = s.delay
                && delay >= duration / 2.0
            {
                return Err((
                    format!("chain.sensors[{i}].delay"),
                    format!(
                        " = {delay}: expected less than half the record ({} s)",
                        duration / 2.0
                    ),
                ));
            }
        }
        Ok(())
    }
}
