//! What a chain fit is given: the chain's layout, its drive, its sensors, its record.

use crate::error::{IdentError, Result};
use msd_signal::{Channel, Dof, Quantity, Recording, ResponseQuantity};
use serde::{Deserialize, Serialize};

/// What drives a chain of masses.
///
/// By default [`ChainDrive::Force`].
///
/// ```
/// use msd_ident::chain::ChainDrive;
/// assert_eq!(serde_json::to_value(ChainDrive::BaseAcceleration)?, "base_acceleration");
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ChainDrive {
    /// A measured force (N) on mass [`ChainSetup::force_at`]. Fixes the scale: every m,
    /// c and k can be identified.
    #[default]
    Force,
    /// A measured acceleration (m/s²) of the ground the first spring and damper stand
    /// on. Scaling every m, c and k together leaves the motion unchanged, so one mass
    /// (or more) must be known.
    BaseAcceleration,
}

/// A sensor's own dynamics: a low-pass filter with unit gain at 0 Hz (an anti-aliasing
/// filter, or the resonance of an accelerometer well above the band).
///
/// ```
/// use msd_ident::chain::LowPass;
/// let filter = LowPass { cutoff_hz: 50.0, ..LowPass::default() };
/// assert_eq!(filter.order, 1);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LowPass {
    /// The cut-off (first order) or natural frequency (second order), Hz (> 0).
    pub cutoff_hz: f64,
    /// 1 (ωc/(s + ωc)) or 2 (ωc²/(s² + 2ζc·ωc·s + ωc²)). By default 1.
    pub order: u8,
    /// ζc of a second-order filter. By default 1/√2 (Butterworth).
    pub damping_ratio: f64,
}

impl Default for LowPass {
    fn default() -> Self {
        Self {
            cutoff_hz: f64::INFINITY,
            order: 1,
            damping_ratio: std::f64::consts::FRAC_1_SQRT_2,
        }
    }
}

/// One response channel of a chain.
///
/// ```
/// use msd_ident::{chain::ChainSensor, ResponseQuantity};
/// let top = ChainSensor { at: 2, quantity: ResponseQuantity::Acceleration, ..ChainSensor::default() };
/// assert!(top.delay.is_none() && !top.estimate_delay);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ChainSensor {
    /// The mass it is on, numbered from 1 at the ground.
    pub at: usize,
    /// What it reads. Under a base acceleration, a displacement or velocity is relative
    /// to the ground and an acceleration absolute (an accelerometer's).
    pub quantity: ResponseQuantity,
    /// A known delay, s (≥ 0): the channel reads the motion this long ago. By default none.
    pub delay: Option<f64>,
    /// Estimate the delay (with an interval), starting from `delay` or 0.
    pub estimate_delay: bool,
    /// A low-pass filter in the sensor's path, known unless `estimate_cutoff`. By default
    /// none.
    pub low_pass: Option<LowPass>,
    /// Estimate the filter's cut-off (with an interval), starting from `low_pass`'s.
    pub estimate_cutoff: bool,
}

impl Default for ChainSensor {
    fn default() -> Self {
        Self {
            at: 1,
            quantity: ResponseQuantity::Displacement,
            delay: None,
            estimate_delay: false,
            low_pass: None,
            estimate_cutoff: false,
        }
    }
}

/// A chain of masses and how it was tested: spring and damper i join mass i to mass
/// i − 1, the first to the ground.
///
/// ```
/// use msd_ident::{chain::{ChainSensor, ChainSetup}, ResponseQuantity};
/// let setup = ChainSetup {
///     masses: 2,
///     force_at: 2,
///     sensors: vec![
///         ChainSensor { at: 1, quantity: ResponseQuantity::Acceleration, ..ChainSensor::default() },
///         ChainSensor { at: 2, quantity: ResponseQuantity::Acceleration, ..ChainSensor::default() },
///     ],
///     ..ChainSetup::default()
/// };
/// assert!(setup.validate().is_ok());
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ChainSetup {
    /// The number of masses, 1 to 8.
    pub masses: usize,
    /// What drives the chain.
    pub drive: ChainDrive,
    /// The mass a force acts on (with [`ChainDrive::Force`]), from 1.
    pub force_at: usize,
    /// The response channels, one or more.
    pub sensors: Vec<ChainSensor>,
}

impl Default for ChainSetup {
    fn default() -> Self {
        Self {
            masses: 1,
            drive: ChainDrive::Force,
            force_at: 1,
            sensors: vec![ChainSensor::default()],
        }
    }
}

/// The most masses a chain may have.
pub const MAX_MASSES: usize = 8;

impl ChainSetup {
    /// Checks the layout: 1 to [`MAX_MASSES`] masses, the force and every sensor on one
    /// of them, delays ≥ 0 and filters with a positive cut-off. The error names the key.
    pub fn validate(&self) -> Result<()> {
        let n = self.masses;
        if !(1..=MAX_MASSES).contains(&n) {
            return Err(setup_error(format!(
                "masses = {n}: expected 1 to {MAX_MASSES}"
            )));
        }
        if self.drive == ChainDrive::Force && !(1..=n).contains(&self.force_at) {
            return Err(setup_error(format!(
                "force_at = {}: expected a mass from 1 to {n}",
                self.force_at
            )));
        }
        if self.sensors.is_empty() {
            return Err(setup_error("sensors: expected at least one".into()));
        }
        for (i, sensor) in self.sensors.iter().enumerate() {
            if !(1..=n).contains(&sensor.at) {
                return Err(setup_error(format!(
                    "sensors[{i}].at = {}: expected a mass from 1 to {n}",
                    sensor.at
                )));
            }
            if let Some(delay) = sensor.delay
                && !(delay.is_finite() && delay >= 0.0)
            {
                return Err(setup_error(format!(
                    "sensors[{i}].delay = {}: expected a finite number of seconds ≥ 0",
                    show(delay)
                )));
            }
            if sensor.estimate_cutoff && sensor.low_pass.is_none() {
                return Err(setup_error(format!(
                    "sensors[{i}].estimate_cutoff = true: expected a low_pass to start from"
                )));
            }
            if let Some(filter) = sensor.low_pass {
                if !(filter.cutoff_hz.is_finite() && filter.cutoff_hz > 0.0) {
                    return Err(setup_error(format!(
                        "sensors[{i}].low_pass.cutoff_hz = {}: expected a finite frequency > 0",
                        filter.cutoff_hz
                    )));
                }
                if !matches!(filter.order, 1 | 2) {
                    return Err(setup_error(format!(
                        "sensors[{i}].low_pass.order = {}: expected 1 or 2",
                        filter.order
                    )));
                }
                if !(filter.damping_ratio.is_finite() && filter.damping_ratio > 0.0) {
                    return Err(setup_error(format!(
                        "sensors[{i}].low_pass.damping_ratio = {}: expected a finite number > 0",
                        filter.damping_ratio
                    )));
                }
            }
        }
        Ok(())
    }

    /// The same chain with ideal sensors: no delay, no filter. Fitting it too shows how
    /// much ignoring the sensors' dynamics biases the estimates.
    ///
    /// ```
    /// use msd_ident::{chain::{ChainSensor, ChainSetup}};
    /// let setup = ChainSetup { sensors: vec![ChainSensor { delay: Some(0.01), ..ChainSensor::default() }], ..ChainSetup::default() };
    /// assert_eq!(setup.with_ideal_sensors().sensors[0].delay, None);
    /// ```
    pub fn with_ideal_sensors(&self) -> Self {
        let mut ideal = self.clone();
        for sensor in &mut ideal.sensors {
            sensor.delay = None;
            sensor.estimate_delay = false;
            sensor.low_pass = None;
            sensor.estimate_cutoff = false;
        }
        ideal
    }
}

/// The RMS a record's series may have: squares of numbers outside this range leave
/// double precision (underflow to zero or overflow to infinity) in the fit's sums.
pub const LEVELS: [f64; 2] = [1e-150, 1e150];

/// Every mass, damper and spring of a chain, from the ground out.
///
/// ```
/// use msd_ident::chain::ChainParameters;
/// let p = ChainParameters { masses: vec![2.0, 1.0], dampers: vec![4.0, 2.0], springs: vec![2e4, 1e4], ..ChainParameters::default() };
/// assert!(p.validate(2).is_ok());
/// assert!(p.validate(3).is_err());
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChainParameters {
    /// m_i, kg (> 0).
    pub masses: Vec<f64>,
    /// c_i, N·s/m (> 0), joining mass i to mass i − 1 (the first to the ground).
    pub dampers: Vec<f64>,
    /// k_i, N/m (> 0), likewise.
    pub springs: Vec<f64>,
    /// Extra springs from each mass to the ground, N/m (≥ 0; 0 where there is none):
    /// one per mass, or none at all (the default). In a fit, those > 0 in the guess are
    /// estimated, the others held at 0.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ground_springs: Vec<f64>,
    /// Extra dampers from each mass to the ground, N·s/m, likewise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ground_dampers: Vec<f64>,
}

impl Default for ChainParameters {
    /// No mass: a start for `..ChainParameters::default()`.
    fn default() -> Self {
        Self {
            masses: Vec::new(),
            dampers: Vec::new(),
            springs: Vec::new(),
            ground_springs: Vec::new(),
            ground_dampers: Vec::new(),
        }
    }
}

impl ChainParameters {
    /// Checks that there are `n` of each, all finite and > 0 (the ground connections,
    /// when given, `n` of each, finite and ≥ 0).
    pub fn validate(&self, n: usize) -> Result<()> {
        for (name, values) in [
            ("ground_springs", &self.ground_springs),
            ("ground_dampers", &self.ground_dampers),
        ] {
            if !values.is_empty() && values.len() != n {
                return Err(setup_error(format!(
                    "{name} has {} values: expected none or one per mass ({n})",
                    values.len()
                )));
            }
            if let Some((i, v)) = values
                .iter()
                .enumerate()
                .find(|(_, v)| !(v.is_finite() && **v >= 0.0))
            {
                return Err(setup_error(format!(
                    "{name}[{i}] = {}: expected a finite number ≥ 0 (0: no connection)",
                    show(*v)
                )));
            }
        }
        for (name, values) in [
            ("masses", &self.masses),
            ("dampers", &self.dampers),
            ("springs", &self.springs),
        ] {
            if values.len() != n {
                return Err(setup_error(format!(
                    "{name} has {} values: expected one per mass ({n})",
                    values.len()
                )));
            }
            if let Some((i, v)) = values
                .iter()
                .enumerate()
                .find(|(_, v)| !(v.is_finite() && **v > 0.0))
            {
                let why = if name == "springs" && *v == 0.0 {
                    format!(
                        ": mass {} would not be connected to {} (expected a stiffness > 0)",
                        i + 1,
                        if i == 0 {
                            "the ground".to_string()
                        } else {
                            format!("mass {i}")
                        }
                    )
                } else {
                    ": expected a finite number > 0".to_string()
                };
                return Err(setup_error(format!("{name}[{i}] = {}{why}", show(*v))));
            }
        }
        Ok(())
    }

    /// The plant for frequency responses (force on `force_at`, response at
    /// `response_at`). [`ChainPlant`](super::ChainPlant) has no extra ground connections:
    /// they are left out.
    pub fn plant(&self, force_at: usize, response_at: usize) -> super::ChainPlant {
        super::ChainPlant {
            masses: self.masses.clone(),
            springs: self.springs.clone(),
            dampers: self.dampers.clone(),
            force_at,
            response_at,
        }
    }
}

impl ChainSetup {
    /// A recording of a test on this setup, every `dt` seconds from rest: the drive's
    /// samples (force on [`force_at`](Self::force_at), N, or base acceleration, m/s²,
    /// linear between samples) and one series per sensor, each channel named after its
    /// sensor (`mass 2 acceleration`), of its quantity, at its mass (DOF `mass:+1`).
    ///
    /// ```
    /// use msd_ident::chain::ChainSetup;
    /// use msd_signal::Quantity;
    /// let record = ChainSetup::default().recording("test", 1e-3, vec![0.0; 4], vec![vec![0.0; 4]]);
    /// assert_eq!((record.len(), record.channels[0].name.as_str()), (4, "mass 1 displacement"));
    /// assert_eq!(record.inputs[0].quantity, Quantity::Force);
    /// ```
    pub fn recording(
        &self,
        name: impl Into<String>,
        dt: f64,
        input: Vec<f64>,
        outputs: Vec<Vec<f64>>,
    ) -> Recording {
        let drive = match self.drive {
            ChainDrive::Force => Channel::new("force", Quantity::Force, input).at(Dof {
                node: self.force_at as u32,
                direction: 1,
            }),
            ChainDrive::BaseAcceleration => {
                Channel::new("base acceleration", Quantity::Acceleration, input).at(Dof {
                    node: 0,
                    direction: 1,
                })
            }
        };
        let mut record = Recording::new(name, 0.0, dt).with_input(drive);
        for (i, samples) in outputs.into_iter().enumerate() {
            record.channels.push(match self.sensors.get(i) {
                Some(sensor) => {
                    let quantity = Quantity::from(sensor.quantity);
                    let name = format!("mass {} {quantity}", sensor.at);
                    Channel::new(name, quantity, samples).at(Dof {
                        node: sensor.at as u32,
                        direction: 1,
                    })
                }
                None => Channel::new(format!("series {}", i + 1), Quantity::Displacement, samples),
            });
        }
        record
    }

    /// Checks `record` against the setup: its grid and samples, one measured drive of
    /// the drive's quantity, one channel per sensor of the sensor's quantity, filters and
    /// delays that the record's length can show.
    pub fn check_recording(&self, record: &Recording) -> Result<()> {
        record.validate()?;
        let drive = match self.drive {
            ChainDrive::Force => Quantity::Force,
            ChainDrive::BaseAcceleration => Quantity::Acceleration,
        };
        match record.inputs.as_slice() {
            [input] if input.quantity == drive => {}
            inputs => {
                return Err(setup_error(format!(
                    "recording `{}` has {} measured inputs ({}): expected one, the drive's {}",
                    record.name,
                    inputs.len(),
                    inputs
                        .iter()
                        .map(|c| format!("`{}` {}", c.name, c.quantity))
                        .collect::<Vec<_>>()
                        .join(", "),
                    drive
                )));
            }
        }
        if record.channels.len() != self.sensors.len() {
            return Err(setup_error(format!(
                "the record has {} output series: expected one per sensor ({})",
                record.channels.len(),
                self.sensors.len()
            )));
        }
        for (i, (channel, sensor)) in record.channels.iter().zip(&self.sensors).enumerate() {
            if channel.quantity != Quantity::from(sensor.quantity) {
                return Err(setup_error(format!(
                    "channel `{}` measures {}: sensors[{i}] reads {}",
                    channel.name,
                    channel.quantity,
                    Quantity::from(sensor.quantity)
                )));
            }
        }
        self.check_duration(record.dt * record.len() as f64)
    }

    /// Refuses sensor filters and delays a record of `duration` seconds cannot show.
    fn check_duration(&self, duration: f64) -> Result<()> {
        for (i, sensor) in self.sensors.iter().enumerate() {
            if let Some(filter) = sensor.low_pass
                && filter.cutoff_hz * duration < 1.0
            {
                return Err(setup_error(format!(
                    "sensors[{i}].low_pass.cutoff_hz = {} Hz: expected at least 1/duration = {} Hz (below, the sensor shows nothing of the motion but the record's mean)",
                    show(filter.cutoff_hz),
                    show(1.0 / duration)
                )));
            }
            if let Some(delay) = sensor.delay
                && delay >= duration / 2.0
            {
                return Err(setup_error(format!(
                    "sensors[{i}].delay = {} s: expected less than half the record ({} s)",
                    show(delay),
                    duration / 2.0
                )));
            }
        }
        Ok(())
    }
}

/// The first series of `record` whose RMS lies outside [`LEVELS`] — `None` for the
/// drive, `Some(i)` for sensor i — and that RMS; `None` when every one is inside.
///
/// ```
/// use msd_ident::chain::{ChainSetup, level_out_of_range};
/// let record = ChainSetup::default().recording("test", 1e-3, vec![0.0; 10], vec![vec![1.0; 10]]);
/// assert_eq!(level_out_of_range(&record), Some((None, 0.0)));
/// ```
pub fn level_out_of_range(record: &Recording) -> Option<(Option<usize>, f64)> {
    let inside = |level: f64| (LEVELS[0]..=LEVELS[1]).contains(&level);
    let drive = rms(record.input());
    if !inside(drive) {
        return Some((None, drive));
    }
    (record.responses().map(rms).enumerate())
        .find(|&(_, level)| !inside(level))
        .map(|(i, level)| (Some(i), level))
}

pub(crate) fn setup_error(reason: String) -> IdentError {
    IdentError::Setup {
        setup: "chain of masses",
        reason,
    }
}

/// A value as written in a message: plainly, or in exponent form when very large or small.
pub(crate) fn show(v: f64) -> String {
    if v != 0.0 && !(1e-4..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// Refuses a record with a series of no signal, or beyond double precision's squares.
pub(crate) fn levels(record: &Recording) -> Result<()> {
    match level_out_of_range(record) {
        None => Ok(()),
        Some((None, level)) if level == 0.0 && record.input().iter().all(|&u| u == 0.0) => Err(
            setup_error("the drive is zero throughout: nothing excites the chain".into()),
        ),
        Some((which, level)) => Err(setup_error(format!(
            "{}: its series has RMS {level:e}: expected between {:e} and {:e} (outside, its squares leave double precision)",
            which.map_or("the drive".to_string(), |i| format!("sensors[{i}]")),
            LEVELS[0],
            LEVELS[1]
        ))),
    }
}

/// The root mean square of `values`.
pub(crate) fn rms(values: &[f64]) -> f64 {
    (values.iter().map(|v| v * v).sum::<f64>() / values.len().max(1) as f64).sqrt()
}
