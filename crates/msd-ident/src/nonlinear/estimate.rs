//! Estimation of a nonlinear model's parameters by output error on ode45 simulations.

use super::model::{ModelStructure, NonlinearParameters};
use super::simulate::{NonlinearSimulation, simulate_nonlinear};
use crate::local::Local;
use crate::{
    DataSet, EstimationOptions, FitMetrics, IdentError, InitialState, Interval, Parameters, Result,
    StopReason, estimate,
};
use msd_opt::{
    Bounds, FiniteDifference, LevenbergMarquardtOptions, MultistartOptions, NelderMeadOptions,
    ResidualFn, levenberg_marquardt, multistart, nelder_mead,
};
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};
use std::time::{Duration, Instant};

/// The optimiser of [`estimate_nonlinear`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NonlinearMethod {
    /// Levenberg–Marquardt with a central finite-difference Jacobian.
    #[default]
    LevenbergMarquardt,
    /// Nelder–Mead (fminsearch) on the sum of squares.
    NelderMead,
}

/// Multistart of [`estimate_nonlinear`]: local runs from a Latin hypercube around the
/// start, in the scaled parameters.
///
/// By default 8 starts, ±0.5 decades for m, c, k, ±1 scale unit for the nonlinear
/// coefficients, seed 0, 2 threads.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NonlinearMultistart {
    /// Number of starts (the first is the nominal start). By default 8.
    pub starts: usize,
    /// Half-width of the box for m, c, k in decades. By default 0.5.
    pub decades: f64,
    /// Half-width of the box for the nonlinear coefficients in scale units (see the
    /// module doc). By default 1.
    pub nonlinear_width: f64,
    /// Seed of the design. By default 0.
    pub seed: u64,
    /// Threads. By default 2.
    pub threads: usize,
}

impl Default for NonlinearMultistart {
    fn default() -> Self {
        Self {
            starts: 8,
            decades: 0.5,
            nonlinear_width: 1.0,
            seed: 0,
            threads: 2,
        }
    }
}

/// Options of [`estimate_nonlinear`].
///
/// | field | default |
/// |---|---|
/// | `method` | Levenberg–Marquardt |
/// | `simulation` | [`NonlinearSimulation::default`] (ode45 1e-8/1e-12, v_s = 1e-3 × RMS velocity) |
/// | `linear_start` | `None`: the fast linear estimate (LM, exact simulation, ARX guess) |
/// | `initial_state` | at rest |
/// | `estimate_initial_state` | false |
/// | `levenberg_marquardt` | MINPACK defaults with central differences (relative step 1e-4) and at most 20·(p + 1) evaluations when `max_evaluations` is `None` |
/// | `nelder_mead` | fminsearch defaults with relative tolerances 1e-8 |
/// | `multistart` | `None` |
/// | `dissipative_damping` | true: F_c ≥ 0, c₂ ≥ 0 |
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NonlinearOptions {
    /// The optimiser. By default Levenberg–Marquardt.
    pub method: NonlinearMethod,
    /// The simulator. By default [`NonlinearSimulation::default`].
    pub simulation: NonlinearSimulation,
    /// Linear parameters to start from (nonlinear coefficients start at 0). `None`:
    /// [`estimate`] with its default (fast) options. By default `None`.
    pub linear_start: Option<Parameters>,
    /// The initial state (or its start value when estimated). By default at rest.
    pub initial_state: InitialState,
    /// Estimate x(t₀) and x'(t₀) with the parameters. By default false.
    pub estimate_initial_state: bool,
    /// Levenberg–Marquardt settings.
    pub levenberg_marquardt: LevenbergMarquardtOptions,
    /// Nelder–Mead settings.
    pub nelder_mead: NelderMeadOptions,
    /// Multistart, or `None` for one local run. By default `None`.
    pub multistart: Option<NonlinearMultistart>,
    /// Keep F_c ≥ 0 and c₂ ≥ 0 (dissipative friction) by bounds in Levenberg–Marquardt
    /// and in the multistart box; Nelder–Mead runs unbounded. Without it an estimate may
    /// take a negative coefficient, whose prediction can diverge. By default true.
    pub dissipative_damping: bool,
}

impl Default for NonlinearOptions {
    fn default() -> Self {
        Self {
            method: NonlinearMethod::LevenbergMarquardt,
            simulation: NonlinearSimulation::default(),
            linear_start: None,
            initial_state: InitialState::REST,
            estimate_initial_state: false,
            levenberg_marquardt: LevenbergMarquardtOptions {
                finite_difference: FiniteDifference::Central,
                finite_difference_step: Some(1e-4),
                ..LevenbergMarquardtOptions::default()
            },
            nelder_mead: NelderMeadOptions {
                x_tolerance: 1e-8,
                f_tolerance: 1e-8,
                relative_tolerances: true,
                adaptive: true,
                ..NelderMeadOptions::default()
            },
            multistart: None,
            dissipative_damping: true,
        }
    }
}

/// The result of [`estimate_nonlinear`].
///
/// Serializes every field, the matrices as lists of rows and the wall time as
/// `wall_time_s` in seconds. Displays the model, each parameter with its interval, the
/// fit, the counts and why the estimator stopped.
#[derive(Debug, Clone, Serialize)]
pub struct NonlinearEstimate {
    /// θ̂.
    pub parameters: NonlinearParameters,
    /// Intervals of the parameters, in the order of their names.
    pub intervals: Vec<Interval>,
    /// The initial state used (estimated when asked).
    pub initial_state: InitialState,
    /// Intervals of x(t₀), x'(t₀) when estimated.
    pub initial_state_intervals: Option<[Interval; 2]>,
    /// Covariance of the physical parameters (and initial state, last, when
    /// estimated): σ̂²·D(JᵀJ)⁻¹D with J the Jacobian in the scaled parameters and D
    /// the derivative of the physical by the scaled parameters.
    #[serde(serialize_with = "crate::ser::matrix_rows")]
    pub covariance: DMatrix<f64>,
    /// Correlation matrix of the estimated quantities (same order as `covariance`).
    #[serde(serialize_with = "crate::ser::matrix_rows")]
    pub correlation: DMatrix<f64>,
    /// Condition number of JᵀJ with its columns scaled to unit norm (unit-free; large
    /// values mean nearly collinear sensitivities, i.e. poorly separable terms).
    pub condition_number: f64,
    /// σ̂ = √(SSE/(N − p)).
    pub sigma: f64,
    /// N − p.
    pub degrees_of_freedom: usize,
    /// Number of estimated quantities p (parameters plus initial state).
    pub estimated: usize,
    /// Σ(y − ŷ)².
    pub sse: f64,
    /// Fit on the estimation data.
    pub fit: FitMetrics,
    /// ŷ on the estimation data.
    pub model_output: Vec<f64>,
    /// y − ŷ.
    pub residuals: Vec<f64>,
    /// The Coulomb smoothing velocity used.
    pub smoothing_velocity: f64,
    /// The linear start.
    pub linear_start: Parameters,
    /// The optimiser.
    pub method: NonlinearMethod,
    /// Starts (1 without multistart).
    pub starts: usize,
    /// Iterations of the best run.
    pub iterations: usize,
    /// Simulations in total (all starts, finite differences and covariance included).
    pub simulations: usize,
    /// Why the best run stopped, and whether it met its convergence test
    /// ([`StopReason::converged`]).
    pub stop: StopReason,
    /// Wall-clock time (serialized as `wall_time_s`, in seconds).
    #[serde(rename = "wall_time_s", serialize_with = "crate::ser::seconds")]
    pub wall_time: Duration,
}

impl std::fmt::Display for NonlinearEstimate {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "model {}", self.parameters.structure)?;
        for (name, i) in self.parameters.names().iter().zip(&self.intervals) {
            writeln!(
                f,
                "  {name:<18} = {:>14.6e} ± {:.3e}  (95 % [{:.6e}, {:.6e}])",
                i.value, i.standard_error, i.ci95[0], i.ci95[1]
            )?;
        }
        writeln!(
            f,
            "  SSE = {:.6e}, σ̂ = {:.4e}, fit {:.2} %, {} simulations, {:.2?}, {}",
            self.sse, self.sigma, self.fit.fit_percent, self.simulations, self.wall_time, self.stop
        )
    }
}

/// The map between physical parameters θ and scaled parameters z: z = ln θ for m, c, k;
/// z = θ/s for the nonlinear coefficients and the initial state.
#[derive(Debug, Clone)]
struct Scaling {
    structure: ModelStructure,
    /// s for every linear-scaled entry (unused for the log ones).
    scale: Vec<f64>,
    estimate_initial_state: bool,
    fixed_initial: InitialState,
}

impl Scaling {
    fn new(
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

    fn len(&self) -> usize {
        self.scale.len()
    }

    fn to_z(&self, p: &NonlinearParameters, initial: InitialState) -> Vec<f64> {
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
    fn physical(&self, z: &[f64]) -> (NonlinearParameters, InitialState) {
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
    fn derivative(&self, z: &[f64]) -> Vec<f64> {
        (0..z.len())
            .map(|i| if i < 3 { z[i].exp() } else { self.scale[i] })
            .collect()
    }
}

fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len().max(1) as f64).sqrt()
}

/// Simulates at z and writes ŷ − y; false when the point is unphysical or fails.
fn residuals_at(
    scaling: &Scaling,
    data: &DataSet,
    simulation: &NonlinearSimulation,
    smoothing: f64,
    z: &[f64],
    out: &mut [f64],
) -> bool {
    let (p, initial) = scaling.physical(z);
    if p.validate().is_err() {
        return false;
    }
    match simulate_nonlinear(&p, &data.excitation, initial, simulation, smoothing) {
        Ok((x, _)) => {
            for ((o, m), y) in out.iter_mut().zip(&x).zip(&data.output) {
                *o = m - y;
            }
            true
        }
        Err(_) => false,
    }
}

/// Estimates the parameters of `structure` on `data` by output error.
///
/// ## The algorithm
/// 1. Linear start: `options.linear_start` or [`estimate`] with its default options
///    (Levenberg–Marquardt on the exact simulator from the ARX guess); nonlinear
///    coefficients start at 0. The Coulomb smoothing velocity is fixed from that start.
/// 2. Scaled parameters z: ln m, ln c, ln k, and the nonlinear coefficients divided by
///    a scale making them O(1) when their force is comparable to the linear one (see the
///    module doc); the initial state (when estimated) divided by the output's RMS and
///    RMS·ωₙ.
/// 3. Levenberg–Marquardt (central differences) or Nelder–Mead on Σ(ŷ − y)², each
///    evaluation one ode45 simulation; optionally from several starts.
/// 4. Covariance σ̂²·D(JᵀJ)⁻¹D from the central-difference Jacobian in z at ẑ, with
///    σ̂² = SSE/(N − p) and Student-t 95 % intervals.
///
/// ```
/// use msd_ident::{estimate_nonlinear, synthetic_nonlinear_data, Excitation, ModelStructure,
///     NonlinearOptions, NonlinearParameters, NonlinearSimulation, Parameters, SyntheticOptions};
/// use msd_signal::paper_identification_input;
/// let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.004, 2001)?;
/// let plant = NonlinearParameters::from_linear(ModelStructure::LINEAR, &Parameters::PAPER);
/// let (data, _) = synthetic_nonlinear_data(&plant, input, &NonlinearSimulation::default(),
///     &SyntheticOptions::named("id"))?;
/// let e = estimate_nonlinear(&data, ModelStructure::LINEAR, &NonlinearOptions::default())?;
/// assert!(e.intervals[2].value > 100.0 && e.intervals[2].value < 140.0);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn estimate_nonlinear(
    data: &DataSet,
    structure: ModelStructure,
    options: &NonlinearOptions,
) -> Result<NonlinearEstimate> {
    let started = Instant::now();
    options.simulation.validate()?;
    let linear_start = match options.linear_start {
        Some(p) => {
            p.validate()?;
            p
        }
        None => {
            let linear = EstimationOptions {
                initial_state: options.initial_state,
                estimate_initial_state: options.estimate_initial_state,
                ..EstimationOptions::default()
            };
            estimate(data, &linear)?.parameters
        }
    };
    let start = NonlinearParameters::from_linear(structure, &linear_start);
    let smoothing = options.simulation.resolve_smoothing_velocity(
        &start,
        &data.excitation,
        options.initial_state,
    )?;
    let scaling = Scaling::new(structure, &linear_start, data, options);
    let p = scaling.len();
    let n = data.len();
    if n <= p + 1 {
        return Err(IdentError::TooFewSamples {
            got: n,
            needed: p + 2,
            why: "output-error estimation needs more samples than estimated quantities",
        });
    }
    let z0 = scaling.to_z(&start, options.initial_state);
    // Indices of F_c or c₂ in z, bounded below by 0 when dissipative damping is asked.
    let dissipative: Vec<usize> = if options.dissipative_damping {
        structure
            .parameter_names()
            .iter()
            .enumerate()
            .filter(|(_, n)| matches!(**n, "coulomb_force" | "quadratic_damping"))
            .map(|(i, _)| i)
            .collect()
    } else {
        Vec::new()
    };
    let mut lm_options = options.levenberg_marquardt.clone();
    if lm_options.max_evaluations.is_none() {
        lm_options.max_evaluations = Some(20 * (p + 1));
    }
    if !dissipative.is_empty() && lm_options.bounds.is_none() {
        let mut lower = vec![f64::NEG_INFINITY; p];
        for &i in &dissipative {
            lower[i] = 0.0;
        }
        lm_options.bounds = Some(Bounds::new(lower, vec![f64::INFINITY; p])?);
    }
    let sim = options.simulation;
    let local = |z_start: &[f64]| -> std::result::Result<Local, msd_opt::OptError> {
        match options.method {
            NonlinearMethod::LevenbergMarquardt => {
                let mut problem = ResidualFn::new(n, |z: &[f64], out: &mut [f64]| {
                    residuals_at(&scaling, data, &sim, smoothing, z, out)
                });
                let r = levenberg_marquardt(&mut problem, z_start, &lm_options)?;
                Ok(Local::levenberg_marquardt(r))
            }
            NonlinearMethod::NelderMead => {
                let mut buffer = vec![0.0; n];
                let mut count = 0usize;
                let r = nelder_mead(
                    |z| {
                        count += 1;
                        if residuals_at(&scaling, data, &sim, smoothing, z, &mut buffer) {
                            buffer.iter().map(|v| v * v).sum()
                        } else {
                            f64::INFINITY
                        }
                    },
                    z_start,
                    &options.nelder_mead,
                )?;
                Ok(Local {
                    evaluations: count,
                    ..Local::nelder_mead(r)
                })
            }
        }
    };

    let (best, starts, mut simulations) = match &options.multistart {
        None => {
            let r = local(&z0)?;
            let s = r.simulations();
            (r, 1, s)
        }
        Some(ms) => {
            let mut lower = z0.clone();
            let mut upper = z0.clone();
            for i in 0..p {
                let w = if i < 3 {
                    ms.decades * std::f64::consts::LN_10
                } else {
                    ms.nonlinear_width
                };
                lower[i] -= w;
                upper[i] += w;
            }
            for &i in &dissipative {
                lower[i] = lower[i].max(0.0);
            }
            let bounds = Bounds::new(lower, upper)?;
            let design = MultistartOptions {
                starts: ms.starts.saturating_sub(1).max(1),
                seed: ms.seed,
                threads: ms.threads,
                ..MultistartOptions::default()
            };
            // A start that cannot even be simulated ranks last instead of failing all.
            let tolerant = |z: &[f64]| Ok(local(z).unwrap_or_else(|e| Local::failed(z, e)));
            let mut results = multistart(&bounds, &design, tolerant)?;
            let nominal = local(&z0)?;
            let total: usize = results
                .iter()
                .map(|r| r.result.simulations())
                .sum::<usize>()
                + nominal.simulations();
            let count = results.len() + 1;
            let first = results.remove(0).result;
            let best = if nominal.cost <= first.cost {
                nominal
            } else {
                first
            };
            (best, count, total)
        }
    };
    let stop = best
        .finished()
        .map_err(|why| IdentError::EstimationFailed {
            reason: format!("{structure}: no start reached a finite cost ({why})"),
        })?;

    // Model output, residuals and the central-difference Jacobian at ẑ.
    let mut r0 = vec![0.0; n];
    if !residuals_at(&scaling, data, &sim, smoothing, &best.x, &mut r0) {
        return Err(IdentError::EstimationFailed {
            reason: format!("{structure}: the model cannot be simulated at the optimum"),
        });
    }
    simulations += 1;
    let mut jacobian = DMatrix::<f64>::zeros(n, p);
    let (mut plus, mut minus) = (vec![0.0; n], vec![0.0; n]);
    let step = options
        .levenberg_marquardt
        .finite_difference_step
        .unwrap_or(1e-4);
    for j in 0..p {
        let h = step * best.x[j].abs().max(1.0);
        let mut z = best.x.clone();
        z[j] = best.x[j] + h;
        let ok_plus = residuals_at(&scaling, data, &sim, smoothing, &z, &mut plus);
        z[j] = best.x[j] - h;
        let ok_minus = residuals_at(&scaling, data, &sim, smoothing, &z, &mut minus);
        simulations += 2;
        let names = structure.parameter_names();
        let name = names.get(j).copied().unwrap_or("initial state");
        match (ok_plus, ok_minus) {
            (true, true) => {
                for i in 0..n {
                    jacobian[(i, j)] = (plus[i] - minus[i]) / (2.0 * h);
                }
            }
            (true, false) => {
                for i in 0..n {
                    jacobian[(i, j)] = (plus[i] - r0[i]) / h;
                }
            }
            (false, true) => {
                for i in 0..n {
                    jacobian[(i, j)] = (r0[i] - minus[i]) / h;
                }
            }
            (false, false) => {
                return Err(IdentError::EstimationFailed {
                    reason: format!(
                        "{structure}: cannot simulate around the optimum to differentiate by {name}"
                    ),
                });
            }
        }
    }
    let sse: f64 = r0.iter().map(|v| v * v).sum();
    let dof = n - p;
    let sigma2 = sse / dof as f64;
    let jtj = jacobian.transpose() * &jacobian;
    let inverse = jtj
        .clone()
        .try_inverse()
        .ok_or_else(|| IdentError::NotIdentifiable {
            reason: format!("{structure}: JᵀJ is singular at the estimate"),
        })?;
    let norms: Vec<f64> = (0..p).map(|j| jtj[(j, j)].sqrt()).collect();
    let normalised = DMatrix::from_fn(p, p, |r, c| jtj[(r, c)] / (norms[r] * norms[c]));
    let eigenvalues = normalised.symmetric_eigen().eigenvalues;
    let (low, high) = eigenvalues
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), &v| (l.min(v), h.max(v)));
    let condition_number = if low > 0.0 { high / low } else { f64::INFINITY };
    let d = scaling.derivative(&best.x);
    let covariance = DMatrix::from_fn(p, p, |r, c| sigma2 * d[r] * inverse[(r, c)] * d[c]);
    let correlation = DMatrix::from_fn(p, p, |r, c| {
        covariance[(r, c)] / (covariance[(r, r)] * covariance[(c, c)]).sqrt()
    });
    let t = crate::uncertainty::t_975(dof);
    let (parameters, initial_state) = scaling.physical(&best.x);
    let interval =
        |i: usize, value: f64| Interval::new(value, covariance[(i, i)].max(0.0).sqrt(), t);
    let np = structure.parameter_count();
    let intervals: Vec<Interval> = (0..np).map(|i| interval(i, parameters.values[i])).collect();
    let initial_state_intervals = options.estimate_initial_state.then(|| {
        [
            interval(np, initial_state.displacement),
            interval(np + 1, initial_state.velocity),
        ]
    });
    let model_output: Vec<f64> = r0.iter().zip(&data.output).map(|(r, y)| r + y).collect();
    let residuals: Vec<f64> = r0.iter().map(|r| -r).collect();
    Ok(NonlinearEstimate {
        fit: FitMetrics::new(&data.output, &model_output),
        parameters,
        intervals,
        initial_state,
        initial_state_intervals,
        covariance,
        correlation,
        condition_number,
        sigma: sigma2.sqrt(),
        degrees_of_freedom: dof,
        estimated: p,
        sse,
        model_output,
        residuals,
        smoothing_velocity: smoothing,
        linear_start,
        method: options.method,
        starts,
        iterations: best.iterations,
        simulations,
        stop,
        wall_time: started.elapsed(),
    })
}

/// Noisy synthetic data from a nonlinear plant: its ode45 response to `excitation` from
/// `options.initial_state` plus the noise of `options` (see
/// [`SyntheticOptions`](crate::SyntheticOptions)). The Coulomb smoothing velocity is
/// resolved from `simulation` on this excitation.
///
/// Returns the noisy data set and the noise-free response, as
/// [`synthetic_data`](crate::synthetic_data).
///
/// ```
/// use msd_ident::{synthetic_nonlinear_data, Excitation, ModelStructure, NonlinearParameters,
///     NonlinearSimulation, Parameters, SyntheticOptions};
/// use msd_signal::paper_identification_input;
/// let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.004, 501)?;
/// let plant = NonlinearParameters::from_linear(ModelStructure::LINEAR, &Parameters::PAPER);
/// let options = SyntheticOptions { sigma: 0.0, ..SyntheticOptions::named("id") };
/// let (data, truth) = synthetic_nonlinear_data(&plant, input, &NonlinearSimulation::default(), &options)?;
/// assert_eq!((data.name.as_str(), data.len()), ("id", 501));
/// assert_eq!(data.output, truth); // σ = 0
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn synthetic_nonlinear_data(
    plant: &NonlinearParameters,
    excitation: crate::Excitation,
    simulation: &NonlinearSimulation,
    options: &crate::SyntheticOptions,
) -> Result<(DataSet, Vec<f64>)> {
    options.validate()?;
    let initial = options.initial_state;
    let smoothing = simulation.resolve_smoothing_velocity(plant, &excitation, initial)?;
    let (truth, _) = simulate_nonlinear(plant, &excitation, initial, simulation, smoothing)?;
    Ok((options.data_set(excitation, truth.clone())?, truth))
}
