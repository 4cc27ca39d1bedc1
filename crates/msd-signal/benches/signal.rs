//! Criterion benchmarks: sampling the paper's identification input on its 7501-point grid,
//! and one Welch H1 estimate on 7501 samples (whole record as one segment).

use std::hint::black_box;

use criterion::{Criterion, criterion_main};
use msd_signal::{WelchOptions, gaussian_noise, h1_estimate, paper_identification_input};

const N: usize = 7501;
const DT: f64 = 0.002;

fn sample_paper_input(c: &mut Criterion) {
    let u = paper_identification_input();
    let mut out = vec![0.0; N];
    c.bench_function("sample paper identification input (7501 points)", |b| {
        b.iter(|| {
            black_box(&u).sample_into(0.0, DT, &mut out);
            black_box(out[N - 1])
        })
    });
}

fn welch_h1(c: &mut Criterion) {
    let u = paper_identification_input().sample(0.0, DT, N);
    let noise = gaussian_noise(1, "bench", 0.0025, N).unwrap_or_default();
    let y: Vec<f64> = u.iter().zip(&noise).map(|(a, e)| 0.01 * a + e).collect();
    let opts = WelchOptions::default();
    c.bench_function("Welch H1 estimate (7501 samples, one segment)", |b| {
        b.iter(|| h1_estimate(black_box(&u), black_box(&y), 1.0 / DT, &opts).map(|f| f.averages))
    });
}

/// The benchmark group (the macro's generated function carries no doc comment).
mod group {
    #![allow(missing_docs)]
    criterion::criterion_group!(benches, super::sample_paper_input, super::welch_h1);
}

criterion_main!(group::benches);
