//! Fitting frequency responses: three modes (fn 10, 23, 41 Hz; ζ 1 %, 2 %, 0.5 %) in
//! 2000 lines with 1 % noise, the stabilization diagram over orders 2–40 and the polish
//! (the issue's ≤ 20 ms); the diagram alone. (One mode as m, c, k is msd-ident's
//! `one_mode` bench.)

use criterion::{Criterion, criterion_group, criterion_main};
use msd_modal::{
    FrfWeighting, ModalOptions, ModalParameters, fit_modes, stabilization_diagram,
    synthetic_frequency_response,
};
use msd_signal::FrequencyResponseEstimate;
use std::hint::black_box;

fn three_modes() -> FrequencyResponseEstimate {
    let modes = [(10.0, 0.01, 1.0), (23.0, 0.02, -0.6), (41.0, 0.005, 0.4)].map(|(f, z, a)| {
        ModalParameters {
            natural_frequency_hz: f,
            damping_ratio: z,
            modal_constant: a,
            modal_constant_imaginary: 0.0,
        }
    });
    let f: Vec<f64> = (1..=2000).map(|i| 0.025 * i as f64).collect();
    synthetic_frequency_response(&f, 0.01, 1, |f| modes.iter().map(|m| m.receptance(f)).sum())
        .expect("valid")
}

fn bench(c: &mut Criterion) {
    let frf = three_modes();
    let options = ModalOptions {
        weighting: FrfWeighting::Relative,
        ..ModalOptions::default()
    };
    assert_eq!(fit_modes(&frf, &options).expect("fit").modes.len(), 3);
    let mut group = c.benchmark_group("frequency_response");
    group.bench_function("three_modes_2000_lines_orders_2_40_and_polish", |b| {
        b.iter(|| fit_modes(black_box(&frf), &options).expect("fit"))
    });
    group.bench_function("stabilization_diagram_orders_2_40", |b| {
        b.iter(|| stabilization_diagram(black_box(&frf), &options).expect("diagram"))
    });
    group.finish();
}

#[allow(missing_docs)]
mod harness {
    use super::*;
    criterion_group!(benches, bench);
}
criterion_main!(harness::benches);
