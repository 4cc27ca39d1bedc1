//! One 15 s, 7501-sample simulation of the paper's plant under the identification input:
//! the floor (a bare 2-state linear recurrence), the exact path, and DP5(4) at RelTol 1e-6.

use criterion::{Criterion, criterion_group, criterion_main};
use msd_ode::{
    Breakpoint, ExactSimulator, Hold, LtiModel, Ode45Options, SMatrix, SVector, SampledInput,
    ode45_with,
};
use std::f64::consts::PI;
use std::hint::black_box;

const M: f64 = 2.5;
const C: f64 = 1.8;
const K: f64 = 120.0;
const DT: f64 = 0.002;
const SAMPLES: usize = 7501;

fn paper_input(t: f64) -> f64 {
    let step = if t >= 0.5 { 6.0 } else { 0.0 };
    let low = if (3.0..9.0).contains(&t) {
        3.0 * (2.0 * PI * 0.5 * t).sin()
    } else {
        0.0
    };
    let high = if (9.0..=15.0).contains(&t) {
        2.5 * (2.0 * PI * 1.4 * t).sin()
    } else {
        0.0
    };
    step + low + high
}

fn model() -> LtiModel<2> {
    LtiModel {
        a: SMatrix::<f64, 2, 2>::new(0.0, 1.0, -K / M, -C / M),
        b: SVector::<f64, 2>::new(0.0, 1.0 / M),
    }
}

fn bench(c: &mut Criterion) {
    let grid: Vec<f64> = (0..SAMPLES).map(|i| i as f64 * DT).collect();
    let force: Vec<f64> = grid.iter().map(|&t| paper_input(t)).collect();
    let breakpoints = [
        Breakpoint {
            index: 250,
            left: 0.0,
            right: 6.0,
        },
        Breakpoint {
            index: 1500,
            left: 6.0,
            right: 6.0,
        },
        Breakpoint {
            index: 4500,
            left: paper_input(9.0 - 1e-12),
            right: paper_input(9.0),
        },
    ];
    let input = SampledInput {
        values: &force,
        breakpoints: &breakpoints,
    };
    let sim = ExactSimulator::new(&model(), DT, Hold::Cubic).expect("valid model");
    let phi = *sim.transition();
    let gamma = SVector::<f64, 2>::new(1e-6, 1e-3);

    let mut group = c.benchmark_group("paper_simulation_7501");
    group.bench_function("floor_bare_recurrence", |b| {
        b.iter(|| {
            let mut x = SVector::<f64, 2>::zeros();
            let mut acc = 0.0;
            for &u in black_box(&force).iter() {
                x = phi * x + gamma * u;
                acc += x[0];
            }
            acc
        })
    });
    group.bench_function("exact_cubic_hold", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            sim.simulate_with(&SVector::zeros(), black_box(&input), |_, x| acc += x[0])
                .expect("simulates");
            acc
        })
    });
    group.bench_function("exact_discretisation_and_simulation", |b| {
        b.iter(|| {
            let sim = ExactSimulator::new(black_box(&model()), DT, Hold::Cubic).expect("valid");
            let mut acc = 0.0;
            sim.simulate_with(&SVector::zeros(), &input, |_, x| acc += x[0])
                .expect("simulates");
            acc
        })
    });
    let options = Ode45Options {
        rel_tol: 1e-6,
        abs_tol: 1e-9,
        ..Ode45Options::default()
    };
    group.bench_function("ode45_rtol_1e-6", |b| {
        b.iter(|| {
            let mut rhs = |t: f64, y: &SVector<f64, 2>, d: &mut SVector<f64, 2>| {
                d[0] = y[1];
                d[1] = (paper_input(t) - C * y[1] - K * y[0]) / M;
            };
            let mut acc = 0.0;
            ode45_with(
                &mut rhs,
                black_box(&grid),
                &SVector::zeros(),
                &options,
                |_, y| acc += y[0],
            )
            .expect("solves");
            acc
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
