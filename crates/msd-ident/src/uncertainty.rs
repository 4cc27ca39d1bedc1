//! Gauss–Newton covariance, confidence intervals and identifiability diagnostics.
//!
//! ## The method
//! With J the N×p Jacobian ∂x̂/∂θ of the model output at θ̂ (exact sensitivities),
//! σ̂² = SSE/(N − p) and Cov(θ̂) ≈ σ̂²·(JᵀJ)⁻¹. Standard errors are the square roots of
//! its diagonal; the 95 % intervals use Student's t with N − p degrees of freedom. The
//! natural frequency and damping ratio get intervals by the delta method,
//! Var g(θ̂) ≈ ∇gᵀ Cov ∇g. The condition number is that of JᵀJ with its columns scaled
//! to unit norm, so it does not depend on the units. The intervals are only as good as
//! the model: they assume white Gaussian output noise and a correct model structure.

use crate::least_squares::SingularError;
use crate::{
    error::{IdentError, Result},
    params::Parameters,
};
pub use msd_opt::statistics::Interval;
pub(crate) use msd_opt::statistics::t_975;
use msd_opt::statistics::{Linearization, correlation, delta_variance};
use nalgebra::DMatrix;
use serde::Serialize;

/// Uncertainty of an estimate.
///
/// Serializes with the matrices as lists of rows. Displays one line per interval, then
/// σ̂, the degrees of freedom, the condition number and every warning.
///
/// ```
/// use msd_ident::{estimate, EstimationOptions, PaperExperiment};
/// let experiment = PaperExperiment::generate(1)?;
/// let u = estimate(&experiment.identification, &EstimationOptions::fast())?.uncertainty;
/// let json = serde_json::to_value(&u).expect("serializable");
/// assert_eq!(json["names"][2], "stiffness");
/// assert_eq!(json["correlation"].as_array().map(Vec::len), Some(3));
/// assert_eq!(json["correlation"][0][2], u.correlation[(0, 2)]); // row 0, column 2
/// assert!(u.to_string().starts_with(&format!("m = {:.6} ± ", u.mass.value)));
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Uncertainty {
    /// Names of the estimated quantities, in the order of the matrices.
    pub names: Vec<&'static str>,
    /// Their estimated values.
    pub values: Vec<f64>,
    /// Covariance matrix σ̂²(JᵀJ)⁻¹.
    #[serde(serialize_with = "crate::ser::matrix_rows")]
    pub covariance: DMatrix<f64>,
    /// Correlation matrix.
    #[serde(serialize_with = "crate::ser::matrix_rows")]
    pub correlation: DMatrix<f64>,
    /// Condition number of the column-normalised JᵀJ.
    pub condition_number: f64,
    /// σ̂ = √(SSE/(N − p)), the estimated noise level.
    pub sigma: f64,
    /// N − p.
    pub degrees_of_freedom: usize,
    /// Mass with interval.
    pub mass: Interval,
    /// Damping with interval.
    pub damping: Interval,
    /// Stiffness with interval.
    pub stiffness: Interval,
    /// Natural frequency (Hz) with interval (delta method).
    pub natural_frequency_hz: Interval,
    /// Damping ratio with interval (delta method).
    pub damping_ratio: Interval,
    /// Plain-language identifiability warnings (empty when all is well).
    pub warnings: Vec<String>,
}

impl std::fmt::Display for Uncertainty {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "m = {}", self.mass)?;
        writeln!(f, "c = {}", self.damping)?;
        writeln!(f, "k = {}", self.stiffness)?;
        writeln!(f, "fn = {} Hz", self.natural_frequency_hz)?;
        writeln!(f, "ζ = {}", self.damping_ratio)?;
        write!(
            f,
            "σ̂ = {:.4e}, {} degrees of freedom, condition number {:.3e}",
            self.sigma, self.degrees_of_freedom, self.condition_number
        )?;
        for warning in &self.warnings {
            write!(
                f,
                "
warning: {warning}"
            )?;
        }
        Ok(())
    }
}

/// Columns of the physical parameters among the estimated quantities: `Some(column)` or
/// `None` for a fixed parameter.
pub(crate) type ParameterColumns = [Option<usize>; 3];

/// Builds the uncertainty from the Jacobian of the model output (N×p), the SSE, and the
/// positions of m, c, k among the columns.
pub(crate) fn from_jacobian(
    jacobian: &DMatrix<f64>,
    sse: f64,
    names: Vec<&'static str>,
    values: Vec<f64>,
    parameters: &Parameters,
    columns: ParameterColumns,
) -> Result<Uncertainty> {
    let normal = jacobian.transpose() * jacobian;
    let (rows, p) = jacobian.shape();
    let noise = ResidualNoise::independent(sse, rows, p)?;
    from_normal_matrix(&normal, noise, names, values, parameters, columns)
}

/// The residuals' sum of squares and the degrees of freedom it is spread over:
/// s² = SSE/dof.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ResidualNoise {
    pub sse: f64,
    /// Rows − p for independent errors; rows − tr((JᵀJ)⁻¹JᵀCJ) for errors correlated by
    /// C (what the fit's residuals actually lose to the parameters).
    pub dof: f64,
}

impl ResidualNoise {
    /// Independent errors: `rows` − `p` degrees of freedom, an error when there are none.
    pub(crate) fn independent(sse: f64, rows: usize, p: usize) -> Result<Self> {
        if rows <= p {
            return Err(IdentError::TooFewSamples {
                got: rows,
                needed: p + 1,
                why: "confidence intervals need more samples than parameters",
            });
        }
        Ok(Self {
            sse,
            dof: (rows - p) as f64,
        })
    }
}

/// The same from a normal matrix (JᵀJ, or the sandwich's for correlated errors) and the
/// residual noise it is scaled by. The intervals use Student's t with ⌊dof⌋ degrees of
/// freedom.
pub(crate) fn from_normal_matrix(
    normal: &DMatrix<f64>,
    noise: ResidualNoise,
    names: Vec<&'static str>,
    values: Vec<f64>,
    parameters: &Parameters,
    columns: ParameterColumns,
) -> Result<Uncertainty> {
    let p = normal.nrows();
    let linearization =
        Linearization::from_normal_matrix(normal).map_err(|e| e.error("the output", &names))?;
    let condition_number = linearization.condition_number;
    let dof = noise.dof.floor().max(1.0) as usize;
    let sigma2 = noise.sse / noise.dof;
    let covariance = linearization.covariance(sigma2);
    let se: Vec<f64> = (0..p).map(|j| covariance[(j, j)].max(0.0).sqrt()).collect();
    let correlation = correlation(&covariance);
    let t = t_975(dof);

    let theta = parameters.to_array();
    let param_se = |i: usize| columns[i].map_or(0.0, |c| se[c]);
    let cov = |i: usize, j: usize| match (columns[i], columns[j]) {
        (Some(a), Some(b)) => covariance[(a, b)],
        _ => 0.0,
    };
    let delta = |gradient: [f64; 3]| delta_variance(&gradient, cov);
    let (m, c, k) = (theta[0], theta[1], theta[2]);
    let fnat = parameters.natural_frequency_hz();
    let zeta = parameters.damping_ratio();
    let fn_var = delta([-fnat / (2.0 * m), 0.0, fnat / (2.0 * k)]);
    let zeta_var = delta([
        -zeta / (2.0 * m),
        1.0 / (2.0 * (m * k).sqrt()),
        -zeta / (2.0 * k),
    ]);

    let mut warnings = Vec::new();
    for r in 0..p {
        for c in (r + 1)..p {
            let rho = correlation[(r, c)];
            if rho.abs() > 0.99 {
                warnings.push(format!(
                    "{} and {} are strongly correlated (ρ = {rho:.3}): the data barely tell them apart; consider fixing one (e.g. a weighed mass) or a richer input",
                    names[r], names[c]
                ));
            }
        }
    }
    if condition_number > 1e8 {
        warnings.push(format!(
            "the sensitivity matrix is ill-conditioned (condition number {condition_number:.1e}): the estimates are fragile"
        ));
    }
    Ok(Uncertainty {
        names,
        values,
        correlation,
        covariance,
        condition_number,
        sigma: sigma2.sqrt(),
        degrees_of_freedom: dof,
        mass: Interval::new(m, param_se(0), t),
        damping: Interval::new(c, param_se(1), t),
        stiffness: Interval::new(k, param_se(2), t),
        natural_frequency_hz: Interval::from_variance(fnat, fn_var, t),
        damping_ratio: Interval::from_variance(zeta, zeta_var, t),
        warnings,
    })
}
