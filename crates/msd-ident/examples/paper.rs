//! Identifies the paper's plant from its synthetic experiment by both methods.
//!
//! `cargo run --release -p msd-ident --example paper`

use msd_ident::{EstimationOptions, PaperExperiment, estimate};

fn main() -> Result<(), msd_ident::IdentError> {
    let experiment = PaperExperiment::generate(1)?;
    for (name, options) in [
        ("paper (Nelder–Mead + ode45)", EstimationOptions::paper()),
        (
            "fast (Levenberg–Marquardt + exact)",
            EstimationOptions::fast(),
        ),
        ("fast, automatic guess", EstimationOptions::default()),
    ] {
        let fit = estimate(&experiment.identification, &options)?;
        println!("{name}\n{fit}\n");
    }
    Ok(())
}
