//! The robust D-optimal design of the paper's plant (9 plants within ±30 %) against the
//! prior-only one: each one's det(cov)^(1/6) ratio to the paper's input on the prior and
//! on every plant of the box (geometric mean and worst) and its largest stroke there,
//! for several line counts, iteration budgets and starts, and with the stroke limited on
//! the prior or on every plant, with the design time.
//!
//! ```text
//! cargo run --release -p msd-ident --example design_robust
//! ```

use msd_ident::{
    Excitation, Parameters,
    design::{DesignOptions, InputComparison, RobustBox, StrokeOn, design_input},
};
use msd_signal::paper_identification_input;

fn main() -> Result<(), msd_ident::IdentError> {
    let paper = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
    println!(
        "plants lines segments iterations starts stroke on | time s | prior | box mean | box worst"
    );
    for (plants, lines, segments, iterations, starts, stroke_on) in [
        (1, 60, 1, 100, 1, StrokeOn::Prior),
        (9, 60, 1, 100, 1, StrokeOn::Prior),
        (9, 60, 1, 200, 1, StrokeOn::Prior),
        (9, 90, 1, 100, 1, StrokeOn::Prior),
        (9, 60, 1, 100, 3, StrokeOn::Prior),
        (9, 60, 3, 100, 1, StrokeOn::Prior),
        (9, 60, 1, 100, 1, StrokeOn::EveryPlant),
    ] {
        let mut options = DesignOptions {
            lines,
            segments,
            iterations,
            starts,
            robust: RobustBox {
                plants: 9,
                ..RobustBox::default()
            },
            ..DesignOptions::default()
        };
        options.constraints.stroke_on = stroke_on;
        let optimised = DesignOptions {
            robust: RobustBox {
                plants,
                ..options.robust
            },
            ..options
        };
        let started = std::time::Instant::now();
        let design = design_input(&Parameters::PAPER, &paper, 2.5e-3, &optimised)?;
        let seconds = started.elapsed().as_secs_f64();
        // The box of the robust design (the same seed gives the same plants).
        let boxed = design_input(
            &Parameters::PAPER,
            &paper,
            2.5e-3,
            &DesignOptions {
                iterations: 1,
                ..options
            },
        )?;
        let ratios = boxed
            .plants
            .iter()
            .map(|p| {
                Ok(InputComparison::new(p, &design.excitation, &paper, 2.5e-3)?.determinant_ratio)
            })
            .collect::<Result<Vec<f64>, msd_ident::IdentError>>()?;
        let mean = ratios.iter().map(|r| r.ln()).sum::<f64>() / ratios.len() as f64;
        let worst = ratios.iter().copied().fold(0.0, f64::max);
        println!(
            "{plants:>6} {lines:>5} {segments:>8} {iterations:>10} {starts:>6} {:>11} | {seconds:>6.2} | {:.3} | {:.3} | {worst:.3}   strokes on the box: up to {:.4} m",
            format!("{stroke_on:?}"),
            design.comparison.determinant_ratio,
            mean.exp(),
            boxed
                .plants
                .iter()
                .map(|p| peak_stroke(p, &design.excitation))
                .fold(0.0, f64::max)
        );
    }
    Ok(())
}

fn peak_stroke(plant: &Parameters, input: &Excitation) -> f64 {
    msd_ident::simulate(
        plant,
        input,
        msd_ident::InitialState::REST,
        &msd_ident::Backend::EXACT,
    )
    .map_or(f64::NAN, |x| x.iter().fold(0.0, |m, v| m.max(v.abs())))
}
