//! The simulated five-storey shear building both output-only methods are tested on
//! (pyOMA2's example): 25.91 kg floors on 10 kN/m storeys, ζ = 2 % in every mode,
//! white-noise forces, accelerations at 100 Hz with 10 % noise, 30,001 samples.

use msd_modal::{OutputRecord, ShearBuilding};
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};

pub(crate) fn building() -> ShearBuilding {
    ShearBuilding {
        masses: vec![25.91; 5],
        stiffnesses: vec![10_000.0; 5],
        damping_ratio: 0.02,
    }
}

pub(crate) fn record(seed: u64) -> OutputRecord {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    building()
        .ambient_record(100.0, 30_001, 0.1, || StandardNormal.sample(&mut rng))
        .expect("a valid building")
}
