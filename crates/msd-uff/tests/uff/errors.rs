//! Malformed files are refused with where (byte, line, dataset), what was found and what
//! was expected: the exact text of each error.

use msd_uff::{Position, UffError};

use crate::fixture_bytes;

pub(crate) fn refuse(bytes: &[u8]) -> UffError {
    msd_uff::parse(bytes).expect_err("a malformed file")
}

/// The file with its first `from` replaced by `to`.
pub(crate) fn edited(name: &str, from: &str, to: &str) -> Vec<u8> {
    let mut bytes = fixture_bytes(name);
    let at = bytes.windows(from.len()).position(|w| w == from.as_bytes());
    let at = at.unwrap_or_else(|| panic!("{name} has no {from:?}"));
    bytes.splice(at..at + from.len(), to.bytes());
    bytes
}

/// Byte offset and line number of the first `needle` in a fixture.
pub(crate) fn locate(bytes: &[u8], needle: &str) -> (usize, usize) {
    let at = bytes
        .windows(needle.len())
        .position(|w| w == needle.as_bytes())
        .expect("found");
    (at, 1 + bytes[..at].iter().filter(|&&b| b == b'\n').count())
}

#[test]
fn a_truncated_ascii_file_says_how_many_values_it_got() {
    let bytes = fixture_bytes("pyuff/ascii_frf_complex.uff");
    let (cut, line) = locate(&bytes, "   4.93331662748e-05");
    let err = refuse(&bytes[..cut]);
    assert!(
        matches!(err, UffError::Truncated { at: Position { dataset: Some(58), line: Some(l), .. }, .. } if l == line)
    );
    assert_eq!(
        err.to_string(),
        format!(
            "dataset 58, byte {cut}, line {line}: the file ends in record 12 (data values): found the end of the \
            file after 20 values, expected 64 values (re, im per point) and the closing \"    -1\""
        )
    );
}

#[test]
fn a_record_with_missing_values_is_refused_at_the_closing_line() {
    let line = "   6.24873166292e-04  -2.93457485801e-04  -2.21638876478e-04  -3.31329075694e-05\n";
    let bytes = edited("pyuff/ascii_frf_complex.uff", line, "");
    let at = bytes.len() - "    -1\n".len(); // the closing line
    let line = bytes[..at].iter().filter(|&&b| b == b'\n').count() + 1;
    assert_eq!(
        refuse(&bytes).to_string(),
        format!(
            "dataset 58, byte {at}, line {line}: record 12 (data values): found 60 values, expected 64 values (re, im per point)"
        )
    );
}

#[test]
fn a_record_with_extra_values_is_refused_at_the_line_that_overflows() {
    let bytes = fixture_bytes("pyuff/ascii_real_even.uff");
    let text = String::from_utf8(bytes).expect("ASCII");
    let last = text
        .lines()
        .rev()
        .nth(1)
        .expect("the last data line")
        .to_string();
    let longer = text
        .replacen(&format!("{last}\n"), &format!("{last}\n{last}\n"), 1)
        .into_bytes();
    let (at, line) = locate(&longer, &last);
    let (at, line) = (at + last.len() + 1, line + 1);
    let err = refuse(&longer);
    assert_eq!(
        err.to_string(),
        format!(
            "dataset 58, byte {at}, line {line}: record 12 (data values): found more than 40 values by this line, \
            expected 40 values (one real value per point)"
        )
    );
}

#[test]
fn a_bad_number_is_quoted_with_its_column() {
    let bytes = edited(
        "pyuff/ascii_uneven.uff",
        "9.93174061433e-01",
        "9.93174O61433e-01",
    );
    let (at, line) = locate(&bytes, "9.93174O61433e-01");
    let err = refuse(&bytes);
    assert!(matches!(
        &err,
        UffError::Malformed {
            field: "record 12, data value",
            ..
        }
    ));
    assert_eq!(
        err.to_string(),
        format!(
            "dataset 58, byte {at}, line {line}: record 12, data value: found \"9.93174O61433e-01\", expected a number"
        )
    );
}

#[test]
fn header_fields_out_of_range_are_named() {
    let cases = [
        (
            "         6        32         1",
            "         3        32         1",
            "record 7, ordinate data type",
            "\"3\"",
            "2, 4, 5 or 6 (real or complex, single or double precision)",
        ),
        (
            "         6        32         1",
            "         6       -32         1",
            "record 7, number of points",
            "\"-32\"",
            "a count (an integer >= 0)",
        ),
        (
            "         6        32         1",
            "         6        32         2",
            "record 7, abscissa spacing",
            "\"2\"",
            "0 (uneven) or 1 (even)",
        ),
        (
            "  0.00000e+00  2.00000e+00",
            "  0.00000e+00  2.0000x+00",
            "record 7, abscissa increment",
            "\"2.0000x+00\"",
            "a number",
        ),
        (
            "plate         3   3",
            "plate        3x   3",
            "record 6, response node",
            "\"3x\"",
            "an integer",
        ),
        (
            "        18    0",
            "        1x    0",
            "records 8-11, specific data type",
            "\"1x\"",
            "an integer",
        ),
    ];
    for (from, to, field, found, expected) in cases {
        let bytes = edited("pyuff/ascii_frf_complex.uff", from, to);
        match refuse(&bytes) {
            UffError::Malformed {
                at,
                field: f,
                found: fd,
                expected: e,
            } => {
                assert_eq!((f, fd.as_str(), e.as_str()), (field, found, expected));
                assert_eq!(at.dataset, Some(58));
                let text = String::from_utf8_lossy(&bytes[at.offset..]);
                let bare = found.trim_matches('"');
                assert!(
                    text.starts_with(bare) || text.trim_start().starts_with(bare),
                    "{field}: offset {} at {:?}",
                    at.offset,
                    &text[..20]
                );
            }
            other => panic!("{field}: {other}"),
        }
    }
}

#[test]
fn a_file_that_does_not_start_with_a_dataset_is_refused_at_byte_0() {
    assert_eq!(
        refuse(b"Time,Force\n0.0,1.0\n").to_string(),
        "byte 0, line 1: dataset start: found \"Time,Force\", expected \"    -1\", the line that opens a dataset"
    );
    assert_eq!(
        refuse(b"    -1\n  5x\n").to_string(),
        "byte 7, line 2: dataset number: found \"  5x\", expected a dataset number in columns 1-6 (e.g. \"    58\")"
    );
    assert_eq!(
        refuse(b"    -1\n").to_string(),
        "byte 7, line 2: the file ends in the dataset number line: found the end of the file, \
         expected a dataset number after \"    -1\""
    );
}

#[test]
fn binary_data_cut_short_is_refused_with_its_byte_counts() {
    let bytes = fixture_bytes("pyuff/binary_single.uff");
    // The data starts after 13 lines: -1, the 58b line, records 1-11.
    let data = bytes
        .iter()
        .enumerate()
        .filter(|(_, b)| **b == b'\n')
        .nth(12)
        .expect("13 lines")
        .0
        + 1;
    let err = refuse(&bytes[..data + 100]);
    assert!(matches!(
        err,
        UffError::Truncated {
            at: Position { line: None, .. },
            ..
        }
    ));
    assert_eq!(
        err.to_string(),
        format!(
            "dataset 58, byte {data}: the file ends in record 12 (binary data): found 100 bytes before the end \
            of the file, expected 128 bytes: 32 values (re, im per point) of 4 bytes"
        )
    );
    let no_close = &bytes[..data + 128];
    assert_eq!(
        refuse(no_close).to_string(),
        format!(
            "dataset 58, byte {}: the file ends in the end of the dataset: found no \"    -1\" line after the \
            binary data, expected \"    -1\", the line that closes a dataset",
            data + 128
        )
    );
}

#[test]
fn binary_formats_this_crate_cannot_decode_are_named() {
    let cases = [
        (
            "58b     1     2",
            "58b     3     2",
            "binary id line, byte ordering",
            "3",
            "1 (little endian) or 2 (big endian)",
        ),
        (
            "58b     1     2",
            "58b     1     3",
            "binary id line, floating-point format",
            "3",
            "2 (IEEE 754); 1 (DEC VMS) and 3 (IBM 5/370) are not read",
        ),
        (
            "58b     1     2          11",
            "58b     1     2          12",
            "binary id line, number of ASCII lines",
            "12",
            "11, as for every dataset 58b",
        ),
    ];
    for (from, to, field, found, expected) in cases {
        let mut bytes = fixture_bytes("pyuff/binary_single.uff");
        bytes.splice(11..11 + from.len(), to.bytes()); // "    -1\n    58b…"
        let err = refuse(&bytes);
        assert_eq!(
            err.to_string(),
            format!(
                "dataset 58, byte {}, line 2: {field}: found {found}, expected {expected}",
                match field {
                    f if f.ends_with("ordering") => 14,
                    f if f.ends_with("format") => 20,
                    _ => 26,
                }
            )
        );
    }
}

#[test]
fn a_dataset_cut_before_its_records_end_names_the_record() {
    let bytes = fixture_bytes("pyuff/mixed.uff");
    let (cut, line) = locate(&bytes, "pyuff 2.5.8");
    assert_eq!(
        refuse(&bytes[..cut]).to_string(),
        format!(
            "dataset 151, byte {cut}, line {line}: the file ends in record 6 (program which wrote the file): found \
            the end of the file, expected record 6 (program which wrote the file)"
        )
    );
    let units = edited("pyuff/mixed.uff", "   2.7314999999999998D+02\n", "");
    let (at, line) = locate(&units, "    -1\n    -1\n    15");
    assert_eq!(
        refuse(&units).to_string(),
        format!(
            "dataset 164, byte {at}, line {line}: the file ends in record 2 (unit factors): found the closing \
            \"    -1\", expected record 2 (unit factors) first"
        )
    );
}
