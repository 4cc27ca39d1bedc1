//! The linearised statistics of a least-squares fit, in one place for every engine: the
//! Gauss–Newton covariance σ̂²(JᵀJ)⁻¹ from the column-scaled normal matrix, its
//! condition number, and the one wording of "not identifiable".
//!
//! Each engine keeps its model (residuals and Jacobian) and its σ̂²; this module turns
//! the Jacobian at the estimate into a covariance or says which parameter the data do not
//! determine.

use crate::{IdentError, Interval};
use nalgebra::DMatrix;

/// A scaled condition number at or above this is singular in double precision.
pub(crate) const SINGULAR_CONDITION: f64 = 1e14;

/// (JᵀJ)⁻¹ of a Jacobian with the columns scaled to unit norm before inverting (which
/// keeps parameters of very different sizes from ruining the inverse), and the scaled
/// matrix's condition number.
#[derive(Debug, Clone)]
pub(crate) struct Linearization {
    /// The inverse of the column-scaled JᵀJ.
    scaled_inverse: DMatrix<f64>,
    /// The columns' norms, √(JᵀJ)ⱼⱼ.
    norms: Vec<f64>,
    /// The ratio of the scaled JᵀJ's largest eigenvalue to its smallest.
    pub condition_number: f64,
}

/// Why a Jacobian gives no covariance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Singular {
    /// The data do not depend on this column at all (zero or non-finite norm).
    Insensitive(usize),
    /// The columns are linearly dependent: this condition number.
    Dependent(f64),
}

impl Singular {
    /// The reason in words: `data` is what was fitted ("the output", "the records", …),
    /// `names` the columns' names.
    pub(crate) fn reason(self, data: &str, names: &[&str]) -> String {
        match self {
            Singular::Insensitive(j) => format!(
                "{data} do not depend on {} (its sensitivity is zero): the input does not excite it",
                names.get(j).copied().unwrap_or("a parameter")
            ),
            Singular::Dependent(condition) => format!(
                "the sensitivities of {} are linearly dependent (condition number {condition:.1e}): {data} cannot tell them apart",
                if names.is_empty() {
                    "the parameters".to_string()
                } else {
                    format!("{names:?}")
                }
            ),
        }
    }

    /// The error of a fit that cannot identify what it was asked.
    pub(crate) fn error(self, data: &str, names: &[&str]) -> IdentError {
        IdentError::NotIdentifiable {
            reason: self.reason(data, names),
        }
    }
}

impl Linearization {
    /// The linearisation of `jacobian` (rows × parameters).
    pub(crate) fn new(jacobian: &DMatrix<f64>) -> Result<Self, Singular> {
        Self::from_normal_matrix(&(jacobian.transpose() * jacobian))
    }

    /// The same from JᵀJ already formed.
    pub(crate) fn from_normal_matrix(jtj: &DMatrix<f64>) -> Result<Self, Singular> {
        let p = jtj.nrows();
        debug_assert_eq!(p, jtj.ncols());
        let norms: Vec<f64> = (0..p).map(|j| jtj[(j, j)].sqrt()).collect();
        if let Some(j) = norms.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(Singular::Insensitive(j));
        }
        let scaled = DMatrix::from_fn(p, p, |r, c| jtj[(r, c)] / (norms[r] * norms[c]));
        // Eigenvalues only (no eigenvectors): the same iteration, a third of the work.
        let (lo, hi) = scaled
            .symmetric_eigenvalues()
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        let condition_number = if lo > 0.0 { hi / lo } else { f64::INFINITY };
        if condition_number.is_nan() || condition_number >= SINGULAR_CONDITION {
            return Err(Singular::Dependent(condition_number));
        }
        let scaled_inverse = scaled
            .try_inverse()
            .ok_or(Singular::Dependent(condition_number))?;
        Ok(Self {
            scaled_inverse,
            norms,
            condition_number,
        })
    }

    /// σ²(JᵀJ)⁻¹: the covariance of the parameters when the residuals have variance σ²
    /// (1 when the Jacobian is already weighted by 1/σ).
    pub(crate) fn covariance(&self, sigma2: f64) -> DMatrix<f64> {
        let n = &self.norms;
        DMatrix::from_fn(n.len(), n.len(), |r, c| {
            sigma2 * self.scaled_inverse[(r, c)] / (n[r] * n[c])
        })
    }
}

/// The correlation matrix of a covariance (0 where a variance is 0).
pub(crate) fn correlation(covariance: &DMatrix<f64>) -> DMatrix<f64> {
    let se: Vec<f64> = (0..covariance.nrows())
        .map(|j| covariance[(j, j)].max(0.0).sqrt())
        .collect();
    DMatrix::from_fn(covariance.nrows(), covariance.ncols(), |r, c| {
        covariance[(r, c)] / (se[r] * se[c])
    })
}

/// The variance gᵀ·Σ·g of a quantity with gradient `g` (the delta method).
pub(crate) fn delta_variance(gradient: &[f64], covariance: impl Fn(usize, usize) -> f64) -> f64 {
    let mut var = 0.0;
    for (i, gi) in gradient.iter().enumerate() {
        for (j, gj) in gradient.iter().enumerate() {
            var += gi * covariance(i, j) * gj;
        }
    }
    var
}

impl Interval {
    /// `value` with the standard error √max(`variance`, 0) and its interval at `t`.
    pub(crate) fn from_variance(value: f64, variance: f64, t: f64) -> Self {
        Self::new(value, variance.max(0.0).sqrt(), t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight line through known points: the covariance is σ²(XᵀX)⁻¹ in closed form.
    #[test]
    fn the_covariance_of_a_line_fit_is_the_closed_form() {
        let x = [0.0, 1.0, 2.0, 3.0, 4.0];
        let j = DMatrix::from_fn(5, 2, |r, c| if c == 0 { 1.0 } else { x[r] });
        let lin = Linearization::new(&j).expect("a line is identifiable");
        // XᵀX = [[5, 10], [10, 30]], det 50: inverse [[0.6, −0.2], [−0.2, 0.1]].
        let cov = lin.covariance(2.0);
        for (got, want) in cov.iter().zip([1.2, -0.4, -0.4, 0.2]) {
            assert!((got - want).abs() < 1e-14, "{got} vs {want}");
        }
        let rho = correlation(&cov)[(0, 1)];
        assert!((rho + 0.4 / (1.2f64 * 0.2).sqrt()).abs() < 1e-14);
    }

    #[test]
    fn a_zero_column_and_two_equal_columns_are_named() {
        let zero = DMatrix::from_fn(4, 2, |r, c| if c == 0 { r as f64 } else { 0.0 });
        let err = Linearization::new(&zero).expect_err("no sensitivity");
        assert_eq!(err, Singular::Insensitive(1));
        assert!(
            err.reason("the output", &["m", "k"])
                .contains("do not depend on k")
        );
        let equal = DMatrix::from_fn(4, 2, |r, _| r as f64 + 1.0);
        let err = Linearization::new(&equal).expect_err("dependent");
        assert!(matches!(err, Singular::Dependent(c) if c >= SINGULAR_CONDITION));
        assert!(
            err.reason("the records", &["m", "k"])
                .contains("linearly dependent")
        );
    }

    #[test]
    fn the_delta_method_of_a_sum_adds_the_covariances() {
        let cov = [[1.0, 0.5], [0.5, 2.0]];
        let var = delta_variance(&[1.0, 1.0], |i, j| cov[i][j]);
        assert_eq!(var, 4.0);
    }
}
