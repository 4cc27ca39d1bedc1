//! The record's DFT pair and the one-segment Hann H1 derived from it.

use msd_signal::Complex64;

/// DFTs of two real records of equal length, their means removed, with one complex FFT:
/// z = (u − ū) + i·(y − ȳ), then U_k = (Z_k + conj Z_{N−k})/2 and
/// Y_k = (Z_k − conj Z_{N−k})/(2i).
pub(super) fn dft_pair(u: &[f64], y: &[f64]) -> (Vec<Complex64>, Vec<Complex64>) {
    debug_assert_eq!(u.len(), y.len());
    let n = u.len();
    let mean = |x: &[f64]| x.iter().sum::<f64>() / n as f64;
    let (mu, my) = (mean(u), mean(y));
    let mut z: Vec<Complex64> = u
        .iter()
        .zip(y)
        .map(|(&a, &b)| Complex64::new(a - mu, b - my))
        .collect();
    crate::fft::forward(n).process(&mut z);
    let mut uf = Vec::with_capacity(n);
    let mut yf = Vec::with_capacity(n);
    // Bin N−k is z[N−k] for k ≥ 1 and z[0] for k = 0 (no modulo in the loop).
    let mirrored = std::iter::once(z[0]).chain(z[1..].iter().rev().copied());
    for (&zk, zm) in z.iter().zip(mirrored) {
        let zc = zm.conj();
        uf.push((zk + zc) * 0.5);
        yf.push((zk - zc) * Complex64::new(0.0, -0.5));
    }
    (uf, yf)
}

/// The one-segment H1 estimate with a periodic Hann window from the rectangular DFTs of
/// the mean-removed records: X_w[k] = ½X[k] − ¼(X[k−1] + X[k+1]) (indices mod N), then
/// H1 = Y_w/U_w on the grid k·fs/N, k = 0…`k_max` (≤ ⌊N/2⌋), with msd-signal's conventions
/// (0 where the input has less than 1e-24 of its peak one-sided power; coherence 1 where
/// both records have power, else 0).
pub(super) fn hann_h1(
    uf: &[Complex64],
    yf: &[Complex64],
    fs: f64,
    k_max: usize,
) -> msd_signal::FrequencyResponseEstimate {
    let n = uf.len();
    let half = n / 2;
    debug_assert!(n >= 3 && k_max <= half);
    // Only k = 0 wraps around (X[−1] = X[N−1]).
    let windowed = |x: &[Complex64], k: usize| {
        let below = if k == 0 { x[n - 1] } else { x[k - 1] };
        x[k] * 0.5 - (below + x[k + 1]) * 0.25
    };
    // The one-sided spectrum doubles every bin but DC and Nyquist.
    let one_sided = |k: usize, c: Complex64| {
        let doubled = k != 0 && 2 * k != n;
        c.norm_sqr() * if doubled { 2.0 } else { 1.0 }
    };
    let (mut peak_u, mut peak_y) = (0.0f64, 0.0f64);
    for k in 0..=half {
        peak_u = peak_u.max(one_sided(k, windowed(uf, k)));
        peak_y = peak_y.max(one_sided(k, windowed(yf, k)));
    }
    let mut h = Vec::with_capacity(k_max + 1);
    let mut coherence = Vec::with_capacity(k_max + 1);
    for k in 0..=k_max {
        let (a, b) = (windowed(uf, k), windowed(yf, k));
        let input_has_power = one_sided(k, a) > 1e-24 * peak_u;
        let output_has_power = one_sided(k, b) > 1e-24 * peak_y;
        let (suu, syy, sxy) = (a.norm_sqr(), b.norm_sqr(), a.conj() * b);
        h.push(if input_has_power {
            sxy / suu
        } else {
            Complex64::new(0.0, 0.0)
        });
        coherence.push(if input_has_power && output_has_power {
            (sxy.norm_sqr() / (suu * syy)).min(1.0)
        } else {
            0.0
        });
    }
    msd_signal::FrequencyResponseEstimate {
        frequency: (0..=k_max).map(|k| k as f64 * fs / n as f64).collect(),
        h,
        coherence,
        averages: 1,
    }
}
