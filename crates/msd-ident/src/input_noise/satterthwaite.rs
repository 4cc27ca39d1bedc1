//! How many degrees of freedom the drive's noise model leaves the intervals: the
//! standard errors are computed from estimated variances (σ̂²_u, σ̂²_a), whose own
//! uncertainty (the Whittle likelihood's Fisher information) makes the t quantile
//! larger. Satterthwaite's approximation: ν = 2·SE⁴ / Var(SE²), SE² being linear in
//! the variances.

use nalgebra::{DMatrix, DVector};

/// The smallest ν over the reported `directions` of θ: `reported` = Cov(θ), `parts`
/// its derivative in each variance (drive first), `covariance` that of the variances.
pub(crate) fn satterthwaite(
    reported: &DMatrix<f64>,
    parts: &[DMatrix<f64>],
    covariance: &DMatrix<f64>,
    directions: &[DVector<f64>],
) -> f64 {
    let quadratic = |m: &DMatrix<f64>, e: &DVector<f64>| (e.transpose() * m * e)[(0, 0)];
    directions
        .iter()
        .filter_map(|e| {
            let se2 = quadratic(reported, e);
            let c = DVector::from_iterator(parts.len(), parts.iter().map(|p| quadratic(p, e)));
            let variance = (c.transpose() * covariance * &c)[(0, 0)];
            (se2 > 0.0 && variance > 0.0).then(|| 2.0 * se2 * se2 / variance)
        })
        .fold(f64::INFINITY, f64::min)
}
