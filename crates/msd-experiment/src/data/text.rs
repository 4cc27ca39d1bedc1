//! The one reader of text tables (time records, FRF tables, output-only records): the
//! file's encoding (UTF-8, UTF-16 with its BOM, else Windows-1252 — a SignalCalc export's
//! `m/s²` in Latin-1), metadata lines before the header found and skipped, a units line
//! under the header, `#` comments and blank lines passed over, any delimiter, a decimal
//! comma, and missing values refused, dropped or interpolated. Every row comes with its
//! 1-based line for messages.

use crate::error::{ExperimentError, Result};
use msd_signal::Complex64;
use serde::{Deserialize, Serialize};
use std::borrow::Cow;
use std::path::Path;

/// What a text table's reader does with a missing value (an empty cell, or `NaN`, `NA`,
/// `N/A`, `#N/A`, `null`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Missing {
    /// Refuse the file, naming the line (the default).
    #[default]
    Refuse,
    /// Drop every row with a missing value; the report says how many.
    Drop,
    /// Fill each gap linearly between its neighbours (the nearest value at an end); the
    /// report says how many.
    Interpolate,
}

impl Missing {
    /// Whether this is the default (`refuse`), left out of `results.json`'s config echo.
    pub fn is_refuse(&self) -> bool {
        *self == Self::Refuse
    }
}

/// How a text table is written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TextFormat {
    /// The field delimiter (one ASCII character).
    pub delimiter: char,
    /// The decimal mark, `.` or `,`.
    pub decimal: char,
    /// Whether a line of column names precedes the data.
    pub header: bool,
    /// Lines to skip before the header; 0 finds metadata lines by themselves.
    pub skip_lines: usize,
    /// What to do with an empty or NaN cell.
    pub missing: Missing,
}

/// The header's names and its 1-based line.
#[derive(Debug, Clone, PartialEq)]
pub struct Header {
    /// The column names.
    pub names: Vec<String>,
    /// The line they are on.
    pub line: usize,
}

/// Reads the table in `bytes` (the file `path`): `on_header` receives the header (or
/// `None` without one) and returns what `on_row` needs; `on_row` receives every data row
/// with its line. Returns the notes a report shows (metadata skipped, units found, the
/// encoding when it was not UTF-8).
pub(crate) fn scan<H>(
    path: &Path,
    bytes: &[u8],
    format: &TextFormat,
    on_header: impl FnOnce(Option<&Header>) -> Result<H>,
    mut on_row: impl FnMut(&H, usize, &csv::StringRecord) -> Result<()>,
) -> Result<Vec<String>> {
    if !format.delimiter.is_ascii() {
        return Err(ExperimentError::data(
            path,
            format!(
                "delimiter {:?}: expected a single ASCII character",
                format.delimiter
            ),
        ));
    }
    let (text, mut notes) = decode(bytes);
    let format = &with_delimiter(path, &text, format, &mut notes)?;
    let text = whitespace_runs(text, format.delimiter);
    let text = text.as_bytes();
    let newlines: Vec<usize> = text
        .iter()
        .enumerate()
        .filter_map(|(i, &b)| (b == b'\n').then_some(i))
        .collect();
    let layout = layout(text, &newlines, format);
    if let (true, Some(line)) = (format.header, layout.headless) {
        return Err(no_header(path, text, &newlines, line));
    }
    notes.extend(layout.notes.iter().cloned());
    let lines = newlines.len() + usize::from(text.last().is_some_and(|&b| b != b'\n'));
    if format.skip_lines >= lines && lines > 0 {
        return Err(ExperimentError::data(
            path,
            format!(
                "skip_lines = {}: the file has {lines} lines: expected fewer lines skipped than it has (the header, then the data, come after them)",
                format.skip_lines
            ),
        ));
    }
    let start = if layout.skip == 0 {
        0
    } else {
        newlines.get(layout.skip - 1).map_or(text.len(), |&i| i + 1)
    };
    let mut reader = csv::ReaderBuilder::new()
        .delimiter(format.delimiter as u8)
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(&text[start..]);
    let line_of = |pos: Option<&csv::Position>| {
        pos.map_or(0, |p| {
            let byte = start + p.byte() as usize;
            // With CRLF the csv crate puts a record's start on the previous line's '\n'
            // (after its '\r'), hence ≤; it also puts it before the comment and blank
            // lines it skipped: the record is on the first line after them.
            let line = 1 + newlines.partition_point(|&i| i <= byte);
            first_data_line(text, &newlines, line)
        })
    };
    let malformed = |e: &csv::Error| match e.position() {
        Some(p) => format!("line {}: malformed CSV: {e}", line_of(Some(p))),
        None => format!("malformed CSV: {e}"),
    };
    let mut records = reader.records();
    let header = if format.header {
        match records.next() {
            Some(Ok(r)) => Some(Header {
                names: r.iter().map(str::to_string).collect(),
                line: line_of(r.position()),
            }),
            Some(Err(e)) => return Err(ExperimentError::data(path, malformed(&e))),
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
    let state = on_header(header.as_ref())?;
    // More fields than the header (or the first data row) has: a decimal comma or a
    // wrong delimiter would shift the columns, so the row is refused.
    let mut fields = header.as_ref().map(|h| h.names.len());
    for r in records {
        let r = r.map_err(|e| ExperimentError::data(path, malformed(&e)))?;
        let line = line_of(r.position());
        if r.iter().all(str::is_empty) || layout.units_lines.contains(&line) {
            continue;
        }
        let expected = *fields.get_or_insert(r.len());
        if r.len() > expected {
            return Err(ExperimentError::data(
                path,
                format!(
                    "line {line}: the row has {} fields, expected {expected} as the {}: a decimal comma, or the wrong delimiter (delimiter = {:?})?",
                    r.len(),
                    if header.is_some() {
                        "header"
                    } else {
                        "first row"
                    },
                    format.delimiter
                ),
            ));
        }
        on_row(&state, line, &r)?;
    }
    Ok(notes)
}

/// The refusal of a table whose first line (`line`, 0-based) is data read with
/// `header = true`.
fn no_header(path: &Path, text: &[u8], newlines: &[usize], line: usize) -> ExperimentError {
    let from = if line == 0 { 0 } else { newlines[line - 1] + 1 };
    let to = newlines.get(line).copied().unwrap_or(text.len());
    let shown: String = String::from_utf8_lossy(&text[from.min(to)..to])
        .chars()
        .take(60)
        .collect();
    ExperimentError::data(
        path,
        format!(
            "line {}: the first line is data, not column names (`{}`): set header = false and give the columns by 0-based number (`msd inspect` prints the lines)",
            line + 1,
            shown.trim()
        ),
    )
}

/// The text as the reader splits it: with the delimiter `" "` (columns separated by
/// runs of spaces or tabs, as NumPy's `savetxt`, MATLAB's `save -ascii` and many loggers
/// write them) each line trimmed and each run made one space; any other delimiter
/// leaves it as it is. Lines stay where they were.
pub(crate) fn whitespace_runs(text: Cow<'_, str>, delimiter: char) -> Cow<'_, str> {
    if delimiter != ' ' {
        return text;
    }
    let mut out = String::with_capacity(text.len());
    for (i, line) in text.split('\n').enumerate() {
        if i > 0 {
            out.push('\n');
        }
        let (body, cr) = match line.strip_suffix('\r') {
            Some(body) => (body, "\r"),
            None => (line, ""),
        };
        let mut fields = body.split([' ', '\t']).filter(|f| !f.is_empty());
        if let Some(first) = fields.next() {
            out.push_str(first);
            for f in fields {
                out.push(' ');
                out.push_str(f);
            }
        }
        out.push_str(cr);
    }
    Cow::Owned(out)
}

/// `format` with its delimiter: with decimal commas and the default `,` delimiter, the
/// one found in the file (`;` or a tab, as spreadsheets write them), said in a note.
fn with_delimiter(
    path: &Path,
    text: &str,
    format: &TextFormat,
    notes: &mut Vec<String>,
) -> Result<TextFormat> {
    if !(format.decimal == ',' && format.delimiter == ',') {
        return Ok(*format);
    }
    match sniff(text).0 {
        d if d != ',' => {
            notes.push(format!(
                "delimiter {d:?} (found in the file: the decimal mark is \",\")"
            ));
            Ok(TextFormat {
                delimiter: d,
                ..*format
            })
        }
        _ => Err(ExperimentError::data(
            path,
            "decimal = \",\": no delimiter other than \",\" splits the data lines alike: expected \";\" or a tab between the columns (set delimiter)",
        )),
    }
}

/// The delimiter that splits the last data lines (no letters but an exponent's, a
/// NaN's or a complex number's imaginary unit) into the same number (≥ 2) of fields — `" "` for runs of spaces or tabs —
/// and the decimal mark their cells use.
pub(crate) fn sniff(text: &str) -> (char, char) {
    let tail: Vec<&str> = text
        .lines()
        .rev()
        .map(str::trim)
        .filter(|l| {
            !l.is_empty()
                && !l.starts_with('#')
                && l.chars()
                    .all(|c| !c.is_alphabetic() || "eEnNaAiIjJ".contains(c))
        })
        .take(20)
        .collect();
    // A cell of data: a number (either decimal mark), a complex number, or missing.
    let cell = |c: &str| {
        let c = c.trim();
        is_missing(c)
            || number(c, '.').is_some()
            || number(c, ',').is_some()
            || complex_cell(c).is_some()
    };
    // Every line split into the same number (≥ 2) of fields; all of them cells of data.
    let alike = |split: &dyn Fn(&str) -> Vec<&str>| {
        let fields: Vec<Vec<&str>> = tail.iter().map(|l| split(l)).collect();
        let same = fields
            .first()
            .is_some_and(|first| first.len() >= 2 && fields.iter().all(|f| f.len() == first.len()));
        (same, same && fields.iter().flatten().all(|c| cell(c)))
    };
    let counted = ['\t', ';', ',', '|']
        .into_iter()
        .map(|d| (d, alike(&|l| l.split(d).collect())))
        .find(|(_, (same, _))| *same);
    // Runs of spaces or tabs where they split every line into cells of data and the
    // single character found does not (a tab between cells that still hold spaces).
    let (_, spaced) = alike(&|l| l.split_whitespace().collect());
    let delimiter = match counted {
        Some((d, (_, clean))) if clean || !spaced => d,
        _ if spaced => ' ',
        _ => ',',
    };
    let commas = delimiter != ','
        && tail.iter().any(|l| {
            l.split(delimiter)
                .any(|c| number(c.trim(), ',').is_some() && c.contains(','))
        });
    (delimiter, if commas { ',' } else { '.' })
}

/// The text of `bytes`: UTF-8 (a BOM dropped), UTF-16 by its BOM, else Windows-1252,
/// which reads every byte (Latin-1's letters and symbols where they are); a note says
/// which when it was not UTF-8.
pub(crate) fn decode(bytes: &[u8]) -> (Cow<'_, str>, Vec<String>) {
    if let Some((encoding, bom)) = encoding_rs::Encoding::for_bom(bytes) {
        let (text, _) = encoding.decode_without_bom_handling(&bytes[bom..]);
        let note = (encoding != encoding_rs::UTF_8)
            .then(|| format!("read as {} (by its byte-order mark)", encoding.name()));
        return (text, note.into_iter().collect());
    }
    match std::str::from_utf8(bytes) {
        Ok(text) => (Cow::Borrowed(text), Vec::new()),
        Err(_) => {
            let (text, _, _) = encoding_rs::WINDOWS_1252.decode(bytes);
            (
                text,
                vec!["not UTF-8: read as Windows-1252 (Latin-1)".into()],
            )
        }
    }
}

/// Where the table starts: the lines skipped before the header, units lines under it,
/// and what a report says of them.
#[derive(Debug, Default, PartialEq)]
pub(crate) struct Layout {
    pub skip: usize,
    pub units_lines: Vec<usize>,
    pub units: Vec<String>,
    pub notes: Vec<String>,
    /// Settings an oscilloscope writes beside its columns' names and units (Rigol's
    /// `Start`, `Increment`), as (name, value).
    pub settings: Vec<(String, f64)>,
    /// The first line of the file (0-based, comment and blank lines aside) when it is
    /// data (every field a number): there is no header, whatever `header` says.
    pub headless: Option<usize>,
}

/// Finds the table in `text` when `format.skip_lines` is 0: the first line whose fields
/// all read as numbers (with the next such line, if any, of the same width) starts the
/// data; with a header, the header is the first of the lines of that width just above
/// it (the others, units); every line above is metadata.
pub(crate) fn layout(text: &[u8], newlines: &[usize], format: &TextFormat) -> Layout {
    if format.skip_lines > 0 {
        return Layout {
            skip: format.skip_lines,
            ..Layout::default()
        };
    }
    let line_text = |i: usize| -> &[u8] {
        let from = if i == 0 { 0 } else { newlines[i - 1] + 1 };
        let to = newlines.get(i).copied().unwrap_or(text.len());
        text[from.min(to)..to].trim_ascii()
    };
    let lines = (newlines.len() + 1).min(500);
    let content: Vec<usize> = (0..lines)
        .filter(|&i| {
            let t = line_text(i);
            !t.is_empty() && !t.starts_with(b"#")
        })
        .collect();
    let fields = |i: usize| -> Vec<String> {
        String::from_utf8_lossy(line_text(i))
            .split(format.delimiter)
            .map(|f| f.trim().trim_matches('"').to_string())
            .collect()
    };
    let numeric = |i: usize| {
        let f = fields(i);
        f.iter().any(|c| !c.is_empty())
            && f.iter()
                .all(|c| c.is_empty() || number(c, format.decimal).is_some())
    };
    let Some(pos) = content.iter().position(|&i| numeric(i)) else {
        return Layout::default();
    };
    let data = content[pos];
    let width = fields(data).len();
    let above = &content[..pos];
    let block = above
        .iter()
        .rev()
        .take_while(|&&i| fields(i).len() == width)
        .count();
    // A header wider than the data whose extra names have no column (LabVIEW's `.lvm`
    // names a `Comment` column its rows leave out) heads them all the same.
    let wider = (format.header && block == 0 && pos > 0)
        .then(|| above[pos - 1])
        .filter(|&i| fields(i).len() > width);
    // An oscilloscope's CSV (Rigol): the names, then their units with the capture's
    // settings beyond the data's columns (`Start`, `Increment`): the names head it.
    // `used`: the data's columns, a trailing delimiter's empty field aside.
    let used = fields(data)
        .iter()
        .rposition(|c| !c.is_empty())
        .map_or(0, |k| k + 1);
    let scope = wider.and_then(|_| scope_header(&fields, above, pos, used, format.decimal));
    let wider = wider.filter(|_| scope.is_none());
    let header = match (format.header, block, wider) {
        (false, _, _) => data,
        (true, 0, _) if scope.is_some() => above[pos - 2],
        (true, 0, Some(i)) => i,
        (true, 0, None) => {
            return Layout {
                headless: (pos == 0).then_some(data),
                ..Layout::default()
            };
        }
        (true, n, _) => above[pos - n],
    };
    let mut out = Layout {
        skip: header,
        ..Layout::default()
    };
    if let Some(i) = wider {
        out.notes.extend(extra_names_note(i, &fields(i)[width..]));
    }
    if !format.header && block > 0 {
        let line = above[pos - 1];
        let shown: String = String::from_utf8_lossy(line_text(line))
            .chars()
            .take(60)
            .collect();
        out.notes.push(format!(
            "line {} looks like a header (`{shown}`: as many fields as the data, not all numbers) but header = false: it was skipped and the columns are read by number; set header = true to name them",
            line + 1
        ));
    }
    if let Some(settings) = scope {
        let units = above[pos - 1];
        out.scope_units(units, fields(units)[..used].to_vec(), settings);
    }
    if format.header && block > 1 {
        out.units_lines = above[pos - block + 1..].iter().map(|i| i + 1).collect();
        out.units = fields(above[pos - 1]);
        out.notes.push(format!(
            "line {}: units {}",
            above[pos - 1] + 1,
            out.units.join(", ")
        ));
    }
    // Without a header, a header-like line just above the data has its own note.
    let named = (!format.header && block > 0).then(|| above[pos - 1]);
    let metadata: Vec<usize> = (above.iter().copied())
        .filter(|&i| i < header && Some(i) != named)
        .collect();
    if let Some(&first) = metadata.first() {
        // Every line above the header (or the header-like line), blank ones included.
        let note = metadata_note(first, named.unwrap_or(header), line_text(first));
        out.notes.push(note);
    }
    out
}

/// The note on a header's names beyond the data's columns (line `line`, 0-based),
/// when there are any.
fn extra_names_note(line: usize, extra: &[String]) -> Option<String> {
    let extra: Vec<&str> = (extra.iter().map(String::as_str))
        .filter(|n| !n.is_empty())
        .collect();
    (!extra.is_empty()).then(|| {
        format!(
            "line {}: the header names columns the data do not hold ({}): passed over",
            line + 1,
            extra.join(", ")
        )
    })
}

impl Layout {
    /// An oscilloscope's units line `units` (0-based) with the capture's `settings`.
    fn scope_units(&mut self, units: usize, names: Vec<String>, settings: Vec<(String, f64)>) {
        self.units_lines = vec![units + 1];
        self.units = names;
        let shown: Vec<String> = (settings.iter()).map(|(n, v)| format!("{n} {v}")).collect();
        self.notes.push(format!(
            "line {}: units {}; settings beside the columns: {}",
            units + 1,
            self.units.join(", "),
            shown.join(", ")
        ));
        self.settings = settings;
    }
}

/// The note on the lines 1 to `last` (1-based) read as metadata, the first of them
/// (0-based `first`, whose text is `text`) shown.
fn metadata_note(first: usize, last: usize, text: &[u8]) -> String {
    let shown: String = String::from_utf8_lossy(text).chars().take(60).collect();
    let lines = if last == 1 {
        "line 1".to_string()
    } else {
        format!("lines 1–{last}")
    };
    format!(
        "{lines} read as metadata and skipped (line {}: `{shown}`); set skip_lines to choose",
        first + 1
    )
}

/// An oscilloscope's two header lines above the data at `pos` (Rigol: `X,CH1,Start,
/// Increment` over `Sequence,Volt,-0.5,0.001`): the line just above the data is wider
/// than it, its cells beyond the data's width are numbers, and the line above that
/// names every column of the data. Returns the settings beyond the data's columns.
fn scope_header(
    fields: &dyn Fn(usize) -> Vec<String>,
    above: &[usize],
    pos: usize,
    width: usize,
    decimal: char,
) -> Option<Vec<(String, f64)>> {
    let (names, units) = (fields(above[pos.checked_sub(2)?]), fields(above[pos - 1]));
    if names.len() < units.len() || units.len() <= width {
        return None;
    }
    let word = |c: &String| !c.is_empty() && number(c, decimal).is_none();
    let named = names[..width].iter().all(word);
    let settings: Vec<(String, f64)> = (names[width..].iter().zip(&units[width..]))
        .filter_map(|(n, v)| Some((n.clone(), number(v, decimal)?)))
        .filter(|(n, _)| !n.is_empty())
        .collect();
    (named && units[..width].iter().all(word) && !settings.is_empty()).then_some(settings)
}

/// A cell as a number with `decimal` as its decimal mark, if it reads as one; a clock
/// time (`12:00:00.002`, with a date before it) as its seconds.
pub(crate) fn number(cell: &str, decimal: char) -> Option<f64> {
    if cell.contains(':') {
        // A logger's clock time (`12:00:00.002`, with a date before it): its seconds.
        return super::clock::clock_seconds(cell, decimal);
    }
    if decimal == ',' && cell.contains('.') {
        return None; // "1.234,5": a thousands separator, not read
    }
    cell.replacen(decimal, ".", 1).parse::<f64>().ok()
}

/// Whether a cell holds no value: empty, or NaN as spreadsheets and loggers write it.
pub(crate) fn is_missing(cell: &str) -> bool {
    let cell = cell.trim().trim_matches('"');
    cell.is_empty()
        || ["nan", "na", "n/a", "#n/a", "null"].contains(&cell.to_ascii_lowercase().as_str())
}

/// A cell as a finite number with `decimal` as its decimal mark (NaN for a missing
/// value when `missing` is not `refuse`); a cell that would read with the other mark
/// says so.
pub(crate) fn parse_cell(
    cell: &str,
    decimal: char,
    missing: Missing,
) -> std::result::Result<f64, String> {
    let cell = cell.trim().trim_matches('"');
    if is_missing(cell) {
        return match missing {
            Missing::Refuse => Err(format!(
                "{}: expected a number (set missing = \"drop\" or \"interpolate\" to pass over missing values)",
                if cell.is_empty() {
                    "empty cell".to_string()
                } else {
                    format!("`{cell}`")
                }
            )),
            Missing::Drop | Missing::Interpolate => Ok(f64::NAN),
        };
    }
    match number(cell, decimal) {
        Some(v) if v.is_finite() => Ok(v),
        Some(v) => Err(format!("{v}: expected a finite number")),
        None if decimal == '.' && number(cell, ',').is_some() => Err(format!(
            "`{cell}` is not a number with a decimal point: a decimal comma? set decimal = \",\" (and a delimiter other than \",\")"
        )),
        None => Err(format!("`{cell}` is not a number")),
    }
}

/// A finite number with a decimal point.
fn parse(cell: &str) -> std::result::Result<f64, String> {
    parse_cell(cell, '.', Missing::Refuse)
}

/// A complex number as text: `a+bj`, `(a+bj)`, `a-bi`, `bj`, `a` (spaces allowed
/// around the sign), each part a finite number.
pub(crate) fn parse_complex(cell: &str) -> std::result::Result<Complex64, String> {
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

/// The unit written at the end of a column's name, `accel [g]` or `force (kN)`.
pub(crate) fn unit_in_name(name: &str) -> Option<&str> {
    let name = name.trim_end();
    let (open, close) = match name.chars().last()? {
        ']' => ('[', ']'),
        ')' => ('(', ')'),
        _ => return None,
    };
    let inner = &name[name.rfind(open)? + 1..name.len() - close.len_utf8()];
    Some(inner.trim()).filter(|u| !u.is_empty())
}

/// A column name's words, lower case (`Magnitude (dB)`: "magnitude", "db").
pub(crate) fn name_words(name: &str) -> impl Iterator<Item = String> + '_ {
    (name.split(|c: char| !c.is_alphanumeric()))
        .filter(|w| !w.is_empty())
        .map(str::to_lowercase)
}

/// Seconds in one `unit` of time (s, ms, µs, min), `None` for any other unit.
pub(crate) fn seconds_per(unit: &str) -> Option<f64> {
    match unit {
        "s" | "sec" => Some(1.0),
        "ms" => Some(1e-3),
        "µs" | "μs" | "us" => Some(1e-6),
        "min" => Some(60.0),
        _ => None,
    }
}

/// The sampling rate, Hz, of a time step of `step` units of `seconds` each: a whole
/// number where it is one to rounding (1000 Hz, not 999.9999999999999).
pub(crate) fn rate_of_step(step: f64, seconds: f64) -> f64 {
    let exact = 1.0 / (step * seconds);
    let whole = exact.round();
    if (whole - exact).abs() <= 1e-9 * exact {
        whole
    } else {
        exact
    }
}

/// A cell that is a complex number with its imaginary unit (`(a+bj)`, `a-bi`): a plain
/// number is not one here.
pub(crate) fn complex_cell(cell: &str) -> Option<Complex64> {
    let c = cell
        .trim()
        .trim_matches('"')
        .trim_end_matches(')')
        .trim_end();
    let imaginary = c.ends_with(['j', 'i', 'J', 'I']);
    imaginary.then(|| parse_complex(cell).ok()).flatten()
}

/// Applies `missing` to the columns read (NaN where a value was missing), rows at
/// `lines`: `drop` removes every row with a missing value, `interpolate` fills each gap
/// linearly between its neighbours (the nearest value at an end). Returns the note that
/// says how many, or an error when a column has no value at all.
pub(crate) fn fill_missing(
    path: &Path,
    columns: &mut [&mut Vec<f64>],
    lines: &mut Vec<usize>,
    missing: Missing,
) -> Result<Option<String>> {
    let gaps: Vec<usize> = (0..lines.len())
        .filter(|&r| columns.iter().any(|c| c[r].is_nan()))
        .collect();
    if gaps.is_empty() {
        return Ok(None);
    }
    let shown = |rows: &[usize]| {
        let mut s: Vec<String> = rows.iter().take(5).map(|&r| lines[r].to_string()).collect();
        if rows.len() > 5 {
            s.push("…".into());
        }
        s.join(", ")
    };
    let where_ = shown(&gaps);
    match missing {
        Missing::Refuse => Ok(None),
        Missing::Drop => {
            let keep: Vec<bool> = (0..lines.len())
                .map(|r| gaps.binary_search(&r).is_err())
                .collect();
            for c in columns.iter_mut() {
                let mut k = keep.iter();
                c.retain(|_| *k.next().unwrap_or(&true));
            }
            let mut k = keep.iter();
            lines.retain(|_| *k.next().unwrap_or(&true));
            Ok(Some(format!(
                "{} row{} with a missing value dropped (line {where_})",
                gaps.len(),
                if gaps.len() == 1 { "" } else { "s" }
            )))
        }
        Missing::Interpolate => {
            let mut count = 0;
            for c in columns.iter_mut() {
                count += interpolate(c).ok_or_else(|| {
                    ExperimentError::data(
                        path,
                        "a column has no value at all: expected at least one number",
                    )
                })?;
            }
            Ok(Some(format!(
                "{count} missing value{} interpolated (line {where_})",
                if count == 1 { "" } else { "s" }
            )))
        }
    }
}

/// Fills the NaNs of `v` linearly between neighbours (the nearest value at an end);
/// how many, or `None` when every value is NaN.
fn interpolate(v: &mut [f64]) -> Option<usize> {
    let known: Vec<usize> = (0..v.len()).filter(|&i| !v[i].is_nan()).collect();
    let (&first, &last) = (known.first()?, known.last()?);
    let mut count = 0;
    for i in 0..v.len() {
        if !v[i].is_nan() {
            continue;
        }
        count += 1;
        v[i] = if i < first {
            v[first]
        } else if i > last {
            v[last]
        } else {
            let k = known.partition_point(|&j| j < i);
            let (a, b) = (known[k - 1], known[k]);
            v[a] + (v[b] - v[a]) * (i - a) as f64 / (b - a) as f64
        };
    }
    Some(count)
}

/// The first line from `line` (1-based) on that is neither a `#` comment nor blank;
/// `newlines` are the offsets of the '\n's of `text`.
fn first_data_line(text: &[u8], newlines: &[usize], mut line: usize) -> usize {
    loop {
        let from = if line == 1 { 0 } else { newlines[line - 2] + 1 };
        let to = newlines.get(line - 1).copied().unwrap_or(text.len());
        let t = &text[from.min(to)..to];
        let skipped = t.starts_with(b"#") || t.trim_ascii().is_empty();
        if !skipped || to == text.len() {
            return line;
        }
        line += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn format(delimiter: char, decimal: char) -> TextFormat {
        TextFormat {
            delimiter,
            decimal,
            header: true,
            skip_lines: 0,
            missing: Missing::Refuse,
        }
    }

    /// Runs of spaces and tabs become one space, each line trimmed, CRLF kept: the
    /// lines stay where they were (line numbers in messages hold).
    #[test]
    fn whitespace_runs_are_one_delimiter() {
        let text = Cow::Borrowed(" t   x\tv \r\n 0  1.5\t\t2\r\n\n#c  d\n");
        assert_eq!(
            whitespace_runs(text.clone(), ' '),
            "t x v\r\n0 1.5 2\r\n\n#c d\n"
        );
        assert_eq!(whitespace_runs(text.clone(), ','), text);
    }

    /// The delimiter is the one that splits every data line into cells of data: a
    /// single tab is a tab, runs of spaces are `" "`, and a tab between cells that
    /// still hold spaces is not taken.
    #[test]
    fn the_delimiter_is_found_among_the_usual_ones() {
        assert_eq!(sniff("t\tx\n0\t1\n1\t2\n"), ('\t', '.'));
        assert_eq!(sniff("t x\n 0.0   1e-3\n 1.0  -2e-3\n"), (' ', '.'));
        assert_eq!(sniff("0  1\t2\n3  4\t5\n"), (' ', '.'));
        assert_eq!(sniff("t;x\n0,5;1,5\n1,5;2,5\n"), (';', ','));
        assert_eq!(sniff("(1+2j) (3-4j)\n(5+6j) (7+8j)\n"), (' ', '.'));
        assert_eq!(sniff("1.0,(0.1+0.2j)\n2.0,(0.3-0.1j)\n"), (',', '.'));
        // A column that is not a number (a time stamp) keeps the delimiter its count
        // finds.
        let stamped = "2026-11-30 12:30:01;1,5;2,5\n2026-11-30 12:30:02;1,6;2,4\n";
        assert_eq!(sniff(stamped), (';', ','));
    }

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

    #[test]
    fn a_header_under_header_false_is_skipped_and_said_once() {
        let f = TextFormat {
            header: false,
            ..format(',', '.')
        };
        let layout = layout_of("station 7\nt,force,x\n0,1,2\n1,2,3\n", &f);
        assert_eq!(layout.skip, 2);
        assert!(
            layout.notes[0].starts_with("line 2 looks like a header"),
            "{:?}",
            layout.notes
        );
        assert!(
            layout.notes[1].starts_with("line 1 read as metadata"),
            "{:?}",
            layout.notes
        );
        assert_eq!(layout.notes.len(), 2);
    }

    /// A table whose first line is data (`numpy.savetxt` without `header=`): read with
    /// `header = true` its first row would name the columns and be lost; it is refused
    /// with the key to set, and read whole with `header = false`.
    #[test]
    fn a_table_without_a_header_is_refused_until_header_false() {
        let text = "0.000,1.5,2e-3\n0.001,1.4,3e-3\n";
        let f = format(',', '.');
        assert_eq!(layout_of(text, &f).headless, Some(0));
        assert_eq!(layout_of(&format!("# rig 3\n{text}"), &f).headless, Some(1));
        assert_eq!(layout_of(&format!("t,F,x\n{text}"), &f).headless, None);
        let path = Path::new("run.csv");
        let e = scan(path, text.as_bytes(), &f, |_| Ok(()), |_, _, _| Ok(()))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(
                "the first line is data, not column names (`0.000,1.5,2e-3`): set header = false"
            ),
            "{e}"
        );
        let headless = TextFormat { header: false, ..f };
        let mut rows = 0;
        scan(
            path,
            text.as_bytes(),
            &headless,
            |_| Ok(()),
            |_, _, _| {
                rows += 1;
                Ok(())
            },
        )
        .unwrap();
        assert_eq!(rows, 2);
    }

    /// LabVIEW's `.lvm`: two header blocks of metadata, then a header that names a
    /// `Comment` column the rows leave out. The header heads the data all the same and
    /// every line above it is metadata; the scan reads the columns by name.
    #[test]
    fn a_labview_measurement_file_reads_by_its_names() {
        let text = "LabVIEW Measurement\t\nWriter_Version\t2\n***End_of_Header***\t\n\t\n\
                    Channels\t2\t\nDelta_X\t1.000000E-3\t1.000000E-3\t\n***End_of_Header***\t\n\
                    X_Value\tForce\tDisplacement\tComment\n0.000\t1.5\t0.1\n0.001\t1.4\t0.2\n";
        let format = TextFormat {
            delimiter: '\t',
            decimal: '.',
            header: true,
            skip_lines: 0,
            missing: Missing::Refuse,
        };
        let l = layout_of(text, &format);
        assert_eq!(l.skip, 7); // the header is line 8
        assert!(
            l.notes[0].contains("(Comment): passed over"),
            "{:?}",
            l.notes
        );
        assert!(
            l.notes[1].starts_with("lines 1–7 read as metadata"),
            "{:?}",
            l.notes
        );
        let mut force = Vec::new();
        let path = Path::new("run.lvm");
        scan(
            path,
            text.as_bytes(),
            &format,
            |h| Ok(h.expect("a header").names.iter().position(|n| n == "Force")),
            |column, _, r| {
                force.push(r[column.expect("Force is named")].parse::<f64>().unwrap());
                Ok(())
            },
        )
        .unwrap();
        assert_eq!(force, [1.5, 1.4]);
    }

    fn layout_of(text: &str, f: &TextFormat) -> Layout {
        let newlines: Vec<usize> = text
            .bytes()
            .enumerate()
            .filter_map(|(i, b)| (b == b'\n').then_some(i))
            .collect();
        layout(text.as_bytes(), &newlines, f)
    }

    #[test]
    fn metadata_lines_and_a_units_line_are_found() {
        let text = "Title: rig 2\nDate: 2026-11-29; 10:00\n\ntime;force;accel\ns;N;m/s²\n0,0;1,5;-0,98\n0,1;1,4;-0,97\n";
        let l = layout_of(text, &format(';', ','));
        assert_eq!(l.skip, 3); // the header is line 4
        assert_eq!(l.units_lines, vec![5]);
        assert_eq!(l.units, vec!["s", "N", "m/s²"]);
        assert!(
            l.notes
                .iter()
                .any(|n| n.contains("lines 1–3 read as metadata")),
            "{:?}",
            l.notes
        );
        // A plain file: nothing skipped, nothing said.
        assert_eq!(
            layout_of("t,F\n0,1\n", &format(',', '.')),
            Layout::default()
        );
    }

    #[test]
    fn latin_1_and_utf_16_text_is_read() {
        let (text, notes) = decode(b"a\tm/s\xb2\n");
        assert_eq!(text, "a\tm/s²\n");
        assert!(notes[0].contains("Windows-1252"));
        let utf16: Vec<u8> = [0xFF, 0xFE]
            .into_iter()
            .chain("t,F\n".encode_utf16().flat_map(u16::to_le_bytes))
            .collect();
        assert_eq!(decode(&utf16).0, "t,F\n");
    }

    #[test]
    fn decimal_commas_read_when_asked_and_are_named_when_not() {
        let refuse = Missing::Refuse;
        assert_eq!(parse_cell("-0,980708", ',', refuse), Ok(-0.980708));
        assert_eq!(parse_cell(" 12 ", ',', refuse), Ok(12.0));
        assert_eq!(parse_cell("1.5e-3", '.', refuse), Ok(1.5e-3));
        let why = parse_cell("-0,980708", '.', refuse).unwrap_err();
        assert!(why.contains("decimal = \",\""), "{why}");
        // A thousands separator with a decimal comma is not guessed at.
        assert!(parse_cell("1.234,5", ',', refuse).is_err());
        let why = parse_cell("abc", '.', refuse).unwrap_err();
        assert!(!why.contains("decimal"), "{why}");
        assert!(
            parse_cell("NaN", '.', refuse)
                .unwrap_err()
                .contains("missing = ")
        );
        assert!(parse_cell("", '.', Missing::Interpolate).unwrap().is_nan());
    }

    /// Damaged text (bytes overwritten, lines cut, any encoding) is read or refused
    /// with the file named, never a panic: 3000 seeded cases of a small export.
    #[test]
    fn damaged_tables_are_read_or_refused_by_name() {
        let good =
            "Rig 2\r\nt;F;x\r\ns;N;m\r\n0,0;1,5;0,1\r\n0,1;1,4;NaN\r\n0,2;1,3;0,3\r\n".as_bytes();
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = |below: usize| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % below as u64) as usize
        };
        let path = Path::new("damaged.csv");
        for case in 0..3000 {
            let mut bytes = good[..good.len() - next(good.len())].to_vec();
            for _ in 0..next(4) {
                if !bytes.is_empty() {
                    let at = next(bytes.len());
                    bytes[at] = next(256) as u8;
                }
            }
            let mut f = format(if case % 2 == 0 { ';' } else { ',' }, ',');
            f.missing = [Missing::Refuse, Missing::Drop, Missing::Interpolate][case % 3];
            let read = scan(
                path,
                &bytes,
                &f,
                |_| Ok(()),
                |_, _, r| {
                    for cell in r.iter() {
                        let _ = parse_cell(cell, f.decimal, f.missing);
                    }
                    Ok(())
                },
            );
            if let Err(e) = read {
                assert!(e.to_string().contains("damaged.csv"), "{e}");
            }
        }
    }

    #[test]
    fn missing_values_are_dropped_or_interpolated_and_counted() {
        let nan = f64::NAN;
        let (mut a, mut b) = (vec![nan, 1.0, nan, 3.0, nan], vec![0.0, 1.0, 2.0, 3.0, 4.0]);
        let mut lines = vec![2, 3, 4, 5, 6];
        let note = fill_missing(
            Path::new("x.csv"),
            &mut [&mut a, &mut b],
            &mut lines,
            Missing::Interpolate,
        )
        .unwrap();
        assert_eq!(a, vec![1.0, 1.0, 2.0, 3.0, 3.0]);
        assert_eq!(
            note.unwrap(),
            "3 missing values interpolated (line 2, 4, 6)"
        );
        let (mut a, mut b) = (vec![nan, 1.0, 2.0], vec![0.0, 1.0, nan]);
        let mut lines = vec![2, 3, 4];
        let note = fill_missing(
            Path::new("x.csv"),
            &mut [&mut a, &mut b],
            &mut lines,
            Missing::Drop,
        )
        .unwrap();
        assert_eq!((a, b, lines), (vec![1.0], vec![1.0], vec![3]));
        assert!(
            note.unwrap()
                .starts_with("2 rows with a missing value dropped")
        );
    }
}
