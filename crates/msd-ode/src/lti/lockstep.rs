//! Several exact simulators driven by one input, stepped together.
//!
//! A Monte Carlo run simulates many parameter sets on the same input. One simulation is
//! a chain of dependent updates x ← Φx + d (its speed is the latency of that chain);
//! B independent chains stepped together keep the floating-point units busy instead, and
//! the input's per-step stencils, identical for every parameter set, are worked out once
//! ([`InputSchedule`]).

use super::{ExactSimulator, Hold, SampledInput, for_each_step};
use crate::error::OdeError;
use nalgebra::SVector;

/// The per-step drive of a sampled input for one hold: for the step into sample i, the
/// stencil variant (jumps and kinks at breakpoints respected) and its node values.
/// Built once per input, validated once, shared by any number of [`Lockstep`] runs.
///
/// ```
/// use msd_ode::{Hold, InputSchedule, SampledInput};
/// let force = vec![1.0; 101];
/// let schedule = InputSchedule::new(&SampledInput::smooth(&force), Hold::Cubic)?;
/// assert_eq!(schedule.samples(), 101);
/// # Ok::<(), msd_ode::OdeError>(())
/// ```
#[derive(Debug, Clone)]
pub struct InputSchedule {
    hold: Hold,
    /// `steps[i − 1]`: (variant, nodes) of the step into sample i.
    steps: Vec<(usize, [f64; 4])>,
}

impl InputSchedule {
    /// The schedule of `input` (validated) for `hold`.
    pub fn new(input: &SampledInput<'_>, hold: Hold) -> Result<Self, OdeError> {
        input.validate()?;
        let mut steps = Vec::with_capacity(input.values.len().saturating_sub(1));
        for_each_step(input, hold, |variant, nodes, i| {
            debug_assert_eq!(i, steps.len() + 1);
            steps.push((variant, nodes));
        });
        Ok(Self { hold, steps })
    }

    /// Number of samples of the input.
    pub fn samples(&self) -> usize {
        self.steps.len() + 1
    }

    /// The hold the schedule was built for.
    pub fn hold(&self) -> Hold {
        self.hold
    }
}

/// `B` exact simulators of the same step and hold, stepped together on one
/// [`InputSchedule`]; each lane gives bit for bit what
/// [`ExactSimulator::simulate_with`] gives alone.
///
/// ```
/// use msd_ode::{ExactSimulator, Hold, InputSchedule, Lockstep, LtiModel, SampledInput, SMatrix, SVector};
/// let model = |k: f64| LtiModel { a: SMatrix::<f64, 2, 2>::new(0.0, 1.0, -k / 2.5, -0.72), b: SVector::<f64, 2>::new(0.0, 0.4) };
/// let sims = [100.0, 120.0].map(|k| ExactSimulator::new(&model(k), 0.002, Hold::Cubic).unwrap());
/// let force = vec![6.0; 1001];
/// let schedule = InputSchedule::new(&SampledInput::smooth(&force), Hold::Cubic)?;
/// let mut lanes = Lockstep::new([&sims[0], &sims[1]], [SVector::zeros(); 2])?;
/// let mut last = [0.0; 2];
/// lanes.advance(&schedule, 1000, |_, x| last = x[0]);
/// let alone = sims[1].simulate(&SVector::zeros(), &SampledInput::smooth(&force))?;
/// assert_eq!(last[1], alone[1000][0]);
/// # Ok::<(), msd_ode::OdeError>(())
/// ```
#[derive(Debug, Clone)]
pub struct Lockstep<const N: usize, const B: usize> {
    hold: Hold,
    dt: f64,
    /// Φ[r][c][lane].
    phi: [[[f64; B]; N]; N],
    /// weights[variant][node][r][lane].
    weights: [[[[f64; B]; N]; 4]; 7],
    /// x[r][lane] at sample `sample`.
    x: [[f64; B]; N],
    sample: usize,
}

impl<const N: usize, const B: usize> Lockstep<N, B> {
    /// Lanes for `simulators` (all of the same step and hold) from the states `x0`, at
    /// sample 0.
    pub fn new(
        simulators: [&ExactSimulator<N>; B],
        x0: [SVector<f64, N>; B],
    ) -> Result<Self, OdeError> {
        let first = simulators.first().ok_or(OdeError::InvalidOption {
            name: "lanes",
            value: 0.0,
            expected: "at least one simulator",
        })?;
        if let Some(other) = simulators
            .iter()
            .find(|s| s.dt != first.dt || s.hold != first.hold)
        {
            return Err(OdeError::InvalidOption {
                name: "dt",
                value: other.dt,
                expected: "the same step and hold in every lane",
            });
        }
        for x in &x0 {
            if let Some((index, &value)) = x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                return Err(OdeError::NonFiniteInitialState { index, value });
            }
        }
        Ok(Self {
            hold: first.hold,
            dt: first.dt,
            phi: std::array::from_fn(|r| {
                std::array::from_fn(|c| std::array::from_fn(|l| simulators[l].phi_rows[r][c]))
            }),
            weights: std::array::from_fn(|v| {
                std::array::from_fn(|m| {
                    std::array::from_fn(|r| std::array::from_fn(|l| simulators[l].weights[v][m][r]))
                })
            }),
            x: std::array::from_fn(|r| std::array::from_fn(|l| x0[l][r])),
            sample: 0,
        })
    }

    /// The current sample index (0 after [`Lockstep::new`]).
    pub fn sample(&self) -> usize {
        self.sample
    }

    /// The lanes' states at the current sample: `state()[r][lane]`.
    pub fn state(&self) -> &[[f64; B]; N] {
        &self.x
    }

    /// The step size.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Steps every lane to sample `until` (clamped to the schedule's last sample),
    /// handing the state at each new sample i to `output(i, x)` (`x[r][lane]`). Allocates
    /// nothing.
    ///
    /// # Panics
    /// If `schedule` was built for another hold (a programming error).
    pub fn advance<F: FnMut(usize, &[[f64; B]; N])>(
        &mut self,
        schedule: &InputSchedule,
        until: usize,
        mut output: F,
    ) {
        assert_eq!(schedule.hold, self.hold, "schedule for another hold");
        let until = until.min(schedule.steps.len());
        if until <= self.sample {
            return;
        }
        for (k, (variant, u)) in schedule.steps[self.sample..until].iter().enumerate() {
            let w = &self.weights[*variant];
            let mut next = [[0.0; B]; N];
            for (r, next_r) in next.iter_mut().enumerate() {
                for l in 0..B {
                    let drive = (w[0][r][l] * u[0] + w[1][r][l] * u[1])
                        + (w[2][r][l] * u[2] + w[3][r][l] * u[3]);
                    let mut acc = self.phi[r][0][l] * self.x[0][l];
                    for c in 1..N {
                        acc += self.phi[r][c][l] * self.x[c][l];
                    }
                    next_r[l] = acc + drive;
                }
            }
            self.x = next;
            output(self.sample + k + 1, &self.x);
        }
        self.sample = until;
    }
}
