//! The one error type of this crate.

/// Everything that can go wrong in `msd-ode`. Each variant says where it happened.
///
/// ```
/// use msd_ode::{Ode45Options, OdeError};
/// let options = Ode45Options { rel_tol: -1.0, ..Ode45Options::default() };
/// let err = options.validate().unwrap_err();
/// assert!(matches!(err, OdeError::InvalidOption { name: "rel_tol", .. }));
/// assert!(err.to_string().contains("rel_tol"));
/// ```
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OdeError {
    /// An option is outside its allowed range.
    #[error("invalid option {name} = {value}: expected {expected}")]
    InvalidOption {
        /// Field name of the option.
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// The allowed range, in words.
        expected: &'static str,
    },
    /// The time span or output grid is unusable.
    #[error("invalid time span at index {index} (t = {value}): {reason}")]
    InvalidTimeSpan {
        /// Index of the offending entry.
        index: usize,
        /// The offending time.
        value: f64,
        /// What was expected.
        reason: &'static str,
    },
    /// An initial-state component is NaN or infinite.
    #[error("initial state component {index} is {value}: expected a finite number")]
    NonFiniteInitialState {
        /// Index of the component.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// The step size fell below 16·eps(t) without meeting the tolerance
    /// (MATLAB: "Unable to meet integration tolerances without reducing the step size
    /// below the smallest value allowed").
    #[error(
        "step size underflow at t = {t}: step {step:e} is below the smallest allowed; the tolerances cannot be met (stiff or singular problem?)"
    )]
    StepSizeUnderflow {
        /// Time reached.
        t: f64,
        /// The step size that failed.
        step: f64,
    },
    /// The step budget ran out before the end of the interval.
    #[error(
        "too many steps: {steps} accepted steps reached at t = {t} before the end of the interval"
    )]
    TooManySteps {
        /// Time reached.
        t: f64,
        /// Steps taken.
        steps: usize,
    },
    /// The right-hand side or the state became NaN or infinite (ode45), or the state of
    /// the exact simulator overflowed (an unstable model or a huge input).
    #[error("non-finite state or derivative at t = {t} (component {component})")]
    NonFiniteState {
        /// Time at which it was detected (for the exact simulator, i·dt from the first
        /// sample, i the first sample whose state is not finite).
        t: f64,
        /// The first non-finite component.
        component: usize,
    },
    /// The system matrices of a linear model are not finite.
    #[error("linear model entry {name}[{row},{col}] is {value}: expected a finite number")]
    NonFiniteModel {
        /// `"a"` or `"b"`.
        name: &'static str,
        /// Row index.
        row: usize,
        /// Column index.
        col: usize,
        /// The value.
        value: f64,
    },
    /// ‖A·dt‖ is too large for a matrix exponential: the model is far too stiff (or its
    /// parameters absurd) for this sampling interval.
    #[error(
        "‖A·dt‖₁ = {norm:e} exceeds {limit:e}: the model is far too stiff for a step of {dt} s (check the parameters or sample faster)"
    )]
    ExponentialOutOfRange {
        /// The 1-norm of the scaled augmented matrix.
        norm: f64,
        /// The largest accepted.
        limit: f64,
        /// The step.
        dt: f64,
    },
    /// A sampled input is unusable.
    #[error("invalid sampled input at sample {index} (value {value}): {reason}")]
    InvalidInput {
        /// Sample or breakpoint index.
        index: usize,
        /// The offending value.
        value: f64,
        /// What was expected.
        reason: &'static str,
    },
    /// The output buffer does not match the input length.
    #[error("output length {got} does not match the input length {expected}")]
    LengthMismatch {
        /// Required length.
        expected: usize,
        /// Length given.
        got: usize,
    },
}
