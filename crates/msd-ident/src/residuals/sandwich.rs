//! The covariance of a least-squares estimate whose residuals are coloured: the sandwich
//! over contiguous blocks of samples (batch means). Each block's score Jᵦᵀ·rᵦ is an
//! independent draw when the residual decorrelates within a block, so
//! Cov θ̂ = B⁻¹·(Σᵦ sᵦ·sᵦᵀ)·B⁻¹·b/(b − 1), with the bread B = JᵀJ (its inverse given) and
//! b blocks; intervals take Student's t on b − 1 degrees of freedom. It holds whatever
//! the residual's spectrum, where s²·(JᵀJ)⁻¹ holds only for white residuals.

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

/// Blocks of the sandwich by default: twenty, so that the t quantile on 19 degrees of
/// freedom (2.09) costs little and each block of a record of a few thousand samples
/// still spans many correlation times of a coloured residual.
pub const BLOCKS: usize = 20;

/// bread·meat·bread·b/(b − 1), the meat Σᵦ (Jᵦᵀrᵦ)(Jᵦᵀrᵦ)ᵀ over `blocks` contiguous
/// blocks of the rows of `jacobian` (n × p) and `residuals` (n), `bread` = (JᵀJ)⁻¹.
pub(crate) fn block_sandwich(
    jacobian: &DMatrix<f64>,
    residuals: &DVector<f64>,
    bread: &DMatrix<f64>,
    blocks: usize,
) -> DMatrix<f64> {
    let (n, p) = jacobian.shape();
    let mut meat = DMatrix::<f64>::zeros(p, p);
    for b in 0..blocks {
        let (lo, hi) = (b * n / blocks, (b + 1) * n / blocks);
        let score = jacobian.rows(lo, hi - lo).transpose() * residuals.rows(lo, hi - lo);
        meat += &score * score.transpose();
    }
    bread * meat * bread * (blocks as f64 / (blocks - 1) as f64)
}

/// How a fit's covariance treats its residuals.
///
/// ```
/// use msd_ident::residuals::sandwich::ResidualCovariance;
/// let c: ResidualCovariance = serde_json::from_str("\"auto\"").unwrap();
/// assert_eq!(c, ResidualCovariance::Auto);
/// assert_eq!(ResidualCovariance::default(), ResidualCovariance::Auto);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ResidualCovariance {
    /// The block sandwich where the residuals fail the Ljung–Box test at 1 %, else
    /// s²·(JᵀJ)⁻¹. The default.
    #[default]
    Auto,
    /// s²·(JᵀJ)⁻¹: white residuals assumed.
    White,
    /// The block sandwich always.
    Sandwich,
}

/// Which covariance a fit reported, and why.
///
/// ```
/// use msd_ident::residuals::sandwich::CovarianceUsed;
/// let used = CovarianceUsed { sandwich: true, blocks: 20, whiteness_p: 1e-9 };
/// assert!(used.to_string().contains("block sandwich over 20 blocks"));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CovarianceUsed {
    /// Whether the block sandwich was used (else s²·(JᵀJ)⁻¹).
    pub sandwich: bool,
    /// Its blocks (Student's t on blocks − 1 degrees of freedom).
    pub blocks: usize,
    /// The Ljung–Box p of the fit's residuals.
    pub whiteness_p: f64,
}

impl std::fmt::Display for CovarianceUsed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.sandwich {
            write!(
                f,
                "intervals from the block sandwich over {} blocks (the residuals are coloured: Ljung–Box p = {:.2e}; s²·(JᵀJ)⁻¹ assumes white residuals and would be too narrow), Student's t on {} degrees of freedom",
                self.blocks,
                self.whiteness_p,
                self.blocks - 1
            )
        } else {
            write!(
                f,
                "intervals from s²·(JᵀJ)⁻¹ (the residuals look white: Ljung–Box p = {:.3})",
                self.whiteness_p
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With white residuals the sandwich estimates s²·(JᵀJ)⁻¹: for a constant regressor
    /// (the mean), both are Var(r)/n, the sandwich as the blocks' scatter.
    #[test]
    fn the_sandwich_of_a_mean_is_the_batch_means_variance() {
        let n = 2000;
        let r: Vec<f64> = (0..n)
            .map(|i| ((i as f64 * 0.7).sin() + (i as f64 * 1.3).cos()) * 0.5)
            .collect();
        let j = DMatrix::from_element(n, 1, 1.0);
        let bread = DMatrix::from_element(1, 1, 1.0 / n as f64);
        let cov = block_sandwich(&j, &DVector::from_vec(r.clone()), &bread, 20);
        // Batch means: the blocks' sums s_b; Σ s_b² /n² · 20/19.
        let sums: Vec<f64> = r.chunks(100).map(|c| c.iter().sum()).collect();
        let expected = sums.iter().map(|s| s * s).sum::<f64>() / (n * n) as f64 * 20.0 / 19.0;
        assert!((cov[(0, 0)] / expected - 1.0).abs() < 1e-12);
    }
}
