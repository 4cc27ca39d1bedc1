//! Writes `configs/data/frf-2dof.uff`, the UFF 58 file `configs/frf-uff.toml` reads: the
//! transfer receptance (force on mass 1, displacement of mass 2) of the two-mass chain
//! of `configs/hammer-2dof.toml`, 0.25–50 Hz every 0.25 Hz, with 1 % complex noise
//! (seed 21), as an ASCII dataset 58 in double precision.
//!
//! ```text
//! cargo run -p msd-experiment --example frf_uff
//! ```
//! A test checks that the shipped file is what this writes.

use msd_experiment::config::ChainPlant;
use msd_uff::{Abscissa, Function58, FunctionType, Ordinate, UffFile};

/// The file's contents.
pub fn frf_2dof() -> UffFile {
    let plant = ChainPlant {
        masses: vec![2.0, 1.0],
        springs: vec![20_000.0, 10_000.0],
        dampers: vec![4.0, 2.0],
        force_at: 1,
        response_at: 2,
    };
    let f: Vec<f64> = (1..=200).map(|i| 0.25 * i as f64).collect();
    let frf = msd_modal::synthetic_frequency_response(&f, 0.01, 21, |f| plant.receptance(f))
        .expect("a valid synthetic response");
    let values = frf.h.iter().map(|h| (h.re, h.im)).collect();
    let mut function = Function58::new(
        FunctionType::FrequencyResponse,
        Abscissa::Even {
            start: 0.25,
            step: 0.25,
        },
        Ordinate::Complex(values),
    );
    function.ids[0] = "two-mass chain, receptance x2/F1, 1 % complex noise (seed 21)".into();
    function.ids[1] = "written by msd-experiment's example frf_uff".into();
    (function.response_node, function.response_direction) = (2, 1);
    (function.reference_node, function.reference_direction) = (1, 1);
    function.abscissa_axis.data_type = 18; // frequency
    function.abscissa_axis.units = "Hz".into();
    function.ordinate_axis.data_type = 8; // displacement
    function.ordinate_axis.units = "m".into();
    function.denominator_axis.data_type = 13; // excitation force
    function.denominator_axis.units = "N".into();
    let mut file = UffFile::default();
    file.functions.push(function);
    file
}

#[allow(dead_code)]
fn main() -> Result<(), msd_uff::UffError> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/data/frf-2dof.uff"
    );
    msd_uff::write(path, &frf_2dof(), &Default::default())?;
    println!("wrote {path}");
    Ok(())
}
