//! Output-only modal analysis of a simulated five-storey shear building (pyOMA2's example:
//! 25.91 kg floors on 10 kN/m storeys, ζ = 2 %, white-noise forces, accelerations at
//! 100 Hz with 10 % noise, 30,001 samples): SSI-cov/ref at default settings against the
//! truth.
//!
//! Run with `cargo run --release -p msd-modal --example shear_building [seed]`.

use msd_modal::{OmaOptions, ShearBuilding, ssi_cov};
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let seed = std::env::args().nth(1).map_or(Ok(1), |s| s.parse())?;
    let building = ShearBuilding {
        masses: vec![25.91; 5],
        stiffnesses: vec![10_000.0; 5],
        damping_ratio: 0.02,
    };
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let record = building.ambient_record(100.0, 30_001, 0.1, || StandardNormal.sample(&mut rng))?;
    let fit = ssi_cov(&record, &OmaOptions::default())?;
    println!("{fit}");
    for (f, _) in building.modes()? {
        println!("true: fn = {f:.5} Hz, ζ = 0.02");
    }
    Ok(())
}
