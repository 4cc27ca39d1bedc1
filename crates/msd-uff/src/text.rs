//! Lines, fixed columns and Fortran numbers: the text layer under the readers and writer.

use std::borrow::Cow;

use crate::error::{Position, UffError};

/// One line of the file, without its line end.
pub(crate) struct Line<'a> {
    /// The text: UTF-8 if the bytes are, else Latin-1 (one character per byte).
    pub text: Cow<'a, str>,
    /// Byte offset of the line's first byte.
    pub offset: usize,
    /// Line number, 1-based.
    pub number: usize,
}

impl Line<'_> {
    /// Characters `start .. start + width` (fewer, or none, past the end of the line).
    pub fn col(&self, start: usize, width: usize) -> &str {
        let mut idx = self.text.char_indices().map(|(i, _)| i).skip(start);
        let Some(from) = idx.next() else { return "" };
        let to = self
            .text
            .char_indices()
            .nth(start.saturating_add(width))
            .map_or(self.text.len(), |(i, _)| i);
        &self.text[from..to]
    }

    /// The position of character `column`.
    pub fn at(&self, dataset: Option<u32>, column: usize) -> Position {
        let bytes_before: usize = self
            .text
            .chars()
            .take(column)
            .map(|c| self.width_of(c))
            .sum();
        Position {
            dataset,
            offset: self.offset + bytes_before,
            line: Some(self.number),
        }
    }

    /// Bytes a character took in the file.
    fn width_of(&self, c: char) -> usize {
        match self.text {
            Cow::Borrowed(_) => c.len_utf8(),
            Cow::Owned(_) => 1, // decoded from Latin-1
        }
    }

    /// Whether this is a `    -1` line, which opens and closes every dataset: `-1` ending
    /// within the first six columns, blanks after.
    pub fn is_delimiter(&self) -> bool {
        is_delimiter(&self.text)
    }
}

/// [`Line::is_delimiter`] of a line's text.
fn is_delimiter(text: &str) -> bool {
    // Most lines are longer and end in a character that is not blank.
    let bytes = text.as_bytes();
    if bytes.len() > 6 && bytes.last().is_some_and(|&b| b > b' ' && b.is_ascii()) {
        return false;
    }
    let t = text.trim_end();
    t.trim_start() == "-1" && t.len() <= 6
}

/// Reads a byte slice line by line, and lets binary data be taken between lines.
pub(crate) struct Lines<'a> {
    pub bytes: &'a [u8],
    /// Offset of the next unread byte.
    pub pos: usize,
    /// Number of the next line.
    pub line: usize,
    /// The longest start of `bytes` that is UTF-8, checked once: its lines need no check.
    utf8: &'a str,
}

impl<'a> Lines<'a> {
    pub fn new(bytes: &'a [u8]) -> Self {
        let utf8 = match std::str::from_utf8(bytes) {
            Ok(text) => text,
            Err(e) => std::str::from_utf8(&bytes[..e.valid_up_to()]).unwrap_or_default(),
        };
        Self {
            bytes,
            pos: 0,
            line: 1,
            utf8,
        }
    }

    /// The next line (ended by LF, CR LF or CR, or by the end of the file); `None` at the end.
    pub fn next_line(&mut self) -> Option<Line<'a>> {
        if self.pos >= self.bytes.len() {
            return None;
        }
        let rest = &self.bytes[self.pos..];
        let len = line_length(rest);
        let raw = &rest[..len];
        // A line within the UTF-8 start begins and ends next to a line end (or at the end of
        // the file), so on character boundaries.
        let checked = self.utf8.get(self.pos..self.pos + len);
        let text = match checked.map_or_else(|| std::str::from_utf8(raw), Ok) {
            Ok(s) => Cow::Borrowed(s),
            Err(_) => Cow::Owned(raw.iter().map(|&b| char::from(b)).collect()),
        };
        let line = Line {
            text,
            offset: self.pos,
            number: self.line,
        };
        self.pass_line(len);
        Some(line)
    }

    /// Moves past the line of `len` bytes at the current position, and its line end.
    fn pass_line(&mut self, len: usize) {
        let ending = match self.bytes.get(self.pos + len..self.pos + len + 2) {
            Some(b"\r\n") => 2,
            _ if self.pos + len < self.bytes.len() => 1,
            _ => 0,
        };
        self.pos += len + ending;
        self.line += 1;
    }

    /// The common line of a data record, read without building a [`Line`]: if the next line
    /// is UTF-8, is not a `    -1` line and holds only numbers, and `out` then holds at most
    /// `max` of them, appends its numbers, moves past it and returns `true`. Otherwise
    /// changes nothing and returns `false`: the line is for [`Lines::next_line`] and
    /// [`data_numbers`], which read it (or say what is wrong with it) as they read any line.
    pub fn numbers_line(&mut self, out: &mut Vec<f64>, max: usize) -> bool {
        let Some(text) = self.utf8.get(self.pos..).filter(|t| !t.is_empty()) else {
            return false;
        };
        let start = out.len();
        let Some(len) = line_numbers(text, out) else {
            return false;
        };
        // The line ends within the UTF-8 start, or the file ends with it.
        let whole = len < text.len() || self.pos + len == self.bytes.len();
        if !whole || out.len() > max || is_delimiter(&text[..len]) {
            out.truncate(start);
            return false;
        }
        self.pass_line(len);
        true
    }

    /// Moves to byte `to` (not before the current position), counting the line feeds passed.
    pub fn skip_to(&mut self, to: usize) {
        let to = to.clamp(self.pos, self.bytes.len());
        self.line += self.bytes[self.pos..to]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        self.pos = to;
    }

    /// The position of the next unread byte.
    pub fn here(&self, dataset: Option<u32>, in_text: bool) -> Position {
        Position {
            dataset,
            offset: self.pos,
            line: in_text.then_some(self.line),
        }
    }

    /// After binary data ending at `self.pos`: finds the line that closes the dataset and
    /// moves past it. Returns the bytes passed over before it (`offset, len`), or `None`
    /// if no closing line follows.
    pub fn close_binary(&mut self) -> Option<(usize, usize)> {
        let (from, b) = (self.pos, self.bytes);
        let mut i = from;
        while i + 1 < b.len() {
            if &b[i..i + 2] == b"-1" {
                let mut end = i + 2;
                while end < b.len() && b[end] == b' ' {
                    end += 1;
                }
                let mut start = i;
                while start > from && i - start < 4 && b[start - 1] == b' ' {
                    start -= 1;
                }
                let line_end = end == b.len() || b[end] == b'\n' || b[end] == b'\r';
                let line_start = start == from || b[start - 1] == b'\n' || b[start - 1] == b'\r';
                if line_end && line_start {
                    self.skip_to(start);
                    self.next_line();
                    return Some((from, start - from));
                }
            }
            i += 1;
        }
        None
    }
}

/// The length of the first line of `rest`: the bytes before the first LF or CR.
fn line_length(rest: &[u8]) -> usize {
    // The lowest zero byte of `v` sets the high bit of its byte, and no lower byte is set.
    let zero_bytes = |v: u64| v.wrapping_sub(ONES) & !v & HIGHS;
    let (lf, cr) = (ONES * u64::from(b'\n'), ONES * u64::from(b'\r'));
    let lowest = |x: u64| zero_bytes(x ^ lf) | zero_bytes(x ^ cr);
    find_byte(rest, 0, lowest, |b| b == b'\n' || b == b'\r')
}

/// The index of the first byte at or after `i` that is a control character or a blank
/// (`<= b' '`), or the length.
fn word_end(bytes: &[u8], i: usize) -> usize {
    // The lowest byte below 0x21 sets the high bit of its byte, and no lower byte is set
    // (bytes from 0x80 never are: they are not blanks either).
    let lowest = |x: u64| x.wrapping_sub(ONES * 0x21) & !x & HIGHS;
    find_byte(bytes, i, lowest, |b| b <= b' ')
}

/// The byte 0x01, and 0x80, in each byte of a `u64`.
const ONES: u64 = u64::from_ne_bytes([0x01; 8]);
const HIGHS: u64 = ONES * 0x80;

/// The index of the first byte at or after `i` that `is` holds for, or the length. Eight
/// bytes at a time, read as a little-endian `u64` `x`: `lowest(x)` sets the high bit of the
/// first such byte, if there is one, and of no byte before it; the rest one at a time.
fn find_byte(
    bytes: &[u8],
    mut i: usize,
    lowest: impl Fn(u64) -> u64,
    is: impl Fn(u8) -> bool,
) -> usize {
    while let Some(chunk) = bytes.get(i..i + 8) {
        let found = lowest(u64::from_le_bytes(chunk.try_into().unwrap_or_default()));
        if found != 0 {
            return i + found.trailing_zeros() as usize / 8;
        }
        i += 8;
    }
    let tail = bytes.get(i..).unwrap_or_default();
    i + tail.iter().position(|&b| is(b)).unwrap_or(tail.len())
}

/// A field of a line: its first column and its text.
pub(crate) type Field<'l> = (usize, &'l str);

/// The blank-separated words of a line, with their columns.
pub(crate) fn words<'l>(line: &'l Line<'_>) -> Vec<Field<'l>> {
    let mut out = Vec::new();
    let mut start = None;
    for (col, (i, c)) in line.text.char_indices().enumerate() {
        match (c.is_whitespace(), start) {
            (false, None) => start = Some((col, i)),
            (true, Some((c0, i0))) => {
                out.push((c0, &line.text[i0..i]));
                start = None;
            }
            _ => {}
        }
    }
    if let Some((c0, i0)) = start {
        out.push((c0, &line.text[i0..]));
    }
    out
}

/// The line cut into fixed columns of the given widths (repeated while the line goes on
/// when `repeat`), trimmed; a field past the end of the line is `""`.
pub(crate) fn columns<'l>(line: &'l Line<'_>, widths: &[usize], repeat: bool) -> Vec<Field<'l>> {
    let n_chars = line.text.chars().count();
    let mut out = Vec::new();
    let mut col = 0;
    for &w in widths.iter().cycle() {
        if (repeat && col >= n_chars) || (!repeat && out.len() == widths.len()) {
            break;
        }
        out.push((col, line.col(col, w).trim()));
        col += w;
    }
    out
}

/// The fields of an all-numeric header line: its words if there are exactly `widths.len()`
/// of them, else the fixed columns of the format (blank fields read as zero, as Fortran does).
pub(crate) fn numeric_fields<'l>(line: &'l Line<'_>, widths: &[usize]) -> Vec<Field<'l>> {
    let w = words(line);
    if w.len() == widths.len() {
        w
    } else {
        columns(line, widths, false)
    }
}

/// A Fortran real: `E`, `D` or no exponent letter (`1.5-100`), NaN and infinities too.
pub(crate) fn parse_real(field: &str) -> Option<f64> {
    parse_word(field.trim())
}

/// [`parse_real`] of a field without surrounding blanks.
#[inline]
fn parse_word(s: &str) -> Option<f64> {
    if s.is_empty() || s.len() > 64 {
        return None;
    }
    s.parse().ok().or_else(|| parse_fortran(s))
}

/// [`parse_word`] of what the standard library does not read: a `D` or no exponent letter.
#[cold]
fn parse_fortran(s: &str) -> Option<f64> {
    let e = s.replace(['D', 'd'], "E");
    if let Ok(v) = e.parse() {
        return Some(v);
    }
    // Fortran drops the letter of three-digit exponents: 0.1234-100.
    let cut = e
        .rfind(['+', '-'])
        .filter(|&i| i > 0 && !e[..i].ends_with(['E', 'e']))?;
    format!("{}E{}", &e[..cut], &e[cut..]).parse().ok()
}

/// The numbers of a data line: its words if all are numbers, else the fixed columns of
/// `widths` (repeated), blank fields skipped. `Err((column, text))` names the first word
/// that is not a number.
pub(crate) fn data_numbers(
    line: &Line<'_>,
    widths: &[usize],
    out: &mut Vec<f64>,
) -> Result<(), (usize, String)> {
    if line_numbers(&line.text, out).is_some() {
        return Ok(());
    }
    let w = words(line);
    let parsed: Vec<Option<f64>> = w.iter().map(|(_, t)| parse_real(t)).collect();
    if parsed.iter().all(Option::is_some) {
        out.extend(parsed.into_iter().flatten());
        return Ok(());
    }
    let fixed: Option<Vec<f64>> = columns(line, widths, true)
        .into_iter()
        .filter(|(_, t)| !t.is_empty())
        .map(|(_, t)| parse_real(t))
        .collect();
    match fixed {
        Some(values) => {
            out.extend(values);
            Ok(())
        }
        None => {
            let bad = parsed.iter().position(Option::is_none).unwrap_or(0);
            Err((w[bad].0, w[bad].1.to_string()))
        }
    }
}

/// The common case of [`data_numbers`], without allocating: the words of `text` up to its
/// first line end (LF or CR), or its end, when they all are numbers. Appends them and
/// returns where they end, the length of the line; otherwise leaves `out` as it was and
/// returns `None`, for the general path to decide. A word holding a character other than
/// ASCII is never a number, so such a line goes to the general path, which splits it as
/// `words` does.
fn line_numbers(text: &str, out: &mut Vec<f64>) -> Option<usize> {
    let start = out.len();
    let end = push_line_numbers(text, out);
    if end.is_none() {
        out.truncate(start);
    }
    end
}

/// [`line_numbers`], leaving the numbers before a word that is not one in `out`.
fn push_line_numbers(text: &str, out: &mut Vec<f64>) -> Option<usize> {
    let bytes = text.as_bytes();
    let mut i = 0;
    loop {
        // The blanks of `char::is_whitespace` in ASCII, which `words` splits on (unlike
        // `u8::is_ascii_whitespace`, they include the vertical tab); other control
        // characters are not blanks, and make the line go to the general path.
        while let Some(&b) = bytes.get(i).filter(|&&b| b <= b' ') {
            match b {
                b'\n' | b'\r' => return Some(i),
                b' ' | b'\t' | b'\x0b' | b'\x0c' => i += 1,
                _ => return None,
            }
        }
        if i == bytes.len() {
            return Some(i);
        }
        let from = i;
        i = word_end(bytes, i);
        out.push(parse_word(&text[from..i])?);
    }
}

/// The fields of a data line holding integers: its words if all are integers, else the
/// non-blank fixed columns of `width`. `Err((column, text))` names the first word that is
/// not an integer.
pub(crate) fn integer_fields<'l>(
    line: &'l Line<'_>,
    width: usize,
) -> Result<Vec<Field<'l>>, (usize, String)> {
    let is_integer = |t: &str| t.parse::<i64>().is_ok();
    let w = words(line);
    if w.iter().all(|(_, t)| is_integer(t)) {
        return Ok(w);
    }
    let fixed: Vec<Field<'l>> = columns(line, &[width], true)
        .into_iter()
        .filter(|(_, t)| !t.is_empty())
        .collect();
    if fixed.iter().all(|(_, t)| is_integer(t)) {
        return Ok(fixed);
    }
    let (column, text) = w
        .into_iter()
        .find(|(_, t)| !is_integer(t))
        .unwrap_or((0, ""));
    Err((column, text.to_string()))
}

/// Reads typed fields of one line, turning failures into [`UffError::Malformed`].
pub(crate) struct FieldReader<'l, 'a> {
    pub line: &'l Line<'a>,
    pub dataset: Option<u32>,
}

impl FieldReader<'_, '_> {
    pub fn malformed(
        &self,
        column: usize,
        field: &'static str,
        found: &str,
        expected: impl Into<String>,
    ) -> UffError {
        UffError::Malformed {
            at: self.line.at(self.dataset, column),
            field,
            found: format!("{found:?}"),
            expected: expected.into(),
        }
    }

    /// An integer field; blank reads as 0, as Fortran does.
    pub fn int<T: TryFrom<i64>>(
        &self,
        (column, text): Field<'_>,
        field: &'static str,
    ) -> Result<T, UffError> {
        if text.is_empty() {
            return T::try_from(0).map_err(|_| self.malformed(column, field, text, "an integer"));
        }
        text.parse::<i64>()
            .ok()
            .and_then(|v| T::try_from(v).ok())
            .ok_or_else(|| self.malformed(column, field, text, "an integer"))
    }

    /// A real field; blank reads as 0, as Fortran does.
    pub fn real(&self, (column, text): Field<'_>, field: &'static str) -> Result<f64, UffError> {
        if text.is_empty() {
            return Ok(0.0);
        }
        parse_real(text).ok_or_else(|| self.malformed(column, field, text, "a number"))
    }
}

/// `v` in scientific notation with a signed two-digit (or three-digit) exponent, `E`
/// written as `letter`: the shortest text that reads back as `v` if it fits `width - 1`
/// characters (one blank keeps fields apart), else the most digits that fit. Right-aligned
/// in `width` columns.
pub(crate) fn format_real(v: f64, width: usize, letter: char) -> String {
    let text = if v.is_nan() {
        "NaN".to_string()
    } else if v.is_infinite() {
        if v > 0.0 { "Inf" } else { "-Inf" }.to_string()
    } else {
        let shortest = fortran_exponent(&format!("{v:E}"), letter);
        if shortest.len() < width {
            shortest
        } else {
            (0..=16)
                .rev()
                .map(|digits| fortran_exponent(&format!("{v:.digits$E}"), letter))
                .find(|t| t.len() < width)
                .map_or(shortest, |t| without_trailing_zeros(&t))
        }
    };
    format!("{text:>width$}")
}

/// `5.100080E-05` as `5.10008E-05` (the same number), so that writing a number read from a
/// file gives the same text again.
fn without_trailing_zeros(text: &str) -> String {
    match text.split_once(['E', 'D']) {
        Some((mantissa, _)) if mantissa.contains('.') => {
            let kept = mantissa.trim_end_matches('0');
            let kept = if kept.ends_with('.') {
                &mantissa[..kept.len() + 1]
            } else {
                kept
            };
            format!("{kept}{}", &text[mantissa.len()..])
        }
        _ => text.to_string(),
    }
}

/// Rust's `1.5E-7` as `1.5E-07`, with a decimal point in the mantissa (`1E0` → `1.0E+00`).
fn fortran_exponent(rust: &str, letter: char) -> String {
    let (mantissa, exponent) = rust.split_once('E').unwrap_or((rust, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    let point = if mantissa.contains('.') { "" } else { ".0" };
    let sign = if exponent < 0 { '-' } else { '+' };
    format!(
        "{mantissa}{point}{letter}{sign}{:02}",
        exponent.unsigned_abs()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fortran_reals_parse() {
        for (text, v) in [
            ("1.0", 1.0),
            (" 2.50000e-03 ", 0.0025),
            ("1.0000000000000000D+00", 1.0),
            ("-0.12345-100", -0.12345e-100),
            ("0.5+003", 500.0),
            ("NaN", f64::NAN),
            ("-Inf", f64::NEG_INFINITY),
        ] {
            let got = parse_real(text).unwrap();
            assert!(got == v || (got.is_nan() && v.is_nan()), "{text}: {got}");
        }
        for bad in ["", "abc", "1.0E", "--1", "1.2.3", "+"] {
            assert_eq!(parse_real(bad), None, "{bad}");
        }
    }

    #[test]
    fn reals_take_the_most_digits_that_fit() {
        assert_eq!(format_real(0.0025, 13, 'E'), "      2.5E-03");
        assert_eq!(format_real(1.0, 13, 'E'), "      1.0E+00");
        assert_eq!(format_real(-0.0, 13, 'E'), "     -0.0E+00");
        assert_eq!(format_real(1.0 / 3.0, 13, 'E'), " 3.333333E-01");
        assert_eq!(format_real(-1.0 / 3.0, 13, 'E'), " -3.33333E-01");
        assert_eq!(format_real(1.0 / 3.0, 20, 'E'), " 3.3333333333333E-01");
        assert_eq!(format_real(-1.0 / 3.0, 20, 'E'), " -3.333333333333E-01");
        assert_eq!(format_real(1e-300 / 3.0, 20, 'E'), " 3.333333333333E-301");
        assert_eq!(format_real(1.0 / 3.0, 25, 'D'), "    3.333333333333333D-01");
        assert_eq!(format_real(f64::NAN, 13, 'E'), "          NaN");
        assert_eq!(format_real(5.100079999e-5, 13, 'E'), "  5.10008E-05");
        assert_eq!(format_real(0.99999999, 13, 'E'), "      1.0E+00");
        for v in [
            1.0 / 3.0,
            -2.0f64.sqrt(),
            5e-324,
            f64::MAX,
            -f64::MIN_POSITIVE,
        ] {
            assert_eq!(parse_real(&format_real(v, 25, 'E')), Some(v));
        }
    }
}
