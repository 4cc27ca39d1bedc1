//! The uncertainty an experiment will give, predicted before it is run.

use super::layout::Layout;
use super::problem::output_jacobian;
use crate::uncertainty::from_jacobian;
use crate::{EstimationOptions, Excitation, IdentError, Parameters, Result, Uncertainty};

/// The Cramér–Rao prediction of an estimate's uncertainty: the intervals that
/// [`estimate`](crate::estimate()) will report on a record of `excitation` from the plant
/// `plant` with white measurement noise of standard deviation `sigma`, estimating what
/// `options` estimates (its fixed parameters, initial state and offset). The covariance
/// is σ²(JᵀJ)⁻¹ with J the exact sensitivities at the plant: the smallest any unbiased
/// estimator reaches, and what least squares reaches on long records.
///
/// Standard errors scale as σ over the force: doubling the input halves them.
///
/// ```
/// use msd_ident::{predicted_uncertainty, EstimationOptions, Excitation, Parameters};
/// use msd_signal::paper_identification_input;
/// let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
/// let plan = predicted_uncertainty(&Parameters::PAPER, &input, 2.5e-3, &EstimationOptions::default())?;
/// // The paper's ζ to about ±0.6 % (95 %).
/// let zeta = plan.damping_ratio;
/// assert!(zeta.ci95[1] - zeta.value < 0.01 * zeta.value);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn predicted_uncertainty(
    plant: &Parameters,
    excitation: &Excitation,
    sigma: f64,
    options: &EstimationOptions,
) -> Result<Uncertainty> {
    plant.validate()?;
    if !(sigma.is_finite() && sigma > 0.0) {
        return Err(IdentError::InvalidParameter {
            name: "noise sigma",
            value: sigma,
            expected: "a finite standard deviation > 0 (with no noise there is nothing to predict)",
        });
    }
    let data = crate::DataSet::new("plan", excitation.clone(), vec![0.0; excitation.len()])?;
    let layout = Layout::new(options, false);
    let plant = layout.apply_fixed(plant);
    let v = layout.pack(&plant, options.initial_state, options.offset);
    let jacobian = output_jacobian(&data, &layout, &v)?;
    let dof = jacobian.nrows().saturating_sub(jacobian.ncols());
    from_jacobian(
        &jacobian,
        sigma * sigma * dof as f64,
        layout.names(),
        v,
        &plant,
        layout.parameter_columns(),
    )
}
