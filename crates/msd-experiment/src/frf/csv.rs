//! Named numeric columns of a table, each value with its line, for the table and
//! records sources: a text file read by the one text reader (`data::text`: encoding,
//! metadata lines, decimal commas, missing values), or a MATLAB, NumPy or TDMS file's
//! channels. Errors name the file, the line, the column and the config key.

use crate::config::Column;
use crate::data::csv::{column_index, pick};
use crate::data::text::{self, Header, Missing, TextFormat, parse_complex};
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
