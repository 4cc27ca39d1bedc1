//! The cost (Nelder–Mead) and the residual problem (Levenberg–Marquardt).

use super::layout::Layout;
use crate::{
    data::DataSet,
    sensitivity::sensitivities,
    simulate::{Backend, simulate_into},
};
use msd_ode::Hold;
use msd_opt::LeastSquaresProblem;
use nalgebra::DMatrix;

/// J(v) = Σ (y − x̂ − offset)² with x̂ from `backend`; +∞ outside the physical region or
/// when the simulation fails, never NaN.
pub(crate) struct Cost<'a> {
    pub data: &'a DataSet,
    pub layout: &'a Layout,
    pub backend: Backend,
    pub model: Vec<f64>,
    pub simulations: usize,
}

impl<'a> Cost<'a> {
    pub(crate) fn new(data: &'a DataSet, layout: &'a Layout, backend: Backend) -> Self {
        Self {
            data,
            layout,
            backend,
            model: vec![0.0; data.len()],
            simulations: 0,
        }
    }

    /// Simulates the model output for `v` into `self.model`; false if not physical or if
    /// the simulation failed.
    pub(crate) fn simulate(&mut self, v: &[f64]) -> bool {
        let (theta, state, offset) = self.layout.unpack(v);
        let positive = theta.mass > 0.0 && theta.damping > 0.0 && theta.stiffness > 0.0;
        if !positive
            || theta.validate().is_err()
            || !state.displacement.is_finite()
            || !state.velocity.is_finite()
            || !offset.is_finite()
        {
            return false;
        }
        self.simulations += 1;
        if simulate_into(
            &theta,
            &self.data.excitation,
            state,
            &self.backend,
            &mut self.model,
        )
        .is_err()
        {
            return false;
        }
        for m in &mut self.model {
            *m += offset;
        }
        true
    }

    pub(crate) fn sse(&mut self, v: &[f64]) -> f64 {
        if !self.simulate(v) {
            return f64::INFINITY;
        }
        let sse: f64 = self
            .data
            .output
            .iter()
            .zip(&self.model)
            .map(|(y, m)| (y - m).powi(2))
            .sum();
        if sse.is_finite() { sse } else { f64::INFINITY }
    }
}

/// Residuals r = y − x̂ − offset in the layout's (log-)parameters, with the exact
/// Jacobian from the sensitivity equations.
pub(crate) struct Residuals<'a> {
    pub cost: Cost<'a>,
    pub hold: Hold,
    pub jacobians: usize,
}

impl LeastSquaresProblem for Residuals<'_> {
    fn residual_count(&self) -> usize {
        self.cost.data.len()
    }

    fn residuals(&mut self, x: &[f64], out: &mut [f64]) -> bool {
        if !self.cost.simulate(x) {
            return false;
        }
        for ((r, y), m) in out
            .iter_mut()
            .zip(&self.cost.data.output)
            .zip(&self.cost.model)
        {
            *r = y - m;
        }
        out.iter().all(|r| r.is_finite())
    }

    fn jacobian(&mut self, x: &[f64], out: &mut DMatrix<f64>) -> bool {
        let layout = self.cost.layout;
        let (theta, state, _) = layout.unpack(x);
        self.jacobians += 1;
        // ∂r/∂ln θ = −θ ∂x/∂θ; ∂r/∂(initial state) = −∂x/∂(initial state); ∂r/∂offset = −1.
        let values = theta.to_array();
        let ok = fill_jacobian(
            self.cost.data,
            layout,
            theta,
            state,
            self.hold,
            out,
            |p| -values[p],
            -1.0,
        );
        ok && out.iter().all(|v| v.is_finite())
    }
}

#[allow(clippy::too_many_arguments)]
/// Fills `out` (N × layout.len(), column-major) with the sensitivities of the model
/// output, column j of parameter p scaled by `parameter_scale(p)`, the state and offset
/// columns by `sign`.
fn fill_jacobian(
    data: &DataSet,
    layout: &Layout,
    theta: crate::params::Parameters,
    state: crate::params::InitialState,
    hold: Hold,
    out: &mut DMatrix<f64>,
    parameter_scale: impl Fn(usize) -> f64,
    sign: f64,
) -> bool {
    let n = data.len();
    debug_assert_eq!(out.shape(), (n, layout.len()));
    let free: Vec<(usize, f64)> = layout.free().map(|p| (p, parameter_scale(p))).collect();
    let nfree = free.len();
    let (has_state, has_offset) = (layout.has_state(), layout.has_offset());
    let columns = out.as_mut_slice();
    let result = sensitivities(&theta, &data.excitation, state, hold, |i, s| {
        for (column, &(p, scale)) in free.iter().enumerate() {
            columns[column * n + i] = scale * s.parameters[p];
        }
        if has_state {
            columns[nfree * n + i] = sign * s.initial_state[0];
            columns[(nfree + 1) * n + i] = sign * s.initial_state[1];
        }
        if has_offset {
            columns[(nfree + 2 * usize::from(has_state)) * n + i] = sign;
        }
    });
    result.is_ok()
}

/// The Jacobian of the model output with respect to the raw estimated quantities
/// (m, c, k as they are, initial state, offset), for the covariance.
pub(crate) fn output_jacobian(
    data: &DataSet,
    layout: &Layout,
    v_raw: &[f64],
) -> crate::error::Result<DMatrix<f64>> {
    let (theta, state, _) = layout.unpack(v_raw);
    theta.validate()?;
    let mut j = DMatrix::<f64>::zeros(data.len(), layout.len());
    if !fill_jacobian(
        data,
        layout,
        theta,
        state,
        Hold::Cubic,
        &mut j,
        |_| 1.0,
        1.0,
    ) {
        return Err(crate::error::IdentError::EstimationFailed {
            reason: "the sensitivities cannot be simulated at the estimate".into(),
        });
    }
    Ok(j)
}
