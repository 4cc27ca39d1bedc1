//! Time records: columns by header name or 0-based index, a time column or a sample
//! rate, from a text table (read by [`super::text`]: any delimiter and encoding, metadata
//! and units lines, decimal commas, missing values) or from a MATLAB, NumPy or TDMS file
//! (read by msd-files as named channels). Every bad cell is reported with the file, its
//! line and the column.

use super::clock::is_clock;
use super::text::{self, Header, TextFormat};
use crate::config::{Column, DataSection};
use crate::error::{ExperimentError, Result};
use crate::sources::Sources;
use std::path::Path;

/// One column to read: its role in messages (`input`, `output`, `acceleration`), the
/// config key that names it (`data.input`, `setup.responses[1].column`), the column and
/// the factor applied on reading with the key that sets it.
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnSpec {
    /// The role, in messages ("no acceleration column named …").
    pub role: String,
    /// The key that names the column.
    pub key: String,
    /// The column.
    pub column: Column,
    /// The factor applied on reading.
    pub scale: f64,
    /// The key that sets the factor.
    pub scale_key: String,
}

/// The columns of a CSV file as read: time and the requested columns, in order.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// Time stamps (from the time column, or i/fs), on a uniform grid.
    pub time: Vec<f64>,
    /// The columns, scaled, in the order asked.
    pub columns: Vec<Vec<f64>>,
    /// Sampling interval, s.
    pub dt: f64,
    /// What the reader did that a report should say (metadata lines skipped, units
    /// found, missing values dropped or interpolated, the encoding).
    pub notes: Vec<String>,
}

/// Reads the input, output and (optional) time columns of a CSV file: a [`Table`] whose
/// columns are the input then the output, scaled.
///
/// Errors name the file, the 1-based line and the column: a missing file, a missing
/// column, an empty or non-numeric cell, NaN or infinity, time that does not increase
/// or is not uniform (within 1 % of the mean step).
pub fn read_csv(d: &DataSection, sources: &Sources, path: &Path) -> Result<Table> {
    let spec = |role: &str, column: &Option<Column>, scale: f64| -> Result<ColumnSpec> {
        let column = column.clone().ok_or_else(|| {
            ExperimentError::data(
                path,
                format!("data.{role}: missing: expected the {role} column"),
            )
        })?;
        Ok(ColumnSpec {
            role: role.into(),
            key: format!("data.{role}"),
            column,
            scale,
            scale_key: format!("data.{role}_scale"),
        })
    };
    let specs = [
        spec("input", &d.input, d.input_scale)?,
        spec("output", &d.output, d.output_scale)?,
    ];
    read_columns(d, sources, path, "data.path", &specs)
}

/// Reads the time (`d.time` or `d.sample_rate`) and the `columns` of the CSV file `path`
/// with the format of `d` (delimiter, header, lines to skip), from `sources` (the disk,
/// or the file's bytes or columns given in memory); `path_key` names the file in
/// messages (`data.path`, `data.path[2]`).
pub fn read_columns(
    d: &DataSection,
    sources: &Sources,
    path: &Path,
    path_key: &str,
    columns: &[ColumnSpec],
) -> Result<Table> {
    if let Some(given) = sources.table(path, path_key)? {
        return from_columns(d, path, &given, columns);
    }
    let bytes = sources.bytes(path, path_key)?;
    let format = d.text_format();
    let mut time = Vec::new();
    let mut values: Vec<Vec<f64>> = vec![Vec::new(); columns.len()];
    let mut lines = Vec::new();
    let time_spec = d.time.clone().map(time_column);
    let indices = |header: Option<&Header>| -> Result<Vec<usize>> {
        let find = |role: &str, key: &str, c: &Column| column_index(path, header, role, key, c);
        columns
            .iter()
            .chain(time_spec.as_ref())
            .map(|c| find(&c.role, &c.key, &c.column))
            .collect()
    };
    // The first time cell when the time column holds clock times.
    let mut clock = None;
    let mut notes = text::scan(path, &bytes, &format, indices, |indices, line, r| {
        for (slot, (spec, &index)) in columns
            .iter()
            .chain(time_spec.as_ref())
            .zip(indices)
            .enumerate()
        {
            let (value, scaled) = cell_value(path, line, r, spec, index, &format)?;
            match values.get_mut(slot) {
                Some(column) => column.push(scaled),
                None => {
                    let cell = r.get(index).unwrap_or_default();
                    if time.is_empty() && is_clock(cell, format.decimal) {
                        clock = Some(cell.trim().to_string());
                    }
                    time.push(value);
                }
            }
        }
        lines.push(line);
        Ok(())
    })?;
    let mut all: Vec<&mut Vec<f64>> = values.iter_mut().collect();
    if time_spec.is_some() {
        all.push(&mut time);
    }
    notes.extend(text::fill_missing(
        path,
        &mut all,
        &mut lines,
        format.missing,
    )?);
    if let Some(Column::Name(name)) = &d.time {
        time_in_seconds(path, name, &time)?;
    }
    if let Some(first) = clock {
        let t0 = time.first().copied().unwrap_or_default();
        time.iter_mut().for_each(|t| *t -= t0);
        notes.push(format!(
            "the time column holds clock times: read as seconds from its first, {first} (0 s)"
        ));
    }
    if let Some(k) = time.windows(2).position(|w| w[1] <= w[0]) {
        return Err(ExperimentError::data(
            path,
            format!(
                "line {}, time column: {} s is not after the previous {} s: expected increasing time",
                lines[k + 1],
                time[k + 1],
                time[k]
            ),
        ));
    }
    let rows = values.first().map_or(time.len(), Vec::len);
    check_rows(path, rows)?;
    let (time, dt) = time_grid(path, d.sample_rate, time, rows, &mut values, &mut notes)?;
    Ok(Table {
        time,
        columns: values,
        dt,
        notes,
    })
}

/// The time column read as the others are, unscaled.
fn time_column(column: Column) -> ColumnSpec {
    ColumnSpec {
        role: "time".into(),
        key: "data.time".into(),
        column,
        scale: 1.0,
        scale_key: String::new(),
    }
}

/// At least msd-ident's minimum of samples.
fn check_rows(path: &Path, rows: usize) -> Result<()> {
    if rows < msd_ident::data::MIN_SAMPLES {
        return Err(ExperimentError::data(
            path,
            format!(
                "{} data rows: expected at least {}",
                rows,
                msd_ident::data::MIN_SAMPLES
            ),
        ));
    }
    Ok(())
}

/// The table of named columns (given in memory, or a MATLAB, NumPy or TDMS file's) for `path`: each spec's column scaled, the
/// time from `d.time` (increasing) or `d.sample_rate`, with the checks of a file.
fn from_columns(
    d: &DataSection,
    path: &Path,
    given: &[(String, Vec<f64>)],
    specs: &[ColumnSpec],
) -> Result<Table> {
    let rows = specs
        .first()
        .map(|s| pick(path, given, &s.column, &s.key).map(<[f64]>::len))
        .transpose()?
        .unwrap_or(0);
    let values = specs
        .iter()
        .map(|s| {
            let column = pick(path, given, &s.column, &s.key)?;
            let scaled: Vec<f64> = column.iter().map(|v| v * s.scale).collect();
            match scaled.iter().position(|v| !v.is_finite()) {
                Some(i) => Err(ExperimentError::data(
                    path,
                    format!(
                        "{} = {}, row {i}: {} × the scale {} ({}) overflows: expected a finite value",
                        s.key, s.column, column[i], s.scale, s.scale_key
                    ),
                )),
                None => Ok(scaled),
            }
        })
        .collect::<Result<Vec<_>>>()?;
    check_rows(path, rows)?;
    let time = match &d.time {
        Some(c) => pick(path, given, c, "data.time")?.to_vec(),
        None => Vec::new(),
    };
    if let Some(Column::Name(name)) = &d.time {
        time_in_seconds(path, name, &time)?;
    }
    if let Some(i) = time.windows(2).position(|w| w[1] <= w[0]) {
        return Err(ExperimentError::data(
            path,
            format!(
                "data.time, row {}: {} s is not after the previous {} s: expected increasing time",
                i + 1,
                time[i + 1],
                time[i]
            ),
        ));
    }
    if time.is_empty() && d.sample_rate.is_none() {
        return Err(ExperimentError::data(
            path,
            "data.time or data.sample_rate: missing: expected one of them",
        ));
    }
    if let Some((s, v)) = specs.iter().zip(&values).find(|(_, v)| v.len() != rows) {
        return Err(ExperimentError::data(
            path,
            format!(
                "{} = {}: {} values where {} = {} has {rows}: expected columns of one length",
                s.key,
                s.column,
                v.len(),
                specs[0].key,
                specs[0].column
            ),
        ));
    }
    if !time.is_empty() && time.len() != rows {
        return Err(ExperimentError::data(
            path,
            format!(
                "data.time: {} values where {} = {} has {rows}: expected columns of one length",
                time.len(),
                specs[0].key,
                specs[0].column
            ),
        ));
    }
    let mut values = values;
    let mut notes = Vec::new();
    let (time, dt) = time_grid(path, d.sample_rate, time, rows, &mut values, &mut notes)?;
    Ok(Table {
        time,
        columns: values,
        dt,
        notes,
    })
}

/// The 0-based index of column `c` (an index, or a name looked up in the header).
pub(crate) fn column_index(
    path: &Path,
    header: Option<&Header>,
    role: &str,
    key: &str,
    c: &Column,
) -> Result<usize> {
    match (c, header) {
        (Column::Index(i), _) => Ok(*i),
        (Column::Name(name), Some(Header { names, line })) => {
            let mut found = (names.iter().enumerate()).filter(|(_, h)| *h == name);
            if let (Some((first, _)), Some((second, _))) = (found.next(), found.next()) {
                return Err(ExperimentError::data(
                    path,
                    format!(
                        "line {line}: two columns are named `{name}` ({key}), #{first} and #{second} (from 0): expected one; rename one, or give the column by its number"
                    ),
                ));
            }
            names.iter().position(|h| h == name).ok_or_else(|| {
                let found: Vec<String> = names
                    .iter()
                    .filter(|h| !h.is_empty())
                    .map(|h| format!("`{h}`"))
                    .collect();
                let hint = match names.as_slice() {
                    [one] => [';', '\t', ',', ' ']
                        .into_iter()
                        .find(|c| one.contains(*c))
                        .map_or(String::new(), |c| {
                            format!(
                                ": the header reads as one field — is the delimiter {:?}? (set delimiter = {:?})",
                                c, c
                            )
                        }),
                    _ => String::new(),
                };
                let role = if role.is_empty() { String::new() } else { format!("{role} ") };
                ExperimentError::data(
                    path,
                    format!(
                        "line {line}: no {role}column named `{name}` ({key}): the header has {}{hint}",
                        found.join(", ")
                    ),
                )
            })
        }
        (Column::Name(name), None) => Err(ExperimentError::data(
            path,
            format!(
                "{key} = \"{name}\": the file has no header (header = false): use a 0-based column index"
            ),
        )),
    }
}

/// The value of one cell (`spec`'s column, at `index` of row `r` on `line`) as read and
/// scaled, refused when it is not a number, overflows or is too large to square.
fn cell_value(
    path: &Path,
    line: usize,
    r: &csv::StringRecord,
    spec: &ColumnSpec,
    index: usize,
    format: &TextFormat,
) -> Result<(f64, f64)> {
    let (role, column, scale) = (&spec.role, &spec.column, spec.scale);
    let cell = r.get(index).ok_or_else(|| {
        ExperimentError::data(
            path,
            format!(
                "line {line}: the row has {} fields, no {role} column {column} (index {index})",
                r.len()
            ),
        )
    })?;
    let value = text::parse_cell(cell, format.decimal, format.missing).map_err(|why| {
        ExperimentError::data(path, format!("line {line}, {role} column {column}: {why}"))
    })?;
    if value.is_nan() {
        return Ok((value, value)); // missing, filled or dropped by the missing policy
    }
    let scaled = value * scale;
    if !scaled.is_finite() {
        return Err(ExperimentError::data(
            path,
            format!(
                "line {line}, {role} column {column}: {value} × the scale {scale} ({}) overflows: expected a finite value",
                spec.scale_key
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
    Ok((value, scaled))
}

/// The record's uniform grid: `sample_rate`'s, or the time column's. Stamps within 1 %
/// of a uniform step (printed with few digits) are put on it; stamps that wander
/// further (a phone's or a logger's clock: phyphox, an Arduino) are resampled onto
/// their median step by linear interpolation, every column alike, and a note says so;
/// a gap (a step over three times the median) is refused.
fn time_grid(
    path: &Path,
    sample_rate: Option<f64>,
    time: Vec<f64>,
    rows: usize,
    values: &mut [Vec<f64>],
    notes: &mut Vec<String>,
) -> Result<(Vec<f64>, f64)> {
    if let Some(fs) = sample_rate {
        let dt = 1.0 / fs;
        return Ok(((0..rows).map(|i| i as f64 * dt).collect(), dt));
    }
    let n = time.len();
    let dt = (time[n - 1] - time[0]) / (n - 1) as f64;
    let t0 = time[0];
    let steps: Vec<f64> = time.windows(2).map(|w| w[1] - w[0]).collect();
    if steps.iter().all(|s| (s - dt).abs() <= 0.01 * dt) {
        // Regularise small jitter (e.g. printed with few digits) onto the uniform grid.
        return Ok(((0..n).map(|i| t0 + i as f64 * dt).collect(), dt));
    }
    let mut sorted = steps.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    if let Some(i) = steps.iter().position(|&s| s > 3.0 * median) {
        return Err(ExperimentError::data(
            path,
            format!(
                "data row {} (0-based), time column: a gap of {} s where the median step is {} s: expected no step over three times the median (a record with samples lost; cut it with data.estimation, or give the parts as separate records)",
                i + 1,
                steps[i],
                median
            ),
        ));
    }
    let mut grid = Vec::new();
    for column in values.iter_mut() {
        let (t, x) = msd_signal::resample_uniform(&time, column, median)
            .map_err(|e| ExperimentError::data(path, format!("time column: {e}")))?;
        *column = x;
        grid = t;
    }
    notes.push(format!(
        "the time column's steps vary ({}–{} s, median {} s, as a sensor's own clock stamps them): the {n} samples were resampled by linear interpolation onto a uniform grid of the median step ({} samples)",
        crate::fmt::sig(sorted[0], 3),
        crate::fmt::sig(sorted[sorted.len() - 1], 3),
        crate::fmt::sig(median, 4),
        grid.len()
    ));
    Ok((grid, median))
}

/// The largest magnitude a data value may have: the sums of squares that every fit and
/// test computes stay finite (1e100² · 1e8 samples = 1e208 < f64::MAX ≈ 1.8e308). No
/// measurement in any unit comes near it; a value beyond it is a corrupt cell or a wrong
/// scale, refused where it is read rather than misdiagnosed later.
pub const LARGEST_VALUE: f64 = 1e100;

/// The column `column` (config key `key`) of the in-memory table `columns` of `path`.
pub(crate) fn pick<'a>(
    path: &Path,
    columns: &'a [(String, Vec<f64>)],
    column: &Column,
    key: &str,
) -> Result<&'a [f64]> {
    let found = match column {
        Column::Name(name) => {
            if columns.iter().filter(|(n, _)| n == name).count() > 1 {
                return Err(ExperimentError::data(
                    path,
                    format!(
                        "{key} = {column}: two channels have that name: expected one; give the column by its number"
                    ),
                ));
            }
            columns.iter().find(|(n, _)| n == name)
        }
        Column::Index(i) => columns.get(*i),
    };
    let names: Vec<String> = columns.iter().map(|(n, _)| format!("`{n}`")).collect();
    let (_, values) = found.ok_or_else(|| {
        ExperimentError::data(
            path,
            format!(
                "{key} = {column}: no such column among the {} the file holds ({})",
                columns.len(),
                names.join(", ")
            ),
        )
    })?;
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(ExperimentError::data(
            path,
            format!(
                "{key} = {column}, row {i} (0-based): {}: expected a finite number",
                values[i]
            ),
        ));
    }
    Ok(values)
}

/// Refuses a time column whose name says it is not in seconds (`Time [ms]`): `data.time`
/// is read in seconds, and read so every frequency would be off by the unit's factor.
fn time_in_seconds(path: &Path, name: &str, time: &[f64]) -> Result<()> {
    let Some(unit) = text::unit_in_name(name) else {
        return Ok(());
    };
    let Some(seconds) = text::seconds_per(unit).filter(|&s| s != 1.0) else {
        return Ok(());
    };
    let rate = match time {
        [first, .., last] => {
            let step = (last - first) / (time.len() - 1) as f64;
            text::rate_of_step(step, seconds).to_string()
        }
        _ => "…".into(),
    };
    Err(ExperimentError::data(
        path,
        format!(
            "data.time = {name:?}: its name says the time is in {unit}, and data.time is read in seconds: give sample_rate = {rate} (Hz, from its step) instead of time"
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A time column named in ms is refused with the rate its step gives; in seconds,
    /// or with no unit, it is the time.
    #[test]
    fn a_time_column_in_milliseconds_is_refused_with_its_rate() {
        let path = Path::new("run.csv");
        let ms: Vec<f64> = (0..100).map(|i| 0.5 * i as f64).collect();
        let err = time_in_seconds(path, "Time [ms]", &ms)
            .unwrap_err()
            .to_string();
        assert!(err.contains("data.time = \"Time [ms]\""), "{err}");
        assert!(err.contains("give sample_rate = 2000 (Hz"), "{err}");
        assert!(time_in_seconds(path, "time (s)", &ms).is_ok());
        assert!(time_in_seconds(path, "t", &ms).is_ok());
        assert!(time_in_seconds(path, "Time [us]", &ms).is_err());
    }

    /// Stamps of a sensor's own clock (steps 10 ms ± 15 %) are resampled onto their
    /// median step, every column alike: a slow sine comes back on the grid within the
    /// linear interpolation's error (ω·Δt)²/8; a gap is refused; stamps within 1 % are
    /// put on their uniform grid untouched.
    #[test]
    fn wandering_time_stamps_are_resampled_and_a_gap_refused() {
        let path = Path::new("phone.csv");
        let time: Vec<f64> = (0..500)
            .scan(0.0, |t, i| {
                let now = *t;
                *t += 0.01 * (1.0 + 0.15 * ((i * 7919 % 13) as f64 / 6.0 - 1.0));
                Some(now)
            })
            .collect();
        let w = std::f64::consts::TAU * 2.0;
        let mut values = vec![time.iter().map(|t| (w * t).sin()).collect::<Vec<f64>>()];
        let mut notes = Vec::new();
        let (grid, dt) = time_grid(path, None, time.clone(), 500, &mut values, &mut notes).unwrap();
        assert!((dt / 0.01 - 1.0).abs() < 0.15, "dt = {dt}");
        assert_eq!(values[0].len(), grid.len());
        let bound = (w * 0.0115).powi(2) / 8.0;
        for (t, x) in grid.iter().zip(&values[0]) {
            assert!((x - (w * t).sin()).abs() <= bound, "t = {t}: {x}");
        }
        assert!(
            notes[0].contains("resampled by linear interpolation"),
            "{notes:?}"
        );
        let mut gap = time.clone();
        for t in &mut gap[300..] {
            *t += 0.05;
        }
        let err = time_grid(path, None, gap, 500, &mut values.clone(), &mut Vec::new());
        assert!(err.unwrap_err().to_string().contains("a gap of"));
        let printed: Vec<f64> = (0..500)
            .map(|i| (i as f64 * 0.01 * 1e4).round() / 1e4)
            .collect();
        let (grid, _) = time_grid(path, None, printed, 500, &mut values, &mut Vec::new()).unwrap();
        assert_eq!(grid.len(), 500);
    }
}
