//! Every pyuff fixture read to the last digit: each value compared, bit for bit, with what
//! pyuff 2.5.8 reads from the same file (the JSON beside it, see `make_fixtures.py`); the
//! nodes and data at nodes are compared in `fixtures_nodes.rs`.

use msd_uff::{
    Abscissa, ByteOrder, Encoding, Function58, FunctionType, Ordinate, Precision, UffFile,
};
use serde_json::Value;

use crate::fixtures_nodes::{check_data55, check_nodes};
use crate::{PYUFF_FIXTURES, fixture, fixture_bytes};

/// A float the script wrote as Python's `repr`: parses to the same double.
pub(crate) fn real(v: &Value) -> f64 {
    v.as_str()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("not a repr float: {v}"))
}

pub(crate) fn int(v: &Value) -> i64 {
    v.as_i64().unwrap_or_else(|| panic!("not an integer: {v}"))
}

pub(crate) fn text(v: &Value) -> &str {
    v.as_str().unwrap_or_else(|| panic!("not a string: {v}"))
}

pub(crate) fn reals(v: &Value) -> Vec<f64> {
    v.as_array().expect("a list").iter().map(real).collect()
}

/// Bit equality, so that NaN and -0.0 count too.
pub(crate) fn same_bits(ours: &[f64], pyuff: &[f64], what: &str) {
    assert_eq!(ours.len(), pyuff.len(), "{what}: lengths");
    for (k, (a, b)) in ours.iter().zip(pyuff).enumerate() {
        assert_eq!(
            a.to_bits(),
            b.to_bits(),
            "{what}[{k}]: ours {a:e}, pyuff {b:e}"
        );
    }
}

fn check_function(f: &Function58, d: &Value, what: &str) {
    let ids: Vec<&str> = ["id1", "id2", "id3", "id4", "id5"]
        .iter()
        .map(|k| text(&d[k]))
        .collect();
    assert_eq!(
        f.ids.iter().map(String::as_str).collect::<Vec<_>>(),
        ids,
        "{what}"
    );
    assert_eq!(
        f.function_type,
        FunctionType::from_code(int(&d["func_type"]) as i32),
        "{what}"
    );
    let dof = (
        f.response_node,
        f.response_direction as i64,
        f.reference_node,
        f.reference_direction as i64,
    );
    assert_eq!(
        dof,
        (
            int(&d["rsp_node"]),
            int(&d["rsp_dir"]),
            int(&d["ref_node"]),
            int(&d["ref_dir"])
        ),
        "{what}"
    );
    assert_eq!(
        (f.function_id, f.version, f.load_case),
        (
            int(&d["func_id"]),
            int(&d["ver_num"]),
            int(&d["load_case_id"])
        )
    );
    assert_eq!(
        (f.response_entity.as_str(), f.reference_entity.as_str()),
        (text(&d["rsp_ent_name"]), text(&d["ref_ent_name"]))
    );
    let (complex, precision) = match int(&d["ord_data_type"]) {
        2 => (false, Precision::Single),
        4 => (false, Precision::Double),
        5 => (true, Precision::Single),
        6 => (true, Precision::Double),
        t => panic!("{what}: ordinate data type {t}"),
    };
    assert_eq!(f.precision, precision, "{what}");
    assert_eq!(f.len() as i64, int(&d["num_pts"]), "{what}");
    match (&f.abscissa, int(&d["abscissa_spacing"])) {
        (Abscissa::Even { start, step }, 1) => {
            same_bits(
                &[*start, *step],
                &[real(&d["abscissa_min"]), real(&d["abscissa_inc"])],
                what,
            );
        }
        (Abscissa::Uneven(_), 0) => {}
        (a, s) => panic!("{what}: abscissa {a:?}, spacing {s}"),
    }
    assert_eq!(f.z_axis_value, real(&d["z_axis_value"]), "{what}");
    let axes = [
        &f.abscissa_axis,
        &f.ordinate_axis,
        &f.denominator_axis,
        &f.z_axis,
    ];
    for (axis, key) in axes
        .iter()
        .zip(["abscissa", "ordinate", "orddenom", "z_axis"])
    {
        assert_eq!(
            axis.data_type as i64,
            int(&d[format!("{key}_spec_data_type")]),
            "{what} {key}"
        );
        assert_eq!(
            axis.label,
            text(&d[format!("{key}_axis_lab")]),
            "{what} {key}"
        );
        assert_eq!(
            axis.units,
            text(&d[format!("{key}_axis_units_lab")]),
            "{what} {key}"
        );
    }
    assert_eq!(
        f.abscissa_axis.length_exponent as i64,
        int(&d["abscissa_len_unit_exp"])
    );
    assert_eq!(
        f.ordinate_axis.force_exponent as i64,
        int(&d["ordinate_force_unit_exp"])
    );
    let encoding = match (int(&d["binary"]), d.get("byte_ordering").map(int)) {
        (0, _) => Encoding::Ascii,
        (1, Some(1)) => Encoding::Binary(ByteOrder::Little),
        (1, Some(2)) => Encoding::Binary(ByteOrder::Big),
        other => panic!("{what}: binary {other:?}"),
    };
    assert_eq!(f.encoding, encoding, "{what}");

    same_bits(&f.abscissa_values(), &reals(&d["x"]), &format!("{what} x"));
    match (&f.ordinate, complex) {
        (Ordinate::Real(y), false) => {
            same_bits(y, &reals(&d["re"]), &format!("{what} re"));
            assert!(d["im"].is_null());
        }
        (Ordinate::Complex(y), true) => {
            let (re, im): (Vec<f64>, Vec<f64>) = y.iter().copied().unzip();
            same_bits(&re, &reals(&d["re"]), &format!("{what} re"));
            same_bits(&im, &reals(&d["im"]), &format!("{what} im"));
        }
        (y, c) => panic!("{what}: ordinate {y:?}, complex {c}"),
    }
}

pub(crate) fn check_file(name: &str) -> UffFile {
    let file = msd_uff::read(fixture(&format!("pyuff/{name}.uff")))
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let doc: Value =
        serde_json::from_slice(&fixture_bytes(&format!("pyuff/{name}.json"))).expect("JSON");
    let (mut functions, mut skipped) = (file.functions.iter(), file.skipped.iter());
    let (mut nodes, mut data_at_nodes) = (file.nodes.iter(), file.data_at_nodes.iter());
    for (i, d) in doc["datasets"]
        .as_array()
        .expect("datasets")
        .iter()
        .enumerate()
    {
        let what = format!("{name} dataset {i}");
        match int(&d["type"]) {
            58 => check_function(functions.next().expect("a function"), d, &what),
            55 => check_data55(data_at_nodes.next().expect("a dataset 55"), d, &what),
            n @ (15 | 2411) => {
                let count = d["node_nums"].as_array().expect("node_nums").len();
                let these: Vec<_> = nodes.by_ref().take(count).cloned().collect();
                check_nodes(&these, n, d, &what);
            }
            151 => {
                let h = file.header.as_ref().expect("a header");
                let got = [
                    &h.model_name,
                    &h.description,
                    &h.db_program,
                    &h.db_created_date,
                    &h.db_created_time,
                    &h.db_saved_date,
                    &h.db_saved_time,
                    &h.program,
                    &h.written_date,
                    &h.written_time,
                ];
                let keys = [
                    "model_name",
                    "description",
                    "db_app",
                    "date_db_created",
                    "time_db_created",
                    "date_db_saved",
                    "time_db_saved",
                    "program",
                    "date_file_written",
                    "time_file_written",
                ];
                for (g, k) in got.iter().zip(keys) {
                    assert_eq!(g.as_str(), text(&d[k]), "{what} {k}");
                }
                let versions = [h.db_version1, h.db_version2, h.file_type].map(|v| v.to_string());
                assert_eq!(
                    versions,
                    ["version_db1", "version_db2", "file_type"].map(|k| text(&d[k]).to_string())
                );
            }
            164 => {
                let u = file.units.as_ref().expect("units");
                assert_eq!(
                    (
                        u.code as i64,
                        u.description.as_str(),
                        u.temperature_mode as i64
                    ),
                    (
                        int(&d["units_code"]),
                        text(&d["units_description"]),
                        int(&d["temp_mode"])
                    )
                );
                same_bits(
                    &[u.length, u.force, u.temperature, u.temperature_offset],
                    &[
                        real(&d["length"]),
                        real(&d["force"]),
                        real(&d["temp"]),
                        real(&d["temp_offset"]),
                    ],
                    &what,
                );
            }
            n => {
                let s = skipped.next().expect("a skipped dataset");
                assert_eq!(
                    (s.number as i64, s.offset as i64),
                    (n, int(&d["offset"])),
                    "{what}"
                );
            }
        }
    }
    assert!(
        functions.next().is_none()
            && skipped.next().is_none()
            && nodes.next().is_none()
            && data_at_nodes.next().is_none(),
        "{name}: more datasets than pyuff read"
    );
    file
}

#[test]
fn every_pyuff_fixture_reads_as_pyuff_reads_it() {
    for name in PYUFF_FIXTURES {
        check_file(name);
    }
}

#[test]
fn the_mixed_file_reads_the_geometry_and_skips_trace_lines_with_their_offset() {
    let file = check_file("mixed");
    let skipped: Vec<(u32, usize, usize, bool)> = file
        .skipped
        .iter()
        .map(|s| (s.number, s.offset, s.line, s.binary))
        .collect();
    assert_eq!(skipped, [(82, 2177, 40, false)]);
    let labels: Vec<i64> = file.nodes.iter().map(|n| n.label).collect();
    assert_eq!(labels, [1, 2, 3]);
    assert_eq!((file.nodes[2].x, file.nodes[2].z), (2.0, 0.5));
    assert_eq!(
        file.header.as_ref().map(|h| h.program.as_str()),
        Some("pyuff 2.5.8")
    );
    assert_eq!(
        file.units.as_ref().map(|u| u.temperature_offset),
        Some(273.15)
    );
    assert_eq!(
        file.functions[1].encoding,
        Encoding::Binary(ByteOrder::Little)
    );
    assert!(file.trailing.is_empty());
}

#[test]
fn bytes_after_binary_data_are_passed_over_and_noted() {
    let file = check_file("binary_trailing");
    let doc: Value =
        serde_json::from_slice(&fixture_bytes("pyuff/binary_trailing.json")).expect("JSON");
    let t = &file.trailing;
    assert_eq!(t.len(), 1);
    assert_eq!(
        (t[0].function, t[0].offset as i64, t[0].len as i64),
        (
            0,
            int(&doc["trailing"]["offset"]),
            int(&doc["trailing"]["len"])
        )
    );
}

#[test]
fn pyuff_s_byte_count_for_complex_binary_data_is_not_trusted() {
    // pyuff writes num_pts * 8 in the 58b line, half the bytes of 32 complex doubles.
    let bytes = fixture_bytes("pyuff/binary_double.uff");
    let second_line = bytes.split(|&b| b == b'\n').nth(1).expect("the 58b line");
    assert_eq!(
        String::from_utf8_lossy(second_line)
            .split_whitespace()
            .nth(4),
        Some("256")
    );
    let file = check_file("binary_double");
    assert_eq!(file.functions[0].len(), 32);
    assert!(matches!(file.functions[0].ordinate, Ordinate::Complex(_)));
}

#[test]
fn lines_ending_in_cr_lf_read_the_same() {
    let bytes = fixture_bytes("pyuff/ascii_uneven.uff");
    let crlf: Vec<u8> = bytes
        .iter()
        .flat_map(|&b| {
            if b == b'\n' {
                vec![b'\r', b'\n']
            } else {
                vec![b]
            }
        })
        .collect();
    assert_eq!(
        msd_uff::parse(&crlf).expect("CR LF"),
        msd_uff::parse(&bytes).expect("LF")
    );
}
