//! Designs inputs for the paper's plant within the paper input's limits (9 N, 0.1115 m,
//! 15 s at 500 Hz, σ = 2.5 mm) and compares each with the paper's input.
//!
//! ```text
//! cargo run --release -p msd-ident --example design_paper [segments] [step time, s]
//! ```

use msd_ident::{
    Excitation, Parameters,
    design::{Criterion, DesignOptions, Normalise, RobustBox, StepOption, design_input},
};
use msd_signal::paper_identification_input;

fn main() -> Result<(), msd_ident::IdentError> {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let paper = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
    for criterion in [Criterion::DOptimal, Criterion::AOptimal, Criterion::Minimax] {
        let mut options = DesignOptions {
            criterion,
            robust: RobustBox {
                plants: args.get(3).map_or(9, |p| *p as usize),
                ..RobustBox::default()
            },
            segments: args.first().map_or(1, |s| *s as usize),
            iterations: args.get(2).map_or(60, |s| *s as usize),
            normalise: if criterion == Criterion::Minimax {
                Normalise::Reference
            } else {
                Normalise::Prior
            },
            ..DesignOptions::default()
        };
        options.constraints.step = args.get(1).filter(|t| **t >= 0.0).map(|&time| StepOption {
            time,
            min_amplitude: 0.0,
        });
        let started = std::time::Instant::now();
        let design = design_input(&Parameters::PAPER, &paper, 2.5e-3, &options)?;
        println!(
            "{design}\n  designed in {:.3} s\n",
            started.elapsed().as_secs_f64()
        );
    }
    Ok(())
}
