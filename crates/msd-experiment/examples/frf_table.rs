//! Writes `configs/data/stepped-sine-table.csv`, the table `configs/frf-table.toml`
//! reads: the paper's plant (m = 2.5 kg, c = 1.8 N·s/m, k = 120 N/m) measured by a
//! stepped sine at 30 logarithmically spaced frequencies from 0.3 to 3 Hz, the
//! receptance with 1 % complex noise (seed 21), as magnitude (m/N) and phase (degrees),
//! one row per excitation frequency.
//!
//! ```text
//! cargo run -p msd-experiment --example frf_table
//! ```
//! A test checks that the shipped file is what this writes.

use msd_experiment::config::ChainPlant;
use std::fmt::Write;

/// The file's contents.
pub fn stepped_sine_table() -> String {
    let plant = ChainPlant::one_mass(2.5, 1.8, 120.0);
    let f: Vec<f64> = (0..30).map(|i| 0.3 * 10f64.powf(i as f64 / 29.0)).collect();
    let frf = msd_modal::synthetic_frequency_response(&f, 0.01, 21, |f| plant.receptance(f))
        .expect("a valid synthetic response");
    let mut text = String::from(
        "# The paper's plant by a stepped sine: receptance with 1 % complex noise (seed 21),\n# written by msd-experiment's example frf_table.\nfrequency_hz,magnitude_m_per_n,phase_deg\n",
    );
    for (f, h) in frf.frequency.iter().zip(&frf.h) {
        let _ = writeln!(text, "{f:.6},{:.9e},{:.6}", h.norm(), h.arg().to_degrees());
    }
    text
}

#[allow(dead_code)]
fn main() -> std::io::Result<()> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/data/stepped-sine-table.csv"
    );
    std::fs::write(path, stepped_sine_table())?;
    println!("wrote {path}");
    Ok(())
}
