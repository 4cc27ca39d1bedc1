//! The paper's Monte Carlo band: N = 1000 samples, ±10 % uniform around the paper's
//! plant, on the validation input (7501 points), with each backend on 1 and 2 threads.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use msd_ident::{Backend, PaperExperiment, Parameters};
use msd_mc::{McOptions, monte_carlo_band};
use std::hint::black_box;
use std::time::Duration;

fn bench(c: &mut Criterion) {
    let experiment = PaperExperiment::generate(0).expect("paper experiment");
    let validation = &experiment.validation;
    let mut group = c.benchmark_group("mc_band_paper_n1000");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(8));
    for backend in [Backend::EXACT, Backend::PAPER] {
        for threads in [1, 2] {
            let options = McOptions {
                samples: 1000,
                threads,
                backend,
                ..McOptions::default()
            };
            let id = BenchmarkId::new(backend.name(), format!("{threads}_threads"));
            group.bench_with_input(id, &options, |b, options| {
                b.iter(|| {
                    monte_carlo_band(
                        &Parameters::PAPER,
                        black_box(&validation.excitation),
                        Some(&validation.output),
                        options,
                    )
                    .expect("band")
                })
            });
        }
    }
    group.finish();
}

#[allow(missing_docs)]
mod harness {
    use super::*;
    criterion_group!(benches, bench);
}
criterion_main!(harness::benches);
