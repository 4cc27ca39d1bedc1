//! EFDD's decay fit: an SDOF bell of singular values turned back into the mode's
//! correlation function, the lag window divided out; the damped frequency from the
//! regression of its zero crossings, the damping ratio from the logarithmic decrement
//! of its extremes.

use msd_signal::Complex64;

use super::options::FddOptions;
use super::spectrum::window_decay;

/// The damped frequency (cycles per lag) and ζ of a bell: `bell[i]` the first singular
/// value at line `first_line + i` of a spectral matrix from `lags` lags (`None` where the
/// fit has fewer than four extremes or no decay).
pub(crate) fn decay(
    bell: &[f64],
    first_line: usize,
    lags: usize,
    options: &FddOptions,
) -> Option<(f64, f64)> {
    fit(&correlation(bell, first_line, lags), options)
}

/// The bell's inverse transform at lags 0 … N/4, divided by its value at lag 0 and by the
/// lag window (which is above 30 % there).
fn correlation(bell: &[f64], first_line: usize, lags: usize) -> Vec<f64> {
    let size = 2 * lags;
    let mut a = vec![Complex64::new(0.0, 0.0); size];
    for (i, &v) in bell.iter().enumerate() {
        let j = first_line + i;
        a[j] = Complex64::new(v, 0.0);
        if j > 0 && j < lags {
            a[size - j] = Complex64::new(v, 0.0);
        }
    }
    rustfft::FftPlannerScalar::new()
        .plan_fft_inverse(size)
        .process(&mut a);
    let beta = window_decay(lags);
    let r0 = a[0].re;
    (0..=lags / 4)
        .map(|k| a[k].re / r0 * (beta * k as f64).exp())
        .collect()
}

/// fn (cycles per lag, damped) and ζ from a correlation function r (r[0] = 1).
fn fit(r: &[f64], options: &FddOptions) -> Option<(f64, f64)> {
    let crossings: Vec<f64> = (0..r.len() - 1)
        .filter(|&k| (r[k] > 0.0) != (r[k + 1] > 0.0))
        .map(|k| k as f64 + r[k] / (r[k] - r[k + 1]))
        .collect();
    // Extreme j ≥ 1 lies between crossings j − 1 and j; extreme 0 is r[0].
    let mut extremes = vec![1.0];
    for pair in crossings.windows(2) {
        let (from, to) = (pair[0].ceil() as usize, pair[1].floor() as usize);
        let k = (from..=to.min(r.len() - 1)).max_by(|&a, &b| r[a].abs().total_cmp(&r[b].abs()))?;
        extremes.push(refined(r, k).abs());
    }
    let first = options.skip_extremes;
    let used: Vec<usize> = (first..extremes.len())
        .take_while(|&j| extremes[j] >= options.min_correlation)
        .take(options.max_extremes)
        .collect();
    if used.len() < 4 {
        return None;
    }
    let (j0, j1) = (used[0], used[used.len() - 1]);
    let z: Vec<(f64, f64)> = (j0.max(1) - 1..=j1.min(crossings.len() - 1))
        .map(|m| (m as f64, crossings[m]))
        .collect();
    let half_period = slope(&z);
    let logs: Vec<(f64, f64)> = used.iter().map(|&j| (j as f64, extremes[j].ln())).collect();
    let delta = -2.0 * slope(&logs);
    let zeta = delta / (4.0 * std::f64::consts::PI.powi(2) + delta * delta).sqrt();
    (half_period > 0.0 && zeta > 0.0).then(|| (0.5 / half_period, zeta))
}

/// The value of the parabola through r[k − 1], r[k], r[k + 1] at its vertex (r[k] at an
/// end).
fn refined(r: &[f64], k: usize) -> f64 {
    if k == 0 || k + 1 >= r.len() {
        return r[k];
    }
    let (a, b, c) = (r[k - 1], r[k], r[k + 1]);
    let curvature = a - 2.0 * b + c;
    if curvature == 0.0 {
        b
    } else {
        b - (a - c).powi(2) / (8.0 * curvature)
    }
}

/// The least-squares slope of y on x.
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(sx, sy), (x, y)| (sx + x / n, sy + y / n));
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx).powi(2))
    });
    sxy / sxx
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_damped_cosine_gives_back_its_frequency_and_damping() {
        // r(k) = e^{−ζωk} cos(ω_d k) with 100 lags per cycle: successive extremes are
        // exactly half a period apart with ratio e^{−ζωπ/ω_d}, so the fit is exact up to
        // the parabola's vertex error, O(h⁴) with h = 2π/100: below 1e-6 relative here.
        let (zeta, cycles_per_lag) = (0.02_f64, 0.01_f64);
        let w = std::f64::consts::TAU * cycles_per_lag / (1.0 - zeta * zeta).sqrt();
        let wd = std::f64::consts::TAU * cycles_per_lag;
        let r: Vec<f64> = (0..2000)
            .map(|k| (-zeta * w * k as f64).exp() * (wd * k as f64).cos())
            .collect();
        let (fd, z) = fit(&r, &FddOptions::default()).expect("a decay");
        assert!((fd / cycles_per_lag - 1.0).abs() < 1e-6, "{fd}");
        assert!((z / zeta - 1.0).abs() < 1e-4, "{z}");
    }

    #[test]
    fn growth_or_too_few_extremes_is_none() {
        let growing: Vec<f64> = (0..2000)
            .map(|k| (0.001 * k as f64).exp() * (0.0628 * k as f64).cos())
            .collect();
        assert_eq!(fit(&growing, &FddOptions::default()), None);
        let short: Vec<f64> = (0..60).map(|k| (0.0628 * k as f64).cos()).collect();
        assert_eq!(fit(&short, &FddOptions::default()), None);
    }
}
