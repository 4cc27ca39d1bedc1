//! Exact forward sensitivities of the displacement to m, c, k and the initial state.
//!
//! ## The equations
//! With z = (x, v) and z' = A(θ) z + b(θ) u, the sensitivities s_θ = ∂z/∂θ obey
//! s_θ' = A s_θ + (∂A/∂θ) z + (∂b/∂θ) u, a linear system driven by the response itself:
//!
//! - ∂/∂m: v_m' = (−k x_m − c v_m)/m + (k x + c v − u)/m²,
//! - ∂/∂c: v_c' = (−k x_c − c v_c)/m − v/m,
//! - ∂/∂k: v_k' = (−k x_k − c v_k)/m − x/m,
//!
//! with x_θ' = v_θ and zero initial values. Together with z they form one 8-state
//! linear system driven by u, which msd-ode simulates exactly with the same hold as the
//! response, so the Jacobian is the exact derivative of the simulated output. The
//! sensitivities to the initial state are the first row of Φⁱ = e^{A·i·dt}.

use crate::{
    data::Excitation,
    error::Result,
    params::{InitialState, Parameters},
};
use msd_ode::{ExactSimulator, Hold, LtiModel, SVector, SampledInput};

/// One sample of the response and its sensitivities.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensitivitySample {
    /// Displacement x(tᵢ).
    pub displacement: f64,
    /// ∂x/∂m, ∂x/∂c, ∂x/∂k.
    pub parameters: [f64; 3],
    /// ∂x/∂x(t₀), ∂x/∂x'(t₀).
    pub initial_state: [f64; 2],
}

/// Simulates the response and its exact sensitivities, handing each sample to
/// `output(i, sample)`; allocates nothing per sample.
///
/// ```
/// use msd_ident::{sensitivity::sensitivities, Excitation, InitialState, Parameters};
/// use msd_ode::Hold;
/// use msd_signal::paper_identification_input;
/// let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
/// let mut dk_final = 0.0;
/// sensitivities(&Parameters::PAPER, &input, InitialState::REST, Hold::Cubic, |_, s| {
///     dk_final = s.parameters[2];
/// })?;
/// assert!(dk_final != 0.0);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn sensitivities<F: FnMut(usize, &SensitivitySample)>(
    parameters: &Parameters,
    excitation: &Excitation,
    initial: InitialState,
    hold: Hold,
    mut output: F,
) -> Result<()> {
    parameters.validate()?;
    let sim = ExactSimulator::new(&sensitivity_model(parameters), excitation.dt(), hold)?;
    let t = sim.transition();
    let phi = [[t[(0, 0)], t[(0, 1)]], [t[(1, 0)], t[(1, 1)]]];
    let mut z0 = SVector::<f64, 8>::zeros();
    z0[0] = initial.displacement;
    z0[1] = initial.velocity;
    let input = SampledInput {
        values: excitation.samples(),
        breakpoints: excitation.breakpoints(),
    };
    // First row of Φⁱ, advanced alongside the simulation: (Φⁱ⁺¹)₀ = (Φⁱ)₀ Φ.
    let mut row = [1.0, 0.0];
    sim.simulate_with(&z0, &input, |i, z| {
        if i > 0 {
            row = [
                row[0] * phi[0][0] + row[1] * phi[1][0],
                row[0] * phi[0][1] + row[1] * phi[1][1],
            ];
        }
        let sample = SensitivitySample {
            displacement: z[0],
            parameters: [z[2], z[4], z[6]],
            initial_state: row,
        };
        output(i, &sample);
    })?;
    Ok(())
}

/// The 8-state system z' = A z + b u of the response (x, v) and its sensitivities
/// (x_m, v_m, x_c, v_c, x_k, v_k), in that order (the equations in the module docs).
pub(crate) fn sensitivity_model(parameters: &Parameters) -> LtiModel<8> {
    parameters.plant().sensitivity_model()
}
