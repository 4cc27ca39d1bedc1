//! The linearised statistics of a least-squares fit, in one place for every engine of
//! the toolkit: the Gauss–Newton covariance σ̂²(JᵀJ)⁻¹ from the column-scaled normal
//! matrix, its condition number and the one wording of "not identifiable", correlation,
//! the delta method, Student's t quantile and the [`Interval`] every result reports.
//!
//! Each engine keeps its model (residuals and Jacobian) and its σ̂²; this module turns
//! the Jacobian at the estimate into a covariance or says which parameter the data do not
//! determine.
//!
//! ```
//! use msd_opt::statistics::{Linearization, t_975, Interval};
//! use nalgebra::DMatrix;
//! // A straight line y = a + b·x through five points: Cov = σ²(XᵀX)⁻¹.
//! let x = [0.0, 1.0, 2.0, 3.0, 4.0];
//! let j = DMatrix::from_fn(5, 2, |r, c| if c == 0 { 1.0 } else { x[r] });
//! let cov = Linearization::new(&j).expect("identifiable").covariance(1.0);
//! let slope = Interval::from_variance(2.0, cov[(1, 1)], t_975(3));
//! assert!((slope.standard_error - 0.1f64.sqrt()).abs() < 1e-14);
//! ```

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, StudentsT};

/// A value with its standard error and 95 % confidence interval.
///
/// Displays as `value ± standard error (95 % CI low … high)`, the numbers with six
/// decimals unless the format gives a precision.
///
/// ```
/// use msd_opt::statistics::Interval;
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
    pub fn new(value: f64, standard_error: f64, t: f64) -> Self {
        Self {
            value,
            standard_error,
            ci95: [value - t * standard_error, value + t * standard_error],
        }
    }

    /// For a positive quantity (a damping ratio): the interval computed on its logarithm,
    /// `value`·exp(±`t`·`standard_error`/`value`), which cannot reach zero (the delta
    /// method: the standard error of ln x is se/x). For small se/x it is `new`'s.
    pub fn positive(value: f64, standard_error: f64, t: f64) -> Self {
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

/// The 97.5 % quantile of Student's t with `dof` degrees of freedom: the half-width of
/// a 95 % interval in standard errors. Where t is undefined (`dof` = 0, which no caller
/// passes: each has more samples than estimated quantities) the normal's 1.96.
///
/// Above ν = 1000 the Cornish–Fisher expansion in 1/ν (Abramowitz & Stegun 26.7.5,
/// four terms), within 1e-15 (three ulp) of scipy's `t.ppf` there; below it statrs's
/// inverse of the incomplete beta function, within 5e-13. Above 10⁴ that inverse drifts (6.5e-7 off at
/// ν = 3·10⁴, 6.8e-6 at 10⁵) and its cost grows with ν (seconds per quantile at 10⁷).
pub fn t_975(dof: usize) -> f64 {
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

/// A scaled condition number at or above this is singular in double precision.
pub const SINGULAR_CONDITION: f64 = 1e14;

/// (JᵀJ)⁻¹ of a Jacobian with the columns scaled to unit norm before inverting (which
/// keeps parameters of very different sizes from ruining the inverse), and the scaled
/// matrix's condition number.
#[derive(Debug, Clone)]
pub struct Linearization {
    /// The inverse of the column-scaled JᵀJ.
    scaled_inverse: DMatrix<f64>,
    /// The columns' norms, √(JᵀJ)ⱼⱼ.
    norms: Vec<f64>,
    /// The ratio of the scaled JᵀJ's largest eigenvalue to its smallest.
    pub condition_number: f64,
}

/// Why a Jacobian gives no covariance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Singular {
    /// The data do not depend on this column at all (zero or non-finite norm).
    Insensitive(usize),
    /// The columns are linearly dependent: this condition number.
    Dependent(f64),
}

impl Singular {
    /// The reason in words: `data` is what was fitted ("the output", "the records", …),
    /// `names` the columns' names.
    pub fn reason(self, data: &str, names: &[&str]) -> String {
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
}

impl Linearization {
    /// The linearisation of `jacobian` (rows × parameters).
    pub fn new(jacobian: &DMatrix<f64>) -> Result<Self, Singular> {
        Self::from_normal_matrix(&(jacobian.transpose() * jacobian))
    }

    /// The same from JᵀJ already formed.
    pub fn from_normal_matrix(jtj: &DMatrix<f64>) -> Result<Self, Singular> {
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
    pub fn covariance(&self, sigma2: f64) -> DMatrix<f64> {
        let n = &self.norms;
        DMatrix::from_fn(n.len(), n.len(), |r, c| {
            sigma2 * self.scaled_inverse[(r, c)] / (n[r] * n[c])
        })
    }
}

/// The correlation matrix of a covariance (0 where a variance is 0).
pub fn correlation(covariance: &DMatrix<f64>) -> DMatrix<f64> {
    let se: Vec<f64> = (0..covariance.nrows())
        .map(|j| covariance[(j, j)].max(0.0).sqrt())
        .collect();
    DMatrix::from_fn(covariance.nrows(), covariance.ncols(), |r, c| {
        covariance[(r, c)] / (se[r] * se[c])
    })
}

/// The variance gᵀ·Σ·g of a quantity with gradient `g` (the delta method).
pub fn delta_variance(gradient: &[f64], covariance: impl Fn(usize, usize) -> f64) -> f64 {
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
    pub fn from_variance(value: f64, variance: f64, t: f64) -> Self {
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
