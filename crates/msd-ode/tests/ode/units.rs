//! The exact simulator does not depend on the units of the state or the input: a change
//! of units x̃ = S·x, ũ = u/g is a similarity of the model, and the simulation must
//! follow it to rounding, however far S and g are from 1. (Sensitivities ∂x/∂m of a
//! 1 µg mass are ~1e9 times x; a force in µN is 1e6 times one in N.)

use crate::common::{Plant, paper_input};
use msd_ode::{ExactSimulator, Hold, LtiModel, SMatrix, SVector, SampledInput};

const DT: f64 = 0.002;
const N: usize = 7501;

fn force() -> Vec<f64> {
    (0..N).map(|i| paper_input(i as f64 * DT)).collect()
}

fn run(model: &LtiModel<2>, values: &[f64]) -> Vec<SVector<f64, 2>> {
    ExactSimulator::new(model, DT, Hold::Cubic)
        .expect("a representable model")
        .simulate(&SVector::zeros(), &SampledInput::smooth(values))
        .expect("simulates")
}

/// Largest |a − b| over the record, relative to the largest |b|, per component.
fn relative_difference(a: &[SVector<f64, 2>], b: &[SVector<f64, 2>]) -> [f64; 2] {
    std::array::from_fn(|j| {
        let scale = b.iter().fold(0.0f64, |m, v| m.max(v[j].abs()));
        let worst = a
            .iter()
            .zip(b)
            .fold(0.0f64, |m, (x, y)| m.max((x[j] - y[j]).abs()));
        worst / scale
    })
}

/// Rounding bound for comparing two exact simulations of the same 7501-sample record:
/// the one-step maps agree to ~10·eps after the exponential, and a stable recurrence
/// accumulates at most ~N such errors, so 1e-11 relative leaves a wide margin while any
/// unit-dependent loss of digits (2e-10 before balancing) fails it.
const ROUNDING: f64 = 1e-11;

#[test]
fn the_state_may_be_in_any_units() {
    let model = Plant::PAPER.model();
    let reference = run(&model, &force());
    for s in [1e-18, 1e-12, 1e-6, 1e6, 1e12, 1e18] {
        // x̃ = S x with S = diag(1, s): Ã = S A S⁻¹, b̃ = S b.
        let sm = SMatrix::<f64, 2, 2>::new(1.0, 0.0, 0.0, s);
        let si = SMatrix::<f64, 2, 2>::new(1.0, 0.0, 0.0, 1.0 / s);
        let scaled = LtiModel {
            a: sm * model.a * si,
            b: sm * model.b,
        };
        let x: Vec<SVector<f64, 2>> = run(&scaled, &force()).into_iter().map(|v| si * v).collect();
        let d = relative_difference(&x, &reference);
        assert!(d[0] < ROUNDING && d[1] < ROUNDING, "s = {s:e}: {d:?}");
    }
}

#[test]
fn the_input_may_be_in_any_units() {
    let model = Plant::PAPER.model();
    let reference = run(&model, &force());
    for g in [1e-18, 1e-9, 1e9, 1e18] {
        // ũ = u/g and b̃ = g·b: the same response.
        let scaled = LtiModel {
            a: model.a,
            b: model.b * g,
        };
        let values: Vec<f64> = force().iter().map(|u| u / g).collect();
        let d = relative_difference(&run(&scaled, &values), &reference);
        assert!(d[0] < ROUNDING && d[1] < ROUNDING, "g = {g:e}: {d:?}");
    }
}

/// A stiffness far beyond any sampling, in any units, is still refused: ωn·dt = 2e13
/// exceeds what the exponential can take however the state is scaled.
#[test]
fn absurd_stiffness_is_refused_in_any_units() {
    let absurd = Plant {
        m: 1e-20,
        c: 1.0,
        k: 1e12,
    };
    for s in [1e-9, 1.0, 1e9] {
        let sm = SMatrix::<f64, 2, 2>::new(1.0, 0.0, 0.0, s);
        let si = SMatrix::<f64, 2, 2>::new(1.0, 0.0, 0.0, 1.0 / s);
        let model = absurd.model();
        let scaled = LtiModel {
            a: sm * model.a * si,
            b: sm * model.b,
        };
        let err = ExactSimulator::new(&scaled, DT, Hold::Cubic).unwrap_err();
        assert!(
            matches!(err, msd_ode::OdeError::ExponentialOutOfRange { norm, .. } if norm > 1e12),
            "s = {s:e}: {err:?}"
        );
    }
}
