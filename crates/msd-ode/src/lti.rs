//! Exact simulation of linear time-invariant systems on a sampled input.
//!
//! ## The algorithm
//! For x' = A x + b u with u sampled on a uniform grid tᵢ = t₀ + i·dt, each interval
//! [tᵢ, tᵢ₊₁] replaces u by a polynomial through neighbouring samples (the *hold*) and
//! integrates that polynomial input exactly:
//!
//! xᵢ₊₁ = Φ xᵢ + Σⱼ Γⱼ aⱼ,  Φ = e^{A dt},  Γⱼ = ∫₀¹ e^{A dt (1−s)} b dt sʲ ds,
//!
//! where aⱼ are the coefficients of the input polynomial in s = (t − tᵢ)/dt. Φ and all Γⱼ
//! come from one matrix exponential of an augmented matrix (Van Loan's method): the state
//! x is driven by the last of a chain of integrators whose initial values select the
//! monomial. The Lagrange coefficients of each stencil are folded into the Γⱼ once, so the
//! per-sample update is Φ xᵢ plus at most four weighted samples, with no allocation.
//! The augmented matrix is balanced first (a diagonal similarity by powers of two, which
//! rounds nothing), so neither the accuracy nor the stiffness limit depends on the units
//! of the state or the input.
//!
//! Holds: [`Hold::Zero`] (u constant at uᵢ, what a naive `lsim` does), [`Hold::First`]
//! (linear between samples, O(dt²) input error), [`Hold::Cubic`] (cubic through four
//! neighbouring samples, O(dt⁴): about 1e-9 relative for the paper's sinusoids on a 2 ms
//! grid). Stencils never cross a [`Breakpoint`]: a jump or kink at a sample instant is
//! represented exactly by its left and right values, and near a breakpoint the cubic
//! falls back to one-sided stencils, then to quadratic or linear ones in pieces too short
//! for four samples.

mod frequency;
pub use frequency::Resolvent;
mod lockstep;
mod ramp;

pub use lockstep::{InputSchedule, Lockstep};
pub use ramp::RampStep;

use crate::error::OdeError;
use nalgebra::{DMatrix, SMatrix, SVector};

/// A linear time-invariant system x' = A x + b u with one input.
///
/// ```
/// use msd_ode::{LtiModel, SMatrix, SVector};
/// // Mass–spring–damper m x'' + c x' + k x = F with state (x, x').
/// let (m, c, k) = (2.5, 1.8, 120.0);
/// let model = LtiModel {
///     a: SMatrix::<f64, 2, 2>::new(0.0, 1.0, -k / m, -c / m),
///     b: SVector::<f64, 2>::new(0.0, 1.0 / m),
/// };
/// assert!(model.validate().is_ok());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LtiModel<const N: usize> {
    /// System matrix A.
    pub a: SMatrix<f64, N, N>,
    /// Input vector b.
    pub b: SVector<f64, N>,
}

impl<const N: usize> LtiModel<N> {
    /// Checks that every entry is finite.
    pub fn validate(&self) -> Result<(), OdeError> {
        for r in 0..N {
            for c in 0..N {
                let value = self.a[(r, c)];
                if !value.is_finite() {
                    return Err(OdeError::NonFiniteModel {
                        name: "a",
                        row: r,
                        col: c,
                        value,
                    });
                }
            }
            if !self.b[r].is_finite() {
                return Err(OdeError::NonFiniteModel {
                    name: "b",
                    row: r,
                    col: 0,
                    value: self.b[r],
                });
            }
        }
        Ok(())
    }
}

/// How the input is reconstructed between samples.
///
/// By default [`Hold::Cubic`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Hold {
    /// Constant at the sample value over each interval (zero-order hold).
    Zero,
    /// Linear between samples (first-order hold).
    First,
    /// Cubic through four neighbouring samples (one-sided near breakpoints).
    #[default]
    Cubic,
}

/// A sample instant where the input jumps or has a kink: its value just before
/// (`left`) and at/after (`right`) the instant. At a breakpoint the sample value itself
/// is ignored in favour of these two.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Breakpoint {
    /// Sample index of the instant.
    pub index: usize,
    /// Limit of the input from the left.
    pub left: f64,
    /// Value of the input at and after the instant.
    pub right: f64,
}

/// An input sampled on the simulator's grid, with its breakpoints (sorted by index).
#[derive(Debug, Clone, Copy)]
pub struct SampledInput<'a> {
    /// u(tᵢ) for every sample i (right values at breakpoints).
    pub values: &'a [f64],
    /// Jumps and kinks at sample instants, strictly increasing in `index`.
    pub breakpoints: &'a [Breakpoint],
}

impl<'a> SampledInput<'a> {
    /// An input without breakpoints.
    pub fn smooth(values: &'a [f64]) -> Self {
        Self {
            values,
            breakpoints: &[],
        }
    }

    /// Checks finiteness and the order of the breakpoints.
    pub fn validate(&self) -> Result<(), OdeError> {
        if self.values.is_empty() {
            return Err(OdeError::InvalidInput {
                index: 0,
                value: f64::NAN,
                reason: "the input has no samples",
            });
        }
        if let Some((index, &value)) = self.values.iter().enumerate().find(|(_, v)| !v.is_finite())
        {
            return Err(OdeError::InvalidInput {
                index,
                value,
                reason: "input samples must be finite",
            });
        }
        let mut previous: Option<usize> = None;
        for bp in self.breakpoints {
            if bp.index >= self.values.len() {
                return Err(OdeError::InvalidInput {
                    index: bp.index,
                    value: bp.right,
                    reason: "breakpoint index is beyond the last sample",
                });
            }
            if previous.is_some_and(|p| bp.index <= p) {
                return Err(OdeError::InvalidInput {
                    index: bp.index,
                    value: bp.right,
                    reason: "breakpoints must be sorted by strictly increasing index",
                });
            }
            if !(bp.left.is_finite() && bp.right.is_finite()) {
                return Err(OdeError::InvalidInput {
                    index: bp.index,
                    value: if bp.left.is_finite() {
                        bp.right
                    } else {
                        bp.left
                    },
                    reason: "breakpoint values must be finite",
                });
            }
            previous = Some(bp.index);
        }
        Ok(())
    }
}

impl SampledInput<'_> {
    /// The hold polynomial of every sample interval, as [`ExactSimulator`] integrates it:
    /// `out[i]` holds the coefficients (a₀, a₁, a₂, a₃) of u(s) = Σⱼ aⱼ sʲ on
    /// [tᵢ, tᵢ₊₁], s = (t − tᵢ)/dt ∈ [0, 1], with the same stencils and breakpoints. An
    /// integrator of a nonlinear system can so follow the input the exact simulator
    /// follows, one smooth polynomial per interval. One entry fewer than samples.
    ///
    /// ```
    /// use msd_ode::{Breakpoint, Hold, SampledInput};
    /// let ramp = [0.0, 1.0, 2.0, 3.0, 4.0];
    /// let cubic = SampledInput::smooth(&ramp).hold_polynomials(Hold::Cubic)?;
    /// assert_eq!(cubic.len(), 4);
    /// for (i, p) in cubic.iter().enumerate() {
    ///     // A ramp stays a ramp: u(s) = i + s.
    ///     let expected = [i as f64, 1.0, 0.0, 0.0];
    ///     assert!(p.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-12), "{p:?}");
    /// }
    /// // A jump at sample 2: the interval before it ends at the left value.
    /// let step = [0.0, 0.0, 1.0, 1.0];
    /// let jumps = [Breakpoint { index: 2, left: 0.0, right: 1.0 }];
    /// let zero = SampledInput { values: &step, breakpoints: &jumps }.hold_polynomials(Hold::First)?;
    /// assert_eq!(zero, [[0.0; 4], [0.0; 4], [1.0, 0.0, 0.0, 0.0]]);
    /// # Ok::<(), msd_ode::OdeError>(())
    /// ```
    pub fn hold_polynomials(&self, hold: Hold) -> Result<Vec<[f64; 4]>, OdeError> {
        self.validate()?;
        let basis: [[[f64; 4]; 4]; 7] = std::array::from_fn(|v| lagrange_monomials(STENCILS[v]));
        let mut out = vec![[0.0; 4]; self.values.len() - 1];
        for_each_step(self, hold, |variant, u, i| {
            let b = &basis[variant];
            out[i - 1] = std::array::from_fn(|j| {
                (b[0][j] * u[0] + b[1][j] * u[1]) + (b[2][j] * u[2] + b[3][j] * u[3])
            });
        });
        Ok(out)
    }
}

/// Stencil variants: node offsets (in samples, relative to the interval start).
const STENCILS: [&[f64]; 7] = [
    &[0.0],                  // ZERO
    &[0.0, 1.0],             // LINEAR
    &[0.0, 1.0, 2.0],        // QUAD_LEFT
    &[-1.0, 0.0, 1.0],       // QUAD_RIGHT
    &[-1.0, 0.0, 1.0, 2.0],  // CUBIC_CENTRED
    &[0.0, 1.0, 2.0, 3.0],   // CUBIC_LEFT
    &[-2.0, -1.0, 0.0, 1.0], // CUBIC_RIGHT
];
const ZERO: usize = 0;
const LINEAR: usize = 1;
const QUAD_LEFT: usize = 2;
const QUAD_RIGHT: usize = 3;
const CUBIC_CENTRED: usize = 4;
const CUBIC_LEFT: usize = 5;
const CUBIC_RIGHT: usize = 6;

/// Exact discretisation of an [`LtiModel`] for one step size and hold, computed once and
/// reused for any input and initial state.
///
/// ```
/// use msd_ode::{ExactSimulator, Hold, LtiModel, SampledInput, SMatrix, SVector};
/// let (m, c, k) = (2.5, 1.8, 120.0);
/// let model = LtiModel {
///     a: SMatrix::<f64, 2, 2>::new(0.0, 1.0, -k / m, -c / m),
///     b: SVector::<f64, 2>::new(0.0, 1.0 / m),
/// };
/// let sim = ExactSimulator::new(&model, 0.002, Hold::Cubic)?;
/// let force = vec![6.0; 7501]; // a step of 6 N applied at t = 0
/// let x = sim.simulate(&SVector::zeros(), &SampledInput::smooth(&force))?;
/// // After 15 s the displacement has settled near F/k = 0.05 m.
/// assert!((x[7500][0] - 6.0 / k).abs() < 1e-3);
/// # Ok::<(), msd_ode::OdeError>(())
/// ```
#[derive(Debug, Clone)]
pub struct ExactSimulator<const N: usize> {
    dt: f64,
    hold: Hold,
    phi: SMatrix<f64, N, N>,
    /// Φ by rows, for the per-sample update written as plain loops (unrolled and
    /// vectorised by the compiler, unlike a generic matrix product).
    phi_rows: [[f64; N]; N],
    /// Stencil weights: `weights[variant][node][component]`.
    weights: [[[f64; N]; 4]; 7],
    /// Γⱼ: the state's response over one step, from rest, to the input u(s) = sʲ.
    gamma: [SVector<f64, N>; 4],
}

impl<const N: usize> ExactSimulator<N> {
    /// Largest ‖D⁻¹[A·dt, b·dt; 0, shift]D‖₁ accepted by [`ExactSimulator::new`], with D
    /// the diagonal balancing of the augmented matrix (so the limit does not depend on
    /// the units of the state or the input).
    pub const MAX_NORM: f64 = 1e12;

    /// Discretises `model` for step `dt` with the given hold.
    ///
    /// Fails with [`OdeError::ExponentialOutOfRange`] when the balanced ‖A·dt‖ exceeds
    /// [`ExactSimulator::MAX_NORM`].
    pub fn new(model: &LtiModel<N>, dt: f64, hold: Hold) -> Result<Self, OdeError> {
        model.validate()?;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(OdeError::InvalidOption {
                name: "dt",
                value: dt,
                expected: "a finite number > 0",
            });
        }
        const D: usize = 3; // highest input monomial
        let size = N + D + 1;
        let mut aug = DMatrix::<f64>::zeros(size, size);
        for r in 0..N {
            for c in 0..N {
                aug[(r, c)] = model.a[(r, c)] * dt;
            }
            aug[(r, N + D)] = model.b[r] * dt;
        }
        for j in 0..D {
            aug[(N + j + 1, N + j)] = 1.0;
        }
        // Balance first: the state and input may be in any units (a sensitivity ∂x/∂m of a
        // 1 µg mass is ~1e9 times x), which scales rows and columns by powers of ten that
        // say nothing about how hard the exponential is. With D from `balance`,
        // e^M = D e^{D⁻¹MD} D⁻¹, exactly (D holds powers of two).
        let scale = balance(&mut aug);
        // Scaling and squaring needs ~log2‖M‖ squarings; beyond this limit the powers
        // inside the Padé step overflow and the squaring count becomes meaningless (the
        // computation would never end), so such a model is refused with an error. 1e12
        // leaves room for very stiff plants (k = 1e8, m = 1e-3 at dt = 2 ms: the balanced
        // norm is about ωn·dt ≈ 6e2).
        let norm = (0..size)
            .map(|c| (0..size).map(|r| aug[(r, c)].abs()).sum::<f64>())
            .fold(0.0, f64::max);
        if norm.is_nan() || norm > Self::MAX_NORM {
            return Err(OdeError::ExponentialOutOfRange {
                norm,
                limit: Self::MAX_NORM,
                dt,
            });
        }
        let mut e = exponential(&aug);
        for r in 0..size {
            for c in 0..size {
                e[(r, c)] *= scale[r] / scale[c];
            }
        }
        if let Some((index, &value)) = e.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(OdeError::NonFiniteModel {
                name: "a",
                row: index % size,
                col: index / size,
                value,
            });
        }
        let phi = SMatrix::<f64, N, N>::from_fn(|r, c| e[(r, c)]);
        // Γⱼ: response to u(s) = sʲ, i.e. j! times the column of y_{D−j}.
        let factorial = [1.0, 1.0, 2.0, 6.0];
        let gamma: [SVector<f64, N>; 4] = std::array::from_fn(|j| {
            SVector::<f64, N>::from_fn(|r, _| factorial[j] * e[(r, N + D - j)])
        });
        let weights = std::array::from_fn(|variant| {
            let w = stencil_weights(STENCILS[variant], &gamma);
            std::array::from_fn(|node| std::array::from_fn(|r| w[node][r]))
        });
        let phi_rows = std::array::from_fn(|r| std::array::from_fn(|c| phi[(r, c)]));
        Ok(Self {
            dt,
            hold,
            phi,
            phi_rows,
            weights,
            gamma,
        })
    }

    /// The sampling interval.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// The hold in use.
    pub fn hold(&self) -> Hold {
        self.hold
    }

    /// The state-transition matrix Φ = e^{A dt}.
    pub fn transition(&self) -> &SMatrix<f64, N, N> {
        &self.phi
    }

    /// Simulates from `x0` and returns the state at every sample.
    pub fn simulate(
        &self,
        x0: &SVector<f64, N>,
        input: &SampledInput<'_>,
    ) -> Result<Vec<SVector<f64, N>>, OdeError> {
        let mut out = vec![SVector::<f64, N>::zeros(); input.values.len()];
        self.simulate_into(x0, input, &mut out)?;
        Ok(out)
    }

    /// Simulates from `x0` into `out` (one state per input sample).
    pub fn simulate_into(
        &self,
        x0: &SVector<f64, N>,
        input: &SampledInput<'_>,
        out: &mut [SVector<f64, N>],
    ) -> Result<(), OdeError> {
        if out.len() != input.values.len() {
            return Err(OdeError::LengthMismatch {
                expected: input.values.len(),
                got: out.len(),
            });
        }
        self.simulate_with(x0, input, |i, x| out[i] = *x)
    }

    /// Simulates from `x0`, handing each sample's state to `output(i, x)`; allocates
    /// nothing.
    ///
    /// A state that overflows (an unstable model, or an input too large for the model)
    /// is [`OdeError::NonFiniteState`] naming the first such sample; `output` has then
    /// seen non-finite states and its results must be discarded.
    ///
    /// ```
    /// # use msd_ode::{ExactSimulator, Hold, LtiModel, SampledInput, SMatrix, SVector, Breakpoint};
    /// # let model = LtiModel { a: SMatrix::<f64, 2, 2>::new(0.0, 1.0, -48.0, -0.72), b: SVector::<f64, 2>::new(0.0, 0.4) };
    /// let sim = ExactSimulator::new(&model, 0.002, Hold::Cubic)?;
    /// // A 6 N step at t = 0.5 s (sample 250), exact thanks to its breakpoint.
    /// let force: Vec<f64> = (0..1001).map(|i| if i >= 250 { 6.0 } else { 0.0 }).collect();
    /// let jumps = [Breakpoint { index: 250, left: 0.0, right: 6.0 }];
    /// let mut peak = 0.0f64;
    /// sim.simulate_with(&SVector::zeros(), &SampledInput { values: &force, breakpoints: &jumps },
    ///     |_, x| peak = peak.max(x[0]))?;
    /// assert!(peak > 6.0 / 120.0); // overshoot of a lightly damped step response
    /// # Ok::<(), msd_ode::OdeError>(())
    /// ```
    pub fn simulate_with<F: FnMut(usize, &SVector<f64, N>)>(
        &self,
        x0: &SVector<f64, N>,
        input: &SampledInput<'_>,
        mut output: F,
    ) -> Result<(), OdeError> {
        input.validate()?;
        if let Some((index, &value)) = x0.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(OdeError::NonFiniteInitialState { index, value });
        }
        let last = self.run(x0, input, &mut output);
        if last.iter().all(|v| v.is_finite()) {
            return Ok(());
        }
        // The state overflowed (an unstable model, or a huge input). Once a component is
        // not finite every component is NaN from the next step on (each is a sum over all
        // of them), so the final state tells; a second pass, only now, finds the first
        // sample for the error.
        let mut first: Option<(usize, usize)> = None;
        self.run(x0, input, &mut |i, x: &SVector<f64, N>| {
            if first.is_none() {
                first = x.iter().position(|v| !v.is_finite()).map(|c| (i, c));
            }
        });
        let (index, component) = first.unwrap_or((input.values.len() - 1, 0));
        Err(OdeError::NonFiniteState {
            t: index as f64 * self.dt,
            component,
        })
    }

    /// The simulation proper, on checked input; returns the final state.
    fn run<F: FnMut(usize, &SVector<f64, N>)>(
        &self,
        x0: &SVector<f64, N>,
        input: &SampledInput<'_>,
        output: &mut F,
    ) -> [f64; N] {
        let mut x: [f64; N] = std::array::from_fn(|i| x0[i]);
        output(0, x0);
        for_each_step(input, self.hold, |variant, u, i| {
            self.advance(&mut x, &self.weights[variant], u, i, output)
        });
        x
    }

    /// One step x ← Φx + Σ_m w_m u_m, then `output(i, x)`.
    #[inline(always)]
    fn advance<F: FnMut(usize, &SVector<f64, N>)>(
        &self,
        x: &mut [f64; N],
        w: &[[f64; N]; 4],
        u: [f64; 4],
        i: usize,
        output: &mut F,
    ) {
        let mut next = [0.0; N];
        for (r, row) in self.phi_rows.iter().enumerate() {
            // The drive does not depend on x: it is summed off the state's dependency
            // chain, so the loop runs at the speed of the bare recurrence x ← Φx + d.
            let drive = (w[0][r] * u[0] + w[1][r] * u[1]) + (w[2][r] * u[2] + w[3][r] * u[3]);
            let mut acc = row[0] * x[0];
            for (p, xc) in row.iter().zip(x.iter()).skip(1) {
                acc += p * xc;
            }
            next[r] = acc + drive;
        }
        *x = next;
        output(i, &SVector::<f64, N>::from(next));
    }
}

/// Visits every step of `input` (validated) in order: `visit(variant, nodes, i)` for the
/// step from sample i − 1 to sample i, with the stencil variant the hold and the
/// breakpoints call for and the stencil's node values.
#[inline]
fn for_each_step<V: FnMut(usize, [f64; 4], usize)>(
    input: &SampledInput<'_>,
    hold: Hold,
    mut visit: V,
) {
    let values = input.values;
    let n = values.len();
    if n == 1 {
        return;
    }
    let mut bps = input.breakpoints.iter().peekable();
    let mut a = 0usize;
    let mut a_value = values[0];
    if let Some(bp) = bps.next_if(|bp| bp.index == 0) {
        a_value = bp.right;
    }
    while a < n - 1 {
        let (b, b_value, b_right) = match bps.next() {
            Some(bp) => (bp.index, bp.left, bp.right),
            None => (n - 1, values[n - 1], values[n - 1]),
        };
        visit_piece(hold, values, a, a_value, b, b_value, &mut visit);
        a = b;
        a_value = b_right;
    }
}

/// Visits the intervals of the smooth piece [a, b] (a < b), whose end values are
/// `a_value` (right value at a) and `b_value` (left value at b): `visit(variant, nodes,
/// i)` for the step into sample i, with the stencil variant and its node values.
#[allow(clippy::too_many_arguments)]
#[inline]
fn visit_piece<V: FnMut(usize, [f64; 4], usize)>(
    hold: Hold,
    values: &[f64],
    a: usize,
    a_value: f64,
    b: usize,
    b_value: f64,
    visit: &mut V,
) {
    debug_assert!(a < b && b < values.len());
    let node = |j: usize| -> f64 {
        if j == a {
            a_value
        } else if j == b {
            b_value
        } else {
            values[j]
        }
    };
    let nodes = b - a + 1;
    match (hold, nodes) {
        (Hold::Zero, _) => {
            for i in a..b {
                visit(ZERO, [node(i), 0.0, 0.0, 0.0], i + 1);
            }
        }
        (Hold::First, _) | (Hold::Cubic, 2) => {
            for i in a..b {
                visit(LINEAR, [node(i), node(i + 1), 0.0, 0.0], i + 1);
            }
        }
        (Hold::Cubic, 3) => {
            let u = [node(a), node(a + 1), node(a + 2), 0.0];
            visit(QUAD_LEFT, u, a + 1);
            visit(QUAD_RIGHT, u, a + 2);
        }
        (Hold::Cubic, _) => {
            // First interval: one-sided stencil a..a+3.
            visit(
                CUBIC_LEFT,
                [node(a), node(a + 1), node(a + 2), node(a + 3)],
                a + 1,
            );
            // Interior intervals i = a+1 ..= b−2: centred stencil i−1..i+2.
            let interior_end = b - 2; // inclusive
            if a < interior_end {
                let i = a + 1;
                visit(
                    CUBIC_CENTRED,
                    [node(i - 1), node(i), node(i + 1), node(i + 2)],
                    i + 1,
                );
            }
            // Fast path: every node strictly inside the piece.
            for (i, u) in ((a + 2)..interior_end).zip(values[a + 1..].windows(4)) {
                visit(CUBIC_CENTRED, [u[0], u[1], u[2], u[3]], i + 1);
            }
            if interior_end >= a + 2 {
                let i = interior_end;
                visit(
                    CUBIC_CENTRED,
                    [node(i - 1), node(i), node(i + 1), node(i + 2)],
                    i + 1,
                );
            }
            // Last interval: one-sided stencil b−3..b.
            visit(
                CUBIC_RIGHT,
                [node(b - 3), node(b - 2), node(b - 1), node(b)],
                b,
            );
        }
    }
}

/// Folds the Lagrange basis of the stencil `offsets` into the monomial responses Γⱼ:
/// W_m = Σⱼ coef_j(ℓ_m) Γⱼ.
fn stencil_weights<const N: usize>(
    offsets: &[f64],
    gamma: &[SVector<f64, N>; 4],
) -> [SVector<f64, N>; 4] {
    let basis = lagrange_monomials(offsets);
    std::array::from_fn(|m| {
        (0..4).fold(SVector::<f64, N>::zeros(), |w, j| {
            w + gamma[j] * basis[m][j]
        })
    })
}

/// Monomial coefficients of the Lagrange basis of the stencil `offsets`:
/// `basis[m][j]` is the coefficient of sʲ in ℓ_m(s) = Π_{q≠m} (s − o_q)/(o_m − o_q)
/// (rows beyond the stencil's nodes are zero).
fn lagrange_monomials(offsets: &[f64]) -> [[f64; 4]; 4] {
    debug_assert!(!offsets.is_empty() && offsets.len() <= 4);
    let mut basis = [[0.0; 4]; 4];
    for (m, coef) in basis.iter_mut().enumerate().take(offsets.len()) {
        coef[0] = 1.0;
        let mut degree = 0;
        for (q, &oq) in offsets.iter().enumerate() {
            if q == m {
                continue;
            }
            let denom = offsets[m] - oq;
            // multiply by (s − oq)/denom
            for d in (0..=degree + 1).rev() {
                let shifted = if d > 0 { coef[d - 1] } else { 0.0 };
                coef[d] = (shifted - oq * coef[d]) / denom;
            }
            degree += 1;
        }
    }
    basis
}

/// e^M. The two sizes the toolkit discretises — 6 (a 2-state plant) and 12 (with its
/// six sensitivity states) — are computed on fixed-size matrices: no allocation, and
/// nalgebra's own products instead of `matrixmultiply`'s, which picks its kernel (with
/// or without FMA, AVX-512 or not) by the CPU it runs on: Φ and Γ no longer depend on
/// that choice. Other sizes take the heap path.
fn exponential(m: &DMatrix<f64>) -> DMatrix<f64> {
    // `exp` is implemented for each fixed size, not for a generic one.
    macro_rules! fixed {
        ($s:literal) => {{
            let e = SMatrix::<f64, $s, $s>::from_fn(|r, c| m[(r, c)]).exp();
            DMatrix::from_fn($s, $s, |r, c| e[(r, c)])
        }};
    }
    debug_assert!(m.is_square());
    match m.nrows() {
        6 => fixed!(6),
        12 => fixed!(12),
        _ => m.exp(),
    }
}

/// Balances `m` in place by a diagonal similarity D⁻¹ M D with powers of two on the
/// diagonal (Parlett & Reinsch 1969, as LAPACK's `gebal` without permutations): each
/// row and column pair is scaled until their off-diagonal 1-norms are within a factor
/// of two. Returns the diagonal of D. Exact: scaling by powers of two rounds nothing.
fn balance(m: &mut DMatrix<f64>) -> Vec<f64> {
    let n = m.nrows();
    let mut d = vec![1.0; n];
    for _sweep in 0..64 {
        let mut done = true;
        for i in 0..n {
            let (mut c, mut r) = (0.0, 0.0);
            for j in (0..n).filter(|&j| j != i) {
                c += m[(j, i)].abs();
                r += m[(i, j)].abs();
            }
            if c == 0.0 || r == 0.0 || !(c + r).is_finite() {
                continue;
            }
            let total = c + r;
            let mut f = 1.0;
            while c < r / 2.0 {
                c *= 2.0;
                r /= 2.0;
                f *= 2.0;
            }
            while c >= r * 2.0 {
                c /= 2.0;
                r *= 2.0;
                f /= 2.0;
            }
            if c + r < 0.95 * total {
                done = false;
                d[i] *= f;
                for j in 0..n {
                    m[(i, j)] /= f;
                    m[(j, i)] *= f;
                }
            }
        }
        if done {
            break;
        }
    }
    d
}
