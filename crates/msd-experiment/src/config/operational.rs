//! The optional `[operational]` section: output-only (operational) modal analysis of a
//! structure's response with no measured input ([`crate::operational`]). Exactly one
//! source: `record` (a file: a NumPy `.npy` array as pyOMA ships its setups, with its
//! `channel_dofs.txt` and `setup_info.txt`, or a CSV file with `[[operational.channels]]`)
//! or `[operational.simulate]` (a shear building with a known truth). The analysis:
//! `method` (`"ssi-cov"`, the default, or `"efdd"`) with its options, `[operational.ssi]`
//! (msd-modal's [`OmaOptions`]) or `[operational.efdd]` ([`FddOptions`]) as they are.
//!
//! ```
//! use msd_experiment::config::Config;
//! let text = r#"
//!     name = "building"
//!     [operational.simulate]
//!     masses = [25.91, 25.91]
//!     stiffnesses = [10000.0, 10000.0]
//!     damping_ratio = 0.02
//!     sample_rate_hz = 100.0
//!     samples = 20000
//!     [operational.ssi]
//!     orders = [2, 40]
//! "#;
//! let config = Config::from_toml_str(text, "building.toml")?;
//! let section = config.operational.as_ref().expect("given");
//! assert_eq!(section.ssi.orders, [2, 40]);
//! assert_eq!(section.simulate.as_ref().map(|s| s.noise), Some(0.1));
//! let both = format!("{text}\n[operational.record]\npath = \"x.npy\"");
//! let err = Config::from_toml_str(&both, "building.toml").unwrap_err();
//! assert!(err.to_string().contains("exactly one of record, records, simulate"), "{err}");
//! # Ok::<(), msd_experiment::ExperimentError>(())
//! ```

use super::{Column, default_true};
use msd_modal::{FddOptions, OmaMethod, OmaOptions, Quantity};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

type Check = std::result::Result<(), (String, String)>;

/// The `[operational]` section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OperationalSection {
    /// A measured record.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub record: Option<RecordSource>,
    /// Several records of one structure, each analysed alone and then combined
    /// (`[[operational.records]]`, each as `record`): setups with a roving sensor and
    /// shared references merged into global shapes, or the hourly records of a monitored
    /// structure tracked from record to record.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub records: Vec<RecordSource>,
    /// How close (relative) two records' frequencies must be to be one mode. By default
    /// 0.01.
    #[serde(default = "hundredth")]
    pub merge_tolerance: f64,
    /// A simulated shear building (the truth known).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub simulate: Option<SimulatedBuilding>,
    /// The structure's nodes and lines, to draw the shapes on (`oma_shapes`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geometry: Option<GeometrySection>,
    /// The channels of a CSV record (for a `.npy` record: read from its
    /// `channel_dofs.txt` and `setup_info.txt` unless given here).
    #[serde(default)]
    pub channels: Vec<OutputChannelSection>,
    /// A channel that is NaN or constant throughout (a dead sensor): `"leave_out"` (the
    /// default: named in the report) or `"refuse"`.
    #[serde(default)]
    pub dead_channels: DeadChannels,
    /// The method: `"ssi-cov"` (the default: SSI-cov/ref with automatic selection),
    /// `"ssi-dat"` (data-driven SSI/ref, the same options) or `"efdd"` (frequency domain
    /// decomposition with EFDD's damping: the quick look).
    #[serde(default)]
    pub method: OmaMethod,
    /// SSI-cov/ref's options (msd-modal's `OmaOptions`, as they are).
    #[serde(default)]
    pub ssi: OmaOptions,
    /// EFDD's options (msd-modal's `FddOptions`, as they are).
    #[serde(default)]
    pub efdd: FddOptions,
}

/// The files of a structure's geometry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeometrySection {
    /// Nodes: a node number and its x, y, z per line (z up; any length unit), an optional
    /// header line (pyOMA's `grid.txt`).
    pub nodes: PathBuf,
    /// Lines: two node numbers per line (pyOMA's `lines.txt`). By default none (the nodes
    /// alone are drawn).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lines: Option<PathBuf>,
    /// The coordinates' unit, for the figure. By default `"m"`.
    #[serde(default = "metre")]
    pub unit: String,
}

fn metre() -> String {
    "m".into()
}

/// What is done with a dead channel.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DeadChannels {
    /// Left out, and said so.
    #[default]
    LeaveOut,
    /// The run stops, naming it.
    Refuse,
}

/// A record file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RecordSource {
    /// The file, relative to the config: `.npy` (samples × channels, float64) or `.csv`.
    pub path: PathBuf,
    /// A `.npy` record's channel file (pyOMA's: channel, node, azimuth, elevation,
    /// name). By default `channel_dofs.txt` beside the record.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub channel_dofs: Option<PathBuf>,
    /// A `.npy` record's setup file (pyOMA's: sampling rate, reference, left-out,
    /// acceleration, velocity and displacement channels). By default `setup_info.txt`
    /// beside the record.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub setup_info: Option<PathBuf>,
    /// Samples per second (a CSV record without a time column; overrides a setup file).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sample_rate_hz: Option<f64>,
    /// A CSV record's time column.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<Column>,
    /// A CSV record's field delimiter. By default `","`; `" "` for columns separated by
    /// runs of spaces or tabs.
    #[serde(default = "comma")]
    pub delimiter: char,
    /// A CSV record's decimal mark: `"."` (the default) or `","`.
    #[serde(
        default = "super::default_decimal",
        skip_serializing_if = "super::is_point"
    )]
    pub decimal: char,
    /// Whether a CSV record's first (non-skipped) line holds column names. By default true.
    #[serde(default = "default_true")]
    pub header: bool,
    /// Lines to skip at the top of a CSV record. By default 0 (metadata lines above the
    /// header are found by themselves).
    #[serde(default)]
    pub skip_lines: usize,
    /// What to do with a missing value in a CSV record: `"refuse"` (the default),
    /// `"drop"` or `"interpolate"`.
    #[serde(default, skip_serializing_if = "crate::data::text::Missing::is_refuse")]
    pub missing: crate::data::text::Missing,
    /// How the report and figure name this record among several (e.g. when it was
    /// taken: "11-28 14:00"). By default its number.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label: Option<String>,
}

fn comma() -> char {
    ','
}

/// One channel of a record.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputChannelSection {
    /// The CSV column (a name, or a 0-based index), or the `.npy` array's column index.
    pub column: Column,
    /// The node it measures at.
    pub node: u32,
    /// Its direction along the geometry's axes: ±1, ±2, ±3 (x, y, z); or give
    /// `azimuth_deg` and `elevation_deg` for an oblique one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<i32>,
    /// An oblique direction's azimuth, degrees (from +x towards +y).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub azimuth_deg: Option<f64>,
    /// An oblique direction's elevation, degrees (up from the x–y plane).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elevation_deg: Option<f64>,
    /// `"displacement"`, `"velocity"` or `"acceleration"` (the default).
    #[serde(default = "acceleration")]
    pub quantity: Quantity,
    /// Whether it is a reference channel. By default every channel is, when none is
    /// named.
    #[serde(default)]
    pub reference: bool,
    /// A factor applied on reading (e.g. 9.81 for g → m/s²). By default 1.
    #[serde(default = "one")]
    pub scale: f64,
}

fn one() -> f64 {
    1.0
}

/// A shear building under white-noise forces on every floor, its floors' accelerations
/// with noise (msd-modal's `ShearBuilding`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulatedBuilding {
    /// The floors' masses, kg, from the ground up.
    pub masses: Vec<f64>,
    /// The storeys' stiffnesses, N/m.
    pub stiffnesses: Vec<f64>,
    /// Every mode's damping ratio.
    pub damping_ratio: f64,
    /// Samples per second.
    pub sample_rate_hz: f64,
    /// Samples per channel.
    pub samples: usize,
    /// Each channel's noise as a fraction of its rms. By default 0.1.
    #[serde(default = "tenth")]
    pub noise: f64,
}

fn tenth() -> f64 {
    0.1
}

fn acceleration() -> Quantity {
    Quantity::Acceleration
}

fn hundredth() -> f64 {
    0.01
}

impl OperationalSection {
    /// Checks the section; errors name the key under `operational.`.
    pub(crate) fn validate(&self) -> Check {
        let err = |key: &str, message: String| Err((format!("operational.{key}"), message));
        let given = [
            self.record.is_some(),
            !self.records.is_empty(),
            self.simulate.is_some(),
        ];
        if given.iter().filter(|&&g| g).count() != 1 {
            let key = ["record", "records", "simulate"]
                .iter()
                .zip(given)
                .filter(|(_, g)| *g)
                .map(|(k, _)| *k)
                .nth(1)
                .unwrap_or("record");
            return err(
                key,
                ": expected exactly one of record, records, simulate".into(),
            );
        }
        if let Some(r) = &self.record {
            validate_record(r, &self.channels)?;
        }
        if self.records.len() == 1 {
            return err(
                "records",
                ": one record: expected two or more [[operational.records]] (or [operational.record] for one)".into(),
            );
        }
        for (i, r) in self.records.iter().enumerate() {
            validate_record(r, &self.channels).map_err(|(key, message)| {
                (
                    key.replace("operational.record", &format!("operational.records[{i}]")),
                    message,
                )
            })?;
        }
        if !(self.merge_tolerance > 0.0 && self.merge_tolerance < 0.5) {
            return err(
                "merge_tolerance",
                format!(
                    " = {}: expected a relative tolerance in (0, 0.5)",
                    self.merge_tolerance
                ),
            );
        }
        if let Some(b) = &self.simulate {
            validate_building(b)?;
        }
        let table = self.options_table();
        let checked = match self.method {
            OmaMethod::SsiCov | OmaMethod::SsiDat => self.ssi.validate(),
            OmaMethod::Efdd => self.efdd.validate(),
        };
        checked.map_err(|e| match e {
            msd_modal::ModalError::InvalidParameter {
                name,
                value,
                expected,
            } => (
                format!("operational.{table}.{name}"),
                format!(" = {value}: expected {expected}"),
            ),
            other => (format!("operational.{table}"), format!(": {other}")),
        })
    }

    /// The table holding the chosen method's options: `ssi` or `efdd`.
    pub fn options_table(&self) -> &'static str {
        match self.method {
            OmaMethod::SsiCov | OmaMethod::SsiDat => "ssi",
            OmaMethod::Efdd => "efdd",
        }
    }
}

fn validate_record(r: &RecordSource, channels: &[OutputChannelSection]) -> Check {
    let err = |key: &str, message: String| Err((format!("operational.{key}"), message));
    super::check_decimal("operational.record", r.decimal, r.delimiter)?;
    if let Some(fs) = r.sample_rate_hz
        && !(fs.is_finite() && fs > 0.0)
    {
        return err(
            "record.sample_rate_hz",
            format!(" = {fs}: expected a positive rate"),
        );
    }
    if let Some(i) = channels.iter().position(|c| c.quantity == Quantity::Force) {
        return err(
            &format!("channels[{i}].quantity"),
            " = \"force\": expected \"displacement\", \"velocity\" or \"acceleration\" (an output-only analysis reads motions)".into(),
        );
    }
    let csv = r
        .path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    if csv && channels.len() < 2 {
        return err(
            "channels",
            ": a CSV record needs at least two [[operational.channels]] (column, node, direction, quantity)".into(),
        );
    }
    if csv && r.time.is_none() && r.sample_rate_hz.is_none() {
        return err(
            "record.time",
            ": missing: expected a time column or record.sample_rate_hz".into(),
        );
    }
    for (i, c) in channels.iter().enumerate() {
        let oblique = c.azimuth_deg.is_some() || c.elevation_deg.is_some();
        match (c.direction, oblique) {
            (Some(d), false) if (1..=3).contains(&d.abs()) => {}
            (None, true) if c.azimuth_deg.is_some() && c.elevation_deg.is_some() => {}
            _ => {
                return err(
                    &format!("channels[{i}]"),
                    ": expected direction = ±1, ±2 or ±3, or both azimuth_deg and elevation_deg"
                        .into(),
                );
            }
        }
        if !(c.scale.is_finite() && c.scale != 0.0) {
            return err(
                &format!("channels[{i}].scale"),
                format!(" = {}: expected a finite, non-zero factor", c.scale),
            );
        }
    }
    Ok(())
}

fn validate_building(b: &SimulatedBuilding) -> Check {
    let err = |key: &str, message: String| Err((format!("operational.simulate.{key}"), message));
    if b.masses.is_empty() || b.masses.len() > 50 {
        return err(
            "masses",
            format!(": {} floors: expected 1 to 50", b.masses.len()),
        );
    }
    if b.stiffnesses.len() != b.masses.len() {
        return err(
            "stiffnesses",
            format!(
                ": {} values: expected one per floor ({})",
                b.stiffnesses.len(),
                b.masses.len()
            ),
        );
    }
    for (key, values) in [("masses", &b.masses), ("stiffnesses", &b.stiffnesses)] {
        if let Some(v) = values.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
            return err(key, format!(": {v}: expected positive, finite values"));
        }
    }
    if !(b.damping_ratio > 0.0 && b.damping_ratio < 1.0) {
        return err(
            "damping_ratio",
            format!(" = {}: expected a ratio in (0, 1)", b.damping_ratio),
        );
    }
    if !(b.sample_rate_hz.is_finite() && b.sample_rate_hz > 0.0) {
        return err(
            "sample_rate_hz",
            format!(" = {}: expected a positive rate", b.sample_rate_hz),
        );
    }
    if b.samples < 1000 {
        return err(
            "samples",
            format!(" = {}: expected at least 1000 samples", b.samples),
        );
    }
    // Every floor's channel is held in memory.
    crate::budget::check(
        "operational.simulate.samples",
        b.samples as f64,
        b.masses.len() as f64,
        crate::budget::Budget::Held,
    )?;
    if !(0.0..=10.0).contains(&b.noise) {
        return err(
            "noise",
            format!(
                " = {}: expected a fraction of the rms from 0 to 10",
                b.noise
            ),
        );
    }
    Ok(())
}
