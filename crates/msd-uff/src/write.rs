//! Writing: [`WriteOptions`] and the writer of datasets 151, 164, 58 and 58b (15, 2411 and
//! 55 in `write55.rs`).

use serde::Serialize;

use crate::read58::Layout;
use crate::text::format_real;
use crate::write55::{write_nodes, write55};
use crate::{
    error::UffError,
    types::{
        Abscissa, ByteOrder, Encoding, Function58, Header151, Ordinate, Precision, UffFile,
        Units164,
    },
};

/// How numbers are written as text.
///
/// ```
/// use msd_uff::{AsciiNumbers, WriteOptions};
/// let exact = WriteOptions { ascii: AsciiNumbers::Exact };
/// assert_eq!(WriteOptions::default().ascii, AsciiNumbers::Fixed);
/// # let _ = exact;
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub enum AsciiNumbers {
    /// The columns of the SDRC description (record 7: `E13.5`; record 12: `E13.5` for single
    /// precision and for an uneven abscissa, `E20.12` for double precision), readable by
    /// every UFF reader, pyuff's fixed-column one included. Each number takes its shortest
    /// text that reads back exactly when that fits the column (one blank kept in front), and
    /// otherwise as many digits as fit: 14 significant digits in 20 columns and 7 in 13,
    /// one fewer for a negative number and one fewer for a three-digit exponent. So `0.5`,
    /// `1e-3` or `2048` come back exactly, `1/3` to about 2e-14 relative (6e-8 in 13
    /// columns), and no number worse than 5e-13 (5e-5 in 13 columns). Binary data is exact either way; the abscissa start and step of
    /// record 7 are text in binary datasets too.
    #[default]
    Fixed,
    /// Every number in 25 columns holding its shortest exact text, so that every `f64`
    /// (NaN aside) reads back identically. Lines are wider than the 80 columns of the
    /// description: this crate and readers that split on blanks read them; fixed-column
    /// readers such as pyuff do not.
    Exact,
}

/// Options for [`crate::write()`] and [`crate::to_bytes`].
///
/// ```
/// let options = msd_uff::WriteOptions::default(); // AsciiNumbers::Fixed
/// # let _ = options;
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct WriteOptions {
    /// How numbers are written as text. By default, [`AsciiNumbers::Fixed`].
    pub ascii: AsciiNumbers,
}

/// The file as bytes: header, units, nodes, data at nodes, then the functions.
pub(crate) fn file_bytes(file: &UffFile, options: &WriteOptions) -> Result<Vec<u8>, UffError> {
    let mut out = Out {
        bytes: Vec::new(),
        dataset: 151,
        index: 0,
    };
    if let Some(header) = &file.header {
        write151(&mut out, header)?;
    }
    if let Some(units) = &file.units {
        out.dataset = 164;
        write164(&mut out, units)?;
    }
    write_nodes(&mut out, &file.nodes, options)?;
    out.dataset = 55;
    for (index, data) in file.data_at_nodes.iter().enumerate() {
        out.index = index;
        write55(&mut out, data, options)?;
    }
    out.dataset = 58;
    for (index, function) in file.functions.iter().enumerate() {
        out.index = index;
        write58(&mut out, function, options)?;
    }
    Ok(out.bytes)
}

/// The bytes written so far and the dataset being written, for errors.
pub(crate) struct Out {
    pub bytes: Vec<u8>,
    pub dataset: u32,
    pub index: usize,
}

impl Out {
    pub(crate) fn line(&mut self, text: &str) {
        self.bytes.extend_from_slice(text.trim_end().as_bytes());
        self.bytes.push(b'\n');
    }

    pub(crate) fn refuse(
        &self,
        field: &'static str,
        value: String,
        expected: impl Into<String>,
    ) -> UffError {
        UffError::Unwritable {
            dataset: self.dataset,
            index: self.index,
            field,
            value,
            expected: expected.into(),
        }
    }

    /// Text of at most `width` characters and no line break.
    pub(crate) fn text<'t>(
        &self,
        field: &'static str,
        text: &'t str,
        width: usize,
    ) -> Result<&'t str, UffError> {
        if text.chars().any(|c| c == '\n' || c == '\r') {
            return Err(self.refuse(field, format!("{text:?}"), "text without line breaks"));
        }
        if text.chars().count() > width {
            return Err(self.refuse(
                field,
                format!("{text:?}"),
                format!("at most {width} characters"),
            ));
        }
        Ok(text)
    }

    /// A whole-line text (80A1), which must not read as the `    -1` that closes a dataset.
    pub(crate) fn text_line(&self, field: &'static str, text: &str) -> Result<String, UffError> {
        let text = self.text(field, text, 80)?;
        if text.trim() == "-1" {
            return Err(self.refuse(
                field,
                format!("{text:?}"),
                "a text other than \"-1\", which closes a dataset",
            ));
        }
        Ok(text.to_string())
    }

    /// An integer right-aligned in `width` columns.
    pub(crate) fn int(
        &self,
        field: &'static str,
        value: impl Into<i64>,
        width: usize,
    ) -> Result<String, UffError> {
        let text = format!("{:>width$}", value.into());
        if text.len() > width {
            return Err(self.refuse(
                field,
                text,
                format!("an integer of at most {width} characters"),
            ));
        }
        Ok(text)
    }
}

fn write151(out: &mut Out, h: &Header151) -> Result<(), UffError> {
    let lines = [
        "    -1".to_string(),
        format!("{:>6}", 151),
        out.text_line("model_name", &h.model_name)?,
        out.text_line("description", &h.description)?,
        out.text_line("db_program", &h.db_program)?,
        format!(
            "{:<10}{:<10}{}{}{}",
            out.text("db_created_date", &h.db_created_date, 10)?,
            out.text("db_created_time", &h.db_created_time, 10)?,
            out.int("db_version1", h.db_version1, 10)?,
            out.int("db_version2", h.db_version2, 10)?,
            out.int("file_type", h.file_type, 10)?,
        ),
        format!(
            "{:<10}{:<10}",
            out.text("db_saved_date", &h.db_saved_date, 10)?,
            out.text("db_saved_time", &h.db_saved_time, 10)?
        ),
        out.text_line("program", &h.program)?,
        format!(
            "{:<10}{:<10}",
            out.text("written_date", &h.written_date, 10)?,
            out.text("written_time", &h.written_time, 10)?
        ),
        "    -1".to_string(),
    ];
    lines.iter().for_each(|l| out.line(l));
    Ok(())
}

fn write164(out: &mut Out, u: &Units164) -> Result<(), UffError> {
    let d = |v: f64| format_real(v, 25, 'D');
    let lines = [
        "    -1".to_string(),
        format!("{:>6}", 164),
        format!(
            "{}{:>20}{}",
            out.int("code", u.code, 10)?,
            out.text("description", &u.description, 20)?,
            out.int("temperature_mode", u.temperature_mode, 10)?
        ),
        format!("{}{}{}", d(u.length), d(u.force), d(u.temperature)),
        d(u.temperature_offset),
        "    -1".to_string(),
    ];
    lines.iter().for_each(|l| out.line(l));
    Ok(())
}

fn write58(out: &mut Out, f: &Function58, options: &WriteOptions) -> Result<(), UffError> {
    let layout = Layout {
        complex: matches!(f.ordinate, Ordinate::Complex(_)),
        even: matches!(f.abscissa, Abscissa::Even { .. }),
        precision: f.precision,
    };
    let values = record12(out, f)?;
    let exact = options.ascii == AsciiNumbers::Exact;
    let real = |v: f64, width: usize| format_real(v, if exact { 25 } else { width }, 'E');
    let (start, step) = match f.abscissa {
        Abscissa::Even { start, step } => (start, step),
        Abscissa::Uneven(_) => (0.0, 0.0),
    };
    let size = match f.precision {
        Precision::Single => 4,
        Precision::Double => 8,
    };
    let id_line = match f.encoding {
        Encoding::Ascii => format!("{:>6}", 58),
        Encoding::Binary(order) => {
            let code = if order == ByteOrder::Little { 1 } else { 2 };
            let n = values.len() * size;
            format!(
                "{:>6}b{code:>6}{:>6}{:>12}{n:>12}{:>6}{:>6}{:>12}{:>12}",
                58, 2, 11, 0, 0, 0, 0
            )
        }
    };
    let mut lines = vec!["    -1".to_string(), id_line];
    for (i, id) in f.ids.iter().enumerate() {
        lines.push(out.text_line(["ids[0]", "ids[1]", "ids[2]", "ids[3]", "ids[4]"][i], id)?);
    }
    lines.push(format!(
        "{}{}{}{} {:>10}{}{} {:>10}{}{}",
        out.int("function_type", f.function_type.code(), 5)?,
        out.int("function_id", f.function_id, 10)?,
        out.int("version", f.version, 5)?,
        out.int("load_case", f.load_case, 10)?,
        out.text("response_entity", &f.response_entity, 10)?,
        out.int("response_node", f.response_node, 10)?,
        out.int("response_direction", f.response_direction, 4)?,
        out.text("reference_entity", &f.reference_entity, 10)?,
        out.int("reference_node", f.reference_node, 10)?,
        out.int("reference_direction", f.reference_direction, 4)?,
    ));
    lines.push(format!(
        "{:>10}{:>10}{:>10}{}{}{}",
        layout.ordinate_data_type(),
        f.len(),
        u8::from(layout.even),
        real(start, 13),
        real(step, 13),
        real(f.z_axis_value, 13)
    ));
    for axis in [
        &f.abscissa_axis,
        &f.ordinate_axis,
        &f.denominator_axis,
        &f.z_axis,
    ] {
        lines.push(format!(
            "{}{}{}{} {:<20} {:<20}",
            out.int("axis data_type", axis.data_type, 10)?,
            out.int("axis length_exponent", axis.length_exponent, 5)?,
            out.int("axis force_exponent", axis.force_exponent, 5)?,
            out.int("axis temperature_exponent", axis.temperature_exponent, 5)?,
            out.text("axis label", &axis.label, 20)?,
            out.text("axis units", &axis.units, 20)?,
        ));
    }
    lines.iter().for_each(|l| out.line(l));
    match f.encoding {
        Encoding::Ascii => {
            let widths = layout.widths();
            for chunk in values.chunks(widths.len()) {
                let line: String = chunk
                    .iter()
                    .zip(widths)
                    .map(|(&v, &w)| real(v, w))
                    .collect();
                out.line(&line);
            }
        }
        Encoding::Binary(order) => {
            for &v in &values {
                match (f.precision, order) {
                    (Precision::Single, ByteOrder::Little) => {
                        out.bytes.extend((v as f32).to_le_bytes())
                    }
                    (Precision::Single, ByteOrder::Big) => {
                        out.bytes.extend((v as f32).to_be_bytes())
                    }
                    (Precision::Double, ByteOrder::Little) => out.bytes.extend(v.to_le_bytes()),
                    (Precision::Double, ByteOrder::Big) => out.bytes.extend(v.to_be_bytes()),
                }
            }
        }
    }
    out.line("    -1");
    Ok(())
}

/// The numbers of record 12 in file order: per point the abscissa (if uneven), then the
/// real and imaginary parts.
fn record12(out: &Out, f: &Function58) -> Result<Vec<f64>, UffError> {
    let x = match &f.abscissa {
        Abscissa::Uneven(x) if x.len() != f.len() => {
            return Err(out.refuse(
                "abscissa",
                format!("{} uneven values", x.len()),
                format!("one per ordinate value ({})", f.len()),
            ));
        }
        Abscissa::Uneven(x) => Some(x),
        Abscissa::Even { .. } => None,
    };
    let mut values = Vec::with_capacity(f.len() * 3);
    for k in 0..f.len() {
        if let Some(x) = x {
            values.push(x[k]);
        }
        match &f.ordinate {
            Ordinate::Real(y) => values.push(y[k]),
            Ordinate::Complex(y) => values.extend([y[k].0, y[k].1]),
        }
    }
    Ok(values)
}
