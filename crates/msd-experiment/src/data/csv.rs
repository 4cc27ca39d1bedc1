//! CSV files: columns by header name or 0-based index, a time column or a sample rate,
//! any delimiter, `#` comment lines, extra columns ignored. Every bad cell is reported
//! with the file, its line and the column.

use super::Record;
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
}

/// Reads the input, output and (optional) time columns of a CSV file.
///
/// Errors name the file, the 1-based line and the column: a missing file, a missing
/// column, an empty or non-numeric cell, NaN or infinity, time that does not increase
/// or is not uniform (within 1 % of the mean step).
pub fn read_csv(d: &DataSection, sources: &Sources, path: &Path) -> Result<Record> {
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
    let mut table = read_columns(d, sources, path, "data.path", &specs)?;
    let output = table.columns.pop().unwrap_or_default();
    let input = table.columns.pop().unwrap_or_default();
    Ok(Record {
        time: table.time,
        input,
        output,
        dt: table.dt,
    })
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
    if let Some(given) = sources.columns(path) {
        return from_columns(d, path, given, columns);
    }
    let bytes = sources.bytes(path, path_key)?;
    let (newlines, start) = line_starts(&bytes, d.skip_lines);
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
            let line = 1 + newlines.partition_point(|&i| i <= byte);
            // The crate also puts it before the comment and blank lines it skipped:
            // the record is on the first line after them.
            first_data_line(&bytes, &newlines, line)
        })
    };
    let mut records = csv.records();
    let header = if d.header {
        Some(read_header(path, records.next(), &line_of)?)
    } else {
        None
    };
    let find = |role: &str, key: &str, c: &Column| column_index(path, &header, role, key, c);
    let indices = columns
        .iter()
        .map(|c| find(&c.role, &c.key, &c.column))
        .collect::<Result<Vec<usize>>>()?;
    let time_col = d
        .time
        .as_ref()
        .map(|c| find("time", "data.time", c))
        .transpose()?;
    let time_spec = time_col
        .zip(d.time.clone())
        .map(|(i, column)| (time_column(column), i));
    let cells: Vec<(&ColumnSpec, usize)> = columns
        .iter()
        .zip(indices)
        .chain(time_spec.as_ref().map(|(s, i)| (s, *i)))
        .collect();

    let mut time = Vec::new();
    let mut values: Vec<Vec<f64>> = vec![Vec::new(); columns.len()];
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
        check_width(path, line, r.len(), expected, header.is_some(), d.delimiter)?;
        for (slot, &(spec, index)) in cells.iter().enumerate() {
            let (value, scaled) = cell_value(path, line, &r, spec, index, d.decimal)?;
            match values.get_mut(slot) {
                Some(column) => column.push(scaled),
                None => time.push(value),
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
    let rows = values.first().map_or(time.len(), Vec::len);
    check_rows(path, rows)?;
    let (time, dt) = time_grid(path, d.sample_rate, time, rows)?;
    Ok(Table {
        time,
        columns: values,
        dt,
    })
}

/// The byte offset of every '\n' of `bytes`, and where the data start after `skip_lines`
/// lines. Line numbers come from these offsets (the csv crate's own count is off by one
/// with CRLF line endings): line of byte b = 1 + number of '\n' before b.
fn line_starts(bytes: &[u8], skip_lines: usize) -> (Vec<usize>, usize) {
    let newlines: Vec<usize> = bytes
        .iter()
        .enumerate()
        .filter_map(|(i, &b)| (b == b'\n').then_some(i))
        .collect();
    let start = if skip_lines == 0 {
        0
    } else {
        newlines.get(skip_lines - 1).map_or(bytes.len(), |&i| i + 1)
    };
    (newlines, start)
}

/// The header's names and its line, from the file's first record.
fn read_header(
    path: &Path,
    first: Option<std::result::Result<csv::StringRecord, csv::Error>>,
    line_of: &impl Fn(Option<&csv::Position>) -> usize,
) -> Result<(Vec<String>, usize)> {
    match first {
        Some(Ok(r)) => Ok((
            r.iter().map(str::to_string).collect(),
            line_of(r.position()),
        )),
        Some(Err(e)) => Err(ExperimentError::data(path, csv_error(&e, line_of))),
        None => Err(ExperimentError::data(
            path,
            "the file is empty: expected a header line and data rows",
        )),
    }
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

/// The table of the columns given in memory for `path`: each spec's column scaled, the
/// time from `d.time` (increasing) or `d.sample_rate`, with the checks of a file.
fn from_columns(
    d: &DataSection,
    path: &Path,
    given: &[(String, Vec<f64>)],
    specs: &[ColumnSpec],
) -> Result<Table> {
    let rows = given.first().map_or(0, |(_, v)| v.len());
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
    let (time, dt) = time_grid(path, d.sample_rate, time, rows)?;
    Ok(Table {
        time,
        columns: values,
        dt,
    })
}

/// The first line from `line` (1-based) on that is neither a `#` comment nor blank;
/// `newlines` are the offsets of the '\n's of `bytes`.
fn first_data_line(bytes: &[u8], newlines: &[usize], mut line: usize) -> usize {
    loop {
        let from = if line == 1 { 0 } else { newlines[line - 2] + 1 };
        let to = newlines.get(line - 1).copied().unwrap_or(bytes.len());
        let text = &bytes[from.min(to)..to];
        let skipped = text.starts_with(b"#") || text.trim_ascii().is_empty();
        if !skipped || to == bytes.len() {
            return line;
        }
        line += 1;
    }
}

/// The 0-based index of column `c` (an index, or a name looked up in the header).
fn column_index(
    path: &Path,
    header: &Option<(Vec<String>, usize)>,
    role: &str,
    key: &str,
    c: &Column,
) -> Result<usize> {
    match (c, header) {
        (Column::Index(i), _) => Ok(*i),
        (Column::Name(name), Some((names, line))) => {
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
                ExperimentError::data(
                    path,
                    format!(
                        "line {line}: no {role} column named `{name}` ({key}): the header has {}{hint}",
                        found.join(", ")
                    ),
                )
            })
        }
        (Column::Name(name), None) => Err(ExperimentError::data(
            path,
            format!(
                "{key} = \"{name}\": the file has no header (data.header = false): use a 0-based column index"
            ),
        )),
    }
}

/// Refuses a row with more fields than the header (or the first data row) has: a
/// decimal comma or a wrong delimiter would shift the columns.
fn check_width(
    path: &Path,
    line: usize,
    fields: usize,
    expected: usize,
    has_header: bool,
    delimiter: char,
) -> Result<()> {
    if fields <= expected {
        return Ok(());
    }
    Err(ExperimentError::data(
        path,
        format!(
            "line {line}: the row has {fields} fields, expected {expected} as the {}: a decimal comma, or the wrong delimiter (data.delimiter = {delimiter:?})?",
            if has_header { "header" } else { "first row" },
        ),
    ))
}

/// The value of one cell (`spec`'s column, at `index` of row `r` on `line`) as read and
/// scaled, refused when it is not a number, overflows or is too large to square.
fn cell_value(
    path: &Path,
    line: usize,
    r: &csv::StringRecord,
    spec: &ColumnSpec,
    index: usize,
    decimal: char,
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
    let value = parse_cell(cell, decimal).map_err(|why| {
        ExperimentError::data(path, format!("line {line}, {role} column {column}: {why}"))
    })?;
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

/// The time grid of `rows` samples: from the sample rate, or the time column's values
/// checked for a uniform step (within 1 %) and regularised onto it.
fn time_grid(
    path: &Path,
    sample_rate: Option<f64>,
    mut time: Vec<f64>,
    rows: usize,
) -> Result<(Vec<f64>, f64)> {
    let dt = match sample_rate {
        Some(fs) => {
            let dt = 1.0 / fs;
            time = (0..rows).map(|i| i as f64 * dt).collect();
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
    Ok((time, dt))
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

/// A cell as a finite number, with `decimal` as its decimal mark; a cell that would read
/// with the other mark says so.
fn parse_cell(cell: &str, decimal: char) -> std::result::Result<f64, String> {
    let cell = cell.trim().trim_matches('"');
    if cell.is_empty() {
        return Err("empty cell: expected a number".into());
    }
    let read = |mark: char| -> Option<f64> {
        if mark == ',' && cell.contains('.') {
            return None; // "1.234,5": a thousands separator, not read
        }
        cell.replacen(mark, ".", 1).parse::<f64>().ok()
    };
    match read(decimal) {
        Some(v) if v.is_finite() => Ok(v),
        Some(v) => Err(format!("{v}: expected a finite number")),
        None if decimal == '.' && read(',').is_some() => Err(format!(
            "`{cell}` is not a number with a decimal point: a decimal comma? set decimal = \",\" (and a delimiter other than \",\")"
        )),
        None => Err(format!("`{cell}` is not a number")),
    }
}

/// The column `column` (config key `key`) of the in-memory table `columns` of `path`.
pub(crate) fn pick<'a>(
    path: &Path,
    columns: &'a [(String, Vec<f64>)],
    column: &Column,
    key: &str,
) -> Result<&'a [f64]> {
    let found = match column {
        Column::Name(name) => columns.iter().find(|(n, _)| n == name),
        Column::Index(i) => columns.get(*i),
    };
    let names: Vec<String> = columns.iter().map(|(n, _)| format!("`{n}`")).collect();
    let (_, values) = found.ok_or_else(|| {
        ExperimentError::data(
            path,
            format!(
                "{key} = {column}: no such column among the {} given in memory ({})",
                columns.len(),
                names.join(", ")
            ),
        )
    })?;
    let rows = columns[0].1.len();
    if values.len() != rows {
        return Err(ExperimentError::data(
            path,
            format!(
                "{key} = {column}: {} values where the first column has {rows}: expected columns of one length",
                values.len()
            ),
        ));
    }
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

#[cfg(test)]
mod tests {
    use super::parse_cell;

    #[test]
    fn decimal_commas_read_when_asked_and_are_named_when_not() {
        assert_eq!(parse_cell("-0,980708", ','), Ok(-0.980708));
        assert_eq!(parse_cell(" 12 ", ','), Ok(12.0));
        assert_eq!(parse_cell("1.5e-3", '.'), Ok(1.5e-3));
        let why = parse_cell("-0,980708", '.').unwrap_err();
        assert!(why.contains("decimal = \",\""), "{why}");
        // A thousands separator with a decimal comma is not guessed at.
        assert!(parse_cell("1.234,5", ',').is_err());
        let why = parse_cell("abc", '.').unwrap_err();
        assert!(!why.contains("decimal"), "{why}");
    }
}
