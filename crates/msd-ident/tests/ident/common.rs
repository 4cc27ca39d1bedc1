//! Shared helpers: the Cramér–Rao bound of the paper experiment.
#![allow(dead_code)]

use msd_ident::sensitivity::sensitivities;
use msd_ident::{DataSet, InitialState, Parameters};
use msd_ode::Hold;
use nalgebra::{DMatrix, Matrix3};

/// Cramér–Rao bound σ²(JᵀJ)⁻¹ of (m, c, k) for white Gaussian output noise of std `sigma`,
/// from the exact sensitivities at the true parameters.
pub fn cramer_rao(truth: &Parameters, data: &DataSet, sigma: f64) -> Matrix3<f64> {
    let n = data.len();
    let mut j = DMatrix::<f64>::zeros(n, 3);
    sensitivities(
        truth,
        &data.excitation,
        InitialState::REST,
        Hold::Cubic,
        |i, s| {
            for p in 0..3 {
                j[(i, p)] = s.parameters[p];
            }
        },
    )
    .expect("sensitivities");
    let fisher = j.transpose() * j / (sigma * sigma);
    let fisher = Matrix3::from_fn(|r, c| fisher[(r, c)]);
    fisher.try_inverse().expect("identifiable")
}

/// Standard deviations √diag of the bound.
pub fn crb_std(crb: &Matrix3<f64>) -> [f64; 3] {
    [crb[(0, 0)].sqrt(), crb[(1, 1)].sqrt(), crb[(2, 2)].sqrt()]
}
