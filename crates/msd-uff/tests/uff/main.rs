//! msd-uff's integration tests, in one binary: the pyuff fixtures read to the last digit,
//! round trips, the files this crate writes, refused files, and inputs that must not panic.

mod data_at_nodes;
mod data_lines;
mod errors;
mod errors55;
mod fixtures;
mod fixtures_nodes;
mod ours;
mod robustness;
mod roundtrip;
mod tolerance;

use std::path::PathBuf;

/// A file under `fixtures/`.
pub fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(name)
}

/// The bytes of a file under `fixtures/`.
pub fn fixture_bytes(name: &str) -> Vec<u8> {
    std::fs::read(fixture(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Every pyuff fixture, by name.
pub const PYUFF_FIXTURES: [&str; 13] = [
    "ascii_real_even",
    "ascii_frf_complex",
    "ascii_uneven",
    "ascii_single",
    "binary_double",
    "binary_single",
    "binary_big_endian",
    "binary_trailing",
    "mixed",
    "modes_real",
    "modes_complex",
    "geometry_15",
    "geometry_2411",
];

use msd_uff::{
    Abscissa, Axis, ByteOrder, Encoding, Function58, FunctionType, Header151, Ordinate, Precision,
    UffFile, Units164,
};

/// The receptance of m = 1.25, c = 3.5, k = 4e4 at `f` Hz as (re, im): values with all 17
/// digits, to test precision.
pub fn receptance(f: f64) -> (f64, f64) {
    let w = 2.0 * std::f64::consts::PI * f;
    let (a, b) = (4.0e4 - 1.25 * w * w, 3.5 * w);
    let d = a * a + b * b;
    (a / d, -b / d)
}

fn axis(data_type: i32, label: &str, units: &str) -> Axis {
    Axis {
        data_type,
        label: label.into(),
        units: units.into(),
        ..Axis::default()
    }
}

/// A file with a header, units and five functions covering the layouts of record 12
/// (even and uneven, real and complex, single and double), all in `encoding`.
pub fn sample_file(encoding: Encoding) -> UffFile {
    let freqs: Vec<f64> = (0..24).map(|k| k as f64 * 0.5).collect();
    let stepped: Vec<f64> = (1..=9).map(|k| 20.0 + k as f64 / 3.0).collect();
    let mut frf = Function58::new(
        FunctionType::FrequencyResponse,
        Abscissa::Even {
            start: 0.0,
            step: 0.5,
        },
        Ordinate::Complex(freqs.iter().map(|&f| receptance(f)).collect()),
    );
    frf.ids[0] = "receptance H(3+Z, 1+Z)".into();
    frf.ids[2] = "23-Nov-26 12:00:00".into();
    (
        frf.response_entity,
        frf.response_node,
        frf.response_direction,
    ) = ("plate".into(), 3, 3);
    (
        frf.reference_entity,
        frf.reference_node,
        frf.reference_direction,
    ) = ("plate".into(), 1, 3);
    frf.abscissa_axis = axis(18, "Frequency", "Hz");
    frf.ordinate_axis = axis(8, "Displacement", "m");
    frf.denominator_axis = axis(13, "Force", "N");

    let mut coherence = Function58::new(
        FunctionType::Coherence,
        Abscissa::Uneven(stepped.clone()),
        Ordinate::Real(stepped.iter().map(|f| 1.0 - 1.0 / (f + 3.0)).collect()),
    );
    coherence.ids[0] = "coherence, stepped sine".into();
    (coherence.response_node, coherence.response_direction) = (4, -2);
    (coherence.reference_node, coherence.reference_direction) = (1, 3);

    let mut sweep = Function58::new(
        FunctionType::FrequencyResponse,
        Abscissa::Uneven(stepped.clone()),
        Ordinate::Complex(stepped.iter().map(|&f| receptance(f)).collect()),
    );
    sweep.ids[0] = "stepped sine, single precision".into();
    sweep.precision = Precision::Single;
    (sweep.response_node, sweep.response_direction) = (12, 6);

    let mut spectrum = Function58::new(
        FunctionType::AutoSpectrum,
        Abscissa::Even {
            start: 0.0,
            step: 0.1220703125,
        },
        Ordinate::Real((0..13).map(|k| 1e-6 / (1.0 + k as f64 / 7.0)).collect()),
    );
    spectrum.ids[0] = "auto spectrum, single precision".into();
    spectrum.precision = Precision::Single;
    spectrum.z_axis_value = 1.5;

    let mut decay = Function58::new(
        FunctionType::TimeResponse,
        Abscissa::Even {
            start: -0.25,
            step: 1.0 / 1024.0,
        },
        Ordinate::Real(
            (0..10)
                .map(|k| (-1.0f64).powi(k) * (k as f64 + 1.0).sqrt() * 1e-3)
                .collect(),
        ),
    );
    decay.ids[0] = "time response".into();
    decay.abscissa_axis = axis(17, "Time", "s");
    decay.function_id = 7;
    decay.version = 2;

    let mut functions = vec![frf, coherence, sweep, spectrum, decay];
    for f in &mut functions {
        f.encoding = encoding;
    }
    if encoding != Encoding::Ascii {
        functions[4].encoding = Encoding::Binary(ByteOrder::Big);
    }
    UffFile {
        header: Some(Header151 {
            model_name: "msd-uff sample".into(),
            description: "one mass on a spring".into(),
            db_program: "msd-uff tests".into(),
            db_created_date: "23-Nov-26".into(),
            db_created_time: "12:00:00".into(),
            db_version1: 1,
            db_version2: 0,
            file_type: 0,
            db_saved_date: "23-Nov-26".into(),
            db_saved_time: "12:30:00".into(),
            program: "msd-uff".into(),
            written_date: "23-Nov-26".into(),
            written_time: "13:00:00".into(),
        }),
        units: Some(Units164 {
            description: "SI units".into(),
            temperature_offset: 273.15,
            ..Units164::default()
        }),
        functions,
        ..UffFile::default()
    }
}
