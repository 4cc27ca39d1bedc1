//! The Cramér–Rao bound of θ under the fitted errors-in-variables model: the intervals an
//! estimator that weighted each line by its noise would reach, against which the
//! output-error estimate's sandwich intervals are measured.
//!
//! With the noise spectrum S_k = D + σ²_u·G_k·G_kᴴ taken as known, the residual lines
//! R_k are independent complex Gaussians whose mean moves with θ by Ĵ_k, so the Fisher
//! information is F = Σ_k 2·Re(Ĵ_kᴴ·S_k⁻¹·Ĵ_k) over the one-sided lines (Whittle; the
//! bound the frequency-domain maximum-likelihood estimator of Pintelon and Schoukens
//! attains). The information S_k itself carries about θ (through G_k in σ²_u·|G_k|²) is
//! left out: it is smaller than the mean's by the drive's signal-to-noise ratio per line.
//! Under white noise (σ_u = 0) F is the white-noise fit's own normal matrix (Parseval):
//! the output-error estimate is efficient there.

use super::restricted::{Hats, Sensitivity, all_line_sensitivities, expected};
use super::scoring::maximise;
use super::spectral::{Lines, SpectralModel, likelihood_lines};
use nalgebra::DMatrix;
use rustfft::num_complex::Complex64;

/// The spectral model by the restricted likelihood of the records `lines` of a fit with
/// sensitivities `fits` and normal-matrix inverse `a_inverse` (`groups` sensor groups),
/// with the Fisher information of θ under it.
pub(crate) fn restricted_fit(
    lines: &[Lines],
    fits: &[Sensitivity],
    a_inverse: &DMatrix<f64>,
    groups: usize,
) -> (SpectralModel, DMatrix<f64>) {
    // Each line's Ĵ_k, taken once for the restricted spectrum and the information.
    let hats = all_line_sensitivities(lines, fits, a_inverse.nrows());
    let restricted = expected(lines, fits, &hats, a_inverse, groups);
    let model = maximise(lines, groups, Some(&restricted));
    let f = information(lines, &hats, &model, a_inverse.nrows());
    (model, f)
}

/// F = Σ_k 2·Re(Ĵ_kᴴ·S_k⁻¹·Ĵ_k) over every record's likelihood lines (p parameters).
fn information(lines: &[Lines], hats: &[Hats], model: &SpectralModel, p: usize) -> DMatrix<f64> {
    let mut f = DMatrix::<f64>::zeros(p, p);
    let d = &model.sensor_variance;
    for (l, hat) in lines.iter().zip(hats) {
        let c = l.groups.len();
        for k in likelihood_lines(l.size) {
            // θ's columns come first in each row of the line's block (width w).
            let (j, w) = (hat.line(k, c), hat.width);
            // S⁻¹ = D⁻¹ − σ²_u·D⁻¹·g·gᴴ·D⁻¹ / (1 + σ²_u·gᴴ·D⁻¹·g) (Woodbury).
            let dg: Vec<Complex64> = (0..c).map(|a| l.transfer[a][k] / d[l.groups[a]]).collect();
            let a: f64 = (0..c).map(|e| (l.transfer[e][k].conj() * dg[e]).re).sum();
            let shrink = model.input_variance / (1.0 + model.input_variance * a);
            // u = gᴴ·D⁻¹·Ĵ (1×p), then Ĵᴴ·S⁻¹·Ĵ = Ĵᴴ·D⁻¹·Ĵ − shrink·uᴴ·u.
            let u: Vec<Complex64> = (0..p)
                .map(|r| (0..c).map(|e| dg[e].conj() * j[e * w + r]).sum())
                .collect();
            for r in 0..p {
                for t in r..p {
                    let plain: f64 = (0..c)
                        .map(|e| (j[e * w + r].conj() * j[e * w + t]).re / d[l.groups[e]])
                        .sum();
                    let x = 2.0 * (plain - shrink * (u[r].conj() * u[t]).re);
                    f[(r, t)] += x;
                    if r != t {
                        f[(t, r)] += x;
                    }
                }
            }
        }
    }
    f
}

/// The efficiency along `direction`: eᵀ·B·e over eᵀ·C·e, the bound's variance over the
/// reported one (`None` where either is not positive: a known parameter).
pub(crate) fn efficiency(
    bound: &DMatrix<f64>,
    reported: &DMatrix<f64>,
    direction: &nalgebra::DVector<f64>,
) -> Option<f64> {
    let of = |m: &DMatrix<f64>| (direction.transpose() * m * direction)[(0, 0)];
    let (b, r) = (of(bound), of(reported));
    (r > 0.0 && b > 0.0).then_some(b / r)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input_noise::spectral::{impulse_spectrum, residual_spectrum};

    /// Under white noise (σ²_u = 0) the information is JᵀJ/σ² by Parseval, less the
    /// two lines the likelihood leaves out (the mean and Nyquist's).
    #[test]
    fn white_noise_information_is_the_normal_matrix() {
        let (n, p, sigma2) = (64usize, 2usize, 0.7);
        let columns: Vec<Vec<f64>> = (0..p)
            .map(|c| {
                (0..n)
                    .map(|t| ((t * (c + 3)) as f64 * 0.41).sin() + 0.2)
                    .collect()
            })
            .collect();
        let lines = Lines {
            size: n,
            groups: vec![0],
            residual: vec![residual_spectrum(std::iter::repeat_n(0.0, n), n)],
            transfer: vec![impulse_spectrum([1.0, 0.5].into_iter(), n)],
        };
        let fit = Sensitivity {
            columns: vec![columns.clone()],
            nuisance: Vec::new(),
            weights: vec![1.0],
        };
        let model = SpectralModel {
            sensor_variance: vec![sigma2],
            input_variance: 0.0,
            covariance: None,
            likelihood_ratio: 0.0,
            p_value: 1.0,
        };
        let hats = all_line_sensitivities(std::slice::from_ref(&lines), &[fit], p);
        let f = information(&[lines], &hats, &model, p);
        let sum = |x: &[f64], y: &[f64], sign: bool| {
            (0..n)
                .map(|t| if sign && t % 2 == 1 { -1.0 } else { 1.0 } * x[t] * y[t])
                .sum::<f64>()
        };
        for r in 0..p {
            for t in 0..p {
                let (a, b) = (&columns[r], &columns[t]);
                let mean = a.iter().sum::<f64>() * b.iter().sum::<f64>() / n as f64;
                let alternating = sum(a, &vec![1.0; n], true) * sum(b, &vec![1.0; n], true);
                let expected = (sum(a, b, false) - mean - alternating / n as f64) / sigma2;
                assert!(
                    (f[(r, t)] - expected).abs() < 1e-9 * expected.abs(),
                    "{r}, {t}: {} against {expected}",
                    f[(r, t)]
                );
            }
        }
    }
}
