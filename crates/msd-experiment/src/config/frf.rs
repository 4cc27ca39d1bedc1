//! The optional `[frequency_response]` section: a frequency response read (a CSV table of
//! a stepped-sine sweep, a UFF 58 file, time records) or simulated from a known plant (a
//! stepped sine, hammer hits), and one mode or several fitted to it ([`crate::frf`]).
//!
//! A config with this section and no time-domain sections (`[plant]`, `[data]`, …) is a
//! frequency-domain experiment of its own. Exactly one source: `sweep`, `hammer`,
//! `shaker`, `table`, `uff` or `records`. One mode is fitted unless `[frequency_response.modes]`
//! is given (msd-ident's [`OneModeOptions`] and msd-modal's [`ModalOptions`], as they are).
//!
//! ```
//! use msd_experiment::config::Config;
//! let text = r#"
//!     name = "sweep"
//!     [frequency_response.plant]
//!     masses = [2.5]
//!     springs = [120.0]
//!     dampers = [1.8]
//!     [frequency_response.sweep]
//!     band_hz = [0.25, 2.5]
//!     lines = 40
//! "#;
//! let config = Config::from_toml_str(text, "sweep.toml")?;
//! assert!(config.frequency_only());
//! let section = config.frequency_response.as_ref().expect("given");
//! assert_eq!(section.sweep.as_ref().map(|s| s.relative_noise), Some(0.01));
//! let bad = text.replace("lines = 40", "lines = 40\n[frequency_response.uff]\npath = \"x.uff\"");
//! let err = Config::from_toml_str(&bad, "sweep.toml").unwrap_err();
//! assert_eq!(err.to_string(), "sweep.toml:10: frequency_response.uff: a second source beside \
//!     `sweep`: expected exactly one of sweep, hammer, shaker, table, set, uff, records");
//! # Ok::<(), msd_experiment::ExperimentError>(())
//! ```

use super::{Column, Config, default_true};
use msd_ident::OneModeOptions;
use msd_modal::ModalOptions;
use msd_signal::{FrfKind, FrfOptions, Signal};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

mod validate;

type Check = std::result::Result<(), (String, String)>;

/// The `[frequency_response]` section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrequencyResponseSection {
    /// The true plant: required by `sweep` and `hammer`; with a file, the truth it is
    /// compared with.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plant: Option<ChainPlant>,
    /// A stepped-sine sweep simulated on the plant.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sweep: Option<SweepSource>,
    /// Hammer hits simulated on the plant.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hammer: Option<HammerSource>,
    /// Time records of a shaker's force (a signal, e.g. a random-phase multisine)
    /// simulated on the plant.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shaker: Option<ShakerSource>,
    /// A measured table (CSV), one row per line.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub table: Option<TableSource>,
    /// A set of measured FRFs of one test (`[[frequency_response.set]]`: one table
    /// each, with its `response` and `reference` DOFs): modes common to all of them,
    /// with their shapes (msd-modal's `fit_mode_set`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub set: Option<Vec<TableSource>>,
    /// A UFF file's dataset 58.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uff: Option<UffSource>,
    /// Measured time records (CSV): force and response columns, one pair per record.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub records: Option<RecordsSource>,
    /// How time records (`hammer`, `shaker`, `records`) become a frequency response: msd-signal's
    /// [`FrfOptions`] (estimator, Welch segments, impact windows, response quantity: the
    /// simulated sources measure the quantity of `kind`). By default H1 over whole
    /// records, the window chosen from the data (rectangular when the force repeats from
    /// record to record, a periodic input over whole periods; otherwise Hann), receptance.
    #[serde(default)]
    pub estimator: FrfOptions,
    /// One mode: msd-ident's [`OneModeOptions`] (`band_hz`, `weighting`). By default
    /// every line, weights from the coherence.
    #[serde(default)]
    pub one_mode: OneModeOptions,
    /// Several modes instead: msd-modal's [`ModalOptions`] (orders, tolerances,
    /// `mode_count`, …). By default not given (one mode).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub modes: Option<ModalOptions>,
    /// The modes a set is compared with (a model's, or a simulation's truth): each with
    /// `natural_frequency_hz`, `damping_ratio` and its `shape` over the set's roving DOFs,
    /// in the set's order. The report gives MAC(estimated, reference) per mode and whether
    /// fn and ζ lie inside their 95 % intervals.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_modes: Option<Vec<ReferenceMode>>,
    /// A UFF file of mode shapes (datasets 55: another test's, or a model's) that a set's
    /// shapes are compared with, relative to the config file: the MAC of every estimated
    /// mode with every mode of the file, on the DOFs both give (a DOF measured in the
    /// opposite sense is negated). The report gives the matrix and each mode's best match.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_shapes: Option<PathBuf>,
    /// A UFF file with the nodes' coordinates (datasets 15 or 2411), relative to the config
    /// file, over which a set's shapes are drawn (`frf_shapes_geometry`). By default the
    /// set's own UFF file's nodes, when it has them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geometry: Option<PathBuf>,
    /// Whether the force is measured in its units: the one-mode fit then reports m, c, k;
    /// otherwise fn, ζ and the gain 1/m (m, c and k scale with the force). By default true.
    #[serde(default = "default_true")]
    pub force_scale_known: bool,
}

pub use msd_ident::chain::ChainPlant;
pub use msd_modal::Dof;

/// A mode a set is compared with: fn, ζ and the shape over the set's roving DOFs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceMode {
    /// Natural frequency, Hz.
    pub natural_frequency_hz: f64,
    /// Damping ratio.
    pub damping_ratio: f64,
    /// The shape's value at each roving DOF, in the set's order (real).
    pub shape: Vec<f64>,
}

/// How the lines of a simulated sweep are spaced.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Spacing {
    /// Equal ratios (a constant relative resolution, as a sweep is usually stepped).
    /// The default.
    #[default]
    Logarithmic,
    /// Equal steps.
    Linear,
}

/// A stepped sine simulated on the plant: each line the exact response with complex
/// noise of relative size `relative_noise` (msd-ident's
/// [`synthetic_frequency_response`](msd_modal::synthetic_frequency_response)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSource {
    /// First and last excitation frequency, Hz (0 < first < last).
    #[serde(deserialize_with = "msd_signal::pair::exactly_two")]
    pub band_hz: [f64; 2],
    /// Number of excitation frequencies (≥ 4).
    pub lines: usize,
    /// Their spacing. By default logarithmic.
    #[serde(default)]
    pub spacing: Spacing,
    /// E|e|²/|H|² of the complex noise. By default 0.01 (1 %).
    #[serde(default = "one_percent")]
    pub relative_noise: f64,
}

fn one_percent() -> f64 {
    0.01
}

/// Hammer hits simulated on the plant: half-sine force pulses, the response computed
/// exactly (the force linear between samples), noise on both channels.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HammerSource {
    /// Number of hits (records). By default 5.
    #[serde(default = "five")]
    pub hits: usize,
    /// Sampling rate, Hz (> 0).
    pub sample_rate: f64,
    /// Length of each record, s.
    pub duration: f64,
    /// Width of the half-sine pulse, s (at least two samples).
    pub pulse_width: f64,
    /// When the pulse starts in each record, s. By default 0.05.
    #[serde(default = "trigger")]
    pub trigger: f64,
    /// Peak force of a hit, N. By default 100.
    #[serde(default = "hundred")]
    pub force_peak: f64,
    /// Relative standard deviation of the peak force from hit to hit. By default 0.2.
    #[serde(default = "fifth")]
    pub force_spread: f64,
    /// Noise on the force channel, N (standard deviation). By default 0.5.
    #[serde(default = "half")]
    pub force_noise: f64,
    /// Noise on the response channel, as a share of the peak response to a hit of
    /// `force_peak`: one sensor noise on every record. By default 0.02.
    #[serde(default = "two_percent")]
    pub response_noise: f64,
}

fn five() -> usize {
    5
}
fn trigger() -> f64 {
    0.05
}
fn hundred() -> f64 {
    100.0
}
fn fifth() -> f64 {
    0.2
}
fn half() -> f64 {
    0.5
}
fn two_percent() -> f64 {
    0.02
}

/// Time records of a shaker simulated on the plant: one run of the force signal from
/// rest, the first `settle` seconds left out, then `records` consecutive records of
/// `duration` seconds; the response is computed exactly for a force linear between
/// points 16 times denser than the samples (so that the sampled force is, to
/// (π·f/(16·fs))²/3, the continuous one), as the quantity of `estimator.kind`, with
/// noise on both channels. A multisine whose period is `duration` makes every record one
/// period of the steady state once the start transient has died out (give `settle` a few
/// time constants 1/(ζ·ωn) of the slowest mode): with a rectangular window its lines do
/// not leak.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShakerSource {
    /// Number of records. By default 4.
    #[serde(default = "four")]
    pub records: usize,
    /// Sampling rate, Hz (> 0).
    pub sample_rate: f64,
    /// Length of each record, s.
    pub duration: f64,
    /// Seconds simulated before the first record. By default 0: the first record then
    /// holds the start transient from rest, which leaks into H1 (the time-domain fit
    /// models it); a few time constants 1/(ζ·ωn) leave the steady state alone.
    #[serde(default)]
    pub settle: f64,
    /// The force, N: any msd-signal [`Signal`] (`kind = "multisine"`, `"prbs"`, …),
    /// t = 0 at the start of the run.
    pub force: Signal,
    /// Noise on the force channel, as a share of the force's RMS. By default 0: the
    /// time-domain fit of the records takes the measured force as exact, and noise on it
    /// adds a resonant residual its intervals do not account for (H1 is biased low by
    /// it, by 1/(1 + noise-to-signal power) per line).
    #[serde(default)]
    pub force_noise: f64,
    /// Noise on the response channel, as a share of the response's RMS. By default 0.02.
    #[serde(default = "two_percent")]
    pub response_noise: f64,
}

fn four() -> usize {
    4
}

/// A measured frequency response as a CSV table: a frequency column (or
/// `frequency_step_hz` when the file has none) and either magnitude and phase, real and
/// imaginary, or one column of complex numbers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TableSource {
    /// The CSV file, relative to the config file.
    pub path: PathBuf,
    /// The frequency column, Hz (increasing); or none, with `frequency_step_hz`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frequency: Option<Column>,
    /// The frequency column's unit: `"Hz"` (the default), `"kHz"`, `"rad/s"` or `"rpm"`
    /// (cycles per minute); the fits work in Hz. A column whose name states another
    /// unit (`Frequency [kHz]`, `w (rad/s)`) is refused until this key says it.
    #[serde(default, skip_serializing_if = "FrequencyUnit::is_hertz")]
    pub frequency_unit: FrequencyUnit,
    /// Without a frequency column: line i (from 0) is at `frequency_start_hz` + i ×
    /// `frequency_step_hz`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frequency_step_hz: Option<f64>,
    /// The first line's frequency without a frequency column, Hz. By default 0.
    #[serde(default)]
    pub frequency_start_hz: f64,
    /// A column of complex numbers as text: `a+bj`, `(a+bj)` (Python, NumPy), `a+bi`
    /// (MATLAB, Octave) or `a` alone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub complex: Option<Column>,
    /// The magnitude column (with `phase`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub magnitude: Option<Column>,
    /// The phase column (with `magnitude`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub phase: Option<Column>,
    /// Whether the phase is in degrees (else radians). By default true.
    #[serde(default = "default_true")]
    pub phase_in_degrees: bool,
    /// Whether the magnitude is in decibels, 20·log₁₀|H| (as analysers export it), else
    /// linear. By default false; a magnitude column whose name says dB is refused
    /// until this key says so.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub magnitude_in_db: bool,
    /// The real-part column (with `imaginary`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub real: Option<Column>,
    /// The imaginary-part column (with `real`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub imaginary: Option<Column>,
    /// The ordinary coherence γ² column, in [0, 1], when the analyser exported it: the
    /// fits then weight each line by what it is worth (the variance of an H1 line,
    /// (1 − γ²)/(K·γ²)·|H|²) and the report shows it. By default none (every line
    /// weighted alike in the measured quantity).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coherence: Option<Column>,
    /// With `coherence`: the number of averages K it was estimated over (the analyser's
    /// header says it). Without it the coherence weights the lines relative to each
    /// other only, and the residuals cannot be checked against the FRF's own noise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub averages: Option<usize>,
    /// What the response measures. By default receptance.
    #[serde(default)]
    pub kind: FrfKind,
    /// In a `set`: the response DOF, `{ node = 1, direction = 3 }` (UFF's numbering:
    /// direction ±1, ±2, ±3 for ±X, ±Y, ±Z).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub response: Option<Dof>,
    /// In a `set`: the reference (force) DOF.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference: Option<Dof>,
    /// Field delimiter. By default `","`; `" "` for columns separated by runs of spaces
    /// or tabs (NumPy's `savetxt`, MATLAB's `save -ascii`).
    #[serde(default = "comma")]
    pub delimiter: char,
    /// Whether the first (non-skipped) line holds column names. By default true.
    #[serde(default = "default_true")]
    pub header: bool,
    /// The decimal mark: `"."` (the default) or `","` (with a delimiter other than `","`).
    #[serde(
        default = "super::default_decimal",
        skip_serializing_if = "super::is_point"
    )]
    pub decimal: char,
    /// Lines to skip before the header. By default 0: metadata lines above the header
    /// (a SignalCalc or spreadsheet export's) and a units line under it are found by
    /// themselves, and the report says which.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub skip_lines: usize,
    /// What to do with a missing value: `"refuse"` (the default), `"drop"` the line or
    /// `"interpolate"` it; the report says how many.
    #[serde(default, skip_serializing_if = "crate::data::text::Missing::is_refuse")]
    pub missing: crate::data::text::Missing,
}

/// The unit of a frequency column.
///
/// ```
/// use msd_experiment::config::FrequencyUnit;
/// assert_eq!(FrequencyUnit::of("kHz"), Some(FrequencyUnit::Kilohertz));
/// assert_eq!(FrequencyUnit::of("rad/s").map(FrequencyUnit::hertz), Some(1.0 / std::f64::consts::TAU));
/// assert_eq!(FrequencyUnit::of("m/s"), None);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum FrequencyUnit {
    /// Hz.
    #[default]
    #[serde(rename = "Hz")]
    Hertz,
    /// kHz.
    #[serde(rename = "kHz")]
    Kilohertz,
    /// rad/s (ω).
    #[serde(rename = "rad/s")]
    RadiansPerSecond,
    /// Cycles per minute (rpm, cpm).
    #[serde(rename = "rpm")]
    PerMinute,
}

impl FrequencyUnit {
    /// Hz in one of this unit.
    pub fn hertz(self) -> f64 {
        match self {
            Self::Hertz => 1.0,
            Self::Kilohertz => 1e3,
            Self::RadiansPerSecond => 1.0 / std::f64::consts::TAU,
            Self::PerMinute => 1.0 / 60.0,
        }
    }

    /// The unit a column's name or units line writes (`Hz`, `kHz`, `rad/s`, `rpm`,
    /// `cpm`, `1/min`; case aside but for the `k`), `None` for any other.
    pub fn of(unit: &str) -> Option<Self> {
        match unit.trim() {
            "Hz" | "hz" | "HZ" | "1/s" => Some(Self::Hertz),
            "kHz" | "khz" | "KHz" | "kHZ" => Some(Self::Kilohertz),
            "rad/s" | "rad/sec" | "rad s^-1" => Some(Self::RadiansPerSecond),
            "rpm" | "RPM" | "cpm" | "CPM" | "1/min" => Some(Self::PerMinute),
            _ => None,
        }
    }

    /// Whether it is Hz (the default, not written).
    pub fn is_hertz(&self) -> bool {
        *self == Self::Hertz
    }

    /// As a config writes it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Hertz => "Hz",
            Self::Kilohertz => "kHz",
            Self::RadiansPerSecond => "rad/s",
            Self::PerMinute => "rpm",
        }
    }
}

fn comma() -> char {
    ','
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// The text format of a table or records source.
macro_rules! text_format {
    ($t:ty) => {
        impl $t {
            /// How its text file is written.
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
    };
}
text_format!(TableSource);
text_format!(RecordsSource);

/// A function of a UFF file (datasets 58 and 58b, read by msd-uff).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UffSource {
    /// The UFF file, relative to the config file.
    pub path: PathBuf,
    /// Which dataset 58 of the file, counted from 1. By default the first frequency
    /// response function.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub function: Option<usize>,
    /// What the response measures. By default from the file: the ordinate axis's data
    /// type (displacement, velocity or acceleration) or, when that is "general" or
    /// unknown, its units (`m/N`, `(m/s)/N`, `(1/N)*(m/s2)`, `g/N`); a file that says
    /// neither, or whose type and units disagree, is refused until this key says.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kind: Option<FrfKind>,
    /// Every frequency response function of the file (datasets 58 of function type 4) as
    /// one set of a test, each with its response and reference node and direction
    /// (instead of `function`). By default false.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub set: bool,
    /// The number of averages K the file's coherence functions were estimated over (the
    /// analyser's setup says it). Each FRF takes the coherence function (dataset 58 of
    /// function type 6) of its response and reference DOFs, when the file holds one, and
    /// the fits weight its lines by it; with K the coherence gives each line's absolute
    /// variance and the residuals are checked against it, without K the lines' relative
    /// weights only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub averages: Option<usize>,
}

/// Measured time records in one CSV file: `force[i]` and `response[i]` are record i.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RecordsSource {
    /// The CSV file, relative to the config file.
    pub path: PathBuf,
    /// Sampling rate, Hz.
    pub sample_rate: f64,
    /// The force column of each record.
    pub force: Vec<Column>,
    /// The response column of each record.
    pub response: Vec<Column>,
    /// Field delimiter. By default `","`; `" "` for columns separated by runs of spaces
    /// or tabs (NumPy's `savetxt`, MATLAB's `save -ascii`).
    #[serde(default = "comma")]
    pub delimiter: char,
    /// Whether the first (non-skipped) line holds column names. By default true.
    #[serde(default = "default_true")]
    pub header: bool,
    /// The decimal mark: `"."` (the default) or `","` (with a delimiter other than `","`).
    #[serde(
        default = "super::default_decimal",
        skip_serializing_if = "super::is_point"
    )]
    pub decimal: char,
    /// Lines to skip before the header. By default 0: metadata lines above the header
    /// (a SignalCalc or spreadsheet export's) and a units line under it are found by
    /// themselves, and the report says which.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub skip_lines: usize,
    /// What to do with a missing value: `"refuse"` (the default), `"drop"` the line or
    /// `"interpolate"` it; the report says how many.
    #[serde(default, skip_serializing_if = "crate::data::text::Missing::is_refuse")]
    pub missing: crate::data::text::Missing,
}

impl Config {
    /// Whether the config is a frequency-domain experiment only: a
    /// `[frequency_response]` section and no time-domain data.
    pub fn frequency_only(&self) -> bool {
        self.frequency_response.is_some()
            && self.data.is_none()
            && self.plant.is_none()
            && self.identification.is_none()
    }
}
