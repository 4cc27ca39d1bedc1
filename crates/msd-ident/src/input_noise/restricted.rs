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
//!
//! Each record's initial state absorbs noise too, and at the same lines: its free
//! responses ring at the resonance. The fit eliminated it (variable projection) and
//! projected θ's columns against it, so P = P_θ + Σ_r P_r over the records' own
//! columns, and each record's lines carry its own block beside θ's. Three records of
//! 10 s (0.1 Hz lines, three across the resonance) lose six degrees of freedom there
//! against θ's three: without them σ̂_u came out 0.25 % for 0.30 % and the intervals'
//! spread over their standard errors 1.06–1.13 (`cargo xtask noise-study`, 400 seeds);
//! with them 0.28 % and 1.03–1.05.

use super::spectral::{Lines, likelihood_lines, spectra};
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
    /// Per channel, the columns of the record's own linear parameters that `columns` were
    /// projected against (its initial state's free responses, each channel's mean
    /// removed where its offset is estimated); empty where there are none. They absorb
    /// noise at the record's resonance lines too, where the drive's noise is largest.
    pub nuisance: Vec<Vec<Vec<f64>>>,
    pub weights: Vec<f64>,
}

impl Sensitivity {
    /// The number of the record's own linear parameters.
    fn nuisances(&self) -> usize {
        self.nuisance.first().map_or(0, Vec::len)
    }

    /// (XᵀW²X)⁻¹ of the nuisance columns X, `None` when there are none or they are
    /// dependent (then they are not accounted for).
    fn nuisance_inverse(&self) -> Option<DMatrix<f64>> {
        let q = self.nuisances();
        let gram = DMatrix::from_fn(q, q, |i, j| {
            (self.nuisance.iter().zip(&self.weights))
                .map(|(x, w)| w * w * x[i].iter().zip(&x[j]).map(|(a, b)| a * b).sum::<f64>())
                .sum()
        });
        (q > 0).then(|| gram.try_inverse()).flatten()
    }
}

/// Each line's Ĵ_k (c × width, row-major, one line after another; unitary scaling) of
/// one record: the p estimated quantities' columns, then the record's nuisance columns.
pub(crate) struct Hats {
    pub width: usize,
    pub values: Vec<Complex64>,
}

impl Hats {
    /// Line k's c × width block.
    pub(crate) fn line(&self, k: usize, c: usize) -> &[Complex64] {
        &self.values[k * c * self.width..(k + 1) * c * self.width]
    }
}

/// The expected residual cross-spectra of each record (`lines[r]`, `fits[r]`) of a fit
/// whose normal matrix has inverse `a_inverse`, with `groups` sensor groups.
///
/// C, the covariance of δθ, is taken in the same frequency-domain model as S (the
/// Whittle lines: Σ over every line of Ĵᴴ·W²·S·W²·Ĵ), so that each line's expected
/// matrix is the exact (I − P)·S·(I − P)ᴴ of that model, positive semi-definite. P
/// includes each record's own linear parameters: the fit projected θ's columns against
/// them, so the full normal matrix is block diagonal, blockdiag(A_θ, A_1, …), and each
/// record's lines see only the θ block and its own.
pub(crate) fn expected(
    lines: &[Lines],
    fits: &[Sensitivity],
    hats: &[Hats],
    a_inverse: &DMatrix<f64>,
    groups: usize,
) -> Vec<Expected> {
    let p = a_inverse.nrows();
    // B_q per unit variance, Jᴴ·W²·S_q·W²·J, each record's over its own lines; θ's block
    // summed over every record.
    let middles: Vec<Vec<DMatrix<f64>>> = (lines.iter().zip(fits).zip(hats))
        .map(|((l, fit), hat)| record_middle(l, fit, hat, groups))
        .collect();
    let shared: Vec<DMatrix<f64>> = (0..=groups)
        .map(|q| {
            (middles.iter())
                .map(|m| m[q].view((0, 0), (p, p)).into_owned())
                .fold(DMatrix::zeros(p, p), |a, b| a + b)
        })
        .collect();
    (lines.iter().zip(fits).zip(hats).zip(middles))
        .map(|(((l, fit), hat), mut middle)| {
            let w = hat.width;
            // blockdiag(A_θ⁻¹, A_r⁻¹): nuisance columns that are dependent are left out.
            let mut inverse = DMatrix::<f64>::zeros(w, w);
            inverse.view_mut((0, 0), (p, p)).copy_from(a_inverse);
            if let Some(own) = fit.nuisance_inverse() {
                inverse.view_mut((p, p), (w - p, w - p)).copy_from(&own);
            }
            let parts: Vec<DMatrix<f64>> = (middle.iter_mut().zip(&shared))
                .map(|(m, s)| {
                    m.view_mut((0, 0), (p, p)).copy_from(s);
                    &inverse * &*m * &inverse
                })
                .collect();
            record_expected(l, fit, hat, &inverse, &parts)
        })
        .collect()
}

/// One record's Jᴴ·W²·S_q·W²·J per unit variance over every line, for the drive (q = 0)
/// then each of `groups` sensor groups (width × width, the record's nuisance columns
/// after θ's). Each term is real and symmetric, and lines k and N − k conjugate (the
/// columns are real): the lines up to N/2 are summed, each below it twice, and the
/// upper triangle mirrored.
fn record_middle(l: &Lines, fit: &Sensitivity, hat: &Hats, groups: usize) -> Vec<DMatrix<f64>> {
    let (c, p) = (l.groups.len(), hat.width);
    let w2: Vec<f64> = fit.weights.iter().map(|w| w * w).collect();
    let mut sums = vec![vec![0.0; p * p]; groups + 1];
    let mut u = vec![Complex64::new(0.0, 0.0); p];
    for k in 0..=l.size / 2 {
        let twice = k > 0 && 2 * k < l.size;
        let weight = if twice { 2.0 } else { 1.0 };
        let j = hat.line(k, c);
        // The drive: u·uᴴ, u = Jᴴ·W²·g.
        for (r, u) in u.iter_mut().enumerate() {
            *u = (0..c)
                .map(|a| j[a * p + r].conj() * w2[a] * l.transfer[a][k])
                .sum();
        }
        for r in 0..p {
            for t in r..p {
                sums[0][r * p + t] += weight * (u[r] * u[t].conj()).re;
                for a in 0..c {
                    let x = (j[a * p + r].conj() * j[a * p + t]).re * w2[a] * w2[a];
                    sums[1 + l.groups[a]][r * p + t] += weight * x;
                }
            }
        }
    }
    (sums.iter())
        .map(|m| DMatrix::from_fn(p, p, |r, t| m[r.min(t) * p + r.max(t)]))
        .collect()
}

/// One record's expected matrices at its likelihood lines, from its normal-matrix
/// inverse `inverse` and the covariance of its parameters per unit variance `parts`.
fn record_expected(
    l: &Lines,
    fit: &Sensitivity,
    hat: &Hats,
    inverse: &DMatrix<f64>,
    parts: &[DMatrix<f64>],
) -> Expected {
    let (c, p) = (l.groups.len(), hat.width);
    let w2: Vec<f64> = fit.weights.iter().map(|w| w * w).collect();
    let zero = Complex64::new(0.0, 0.0);
    // Buffers reused at every line: most lines are dropped as negligible.
    let (mut jm, mut h) = (vec![zero; c * p], vec![zero; c * c]);
    let mut matrices = vec![vec![zero; c * c]; parts.len()];
    let out = likelihood_lines(l.size)
        .map(|k| {
            let j = hat.line(k, c);
            sandwich(j, inverse, p, &mut jm, &mut h);
            let mut largest = 0.0f64;
            for (q, (part, m)) in parts.iter().zip(&mut matrices).enumerate() {
                sandwich(j, part, p, &mut jm, m);
                let unit = |a: usize, b: usize| {
                    if q == 0 {
                        l.transfer[a][k] * l.transfer[b][k].conj()
                    } else if a == b && l.groups[a] == q - 1 {
                        Complex64::new(1.0, 0.0)
                    } else {
                        zero
                    }
                };
                // (H·W²·S)[a][b], then M = S − H·W²·S − (H·W²·S)ᴴ + J·C_q·Jᴴ.
                let hws = |a: usize, b: usize| -> Complex64 {
                    (0..c).map(|e| h[a * c + e] * w2[e] * unit(e, b)).sum()
                };
                let (mut change, mut size) = (0.0, 0.0);
                for a in 0..c {
                    for b in 0..c {
                        let s = unit(a, b);
                        m[a * c + b] -= hws(a, b) + hws(b, a).conj();
                        change += m[a * c + b].norm_sqr();
                        size += s.norm_sqr();
                        m[a * c + b] += s;
                    }
                }
                if size > 0.0 {
                    largest = largest.max((change / size).sqrt());
                }
            }
            (largest >= NEGLIGIBLE).then(|| matrices.clone())
        })
        .collect();
    Expected { lines: out }
}

/// J·M·Jᴴ (c×c, row-major, into `out`) of the line's Ĵ (c×p, row-major) and a real
/// p×p `m`, with `jm` (c×p) for J·M.
fn sandwich(
    j: &[Complex64],
    m: &DMatrix<f64>,
    p: usize,
    jm: &mut [Complex64],
    out: &mut [Complex64],
) {
    for (i, v) in jm.iter_mut().enumerate() {
        let (a, t) = (i / p, i % p);
        *v = (0..p).map(|r| j[a * p + r] * m[(r, t)]).sum();
    }
    let c = jm.len() / p.max(1);
    for (i, v) in out.iter_mut().enumerate() {
        let (a, b) = (i / c, i % c);
        *v = (0..p).map(|t| jm[a * p + t] * j[b * p + t].conj()).sum();
    }
}

/// Each record's [`line_sensitivities`] (`p` parameters).
pub(super) fn all_line_sensitivities(lines: &[Lines], fits: &[Sensitivity], p: usize) -> Vec<Hats> {
    (lines.iter().zip(fits))
        .map(|(l, fit)| line_sensitivities(l, fit, p))
        .collect()
}

/// Ĵ_k at every line k of the record: θ's `p` columns, then its nuisance columns.
fn line_sensitivities(l: &Lines, fit: &Sensitivity, p: usize) -> Hats {
    let c = l.groups.len();
    let width = p + fit.nuisances();
    let scale = 1.0 / (l.size as f64).sqrt();
    let hat: Vec<Vec<Vec<Complex64>>> = (fit.columns.iter())
        .zip(fit.nuisance.iter().map(Some).chain(std::iter::repeat(None)))
        .map(|(cols, own)| {
            let all = cols.iter().chain(own.into_iter().flatten());
            spectra(all.map(|x| x.iter().copied()), l.size, scale)
        })
        .collect();
    let mut values = Vec::with_capacity(l.size * c * width);
    for k in 0..l.size {
        for channel in &hat {
            values.extend(channel.iter().map(|col| col[k]));
        }
    }
    Hats { width, values }
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
        let (n, p) = (32usize, 2usize);
        let j = DMatrix::from_fn(n, p, |t, c| {
            ((t * (c + 2)) as f64 * 0.37).cos() + 0.1 * c as f64
        });
        matches_the_time_domain(j, DMatrix::zeros(n, 0));
    }

    /// With a record's own linear parameters (an initial state's free responses, mean
    /// removed) that θ's columns were projected against, P is the sum of both
    /// projections: the lines near the free response's frequency lose more.
    #[test]
    fn the_records_own_columns_are_projected_out_too() {
        let (n, p, w) = (32usize, 2usize, 1.3);
        let mut x = DMatrix::from_fn(n, 2, |t, c| {
            let t = t as f64;
            (-0.15 * t).exp()
                * if c == 0 {
                    (0.8 * t).cos()
                } else {
                    (0.8 * t).sin()
                }
        });
        for mut column in x.column_iter_mut() {
            let mean = column.mean();
            column.add_scalar_mut(-mean);
        }
        let raw = DMatrix::from_fn(n, p, |t, c| {
            ((t * (c + 2)) as f64 * 0.37).cos() + 0.1 * c as f64
        });
        // Kaufman's projection: θ's columns orthogonal to X in the weighted metric.
        let xtx = (x.transpose() * &x).try_inverse().expect("independent");
        let j = &raw - &x * xtx * x.transpose() * &raw;
        assert!((x.transpose() * &j).norm() < 1e-12 * w);
        matches_the_time_domain(j, x);
    }

    /// `expected` against the time domain for θ's columns `j` and the record's own `x`.
    fn matches_the_time_domain(j: DMatrix<f64>, x: DMatrix<f64>) {
        let (n, p, q, w) = (j.nrows(), j.ncols(), x.ncols(), 1.3);
        let g: Vec<f64> = (0..n)
            .map(|t| (-0.2 * t as f64).exp() * (0.9 * t as f64).sin())
            .collect();
        let lines = Lines {
            size: n,
            groups: vec![0],
            residual: vec![vec![Complex64::new(0.0, 0.0); n]],
            transfer: vec![impulse_spectrum(g.iter().copied(), n)],
        };
        let a = j.transpose() * &j * (w * w);
        let a_inverse = a.clone().try_inverse().expect("invertible");
        let columns = |m: &DMatrix<f64>| -> Vec<Vec<f64>> {
            m.column_iter()
                .map(|c| c.iter().copied().collect())
                .collect()
        };
        let fit = Sensitivity {
            columns: vec![columns(&j)],
            nuisance: if q > 0 { vec![columns(&x)] } else { Vec::new() },
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
        let mut projector =
            DMatrix::<f64>::identity(n, n) - &j * &a_inverse * j.transpose() * (w * w);
        if q > 0 {
            let own = (x.transpose() * &x).try_inverse().expect("independent");
            projector -= &x * own * x.transpose();
        }
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
