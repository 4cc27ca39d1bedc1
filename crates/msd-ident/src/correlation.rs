//! Sample auto- and cross-correlations: direct sums, and one FFT pair for both at once.

use msd_signal::Complex64;

/// Sample autocorrelation r₀…r_L of `x` (mean removed, normalised by lag 0).
///
/// ```
/// let r = msd_ident::correlation::autocorrelation(&[1.0, -1.0, 1.0, -1.0], 2);
/// assert_eq!(r, vec![1.0, -0.75, 0.5]);
/// ```
pub fn autocorrelation(x: &[f64], max_lag: usize) -> Vec<f64> {
    let n = x.len();
    let mean = x.iter().sum::<f64>() / n as f64;
    let xc: Vec<f64> = x.iter().map(|v| v - mean).collect();
    let c0 = dot(&xc, &xc);
    (0..=max_lag)
        .map(|k| {
            if k >= n || c0 == 0.0 {
                return if k == 0 { 1.0 } else { 0.0 };
            }
            dot(&xc[k..], &xc[..n - k]) / c0
        })
        .collect()
}

/// Sample cross-correlation ρ(τ) of e(t) with u(t − τ) for τ = −L…L.
///
/// ```
/// // y is x delayed by one sample: the correlation peaks at τ = 1.
/// let x = [0.0, 1.0, 0.0, -1.0, 0.0, 1.0, 0.0, -1.0];
/// let y = [0.0, 0.0, 1.0, 0.0, -1.0, 0.0, 1.0, 0.0];
/// let rho = msd_ident::correlation::cross_correlation(&y, &x, 2);
/// let best = rho.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).unwrap().0;
/// assert_eq!(best as i64 - 2, 1);
/// ```
pub fn cross_correlation(e: &[f64], u: &[f64], max_lag: usize) -> Vec<f64> {
    let n = e.len().min(u.len());
    let me = e[..n].iter().sum::<f64>() / n as f64;
    let mu = u[..n].iter().sum::<f64>() / n as f64;
    let ec: Vec<f64> = e[..n].iter().map(|v| v - me).collect();
    let uc: Vec<f64> = u[..n].iter().map(|v| v - mu).collect();
    let norm = (dot(&ec, &ec) * dot(&uc, &uc)).sqrt();
    let l = max_lag as i64;
    (-l..=l)
        .map(|tau| {
            if norm == 0.0 || tau.unsigned_abs() as usize >= n {
                return 0.0;
            }
            let shift = tau.unsigned_abs() as usize;
            // Σₜ e(t)·u(t − τ) over the overlap, written as one contiguous dot product.
            let s = if tau >= 0 {
                dot(&ec[shift..], &uc[..n - shift])
            } else {
                dot(&ec[..n - shift], &uc[shift..])
            };
            s / norm
        })
        .collect()
}

/// Dot product with sixteen independent accumulators, so that the loop vectorises and the
/// additions' latency is hidden (the correlations are ~80 dot products of ~7500 terms).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    const LANES: usize = 16;
    debug_assert_eq!(a.len(), b.len());
    let mut acc = [0.0f64; LANES];
    let (ca, cb) = (a.chunks_exact(LANES), b.chunks_exact(LANES));
    let tail: f64 = ca
        .remainder()
        .iter()
        .zip(cb.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in ca.zip(cb) {
        for k in 0..LANES {
            acc[k] += x[k] * y[k];
        }
    }
    let mut width = LANES;
    while width > 1 {
        width /= 2;
        for k in 0..width {
            acc[k] += acc[k + width];
        }
    }
    acc[0] + tail
}

/// The autocorrelation r₀…r_L of `e` and the cross-correlation ρ(−L…L) of `e` with `u`,
/// equal to [`autocorrelation`] and [`cross_correlation`] up to FFT rounding (about
/// ε·log₂M relative to the normalising sums; tested), computed with two FFTs of a
/// power-of-two length M ≥ N + L instead of (3L + 2) dot products of length N.
///
/// z = ẽ + i·ũ (means removed) is transformed once; E and U are split off by conjugate
/// symmetry; the inverse transform of |E|² + i·E·conj(U) holds both correlation sequences
/// (each real) in its real and imaginary parts. The zero padding to M ≥ N + L keeps
/// the circular correlation free of wrap-around at lags up to L.
pub(crate) fn correlations(e: &[f64], u: &[f64], max_lag: usize) -> (Vec<f64>, Vec<f64>) {
    let n = e.len();
    debug_assert_eq!(n, u.len());
    debug_assert!(max_lag < n);
    let m = (n + max_lag + 1).next_power_of_two();
    let mean = |x: &[f64]| x.iter().sum::<f64>() / n as f64;
    let (me, mu) = (mean(e), mean(u));
    let mut z = Vec::with_capacity(m);
    z.extend(
        e.iter()
            .zip(u)
            .map(|(&et, &ut)| Complex64::new(et - me, ut - mu)),
    );
    z.resize(m, Complex64::new(0.0, 0.0));
    crate::fft::forward(m).process(&mut z);
    // W_k = |E_k|² + i·E_k·conj(U_k), with E_k = (Z_k + conj Z_{M−k})/2 and
    // U_k = (Z_k − conj Z_{M−k})/(2i). Pairs (k, M − k) are updated together in place.
    let spectrum = |zk: Complex64, zm: Complex64| {
        let (ek, uk) = crate::fft::split(zk, zm);
        Complex64::new(ek.norm_sqr(), 0.0) + Complex64::new(0.0, 1.0) * (ek * uk.conj())
    };
    z[0] = spectrum(z[0], z[0]);
    for k in 1..=m / 2 {
        let j = m - k;
        let (zk, zj) = (z[k], z[j]);
        z[k] = spectrum(zk, zj);
        z[j] = spectrum(zj, zk);
    }
    crate::fft::inverse(m).process(&mut z);
    // z_τ / M = Σₜ ẽ(t)·ẽ(t − τ) + i·Σₜ ẽ(t)·ũ(t − τ), τ taken mod M.
    let c0 = z[0].re;
    let cu: f64 = u.iter().map(|v| (v - mu) * (v - mu)).sum::<f64>() * m as f64;
    let norm = (c0 * cu).sqrt();
    let auto = (0..=max_lag)
        .map(|k| match (k, c0 == 0.0) {
            (0, _) => 1.0,
            (_, true) => 0.0,
            _ => z[k].re / c0,
        })
        .collect();
    let l = max_lag as i64;
    let cross = (-l..=l)
        .map(|tau| {
            if norm == 0.0 {
                return 0.0;
            }
            z[tau.rem_euclid(m as i64) as usize].im / norm
        })
        .collect();
    (auto, cross)
}
