//! The data stage: synthetic records generated from the config's plant, or a measured
//! record read from a CSV file, preprocessed and cut into estimation and validation
//! parts.
//!
//! CSV files: one column each for the input and the output (by header name or 0-based
//! index), a time column or a sample rate, any delimiter, `#` comment lines, extra
//! columns ignored. Every bad cell is reported with the file, its line and the column.

use crate::config::{Column, Columns, Config, DataSection, Kind, Preprocess, Range};
use crate::{ExperimentError, Result};
use msd_ident::{
    DataSet, Excitation, Parameters, SyntheticOptions, synthetic_data, synthetic_nonlinear_data,
};
use std::path::{Path, PathBuf};

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
        (Some(d), Kind::Measured) => load_measured(d, config_path),
        _ => synthetic(config, config_path, seed),
    }
}

fn synthetic(config: &Config, config_path: &Path, seed: u64) -> Result<ExperimentData> {
    let missing =
        |what: &str| ExperimentError::config(config_path, format!("{what}: missing section"));
    let plant = config.plant.ok_or_else(|| missing("plant"))?;
    let time = config.time.ok_or_else(|| missing("time"))?;
    let noise = config.noise.ok_or_else(|| missing("noise"))?;
    let id_input = config
        .identification
        .as_ref()
        .ok_or_else(|| missing("identification"))?
        .input
        .clone();
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
    let id_exc = Excitation::from_signal(id_input, time.start, time.dt, n)
        .map_err(bad("identification.input"))?;
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
            &msd_ident::NonlinearSimulation {
                solver: msd_ident::NonlinearSolver::Ode45,
                ..msd_ident::NonlinearSimulation::default()
            },
            &options,
        ),
    }
}

/// The columns of a CSV file as read.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// Time stamps (from the time column, or i/fs).
    pub time: Vec<f64>,
    /// The input column (scaled).
    pub input: Vec<f64>,
    /// The output column (scaled).
    pub output: Vec<f64>,
    /// Sampling interval, s.
    pub dt: f64,
}

fn load_measured(d: &DataSection, config_path: &Path) -> Result<ExperimentData> {
    let base = config_path.parent().unwrap_or(Path::new(""));
    let path = base.join(&d.path);
    let record = read_csv(d, &path)?;
    let rows = record.input.len();
    let (record, factor) = preprocess(record, &d.preprocessing, &path)?;
    let n = record.input.len();
    let est = resolve_range(&d.estimation, &record, rows, factor, "data.estimation")
        .map_err(|m| ExperimentError::config(config_path, m))?;
    let val_spec = d.validation.unwrap_or(d.estimation);
    let val = resolve_range(&val_spec, &record, rows, factor, "data.validation")
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
    if initial + msd_ident::MIN_SAMPLES > val[1] - val[0] {
        return Err(ExperimentError::config(
            config_path,
            format!(
                "data.validation.initial_samples = {initial}: expected fewer than the {} samples of the validation range less {}",
                val[1] - val[0],
                msd_ident::MIN_SAMPLES
            ),
        ));
    }
    let make = |name: &str, [a, b]: [usize; 2]| -> Result<DataSet> {
        let excitation =
            Excitation::from_samples(record.time[a], record.dt, record.input[a..b].to_vec())
                .map_err(|e| ExperimentError::data(&path, e.to_string()))?;
        let mut set = DataSet::new(name, excitation, record.output[a..b].to_vec())
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
        notes: overlap_note(est, val).into_iter().collect(),
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
fn overlap_note(est: [usize; 2], val: [usize; 2]) -> Option<String> {
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

/// Reads the input, output and (optional) time columns of a CSV file.
///
/// Errors name the file, the 1-based line and the column: a missing file, a missing
/// column, an empty or non-numeric cell, NaN or infinity, time that does not increase
/// or is not uniform (within 1 % of the mean step).
pub fn read_csv(d: &DataSection, path: &Path) -> Result<Record> {
    let file = std::fs::File::open(path).map_err(|e| {
        ExperimentError::data(
            path,
            match crate::fetch::command_for(path) {
                Some(command) => format!(
                    "cannot open the data file (data.path = {:?}): {e}; fetch it with {command}",
                    d.path
                ),
                None => format!("cannot open the data file (data.path = {:?}): {e}", d.path),
            },
        )
    })?;
    let mut bytes = Vec::new();
    std::io::Read::read_to_end(&mut std::io::BufReader::new(file), &mut bytes)
        .map_err(|e| ExperimentError::data(path, format!("cannot read: {e}")))?;
    // Line numbers come from byte offsets (the csv crate's own count is off by one
    // with CRLF line endings): line of byte b = 1 + number of '\n' before b.
    let newlines: Vec<usize> = bytes
        .iter()
        .enumerate()
        .filter_map(|(i, &b)| (b == b'\n').then_some(i))
        .collect();
    let start = if d.skip_lines == 0 {
        0
    } else {
        newlines
            .get(d.skip_lines - 1)
            .map_or(bytes.len(), |&i| i + 1)
    };
    if !d.delimiter.is_ascii() {
        return Err(ExperimentError::data(
            path,
            format!(
                "delimiter {:?}: expected a single ASCII character",
                d.delimiter
            ),
        ));
    }
    let mut csv = csv::ReaderBuilder::new()
        .delimiter(d.delimiter as u8)
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(&bytes[start..]);
    let line_of = |pos: Option<&csv::Position>| {
        pos.map_or(0, |p| {
            let byte = start + p.byte() as usize;
            // With CRLF the csv crate puts a record's start on the previous line's
            // '\n' (after its '\r'), hence ≤: that newline ends the previous line.
            1 + newlines.partition_point(|&i| i <= byte)
        })
    };
    let mut records = csv.records();
    let header: Option<(Vec<String>, usize)> = if d.header {
        match records.next() {
            Some(Ok(r)) => Some((
                r.iter().map(str::to_string).collect(),
                line_of(r.position()),
            )),
            Some(Err(e)) => return Err(ExperimentError::data(path, csv_error(&e, &line_of))),
            None => {
                return Err(ExperimentError::data(
                    path,
                    "the file is empty: expected a header line and data rows",
                ));
            }
        }
    } else {
        None
    };
    let find = |role: &str, c: &Column| -> Result<usize> {
        match (c, &header) {
            (Column::Index(i), _) => Ok(*i),
            (Column::Name(name), Some((names, line))) => names
                .iter()
                .position(|h| h == name)
                .ok_or_else(|| {
                    let found: Vec<String> = names
                        .iter()
                        .filter(|h| !h.is_empty())
                        .map(|h| format!("`{h}`"))
                        .collect();
                    ExperimentError::data(
                        path,
                        format!(
                            "line {line}: no {role} column named `{name}` (data.{role}): the header has {}",
                            found.join(", ")
                        ),
                    )
                }),
            (Column::Name(name), None) => Err(ExperimentError::data(
                path,
                format!("data.{role} = \"{name}\": the file has no header (data.header = false): use a 0-based column index"),
            )),
        }
    };
    let input_col = find("input", &d.input)?;
    let output_col = find("output", &d.output)?;
    let time_col = d.time.as_ref().map(|c| find("time", c)).transpose()?;
    let columns: Vec<(&str, usize, Column)> = [
        Some(("input", input_col, d.input.clone())),
        Some(("output", output_col, d.output.clone())),
        time_col.zip(d.time.clone()).map(|(i, c)| ("time", i, c)),
    ]
    .into_iter()
    .flatten()
    .collect();

    let (mut time, mut input, mut output) = (Vec::new(), Vec::new(), Vec::new());
    // More fields than the header (or the first data row) has: a decimal comma or a
    // wrong delimiter would shift the columns, so the row is refused.
    let mut fields = header.as_ref().map(|(names, _)| names.len());
    for r in records {
        let r = r.map_err(|e| ExperimentError::data(path, csv_error(&e, &line_of)))?;
        let line = line_of(r.position());
        if r.iter().all(str::is_empty) {
            continue; // a blank line
        }
        let expected = *fields.get_or_insert(r.len());
        if r.len() > expected {
            return Err(ExperimentError::data(
                path,
                format!(
                    "line {line}: the row has {} fields, expected {expected} as the {}: a decimal comma, or the wrong delimiter (data.delimiter = {:?})?",
                    r.len(),
                    if header.is_some() {
                        "header"
                    } else {
                        "first row"
                    },
                    d.delimiter
                ),
            ));
        }
        for (role, index, column) in &columns {
            let cell = r.get(*index).ok_or_else(|| {
                ExperimentError::data(
                    path,
                    format!(
                        "line {line}: the row has {} fields, no {role} column {column} (index {index})",
                        r.len()
                    ),
                )
            })?;
            let value = parse_cell(cell).map_err(|why| {
                ExperimentError::data(path, format!("line {line}, {role} column {column}: {why}"))
            })?;
            let scale = match *role {
                "input" => d.input_scale,
                "output" => d.output_scale,
                _ => 1.0,
            };
            let scaled = value * scale;
            if !scaled.is_finite() {
                return Err(ExperimentError::data(
                    path,
                    format!(
                        "line {line}, {role} column {column}: {value} × the scale {scale} (data.{role}_scale) overflows: expected a finite value"
                    ),
                ));
            }
            if scaled.abs() > LARGEST_VALUE {
                return Err(ExperimentError::data(
                    path,
                    format!(
                        "line {line}, {role} column {column}: {scaled:e} is too large to compute with (sums of its square overflow): expected |value| <= {LARGEST_VALUE:e}; check the column and its scale"
                    ),
                ));
            }
            match *role {
                "input" => input.push(scaled),
                "output" => output.push(scaled),
                _ => time.push(value),
            }
        }
        if let (Some(_), [.., a, b]) = (time_col, time.as_slice())
            && b <= a
        {
            return Err(ExperimentError::data(
                path,
                format!(
                    "line {line}, time column: {b} s is not after the previous {a} s: expected increasing time"
                ),
            ));
        }
    }
    if input.len() < msd_ident::MIN_SAMPLES {
        return Err(ExperimentError::data(
            path,
            format!(
                "{} data rows: expected at least {}",
                input.len(),
                msd_ident::MIN_SAMPLES
            ),
        ));
    }
    let dt = match d.sample_rate {
        Some(fs) => {
            let dt = 1.0 / fs;
            time = (0..input.len()).map(|i| i as f64 * dt).collect();
            dt
        }
        None => {
            let n = time.len();
            let dt = (time[n - 1] - time[0]) / (n - 1) as f64;
            if let Some(i) = time
                .windows(2)
                .position(|w| ((w[1] - w[0]) - dt).abs() > 0.01 * dt)
            {
                return Err(ExperimentError::data(
                    path,
                    format!(
                        "data row {} (0-based), time column: step {} s: expected a uniform step of {dt} s (within 1 %)",
                        i + 1,
                        time[i + 1] - time[i]
                    ),
                ));
            }
            // Regularise small jitter (e.g. printed with few digits) onto the uniform grid.
            let t0 = time[0];
            time = (0..n).map(|i| t0 + i as f64 * dt).collect();
            dt
        }
    };
    Ok(Record {
        time,
        input,
        output,
        dt,
    })
}

fn csv_error(e: &csv::Error, line_of: &dyn Fn(Option<&csv::Position>) -> usize) -> String {
    match e.position() {
        Some(p) => format!("line {}: malformed CSV: {e}", line_of(Some(p))),
        None => format!("malformed CSV: {e}"),
    }
}

/// The largest magnitude a data value may have: the sums of squares that every fit and
/// test computes stay finite (1e100² · 1e8 samples = 1e208 < f64::MAX ≈ 1.8e308). No
/// measurement in any unit comes near it; a value beyond it is a corrupt cell or a wrong
/// scale, refused where it is read rather than misdiagnosed later.
pub const LARGEST_VALUE: f64 = 1e100;

fn parse_cell(cell: &str) -> std::result::Result<f64, String> {
    let cell = cell.trim().trim_matches('"');
    if cell.is_empty() {
        return Err("empty cell: expected a number".into());
    }
    match cell.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(v) => Err(format!("{v}: expected a finite number")),
        Err(_) => Err(format!("`{cell}` is not a number")),
    }
}

/// Applies the preprocessing steps in order; returns the record and the total
/// decimation factor.
fn preprocess(mut r: Record, steps: &[Preprocess], path: &Path) -> Result<(Record, usize)> {
    let mut factor = 1;
    let fail = |i: usize, e: msd_signal::SignalError| {
        ExperimentError::data(path, format!("data.preprocessing[{i}]: {e}"))
    };
    for (i, step) in steps.iter().enumerate() {
        let apply = |r: &mut Record,
                     columns: Columns,
                     f: &dyn Fn(&[f64]) -> msd_signal::Result<Vec<f64>>|
         -> Result<()> {
            if columns != Columns::Output {
                r.input = f(&r.input).map_err(|e| fail(i, e))?;
            }
            if columns != Columns::Input {
                r.output = f(&r.output).map_err(|e| fail(i, e))?;
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
fn resolve_range(
    range: &Range,
    r: &Record,
    rows: usize,
    factor: usize,
    field: &str,
) -> std::result::Result<[usize; 2], String> {
    let n = r.input.len();
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
            let t0 = r.time[0];
            let t_end = t0 + (n as f64) * r.dt;
            if ta < t0 - 1e-9 * r.dt || tb > t_end + 1e-9 * r.dt {
                return Err(format!(
                    "{field}.time = [{ta}, {tb}]: outside the data: expected {t0} <= start < end <= {t_end} s"
                ));
            }
            let index = |t: f64| (((t - t0) / r.dt) - 1e-9).ceil().max(0.0) as usize;
            [index(ta), index(tb).min(n)]
        }
        (None, None) => [0, n],
    };
    if b.saturating_sub(a) < msd_ident::MIN_SAMPLES {
        return Err(format!(
            "{field}: [{a}, {b}) holds {} samples: expected at least {}",
            b.saturating_sub(a),
            msd_ident::MIN_SAMPLES
        ));
    }
    Ok([a, b])
}
