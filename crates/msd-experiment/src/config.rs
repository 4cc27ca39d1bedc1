//! Experiment configs: TOML read with serde, unknown keys refused, every value checked
//! and any error reported as one line naming the file, the line and the field.
//!
//! A config describes either a **synthetic** experiment (sections `plant`, `time`,
//! `noise`, `identification`, `validation`: data generated from a known plant) or a
//! **measured** one (section `data`: a CSV file with input and output columns). Both
//! share `estimation`, `residuals`, `frequency_check`, `monte_carlo`, `output` and the
//! optional `nonlinear` ([`NonlinearSection`]: nonlinear models and their comparison).
//! The shipped configs in `configs/` document every field in their comments.
//!
//! ```
//! let text = r#"
//!     name = "tiny"
//!     [plant]
//!     mass = 2.5
//!     damping = 1.8
//!     stiffness = 120.0
//!     [time]
//!     duration = 2.0
//!     dt = 0.01
//!     [noise]
//!     sigma = 0.001
//!     [identification.input]
//!     kind = "step"
//!     amplitude = 1.0
//!     time = 0.1
//!     [validation.input]
//!     kind = "sine"
//!     amplitude = 1.0
//!     frequency = 1.0
//! "#;
//! let config = msd_experiment::config::Config::from_toml_str(text, "tiny.toml")?;
//! assert_eq!(config.seed, 1);
//! assert_eq!(config.time.unwrap().samples(), 201);
//! # Ok::<(), msd_experiment::ExperimentError>(())
//! ```

use crate::error::{ExperimentError, Result};
use crate::sources::Sources;
use msd_ident::{
    Backend, EstimationOptions, InitialState, Parameters, ResidualOptions, data::MIN_SAMPLES,
};
use msd_mc::{McOptions, Sampling};
use msd_signal::Signal;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::path::{Path, PathBuf};

mod chain;
mod experiment;
mod frf;
mod nonlinear;
mod operational;
mod pilot;
pub mod setup;
pub use chain::{ChainSection, ChainSensorSection};
pub use experiment::{Experiment, ExperimentKind, Spec};
pub use frf::{
    ChainPlant, FrequencyResponseSection, FrequencyUnit, HammerSource, RecordsSource,
    ReferenceMode, ShakerSource, Spacing, SweepSource, TableSource, UffSource,
};
pub use nonlinear::{Candidates, NonlinearMultistartSection, NonlinearSection};
pub use operational::{
    DeadChannels, GeometrySection, OperationalSection, OutputChannelSection, RecordSource,
    SimulatedBuilding,
};
pub use pilot::PilotSection;
pub use setup::{ExcitationKind, Frame, Quantity, Response, SetupSection, StrokeCondition};

/// A whole experiment config.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// Name of the experiment; outputs go to `target/experiments/<name>/`.
    pub name: String,
    /// One sentence for the report. By default empty.
    #[serde(default)]
    pub description: String,
    /// Seed of every random draw (noise, Monte Carlo, multistart). By default 1.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// What drives the plant and what is measured (off unless given: a force and one
    /// displacement channel, the paper's setup).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub setup: Option<SetupSection>,
    /// A chain of masses tested in the time domain (`crate::chain`; off unless given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chain: Option<ChainSection>,
    /// The true plant (synthetic experiments).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plant: Option<Plant>,
    /// The time grid of both synthetic records.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<TimeGrid>,
    /// Measurement noise of the synthetic records.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise: Option<Noise>,
    /// The identification input (synthetic experiments).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub identification: Option<InputSection>,
    /// The validation input (synthetic) and how the model is simulated on it.
    #[serde(default)]
    pub validation: ValidationSection,
    /// A measured record (instead of `plant`, `time`, `noise`, `identification`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub data: Option<DataSection>,
    /// How θ = (m, c, k) is estimated: msd-ident's options, as they are.
    #[serde(default)]
    pub estimation: EstimationOptions,
    /// Residual diagnostics: msd-ident's options, as they are.
    #[serde(default)]
    pub residuals: ResidualOptions,
    /// Frequency-domain consistency check.
    #[serde(default)]
    pub frequency_check: FrequencySection,
    /// Monte Carlo robustness band on the validation input.
    #[serde(default)]
    pub monte_carlo: MonteCarloSection,
    /// Nonlinear models: one estimated, or several compared (off unless given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nonlinear: Option<NonlinearSection>,
    /// A frequency response and the modes fitted to it (`crate::frf`; off unless given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frequency_response: Option<FrequencyResponseSection>,
    /// Output-only modal analysis of a record with no measured input
    /// (`crate::operational`; off unless given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub operational: Option<OperationalSection>,
    /// What is written.
    #[serde(default)]
    pub output: OutputSection,
    /// Excitation design (`msd design`, [`crate::design`]): msd-ident's options, as
    /// they are. Off unless given; a run ignores it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub design: Option<msd_ident::design::DesignOptions>,
    /// Sequential design: the pilot test whose estimate replaces `[plant]` as the
    /// design's prior ([`crate::design::Pilot`]). Off unless given; only with `[design]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pilot: Option<PilotSection>,
    /// Where the data files come from: the config file's folder, and any file given in
    /// memory ([`Sources`]). Not a key of the file: set by [`Config::load`] and
    /// [`Config::from_toml_str`], extended by a program that holds its data.
    #[serde(skip)]
    pub sources: Sources,
}

fn default_seed() -> u64 {
    1
}

/// The true plant of a synthetic experiment.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plant {
    /// Mass m, kg (> 0).
    pub mass: f64,
    /// Damping c, N·s/m (≥ 0).
    pub damping: f64,
    /// Stiffness k, N/m (> 0).
    pub stiffness: f64,
    /// State at the start of both records. By default at rest.
    #[serde(default)]
    pub initial_state: InitialState,
    /// Coulomb friction force F_c, N (≥ 0; not with `quadratic_damping`). By default 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub coulomb_force: f64,
    /// Quadratic damping c₂ of c₂·x'|x'|, N·s²/m² (≥ 0; not with `coulomb_force`). By
    /// default 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub quadratic_damping: f64,
    /// Cubic stiffness k₃ of k₃·x³, N/m³ (either sign). By default 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub cubic_stiffness: f64,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

impl Plant {
    /// The physical parameters (the linear part).
    pub fn parameters(&self) -> Parameters {
        Parameters {
            mass: self.mass,
            damping: self.damping,
            stiffness: self.stiffness,
        }
    }

    /// The plant as a nonlinear model when it has a nonlinear term (its data are then
    /// simulated by ode45), else `None`.
    ///
    /// ```
    /// let plant: msd_experiment::config::Plant =
    ///     toml::from_str("mass = 2.5\ndamping = 1.8\nstiffness = 120.0\ncubic_stiffness = 3000.0").unwrap();
    /// assert_eq!(plant.nonlinear().unwrap().structure.name(), "viscous+cubic");
    /// ```
    pub fn nonlinear(&self) -> Option<msd_ident::nonlinear::NonlinearParameters> {
        use msd_ident::nonlinear::{DampingLaw, ModelStructure, StiffnessLaw};
        let (damping, extra) = if self.coulomb_force != 0.0 {
            (DampingLaw::CoulombViscous, Some(self.coulomb_force))
        } else if self.quadratic_damping != 0.0 {
            (DampingLaw::QuadraticViscous, Some(self.quadratic_damping))
        } else {
            (DampingLaw::Viscous, None)
        };
        let cubic = (self.cubic_stiffness != 0.0).then_some(self.cubic_stiffness);
        if extra.is_none() && cubic.is_none() {
            return None;
        }
        let structure = ModelStructure {
            damping,
            stiffness: if cubic.is_some() {
                StiffnessLaw::Cubic
            } else {
                StiffnessLaw::Linear
            },
        };
        let mut values = vec![self.mass, self.damping, self.stiffness];
        values.extend(extra);
        values.extend(cubic);
        Some(msd_ident::nonlinear::NonlinearParameters { structure, values })
    }
}

/// A uniform time grid `start, start + dt, …, start + duration` (both ends included).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeGrid {
    /// First instant, s. By default 0.
    #[serde(default)]
    pub start: f64,
    /// Length of the record, s (≥ dt).
    pub duration: f64,
    /// Sampling interval, s (> 0).
    pub dt: f64,
}

impl TimeGrid {
    /// Number of samples: ⌊duration/dt⌋ + 1 (both ends included when dt divides the
    /// duration).
    /// Saturates at `usize::MAX` for absurd grids (the config's sample limit then
    /// refuses them by name).
    pub fn samples(&self) -> usize {
        ((self.duration / self.dt * (1.0 + 1e-12)).floor() as usize).saturating_add(1)
    }
}

/// Measurement noise: white Gaussian on the displacement.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Noise {
    /// Standard deviation σ, in the output unit (≥ 0).
    pub sigma: f64,
}

/// An input section: `[identification.input]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputSection {
    /// The excitation, any msd-signal [`Signal`].
    pub input: Signal,
}

/// The `[validation]` section.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ValidationSection {
    /// The validation input (synthetic experiments only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub input: Option<Signal>,
    /// Simulator for the validation prediction. By default the estimation backend.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub backend: Option<Backend>,
}

/// Which record the frequency check uses.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RecordChoice {
    /// The identification record.
    Identification,
    /// The validation record (the default: a chirp or multisine is broadband).
    #[default]
    Validation,
}

impl RecordChoice {
    /// "identification" or "validation".
    pub fn name(&self) -> &'static str {
        match self {
            RecordChoice::Identification => "identification",
            RecordChoice::Validation => "validation",
        }
    }
}

/// The `[frequency_check]` section: msd-ident's `FrequencyCheckOptions` plus the
/// record to use.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FrequencySection {
    /// Run the check. By default true.
    pub enabled: bool,
    /// The record: "validation" (by default) or "identification".
    pub data: RecordChoice,
    /// Fit band in Hz; by default chosen from the input's power.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[serde(default, deserialize_with = "msd_signal::pair::optional")]
    pub band_hz: Option<[f64; 2]>,
    /// Share of the input's peak DFT power that marks a frequency as excited.
    /// By default 0.01.
    pub power_threshold: f64,
    /// Allowed relative difference of fn between data and model. By default 0.01.
    pub frequency_tolerance: f64,
    /// Allowed relative difference of ζ between data and model. By default 0.2.
    pub damping_tolerance: f64,
    /// Allowed normalised output error of the model in the band. By default 0.25.
    pub max_relative_error: f64,
}

impl Default for FrequencySection {
    fn default() -> Self {
        let o = msd_ident::frequency::FrequencyCheckOptions::default();
        Self {
            enabled: true,
            data: RecordChoice::Validation,
            band_hz: o.band_hz,
            power_threshold: o.power_threshold,
            frequency_tolerance: o.frequency_tolerance,
            damping_tolerance: o.damping_tolerance,
            max_relative_error: o.max_relative_error,
        }
    }
}

impl FrequencySection {
    /// As msd-ident's options.
    pub fn options(&self) -> msd_ident::frequency::FrequencyCheckOptions {
        msd_ident::frequency::FrequencyCheckOptions {
            band_hz: self.band_hz,
            power_threshold: self.power_threshold,
            frequency_tolerance: self.frequency_tolerance,
            damping_tolerance: self.damping_tolerance,
            max_relative_error: self.max_relative_error,
        }
    }
}

/// The `[monte_carlo]` section.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MonteCarloSection {
    /// Run the Monte Carlo stage. By default true.
    pub enabled: bool,
    /// Number of parameter draws. By default 1000 (the paper).
    pub samples: usize,
    /// Half-width of the uniform draw around θ̂, as a fraction. By default 0.10 (±10 %).
    pub spread: f64,
    /// Lower and upper percentile of the band, in percent. By default [5, 95] (90 %).
    #[serde(deserialize_with = "msd_signal::pair::exactly_two")]
    pub percentiles: [f64; 2],
    /// Worker threads. By default 2 (`--threads` overrides).
    pub threads: usize,
    /// Simulator of the draws. By default the validation backend.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub backend: Option<Backend>,
}

impl Default for MonteCarloSection {
    fn default() -> Self {
        Self {
            enabled: true,
            samples: 1000,
            spread: 0.10,
            percentiles: [5.0, 95.0],
            threads: 2,
            backend: None,
        }
    }
}

impl MonteCarloSection {
    /// As msd-mc's options: N = `samples`, uniform draws of ±`spread`, the band's
    /// percentiles with the median between them, `threads`; the seed, backend and
    /// initial state are the run's, set by the pipeline.
    pub fn options(&self) -> McOptions {
        let [low, high] = self.percentiles;
        McOptions {
            samples: self.samples,
            sampling: Sampling::Uniform {
                percent: self.spread * 100.0,
            },
            percentiles: vec![low, 50.0, high],
            threads: self.threads,
            ..McOptions::default()
        }
    }

    /// msd-mc's refusal of [`MonteCarloSection::options`] as (TOML key, message).
    fn refusal(&self, error: msd_mc::McError) -> (String, String) {
        use msd_mc::McError::*;
        let (key, value) = match error {
            ZeroSamples => ("samples", self.samples.to_string()),
            ZeroThreads | TooManyThreads { .. } => ("threads", self.threads.to_string()),
            BudgetTooSmall { .. } => {
                let largest = self.options().max_samples();
                let message = format!(
                    " = {}: expected at most {largest} draws (the band's memory budget: {error})",
                    self.samples
                );
                return ("monte_carlo.samples".into(), message);
            }
            InvalidPercent { .. } => ("spread", self.spread.to_string()),
            PercentileOutOfRange { .. } | UnorderedPercentiles { .. } => {
                let [low, high] = self.percentiles;
                ("percentiles", format!("[{low}, {high}]"))
            }
            _ => return ("monte_carlo".into(), format!(": {error}")),
        };
        (format!("monte_carlo.{key}"), format!(" = {value}: {error}"))
    }
}

/// The `[output]` section.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OutputSection {
    /// Output folder, relative to the current directory. By default
    /// `target/experiments/<name>` in the workspace (`--out` overrides).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dir: Option<PathBuf>,
}

/// The first top-level section of `text` that `config`'s kind does not read, refused by
/// name with the kind and the sections it reads (a section silently ignored would let a
/// user believe it was applied).
fn unused_sections(text: &str, config: &Config) -> std::result::Result<(), (String, String)> {
    const COMMON: [&str; 4] = ["name", "description", "seed", "output"];
    let (kind, reads): (&str, &[&str]) = if config.operational.is_some() {
        (
            "an [operational] config (output-only modal analysis)",
            &["operational"],
        )
    } else if config.frequency_only() {
        ("a frequency-response config", &["frequency_response"])
    } else if config.chain.is_some() {
        (
            "a [chain] config (a chain of masses)",
            &["chain", "time", "identification", "data"],
        )
    } else if config.setup.is_some() {
        (
            "a [setup] config (a lab setup)",
            &[
                "setup",
                "plant",
                "time",
                "noise",
                "identification",
                "data",
                "estimation",
                "residuals",
            ],
        )
    } else {
        (
            "a force-and-displacement config (the paper's workflow)",
            &[
                "plant",
                "time",
                "noise",
                "identification",
                "validation",
                "data",
                "estimation",
                "residuals",
                "frequency_check",
                "monte_carlo",
                "nonlinear",
                "design",
                "pilot",
            ],
        )
    };
    let Ok(table) = text.parse::<toml::Table>() else {
        return Ok(());
    };
    let unused = table
        .keys()
        .find(|k| !COMMON.contains(&k.as_str()) && !reads.contains(&k.as_str()));
    match unused {
        Some(key) => Err((
            key.clone(),
            format!(
                ": {kind} does not read this section (it reads [{}]); remove it, or put it in a config of its own kind",
                reads.join("], [")
            ),
        )),
        None => Ok(()),
    }
}

/// A CSV column: its header name (a string) or its 0-based index (an integer).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Column {
    /// By header name.
    Name(String),
    /// By 0-based position.
    Index(usize),
}

impl std::fmt::Display for Column {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Column::Name(n) => write!(f, "`{n}`"),
            Column::Index(i) => write!(f, "#{i}"),
        }
    }
}

impl Serialize for Column {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            Column::Name(n) => s.serialize_str(n),
            Column::Index(i) => s.serialize_u64(*i as u64),
        }
    }
}

impl<'de> Deserialize<'de> for Column {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = Column;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a column name (string) or a 0-based column index (integer >= 0)")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> std::result::Result<Column, E> {
                Ok(Column::Name(v.to_string()))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> std::result::Result<Column, E> {
                usize::try_from(v)
                    .map(Column::Index)
                    .map_err(|_| E::invalid_value(serde::de::Unexpected::Signed(v), &self))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> std::result::Result<Column, E> {
                Ok(Column::Index(v as usize))
            }
        }
        d.deserialize_any(Visitor)
    }
}

/// Which columns a preprocessing step touches.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Columns {
    /// Input and output. The default.
    #[default]
    Both,
    /// The input only.
    Input,
    /// The output only.
    Output,
}

/// One preprocessing step, applied to the whole record in order, before the ranges are
/// cut.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Preprocess {
    /// Subtract the mean.
    RemoveMean {
        /// Columns to treat. By default both.
        #[serde(default)]
        columns: Columns,
    },
    /// Subtract the least-squares straight line.
    DetrendLinear {
        /// Columns to treat. By default both.
        #[serde(default)]
        columns: Columns,
    },
    /// Centred moving average over `window` samples (odd, ≥ 1).
    MovingAverage {
        /// Window length in samples.
        window: usize,
        /// Columns to treat. By default both.
        #[serde(default)]
        columns: Columns,
    },
    /// Anti-aliased decimation of both columns by an integer factor (the time step
    /// grows by the factor).
    Decimate {
        /// The factor (≥ 1).
        factor: usize,
    },
}

/// A part of the record: `range = [start, end)` in samples (0-based, the first data row
/// is 0) or `time = [t_start, t_end)` in seconds from the first sample's time.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Range {
    /// Sample indices `[start, end)` of the file's data rows.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "msd_signal::pair::optional"
    )]
    pub range: Option<[usize; 2]>,
    /// Times `[start, end)`, in seconds on the record's own time axis.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "msd_signal::pair::optional"
    )]
    pub time: Option<[f64; 2]>,
    /// Leading samples used only to settle the initial state, not scored (validation).
    /// By default 0.
    #[serde(default)]
    pub initial_samples: usize,
}

/// A measured record in a CSV file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DataSection {
    /// The CSV file, relative to the config file; a `[setup]` config takes a list of
    /// files, one record each (repeats of the test, all with the same columns).
    pub path: Paths,
    /// The input column: the force, or what `setup.excitation` names (the base's
    /// motion, the imposed stroke). Not with `setup.excitation = "none"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub input: Option<Column>,
    /// The output (displacement) column; a `[setup]` config names its response
    /// columns in `setup.responses` instead.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub output: Option<Column>,
    /// A time column (s); give this or `sample_rate`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<Column>,
    /// Sampling rate, Hz; give this or `time`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sample_rate: Option<f64>,
    /// Field delimiter. By default `","`; `" "` for columns separated by runs of spaces
    /// or tabs (NumPy's `savetxt`, MATLAB's `save -ascii`).
    #[serde(default = "default_delimiter")]
    pub delimiter: char,
    /// The decimal mark: `"."` (the default) or `","` (with a delimiter other than `","`,
    /// as European spreadsheets write CSV: `;` and `-0,98`).
    #[serde(default = "default_decimal", skip_serializing_if = "is_point")]
    pub decimal: char,
    /// Whether the first (non-skipped) line holds column names. By default true.
    #[serde(default = "default_true")]
    pub header: bool,
    /// Lines to skip at the top of the file (before the header). By default 0: lines
    /// of metadata above the header (and a units line under it) are found by themselves
    /// and the report says which.
    #[serde(default)]
    pub skip_lines: usize,
    /// What to do with a missing value (an empty cell, `NaN`, `NA`): `"refuse"` (the
    /// default), `"drop"` the row or `"interpolate"` it; the report says how many.
    #[serde(default, skip_serializing_if = "crate::data::text::Missing::is_refuse")]
    pub missing: crate::data::text::Missing,
    /// Unit of the input column after scaling, for the report. By default "N".
    #[serde(default = "default_input_unit")]
    pub input_unit: String,
    /// Unit of the output column after scaling, for the report. By default "m".
    #[serde(default = "default_output_unit")]
    pub output_unit: String,
    /// Factor applied to the input column on reading (e.g. 1e-3 for mN → N). By default 1.
    #[serde(default = "default_one")]
    pub input_scale: f64,
    /// Factor applied to the output column on reading (e.g. 1e-3 for mm → m). By default 1.
    #[serde(default = "default_one")]
    pub output_scale: f64,
    /// Preprocessing steps, in order. By default none.
    #[serde(default)]
    pub preprocessing: Vec<Preprocess>,
    /// The part used for estimation. By default the whole record.
    #[serde(default)]
    pub estimation: Range,
    /// The part used for validation. By default the estimation part.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub validation: Option<Range>,
    /// A `[setup]` config: records of the same test read with the same columns, not
    /// fitted but predicted by the fit (validation on fresh data): one file or a list.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub validation_path: Option<Paths>,
}

impl DataSection {
    /// How its text files are written.
    pub fn text_format(&self) -> crate::data::text::TextFormat {
        crate::data::text::TextFormat {
            delimiter: self.delimiter,
            decimal: self.decimal,
            header: self.header,
            skip_lines: self.skip_lines,
            missing: self.missing,
        }
    }
}

/// One file or several: `path = "run.csv"` or `path = ["run1.csv", "run2.csv"]`.
///
/// ```
/// use msd_experiment::config::Paths;
/// let one: Paths = toml::from_str::<toml::Table>("p = \"a.csv\"").unwrap()["p"].clone().try_into().unwrap();
/// assert_eq!(one.0.len(), 1);
/// let two: Paths = toml::Value::Array(vec!["a.csv".into(), "b.csv".into()]).try_into().unwrap();
/// assert_eq!(two.to_string(), "[\"a.csv\", \"b.csv\"]");
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Paths(pub Vec<PathBuf>);

impl Paths {
    /// The first file (the only one of a classic config).
    pub fn first(&self) -> &Path {
        self.0.first().map_or(Path::new(""), PathBuf::as_path)
    }

    /// The key that names file `i` in messages: `data.path` for a single file, else
    /// `data.path[i]`.
    pub fn key(&self, i: usize) -> String {
        if self.0.len() == 1 {
            "data.path".into()
        } else {
            format!("data.path[{i}]")
        }
    }
}

impl std::fmt::Display for Paths {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.0.as_slice() {
            [one] => write!(f, "{:?}", one.display().to_string()),
            many => {
                let names: Vec<String> = many
                    .iter()
                    .map(|p| format!("{:?}", p.display().to_string()))
                    .collect();
                write!(f, "[{}]", names.join(", "))
            }
        }
    }
}

impl Serialize for Paths {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self.0.as_slice() {
            [one] => one.serialize(s),
            many => many.serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for Paths {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged, expecting = "a file name or a list of file names")]
        enum OneOrMany {
            One(PathBuf),
            Many(Vec<PathBuf>),
        }
        match OneOrMany::deserialize(d)? {
            OneOrMany::One(p) => Ok(Paths(vec![p])),
            OneOrMany::Many(v) if v.is_empty() => Err(serde::de::Error::custom(
                "an empty list: expected a file name or a list of at least one",
            )),
            OneOrMany::Many(v) => Ok(Paths(v)),
        }
    }
}

fn default_delimiter() -> char {
    ','
}
pub(crate) fn default_decimal() -> char {
    '.'
}
pub(crate) fn is_point(c: &char) -> bool {
    *c == '.'
}
fn default_true() -> bool {
    true
}
fn default_one() -> f64 {
    1.0
}
fn default_input_unit() -> String {
    "N".into()
}
fn default_output_unit() -> String {
    "m".into()
}

/// What kind of experiment a config describes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Data generated from a known plant.
    Synthetic,
    /// Data read from a file.
    Measured,
}

impl Config {
    /// Reads, parses and checks a config file.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            ExperimentError::config(path, format!("cannot read the config file: {e}"))
        })?;
        Self::from_toml_str(&text, path)
    }

    /// A config given as a tree of values (a dict from Python, JSON): written as TOML
    /// and read as a file would be, so that the messages name keys and values the same
    /// way; `file` names it and its folder resolves relative paths.
    ///
    /// ```
    /// use msd_experiment::config::Config;
    /// let data = serde_json::json!({"path": "run.csv", "input": "F", "output": "x", "time": "t"});
    /// let value = serde_json::json!({"name": "dict", "data": data, "monte_carlo": {"samples": 20}});
    /// let config = Config::from_value(value, "lab/config.toml")?;
    /// assert_eq!(config.monte_carlo.samples, 20);
    /// assert_eq!(config.sources.dir(), std::path::Path::new("lab"));
    /// let bad = serde_json::json!({"name": "dict", "data": data, "monte_carlo": {"sampels": 20}});
    /// assert!(Config::from_value(bad, "config.toml").unwrap_err().to_string().contains("sampels"));
    /// # Ok::<(), msd_experiment::ExperimentError>(())
    /// ```
    pub fn from_value(value: serde_json::Value, file: impl AsRef<Path>) -> Result<Self> {
        let file = file.as_ref();
        let text = serde_json::from_value::<toml::Table>(value)
            .map_err(|e| e.to_string())
            .and_then(|t| toml::to_string(&t).map_err(|e| e.to_string()))
            .map_err(|e| {
                ExperimentError::config(
                    file,
                    format!("{e}: expected a table of keys (no null values)"),
                )
            })?;
        Self::from_toml_str(&text, file)
    }

    /// Parses and checks a config from its text; `file` names it in errors and its
    /// folder resolves relative paths ([`Config::sources`]).
    pub fn from_toml_str(text: &str, file: impl AsRef<Path>) -> Result<Self> {
        let file = file.as_ref();
        let mut config: Config = toml::from_str(text).map_err(|e| {
            if let Some(err) = unknown_variant(text, &e, file) {
                return err;
            }
            let location = e
                .span()
                .map(|s| {
                    let (line, column) = line_column(text, s.start);
                    format!(":{line}:{column}")
                })
                .unwrap_or_default();
            let message = e.message().trim().replace('\n', " ");
            ExperimentError::Config {
                file: format!("{}{location}", file.display()),
                message: match e.span().map(|s| key_of_value(text, s.start)) {
                    // A value's error names its key and the value as written.
                    Some(Some((key, value))) => format!("{key} = {value}: {message}"),
                    // A table-level error (e.g. a missing field) points at the table's
                    // header: name it.
                    _ => {
                        let header = e
                            .span()
                            .and_then(|s| text.get(s.start..))
                            .and_then(|rest| rest.lines().next())
                            .map(str::trim)
                            .filter(|l| l.starts_with('['))
                            .map(|l| format!(" in {l}"))
                            .unwrap_or_default();
                        format!("{message}{header}")
                    }
                },
            }
        })?;
        if let Some((key, value)) = table_written_as_array(text, &config) {
            let line = locate_key(text, &key)
                .map(|l| format!(":{l}"))
                .unwrap_or_default();
            return Err(ExperimentError::Config {
                file: format!("{}{line}", file.display()),
                message: format!(
                    "{key} = {value}: expected a table of named values (e.g. {key} = {{ … }} or a [{key}] section); quantities are read by name, never by position"
                ),
            });
        }
        unused_sections(text, &config)
            .and_then(|()| config.validate())
            .map_err(|(field, message)| {
                let line = locate_key(text, &field)
                    .map(|l| format!(":{l}"))
                    .unwrap_or_default();
                ExperimentError::Config {
                    file: format!("{}{line}", file.display()),
                    message: format!("{field}{message}"),
                }
            })?;
        config.sources = Sources::new(file);
        Ok(config)
    }

    /// A config named `name` with every option at its default and no data sections: for
    /// a Rust program that runs the stages on records it holds ([`crate::run_in_memory`]).
    ///
    /// ```
    /// use msd_experiment::config::Config;
    /// let mut config = Config::new("bench");
    /// config.monte_carlo.samples = 200;
    /// assert_eq!(config.seed, 1);
    /// assert!(config.plant.is_none() && config.data.is_none());
    /// ```
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            description: String::new(),
            seed: default_seed(),
            setup: None,
            chain: None,
            plant: None,
            time: None,
            noise: None,
            identification: None,
            validation: ValidationSection::default(),
            data: None,
            estimation: EstimationOptions::default(),
            residuals: ResidualOptions::default(),
            frequency_check: FrequencySection::default(),
            monte_carlo: MonteCarloSection::default(),
            nonlinear: None,
            frequency_response: None,
            operational: None,
            output: OutputSection::default(),
            design: None,
            pilot: None,
            sources: Sources::default(),
        }
    }

    /// Synthetic or measured.
    pub fn kind(&self) -> Kind {
        if self.data.is_some() {
            Kind::Measured
        } else {
            Kind::Synthetic
        }
    }

    /// The validation backend: `[validation] backend`, else the estimation backend.
    pub fn validation_backend(&self) -> Backend {
        self.validation.backend.unwrap_or(self.estimation.backend)
    }

    /// The Monte Carlo backend: `[monte_carlo] backend`, else the validation backend.
    pub fn monte_carlo_backend(&self) -> Backend {
        self.monte_carlo
            .backend
            .unwrap_or_else(|| self.validation_backend())
    }

    /// Checks every value; on failure returns the field path and the rest of the
    /// message (starting with " = value: expected …" or ": …").
    fn validate(&self) -> std::result::Result<(), (String, String)> {
        let err = |field: &str, message: String| Err((field.to_string(), message));
        if self.name.trim().is_empty()
            || self
                .name
                .chars()
                .any(|c| !(c.is_alphanumeric() || "-_.".contains(c)))
            || self.name.starts_with('.')
        {
            return err(
                "name",
                format!(
                    " = {:?}: expected a non-empty folder name of letters, digits, '-', '_' or '.'",
                    self.name
                ),
            );
        }
        // The kind's checks, by the one rule that tells the kind.
        let kind = ExperimentKind::of(self);
        if let (ExperimentKind::Operational, Some(section)) = (kind, &self.operational) {
            return section.validate();
        }
        if let Some(section) = &self.frequency_response {
            section.validate()?;
        }
        if kind == ExperimentKind::FrequencyResponse {
            return Ok(());
        }
        if let Some(pilot) = &self.pilot {
            self.validate_pilot(pilot)?;
        }
        if let (ExperimentKind::Chain, Some(chain)) = (kind, &self.chain) {
            return self.validate_chain(chain);
        }
        match (&self.setup, self.kind()) {
            (Some(setup), kind) => setup.validate_config(self, kind)?,
            (None, Kind::Synthetic) => self.validate_synthetic()?,
            (None, Kind::Measured) => self.validate_measured()?,
        }
        self.validate_options()
    }

    /// Checks the options of the stages (everything but the data sections), as
    /// reading a file does; for a config built in Rust and run on
    /// records in memory ([`crate::run_in_memory`]). Errors name the field.
    ///
    /// ```
    /// let mut config = msd_experiment::config::Config::new("bench");
    /// assert!(config.check_options().is_ok());
    /// config.residuals.max_lag = 0;
    /// let err = config.check_options().unwrap_err();
    /// assert_eq!(err.to_string(), "config of bench: residuals.max_lag = 0: expected an integer >= 1");
    /// ```
    pub fn check_options(&self) -> Result<()> {
        self.validate_options()
            .map_err(|(field, message)| ExperimentError::Config {
                file: format!("config of {}", self.name),
                message: format!("{field}{message}"),
            })
    }

    fn validate_options(&self) -> std::result::Result<(), (String, String)> {
        self.validate_estimation()?;
        if let Some(b) = &self.validation.backend {
            check_backend("validation.backend", b)?;
        }
        self.residuals
            .validate()
            .map_err(|e| library_error("residuals", e))?;
        if self.frequency_check.enabled {
            self.frequency_check
                .options()
                .validate()
                .map_err(|e| library_error("frequency_check", e))?;
        }
        let mc = &self.monte_carlo;
        if mc.enabled {
            mc.options().validate().map_err(|e| mc.refusal(e))?;
            if let Some(b) = &mc.backend {
                check_backend("monte_carlo.backend", b)?;
            }
        }
        if let Some(n) = &self.nonlinear {
            n.validate(&self.estimation)?;
        }
        if let Some(d) = &self.design {
            let per_plant = crate::budget::samples_per_experiment(self);
            crate::budget::check(
                "design.robust.plants",
                d.robust.plants as f64,
                per_plant,
                crate::budget::Budget::Fitted,
            )?;
        }
        Ok(())
    }

    /// A `[pilot]` needs a `[design]`, one source, and no `[plant]` (its estimate is the
    /// plant) nor `[data]`.
    fn validate_pilot(&self, pilot: &PilotSection) -> std::result::Result<(), (String, String)> {
        pilot.validate()?;
        let refuse = |field: &str, why: &str| Err((field.to_string(), why.to_string()));
        if self.design.is_none() {
            return refuse(
                "pilot",
                ": only with a [design] section (the pilot's estimate is the design's prior)",
            );
        }
        if self.plant.is_some() {
            return refuse(
                "plant",
                ": not with [pilot]: the pilot's estimate is the prior plant (remove one of them)",
            );
        }
        if self.data.is_some() || self.setup.is_some() {
            return refuse(
                "pilot",
                ": only in a synthetic design config ([time], [identification.input], [validation.input]; no [data] or [setup])",
            );
        }
        let spread = self.design.as_ref().map_or(0.3, |d| d.robust.spread);
        if spread != msd_ident::design::RobustBox::default().spread {
            return Err((
                "design.robust.spread".into(),
                format!(
                    " = {spread}: not with [pilot]: the pilot's standard errors set the box (±3 of its largest relative standard error); remove the key"
                ),
            ));
        }
        Ok(())
    }

    /// A `[chain]` needs `[time]` and `[identification.input]` (the drive's samples) and
    /// the true chain — or measured records in `[data]`: one file, the drive's column,
    /// each sensor's.
    fn validate_chain(&self, chain: &ChainSection) -> std::result::Result<(), (String, String)> {
        if let Some(d) = &self.data {
            return validate_chain_data(
                chain,
                d,
                self.time.is_some(),
                self.identification.is_some(),
            );
        }
        if chain.plant.is_none() {
            return Err((
                "chain.plant".into(),
                ": missing: a [chain] config without [data] simulates its records from the true chain".into(),
            ));
        }
        let Some(time) = &self.time else {
            return Err((
                "time".into(),
                ": missing section: a [chain] config needs [time]".into(),
            ));
        };
        validate_time(time)?;
        if self.identification.is_none() {
            return Err((
                "identification.input".into(),
                ": missing section: a [chain] config needs the drive's signal".into(),
            ));
        }
        // The record, the fit's copies and the Monte Carlo band's draws (every draw's
        // response of every sensor is held for the percentiles) per second of record.
        let sensors = chain.sensors.len() as f64;
        let draws = msd_mc::ChainBandOptions::default().samples as f64;
        let per_second = (sensors + 1.0 + sensors * draws) / time.dt;
        crate::budget::check("time.duration", time.duration, per_second, crate::budget::Budget::Held)
            .map_err(|(key, message)| {
                let held = sensors + 1.0 + sensors * draws;
                (
                    key,
                    format!(
                        "{message} s at time.dt = {} s ({held} values a sample: the drive, {sensors} sensors and the Monte Carlo band's {draws} draws of each); shorten time.duration or lengthen time.dt",
                        time.dt
                    ),
                )
            })?;
        // The fit's work: the record's samples weighted by the simulation's size, against
        // the budget a --verify has (a run fits a few times: the hold-out, ideal sensors).
        let work = chain.work_per_sample() / time.dt;
        crate::budget::check("time.duration", time.duration, work, crate::budget::Budget::Verified)
            .map_err(|(key, message)| {
                (
                    key,
                    format!(
                        "{message} s at time.dt = {} s for this chain's fit ({} masses: each sample costs {:.0} of a single mass's); shorten time.duration or lengthen time.dt",
                        time.dt,
                        chain.size(),
                        chain.work_per_sample()
                    ),
                )
            })?;
        chain.validate(time.duration)
    }

    fn validate_synthetic(&self) -> std::result::Result<(), (String, String)> {
        let missing = |field: &str, what: &str| {
            Err((
                field.to_string(),
                format!(
                    ": missing section: expected {what} (or a [data] section for measured data)"
                ),
            ))
        };
        // A sequential design's plant (and by default its noise) come from its pilot.
        let pilot = self.pilot.is_some();
        if self.plant.is_none() && !pilot {
            return missing("plant", "the true plant { mass, damping, stiffness }");
        }
        let Some(time) = &self.time else {
            return missing("time", "the time grid { duration, dt }");
        };
        if self.noise.is_none() && !pilot {
            return missing("noise", "the noise level { sigma }");
        }
        let Some(identification) = &self.identification else {
            return missing(
                "identification",
                "the identification input [identification.input]",
            );
        };
        let Some(validation_input) = &self.validation.input else {
            return missing(
                "validation.input",
                "the validation input [validation.input]",
            );
        };
        if let Some(plant) = &self.plant {
            validate_plant(plant)?;
        }
        validate_time(time)?;
        // The identification and validation records, input and displacement each.
        crate::budget::check(
            "time.duration",
            time.duration,
            4.0 / time.dt,
            crate::budget::Budget::Held,
        )?;
        if let Some(noise) = &self.noise {
            check_non_negative("noise.sigma", noise.sigma)?;
        }
        if let Err(e) = identification.input.validate() {
            return Err(("identification.input".into(), format!(": {e}")));
        }
        if let Err(e) = validation_input.validate() {
            return Err(("validation.input".into(), format!(": {e}")));
        }
        Ok(())
    }

    fn validate_measured(&self) -> std::result::Result<(), (String, String)> {
        for (field, present) in [
            ("plant", self.plant.is_some()),
            ("time", self.time.is_some()),
            ("noise", self.noise.is_some()),
            ("identification", self.identification.is_some()),
            ("validation.input", self.validation.input.is_some()),
        ] {
            if present {
                return Err((
                    field.into(),
                    ": not allowed with a [data] section: a config describes either synthetic or measured data".into(),
                ));
            }
        }
        let Some(d) = &self.data else { return Ok(()) };
        check_decimal("data", d.decimal, d.delimiter)?;
        if self.setup.is_none() {
            if let Some(v) = &d.validation_path {
                return Err((
                    "data.validation_path".into(),
                    format!(
                        " = {v}: only in a [setup] config (here data.validation gives the validation part of the record)"
                    ),
                ));
            }
            match d.path.0.len() {
                0 => return Err(("data.path".into(), " = []: expected a CSV file".into())),
                1 => {}
                n => {
                    return Err((
                        "data.path".into(),
                        format!(
                            " = {}: {n} files: expected one (several records are fitted together by a [setup] config)",
                            d.path
                        ),
                    ));
                }
            }
            for (key, column) in [("data.input", &d.input), ("data.output", &d.output)] {
                if column.is_none() {
                    return Err((
                        key.into(),
                        ": missing: expected the column (a header name or a 0-based index)".into(),
                    ));
                }
            }
        }
        for (i, p) in d.path.0.iter().enumerate() {
            if p.as_os_str().is_empty() {
                return Err((d.path.key(i), " = \"\": expected a CSV file".into()));
            }
        }
        match (&d.time, d.sample_rate) {
            (None, None) => {
                return Err((
                    "data".into(),
                    ": neither `time` nor `sample_rate` given: expected exactly one".into(),
                ));
            }
            (Some(_), Some(_)) => {
                return Err((
                    "data.sample_rate".into(),
                    ": both `time` and `sample_rate` given: expected exactly one".into(),
                ));
            }
            (None, Some(fs)) => check_positive("data.sample_rate", fs)?,
            (Some(_), None) => {}
        }
        check_finite_nonzero("data.input_scale", d.input_scale)?;
        check_finite_nonzero("data.output_scale", d.output_scale)?;
        for (i, step) in d.preprocessing.iter().enumerate() {
            match step {
                Preprocess::MovingAverage { window, .. } if *window == 0 || window % 2 == 0 => {
                    return Err((
                        format!("data.preprocessing[{i}].window"),
                        format!(" = {window}: expected an odd integer >= 1"),
                    ));
                }
                Preprocess::Decimate { factor } if *factor == 0 => {
                    return Err((
                        format!("data.preprocessing[{i}].factor"),
                        " = 0: expected an integer >= 1".into(),
                    ));
                }
                _ => {}
            }
        }
        for (name, range) in [
            ("data.estimation", Some(&d.estimation)),
            ("data.validation", d.validation.as_ref()),
        ] {
            let Some(r) = range else { continue };
            match (r.range, r.time) {
                (Some(_), Some(_)) => {
                    return Err((
                        format!("{name}.time"),
                        ": both `range` and `time` given: expected at most one".into(),
                    ));
                }
                (Some([a, b]), None) if a >= b => {
                    return Err((
                        format!("{name}.range"),
                        format!(" = [{a}, {b}]: expected start < end"),
                    ));
                }
                (None, Some([a, b])) if !(a.is_finite() && b.is_finite() && a < b) => {
                    return Err((
                        format!("{name}.time"),
                        format!(" = [{a}, {b}]: expected finite start < end (s)"),
                    ));
                }
                _ => {}
            }
        }
        Ok(())
    }

    fn validate_estimation(&self) -> std::result::Result<(), (String, String)> {
        check_backend("estimation.backend", &self.estimation.backend)?;
        self.estimation
            .validate()
            .map_err(|e| library_error("estimation", e))
    }
}

/// Checks the `[plant]` section.
fn validate_plant(plant: &Plant) -> std::result::Result<(), (String, String)> {
    plant
        .parameters()
        .validate()
        .map_err(|e| library_error("plant", e))?;
    check_non_negative("plant.coulomb_force", plant.coulomb_force)?;
    check_non_negative("plant.quadratic_damping", plant.quadratic_damping)?;
    check_finite("plant.cubic_stiffness", plant.cubic_stiffness)?;
    if plant.coulomb_force != 0.0 && plant.quadratic_damping != 0.0 {
        return Err((
            "plant.quadratic_damping".into(),
            format!(
                " = {}: given with coulomb_force = {}: expected at most one nonlinear damping term (no model structure has both)",
                plant.quadratic_damping, plant.coulomb_force
            ),
        ));
    }
    check_finite(
        "plant.initial_state.displacement",
        plant.initial_state.displacement,
    )?;
    check_finite("plant.initial_state.velocity", plant.initial_state.velocity)?;
    Ok(())
}

/// Checks the `[time]` section.
fn validate_time(time: &TimeGrid) -> std::result::Result<(), (String, String)> {
    check_finite("time.start", time.start)?;
    check_positive("time.dt", time.dt)?;
    check_positive("time.duration", time.duration)?;
    if time.duration < time.dt {
        return Err((
            "time.duration".into(),
            format!(
                " = {}: expected at least one step dt = {} (the record would hold one sample)",
                time.duration, time.dt
            ),
        ));
    }
    let n = time.samples();
    if n < MIN_SAMPLES {
        return Err((
            "time.duration".into(),
            format!(
                " = {}: gives {n} samples at dt = {}: expected at least {MIN_SAMPLES}",
                time.duration, time.dt
            ),
        ));
    }
    Ok(())
}

/// msd-ident's refusal of an option as (TOML key, rest of the message): the option it
/// names under `section`, else the section itself.
fn library_error(section: &str, error: msd_ident::IdentError) -> (String, String) {
    match error {
        msd_ident::IdentError::InvalidParameter {
            name,
            value,
            expected,
        }
        | msd_ident::IdentError::Modal(msd_modal::ModalError::InvalidParameter {
            name,
            value,
            expected,
        }) => (
            format!("{section}.{name}"),
            format!(" = {value}: expected {expected}"),
        ),
        other => {
            let text = other.to_string();
            let text = text.strip_prefix("invalid ").unwrap_or(&text).to_string();
            (section.to_string(), format!(": {text}"))
        }
    }
}

fn check_backend(field: &str, b: &Backend) -> std::result::Result<(), (String, String)> {
    b.validate().map_err(|e| {
        let text = e.to_string();
        (field.to_string(), format!(": {text}"))
    })
}

/// A value as written in a message: plainly, or in exponent form when very large or
/// small (1e300 is not 301 digits).
pub(crate) fn show(v: f64) -> String {
    if v.is_finite() && v != 0.0 && !(1e-4..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

fn check_positive(field: &str, v: f64) -> std::result::Result<(), (String, String)> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err((
            field.into(),
            format!(" = {}: expected a finite number > 0", show(v)),
        ))
    }
}

fn check_non_negative(field: &str, v: f64) -> std::result::Result<(), (String, String)> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err((
            field.into(),
            format!(" = {}: expected a finite number >= 0", show(v)),
        ))
    }
}

fn check_finite(field: &str, v: f64) -> std::result::Result<(), (String, String)> {
    if v.is_finite() {
        Ok(())
    } else {
        Err((
            field.into(),
            format!(" = {}: expected a finite number", show(v)),
        ))
    }
}

fn check_finite_nonzero(field: &str, v: f64) -> std::result::Result<(), (String, String)> {
    if v.is_finite() && v != 0.0 {
        Ok(())
    } else {
        Err((
            field.into(),
            format!(" = {}: expected a finite, non-zero factor", show(v)),
        ))
    }
}

/// The first key that the config's types read as a table of named fields but `text`
/// gives as an array (`plant = [1, 2, 3]`, which serde would read by position: m, c, k in
/// that order), with the array as written. Found by comparing the text with the config
/// written back: no list of table keys to keep in step with the types.
fn table_written_as_array(text: &str, config: &Config) -> Option<(String, toml::Value)> {
    let given: toml::Table = toml::from_str(text).ok()?;
    let read = toml::Table::try_from(config).ok()?;
    first_array_for_table(&given, &read, "")
}

fn first_array_for_table(
    given: &toml::Table,
    read: &toml::Table,
    prefix: &str,
) -> Option<(String, toml::Value)> {
    use toml::Value::{Array, Table};
    given.iter().find_map(|(key, value)| {
        let path = if prefix.is_empty() {
            key.clone()
        } else {
            format!("{prefix}.{key}")
        };
        match (value, read.get(key)?) {
            (Array(_), Table(_)) => Some((path, value.clone())),
            (Table(g), Table(r)) => first_array_for_table(g, r, &path),
            (Array(g), Array(r)) => g.iter().zip(r).find_map(|pair| match pair {
                (Table(g), Table(r)) => first_array_for_table(g, r, &path),
                (Array(_), Table(_)) => Some((path.clone(), value.clone())),
                _ => None,
            }),
            _ => None,
        }
    })
}

/// The dotted key and the value text of a `key = value` line whose value holds byte
/// `offset` (its start, or an element of an array; the table header above gives the
/// key's section); `None` elsewhere (a table header, a key, an inline table's inside).
fn key_of_value(text: &str, offset: usize) -> Option<(String, String)> {
    let line_start = text.get(..offset)?.rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[offset..].find('\n').map_or(text.len(), |i| offset + i);
    let (key, value) = text[line_start..line_end].split_once('=')?;
    let key = key.trim();
    // The offset lies in the value: at its start, or at an element of an array (not
    // inside an inline table, whose own keys the message names).
    let starts_value = line_start
        + text[line_start..line_end].find('=')?
        + 1
        + (value.len() - value.trim_start().len());
    let in_value =
        offset == starts_value || (offset > starts_value && value.trim_start().starts_with('['));
    if !in_value || key.is_empty() || key.starts_with('[') {
        return None;
    }
    let value = value.split(" #").next().unwrap_or(value).trim().to_string();
    let section = text[..line_start]
        .lines()
        .rev()
        .map(str::trim)
        .find(|l| l.starts_with('[') && !l.starts_with("[["))
        .map(|l| l.trim_matches(|c| c == '[' || c == ']').trim().to_string());
    let key = match section {
        Some(section) => format!("{section}.{key}"),
        None => key.to_string(),
    };
    Some((key, value))
}

/// 1-based line and column of byte `offset` in `text`.
pub(crate) fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let column = before
        .rfind('\n')
        .map_or(before.chars().count(), |p| before[p + 1..].chars().count())
        + 1;
    (line, column)
}

/// The 1-based line where the dotted key `path` (e.g. `plant.mass`) is set, found by a
/// plain scan of table headers and `key =` lines; `None` when it cannot be told.
/// An unknown variant inside a tagged table (`kind = "bogus"` in a term of
/// `[validation.input]`): toml points at the table, so the line that writes the value
/// is found below it and named with its key.
fn unknown_variant(text: &str, e: &toml::de::Error, file: &Path) -> Option<ExperimentError> {
    let message = e.message().trim().replace('\n', " ");
    let variant = message
        .strip_prefix("unknown variant `")?
        .split('`')
        .next()?;
    let start = e.span()?.start;
    let quoted = format!("\"{variant}\"");
    let offset = text.get(start..)?.find(&quoted)? + start;
    let (line, column) = line_column(text, offset);
    let written = text[..offset].rsplit('\n').next()?.trim();
    let key = written.strip_suffix('=')?.trim();
    let table = text[..offset]
        .lines()
        .rev()
        .map(str::trim)
        .find(|l| l.starts_with('['))
        .map(|l| format!(" in {l}"))
        .unwrap_or_default();
    Some(ExperimentError::Config {
        file: format!("{}:{line}:{column}", file.display()),
        message: format!("{key} = {quoted}{table}: {message}"),
    })
}

pub(crate) fn locate_key(text: &str, path: &str) -> Option<usize> {
    let path = path.split('[').next().unwrap_or(path);
    let mut table = String::new();
    let mut table_line = None;
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.starts_with('[') {
            let name = line
                .trim_start_matches('[')
                .split(']')
                .next()
                .unwrap_or("")
                .trim()
                .to_string();
            if name == path {
                table_line = Some(i + 1);
            }
            table = name;
            continue;
        }
        if let Some((key, _)) = line.split_once('=') {
            let key = key.trim().trim_matches('"');
            let full = if table.is_empty() {
                key.to_string()
            } else {
                format!("{table}.{key}")
            };
            if full == path {
                return Some(i + 1);
            }
            // `initial_state = { displacement = … }` and friends: the parent key's line.
            if path.starts_with(&format!("{full}.")) && line.contains('{') {
                return Some(i + 1);
            }
        }
    }
    table_line
}

/// A decimal mark `"."` or `","`, not the delimiter; errors name `{table}.decimal`.
/// A `[chain]` on measured records: `[data]` with one file, the drive's column and no
/// output column; every sensor's column; no true chain, no synthetic sections.
fn validate_chain_data(
    chain: &ChainSection,
    d: &DataSection,
    time: bool,
    identification: bool,
) -> std::result::Result<(), (String, String)> {
    let not_with_data =
        |key: &str, why: &str| Err((key.to_string(), format!(": not with [data]: {why}")));
    if chain.plant.is_some() {
        return not_with_data(
            "chain.plant",
            "the measured chain is what the fit finds (its guess starts the fit)",
        );
    }
    if time {
        return not_with_data(
            "time",
            "the records give the sampling (data.time or data.sample_rate)",
        );
    }
    if identification {
        return not_with_data("identification", "the records give the drive (data.input)");
    }
    check_decimal("data", d.decimal, d.delimiter)?;
    if d.path.0.len() != 1 {
        return Err((
            "data.path".into(),
            format!(
                " = {}: expected one file holding the drive and every sensor",
                d.path
            ),
        ));
    }
    if d.input.is_none() {
        return Err((
            "data.input".into(),
            ": missing: expected the drive's column (the force, or the base acceleration)".into(),
        ));
    }
    if d.output.is_some() {
        return Err(("data.output".into(), ": not read by a [chain] config: each sensor names its column (chain.sensors[i].column)".into()));
    }
    if let Some(i) = chain.sensors.iter().position(|s| s.column.is_none()) {
        return Err((
            format!("chain.sensors[{i}].column"),
            ": missing: with [data], each sensor names its column".into(),
        ));
    }
    if d.time.is_none() && d.sample_rate.is_none() {
        return Err((
            "data.time".into(),
            ": missing: expected data.time or data.sample_rate".into(),
        ));
    }
    chain.validate(f64::INFINITY)
}

pub(crate) fn check_decimal(
    table: &str,
    decimal: char,
    delimiter: char,
) -> std::result::Result<(), (String, String)> {
    if decimal != '.' && decimal != ',' {
        return Err((
            format!("{table}.decimal"),
            format!(" = {decimal:?}: expected \".\" or \",\""),
        ));
    }
    // Decimal commas beside the default delimiter: the delimiter is found in the file.
    if decimal == delimiter && decimal != ',' {
        return Err((
            format!("{table}.decimal"),
            format!(
                " = {decimal:?} is also the delimiter: expected another {table}.delimiter (\";\" or a tab with decimal commas)"
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_empty_list_of_data_files_names_its_key() {
        let text = "name = \"x\"\n[data]\npath = []\ninput = \"f\"\noutput = \"x\"\n";
        let err = Config::from_toml_str(text, "x.toml").expect_err("refused");
        let message = err.to_string();
        assert!(
            message.contains("data.path") && message.contains("empty list"),
            "{message}"
        );
    }

    #[test]
    fn locates_keys_in_tables() {
        let text = "name = \"x\"\n[plant]\nmass = -1\n\n[estimation.backend]\nkind = \"ode45\"\n";
        assert_eq!(locate_key(text, "name"), Some(1));
        assert_eq!(locate_key(text, "plant.mass"), Some(3));
        assert_eq!(locate_key(text, "estimation.backend"), Some(5));
        assert_eq!(locate_key(text, "estimation.backend.kind"), Some(6));
        assert_eq!(locate_key(text, "monte_carlo.samples"), None);
    }

    #[test]
    fn an_unknown_variant_in_a_tagged_table_is_named_at_its_line() {
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../configs/paper-fast.toml"
        ))
        .unwrap();
        let at = text.find("kind = \"chirp\"").expect("a chirp term");
        let line = text[..at].lines().count() + 1;
        let bad = text.replacen("kind = \"chirp\"", "kind = \"chirpp\"", 1);
        let err = Config::from_toml_str(&bad, "p.toml")
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with(&format!("p.toml:{line}:8: kind = \"chirpp\" in [[")),
            "{err}"
        );
        assert!(err.contains("input.terms]]: unknown variant"), "{err}");
    }

    #[test]
    fn line_and_column_are_one_based() {
        assert_eq!(line_column("ab\ncd", 0), (1, 1));
        assert_eq!(line_column("ab\ncd", 4), (2, 2));
    }
}
