//! The frequency-consistency check on the paper's data, for several seeds.
//!
//! `cargo run --release -p msd-ident --example frequency`
use msd_ident::{
    PaperExperiment, Parameters,
    frequency::{FrequencyCheckOptions, frequency_check},
};

fn main() -> Result<(), msd_ident::IdentError> {
    for seed in 1..=5 {
        let e = PaperExperiment::generate(seed)?;
        for (name, data) in [
            ("validation", &e.validation),
            ("identification", &e.identification),
        ] {
            let c = frequency_check(
                data,
                &Parameters::PAPER,
                None,
                &FrequencyCheckOptions::default(),
            )?;
            println!(
                "seed {seed} {name}: fn {:.4} ({:+.2} %), ζ {:.4} ({:+.1} %), band {:.2}–{:.2} Hz, err {:.3}, {}",
                c.natural_frequency_hz,
                100.0 * (c.natural_frequency_hz / 1.102658 - 1.0),
                c.damping_ratio,
                100.0 * (c.damping_ratio / 0.051962 - 1.0),
                c.band_hz[0],
                c.band_hz[1],
                c.model_relative_error,
                c.consistent
            );
        }
    }
    let wrong = Parameters {
        stiffness: 96.0,
        ..Parameters::PAPER
    };
    let c = frequency_check(
        &PaperExperiment::generate(1)?.validation,
        &wrong,
        None,
        &FrequencyCheckOptions::default(),
    )?;
    println!("k −20 %: {}", c.verdict);
    Ok(())
}
