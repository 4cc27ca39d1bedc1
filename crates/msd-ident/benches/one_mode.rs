//! One mode fitted as m, c, k to a 40-line stepped sine of the paper's plant with 1 %
//! noise.

use criterion::{Criterion, criterion_group, criterion_main};
use msd_ident::{OneModeOptions, Parameters, fit_one_mode, frequency::model_response};
use msd_modal_core::synthetic_frequency_response;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let f: Vec<f64> = (0..40).map(|i| 0.25 + 2.25 * i as f64 / 39.0).collect();
    let sweep = synthetic_frequency_response(&f, 0.01, 1, |f| {
        model_response(&Parameters::PAPER, std::f64::consts::TAU * f)
    })
    .expect("valid");
    let mut group = c.benchmark_group("frequency_response");
    group.bench_function("one_mode_40_lines", |b| {
        b.iter(|| fit_one_mode(black_box(&sweep), &OneModeOptions::default()).expect("fit"))
    });
    group.finish();
}

#[allow(missing_docs)]
mod harness {
    use super::*;
    criterion_group!(benches, bench);
}
criterion_main!(harness::benches);
