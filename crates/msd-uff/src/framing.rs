//! A dataset's framing: the id line after the opening `    -1`, its records, and the
//! closing `    -1`, shared by every dataset reader.

use crate::error::UffError;
use crate::text::{FieldReader, Line, Lines, numeric_fields};

/// The line after the opening `    -1`: the dataset number and, for binary datasets (a `b`
/// in column 7), the fields of the 58b description.
pub(crate) struct IdLine {
    pub number: u32,
    pub binary: Option<BinaryId>,
}

/// Fields 3–6 of a binary dataset's id line, Format(I6,1A1,I6,I6,I12,I12,I6,I6,I12,I12).
pub(crate) struct BinaryId {
    pub byte_order: i64,
    pub float_format: i64,
    pub ascii_lines: i64,
    pub bytes: i64,
    /// The line, for error positions.
    pub line: usize,
    pub offset: usize,
}

/// Text as found, quoted, cut to 40 characters.
pub(crate) fn quote(text: &str) -> String {
    let cut: String = text.chars().take(40).collect();
    if cut.len() < text.len() {
        format!("{cut:?}…")
    } else {
        format!("{cut:?}")
    }
}

/// The id line after a dataset's opening `    -1`: its number and, for a binary
/// dataset, the fields of its description.
pub(crate) fn parse_id_line(line: &Line<'_>) -> Result<IdLine, UffError> {
    let head = line.col(0, 6).trim();
    let number = head.parse::<u32>().map_err(|_| UffError::Malformed {
        at: line.at(None, 0),
        field: "dataset number",
        found: quote(&line.text),
        expected: "a dataset number in columns 1-6 (e.g. \"    58\")".into(),
    })?;
    if !line.col(6, 1).eq_ignore_ascii_case("b") {
        return Ok(IdLine {
            number,
            binary: None,
        });
    }
    let reader = FieldReader {
        line,
        dataset: Some(number),
    };
    let rest = Line {
        text: line.col(7, usize::MAX).into(),
        offset: 0,
        number: 0,
    };
    let fields: Vec<(usize, &str)> = numeric_fields(&rest, &[6, 6, 12, 12, 6, 6, 12, 12])
        .into_iter()
        .map(|(c, t)| (c + 7, t))
        .collect();
    let binary = BinaryId {
        byte_order: reader.int(fields[0], "binary id line, byte ordering")?,
        float_format: reader.int(fields[1], "binary id line, floating-point format")?,
        ascii_lines: reader.int(fields[2], "binary id line, number of ASCII lines")?,
        bytes: reader.int(fields[3], "binary id line, number of bytes")?,
        line: line.number,
        offset: line.offset,
    };
    Ok(IdLine {
        number,
        binary: Some(binary),
    })
}

/// The next line of dataset `number`, or an error naming `record`.
pub(crate) fn record<'a>(
    lines: &mut Lines<'a>,
    number: u32,
    record: &'static str,
) -> Result<Line<'a>, UffError> {
    match lines.next_line() {
        Some(line) if !line.is_delimiter() => Ok(line),
        Some(line) => Err(UffError::Truncated {
            at: line.at(Some(number), 0),
            field: record,
            found: "the closing \"    -1\"".into(),
            expected: format!("{record} first"),
        }),
        None => Err(UffError::Truncated {
            at: lines.here(Some(number), true),
            field: record,
            found: "the end of the file".into(),
            expected: record.into(),
        }),
    }
}

/// Passes over the lines up to and including the closing `    -1` of an ASCII dataset.
pub(crate) fn close_ascii(lines: &mut Lines<'_>, number: u32) -> Result<(), UffError> {
    loop {
        match lines.next_line() {
            Some(line) if line.is_delimiter() => return Ok(()),
            Some(_) => {}
            None => {
                return Err(UffError::Truncated {
                    at: lines.here(Some(number), true),
                    field: "the end of the dataset",
                    found: "the end of the file".into(),
                    expected: "\"    -1\", the line that closes a dataset".into(),
                });
            }
        }
    }
}

/// The error for binary data not followed by a closing `    -1`.
pub(crate) fn missing_close(lines: &Lines<'_>, number: u32) -> UffError {
    UffError::Truncated {
        at: lines.here(Some(number), false),
        field: "the end of the dataset",
        found: "no \"    -1\" line after the binary data".into(),
        expected: "\"    -1\", the line that closes a dataset".into(),
    }
}
