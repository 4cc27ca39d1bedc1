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

use crate::least_squares::{self, Linearization};
use crate::{IdentError, Parameters, Result};
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, StudentsT};

/// A value with its standard error and 95 % confidence interval.
///
/// Displays as `value ± standard error (95 % CI low … high)`, the numbers with six
/// decimals unless the format gives a precision.
///
/// ```
/// use msd_ident::Interval;
/// let k = Interval { value: 120.0, standard_error: 0.5, ci95: [119.0, 121.0] };
/// assert_eq!(format!("{k:.1}"), "120.0 ± 5.00e-1 (95 % CI 119.0 … 121.0)");
/// assert_eq!(serde_json::to_value(k)?["ci95"][1], 121.0);
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Interval {
    /// The estimate.
    pub value: f64,
    /// Its standard error (0 for a fixed parameter).
    pub standard_error: f64,
    /// The 95 % confidence interval [low, high].
    pub ci95: [f64; 2],
}

impl Interval {
    /// `value` ± `t`·`standard_error`.
    pub(crate) fn new(value: f64, standard_error: f64, t: f64) -> Self {
        Self {
            value,
            standard_error,
            ci95: [value - t * standard_error, value + t * standard_error],
        }
    }

    /// For a positive quantity (a damping ratio): the interval computed on its logarithm,
    /// `value`·exp(±`t`·`standard_error`/`value`), which cannot reach zero (the delta
    /// method: the standard error of ln x is se/x). For small se/x it is `new`'s.
    pub(crate) fn positive(value: f64, standard_error: f64, t: f64) -> Self {
        debug_assert!(value > 0.0);
        let spread = (t * standard_error / value).exp();
        Self {
            value,
            standard_error,
            ci95: [value / spread, value * spread],
        }
    }

    /// Whether `x` lies inside the 95 % interval.
    pub fn contains(&self, x: f64) -> bool {
        self.ci95[0] <= x && x <= self.ci95[1]
    }
}

impl std::fmt::Display for Interval {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let p = f.precision().unwrap_or(6);
        write!(
            f,
            "{:.p$} ± {:.2e} (95 % CI {:.p$} … {:.p$})",
            self.value, self.standard_error, self.ci95[0], self.ci95[1]
        )
    }
}

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

/// The 97.5 % quantile of Student's t with `dof` degrees of freedom: the half-width of
/// a 95 % interval in standard errors. Where t is undefined (`dof` = 0, which no caller
/// passes: each has more samples than estimated quantities) the normal's 1.96.
///
/// Above [`LARGE_DOF`] the Cornish–Fisher expansion in 1/ν (Abramowitz & Stegun 26.7.5,
/// four terms), within 1e-15 (three ulp) of scipy's `t.ppf` there; below it statrs's
/// inverse of the incomplete beta function, within 5e-13. Above 10⁴ that inverse drifts (6.5e-7 off at
/// ν = 3·10⁴, 6.8e-6 at 10⁵) and its cost grows with ν (seconds per quantile at 10⁷).
pub(crate) fn t_975(dof: usize) -> f64 {
    const Z: f64 = 1.959_963_984_540_054;
    if dof > LARGE_DOF {
        let (nu, z2) = (dof as f64, Z * Z);
        let g1 = Z * (z2 + 1.0) / 4.0;
        let g2 = Z * ((5.0 * z2 + 16.0) * z2 + 3.0) / 96.0;
        let g3 = Z * (((3.0 * z2 + 19.0) * z2 + 17.0) * z2 - 15.0) / 384.0;
        let g4 = Z * ((((79.0 * z2 + 776.0) * z2 + 1482.0) * z2 - 1920.0) * z2 - 945.0) / 92160.0;
        return Z + (g1 + (g2 + (g3 + g4 / nu) / nu) / nu) / nu;
    }
    StudentsT::new(0.0, 1.0, dof as f64)
        .map(|d| d.inverse_cdf(0.975))
        .unwrap_or(Z)
}

/// Degrees of freedom above which [`t_975`] is the expansion in 1/ν.
const LARGE_DOF: usize = 1_000;

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
    let rows = jacobian.nrows();
    from_normal_matrix(&normal, rows, sse, names, values, parameters, columns)
}

/// The same from the normal matrix JᵀJ of a Jacobian of `n` rows.
pub(crate) fn from_normal_matrix(
    normal: &DMatrix<f64>,
    n: usize,
    sse: f64,
    names: Vec<&'static str>,
    values: Vec<f64>,
    parameters: &Parameters,
    columns: ParameterColumns,
) -> Result<Uncertainty> {
    let p = normal.nrows();
    if n <= p {
        return Err(IdentError::TooFewSamples {
            got: n,
            needed: p + 1,
            why: "confidence intervals need more samples than parameters",
        });
    }
    let linearization =
        Linearization::from_normal_matrix(normal).map_err(|e| e.error("the output", &names))?;
    let condition_number = linearization.condition_number;
    let dof = n - p;
    let sigma2 = sse / dof as f64;
    let covariance = linearization.covariance(sigma2);
    let se: Vec<f64> = (0..p).map(|j| covariance[(j, j)].max(0.0).sqrt()).collect();
    let correlation = least_squares::correlation(&covariance);
    let t = t_975(dof);

    let theta = parameters.to_array();
    let param_se = |i: usize| columns[i].map_or(0.0, |c| se[c]);
    let cov = |i: usize, j: usize| match (columns[i], columns[j]) {
        (Some(a), Some(b)) => covariance[(a, b)],
        _ => 0.0,
    };
    let delta = |gradient: [f64; 3]| least_squares::delta_variance(&gradient, cov);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Golden values of Student's t quantile (MATLAB `tinv(0.975, ν)`), and the normal's
    /// where t is undefined.
    #[test]
    fn t_975_is_students_quantile() {
        for (dof, t) in [(1, 12.706_204_736_174_7), (10, 2.228_138_851_986_27)] {
            assert!((t_975(dof) - t).abs() < 1e-9, "ν = {dof}: {}", t_975(dof));
        }
        assert_eq!(t_975(0), 1.959_963_984_540_054);
        // scipy's t.ppf(0.975, ν) on both sides of the switch to the expansion, and where
        // statrs's inverse drifts (ν ≥ 3·10⁴).
        for (dof, t) in [
            (1_000, 1.962_339_080_826_408_3),
            (7_497, 1.960_280_464_166_506_6),
            (30_000, 1.960_043_063_383_934_7),
            (100_000, 1.959_987_707_534_609_5),
            (1_000_000, 1.959_966_356_814_107),
            (10_000_000, 1.959_964_221_767_205),
            (50_000_000, 1.959_964_031_985_479_9),
        ] {
            assert!(
                (t_975(dof) - t).abs() < 1e-12 * t,
                "ν = {dof}: {}",
                t_975(dof)
            );
        }
        let i = Interval::new(10.0, 0.5, 2.0);
        assert_eq!(
            (i.ci95, i.contains(11.0), i.contains(11.1)),
            ([9.0, 11.0], true, false)
        );
    }
}
