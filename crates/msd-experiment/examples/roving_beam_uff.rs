//! Writes `configs/data/roving-hammer-beam.uff`: a simulated roving-hammer test on a
//! simply supported beam, ten points (x_i = i·L/11), the accelerometer at point 3 and the
//! hammer at every point, five modes with damping ratios from 1e-2 to 1e-4, 1–350 Hz at
//! 1 Hz lines, 1 % complex noise: ten accelerance FRFs as datasets 58 with their nodes,
//! and the points' coordinates (dataset 15, x_i = 0.1·i m on a 1.1 m beam). Also writes
//! `configs/data/roving-hammer-beam-model.uff`: the model's five shapes as datasets 55 (a
//! test's shapes are compared with such a file). `configs/roving-hammer-beam.toml` fits
//! the FRFs and compares the modes with the truth.
//!
//!     cargo run -p msd-experiment --example roving_beam_uff

use msd_modal::{ModalParameters, synthetic_frequency_response};
use msd_uff::{
    Abscissa, Analysis55, Data55, Function58, FunctionType, Node, Ordinate, Precision, UffFile,
};

/// fn = 12 r² Hz (a simply supported beam) and ζ of each mode.
pub const MODES: [(f64, f64); 5] = [
    (12.0, 1e-2),
    (48.0, 3e-3),
    (108.0, 1e-3),
    (192.0, 3e-4),
    (300.0, 1e-4),
];
/// The points.
pub const POINTS: usize = 10;
/// The accelerometer's point.
pub const RESPONSE: usize = 3;

/// Mode r's shape at point i (from 1): sin((r + 1)π·i/11), unit modal mass 0.5 kg.
pub fn shape(r: usize, i: usize) -> f64 {
    ((r + 1) as f64 * std::f64::consts::PI * i as f64 / (POINTS + 1) as f64).sin()
}

/// The ten FRFs as a UFF file.
pub fn roving_beam() -> UffFile {
    let f: Vec<f64> = (1..=350).map(f64::from).collect();
    let mut file = UffFile::default();
    for hammer in 1..=POINTS {
        let terms: Vec<ModalParameters> = MODES
            .iter()
            .enumerate()
            .map(|(r, &(fn_hz, zeta))| ModalParameters {
                natural_frequency_hz: fn_hz,
                damping_ratio: zeta,
                modal_constant: shape(r, RESPONSE) * shape(r, hammer) / 0.5,
                modal_constant_imaginary: 0.0,
            })
            .collect();
        let accelerance = |f: f64| {
            let w = std::f64::consts::TAU * f;
            -w * w
                * terms
                    .iter()
                    .map(|m| m.receptance(f))
                    .sum::<msd_signal::Complex64>()
        };
        let frf = synthetic_frequency_response(&f, 0.01, 30 + hammer as u64, accelerance)
            .expect("a valid synthetic response");
        let values = frf.h.iter().map(|h| (h.re, h.im)).collect();
        let mut function = Function58::new(
            FunctionType::FrequencyResponse,
            Abscissa::Even {
                start: 1.0,
                step: 1.0,
            },
            Ordinate::Complex(values),
        );
        function.ids[0] =
            format!("simply supported beam, accelerance a{RESPONSE}/F{hammer}, 1 % noise");
        function.ids[1] = "written by msd-experiment's example roving_beam_uff".into();
        (function.response_node, function.response_direction) = (RESPONSE as i64, 3);
        (function.reference_node, function.reference_direction) = (hammer as i64, 3);
        function.abscissa_axis.data_type = 18;
        function.abscissa_axis.units = "Hz".into();
        function.ordinate_axis.data_type = 12; // acceleration
        function.ordinate_axis.units = "m/s2".into();
        function.denominator_axis.data_type = 13;
        function.denominator_axis.units = "N".into();
        file.functions.push(function);
    }
    file.nodes = (1..=POINTS)
        .map(|i| Node {
            label: i as i64,
            x: 0.1 * i as f64,
            precision: Precision::Single,
            ..Default::default()
        })
        .collect();
    file
}

/// The model's shapes (unit modal mass 0.5 kg as simulated) as datasets 55: real normal
/// modes, Z displacements at the ten points.
pub fn beam_model() -> UffFile {
    let data_at_nodes = MODES
        .iter()
        .enumerate()
        .map(|(r, &(fn_hz, zeta))| Data55 {
            ids: [
                "simply supported beam, 10 points".into(),
                "the model of msd-experiment's example roving_beam_uff".into(),
                "NONE".into(),
                "NONE".into(),
                "NONE".into(),
            ],
            analysis: Analysis55::NormalMode {
                load_case: 1,
                mode: r as i64 + 1,
                frequency: fn_hz,
                modal_mass: 0.5,
                viscous_damping: zeta,
                hysteretic_damping: 0.0,
            },
            nodes: (1..=POINTS as i64).collect(),
            values: (1..=POINTS)
                .map(|i| vec![(0.0, 0.0), (0.0, 0.0), (shape(r, i), 0.0)])
                .collect(),
            ..Default::default()
        })
        .collect();
    UffFile {
        data_at_nodes,
        ..Default::default()
    }
}

#[allow(dead_code)]
fn main() -> Result<(), msd_uff::UffError> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/data/roving-hammer-beam.uff"
    );
    msd_uff::write(path, &roving_beam(), &Default::default())?;
    println!("wrote {path}");
    let model = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/data/roving-hammer-beam-model.uff"
    );
    msd_uff::write(model, &beam_model(), &Default::default())?;
    println!("wrote {model}");
    for r in 0..MODES.len() {
        let values: Vec<String> = (1..=POINTS)
            .map(|i| format!("{:.6}", shape(r, i)))
            .collect();
        println!("shape {}: [{}]", r + 1, values.join(", "));
    }
    Ok(())
}
