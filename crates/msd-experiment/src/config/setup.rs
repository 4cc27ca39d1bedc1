//! The optional `[setup]` section: what drives the plant (a force on the mass, the
//! base's motion, an imposed stroke, or nothing: a free decay) and what the sensors
//! measure (displacement, velocity, acceleration; several channels at once), for the
//! synthetic plant and for measured `[data]` alike. Without it a config is the paper's
//! setup: a force and one displacement channel.
//!
//! ```
//! use msd_experiment::config::{ExcitationKind, Quantity, SetupSection};
//! let setup: SetupSection = toml::from_str(r#"
//!     excitation = "force"
//!     responses = [
//!         { quantity = "displacement", sigma = 2.5e-3 },
//!         { quantity = "acceleration", sigma = 0.05, unit = "g", scale = 9.80665 },
//!     ]
//!     records = 3
//! "#).unwrap();
//! assert_eq!(setup.excitation, ExcitationKind::Force);
//! assert_eq!(setup.responses[1].quantity, Quantity::Acceleration);
//! assert_eq!(setup.responses[1].channel_name(), "acceleration");
//! ```

use super::{
    Column, Config, Kind, check_finite, check_non_negative, check_positive, default_one,
    validate_plant, validate_time,
};
use serde::{Deserialize, Serialize};

/// What drives the plant.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ExcitationKind {
    /// A measured force on the mass (a shaker through a force cell, a hammer).
    #[default]
    Force,
    /// The base moves; its displacement z is measured.
    BaseDisplacement,
    /// The base moves; its acceleration z″ is measured (a shaker table's accelerometer).
    BaseAcceleration,
    /// A stroke x(t) is imposed and measured, the force is measured (a damper test
    /// machine).
    ImposedDisplacement,
    /// Nothing: the mass is released and rings down (a free decay).
    None,
}

impl ExcitationKind {
    /// The name as written in a config.
    pub fn name(&self) -> &'static str {
        match self {
            ExcitationKind::Force => "force",
            ExcitationKind::BaseDisplacement => "base_displacement",
            ExcitationKind::BaseAcceleration => "base_acceleration",
            ExcitationKind::ImposedDisplacement => "imposed_displacement",
            ExcitationKind::None => "none",
        }
    }

    /// The drive's SI unit.
    pub fn unit(&self) -> &'static str {
        match self {
            ExcitationKind::Force => "N",
            ExcitationKind::BaseDisplacement | ExcitationKind::ImposedDisplacement => "m",
            ExcitationKind::BaseAcceleration => "m/s²",
            ExcitationKind::None => "",
        }
    }

    /// What the measured drive is (none for a free decay).
    pub fn quantity(&self) -> Option<Quantity> {
        match self {
            ExcitationKind::Force => Some(Quantity::Force),
            ExcitationKind::BaseDisplacement | ExcitationKind::ImposedDisplacement => {
                Some(Quantity::Displacement)
            }
            ExcitationKind::BaseAcceleration => Some(Quantity::Acceleration),
            ExcitationKind::None => None,
        }
    }

    /// The drive channel's name in a record and its file: the excitation's name, `stroke`
    /// for the test machine's.
    pub fn channel_name(&self) -> &'static str {
        match self {
            ExcitationKind::ImposedDisplacement => "stroke",
            other => other.name(),
        }
    }
}

impl ExcitationKind {
    /// Whether a response of `quantity` in `frame` can be predicted from this drive: a
    /// base measured by its acceleration gives the motion relative to it and the
    /// absolute acceleration; one measured by its displacement the absolute and the
    /// relative displacement (the others would need the base's motion differentiated
    /// or integrated).
    pub fn measures(&self, quantity: Quantity, frame: Frame) -> bool {
        use Quantity::*;
        match (self, frame) {
            (ExcitationKind::ImposedDisplacement, _) => quantity == Force,
            (_, _) if quantity == Force => false,
            (ExcitationKind::Force | ExcitationKind::None, f) => f == Frame::Absolute,
            (ExcitationKind::BaseAcceleration, Frame::Relative) => true,
            (ExcitationKind::BaseAcceleration, Frame::Absolute) => quantity == Acceleration,
            (ExcitationKind::BaseDisplacement, _) => quantity == Displacement,
        }
    }

    /// The responses [`measures`](Self::measures) accepts, in words.
    pub fn responses(&self) -> &'static str {
        match self {
            ExcitationKind::Force | ExcitationKind::None => {
                "displacement, velocity or acceleration of the mass (frame = \"absolute\")"
            }
            ExcitationKind::BaseAcceleration => {
                "the relative displacement, velocity or acceleration (frame = \"relative\"), or the absolute acceleration"
            }
            ExcitationKind::BaseDisplacement => "the absolute or the relative displacement",
            ExcitationKind::ImposedDisplacement => "the force",
        }
    }
}

/// What a channel measures and whose motion (msd-signal's, as every record spells them).
pub use msd_signal::{Frame, Quantity};

/// One response channel: `{ quantity, frame, sigma, column, scale, unit, name }`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Response {
    /// What the channel measures.
    pub quantity: Quantity,
    /// The mass's absolute motion or its motion relative to the base. By default
    /// absolute.
    #[serde(default)]
    pub frame: Frame,
    /// Synthetic data: the standard deviation of the channel's white noise, in its SI
    /// unit. By default `[noise] sigma`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma: Option<f64>,
    /// Measured data: the channel's column in `[data]`'s file(s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub column: Option<Column>,
    /// Measured data: the factor to SI applied on reading (9.80665 for an accelerometer
    /// in g, 1e-3 for mm). By default 1.
    #[serde(default = "default_one")]
    pub scale: f64,
    /// The unit the file holds, for the report (the channel is in SI after `scale`).
    /// By default the SI unit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
    /// The channel's name in tables and figures. By default its quantity (with its
    /// frame when relative, and a number when two channels would share it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
}

impl Response {
    /// The channel's name: `name`, else its quantity (`relative_` first for the
    /// relative frame).
    pub fn channel_name(&self) -> String {
        match (&self.name, self.frame) {
            (Some(n), _) => n.clone(),
            (None, Frame::Absolute) => self.quantity.to_string(),
            (None, Frame::Relative) => format!("relative_{}", self.quantity),
        }
    }
}

/// One test condition of a damper test machine: a sine stroke.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrokeCondition {
    /// Stroke frequency, Hz (> 0).
    pub frequency: f64,
    /// Stroke amplitude X, m (> 0).
    pub amplitude: f64,
}

/// The `[setup]` section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SetupSection {
    /// What drives the plant. By default a force.
    #[serde(default)]
    pub excitation: ExcitationKind,
    /// The response channels. By default one displacement channel (a force for an
    /// imposed stroke).
    #[serde(default)]
    pub responses: Vec<Response>,
    /// The weighed mass, kg: with base excitation or a free decay it turns ωn and ζ into
    /// c and k.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub known_mass: Option<f64>,
    /// The static stiffness, N/m (from a static load test): with base excitation or a
    /// free decay it turns ωn and ζ into m and c.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub known_stiffness: Option<f64>,
    /// Synthetic data: the number of records (repeats of the test, each with its own
    /// noise), fitted together. By default 1.
    #[serde(default = "default_records")]
    pub records: usize,
    /// Synthetic data: the standard deviation of the noise on the measured drive (base
    /// motion, imposed stroke), in its SI unit. By default 0.
    #[serde(default)]
    pub input_sigma: f64,
    /// What the intervals assume of the noise: `input_noise`, the measured drive's own
    /// noise estimated with the sensors' and seen through the plant (a load cell's, a
    /// base accelerometer's), or `white`, the drive taken as exact. By default
    /// `input_noise` on measured data and on a synthetic drive with noise
    /// (`input_sigma` > 0), `white` on a synthetic drive, exact by construction. A free
    /// decay has no drive: white.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise_model: Option<msd_ident::records::NoiseModel>,
    /// With a single record and no `[data.validation]`: the share of its samples at the
    /// end predicted by the plant fitted to the rest, a check on fresh data (the
    /// estimates use every sample). 0 for none. By default 0.2.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hold_out: Option<f64>,
    /// Damper test machine: the test conditions (synthetic data: the strokes to impose).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub conditions: Vec<StrokeCondition>,
    /// Damper test machine: whole stroke cycles per condition. By default 5.
    #[serde(default = "default_cycles")]
    pub cycles: usize,
    /// Test machine: how the stroke is analysed. `"harmonic"`: each record one sine
    /// condition, its derivatives from a Fourier fit (loops, c_eq, k′ per condition);
    /// `"any"`: inverse dynamics on the whole record of any stroke (a positioning move, a
    /// random or swept stroke: stroke and force low-passed alike, derivatives by central
    /// differences). By default `"auto"`: harmonic when every measured record's
    /// acceleration is at least 90 % in its fundamental, else any.
    #[serde(default, skip_serializing_if = "StrokeAnalysis::is_auto")]
    pub stroke: StrokeAnalysis,
    /// Test machine, any stroke: the low-pass cut-off in Hz. By default 10× the
    /// frequency below which 99 % of the stroke velocity's power lies.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cutoff_hz: Option<f64>,
    /// Test machine, any stroke: whether a stiffness k is estimated. By default false.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub stiffness: bool,
}

/// How a test machine's stroke is analysed (`setup.stroke`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StrokeAnalysis {
    /// Harmonic when every record's acceleration is ≥ 90 % fundamental, else any.
    #[default]
    Auto,
    /// Sine conditions, Fourier fits.
    Harmonic,
    /// Inverse dynamics of any stroke.
    Any,
}

impl StrokeAnalysis {
    /// Whether this is the default.
    pub fn is_auto(&self) -> bool {
        *self == Self::Auto
    }
}

fn default_records() -> usize {
    1
}
fn default_cycles() -> usize {
    5
}

impl SetupSection {
    /// The response channels, the default one when none is given.
    pub fn channels(&self) -> Vec<Response> {
        if !self.responses.is_empty() {
            return self.responses.clone();
        }
        let quantity = match self.excitation {
            ExcitationKind::ImposedDisplacement => Quantity::Force,
            _ => Quantity::Displacement,
        };
        vec![Response {
            quantity,
            frame: Frame::Absolute,
            sigma: None,
            column: None,
            scale: 1.0,
            unit: None,
            name: None,
        }]
    }

    /// Checks the values that need no other section; errors as (field, message).
    pub(crate) fn validate(&self) -> std::result::Result<(), (String, String)> {
        if let Some(m) = self.known_mass {
            check_positive("setup.known_mass", m)?;
        }
        if let Some(k) = self.known_stiffness {
            check_positive("setup.known_stiffness", k)?;
        }
        if self.known_mass.is_some() && self.known_stiffness.is_some() {
            return Err((
                "setup.known_stiffness".into(),
                ": given with setup.known_mass: expected at most one (either fixes the scale that the data cannot)".into(),
            ));
        }
        if self.records == 0 {
            return Err((
                "setup.records".into(),
                " = 0: expected an integer >= 1".into(),
            ));
        }
        check_non_negative("setup.input_sigma", self.input_sigma)?;
        if let Some(h) = self.hold_out.filter(|h| !(0.0..=0.5).contains(h)) {
            return Err((
                "setup.hold_out".into(),
                format!(" = {h}: expected a share of the record from 0 (none) to 0.5"),
            ));
        }
        self.validate_channels()?;
        if self.excitation == ExcitationKind::ImposedDisplacement {
            if self.cycles < 2 {
                return Err((
                    "setup.cycles".into(),
                    format!(" = {}: expected at least 2 whole cycles", self.cycles),
                ));
            }
            for (i, c) in self.conditions.iter().enumerate() {
                check_positive(&format!("setup.conditions[{i}].frequency"), c.frequency)?;
                check_positive(&format!("setup.conditions[{i}].amplitude"), c.amplitude)?;
            }
        }
        Ok(())
    }

    fn validate_channels(&self) -> std::result::Result<(), (String, String)> {
        let channels = self.channels();
        let mut names: Vec<String> = Vec::new();
        for (i, r) in channels.iter().enumerate() {
            let key = |field: &str| format!("setup.responses[{i}].{field}");
            if let Some(s) = r.sigma {
                check_non_negative(&key("sigma"), s)?;
            }
            check_finite(&key("scale"), r.scale)?;
            if r.scale == 0.0 {
                return Err((key("scale"), " = 0: expected a nonzero factor".into()));
            }
            let machine = self.excitation == ExcitationKind::ImposedDisplacement;
            if machine != (r.quantity == Quantity::Force) {
                let why = if machine {
                    "a test machine's response is the force: expected quantity = \"force\""
                } else {
                    "a force is measured by a test machine only (setup.excitation = \"imposed_displacement\"): expected displacement, velocity or acceleration"
                };
                return Err((key("quantity"), format!(" = \"{}\": {why}", r.quantity)));
            }
            if !machine && !self.excitation.measures(r.quantity, r.frame) {
                return Err((
                    key("quantity"),
                    format!(
                        " = \"{}\" (frame = \"{}\"): not a response of setup.excitation = \"{}\": expected {}",
                        r.quantity,
                        r.frame,
                        self.excitation.name(),
                        self.excitation.responses()
                    ),
                ));
            }
            let name = r.channel_name();
            if names.contains(&name) {
                return Err((
                    key("name"),
                    format!(": two channels are called {name:?}: give each a `name` of its own"),
                ));
            }
            names.push(name);
        }
        if self.excitation == ExcitationKind::ImposedDisplacement && channels.len() != 1 {
            return Err((
                "setup.responses".into(),
                format!(
                    ": {} channels: a test machine measures one force",
                    channels.len()
                ),
            ));
        }
        Ok(())
    }

    /// Checks a whole config with this section: the synthetic plant or the measured
    /// files, and what the setup needs of them.
    pub(crate) fn validate_config(
        &self,
        config: &Config,
        kind: Kind,
    ) -> std::result::Result<(), (String, String)> {
        self.validate()?;
        let drive = self.excitation;
        let needs_input = !matches!(
            drive,
            ExcitationKind::None | ExcitationKind::ImposedDisplacement
        );
        if drive == ExcitationKind::None && config.identification.is_some() {
            return Err((
                "identification".into(),
                ": setup.excitation = \"none\" (a free decay) has no input: remove [identification.input]".into(),
            ));
        }
        if config.validation.input.is_some() {
            return Err((
                "validation.input".into(),
                ": a [setup] run validates each record on the others (leave one record out): remove [validation.input]".into(),
            ));
        }
        match kind {
            Kind::Measured => self.validate_measured(config),
            Kind::Synthetic => self.validate_synthetic(config, needs_input),
        }
    }

    fn validate_synthetic(
        &self,
        config: &Config,
        needs_input: bool,
    ) -> std::result::Result<(), (String, String)> {
        let missing = |field: &str, what: &str| {
            Err((
                field.to_string(),
                format!(
                    ": missing section: expected {what} (or a [data] section for measured data)"
                ),
            ))
        };
        let Some(plant) = &config.plant else {
            return missing("plant", "the true plant { mass, damping, stiffness }");
        };
        let Some(time) = &config.time else {
            return missing("time", "the time grid { duration, dt }");
        };
        validate_plant(plant)?;
        validate_time(time)?;
        self.check_budget(time)?;
        if plant.nonlinear().is_some() && self.excitation != ExcitationKind::ImposedDisplacement {
            return Err((
                "plant".into(),
                ": a nonlinear term with a [setup]: expected a linear plant (nonlinear damping laws are identified on a test machine, setup.excitation = \"imposed_displacement\")".into(),
            ));
        }
        if let Some(noise) = &config.noise {
            check_non_negative("noise.sigma", noise.sigma)?;
        } else if let Some(i) = self.channels().iter().position(|r| r.sigma.is_none()) {
            return Err((
                format!("setup.responses[{i}].sigma"),
                ": missing: expected the channel's noise level (or a [noise] section for every channel)".into(),
            ));
        }
        match (&config.identification, needs_input) {
            (None, true) => missing(
                "identification",
                &format!("the {} [identification.input]", self.excitation.name()),
            ),
            (Some(i), _) => i
                .input
                .validate()
                .map_err(|e| ("identification.input".to_string(), format!(": {e}"))),
            (None, false) => self.validate_conditions(),
        }
    }

    /// The samples the synthetic records or the test machine's conditions take, against
    /// the budget ([`crate::budget`]): the records, or a condition's frequency (its
    /// cycles at dt), or the cycles, named.
    fn check_budget(&self, time: &super::TimeGrid) -> std::result::Result<(), (String, String)> {
        use crate::budget::{Budget, check};
        let channels = self.channels().len() as f64 + 1.0;
        if self.excitation != ExcitationKind::ImposedDisplacement {
            // One record past the budget: its duration is the cause; else the records.
            let records = self.records as f64;
            check(
                "time.duration",
                time.duration,
                channels / time.dt,
                Budget::Held,
            )?;
            let per_record = channels * time.samples() as f64;
            return check("setup.records", records, per_record, Budget::Held);
        }
        let cycles = self.cycles as f64;
        let per_condition = |f: f64| channels * cycles / (f * time.dt);
        for (i, c) in self.conditions.iter().enumerate() {
            // One condition past the budget even at the fewest cycles (2): its frequency
            // is the cause.
            if 2.0 / cycles * per_condition(c.frequency) > crate::budget::SAMPLES_HELD {
                let lowest = per_condition(1.0) / crate::budget::SAMPLES_HELD;
                return Err((
                    format!("setup.conditions[{i}].frequency"),
                    format!(
                        " = {}: {} cycles at dt = {} take {:.3e} samples with the channels; the budget is {:.0e} samples held at once, so the lowest frequency accepted is {lowest:.3e} Hz",
                        c.frequency,
                        self.cycles,
                        time.dt,
                        per_condition(c.frequency),
                        crate::budget::SAMPLES_HELD
                    ),
                ));
            }
        }
        let per_cycle: f64 = self
            .conditions
            .iter()
            .map(|c| channels / (c.frequency * time.dt))
            .sum();
        check("setup.cycles", cycles, per_cycle, Budget::Held)
    }

    fn validate_conditions(&self) -> std::result::Result<(), (String, String)> {
        if self.excitation == ExcitationKind::ImposedDisplacement && self.conditions.is_empty() {
            return Err((
                "setup.conditions".into(),
                ": missing: expected the strokes to impose, [{ frequency, amplitude }, …]".into(),
            ));
        }
        Ok(())
    }

    fn validate_measured(&self, config: &Config) -> std::result::Result<(), (String, String)> {
        config.validate_measured()?;
        let Some(d) = &config.data else { return Ok(()) };
        if d.output.is_some() {
            return Err((
                "data.output".into(),
                ": with a [setup] the response columns are setup.responses[i].column: remove data.output".into(),
            ));
        }
        let drive = self.excitation;
        match (&d.input, drive) {
            (Some(_), ExcitationKind::None) => {
                return Err((
                    "data.input".into(),
                    ": setup.excitation = \"none\" (a free decay) has no input: remove data.input"
                        .into(),
                ));
            }
            (None, d) if d != ExcitationKind::None => {
                return Err((
                    "data.input".into(),
                    format!(
                        ": missing: expected the column of the {} (setup.excitation)",
                        d.name()
                    ),
                ));
            }
            _ => {}
        }
        if !d.preprocessing.is_empty() {
            return Err((
                "data.preprocessing".into(),
                ": not with a [setup] (its records are fitted as read; each channel's offset is estimated): remove data.preprocessing".into(),
            ));
        }
        for (key, range) in [
            ("data.estimation", Some(&d.estimation)),
            ("data.validation", d.validation.as_ref()),
        ] {
            if let Some(n) = range.map(|r| r.initial_samples).filter(|&n| n != 0) {
                return Err((
                    format!("{key}.initial_samples"),
                    format!(
                        " = {n}: not with a [setup], which fits each record's initial state: remove it"
                    ),
                ));
            }
        }
        if d.validation.is_some() && drive == ExcitationKind::ImposedDisplacement {
            return Err((
                "data.validation".into(),
                ": a test machine's laws are judged on each stroke's own cycles: remove data.validation".into(),
            ));
        }
        if let Some(i) = self.channels().iter().position(|r| r.column.is_none()) {
            return Err((
                format!("setup.responses[{i}].column"),
                ": missing: expected the channel's column in the data file(s)".into(),
            ));
        }
        Ok(())
    }
}
