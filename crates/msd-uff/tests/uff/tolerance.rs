//! What real files do that the description does not: Fortran number forms, numbers that
//! touch in their columns, binary datasets of other kinds, blank lines between datasets.

use msd_uff::{Abscissa, Ordinate, Precision};

/// A dataset 58 with the given record 7 and data lines.
fn dataset58(record7: &str, data: &[&str]) -> String {
    let mut lines = vec![
        "    -1",
        "    58",
        "written by hand",
        "NONE",
        "NONE",
        "NONE",
        "NONE",
        "    1         0    0         0       NONE         5  -3       NONE         0   0",
        record7,
        "        17    0    0    0 Time                 s",
        "         8    0    0    0 Displacement         m",
        "         0    0    0    0 NONE                 NONE",
        "         0    0    0    0 NONE                 NONE",
    ];
    lines.extend(data);
    lines.push("    -1");
    lines.join("\n") + "\n"
}

#[test]
fn numbers_that_touch_in_their_columns_are_read_by_column() {
    // 1PE13.6-style fields leave no blank before a minus sign; D exponents and Fortran's
    // letterless three-digit exponents come from other writers.
    let fields = [
        "-1.234567E+00",
        "-2.345678E-01",
        "3.000000E+00",
        "4.0D+00",
        "5.0D-01",
        "-1.5-100",
    ];
    let first: String = fields.iter().map(|f| format!("{f:>13}")).collect();
    let text = dataset58(
        "         2         7         1-2.500000E-01 1.000000E-03  0.00000E+00",
        &[&first, " 7.000000E+00"],
    );
    let file = msd_uff::parse(text.as_bytes()).expect("read");
    let f = &file.functions[0];
    assert_eq!(f.precision, Precision::Single);
    assert_eq!(
        f.abscissa,
        Abscissa::Even {
            start: -0.25,
            step: 1e-3
        }
    );
    assert_eq!(
        f.ordinate,
        Ordinate::Real(vec![-1.234567, -0.2345678, 3.0, 4.0, 0.5, -1.5e-100, 7.0])
    );
    assert_eq!((f.response_node, f.response_direction), (5, -3));
}

#[test]
fn a_binary_dataset_of_another_kind_is_skipped_by_its_byte_count() {
    // Its data holds a line that reads "    -1": only the byte count finds the real end.
    let mut bytes =
        b"\n    -1\n  2414b     1     2           1          16\nan ASCII line\n".to_vec();
    bytes.extend(b"12\n    -1\n34567"); // 16 bytes of "binary" data
    bytes.extend(b"    -1\n\n\n");
    let header =
        "    -1\n   151\nmodel\ndescription\nprogram\n01-Jan-26 10:00:00\n\nprogram\n\n    -1\n";
    bytes.extend(header.as_bytes());
    let file = msd_uff::parse(&bytes).expect("read");
    let skipped: Vec<_> = file
        .skipped
        .iter()
        .map(|s| (s.number, s.offset, s.line, s.binary))
        .collect();
    assert_eq!(skipped, [(2414, 1, 2, true)]);
    let h = file.header.expect("the header after it");
    assert_eq!(
        (
            h.model_name.as_str(),
            h.db_created_time.as_str(),
            h.written_date.as_str()
        ),
        ("model", "10:00:00", "")
    );
}

#[test]
fn a_second_header_is_skipped_with_a_note() {
    let header = "    -1\n   151\nfirst\n\n\n\n\n\n\n    -1\n";
    let second = header.replace("first", "second");
    let file = msd_uff::parse(format!("{header}{second}").as_bytes()).expect("read");
    assert_eq!(file.header.map(|h| h.model_name), Some("first".to_string()));
    assert_eq!(file.skipped[0].note, "a second one: the first is kept");
    assert_eq!(
        (
            file.skipped[0].number,
            file.skipped[0].offset,
            file.skipped[0].line
        ),
        (151, header.len(), 11)
    );
}
