//! The output-error problem of the nonlinear estimator: the scaled parameters, the
//! residuals and their Jacobian from the forward sensitivities, the statistics at the
//! optimum, and the initial-state fit of a fixed model.

use super::estimate::NonlinearOptions;
use super::model::{Forces, ModelStructure, NonlinearParameters};
use super::rk4::Columns;
use super::simulate::{NonlinearSimulation, NonlinearSolver, Simulator, checked_forces};
use crate::correlation::autocorrelation;
use crate::least_squares::SingularError;
use crate::residuals::ljung_box;
use crate::residuals::sandwich::{BLOCKS, CovarianceUsed, ResidualCovariance, block_sandwich};
use crate::{
    data::DataSet,
    error::{IdentError, Result},
    params::{InitialState, Parameters},
};
use msd_opt::statistics::Interval;
use msd_opt::statistics::{Linearization, correlation};
use msd_opt::{LeastSquaresProblem, LevenbergMarquardtOptions, levenberg_marquardt};
use nalgebra::{DMatrix, DVector};

/// The map between physical parameters θ and scaled parameters z: z = ln θ for m, c, k;
/// z = θ/s for the nonlinear coefficients and the initial state.
#[derive(Debug, Clone)]
pub(super) struct Scaling {
    pub structure: ModelStructure,
    /// s for every linear-scaled entry (unused for the log ones).
    scale: Vec<f64>,
    pub estimate_initial_state: bool,
    fixed_initial: InitialState,
}

impl Scaling {
    pub fn new(
        structure: ModelStructure,
        start: &Parameters,
        data: &DataSet,
        options: &NonlinearOptions,
    ) -> Self {
        let y_rms = rms(&data.output).max(f64::MIN_POSITIVE);
        let omega = start.natural_frequency();
        let v_rms = y_rms * omega;
        let mut scale = vec![1.0; 3];
        for name in structure.parameter_names().iter().skip(3) {
            scale.push(match *name {
                // Force of the size of the viscous force at the typical speed.
                "coulomb_force" => (start.damping * v_rms).max(start.stiffness * y_rms * 1e-2),
                // c₂·v_rms² equal to c·v_rms.
                "quadratic_damping" => {
                    (start.damping / v_rms).max(start.stiffness * 1e-2 / (v_rms * omega))
                }
                // k₃·x_rms² equal to k.
                _ => start.stiffness / (y_rms * y_rms),
            });
        }
        if options.estimate_initial_state {
            scale.push(y_rms);
            scale.push(v_rms);
        }
        Self {
            structure,
            scale,
            estimate_initial_state: options.estimate_initial_state,
            fixed_initial: options.initial_state,
        }
    }

    pub fn len(&self) -> usize {
        self.scale.len()
    }

    pub fn to_z(&self, p: &NonlinearParameters, initial: InitialState) -> Vec<f64> {
        let mut z: Vec<f64> = p
            .values
            .iter()
            .enumerate()
            .map(|(i, &v)| if i < 3 { v.ln() } else { v / self.scale[i] })
            .collect();
        if self.estimate_initial_state {
            let n = z.len();
            z.push(initial.displacement / self.scale[n]);
            z.push(initial.velocity / self.scale[n + 1]);
        }
        z
    }

    /// θ from z (no range check).
    pub fn physical(&self, z: &[f64]) -> (NonlinearParameters, InitialState) {
        let np = self.structure.parameter_count();
        let values = (0..np)
            .map(|i| {
                if i < 3 {
                    z[i].exp()
                } else {
                    z[i] * self.scale[i]
                }
            })
            .collect();
        let initial = if self.estimate_initial_state {
            InitialState {
                displacement: z[np] * self.scale[np],
                velocity: z[np + 1] * self.scale[np + 1],
            }
        } else {
            self.fixed_initial
        };
        (
            NonlinearParameters {
                structure: self.structure,
                values,
            },
            initial,
        )
    }

    /// dθ_i/dz_i.
    pub fn derivative(&self, z: &[f64]) -> Vec<f64> {
        (0..z.len())
            .map(|i| if i < 3 { z[i].exp() } else { self.scale[i] })
            .collect()
    }
}

fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len().max(1) as f64).sqrt()
}

/// Output error ŷ − y in the scaled parameters z: the residuals by the simulator, the
/// Jacobian ∂ŷ/∂z from the forward sensitivities (one augmented RK4 simulation).
pub(super) struct OutputError<'a> {
    scaling: &'a Scaling,
    pub data: &'a DataSet,
    pub simulator: Simulator<'a>,
    pub smoothing: f64,
    /// The model output of a sensitivity run (the Jacobian's by-product).
    output: Vec<f64>,
    /// Simulations run, augmented ones included.
    pub simulations: usize,
}

impl<'a> OutputError<'a> {
    pub fn new(
        scaling: &'a Scaling,
        data: &'a DataSet,
        simulator: Simulator<'a>,
        smoothing: f64,
    ) -> Self {
        Self {
            scaling,
            data,
            simulator,
            smoothing,
            output: vec![0.0; data.len()],
            simulations: 0,
        }
    }

    /// The forces and initial state at z; `None` outside the physical range.
    pub fn point(&self, z: &[f64]) -> Option<(Forces, InitialState)> {
        let (p, initial) = self.scaling.physical(z);
        p.validate().ok()?;
        let finite = initial.displacement.is_finite() && initial.velocity.is_finite();
        finite.then(|| (Forces::new(&p, self.smoothing), initial))
    }

    /// Σ(ŷ − y)² at z, +∞ where the model cannot be simulated.
    pub fn sse(&mut self, z: &[f64], buffer: &mut [f64]) -> f64 {
        if self.residuals(z, buffer) {
            buffer.iter().map(|v| v * v).sum()
        } else {
            f64::INFINITY
        }
    }
}

impl LeastSquaresProblem for OutputError<'_> {
    fn residual_count(&self) -> usize {
        self.data.len()
    }

    fn residuals(&mut self, z: &[f64], out: &mut [f64]) -> bool {
        let Some((forces, initial)) = self.point(z) else {
            return false;
        };
        self.simulations += 1;
        if self.simulator.output(&forces, initial, out).is_err() {
            return false;
        }
        for (o, y) in out.iter_mut().zip(&self.data.output) {
            *o -= y;
        }
        true
    }

    fn jacobian(&mut self, z: &[f64], out: &mut DMatrix<f64>) -> bool {
        let Some((forces, initial)) = self.point(z) else {
            return false;
        };
        self.simulations += 1;
        let scale = self.scaling.derivative(z);
        let np = self.scaling.structure.parameter_count();
        let state = self
            .scaling
            .estimate_initial_state
            .then(|| [scale[np], scale[np + 1]]);
        let columns = Columns::new(&forces, &scale[..np], state);
        let rk4 = &self.simulator.rk4;
        rk4.sensitivities(
            &forces,
            initial,
            &columns,
            &mut self.output,
            out.as_mut_slice(),
        );
        // Supplied even when not finite: the solver then stops, saying so.
        true
    }
}

/// The model at the optimum: ŷ, ŷ − y and the Jacobian ∂ŷ/∂z.
pub(super) struct AtOptimum {
    pub output: Vec<f64>,
    pub residuals: Vec<f64>,
    pub jacobian: DMatrix<f64>,
}

pub(super) fn at_optimum(problem: &mut OutputError<'_>, z: &[f64]) -> Result<AtOptimum> {
    let n = problem.data.len();
    let structure = problem.scaling.structure;
    let mut residuals = vec![0.0; n];
    if !problem.residuals(z, &mut residuals) {
        return Err(IdentError::EstimationFailed {
            reason: format!("{structure}: the model cannot be simulated at the optimum"),
        });
    }
    let mut jacobian = DMatrix::<f64>::zeros(n, z.len());
    if !(problem.jacobian(z, &mut jacobian) && jacobian.iter().all(|v| v.is_finite())) {
        return Err(IdentError::EstimationFailed {
            reason: format!("{structure}: the sensitivities cannot be simulated at the optimum"),
        });
    }
    let output = residuals
        .iter()
        .zip(&problem.data.output)
        .map(|(r, y)| r + y)
        .collect();
    Ok(AtOptimum {
        output,
        residuals,
        jacobian,
    })
}

/// Under RK4, the output's error by step doubling: RK4's error falls 2⁴-fold when the
/// sub-steps double, so ŷ(M) − y = 16/15·(ŷ(M) − ŷ(2M)) to leading order. `None` under
/// ode45.
pub(super) fn step_doubling(
    problem: &OutputError<'_>,
    parameters: &NonlinearParameters,
    initial: InitialState,
    output: &[f64],
) -> Result<Option<f64>> {
    if problem.simulator.solver != NonlinearSolver::Rk4 {
        return Ok(None);
    }
    let mut fine = problem.simulator.rk4.clone();
    fine.set_steps(2 * fine.steps());
    let mut doubled = vec![0.0; output.len()];
    fine.simulate(
        &Forces::new(parameters, problem.smoothing),
        initial,
        &mut doubled,
    );
    let worst = output
        .iter()
        .zip(&doubled)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    Ok(Some(16.0 / 15.0 * worst))
}

/// The Gauss–Newton statistics at the optimum.
pub(super) struct Statistics {
    pub sse: f64,
    pub dof: usize,
    pub sigma2: f64,
    pub covariance: DMatrix<f64>,
    pub correlation: DMatrix<f64>,
    pub condition_number: f64,
    t: f64,
    /// The covariance reported and why; with the sandwich, the white-noise covariance
    /// and its t beside it.
    pub used: CovarianceUsed,
    pub white: Option<(DMatrix<f64>, f64)>,
}

impl Statistics {
    /// σ̂² = SSE/(N − p), covariance σ̂²·D(JᵀJ)⁻¹D, the correlation and the condition
    /// number of JᵀJ with unit-norm columns (refused at 10¹⁴, as every fit does).
    pub fn new(
        at: &AtOptimum,
        scaling: &Scaling,
        z: &[f64],
        structure: ModelStructure,
        treatment: ResidualCovariance,
    ) -> Result<Self> {
        let (n, p) = at.jacobian.shape();
        let sse: f64 = at.residuals.iter().map(|v| v * v).sum();
        let dof = n - p;
        let sigma2 = sse / dof as f64;
        let mut names = structure.parameter_names();
        names.extend(["x0", "v0"]);
        names.truncate(p);
        let linearization = Linearization::new(&at.jacobian)
            .map_err(|e| e.error(&format!("the record ({structure})"), &names))?;
        // In the physical parameters θ = θ(z): D·Cov(z)·D with D = dθ/dz diagonal.
        let d = scaling.derivative(z);
        let physical =
            |in_z: &DMatrix<f64>| DMatrix::from_fn(p, p, |r, c| d[r] * in_z[(r, c)] * d[c]);
        let white = physical(&linearization.covariance(sigma2));
        let lags = crate::residuals::ResidualOptions::default()
            .max_lag
            .min(n / 5)
            .max(1);
        let whiteness_p = ljung_box(&autocorrelation(&at.residuals, lags), n).p_value;
        let sandwich = match treatment {
            ResidualCovariance::White => false,
            ResidualCovariance::Sandwich => true,
            ResidualCovariance::Auto => whiteness_p < 0.01,
        } && n >= 2 * BLOCKS;
        let used = CovarianceUsed {
            sandwich,
            blocks: BLOCKS,
            whiteness_p,
        };
        let t_white = crate::uncertainty::t_975(dof);
        let (covariance, t, white) = if sandwich {
            let bread = linearization.covariance(1.0);
            let r = DVector::from_column_slice(&at.residuals);
            let in_z = block_sandwich(&at.jacobian, &r, &bread, BLOCKS);
            let t = crate::uncertainty::t_975(BLOCKS - 1);
            (physical(&in_z), t, Some((white, t_white)))
        } else {
            (white, t_white, None)
        };
        let correlation = correlation(&covariance);
        Ok(Self {
            sse,
            dof,
            sigma2,
            condition_number: linearization.condition_number,
            covariance,
            correlation,
            t,
            used,
            white,
        })
    }

    /// With the sandwich: the intervals s²·(JᵀJ)⁻¹ would have given.
    pub fn white_intervals(&self, parameters: &NonlinearParameters) -> Option<Vec<Interval>> {
        let (cov, t) = self.white.as_ref()?;
        Some(
            (parameters.values.iter().enumerate())
                .map(|(i, &v)| Interval::new(v, cov[(i, i)].max(0.0).sqrt(), *t))
                .collect(),
        )
    }

    /// The intervals of the parameters, and of the initial state when estimated.
    pub fn intervals(
        &self,
        parameters: &NonlinearParameters,
        initial: InitialState,
        with_state: bool,
    ) -> (Vec<Interval>, Option<[Interval; 2]>) {
        let np = parameters.values.len();
        let values = parameters.values.iter();
        let intervals = values
            .enumerate()
            .map(|(i, &v)| self.interval(i, v))
            .collect();
        let state = with_state.then(|| {
            [
                self.interval(np, initial.displacement),
                self.interval(np + 1, initial.velocity),
            ]
        });
        (intervals, state)
    }

    /// The interval of estimated quantity `i` at `value`.
    fn interval(&self, i: usize, value: f64) -> Interval {
        Interval::new(value, self.covariance[(i, i)].max(0.0).sqrt(), self.t)
    }
}

/// x(t₀), x'(t₀) of the fixed model `parameters` fitted to `data` by Levenberg–Marquardt,
/// in units of the output's RMS and RMS·ωₙ, the Jacobian from the state's sensitivities
/// (finite differences would drown in an adaptive solver's error). For
/// [`fit_initial_state`](super::fit_initial_state).
pub(crate) fn fit_state(
    parameters: &NonlinearParameters,
    data: &DataSet,
    simulation: &NonlinearSimulation,
    smoothing_velocity: f64,
) -> Result<InitialState> {
    let forces = checked_forces(parameters, simulation, smoothing_velocity)?;
    let y_rms = rms(&data.output).max(f64::MIN_POSITIVE);
    let scale = [y_rms, y_rms * parameters.linear_part().natural_frequency()];
    let mut simulator = Simulator::new(&data.excitation, simulation)?;
    let start = InitialState {
        displacement: data.output[0],
        velocity: 0.0,
    };
    let mut buffer = vec![0.0; data.len()];
    simulator.fit_steps(&forces, start, &mut buffer)?;
    let mut problem = StateFit {
        simulator,
        forces,
        columns: Columns::new(&forces, &[], Some(scale)),
        scale,
        output: &data.output,
        buffer,
    };
    let z0 = [start.displacement / scale[0], 0.0];
    let r = levenberg_marquardt(&mut problem, &z0, &LevenbergMarquardtOptions::default())?;
    Ok(problem.state(&r.x))
}

/// The initial state's least-squares problem of [`fit_state`].
struct StateFit<'a> {
    simulator: Simulator<'a>,
    forces: Forces,
    columns: Columns,
    scale: [f64; 2],
    output: &'a [f64],
    buffer: Vec<f64>,
}

impl StateFit<'_> {
    fn state(&self, z: &[f64]) -> InitialState {
        InitialState {
            displacement: z[0] * self.scale[0],
            velocity: z[1] * self.scale[1],
        }
    }
}

impl LeastSquaresProblem for StateFit<'_> {
    fn residual_count(&self) -> usize {
        self.output.len()
    }

    fn residuals(&mut self, z: &[f64], out: &mut [f64]) -> bool {
        let ok = self
            .simulator
            .output(&self.forces, self.state(z), out)
            .is_ok();
        for (o, y) in out.iter_mut().zip(self.output) {
            *o -= y;
        }
        ok
    }

    fn jacobian(&mut self, z: &[f64], out: &mut DMatrix<f64>) -> bool {
        let state = self.state(z);
        let rk4 = &self.simulator.rk4;
        rk4.sensitivities(
            &self.forces,
            state,
            &self.columns,
            &mut self.buffer,
            out.as_mut_slice(),
        );
        // Supplied even when not finite: the solver then stops, saying so.
        true
    }
}
