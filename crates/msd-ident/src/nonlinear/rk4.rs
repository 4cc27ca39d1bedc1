//! The fast simulator of the nonlinear models: classical Runge–Kutta (RK4), sample
//! interval by sample interval on the hold polynomial of the input, with the forward
//! sensitivities integrated beside the state.
//!
//! ## Why per sample
//! A measured force is known at the samples only; the hold (msd-ode's
//! [`Hold`](msd_ode::Hold), as the linear model's exact backend) makes it one
//! polynomial per interval, with a kink or a jump at every sample. An adaptive solver
//! stepping across those kinks keeps rejecting steps; a fixed-step scheme restarted at
//! each sample only ever sees a smooth polynomial.
//!
//! ## Sub-steps and error
//! Each interval is cut into M equal sub-steps, M = ⌈ρ·dt/θ⌉ with θ = [`PHASE_PER_STEP`]
//! and ρ = √|K| + |C| ≥ |λ| a bound on the eigenvalues of the linearised dynamics
//! (K = f_s'(x)/m, C = f_d'(x')/m) over the trajectory. RK4 errs on y' = λy by
//! (λh)⁵/120 a step: at |λ|h ≤ 0.1 an oscillator's frequency is shifted by
//! (ωh)⁴/120 ≤ 8.3e-7 relative, and its response near resonance by that over ζ
//! (1.7e-5 at ζ = 5 %) — far below any noise level of a real record.
//!
//! ## Sensitivities
//! RK4 applied to the state and its sensitivities together gives exactly the
//! derivative of the discrete solution (each stage of the sensitivities is the
//! derivative of the state's stage), so a Jacobian from here is exact for the output
//! the same sub-steps simulate.

use super::model::Forces;
use crate::{
    data::Excitation,
    error::{IdentError, Result},
    params::InitialState,
};
use msd_ode::{Hold, SampledInput};

/// θ: the largest ρ·h, ρ the eigenvalue bound and h the sub-step (see the module doc).
pub(crate) const PHASE_PER_STEP: f64 = 0.1;

/// Most sub-steps a sample interval may take (ρ·dt ≤ 100).
const MAX_STEPS: usize = 1000;

/// Sensitivity columns beside the state: up to 5 parameters and the initial state,
/// padded to 8 so that the column loops have a fixed length and vectorise.
pub(crate) const MAX_COLUMNS: usize = 8;

/// Length of the augmented state: x, x', then ξ of every column, then η.
const AUGMENTED: usize = 2 + 2 * MAX_COLUMNS;

/// The columns of a Jacobian ∂x/∂z: parameter j of the vector (its forcing ∂a/∂θⱼ
/// times dθⱼ/dzⱼ), then optionally x(t₀) and x'(t₀) (their initial sensitivities
/// dx(t₀)/dz and dx'(t₀)/dz).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Columns {
    /// Number of columns.
    pub count: usize,
    /// dθⱼ/dzⱼ for a parameter column, 0 for a state column.
    pub weight: [f64; MAX_COLUMNS],
    /// Index in [`Linearised::partials`](super::model::Linearised) of a parameter column.
    pub partial: [usize; MAX_COLUMNS],
    /// Initial (ξ, η) of each column.
    pub start: [[f64; 2]; MAX_COLUMNS],
}

impl Columns {
    /// The parameters of `forces` scaled by `scale` (dθ/dz, one per parameter), then
    /// the initial state scaled by `state` when given.
    pub fn new(forces: &Forces, scale: &[f64], state: Option<[f64; 2]>) -> Self {
        let count = scale.len() + if state.is_some() { 2 } else { 0 };
        debug_assert!(scale.len() <= 5 && count <= 7);
        let mut c = Self {
            count,
            weight: [0.0; MAX_COLUMNS],
            partial: [0; MAX_COLUMNS],
            start: [[0.0; 2]; MAX_COLUMNS],
        };
        for (j, &s) in scale.iter().enumerate() {
            c.weight[j] = s;
            c.partial[j] = forces.order[j];
        }
        if let Some([x, v]) = state {
            c.start[scale.len()] = [x, 0.0];
            c.start[scale.len() + 1] = [0.0, v];
        }
        c
    }
}

/// RK4 on the hold polynomials of one excitation, with a fixed number of sub-steps.
#[derive(Debug, Clone)]
pub(crate) struct HoldRk4 {
    polynomials: Vec<[f64; 4]>,
    dt: f64,
    steps: usize,
}

impl HoldRk4 {
    /// The hold polynomials of `excitation`, one sub-step a sample until told more.
    pub fn new(excitation: &Excitation, hold: Hold) -> Result<Self> {
        let input = SampledInput {
            values: excitation.samples(),
            breakpoints: excitation.breakpoints(),
        };
        Ok(Self {
            polynomials: input.hold_polynomials(hold)?,
            dt: excitation.dt(),
            steps: 1,
        })
    }

    /// Sub-steps per sample interval.
    pub fn steps(&self) -> usize {
        self.steps
    }

    /// Sets the sub-steps per sample interval.
    pub fn set_steps(&mut self, steps: usize) {
        debug_assert!((1..=MAX_STEPS).contains(&steps));
        self.steps = steps;
    }

    /// The sub-steps an eigenvalue bound `rate` needs: ⌈rate·dt/θ⌉, at least 1; an
    /// error beyond [`MAX_STEPS`] (a model too stiff for this sampling interval).
    pub fn steps_for(&self, rate: f64) -> Result<usize> {
        let needed = (rate * self.dt / PHASE_PER_STEP).ceil().max(1.0);
        if needed.is_finite() && needed <= MAX_STEPS as f64 {
            Ok(needed as usize)
        } else {
            Err(IdentError::InvalidParameter {
                name: "RK4 sub-steps per sample (the model's eigenvalue bound × dt / 0.1)",
                value: needed,
                expected: "at most 1000: the model is too stiff for the sample-hold simulator at this sampling interval; use solver = \"ode45\"",
            })
        }
    }

    /// The displacement at every sample into `out` (one per sample, the first the
    /// initial one); returns the largest eigenvalue bound met at a sample. A diverging
    /// model leaves non-finite values in `out`.
    pub fn simulate(&self, forces: &Forces, initial: InitialState, out: &mut [f64]) -> f64 {
        debug_assert_eq!(out.len(), self.polynomials.len() + 1);
        let mut y = [initial.displacement, initial.velocity];
        let mut rate = forces.rate(y[0], y[1]);
        out[0] = y[0];
        let f = Plain(forces);
        for (i, a) in self.polynomials.iter().enumerate() {
            self.interval(a, &mut y, &f);
            out[i + 1] = y[0];
            rate = rate.max(forces.rate(y[0], y[1]));
        }
        rate
    }

    /// As [`HoldRk4::simulate`], and ∂x/∂z of every column into `jacobian` (column-major,
    /// samples × `columns.count`).
    pub fn sensitivities(
        &self,
        forces: &Forces,
        initial: InitialState,
        columns: &Columns,
        out: &mut [f64],
        jacobian: &mut [f64],
    ) -> f64 {
        let n = out.len();
        debug_assert_eq!(n, self.polynomials.len() + 1);
        debug_assert_eq!(jacobian.len(), n * columns.count);
        let mut y = [0.0; AUGMENTED];
        y[0] = initial.displacement;
        y[1] = initial.velocity;
        for j in 0..columns.count {
            y[XI + j] = columns.start[j][0];
            y[ETA + j] = columns.start[j][1];
        }
        let f = Augmented { forces, columns };
        let mut rate = forces.rate(y[0], y[1]);
        let mut write = |i: usize, y: &[f64; AUGMENTED]| {
            out[i] = y[0];
            for j in 0..columns.count {
                jacobian[j * n + i] = y[XI + j];
            }
        };
        write(0, &y);
        for (i, a) in self.polynomials.iter().enumerate() {
            self.interval(a, &mut y, &f);
            write(i + 1, &y);
            rate = rate.max(forces.rate(y[0], y[1]));
        }
        rate
    }

    /// Advances `y` over one sample interval whose input is the polynomial `a` in
    /// s ∈ [0, 1], by the sub-steps.
    #[inline(always)]
    fn interval<const N: usize>(&self, a: &[f64; 4], y: &mut [f64; N], f: &impl System<N>) {
        let m = self.steps as f64;
        let h = self.dt / m;
        let mut u0 = a[0];
        for k in 0..self.steps {
            let u_half = horner(a, (k as f64 + 0.5) / m);
            let u1 = horner(a, (k + 1) as f64 / m);
            rk4_step(y, h, [u0, u_half, u1], f);
            u0 = u1;
        }
    }
}

/// y' = f(u, y), u the input at the time of the evaluation.
trait System<const N: usize> {
    fn derivative(&self, u: f64, y: &[f64; N], d: &mut [f64; N]);
}

/// The model's state (x, x').
struct Plain<'a>(&'a Forces);

impl System<2> for Plain<'_> {
    #[inline(always)]
    fn derivative(&self, u: f64, y: &[f64; 2], d: &mut [f64; 2]) {
        d[0] = y[1];
        d[1] = self.0.acceleration(u, y[0], y[1]);
    }
}

/// Index of the first ξ and the first η in the augmented state.
const XI: usize = 2;
const ETA: usize = 2 + MAX_COLUMNS;

/// The state and the sensitivities (ξ, η) = ∂(x, x')/∂z of every column:
/// ξ' = η, η' = w·∂a/∂θ − K·ξ − C·η. Every column is advanced, the padding too (it
/// stays 0), so that the loops have a fixed length.
struct Augmented<'a> {
    forces: &'a Forces,
    columns: &'a Columns,
}

impl System<AUGMENTED> for Augmented<'_> {
    #[inline(always)]
    fn derivative(&self, u: f64, y: &[f64; AUGMENTED], d: &mut [f64; AUGMENTED]) {
        let l = self.forces.linearised(u, y[0], y[1]);
        d[0] = y[1];
        d[1] = l.acceleration;
        let c = self.columns;
        let forcing: [f64; MAX_COLUMNS] =
            std::array::from_fn(|j| c.weight[j] * l.partials[c.partial[j]]);
        for j in 0..MAX_COLUMNS {
            d[XI + j] = y[ETA + j];
            d[ETA + j] = forcing[j] - l.stiffness * y[XI + j] - l.damping * y[ETA + j];
        }
    }
}

/// a₀ + a₁s + a₂s² + a₃s³.
#[inline(always)]
fn horner(a: &[f64; 4], s: f64) -> f64 {
    a[0] + s * (a[1] + s * (a[2] + s * a[3]))
}

/// One classical RK4 step of y' = f(u(t), y), the input at the step's start, middle
/// and end given in `u` (nodes 0, 1/2, 1/2, 1; weights 1/6, 1/3, 1/3, 1/6).
#[inline(always)]
fn rk4_step<const N: usize>(y: &mut [f64; N], h: f64, u: [f64; 3], f: &impl System<N>) {
    let (mut k1, mut k2, mut k3, mut k4) = ([0.0; N], [0.0; N], [0.0; N], [0.0; N]);
    let mut stage = [0.0; N];
    f.derivative(u[0], y, &mut k1);
    for i in 0..N {
        stage[i] = y[i] + 0.5 * h * k1[i];
    }
    f.derivative(u[1], &stage, &mut k2);
    for i in 0..N {
        stage[i] = y[i] + 0.5 * h * k2[i];
    }
    f.derivative(u[1], &stage, &mut k3);
    for i in 0..N {
        stage[i] = y[i] + h * k3[i];
    }
    f.derivative(u[2], &stage, &mut k4);
    let sixth = h / 6.0;
    for i in 0..N {
        y[i] += sixth * ((k1[i] + k4[i]) + 2.0 * (k2[i] + k3[i]));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// y' = y on [0, 1] with RK4's weights: one step gives the Taylor polynomial of e
    /// to fourth order exactly, and halving the step divides the error by about 2⁴.
    #[test]
    fn rk4_is_fourth_order() {
        struct Growth;
        impl System<1> for Growth {
            fn derivative(&self, _: f64, y: &[f64; 1], d: &mut [f64; 1]) {
                d[0] = y[0];
            }
        }
        let f = Growth;
        let mut y = [1.0];
        rk4_step(&mut y, 1.0, [0.0; 3], &f);
        assert_eq!(y[0], 1.0 + 1.0 + 0.5 + 1.0 / 6.0 + 1.0 / 24.0);
        let error = |steps: usize| {
            let mut y = [1.0];
            for _ in 0..steps {
                rk4_step(&mut y, 1.0 / steps as f64, [0.0; 3], &f);
            }
            (y[0] - std::f64::consts::E).abs()
        };
        let ratio = error(8) / error(16);
        assert!((ratio.log2() - 4.0).abs() < 0.1, "{ratio}");
    }

    /// The input polynomial is sampled at the step's start, middle and end: y' = u(s)
    /// with a cubic u integrates exactly (Simpson's rule is exact for cubics).
    #[test]
    fn the_input_polynomial_is_integrated_exactly() {
        let excitation =
            Excitation::from_samples(0.0, 0.5, vec![0.0, 1.0, 8.0, 27.0, 64.0]).expect("valid");
        let mut rk4 = HoldRk4::new(&excitation, Hold::Cubic).expect("valid");
        rk4.set_steps(3);
        struct Input;
        impl System<1> for Input {
            fn derivative(&self, u: f64, _: &[f64; 1], d: &mut [f64; 1]) {
                d[0] = u;
            }
        }
        let f = Input;
        let mut y = [0.0];
        for a in &rk4.polynomials {
            rk4.interval(a, &mut y, &f);
        }
        // ∫₀⁴ s³ ds in sample units, times dt.
        assert!((y[0] - 0.5 * 64.0).abs() < 1e-12, "{}", y[0]);
    }
}
