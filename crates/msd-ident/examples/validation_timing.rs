//! Where the validation stage spends its time (release build recommended).
//!
//! `cargo run --release -p msd-ident --example validation_timing`
use msd_ident::{
    Backend, InitialState, PaperExperiment, Parameters, ResidualOptions, ValidationOptions,
    correlation::cross_correlation,
    frequency::{FrequencyCheckOptions, frequency_check},
    residual_analysis, simulate, validate_model,
};
use std::time::Instant;

fn time<T>(name: &str, reps: usize, mut f: impl FnMut() -> T) {
    let _ = f();
    let start = Instant::now();
    for _ in 0..reps {
        std::hint::black_box(f());
    }
    println!(
        "{name:<32} {:>8.1} µs",
        start.elapsed().as_secs_f64() / reps as f64 * 1e6
    );
}

fn main() -> Result<(), msd_ident::IdentError> {
    let e = PaperExperiment::generate(1)?;
    let p = Parameters::PAPER;
    let data = &e.validation;
    let model = simulate(&p, &data.excitation, InitialState::REST, &Backend::EXACT)?;
    let residuals: Vec<f64> = data.output.iter().zip(&model).map(|(y, m)| y - m).collect();
    time("exact simulation", 200, || {
        simulate(&p, &data.excitation, InitialState::REST, &Backend::EXACT)
    });
    time("cross-correlation (51 lags)", 200, || {
        cross_correlation(&residuals, data.excitation.samples(), 25)
    });
    time("residual analysis", 200, || {
        residual_analysis(
            &residuals,
            data.excitation.samples(),
            &ResidualOptions::default(),
        )
    });
    let fs = 1.0 / data.excitation.dt();
    time("H1 estimate (msd-signal)", 200, || {
        msd_signal::h1_estimate(
            data.excitation.samples(),
            &data.output,
            fs,
            &msd_signal::WelchOptions::default(),
        )
    });
    time("frequency check", 200, || {
        frequency_check(data, &p, None, &FrequencyCheckOptions::default())
    });
    time("whole stage (as the criterion bench)", 200, || {
        let v = validate_model(&p, data, &ValidationOptions::default());
        (
            v,
            frequency_check(data, &p, None, &FrequencyCheckOptions::default()),
        )
    });
    Ok(())
}
