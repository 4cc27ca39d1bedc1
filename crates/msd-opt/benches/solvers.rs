//! Criterion benchmarks: Nelder–Mead and Levenberg–Marquardt on Rosenbrock and on
//! a 3-parameter least-squares fit (y = a·exp(−b·t)·cos(c·t), 200 samples).
//!
//! The costs here take well under a microsecond, so the time per evaluation
//! (printed once per benchmark) is an upper bound on the solver's own overhead,
//! to compare with one cost evaluation of the paper's problem (about 20 µs).

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_main};
use msd_opt::{
    LeastSquaresProblem, LevenbergMarquardtOptions, NelderMeadOptions, levenberg_marquardt,
    nelder_mead,
};
use nalgebra::DMatrix;

fn rosenbrock(x: &[f64]) -> f64 {
    100.0 * (x[1] - x[0] * x[0]).powi(2) + (1.0 - x[0]).powi(2)
}

struct RosenbrockLs;

impl LeastSquaresProblem for RosenbrockLs {
    fn residual_count(&self) -> usize {
        2
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        r[0] = 10.0 * (x[1] - x[0] * x[0]);
        r[1] = 1.0 - x[0];
        true
    }
    fn jacobian(&mut self, x: &[f64], j: &mut DMatrix<f64>) -> bool {
        j[(0, 0)] = -20.0 * x[0];
        j[(0, 1)] = 10.0;
        j[(1, 0)] = -1.0;
        j[(1, 1)] = 0.0;
        true
    }
}

/// y = a·exp(−b·t)·cos(c·t) sampled at 200 points, exact data from (2, 0.3, 4).
struct DecayFit {
    t: Vec<f64>,
    y: Vec<f64>,
}

impl DecayFit {
    fn new() -> Self {
        let t: Vec<f64> = (0..200).map(|i| i as f64 * 0.025).collect();
        let y = t
            .iter()
            .map(|&t| 2.0 * (-0.3 * t).exp() * (4.0 * t).cos())
            .collect();
        Self { t, y }
    }
    fn sum_of_squares(&self, x: &[f64]) -> f64 {
        self.t
            .iter()
            .zip(&self.y)
            .map(|(&t, &y)| (x[0] * (-x[1] * t).exp() * (x[2] * t).cos() - y).powi(2))
            .sum()
    }
}

impl LeastSquaresProblem for DecayFit {
    fn residual_count(&self) -> usize {
        self.t.len()
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        for ((ri, &t), &y) in r.iter_mut().zip(&self.t).zip(&self.y) {
            *ri = x[0] * (-x[1] * t).exp() * (x[2] * t).cos() - y;
        }
        true
    }
    fn jacobian(&mut self, x: &[f64], j: &mut DMatrix<f64>) -> bool {
        for (i, &t) in self.t.iter().enumerate() {
            let e = (-x[1] * t).exp();
            let (s, c) = (x[2] * t).sin_cos();
            j[(i, 0)] = e * c;
            j[(i, 1)] = -x[0] * t * e * c;
            j[(i, 2)] = -x[0] * t * e * s;
        }
        true
    }
}

/// Prints the mean time per cost evaluation of one solve, repeated.
fn per_evaluation(name: &str, evaluations: usize, mut solve: impl FnMut()) {
    let reps = 200;
    let start = Instant::now();
    for _ in 0..reps {
        solve();
    }
    let per = start.elapsed().as_secs_f64() / (reps * evaluations) as f64;
    println!(
        "{name}: {evaluations} evaluations, {:.3} µs per evaluation",
        per * 1e6
    );
}

fn benches(c: &mut Criterion) {
    let nm = NelderMeadOptions::default();
    let lm = LevenbergMarquardtOptions::default();
    let x0 = [-1.2, 1.0];
    let fit = DecayFit::new();
    let fit_x0 = [1.5, 0.2, 3.8];

    let evals = nelder_mead(rosenbrock, &x0, &nm).unwrap().evaluations;
    per_evaluation("nelder_mead/rosenbrock", evals, || {
        black_box(nelder_mead(rosenbrock, &x0, &nm).unwrap());
    });
    c.bench_function("nelder_mead/rosenbrock", |b| {
        b.iter(|| nelder_mead(rosenbrock, black_box(&x0), &nm).unwrap())
    });

    let evals = nelder_mead(|x| fit.sum_of_squares(x), &fit_x0, &nm)
        .unwrap()
        .evaluations;
    per_evaluation("nelder_mead/decay_fit", evals, || {
        black_box(nelder_mead(|x| fit.sum_of_squares(x), &fit_x0, &nm).unwrap());
    });
    c.bench_function("nelder_mead/decay_fit", |b| {
        b.iter(|| nelder_mead(|x| fit.sum_of_squares(x), black_box(&fit_x0), &nm).unwrap())
    });

    let r = levenberg_marquardt(&mut RosenbrockLs, &x0, &lm).unwrap();
    per_evaluation(
        "levenberg_marquardt/rosenbrock",
        r.evaluations + r.jacobian_evaluations,
        || {
            black_box(levenberg_marquardt(&mut RosenbrockLs, &x0, &lm).unwrap());
        },
    );
    c.bench_function("levenberg_marquardt/rosenbrock", |b| {
        b.iter(|| levenberg_marquardt(&mut RosenbrockLs, black_box(&x0), &lm).unwrap())
    });

    let mut fit_ls = DecayFit::new();
    let r = levenberg_marquardt(&mut fit_ls, &fit_x0, &lm).unwrap();
    per_evaluation(
        "levenberg_marquardt/decay_fit",
        r.evaluations + r.jacobian_evaluations,
        || {
            black_box(levenberg_marquardt(&mut fit_ls, &fit_x0, &lm).unwrap());
        },
    );
    c.bench_function("levenberg_marquardt/decay_fit", |b| {
        b.iter(|| levenberg_marquardt(&mut fit_ls, black_box(&fit_x0), &lm).unwrap())
    });
}

/// The group lives in a private module: `criterion_group!` makes a public function.
mod group {
    use super::benches;
    criterion::criterion_group!(solvers, benches);
}

criterion_main!(group::solvers);
