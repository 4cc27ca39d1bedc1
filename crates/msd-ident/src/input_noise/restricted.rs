//! The residuals' expected cross-spectrum once the fit has absorbed its share of the
//! noise: the likelihood of σ²_a and σ²_u written for the residuals r = (I − P)·v that
//! the fit leaves, not for the noise v itself.
//!
//! The fit moves θ by δθ = A⁻¹·Jᵀ·W²·v (A = JᵀW²J), so at line k, with Ĵ_k the c×p
//! DFT of each channel's sensitivity (unitary scaling), H_k = Ĵ_k·A⁻¹·Ĵ_kᴴ and C the
//! sandwich covariance of δθ:
//! E[R_k·R_kᴴ] = S_k − H_k·W²·S_k − S_k·W²·H_k + Ĵ_k·C·Ĵ_kᴴ,
//! linear in the variances as S_k and C are. The lines where the sensitivities are large
//! (the resonance) lose most; there the drive's noise is largest. Without this, σ̂_u
//! comes out low where those lines carry it (0.23–0.25 % for 0.30 % on a load cell):
//! the restricted-likelihood (REML) correction for the absorbed degrees of freedom.

use super::spectral::{Lines, likelihood_lines, spectrum};
use nalgebra::DMatrix;
use rustfft::num_complex::Complex64;

/// One record's expected residual cross-spectrum per unit variance: for each likelihood
/// line, for the drive (q = 0) then each sensor group, a c×c matrix (row-major); `None`
/// at a line where the fit absorbed less than [`NEGLIGIBLE`] of each part (most lines:
/// the sensitivities gather at the resonances), which keeps the noise's own spectrum.
pub(crate) struct Expected {
    pub lines: Vec<Option<Vec<Vec<Complex64>>>>,
}

/// The relative correction below which a line keeps the noise's spectrum: it moves the
/// variances by less than 1e-4 of themselves, far inside their standard errors.
pub(crate) const NEGLIGIBLE: f64 = 1e-4;

/// One record's sensitivities for [`expected`]: per channel, per estimated quantity, the
/// residual's derivative in the likelihood's units (the record's samples), and each
/// channel's weight in the fit.
pub(crate) struct Sensitivity {
    pub columns: Vec<Vec<Vec<f64>>>,
    pub weights: Vec<f64>,
}

/// The expected residual cross-spectra of each record (`lines[r]`, `fits[r]`) of a fit
/// whose normal matrix has inverse `a_inverse`, with `groups` sensor groups.
///
/// C, the covariance of δθ, is taken in the same frequency-domain model as S (the
/// Whittle lines: Σ over every line of Ĵᴴ·W²·S·W²·Ĵ), so that each line's expected
/// matrix is the exact (I − P)·S·(I − P)ᴴ of that model, positive semi-definite.
pub(crate) fn expected(
    lines: &[Lines],
    fits: &[Sensitivity],
    hats: &[Vec<Complex64>],
    a_inverse: &DMatrix<f64>,
    groups: usize,
) -> Vec<Expected> {
    let p = a_inverse.nrows();
    // B_q per unit variance, summed over every line of every record: Jᴴ·W²·S_q·W²·J.
    let mut middle = vec![DMatrix::<f64>::zeros(p, p); groups + 1];
    for ((l, fit), hat) in lines.iter().zip(fits).zip(hats) {
        let c = l.groups.len();
        let w2: Vec<f64> = fit.weights.iter().map(|w| w * w).collect();
        for k in 0..l.size {
            let j = &hat[k * c * p..(k + 1) * c * p];
            // The drive: u·uᴴ, u = Jᴴ·W²·g.
            let u: Vec<Complex64> = (0..p)
                .map(|r| {
                    (0..c)
                        .map(|a| j[a * p + r].conj() * w2[a] * l.transfer[a][k])
                        .sum()
                })
                .collect();
            for r in 0..p {
                for t in 0..p {
                    middle[0][(r, t)] += (u[r] * u[t].conj()).re;
                    for a in 0..c {
                        let x = (j[a * p + r].conj() * j[a * p + t]).re * w2[a] * w2[a];
                        middle[1 + l.groups[a]][(r, t)] += x;
                    }
                }
            }
        }
    }
    let parts: Vec<DMatrix<f64>> = middle.iter().map(|b| a_inverse * b * a_inverse).collect();
    lines
        .iter()
        .zip(fits)
        .zip(hats)
        .map(|((l, fit), hat)| {
            let c = l.groups.len();
            let w2: Vec<f64> = fit.weights.iter().map(|w| w * w).collect();
            let out = likelihood_lines(l.size)
                .map(|k| {
                    let j = &hat[k * c * p..(k + 1) * c * p];
                    let h = sandwich(j, a_inverse, c, p);
                    let g: Vec<Complex64> = (0..c).map(|a| l.transfer[a][k]).collect();
                    let mut largest = 0.0f64;
                    let matrices: Vec<Vec<Complex64>> = (0..=groups)
                        .map(|q| {
                            let mut m = sandwich(j, &parts[q], c, p);
                            let unit = |a: usize, b: usize| {
                                if q == 0 {
                                    g[a] * g[b].conj()
                                } else if a == b && l.groups[a] == q - 1 {
                                    Complex64::new(1.0, 0.0)
                                } else {
                                    Complex64::new(0.0, 0.0)
                                }
                            };
                            // (H·W²·S)[a][b], then M = S − H·W²·S − (H·W²·S)ᴴ + J·C_q·Jᴴ.
                            let hws: Vec<Complex64> = (0..c * c)
                                .map(|i| {
                                    let (a, b) = (i / c, i % c);
                                    (0..c).map(|e| h[a * c + e] * w2[e] * unit(e, b)).sum()
                                })
                                .collect();
                            let (mut change, mut size) = (0.0, 0.0);
                            for a in 0..c {
                                for b in 0..c {
                                    let s = unit(a, b);
                                    m[a * c + b] -= hws[a * c + b] + hws[b * c + a].conj();
                                    change += m[a * c + b].norm_sqr();
                                    size += s.norm_sqr();
                                    m[a * c + b] += s;
                                }
                            }
                            if size > 0.0 {
                                largest = largest.max((change / size).sqrt());
                            }
                            m
                        })
                        .collect();
                    (largest >= NEGLIGIBLE).then_some(matrices)
                })
                .collect();
            Expected { lines: out }
        })
        .collect()
}

/// J·M·Jᴴ (c×c, row-major) of the line's Ĵ (c×p, row-major) and a real p×p `m`.
fn sandwich(j: &[Complex64], m: &DMatrix<f64>, c: usize, p: usize) -> Vec<Complex64> {
    let jm: Vec<Complex64> = (0..c * p)
        .map(|i| {
            let (a, t) = (i / p, i % p);
            (0..p).map(|r| j[a * p + r] * m[(r, t)]).sum()
        })
        .collect();
    (0..c * c)
        .map(|i| {
            let (a, b) = (i / c, i % c);
            (0..p).map(|t| jm[a * p + t] * j[b * p + t].conj()).sum()
        })
        .collect()
}

/// Each record's [`line_sensitivities`] (`p` parameters).
pub(super) fn all_line_sensitivities(
    lines: &[Lines],
    fits: &[Sensitivity],
    p: usize,
) -> Vec<Vec<Complex64>> {
    (lines.iter().zip(fits))
        .map(|(l, fit)| line_sensitivities(l, fit, p))
        .collect()
}

/// Ĵ_k (c×p, row-major) at every line k of the record, one after another; unitary
/// scaling.
fn line_sensitivities(l: &Lines, fit: &Sensitivity, p: usize) -> Vec<Complex64> {
    let c = l.groups.len();
    let scale = 1.0 / (l.size as f64).sqrt();
    let hat: Vec<Vec<Vec<Complex64>>> = fit
        .columns
        .iter()
        .map(|cols| {
            cols.iter()
                .map(|x| spectrum(x.iter().copied(), l.size, scale))
                .collect()
        })
        .collect();
    let mut out = Vec::with_capacity(l.size * c * p);
    for k in 0..l.size {
        for channel in &hat {
            out.extend(channel.iter().map(|col| col[k]));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input_noise::spectral::impulse_spectrum;
    use std::f64::consts::TAU;

    /// Where the noise is circulant (exactly diagonal in the DFT basis, the Whittle
    /// model without approximation), each line's expected matrix is the DFT diagonal of
    /// (I − P)·Σ_q·(I − P)ᵀ computed in the time domain, to rounding.
    #[test]
    fn the_expected_spectrum_is_that_of_the_projected_noise() {
        let (n, p, w) = (32usize, 2usize, 1.3);
        let g: Vec<f64> = (0..n)
            .map(|t| (-0.2 * t as f64).exp() * (0.9 * t as f64).sin())
            .collect();
        let lines = Lines {
            size: n,
            groups: vec![0],
            residual: vec![vec![Complex64::new(0.0, 0.0); n]],
            transfer: vec![impulse_spectrum(g.iter().copied(), n)],
        };
        let j = DMatrix::from_fn(n, p, |t, c| {
            ((t * (c + 2)) as f64 * 0.37).cos() + 0.1 * c as f64
        });
        let a = j.transpose() * &j * (w * w);
        let a_inverse = a.clone().try_inverse().expect("invertible");
        let fit = Sensitivity {
            columns: vec![
                (0..p)
                    .map(|c| j.column(c).iter().copied().collect())
                    .collect(),
            ],
            weights: vec![w],
        };
        let hats =
            all_line_sensitivities(std::slice::from_ref(&lines), std::slice::from_ref(&fit), p);
        let got = expected(
            std::slice::from_ref(&lines),
            std::slice::from_ref(&fit),
            &hats,
            &a_inverse,
            1,
        );
        // Σ_u[t, s] = (1/N)·Σ_k |G_k|²·e^{iω_k(t − s)}, Σ_a = I.
        let power: Vec<f64> = lines.transfer[0].iter().map(|v| v.norm_sqr()).collect();
        let circulant = DMatrix::from_fn(n, n, |t, s| {
            (0..n)
                .map(|k| power[k] * (TAU * k as f64 * (t as f64 - s as f64) / n as f64).cos())
                .sum::<f64>()
                / n as f64
        });
        let projector = DMatrix::<f64>::identity(n, n) - &j * &a_inverse * j.transpose() * (w * w);
        for (q, sigma) in [circulant, DMatrix::identity(n, n)].iter().enumerate() {
            let e = &projector * sigma * projector.transpose();
            for (i, k) in likelihood_lines(n).enumerate() {
                let diagonal: f64 = (0..n)
                    .flat_map(|t| (0..n).map(move |s| (t, s)))
                    .map(|(t, s)| {
                        e[(t, s)] * (TAU * k as f64 * (t as f64 - s as f64) / n as f64).cos()
                    })
                    .sum::<f64>()
                    / n as f64;
                let m = got[0].lines[i]
                    .as_ref()
                    .map_or_else(|| if q == 0 { power[k] } else { 1.0 }.into(), |m| m[q][0]);
                assert!(
                    (m.re - diagonal).abs() < 1e-9 * diagonal.abs().max(1.0) && m.im.abs() < 1e-9,
                    "q {q}, line {k}: {m} against {diagonal}"
                );
            }
        }
    }
}
