//! The fixtures (written by scipy, numpy and npTDMS: `fixtures/make.py`) read back to the
//! values that wrote them: t = i/100 s, force = sin(2π·3·t), x = 0.01 cos(2π·3·t).

use msd_files::{FileFormat, read};
use std::path::{Path, PathBuf};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(name)
}

fn t(i: usize) -> f64 {
    i as f64 / 100.0
}
fn force(i: usize) -> f64 {
    (2.0 * std::f64::consts::PI * 3.0 * t(i)).sin()
}
fn x(i: usize) -> f64 {
    0.01 * (2.0 * std::f64::consts::PI * 3.0 * t(i)).cos()
}

/// `values` equal `f(i)` to within `tol` (relative to 1): 1e-15 for float64 (the same
/// libm on both sides, or a ulp apart), 1e-7 for float32 (its ε is 1.2e-7).
fn assert_series(values: &[f64], f: impl Fn(usize) -> f64, tol: f64) {
    assert_eq!(values.len(), 200);
    for (i, v) in values.iter().enumerate() {
        assert!((v - f(i)).abs() <= tol, "sample {i}: {v} against {}", f(i));
    }
}

#[test]
fn matlab_level_5_variables_are_channels_and_text_is_left_out() {
    let c = read(&fixture("record-v5.mat")).unwrap();
    assert_eq!(c.format, FileFormat::Mat);
    let names: Vec<&str> = c.channels.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(
        names,
        ["t", "force", "X[0]", "X[1]", "H.re", "H.im", "count"]
    );
    assert_eq!(c.skipped, ["note: text: not read (expected numbers)"]);
    assert_series(
        &c.channel("count").unwrap().values,
        |i| i as f64 - 100.0,
        0.0,
    );
    assert_series(&c.channel("t").unwrap().values, t, 1e-15);
    assert_series(&c.channel("X[1]").unwrap().values, x, 1e-15);
    assert_series(&c.channel("H.im").unwrap().values, x, 1e-15);
}

#[test]
fn matlab_level_7_compressed_reads_as_level_5() {
    let c = read(&fixture("record-v7.mat")).unwrap();
    assert_series(&c.channel("force").unwrap().values, force, 1e-15);
}

/// A structure's fields are channels named `s.field` (nested: `s.a.b`; in a structure
/// array `s(k).field`, k from 1), a cell array's cells `c{k}`; text left out and said.
#[test]
fn matlab_structures_and_cells_are_read_part_by_part() {
    let c = read(&fixture("struct-v5.mat")).unwrap();
    let names: Vec<&str> = c.channels.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "rec.t",
            "rec.signals.values[0]",
            "rec.signals.values[1]",
            "runs(1).force",
            "runs(1).x",
            "runs(2).force",
            "runs(2).x",
            "cells{1}",
            "cells{2}"
        ]
    );
    assert_eq!(
        c.skipped,
        [
            "rec.signals.label: text: not read (expected numbers)",
            "cells{3}: text: not read (expected numbers)"
        ]
    );
    assert_series(&c.channel("cells{2}").unwrap().values, force, 1e-15);
    assert_series(&c.channel("rec.t").unwrap().values, t, 1e-15);
    assert_series(
        &c.channel("rec.signals.values[1]").unwrap().values,
        x,
        1e-15,
    );
    assert_series(
        &c.channel("runs(2).force").unwrap().values,
        |i| -force(i),
        1e-15,
    );
}

#[test]
fn numpy_arrays_split_into_channels_along_the_shorter_dimension() {
    let c = read(&fixture("record.npy")).unwrap();
    assert_eq!(c.channels.len(), 3);
    assert_eq!(c.channels[1].name, "record[1]");
    assert_series(&c.channels[1].values, force, 1e-15);
    let z = read(&fixture("record.npz")).unwrap();
    assert_eq!(z.format, FileFormat::Npz);
    assert_series(&z.channel("x").unwrap().values, x, 1e-9);
}

#[test]
fn tdms_channels_carry_their_unit_and_rate_across_segments() {
    let c = read(&fixture("record.tdms")).unwrap();
    let f = c.channel("Force").unwrap();
    assert_eq!(f.unit.as_deref(), Some("N"));
    assert_eq!(f.sample_rate_hz, Some(100.0));
    assert_series(&f.values, force, 1e-15);
    let a = c.channel("Accel").unwrap();
    assert_eq!(a.unit.as_deref(), Some("m/s²"));
    assert_series(&a.values, x, 1e-9);
}

#[test]
fn a_missing_file_and_an_unknown_extension_name_the_file() {
    let e = read(Path::new("no/such.mat")).unwrap_err().to_string();
    assert!(e.starts_with("no/such.mat: cannot read the file"), "{e}");
    let e = read(Path::new("run.xlsx")).unwrap_err().to_string();
    assert!(
        e.contains("run.xlsx") && e.contains("expected .mat, .npy"),
        "{e}"
    );
}

#[test]
fn a_level_7_3_file_is_refused_with_the_advice_to_save_with_v7() {
    let mut bytes = b"MATLAB 7.3 MAT-file, Platform: GLNXA64, HDF5 schema 1.00 .".to_vec();
    bytes.resize(512, b' ');
    let e = msd_files::read_bytes("big.mat", &bytes)
        .unwrap_err()
        .to_string();
    assert!(e.contains("7.3") && e.contains("'-v7'"), "{e}");
}
