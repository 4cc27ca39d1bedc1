//! A damping law's coefficients as a planned test will give them.

use super::LawFit;
use crate::law::DampingLaw;
use msd_opt::statistics::Interval;
use nalgebra::DMatrix;
use serde::Serialize;

/// One damping law's coefficients as a planned test machine will estimate them
/// ([`predicted_dynamometer`](super::predicted_dynamometer)): the values the prior
/// plant gives, the standard errors and 95 % intervals the run will report.
///
/// ```
/// use msd_ident::{dynamometer::{DynamometerNoise, DynamometerOptions, predicted_dynamometer, synthetic_dynamometer, SyntheticDynamometer}, nonlinear::DampingLaw};
/// let spec = SyntheticDynamometer { force_noise: 0.0, displacement_noise: 0.0, ..Default::default() };
/// let noise = DynamometerNoise { force_sigma: 1.0, stroke_sigma: 0.0 };
/// let options = DynamometerOptions { laws: vec![DampingLaw::Viscous], ..Default::default() };
/// let law = &predicted_dynamometer(&synthetic_dynamometer(&spec)?, &noise, &options)?[0];
/// assert_eq!(law.names, ["mass", "damping", "stiffness", "force_offset"]);
/// assert!(law.coefficient("damping").unwrap().standard_error > 0.0);
/// println!("{law}");
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PredictedLaw {
    /// The damping law f_d.
    pub law: DampingLaw,
    /// The coefficients' names, in the order of [`LawFit::names`].
    pub names: Vec<&'static str>,
    /// The coefficients: prior values, predicted standard errors and 95 % intervals
    /// (Student's t, as the run computes them).
    pub coefficients: Vec<Interval>,
    /// The predicted covariance, rows in the order of `names`.
    #[serde(serialize_with = "crate::ser::matrix_rows")]
    pub covariance: DMatrix<f64>,
    /// The load cell's σ_F the prediction assumes, N.
    pub force_sigma: f64,
}

impl PredictedLaw {
    /// The coefficient `name`, if the law has it.
    pub fn coefficient(&self, name: &str) -> Option<&Interval> {
        super::law_fit::named(&self.names, &self.coefficients, name)
    }

    /// The coefficients' correlation matrix, rows in the order of `names`.
    pub fn correlation(&self) -> DMatrix<f64> {
        let c = &self.covariance;
        DMatrix::from_fn(c.nrows(), c.ncols(), |r, k| {
            c[(r, k)] / (c[(r, r)] * c[(k, k)]).sqrt()
        })
    }
}

impl From<LawFit> for PredictedLaw {
    fn from(fit: LawFit) -> Self {
        Self {
            law: fit.law,
            names: fit.names,
            coefficients: fit.coefficients,
            covariance: fit.covariance,
            force_sigma: fit.force_sigma,
        }
    }
}

impl std::fmt::Display for PredictedLaw {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:?} law, σ_F = {:.3e} N:", self.law, self.force_sigma)?;
        for (n, c) in self.names.iter().zip(&self.coefficients) {
            write!(f, " {n} {:.5e} ± {:.2e};", c.value, c.standard_error)?;
        }
        Ok(())
    }
}
