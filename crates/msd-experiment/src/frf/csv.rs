//! Named numeric columns of a table, each value with its line, for the table and
//! records sources: a text file read by the one text reader (`data::text`: encoding,
//! metadata lines, decimal commas, missing values), or a MATLAB, NumPy or TDMS file's
//! channels. Errors name the file, the line, the column and the config key.

use crate::config::Column;
use crate::data::csv::{column_index, pick};
use crate::data::text::{self, Header, Missing, TextFormat};
use crate::error::{ExperimentError, Result};
use crate::sources::Sources;
use msd_signal::Complex64;
use std::path::Path;

/// The columns read: `values[c][row]`, the complex column if one was asked for, the
/// 1-based line of each row, and what the reader did that a report should say.
pub(crate) struct Columns {
    pub values: Vec<Vec<f64>>,
    pub complex: Vec<Complex64>,
    pub lines: Vec<usize>,
    pub notes: Vec<String>,
}

/// Where to read: the file, how it is written, and the columns as
/// `(config key, column)`.
pub(crate) struct Request<'a> {
    /// Where the file comes from (the disk, or memory).
    pub sources: &'a Sources,
    pub path: &'a Path,
    /// The key of the file in the config, for messages (`frequency_response.table.path`).
    pub path_key: &'a str,
    pub format: TextFormat,
    pub columns: Vec<(String, &'a Column)>,
    /// A column of complex numbers as text, `(config key, column)`.
    pub complex: Option<(String, &'a Column)>,
}

/// Reads the requested columns; blank lines and `#` comments are passed over.
pub(crate) fn read(request: &Request<'_>) -> Result<Columns> {
    let path = request.path;
    let fail = |message: String| ExperimentError::data(path, message);
    if let Some(given) = request.sources.table(path, request.path_key)? {
        return from_columns(request, &given);
    }
    let bytes = request.sources.bytes(path, request.path_key)?;
    let format = &request.format;
    let mut out = Columns {
        values: vec![Vec::new(); request.columns.len()],
        complex: Vec::new(),
        lines: Vec::new(),
        notes: Vec::new(),
    };
    let indices = |header: Option<&Header>| -> Result<(Vec<usize>, Option<usize>)> {
        let find = |key: &str, c: &Column| column_index(path, header, "", key, c);
        let columns = request
            .columns
            .iter()
            .map(|(key, column)| find(key, column))
            .collect::<Result<Vec<usize>>>()?;
        let complex = request
            .complex
            .as_ref()
            .map(|(key, column)| find(key, column))
            .transpose()?;
        Ok((columns, complex))
    };
    let notes = text::scan(
        path,
        &bytes,
        format,
        indices,
        |(indices, complex), line, r| {
            // The cell of `column` at `index`, or why not, with the line and the key.
            let cell = |index: usize, key: &str, column: &Column| {
                r.get(index).ok_or_else(|| {
                    fail(format!(
                        "line {line}: the row has {} fields, no column {column} ({key}){}",
                        r.len(),
                        numbering(column, r.len())
                    ))
                })
            };
            for (c, (&index, (key, column))) in indices.iter().zip(&request.columns).enumerate() {
                let v = text::parse_cell(cell(index, key, column)?, format.decimal, format.missing)
                    .map_err(|why| fail(format!("line {line}, column {column} ({key}): {why}")))?;
                out.values[c].push(v);
            }
            if let (Some(index), Some((key, column))) = (complex, &request.complex) {
                let text = cell(*index, key, column)?;
                let z = if text::is_missing(text) && format.missing != Missing::Refuse {
                    Complex64::new(f64::NAN, f64::NAN)
                } else {
                    parse_complex(text).map_err(|why| {
                        fail(format!("line {line}, column {column} ({key}): {why}"))
                    })?
                };
                out.complex.push(z);
            }
            out.lines.push(line);
            Ok(())
        },
    )?;
    out.notes = notes;
    fill(path, &mut out, format.missing)?;
    if out.lines.is_empty() {
        return Err(fail("no data rows: expected at least one".into()));
    }
    Ok(out)
}

/// The missing policy applied to every column read, the complex one as its two parts.
fn fill(path: &Path, out: &mut Columns, missing: Missing) -> Result<()> {
    let (mut re, mut im): (Vec<f64>, Vec<f64>) = out.complex.iter().map(|z| (z.re, z.im)).unzip();
    let mut all: Vec<&mut Vec<f64>> = out.values.iter_mut().collect();
    if !re.is_empty() {
        all.push(&mut re);
        all.push(&mut im);
    }
    if let Some(note) = text::fill_missing(path, &mut all, &mut out.lines, missing)? {
        out.notes.push(note);
        out.complex = re
            .into_iter()
            .zip(im)
            .map(|(re, im)| Complex64::new(re, im))
            .collect();
    }
    Ok(())
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

/// A finite number with a decimal point.
fn parse(cell: &str) -> std::result::Result<f64, String> {
    text::parse_cell(cell, '.', Missing::Refuse)
}

/// A complex number as text: `a+bj`, `(a+bj)`, `a-bi`, `bj`, `a` (spaces allowed
/// around the sign), each part a finite number.
fn parse_complex(cell: &str) -> std::result::Result<Complex64, String> {
    let quoted = cell.trim_matches('"').trim();
    if quoted.starts_with('(') != quoted.ends_with(')') {
        return Err(format!(
            "`{cell}` is not a complex number: its parenthesis is not closed (a line cut short, or a decimal comma read as the delimiter: then set decimal = \",\" and the file's own delimiter)"
        ));
    }
    let text: String = quoted
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
    let rows = values.first().map_or(0, Vec::len);
    if let Some((c, (key, column))) = values
        .iter()
        .zip(&request.columns)
        .find(|(v, _)| v.len() != rows)
    {
        return Err(ExperimentError::data(
            request.path,
            format!(
                "{key} = {column}: {} values where {} has {rows}: expected columns of one length",
                c.len(),
                request.columns[0].0
            ),
        ));
    }
    Ok(Columns {
        values,
        complex: Vec::new(),
        lines: (1..=rows).collect(),
        notes: Vec::new(),
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
        // Issue 46 §5: `(-0,077+2,6e-08j)` split at its decimal commas gave `(-0`, read
        // as 0; a last line cut short gave a real number.
        assert!(parse_complex("077+2").is_err());
        for cut in ["(-0", "6e-08j)", "(-0.08208477"] {
            let err = parse_complex(cut).unwrap_err();
            assert!(err.contains("parenthesis is not closed"), "{err}");
        }
    }
}
