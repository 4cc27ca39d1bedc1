//! The Cramér–Rao prediction of each shipped design against many simulated tests: for
//! the paper's input and the D-, A- and minimax designs on the paper's plant, the
//! standard deviation of m, c, k over N noise seeds (Levenberg–Marquardt on the exact
//! simulation, as `design --verify`) over the predicted standard error, with the
//! standard error of that ratio (from the sample kurtosis: √((κ − 1)/(4N)), 1/√(2N) for
//! Gaussian estimates), and the mean error in predicted standard errors.
//!
//! ```text
//! cargo run --release -p msd-ident --example design_verify [seeds, default 2000]
//! ```

use msd_ident::{
    EstimationOptions, Excitation, Parameters, SyntheticOptions,
    design::{Criterion, DesignOptions, Normalise, design_input},
    estimate, predicted_uncertainty, synthetic_data,
};
use msd_signal::paper_identification_input;

fn main() -> Result<(), msd_ident::IdentError> {
    let seeds: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(2000);
    let paper = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
    let mut inputs = vec![("paper input".to_string(), paper.clone())];
    for (criterion, normalise) in [
        (Criterion::DOptimal, Normalise::Prior),
        (Criterion::AOptimal, Normalise::Prior),
        (Criterion::Minimax, Normalise::Reference),
    ] {
        let options = DesignOptions {
            criterion,
            normalise,
            ..DesignOptions::default()
        };
        let design = design_input(&Parameters::PAPER, &paper, 2.5e-3, &options)?;
        inputs.push((criterion.to_string(), design.excitation));
    }
    let options = EstimationOptions::fast();
    for (name, input) in &inputs {
        report(name, input, seeds, &options)?;
    }
    Ok(())
}

fn report(
    name: &str,
    input: &Excitation,
    seeds: usize,
    options: &EstimationOptions,
) -> Result<(), msd_ident::IdentError> {
    let plant = Parameters::PAPER;
    let predicted = predicted_uncertainty(&plant, input, 2.5e-3, options)?;
    let se = [
        predicted.mass.standard_error,
        predicted.damping.standard_error,
        predicted.stiffness.standard_error,
    ];
    let truth = [plant.mass, plant.damping, plant.stiffness];
    let mut values = [vec![], vec![], vec![]];
    let started = std::time::Instant::now();
    for seed in 0..seeds as u64 {
        let synthetic = SyntheticOptions {
            seed,
            sigma: 2.5e-3,
            ..SyntheticOptions::named("identification")
        };
        let (data, _) = synthetic_data(&plant, input.clone(), &synthetic)?;
        let p = estimate(&data, options)?.parameters;
        for (v, x) in values.iter_mut().zip([p.mass, p.damping, p.stiffness]) {
            v.push(x);
        }
    }
    println!(
        "{name}: {seeds} seeds in {:.1} s",
        started.elapsed().as_secs_f64()
    );
    for (i, parameter) in ["mass", "damping", "stiffness"].iter().enumerate() {
        let v = &values[i];
        let n = v.len() as f64;
        let mean = v.iter().sum::<f64>() / n;
        let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let m4 = v.iter().map(|x| (x - mean).powi(4)).sum::<f64>() / n;
        let kurtosis = m4 / (var * var);
        let ratio = var.sqrt() / se[i];
        let ratio_se = ((kurtosis - 1.0) / (4.0 * n)).sqrt();
        println!(
            "  {parameter:<9} sd/predicted {ratio:.4} ± {ratio_se:.4} ({:+.1} σ), kurtosis {kurtosis:.2}, mean error {:+.3} SE (± {:.3})",
            (ratio - 1.0) / ratio_se,
            (mean - truth[i]) / se[i],
            ratio * n.sqrt().recip()
        );
    }
    Ok(())
}
