//! The data stage: synthetic records generated from the config's plant, or a measured
//! record read from a CSV file, preprocessed and cut into estimation and validation
//! parts.
//!
//! CSV files: one column each for the input and the output (by header name or 0-based
//! index), a time column or a sample rate, any delimiter, `#` comment lines, extra
//! columns ignored. Every bad cell is reported with the file, its line and the column.

use crate::config::{Columns, Config, DataSection, Kind, Preprocess, Range};
use crate::error::{ExperimentError, Result};
use crate::sources::Sources;
use msd_ident::{
    DataSet, Excitation, Parameters, SyntheticOptions, nonlinear::synthetic_nonlinear_data,
    synthetic_data,
};
use std::path::{Path, PathBuf};

mod clock;
pub(crate) mod csv;
pub mod text;
pub(crate) mod uff;
pub use csv::{ColumnSpec, LARGEST_VALUE, Table, read_columns, read_csv};

/// Both records of an experiment and what is known about them.
#[derive(Debug, Clone)]
pub struct ExperimentData {
    /// Synthetic or measured.
    pub kind: Kind,
    /// The estimation record.
    pub identification: DataSet,
    /// The validation record.
    pub validation: DataSet,
    /// Noise-free identification response (synthetic only).
    pub identification_truth: Option<Vec<f64>>,
    /// Noise-free validation response (synthetic only).
    pub validation_truth: Option<Vec<f64>>,
    /// The true plant (synthetic only).
    pub truth: Option<Parameters>,
    /// Leading validation samples that only settle the initial state (not scored).
    pub validation_initial_samples: usize,
    /// What the user should know about the records (e.g. a validation part that
    /// overlaps the estimation part). Empty when all is well.
    pub notes: Vec<String>,
    /// Where the data came from, for the report.
    pub source: Source,
}

impl ExperimentData {
    /// Records a Rust program already holds: `identification` to estimate on,
    /// `validation` to predict (it may be the same record). Nothing about the plant is
    /// known, so the run reports them as measured data; no file is read.
    ///
    /// ```
    /// use msd_experiment::data::ExperimentData;
    /// use msd_ident::DataSet;
    /// let t: Vec<f64> = (0..100).map(|i| i as f64 * 0.01).collect();
    /// let force = vec![1.0; 100];
    /// let x: Vec<f64> = t.iter().map(|t| 0.01 * (1.0 - (-t).exp())).collect();
    /// let set = DataSet::from_columns("bench", &t, force, x)?;
    /// let data = ExperimentData::in_memory(set.clone(), set);
    /// assert!(data.truth.is_none());
    /// # Ok::<(), msd_ident::IdentError>(())
    /// ```
    pub fn in_memory(identification: DataSet, validation: DataSet) -> Self {
        Self {
            kind: Kind::Measured,
            identification,
            validation,
            identification_truth: None,
            validation_truth: None,
            truth: None,
            validation_initial_samples: 0,
            notes: Vec::new(),
            source: Source::InMemory,
        }
    }
}

/// Where the data came from.
#[derive(Debug, Clone, PartialEq)]
pub enum Source {
    /// Given in memory by a Rust program ([`ExperimentData::in_memory`]).
    InMemory,
    /// Generated from the config's plant with the seed.
    Synthetic {
        /// Noise standard deviation.
        sigma: f64,
    },
    /// Read from a CSV file.
    Measured {
        /// The file, resolved against the config's folder.
        path: PathBuf,
        /// Data rows read.
        rows: usize,
        /// Sampling interval after preprocessing, s.
        dt: f64,
        /// Sample ranges `[start, end)` of the estimation and validation parts, in the
        /// preprocessed record.
        estimation_range: [usize; 2],
        /// See `estimation_range`.
        validation_range: [usize; 2],
    },
}

/// Generates or loads the records that `config` describes; `config_path` resolves a
/// data file's relative path and names the config in errors.
pub fn load(config: &Config, config_path: &Path, seed: u64) -> Result<ExperimentData> {
    match (&config.data, config.kind()) {
        (Some(d), Kind::Measured) => load_measured(d, &config.sources, config_path),
        _ => synthetic(config, config_path, seed),
    }
}

fn synthetic(config: &Config, config_path: &Path, seed: u64) -> Result<ExperimentData> {
    let missing =
        |what: &str| ExperimentError::config(config_path, format!("{what}: missing section"));
    let plant = config.plant.ok_or_else(|| match config.pilot {
        Some(_) => ExperimentError::config(
            config_path,
            "plant: missing section: this config takes its plant from its [pilot]; run it with `design`, then the designed.toml it writes",
        ),
        None => missing("plant"),
    })?;
    let time = config.time.ok_or_else(|| missing("time"))?;
    let noise = config.noise.ok_or_else(|| missing("noise"))?;
    let id_exc = identification_excitation(config, config_path)?;
    let val_input = config
        .validation
        .input
        .clone()
        .ok_or_else(|| missing("validation.input"))?;
    let n = time.samples();
    let bad = |field: &'static str| {
        move |e: msd_ident::IdentError| {
            ExperimentError::config(config_path, format!("{field}: {e}"))
        }
    };
    let val_exc = Excitation::from_signal(val_input, time.start, time.dt, n)
        .map_err(bad("validation.input"))?;
    let truth = plant.parameters();
    let record = |name: &'static str, excitation: Excitation| {
        plant_record(&plant, name, excitation, noise.sigma, seed)
            .map_err(|e| ExperimentError::run("data", e))
    };
    let (identification, id_truth) = record("identification", id_exc)?;
    let (validation, val_truth) = record("validation", val_exc)?;
    Ok(ExperimentData {
        kind: Kind::Synthetic,
        identification,
        validation,
        identification_truth: Some(id_truth),
        validation_truth: Some(val_truth),
        truth: Some(truth),
        validation_initial_samples: 0,
        notes: Vec::new(),
        source: Source::Synthetic { sigma: noise.sigma },
    })
}

/// The identification input of a synthetic config, sampled on its time grid.
pub(crate) fn identification_excitation(config: &Config, config_path: &Path) -> Result<Excitation> {
    let missing =
        |what: &str| ExperimentError::config(config_path, format!("{what}: missing section"));
    let time = config.time.ok_or_else(|| missing("time"))?;
    let input = config
        .identification
        .as_ref()
        .ok_or_else(|| missing("identification"))?
        .input
        .clone();
    Excitation::from_signal(input, time.start, time.dt, time.samples())
        .map_err(|e| ExperimentError::config(config_path, format!("identification.input: {e}")))
}

/// The synthetic drive: `[identification.input]` on the `[time]` grid (none for a free
/// decay or a test machine), as a lab records it: its samples alone, no breakpoints
/// between them, so that the synthetic run and its measured template (which reads these
/// samples back) describe the same experiment, the one the fit's model assumes.
pub(crate) fn synthetic_input(config: &Config, config_path: &Path) -> Result<Option<Excitation>> {
    let (Some(section), Some(time)) = (&config.identification, config.time) else {
        return Ok(None);
    };
    let signal = |e| ExperimentError::config(config_path, format!("identification.input: {e}"));
    let x = Excitation::from_signal(section.input.clone(), time.start, time.dt, time.samples())
        .map_err(signal)?;
    Excitation::from_samples(x.t0(), x.dt(), x.samples().to_vec())
        .map(Some)
        .map_err(signal)
}

/// One noisy record of the plant and its noise-free response: the exact simulation of a
/// linear plant, or ode45 on the continuous force (RelTol 1e-8, AbsTol 1e-12: msd-ident's
/// default tolerances) for a plant with nonlinear terms; the noise from the stream named
/// `name` of `seed`.
fn plant_record(
    plant: &crate::config::Plant,
    name: &str,
    excitation: Excitation,
    sigma: f64,
    seed: u64,
) -> msd_ident::Result<(DataSet, Vec<f64>)> {
    let options = SyntheticOptions {
        initial_state: plant.initial_state,
        sigma,
        seed,
        ..SyntheticOptions::named(name)
    };
    match plant.nonlinear() {
        None => synthetic_data(&plant.parameters(), excitation, &options),
        Some(nonlinear) => synthetic_nonlinear_data(
            &nonlinear,
            excitation,
            &msd_ident::nonlinear::NonlinearSimulation {
                solver: msd_ident::nonlinear::NonlinearSolver::Ode45,
                ..msd_ident::nonlinear::NonlinearSimulation::default()
            },
            &options,
        ),
    }
}

fn load_measured(d: &DataSection, sources: &Sources, config_path: &Path) -> Result<ExperimentData> {
    let path = sources.path(d.path.first());
    let record = read_csv(d, sources, &path)?;
    let rows = record.time.len();
    let (record, factor) = preprocess(record, &d.preprocessing, &path)?;
    let [input, output] = [&record.columns[INPUT], &record.columns[OUTPUT]];
    let n = input.len();
    let grid = (n, record.time[0], record.dt);
    let est = resolve_range(&d.estimation, grid, rows, factor, "data.estimation")
        .map_err(|m| ExperimentError::config(config_path, m))?;
    let val_spec = d.validation.unwrap_or(d.estimation);
    let val = resolve_range(&val_spec, grid, rows, factor, "data.validation")
        .map_err(|m| ExperimentError::config(config_path, m))?;
    if d.estimation.initial_samples != 0 {
        return Err(ExperimentError::config(
            config_path,
            format!(
                "data.estimation.initial_samples = {}: only for data.validation; set estimation.estimate_initial_state = true instead",
                d.estimation.initial_samples
            ),
        ));
    }
    let initial = val_spec.initial_samples;
    if initial + msd_ident::data::MIN_SAMPLES > val[1] - val[0] {
        return Err(ExperimentError::config(
            config_path,
            format!(
                "data.validation.initial_samples = {initial}: expected fewer than the {} samples of the validation range less {}",
                val[1] - val[0],
                msd_ident::data::MIN_SAMPLES
            ),
        ));
    }
    let make = |name: &str, [a, b]: [usize; 2]| -> Result<DataSet> {
        let excitation = Excitation::from_samples(record.time[a], record.dt, input[a..b].to_vec())
            .map_err(|e| ExperimentError::data(&path, e.to_string()))?;
        let mut set = DataSet::new(name, excitation, output[a..b].to_vec())
            .map_err(|e| ExperimentError::data(&path, format!("{name} range {a}..{b}: {e}")))?;
        set.input_unit = d.input_unit.clone();
        set.output_unit = d.output_unit.clone();
        Ok(set)
    };
    let identification = make("identification", est)?;
    let validation = make("validation", val)?;
    debug_assert!(val[1] <= n && est[1] <= n);
    Ok(ExperimentData {
        kind: Kind::Measured,
        identification,
        validation,
        identification_truth: None,
        validation_truth: None,
        truth: None,
        validation_initial_samples: initial,
        notes: record
            .notes
            .iter()
            .cloned()
            .chain(overlap_note(est, val))
            .collect(),
        source: Source::Measured {
            path,
            rows,
            dt: record.dt,
            estimation_range: est,
            validation_range: val,
        },
    })
}

/// A note when the validation samples `[a, b)` overlap the estimation samples: the
/// validation then scores data the model was fitted to, and says less than it seems.
pub(crate) fn overlap_note(est: [usize; 2], val: [usize; 2]) -> Option<String> {
    let shared = val[1].min(est[1]).saturating_sub(val[0].max(est[0]));
    (shared > 0).then(|| {
        format!(
            "the validation samples {}..{} share {shared} samples ({:.0} %) with the estimation samples {}..{}: the validation scores data the model was fitted to and says less than it seems; give data.validation a part of its own",
            val[0],
            val[1],
            100.0 * shared as f64 / (val[1] - val[0]) as f64,
            est[0],
            est[1]
        )
    })
}

/// The input's and the output's columns in [`read_csv`]'s table.
const INPUT: usize = 0;
const OUTPUT: usize = 1;

/// Applies the preprocessing steps in order; returns the table and the total
/// decimation factor.
fn preprocess(mut r: Table, steps: &[Preprocess], path: &Path) -> Result<(Table, usize)> {
    let mut factor = 1;
    let fail = |i: usize, e: msd_signal::SignalError| {
        ExperimentError::data(path, format!("data.preprocessing[{i}]: {e}"))
    };
    for (i, step) in steps.iter().enumerate() {
        let apply = |r: &mut Table,
                     columns: Columns,
                     f: &dyn Fn(&[f64]) -> msd_signal::Result<Vec<f64>>|
         -> Result<()> {
            if columns != Columns::Output {
                r.columns[INPUT] = f(&r.columns[INPUT]).map_err(|e| fail(i, e))?;
            }
            if columns != Columns::Input {
                r.columns[OUTPUT] = f(&r.columns[OUTPUT]).map_err(|e| fail(i, e))?;
            }
            Ok(())
        };
        match *step {
            Preprocess::RemoveMean { columns } => apply(&mut r, columns, &msd_signal::remove_mean)?,
            Preprocess::DetrendLinear { columns } => {
                apply(&mut r, columns, &msd_signal::detrend_linear)?
            }
            Preprocess::MovingAverage { window, columns } => {
                apply(&mut r, columns, &|x| msd_signal::moving_average(x, window))?
            }
            Preprocess::Decimate { factor: f } => {
                apply(&mut r, Columns::Both, &|x| msd_signal::decimate(x, f))?;
                r.time = r.time.iter().step_by(f).copied().collect();
                r.dt *= f as f64;
                factor *= f;
            }
        }
    }
    Ok((r, factor))
}

/// A [`Range`] as sample indices `[start, end)` of the preprocessed record.
/// The samples `[start, end)` of a record of `n` samples from `t0` every `dt` (after
/// decimation by `factor`, from `rows` rows in the file) that `range` names.
pub(crate) fn resolve_range(
    range: &Range,
    (n, t0, dt): (usize, f64, f64),
    rows: usize,
    factor: usize,
    field: &str,
) -> std::result::Result<[usize; 2], String> {
    let [a, b] = match (range.range, range.time) {
        (Some([a, b]), _) => {
            if b > rows {
                return Err(format!(
                    "{field}.range = [{a}, {b}]: outside the data: expected 0 <= start < end <= {rows} (data rows in the file)"
                ));
            }
            [a.div_ceil(factor), b.div_ceil(factor)]
        }
        (None, Some([ta, tb])) => {
            let t_end = t0 + (n as f64) * dt;
            if ta < t0 - 1e-9 * dt || tb > t_end + 1e-9 * dt {
                return Err(format!(
                    "{field}.time = [{ta}, {tb}]: outside the data: expected {t0} <= start < end <= {t_end} s"
                ));
            }
            let index = |t: f64| (((t - t0) / dt) - 1e-9).ceil().max(0.0) as usize;
            [index(ta), index(tb).min(n)]
        }
        (None, None) => [0, n],
    };
    if b.saturating_sub(a) < msd_ident::data::MIN_SAMPLES {
        return Err(format!(
            "{field}: [{a}, {b}) holds {} samples: expected at least {}",
            b.saturating_sub(a),
            msd_ident::data::MIN_SAMPLES
        ));
    }
    Ok([a, b])
}
