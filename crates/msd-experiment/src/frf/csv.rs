//! Named numeric columns of a CSV file, each value with its line, for the table and
//! records sources: errors name the file, the line, the column and the config key.

use crate::config::Column;
use crate::data::csv::pick;
use crate::error::{ExperimentError, Result};
use crate::sources::Sources;
use msd_signal::Complex64;
use std::path::Path;

/// The columns read: `values[c][row]`, the complex column if one was asked for, and the
/// 1-based line of each row.
pub(crate) struct Columns {
    pub values: Vec<Vec<f64>>,
    pub complex: Vec<Complex64>,
    pub lines: Vec<usize>,
}

/// Where to read: the file, its delimiter and header, and the columns as
/// `(config key, column)`.
pub(crate) struct Request<'a> {
    /// Where the file comes from (the disk, or memory).
    pub sources: &'a Sources,
    pub path: &'a Path,
    /// The key of the file in the config, for messages (`frequency_response.table.path`).
    pub path_key: &'a str,
    pub delimiter: char,
    pub header: bool,
    pub columns: Vec<(String, &'a Column)>,
    /// A column of complex numbers as text, `(config key, column)`.
    pub complex: Option<(String, &'a Column)>,
}

/// Reads the requested columns; blank lines and `#` comments are passed over.
pub(crate) fn read(request: &Request<'_>) -> Result<Columns> {
    let path = request.path;
    let fail = |message: String| ExperimentError::data(path, message);
    if let Some(given) = request.sources.columns(path) {
        return from_columns(request, given);
    }
    let bytes = request.sources.read(path).map_err(|e| {
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
    let complex = match &request.complex {
        Some((key, column)) => Some((
            index_of(column, key, header.as_ref().map(|h| (h, line_of(h)))).map_err(&fail)?,
            key,
            *column,
        )),
        None => None,
    };
    let mut out = Columns {
        values: vec![Vec::new(); indices.len()],
        complex: Vec::new(),
        lines: Vec::new(),
    };
    for r in records {
        let r = r.map_err(|e| fail(e.to_string()))?;
        if r.iter().all(str::is_empty) {
            continue;
        }
        let line = line_of(&r);
        // The cell of `column` parsed by `parse`, or why not, with the line and the key.
        let cell =
            |index: usize,
             key: &str,
             column: &Column,
             parse: &dyn Fn(&str) -> std::result::Result<Complex64, String>| {
                let text = r.get(index).ok_or_else(|| {
                    fail(format!(
                        "line {line}: the row has {} fields, no column {column} ({key}){}",
                        r.len(),
                        numbering(column, r.len())
                    ))
                })?;
                parse(text).map_err(|why: String| {
                    fail(format!("line {line}, column {column} ({key}): {why}"))
                })
            };
        for (c, (&index, (key, column))) in indices.iter().zip(&request.columns).enumerate() {
            out.values[c].push(
                cell(index, key, column, &|t| {
                    parse(t).map(|v| Complex64::new(v, 0.0))
                })?
                .re,
            );
        }
        if let Some((index, key, column)) = complex {
            out.complex.push(cell(index, key, column, &parse_complex)?);
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

/// For a column given by number: how the row's columns are numbered.
fn numbering(column: &Column, fields: usize) -> String {
    match column {
        Column::Index(_) => format!(
            "; columns are numbered from 0, so this row's are #0 … #{}",
            fields.saturating_sub(1)
        ),
        Column::Name(_) => String::new(),
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

/// A complex number as text: `a+bj`, `(a+bj)`, `a-bi`, `bj`, `a` (spaces allowed
/// around the sign), each part a finite number.
fn parse_complex(cell: &str) -> std::result::Result<Complex64, String> {
    let text: String = cell
        .trim_matches('"')
        .trim()
        .trim_start_matches('(')
        .trim_end_matches(')')
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect();
    let bad =
        || format!("`{cell}` is not a complex number (expected e.g. `1.5-2e-3j` or `(1.5-2e-3j)`)");
    if text.is_empty() {
        return Err("empty cell: expected a complex number".into());
    }
    let Some(body) = text.strip_suffix(['j', 'i', 'J', 'I']) else {
        return parse(&text).map(|re| Complex64::new(re, 0.0));
    };
    // The sign that starts the imaginary part: the last + or − not after an exponent's e.
    let bytes = body.as_bytes();
    let split = (1..bytes.len())
        .rev()
        .find(|&i| matches!(bytes[i], b'+' | b'-') && !matches!(bytes[i - 1], b'e' | b'E'))
        .unwrap_or(0);
    let (re, im) = body.split_at(split);
    let part = |p: &str| match p {
        "" | "+" => Ok(1.0),
        "-" => Ok(-1.0),
        _ => parse(p),
    };
    let re = if re.is_empty() { Ok(0.0) } else { parse(re) };
    match (re, part(im)) {
        (Ok(re), Ok(im)) => Ok(Complex64::new(re, im)),
        _ => Err(bad()),
    }
}

/// The requested columns of a table given in memory (a complex column needs the text of
/// a file: give the real and imaginary parts as columns instead).
fn from_columns(request: &Request<'_>, given: &[(String, Vec<f64>)]) -> Result<Columns> {
    if let Some((key, column)) = &request.complex {
        return Err(ExperimentError::data(
            request.path,
            format!(
                "{key} = {column}: a column of complex numbers as text cannot be given in memory: give the real and imaginary parts"
            ),
        ));
    }
    let values = request
        .columns
        .iter()
        .map(|(key, column)| pick(request.path, given, column, key).map(<[f64]>::to_vec))
        .collect::<Result<Vec<_>>>()?;
    let rows = given.first().map_or(0, |(_, v)| v.len());
    Ok(Columns {
        values,
        complex: Vec::new(),
        lines: (1..=rows).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn complex_numbers_in_the_usual_notations() {
        let c = |re, im| Ok(Complex64::new(re, im));
        assert_eq!(
            parse_complex("(-0.0774752256830106+2.6838208936737454e-08j)"),
            c(-0.0774752256830106, 2.6838208936737454e-08)
        );
        assert_eq!(parse_complex("1.5e+3-2E-3i"), c(1500.0, -0.002));
        assert_eq!(parse_complex(" 2 - 3 j "), c(2.0, -3.0));
        assert_eq!(parse_complex("-4j"), c(0.0, -4.0));
        assert_eq!(parse_complex("j"), c(0.0, 1.0));
        assert_eq!(parse_complex("7"), c(7.0, 0.0));
        for bad in ["1+xj", "(1+2k)", "nan+1j", "1+infj", "()"] {
            assert!(parse_complex(bad).is_err(), "{bad}");
        }
    }
}
