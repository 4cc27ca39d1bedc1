//! Reading: the dataset loop, the id line, datasets 151 and 164, and skipping the rest.

use crate::framing::{IdLine, close_ascii, missing_close, parse_id_line, quote, record};
use crate::read55::{read15, read55, read2411};
use crate::read58::read58;
use crate::text::{FieldReader, Line, Lines, columns, data_numbers};
use crate::{
    error::{Position, UffError},
    types::{Header151, Skipped, TrailingBytes, UffFile, Units164},
};

/// Parses a whole file; see [`crate::parse`].
pub(crate) fn parse_file(bytes: &[u8]) -> Result<UffFile, UffError> {
    let mut file = UffFile::default();
    let mut lines = Lines::new(bytes);
    while let Some(open) = next_non_blank(&mut lines) {
        if !open.is_delimiter() {
            return Err(UffError::Malformed {
                at: open.at(None, 0),
                field: "dataset start",
                found: quote(&open.text),
                expected: "\"    -1\", the line that opens a dataset".into(),
            });
        }
        let id_line = lines.next_line().ok_or_else(|| UffError::Truncated {
            at: lines.here(None, true),
            field: "the dataset number line",
            found: "the end of the file".into(),
            expected: "a dataset number after \"    -1\"".into(),
        })?;
        let id = parse_id_line(&id_line)?;
        let skip = |note: &str| Skipped {
            number: id.number,
            offset: open.offset,
            line: open.number,
            binary: id.binary.is_some(),
            note: note.into(),
        };
        match id.number {
            58 => {
                let (function, trailing) = read58(&mut lines, &id)?;
                if let Some((offset, len)) = trailing.filter(|&(_, len)| len > 0) {
                    let function = file.functions.len();
                    file.trailing.push(TrailingBytes {
                        function,
                        offset,
                        len,
                    });
                }
                file.functions.push(function);
            }
            55 if id.binary.is_none() => file.data_at_nodes.push(read55(&mut lines)?),
            15 if id.binary.is_none() => file.nodes.extend(read15(&mut lines)?),
            2411 if id.binary.is_none() => file.nodes.extend(read2411(&mut lines)?),
            151 if file.header.is_none() && id.binary.is_none() => {
                file.header = Some(read151(&mut lines)?);
            }
            164 if file.units.is_none() && id.binary.is_none() => {
                file.units = Some(read164(&mut lines, &open)?);
            }
            151 | 164 if id.binary.is_none() => {
                skip_dataset(&mut lines, &id)?;
                file.skipped.push(skip("a second one: the first is kept"));
            }
            _ => {
                skip_dataset(&mut lines, &id)?;
                file.skipped.push(skip("not read by msd-uff"));
            }
        }
    }
    Ok(file)
}

/// The next line that is not blank (blank lines between datasets are passed over).
fn next_non_blank<'a>(lines: &mut Lines<'a>) -> Option<Line<'a>> {
    std::iter::from_fn(|| lines.next_line()).find(|l| !l.text.trim().is_empty())
}

/// Passes over a dataset this crate does not read. A binary one is passed over by its
/// counts of ASCII lines and bytes, so its data cannot be mistaken for a closing line.
fn skip_dataset(lines: &mut Lines<'_>, id: &IdLine) -> Result<(), UffError> {
    let Some(binary) = &id.binary else {
        return close_ascii(lines, id.number);
    };
    for _ in 0..binary.ascii_lines.max(0) {
        record(lines, id.number, "the ASCII lines of a binary dataset")?;
    }
    let data_start = lines.pos;
    let len = usize::try_from(binary.bytes).unwrap_or(usize::MAX);
    if lines.bytes.len() - data_start < len {
        return Err(UffError::Truncated {
            at: Position {
                dataset: Some(id.number),
                offset: data_start,
                line: None,
            },
            field: "binary data",
            found: format!("{} bytes", lines.bytes.len() - data_start),
            expected: format!(
                "{} bytes, as the id line at byte {} says",
                binary.bytes, binary.offset
            ),
        });
    }
    lines.skip_to(data_start + len);
    lines
        .close_binary()
        .map(|_| ())
        .ok_or_else(|| missing_close(lines, id.number))
}

/// Dataset 151, the header: seven records, as pyuff's `dataset_151.py` documents them.
fn read151(lines: &mut Lines<'_>) -> Result<Header151, UffError> {
    let text = |l: &Line<'_>| l.text.trim_end().to_string();
    let model = record(lines, 151, "record 1 (model file name)")?;
    let description = record(lines, 151, "record 2 (model file description)")?;
    let db_program = record(lines, 151, "record 3 (program which created the database)")?;
    let created = record(lines, 151, "record 4 (database created)")?;
    let saved = record(lines, 151, "record 5 (database last saved)")?;
    let program = record(lines, 151, "record 6 (program which wrote the file)")?;
    let written = record(lines, 151, "record 7 (file written)")?;
    let c = columns(&created, &[10, 10, 10, 10, 10], false);
    let reader = FieldReader {
        line: &created,
        dataset: Some(151),
    };
    let header = Header151 {
        model_name: text(&model),
        description: text(&description),
        db_program: text(&db_program),
        db_created_date: c[0].1.into(),
        db_created_time: c[1].1.into(),
        db_version1: reader.int(c[2], "record 4, version from database")?,
        db_version2: reader.int(c[3], "record 4, version from database")?,
        file_type: reader.int(c[4], "record 4, file type")?,
        db_saved_date: saved.col(0, 10).trim().into(),
        db_saved_time: saved.col(10, 10).trim().into(),
        program: text(&program),
        written_date: written.col(0, 10).trim().into(),
        written_time: written.col(10, 10).trim().into(),
    };
    close_ascii(lines, 151)?;
    Ok(header)
}

/// Dataset 164, the units: Format(I10,20A1,I10), then four factors in D25.17.
fn read164(lines: &mut Lines<'_>, open: &Line<'_>) -> Result<Units164, UffError> {
    let first = record(
        lines,
        164,
        "record 1 (units code, description, temperature mode)",
    )?;
    let c = columns(&first, &[10, 20, 10], false);
    let reader = FieldReader {
        line: &first,
        dataset: Some(164),
    };
    let (code, description) = (
        reader.int(c[0], "record 1, units code")?,
        c[1].1.to_string(),
    );
    let temperature_mode = reader.int(c[2], "record 1, temperature mode")?;
    let mut factors = Vec::new();
    while factors.len() < 4 {
        let line = record(lines, 164, "record 2 (unit factors)")?;
        data_numbers(&line, &[25, 25, 25], &mut factors).map_err(|(col, text)| {
            FieldReader {
                line: &line,
                dataset: Some(164),
            }
            .malformed(col, "record 2, unit factor", &text, "a number")
        })?;
    }
    if factors.len() > 4 {
        return Err(UffError::Malformed {
            at: Position {
                dataset: Some(164),
                offset: open.offset,
                line: Some(open.number),
            },
            field: "record 2 (unit factors)",
            found: format!("{} numbers", factors.len()),
            expected: "4: length, force, temperature, temperature offset".into(),
        });
    }
    close_ascii(lines, 164)?;
    Ok(Units164 {
        code,
        description,
        temperature_mode,
        length: factors[0],
        force: factors[1],
        temperature: factors[2],
        temperature_offset: factors[3],
    })
}
