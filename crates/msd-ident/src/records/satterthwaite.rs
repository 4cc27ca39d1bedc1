//! How many degrees of freedom the drive's noise model leaves the intervals: the
//! standard errors are computed from estimated variances (σ̂²_u, σ̂²_a), whose own
//! uncertainty (the Whittle likelihood's Fisher information) makes the t quantile
//! larger. Satterthwaite's approximation: ν = 2·SE⁴ / Var(SE²), SE² being linear in
//! the variances.

use super::noise_model::{Lines, likelihood_lines};
use super::problem::Joint;
use nalgebra::{DMatrix, Matrix3, Vector3};
use rustfft::num_complex::Complex64;

/// The Fisher information of (σ²_u, σ²_a…) in the Whittle likelihood:
/// F_ij = Σ tr(S⁻¹·∂ᵢS·S⁻¹·∂ⱼS) over the records' lines, S = D + σ²_u·G·Gᴴ.
pub(super) fn fisher(problem: &Joint<'_>, lines: &[Lines], d: &[f64], s_u: f64) -> DMatrix<f64> {
    let q = 1 + d.len();
    let mut f = DMatrix::<f64>::zeros(q, q);
    for (rec, l) in problem.records.iter().zip(lines) {
        let c = rec.groups.len();
        for k in likelihood_lines(l.size) {
            let g = nalgebra::DVector::from_fn(c, |ch, _| l.transfer[ch][k]);
            let mut s = &g * g.adjoint() * Complex64::new(s_u, 0.0);
            for (ch, &group) in rec.groups.iter().enumerate() {
                s[(ch, ch)] += d[group];
            }
            let Some(inverse) = s.try_inverse() else {
                continue;
            };
            // S⁻¹·∂S for σ²_u, then for each group.
            let mut m = vec![&inverse * &g * g.adjoint()];
            for group in 0..d.len() {
                let mut part = DMatrix::<Complex64>::zeros(c, c);
                for (ch, &of) in rec.groups.iter().enumerate() {
                    if of == group {
                        part.set_column(ch, &inverse.column(ch));
                    }
                }
                m.push(part);
            }
            for i in 0..q {
                for j in i..q {
                    let t = (&m[i] * &m[j]).trace().re;
                    f[(i, j)] += t;
                    if i != j {
                        f[(j, i)] += t;
                    }
                }
            }
        }
    }
    f
}

/// The smallest ν over the reported directions of ln θ (fn, ζ, each parameter, c over
/// k): `reported` = Cov(ln θ), `parts` its derivative in each variance (drive first),
/// `covariance` that of the variances.
pub(super) fn satterthwaite(
    reported: &Matrix3<f64>,
    parts: &[Matrix3<f64>],
    covariance: &DMatrix<f64>,
) -> f64 {
    let directions = [
        Vector3::new(-0.5, 0.0, 0.5),
        Vector3::new(-0.5, 1.0, -0.5),
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(0.0, 1.0, 0.0),
        Vector3::new(0.0, 0.0, 1.0),
        Vector3::new(0.0, 1.0, -1.0),
    ];
    let quadratic = |m: &Matrix3<f64>, e: &Vector3<f64>| (e.transpose() * m * e)[(0, 0)];
    directions
        .iter()
        .filter_map(|e| {
            let se2 = quadratic(reported, e);
            let c = nalgebra::DVector::from_iterator(
                parts.len(),
                parts.iter().map(|p| quadratic(p, e)),
            );
            let variance = (c.transpose() * covariance * &c)[(0, 0)];
            (se2 > 0.0 && variance > 0.0).then(|| 2.0 * se2 * se2 / variance)
        })
        .fold(f64::INFINITY, f64::min)
}
