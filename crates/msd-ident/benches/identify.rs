//! Identification and validation of the paper experiment: the paper's method
//! (Nelder–Mead + ode45 at RelTol 1e-6) and the fast method (Levenberg–Marquardt +
//! exact simulation); validation with the full diagnostics.

use criterion::{Criterion, criterion_group, criterion_main};
use msd_ident::{
    Backend, EstimationOptions, InitialState, PaperExperiment, ValidationOptions, estimate,
    frequency::{FrequencyCheckOptions, frequency_check},
    simulate, validate_model,
};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let e = PaperExperiment::generate(1).expect("data");
    let fit = estimate(&e.identification, &EstimationOptions::fast()).expect("fit");
    let mut group = c.benchmark_group("paper_identification");
    group.sample_size(20);
    group.bench_function("paper_method_nelder_mead_ode45", |b| {
        b.iter(|| estimate(black_box(&e.identification), &EstimationOptions::paper()).expect("fit"))
    });
    group.bench_function("fast_method_levenberg_marquardt_exact", |b| {
        b.iter(|| estimate(black_box(&e.identification), &EstimationOptions::fast()).expect("fit"))
    });
    group.bench_function("fast_method_automatic_guess", |b| {
        b.iter(|| {
            estimate(black_box(&e.identification), &EstimationOptions::default()).expect("fit")
        })
    });
    group.bench_function("one_exact_simulation", |b| {
        b.iter(|| {
            simulate(
                black_box(&fit.parameters),
                &e.identification.excitation,
                InitialState::REST,
                &Backend::EXACT,
            )
        })
    });
    group.bench_function("validation_with_diagnostics_and_frequency_check", |b| {
        b.iter(|| {
            let v = validate_model(
                &fit.parameters,
                black_box(&e.validation),
                &ValidationOptions::default(),
            )
            .expect("validate");
            let f = frequency_check(
                &e.validation,
                &fit.parameters,
                Some(&fit.uncertainty),
                &FrequencyCheckOptions::default(),
            )
            .expect("check");
            (v, f)
        })
    });
    group.finish();
}

#[allow(missing_docs)]
mod harness {
    use super::*;
    criterion_group!(benches, bench);
}
criterion_main!(harness::benches);
