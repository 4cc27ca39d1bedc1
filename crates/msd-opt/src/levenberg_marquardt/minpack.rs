//! MINPACK's linear-algebra kernels, translated from Moré, Garbow & Hillstrom's
//! Fortran (`qrfac`, `lmpar`, `qrsolv`, `enorm`): a Householder QR with column
//! pivoting, the Levenberg–Marquardt parameter search of Moré (1978), and the
//! Givens-rotation solve of the damped system
//! `[J; √λ·D]·p ≈ [−f; 0]` in the least-squares sense.
//!
//! Matrices are column-major slices with leading dimension `ld` (the number of
//! rows of the Jacobian); indices are 0-based.

// A translation of MINPACK keeps its index loops, which read like the Fortran.
#![allow(clippy::needless_range_loop)]

/// Euclidean norm that neither overflows nor underflows.
///
/// Fast path: the plain sum of squares (four accumulators, so it vectorises), used when
/// it is finite and above 1e-280 — then no square overflowed, and any square that
/// underflowed is below 1e-300·len, negligible at f64 precision beside the sum. Otherwise
/// MINPACK-style accumulation with a running scale.
pub(crate) fn enorm(v: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let chunks = v.chunks_exact(4);
    let tail = chunks.remainder();
    for c in chunks {
        for k in 0..4 {
            acc[k] += c[k] * c[k];
        }
    }
    let sum = (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail.iter().map(|x| x * x).sum::<f64>();
    if sum.is_finite() && sum > 1e-280 {
        return sum.sqrt();
    }
    scaled_norm(v)
}

/// MINPACK-style norm accumulated with a running scale.
fn scaled_norm(v: &[f64]) -> f64 {
    let mut scale = 0.0_f64;
    let mut ssq = 1.0_f64;
    for &x in v {
        if x != 0.0 {
            let a = x.abs();
            if scale < a {
                ssq = 1.0 + ssq * (scale / a) * (scale / a);
                scale = a;
            } else {
                ssq += (a / scale) * (a / scale);
            }
        }
    }
    scale * ssq.sqrt()
}

/// Householder QR with column pivoting of the `m×n` matrix `a` (as `qrfac` with
/// `pivot = .true.`). On return the upper triangle of `a` holds R except its
/// diagonal, which is in `rdiag`; the lower trapezoid holds the Householder
/// vectors; `ipvt[j]` is the original index of column j; `acnorm` the column norms.
pub(crate) fn qrfac(
    m: usize,
    n: usize,
    a: &mut [f64],
    ipvt: &mut [usize],
    rdiag: &mut [f64],
    acnorm: &mut [f64],
    wa: &mut [f64],
) {
    for j in 0..n {
        acnorm[j] = enorm(&a[j * m..(j + 1) * m]);
        rdiag[j] = acnorm[j];
        wa[j] = rdiag[j];
        ipvt[j] = j;
    }
    for j in 0..m.min(n) {
        // Bring the column of largest remaining norm into the pivot position.
        let mut kmax = j;
        for k in j..n {
            if rdiag[k] > rdiag[kmax] {
                kmax = k;
            }
        }
        if kmax != j {
            for i in 0..m {
                a.swap(i + j * m, i + kmax * m);
            }
            rdiag[kmax] = rdiag[j];
            wa[kmax] = wa[j];
            ipvt.swap(j, kmax);
        }
        let cj = j * m;
        let mut ajnorm = enorm(&a[cj + j..cj + m]);
        if ajnorm != 0.0 {
            if a[cj + j] < 0.0 {
                ajnorm = -ajnorm;
            }
            for i in j..m {
                a[cj + i] /= ajnorm;
            }
            a[cj + j] += 1.0;
            // Apply the transformation to the remaining columns and update norms.
            for k in j + 1..n {
                let ck = k * m;
                let mut sum = 0.0;
                for i in j..m {
                    sum += a[cj + i] * a[ck + i];
                }
                let temp = sum / a[cj + j];
                for i in j..m {
                    a[ck + i] -= temp * a[cj + i];
                }
                if rdiag[k] != 0.0 {
                    let temp = a[ck + j] / rdiag[k];
                    rdiag[k] *= (1.0 - temp * temp).max(0.0).sqrt();
                    if 0.05 * (rdiag[k] / wa[k]).powi(2) <= f64::EPSILON {
                        rdiag[k] = enorm(&a[ck + j + 1..ck + m]);
                        wa[k] = rdiag[k];
                    }
                }
            }
        }
        rdiag[j] = -ajnorm;
    }
}

/// Solves `R·z = Qᵀb, √λ·D·z = 0` in the least-squares sense by Givens rotations
/// (`qrsolv`). `r` holds R in its upper triangle (leading dimension `ld`); on
/// return its strict lower triangle holds Sᵀ with `Pᵀ(JᵀJ + λD²)P = SᵀS`, and
/// `sdiag` the diagonal of S. `diag` here is √λ·D.
#[allow(clippy::too_many_arguments)]
pub(crate) fn qrsolv(
    n: usize,
    r: &mut [f64],
    ld: usize,
    ipvt: &[usize],
    diag: &[f64],
    qtb: &[f64],
    x: &mut [f64],
    sdiag: &mut [f64],
    wa: &mut [f64],
) {
    let idx = |i: usize, j: usize| i + j * ld;
    for j in 0..n {
        for i in j..n {
            r[idx(i, j)] = r[idx(j, i)];
        }
        x[j] = r[idx(j, j)];
        wa[j] = qtb[j];
    }
    for j in 0..n {
        let l = ipvt[j];
        if diag[l] != 0.0 {
            for s in sdiag[j..n].iter_mut() {
                *s = 0.0;
            }
            sdiag[j] = diag[l];
            let mut qtbpj = 0.0;
            for k in j..n {
                if sdiag[k] == 0.0 {
                    continue;
                }
                let rkk = r[idx(k, k)];
                let (cos, sin) = if rkk.abs() < sdiag[k].abs() {
                    let cotan = rkk / sdiag[k];
                    let sin = 0.5 / (0.25 + 0.25 * cotan * cotan).sqrt();
                    (sin * cotan, sin)
                } else {
                    let tan = sdiag[k] / rkk;
                    let cos = 0.5 / (0.25 + 0.25 * tan * tan).sqrt();
                    (cos, cos * tan)
                };
                r[idx(k, k)] = cos * rkk + sin * sdiag[k];
                let temp = cos * wa[k] + sin * qtbpj;
                qtbpj = -sin * wa[k] + cos * qtbpj;
                wa[k] = temp;
                for i in k + 1..n {
                    let rik = r[idx(i, k)];
                    let temp = cos * rik + sin * sdiag[i];
                    sdiag[i] = -sin * rik + cos * sdiag[i];
                    r[idx(i, k)] = temp;
                }
            }
        }
        sdiag[j] = r[idx(j, j)];
        r[idx(j, j)] = x[j];
    }
    // Solve the triangular system; if singular, a least-squares solution.
    let mut nsing = n;
    for j in 0..n {
        if sdiag[j] == 0.0 && nsing == n {
            nsing = j;
        }
        if nsing < n {
            wa[j] = 0.0;
        }
    }
    for j in (0..nsing).rev() {
        let mut sum = 0.0;
        for i in j + 1..nsing {
            sum += r[idx(i, j)] * wa[i];
        }
        wa[j] = (wa[j] - sum) / sdiag[j];
    }
    for j in 0..n {
        x[ipvt[j]] = wa[j];
    }
}

/// The Gauss–Newton direction of `lmpar` into `x` (a least-squares solution where R is
/// singular: the components from its first zero diagonal on are 0); R's rank, `nsing`.
fn gauss_newton_direction(
    n: usize,
    r: &[f64],
    ld: usize,
    ipvt: &[usize],
    qtb: &[f64],
    x: &mut [f64],
    wa1: &mut [f64],
) -> usize {
    let idx = |i: usize, j: usize| i + j * ld;
    let mut nsing = n;
    for j in 0..n {
        wa1[j] = qtb[j];
        if r[idx(j, j)] == 0.0 && nsing == n {
            nsing = j;
        }
        if nsing < n {
            wa1[j] = 0.0;
        }
    }
    for j in (0..nsing).rev() {
        wa1[j] /= r[idx(j, j)];
        let temp = wa1[j];
        for i in 0..j {
            wa1[i] -= r[idx(i, j)] * temp;
        }
    }
    for j in 0..n {
        x[ipvt[j]] = wa1[j];
    }
    nsing
}

/// Determines the Levenberg–Marquardt parameter λ (`lmpar`) so that the solution
/// `x` of the damped system has `‖D·x‖` within 10 % of `delta` (or λ = 0 when the
/// Gauss–Newton step is already short enough). Returns the new λ; `x` holds the
/// step (to be negated: it solves `J·x ≈ f`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn lmpar(
    n: usize,
    r: &mut [f64],
    ld: usize,
    ipvt: &[usize],
    diag: &[f64],
    qtb: &[f64],
    delta: f64,
    par_in: f64,
    x: &mut [f64],
    sdiag: &mut [f64],
    wa1: &mut [f64],
    wa2: &mut [f64],
) -> f64 {
    let idx = |i: usize, j: usize| i + j * ld;
    let dwarf = f64::MIN_POSITIVE;
    let nsing = gauss_newton_direction(n, r, ld, ipvt, qtb, x, wa1);
    for j in 0..n {
        wa2[j] = diag[j] * x[j];
    }
    let mut dxnorm = enorm(&wa2[..n]);
    let mut fp = dxnorm - delta;
    if fp <= 0.1 * delta {
        return 0.0;
    }
    // Lower bound parl from the Newton step (zero if rank deficient).
    let mut parl = 0.0;
    if nsing == n {
        for j in 0..n {
            let l = ipvt[j];
            wa1[j] = diag[l] * (wa2[l] / dxnorm);
        }
        for j in 0..n {
            let mut sum = 0.0;
            for i in 0..j {
                sum += r[idx(i, j)] * wa1[i];
            }
            wa1[j] = (wa1[j] - sum) / r[idx(j, j)];
        }
        let temp = enorm(&wa1[..n]);
        parl = ((fp / delta) / temp) / temp;
    }
    // Upper bound paru.
    for j in 0..n {
        let mut sum = 0.0;
        for i in 0..=j {
            sum += r[idx(i, j)] * qtb[i];
        }
        wa1[j] = sum / diag[ipvt[j]];
    }
    let gnorm = enorm(&wa1[..n]);
    let mut paru = gnorm / delta;
    if paru == 0.0 {
        paru = dwarf / delta.min(0.1);
    }
    let mut par = par_in.max(parl).min(paru);
    if par == 0.0 {
        par = gnorm / dxnorm;
    }
    let mut iter = 0;
    loop {
        iter += 1;
        if par == 0.0 {
            par = dwarf.max(0.001 * paru);
        }
        let s = par.sqrt();
        for j in 0..n {
            wa1[j] = s * diag[j];
        }
        qrsolv(n, r, ld, ipvt, wa1, qtb, x, sdiag, wa2);
        for j in 0..n {
            wa2[j] = diag[j] * x[j];
        }
        dxnorm = enorm(&wa2[..n]);
        let previous = fp;
        fp = dxnorm - delta;
        if fp.abs() <= 0.1 * delta
            || (parl == 0.0 && fp <= previous && previous < 0.0)
            || iter == 10
        {
            return par;
        }
        // Newton correction.
        for j in 0..n {
            let l = ipvt[j];
            wa1[j] = diag[l] * (wa2[l] / dxnorm);
        }
        for j in 0..n {
            wa1[j] /= sdiag[j];
            let temp = wa1[j];
            for i in j + 1..n {
                wa1[i] -= r[idx(i, j)] * temp;
            }
        }
        let temp = enorm(&wa1[..n]);
        let parc = ((fp / delta) / temp) / temp;
        if fp > 0.0 {
            parl = parl.max(par);
        }
        if fp < 0.0 {
            paru = paru.min(par);
        }
        par = parl.max(par + parc);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enorm_is_robust() {
        assert_eq!(enorm(&[3.0, 4.0]), 5.0);
        assert_eq!(enorm(&[]), 0.0);
        assert!((enorm(&[1e200, 1e200]) - 2f64.sqrt() * 1e200).abs() < 1e186);
        assert!((enorm(&[1e-200, 1e-200]) - 2f64.sqrt() * 1e-200).abs() < 1e-214);
        // Both paths agree on ordinary vectors, lengths not a multiple of 4 included.
        let v: Vec<f64> = (0..7503)
            .map(|i| ((i * 37 % 101) as f64 - 50.0) * 1e-3)
            .collect();
        assert!((enorm(&v) - scaled_norm(&v)).abs() <= 4.0 * f64::EPSILON * enorm(&v));
        assert!((enorm(&[1e300, 1e300, 1e300]) - 3f64.sqrt() * 1e300).abs() < 1e286);
    }

    #[test]
    fn qr_reproduces_the_column_norms_and_r() {
        // A = [[3, 1], [4, 2]] (columns (3,4) and (1,2)); |R| diagonal = (5, 2/5).
        let mut a = [3.0, 4.0, 1.0, 2.0];
        let (mut ipvt, mut rdiag, mut acnorm, mut wa) = ([0; 2], [0.0; 2], [0.0; 2], [0.0; 2]);
        qrfac(2, 2, &mut a, &mut ipvt, &mut rdiag, &mut acnorm, &mut wa);
        assert_eq!(ipvt, [0, 1]);
        assert!((acnorm[0] - 5.0).abs() < 1e-15);
        assert!((rdiag[0].abs() - 5.0).abs() < 1e-15);
        // |det A| = 2 = |r11·r22|.
        assert!((rdiag[0] * rdiag[1]).abs() - 2.0 < 1e-14);
    }

    #[test]
    fn lmpar_returns_gauss_newton_inside_the_trust_region() {
        // J = I (R = I, no pivoting), f such that Qᵀf = (1, 2): the Gauss–Newton
        // step (1, 2) has norm √5 < delta = 10, so λ = 0 and x = (1, 2).
        let mut r = [1.0, 0.0, 0.0, 1.0];
        let (ipvt, diag, qtb) = ([0, 1], [1.0, 1.0], [1.0, 2.0]);
        let (mut x, mut sdiag, mut w1, mut w2) = ([0.0; 2], [0.0; 2], [0.0; 2], [0.0; 2]);
        let par = lmpar(
            2, &mut r, 2, &ipvt, &diag, &qtb, 10.0, 0.0, &mut x, &mut sdiag, &mut w1, &mut w2,
        );
        assert_eq!(par, 0.0);
        assert_eq!(x, [1.0, 2.0]);
        // With delta = 1 the step is (1, 2)/(1 + λ), so λ ≈ √5 − 1 within 10 %.
        let par = lmpar(
            2, &mut r, 2, &ipvt, &diag, &qtb, 1.0, 0.0, &mut x, &mut sdiag, &mut w1, &mut w2,
        );
        let norm = enorm(&x);
        assert!((norm - 1.0).abs() <= 0.1, "{norm}");
        assert!((x[0] - 1.0 / (1.0 + par)).abs() < 1e-14);
    }
}
