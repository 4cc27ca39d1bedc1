//! Named numeric columns of a CSV file, each value with its line, for the table and
//! records sources: errors name the file, the line, the column and the config key.

use crate::config::Column;
use crate::{ExperimentError, Result};
use std::path::Path;

/// The columns read: `values[c][row]`, and the 1-based line of each row.
pub(crate) struct Columns {
    pub values: Vec<Vec<f64>>,
    pub lines: Vec<usize>,
}

/// Where to read: the file, its delimiter and header, and the columns as
/// `(config key, column)`.
pub(crate) struct Request<'a> {
    pub path: &'a Path,
    /// The key of the file in the config, for messages (`frequency_response.table.path`).
    pub path_key: &'a str,
    pub delimiter: char,
    pub header: bool,
    pub columns: Vec<(String, &'a Column)>,
}

/// Reads the requested columns; blank lines and `#` comments are passed over.
pub(crate) fn read(request: &Request<'_>) -> Result<Columns> {
    let path = request.path;
    let fail = |message: String| ExperimentError::data(path, message);
    let bytes = std::fs::read(path).map_err(|e| {
        fail(format!(
            "cannot open the file ({} = {:?}): {e}",
            request.path_key,
            path.file_name().unwrap_or_default()
        ))
    })?;
    if !request.delimiter.is_ascii() {
        return Err(fail(format!(
            "delimiter {:?}: expected a single ASCII character",
            request.delimiter
        )));
    }
    let mut reader = csv::ReaderBuilder::new()
        .delimiter(request.delimiter as u8)
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(bytes.as_slice());
    let line_of = |r: &csv::StringRecord| r.position().map_or(0, |p| p.line() as usize);
    let mut records = reader.records();
    let header = if request.header {
        match records.next() {
            Some(Ok(r)) => Some(r),
            Some(Err(e)) => return Err(fail(e.to_string())),
            None => return Err(fail("the file is empty: expected a header line".into())),
        }
    } else {
        None
    };
    let indices = request
        .columns
        .iter()
        .map(|(key, column)| {
            index_of(column, key, header.as_ref().map(|h| (h, line_of(h)))).map_err(&fail)
        })
        .collect::<Result<Vec<usize>>>()?;
    let mut out = Columns {
        values: vec![Vec::new(); indices.len()],
        lines: Vec::new(),
    };
    for r in records {
        let r = r.map_err(|e| fail(e.to_string()))?;
        if r.iter().all(str::is_empty) {
            continue;
        }
        let line = line_of(&r);
        for (c, (&index, (key, column))) in indices.iter().zip(&request.columns).enumerate() {
            let cell = r.get(index).ok_or_else(|| {
                fail(format!(
                    "line {line}: the row has {} fields, no column {column} ({key})",
                    r.len()
                ))
            })?;
            let value = parse(cell)
                .map_err(|why| fail(format!("line {line}, column {column} ({key}): {why}")))?;
            out.values[c].push(value);
        }
        out.lines.push(line);
    }
    if out.lines.is_empty() {
        return Err(fail("no data rows: expected at least one".into()));
    }
    Ok(out)
}

/// The 0-based index of `column`, looked up in the header by name.
fn index_of(
    column: &Column,
    key: &str,
    header: Option<(&csv::StringRecord, usize)>,
) -> std::result::Result<usize, String> {
    match (column, header) {
        (Column::Index(i), _) => Ok(*i),
        (Column::Name(name), Some((h, line))) => {
            h.iter().position(|n| n == name).ok_or_else(|| {
                let found: Vec<String> = h.iter().map(|n| format!("`{n}`")).collect();
                format!(
                    "line {line}: no column named `{name}` ({key}): the header has {}",
                    found.join(", ")
                )
            })
        }
        (Column::Name(name), None) => Err(format!(
            "{key} = \"{name}\": the file has no header (header = false): use a 0-based column index"
        )),
    }
}

fn parse(cell: &str) -> std::result::Result<f64, String> {
    let cell = cell.trim_matches('"');
    match cell.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(v) => Err(format!("{v}: expected a finite number")),
        Err(_) if cell.is_empty() => Err("empty cell: expected a number".into()),
        Err(_) => Err(format!("`{cell}` is not a number")),
    }
}
