//! `configs/roving-hammer-beam.toml`: the UFF file it reads is the one the
//! `roving_beam_uff` example writes, and the set's fit finds the beam's modes: every
//! mode, fn within 0.1 %, ζ within 5 %, MAC with the true shape >= 0.99, modal masses
//! of the shapes as the simulation made them.

use msd_experiment::config::Config;
use msd_experiment::frf::{self, FrfFit};

#[path = "../../examples/roving_beam_uff.rs"]
mod example;

const CONFIG: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../configs/roving-hammer-beam.toml"
);

#[test]
fn the_shipped_beam_file_is_what_the_example_writes() {
    let shipped = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/data/roving-hammer-beam.uff"
    );
    let bytes = std::fs::read(shipped).expect("the shipped file");
    let written = msd_uff::to_bytes(&example::roving_beam(), &Default::default()).expect("bytes");
    assert!(
        bytes == written,
        "configs/data/roving-hammer-beam.uff differs: run the example again"
    );
}

#[test]
fn the_roving_hammer_set_gives_the_beams_modes_and_shapes() {
    let config = Config::load(CONFIG.as_ref()).expect("valid");
    let reference = config
        .frequency_response
        .as_ref()
        .and_then(|s| s.reference_modes.clone())
        .expect("the true modes");
    let outcome = frf::run(config, CONFIG.as_ref(), &Default::default()).expect("fits");
    let FrfFit::Set(fit) = &outcome.fit else {
        panic!("a set")
    };
    assert_eq!(fit.modes.len(), example::MODES.len(), "{fit}");
    let macs = frf::reference_mac(fit, &reference);
    for (r, (mode, &(fn_hz, zeta))) in fit.modes.iter().zip(&example::MODES).enumerate() {
        let f = mode.natural_frequency_hz.value;
        assert!((f / fn_hz - 1.0).abs() < 1e-3, "mode {}: {f} Hz", r + 1);
        let z = mode.damping_ratio.value;
        assert!((z / zeta - 1.0).abs() < 0.05, "mode {}: ζ = {z}", r + 1);
        assert!(macs[r] >= 0.99, "mode {}: MAC {}", r + 1, macs[r]);
        // The unit shape's modal mass: 0.5 kg / (largest |sin|)².
        let largest = (1..=example::POINTS)
            .map(|i| example::shape(r, i).abs())
            .fold(0.0, f64::max);
        let expected = 0.5 / (largest * largest);
        let mass = mode.modal_mass.expect("point 3 is a driving point");
        assert!(
            (mass / expected - 1.0).abs() < 0.05,
            "mode {}: {mass} kg vs {expected}",
            r + 1
        );
    }
}
