//! Malformed datasets 55, 15 and 2411 are refused with the dataset, byte and line, what
//! was found and what was expected: the exact text of each error.

use msd_uff::{Position, UffError};

use crate::errors::{edited, locate, refuse};
use crate::fixture_bytes;

const MODES: &str = "pyuff/modes_real.uff";

/// Byte offset and line of `needle`'s first character after `skip` leading characters.
fn at(bytes: &[u8], needle: &str, skip: usize) -> (usize, usize) {
    let (offset, line) = locate(bytes, needle);
    let lines_before = needle[..skip].matches('\n').count();
    (offset + skip, line + lines_before)
}

#[test]
fn a_dataset_55_cut_in_its_node_values_says_how_many_it_got() {
    let bytes = fixture_bytes(MODES);
    let (cut, line) = at(&bytes, "\n         3\n  0.0", 12);
    let err = refuse(&bytes[..cut]);
    assert!(matches!(
        err,
        UffError::Truncated { at: Position { dataset: Some(55), line: Some(l), .. }, .. } if l == line
    ));
    assert_eq!(
        err.to_string(),
        format!(
            "dataset 55, byte {cut}, line {line}: the file ends in record 10 (data at a node): found the end \
             of the file after 0 numbers, expected 3 numbers for node 3: 3 real values and the closing \"    -1\""
        )
    );
    let (cut, line) = at(&bytes, "  2.84705e+01", 0);
    assert_eq!(
        refuse(&bytes[..cut]).to_string(),
        format!(
            "dataset 55, byte {cut}, line {line}: the file ends in record 8 (real parameters): found the end \
             of the file after 0 numbers, expected 4 numbers as record 7 says and the closing \"    -1\""
        )
    );
    let (cut, line) = at(&bytes, "msd-uff fixture: normal modes", 0);
    assert_eq!(
        refuse(&bytes[..cut]).to_string(),
        format!(
            "dataset 55, byte {cut}, line {line}: the file ends in record 1 (ID line 1): found the end of the \
             file, expected record 1 (ID line 1)"
        )
    );
}

#[test]
fn a_node_with_values_missing_is_refused_where_its_count_goes_wrong() {
    // Node 2's values removed: node 3's number is read as node 2's first value.
    let bytes = edited(MODES, "  0.00000e+00 -1.58114e-02  6.32456e-01\n", "");
    let (offset, line) = at(&bytes, "\n  0.00000e+00 -3.09879e-02", 1);
    assert_eq!(
        refuse(&bytes).to_string(),
        format!(
            "dataset 55, byte {offset}, line {line}: record 10 (data at a node): found 4 numbers by this line, \
             expected 3 numbers for node 2: 3 real values"
        )
    );
    // The closing line where a node's values should be.
    let bytes = edited(MODES, "  0.00000e+00 -4.47214e-02  8.94427e-01\n", "");
    let (offset, line) = at(&bytes, "\n         4\n    -1", 12);
    assert_eq!(
        refuse(&bytes).to_string(),
        format!(
            "dataset 55, byte {offset}, line {line}: record 10 (data at a node): found the closing \"    -1\" \
             after 0 numbers, expected 3 numbers for node 4: 3 real values"
        )
    );
}

#[test]
fn a_node_line_that_is_not_a_node_number_is_quoted() {
    let bytes = edited(MODES, "\n         3\n", "\n        3x\n");
    let (offset, line) = at(&bytes, "\n        3x\n", 9);
    let err = refuse(&bytes);
    assert!(matches!(
        &err,
        UffError::Malformed {
            field: "record 9, node number",
            ..
        }
    ));
    assert_eq!(
        err.to_string(),
        format!(
            "dataset 55, byte {offset}, line {line}: record 9, node number: found \"3x\", expected a node \
             number (an integer, Format I10)"
        )
    );
    let bytes = edited(MODES, "\n         3\n", "\n         3         4\n");
    let (offset, line) = at(&bytes, "\n         3         4\n", 10);
    assert_eq!(
        refuse(&bytes).to_string(),
        format!(
            "dataset 55, byte {offset}, line {line}: record 9, node number: found \"3         4\", expected a \
             node number alone on its line (Format I10), its values on the next lines"
        )
    );
}

#[test]
fn record_6_to_10_fields_out_of_range_are_named() {
    let cases = [
        (
            "         2         8         2         3\n",
            "         2         8         7         3\n",
            "record 6, data type",
            "\"7\"",
            "2 (real) or 5 (complex)",
        ),
        (
            "         2         8         2         3\n",
            "         2         8         2        -3\n",
            "record 6, number of data values per node",
            "\"-3\"",
            "a count (an integer >= 0)",
        ),
        (
            "         2         4         1         1\n",
            "        12         4         1         1\n",
            "record 7, number of integer parameters",
            "\"12\"",
            "0 to 10",
        ),
        (
            "         2         4         1         1\n",
            "         2        13         1         1\n",
            "record 7, number of real parameters",
            "\"13\"",
            "0 to 12",
        ),
        (
            "         2         4         1         1\n",
            "         2         4         1       1.5\n",
            "record 7, integer parameter",
            "\"1.5\"",
            "an integer",
        ),
        (
            "7.82624e-03",
            "7.82624e-0x",
            "record 8, real parameter",
            "\"7.82624e-0x\"",
            "a number",
        ),
        (
            "3.42282e-01",
            "3.42282e-0l",
            "record 10, data value",
            "\"3.42282e-0l\"",
            "a number",
        ),
    ];
    for (from, to, field, found, expected) in cases {
        let bytes = edited(MODES, from, to);
        match refuse(&bytes) {
            UffError::Malformed {
                at,
                field: f,
                found: fd,
                expected: e,
            } => {
                assert_eq!((f, fd.as_str(), e.as_str()), (field, found, expected));
                assert_eq!(at.dataset, Some(55));
                let bare = found.trim_matches('"');
                let text = String::from_utf8_lossy(&bytes[at.offset..]);
                assert!(text.starts_with(bare), "{field}: at {:?}", &text[..20]);
                let line = 1 + bytes[..at.offset].iter().filter(|&&b| b == b'\n').count();
                assert_eq!(at.line, Some(line), "{field}");
            }
            other => panic!("{field}: {other}"),
        }
    }
}

#[test]
fn bad_nodes_are_refused_with_their_dataset_and_line() {
    let bytes = edited("pyuff/geometry_15.uff", "1.23457E+02", "1.23457E+0x");
    let (offset, line) = locate(&bytes, "1.23457E+0x");
    assert_eq!(
        refuse(&bytes).to_string(),
        format!(
            "dataset 15, byte {offset}, line {line}: record 1, z coordinate: found \"1.23457E+0x\", expected a number"
        )
    );
    let bytes = edited(
        "pyuff/geometry_15.uff",
        "         3         0",
        "         3       0.5",
    );
    let (offset, line) = locate(&bytes, "0.5");
    assert_eq!(
        refuse(&bytes).to_string(),
        format!(
            "dataset 15, byte {offset}, line {line}: record 1, definition coordinate system number: found \"0.5\", \
             expected an integer"
        )
    );
    let bytes = fixture_bytes("pyuff/geometry_15.uff");
    let cut = bytes.len() - "    -1\n".len();
    let line = 1 + bytes[..cut].iter().filter(|&&b| b == b'\n').count();
    assert_eq!(
        refuse(&bytes[..cut]).to_string(),
        format!(
            "dataset 15, byte {cut}, line {line}: the file ends in record 1 (node): found the end of the file, \
             expected a node, or \"    -1\", the line that closes a dataset"
        )
    );
    let bytes = fixture_bytes("pyuff/geometry_2411.uff");
    let (cut, line) = at(&bytes, "        11\n", 11);
    assert_eq!(
        refuse(&bytes[..cut]).to_string(),
        format!(
            "dataset 2411, byte {cut}, line {line}: the file ends in record 2 (node coordinates): found the end \
             of the file, expected record 2 (node coordinates)"
        )
    );
    let bytes = edited(
        "pyuff/geometry_2411.uff",
        "-1.2500000000000000e-01",
        "-1.2500000000000000e-0?",
    );
    let (offset, line) = locate(&bytes, "-1.2500000000000000e-0?");
    assert_eq!(
        refuse(&bytes).to_string(),
        format!(
            "dataset 2411, byte {offset}, line {line}: record 2, y coordinate: found \"-1.2500000000000000e-0?\", \
             expected a number"
        )
    );
}

#[test]
fn a_binary_dataset_55_is_passed_over_by_its_byte_count() {
    let text = "    -1\n    55b     1     2           2          16\nNONE\nNONE\n-1-1-1-1-1-1-1-1\n    -1\n";
    let file = msd_uff::parse(text.as_bytes()).expect("skipped");
    assert!(file.data_at_nodes.is_empty());
    assert_eq!((file.skipped[0].number, file.skipped[0].binary), (55, true));
}
