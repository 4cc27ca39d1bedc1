//! One exact step of a linear system of any size whose input is a ramp: the heap-sized
//! companion of [`ExactSimulator`](crate::lti::ExactSimulator) for systems whose size is known
//! only at run time (chains of masses with their sensitivities).

use super::{balance, exponential};
use crate::error::OdeError;
use nalgebra::{DMatrix, DVector};

/// x(t + h) = Φ·x(t) + Γᵤ·u(t) + Γᵥ·u′ for x′ = A·x + b·u, when over [t, t + h] the input
/// is the ramp u(t) + u′·(s − t): the first-order hold of a sampled input with slope
/// u′ = (uᵢ₊₁ − uᵢ)/dt. A step `h` shorter than the sampling interval, with the slope of
/// the whole interval, gives the state between samples (a delayed sensor reads it).
///
/// Φ, Γᵤ and Γᵥ come from one matrix exponential of [[A, b, 0], [0, 0, 1], [0, 0, 0]]·h
/// (Van Loan), balanced first as in [`ExactSimulator`](crate::lti::ExactSimulator).
///
/// ```
/// use msd_ode::RampStep;
/// use nalgebra::{DMatrix, DVector};
/// // x′ = u: one step integrates the ramp exactly, x(h) = u·h + u′·h²/2.
/// let step = RampStep::new(&DMatrix::zeros(1, 1), &DVector::from_element(1, 1.0), 0.5)?;
/// assert_eq!((step.phi[(0, 0)], step.input[0], step.slope[0]), (1.0, 0.5, 0.125));
/// # Ok::<(), msd_ode::OdeError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct RampStep {
    /// Φ = e^{A·h}.
    pub phi: DMatrix<f64>,
    /// Γᵤ = ∫₀ʰ e^{A·s} ds · b: the response to the input's value at the start.
    pub input: DVector<f64>,
    /// Γᵥ = ∫₀ʰ e^{A·s}·(h − s) ds · b: the response to its slope.
    pub slope: DVector<f64>,
}

impl RampStep {
    /// Discretises x′ = `a`·x + `b`·u for the step `h` (> 0, finite).
    ///
    /// Fails on a non-finite or mis-sized model, a bad `h`, or a balanced ‖A·h‖ above
    /// [`ExactSimulator::MAX_NORM`](crate::ExactSimulator::MAX_NORM).
    pub fn new(a: &DMatrix<f64>, b: &DVector<f64>, h: f64) -> Result<Self, OdeError> {
        let n = a.nrows();
        if a.ncols() != n || b.len() != n {
            return Err(OdeError::InvalidOption {
                name: "b",
                value: b.len() as f64,
                expected: "a square a and a b with as many rows",
            });
        }
        for ((r, c), &value) in a
            .iter()
            .enumerate()
            .map(|(i, v)| ((i % n, i / n), v))
            .chain(b.iter().enumerate().map(|(r, v)| ((r, n), v)))
        {
            if !value.is_finite() {
                let name = if c == n { "b" } else { "a" };
                let col = if c == n { 0 } else { c };
                return Err(OdeError::NonFiniteModel {
                    name,
                    row: r,
                    col,
                    value,
                });
            }
        }
        if !(h.is_finite() && h > 0.0) {
            return Err(OdeError::InvalidOption {
                name: "h",
                value: h,
                expected: "a finite number > 0",
            });
        }
        let mut aug = DMatrix::<f64>::zeros(n + 2, n + 2);
        aug.view_mut((0, 0), (n, n)).copy_from(&(a * h));
        aug.view_mut((0, n), (n, 1)).copy_from(&(b * h));
        aug[(n, n + 1)] = 1.0;
        let scale = balance(&mut aug);
        let norm = (0..n + 2)
            .map(|c| aug.column(c).iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0, f64::max);
        let limit = crate::ExactSimulator::<1>::MAX_NORM;
        if norm.is_nan() || norm > limit {
            return Err(OdeError::ExponentialOutOfRange { norm, limit, dt: h });
        }
        let mut e = exponential(&aug);
        for r in 0..n + 2 {
            for c in 0..n + 2 {
                e[(r, c)] *= scale[r] / scale[c];
            }
        }
        // Column n is the response to a unit input held at its start value (its
        // integrator starts at 1); column n + 1 to a unit slope, in units of h: ×h.
        Ok(Self {
            phi: e.view((0, 0), (n, n)).clone_owned(),
            input: e.view((0, n), (n, 1)).column(0).clone_owned(),
            slope: e.view((0, n + 1), (n, 1)).column(0) * h,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_damped_oscillator_steps_as_the_fixed_size_simulator() {
        // m x″ + c x′ + k x = u with a ramp: the closed form through ExactSimulator<2>
        // with the first-order hold gives the same state to rounding.
        let (m, c, k, dt) = (2.5, 1.8, 120.0, 0.01);
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -k / m, -c / m]);
        let b = DVector::from_column_slice(&[0.0, 1.0 / m]);
        let step = RampStep::new(&a, &b, dt).unwrap();
        let model = crate::lti::LtiModel {
            a: nalgebra::SMatrix::<f64, 2, 2>::from_row_slice(&[0.0, 1.0, -k / m, -c / m]),
            b: nalgebra::SVector::<f64, 2>::new(0.0, 1.0 / m),
        };
        let u: Vec<f64> = (0..50).map(|i| (0.3 * i as f64).sin()).collect();
        let fixed = crate::ExactSimulator::new(&model, dt, crate::Hold::First)
            .unwrap()
            .simulate(
                &nalgebra::SVector::zeros(),
                &crate::SampledInput::smooth(&u),
            )
            .unwrap();
        let mut x = DVector::zeros(2);
        for i in 0..u.len() - 1 {
            x = &step.phi * &x + &step.input * u[i] + &step.slope * ((u[i + 1] - u[i]) / dt);
            let want = fixed[i + 1];
            // Both are exact to rounding of a state of size 1e-2: 1e-15 absolute.
            assert!(
                (x[0] - want[0]).abs() < 1e-15 && (x[1] - want[1]).abs() < 1e-14,
                "{i}"
            );
        }
    }

    #[test]
    fn bad_models_are_refused() {
        let a = DMatrix::from_element(2, 2, f64::NAN);
        let b = DVector::zeros(2);
        assert!(matches!(
            RampStep::new(&a, &b, 0.1),
            Err(OdeError::NonFiniteModel { name: "a", .. })
        ));
        let a = DMatrix::zeros(2, 2);
        assert!(RampStep::new(&a, &DVector::zeros(3), 0.1).is_err());
        assert!(RampStep::new(&a, &b, 0.0).is_err());
        assert!(RampStep::new(&(a.add_scalar(1e14)), &b, 1.0).is_err());
    }
}
