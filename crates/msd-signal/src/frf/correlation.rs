//! How the errors of neighbouring lines of a frequency response are correlated.
//!
//! A window w on a record of L samples makes the DFT of white noise n correlated from
//! line to line: E[N_k·conj(N_{k+d})] = σ²·conj(W₂(d)), W₂ the DFT of w² (Harris 1978).
//! The rectangular window leaves the lines independent, the Hann window correlates
//! three (ρ(±1) = −2/3, ρ(±2) = 1/6), the exponential window e^(−t/τ) of an impact test
//! about T/τ of them, with ρ(d) ≈ 1/(1 − jπdτ/T) complex. The error an H1 estimate
//! takes from the response's noise, Σᵢ conj(Xᵢₖ)·Nᵢₖ/S_xx,k, is correlated through the
//! response's window and the force spectra's own line-to-line products; the relative
//! error the force's noise makes (δH/H ≈ −Σᵢ conj(Xᵢₖ)·Mᵢₖ/S_xx,k) through the force's
//! window and the same products. A fit whose covariance takes the lines as independent
//! is too confident by about Σ_d ρ(d) (T/τ for the exponential window, twice its
//! equivalent noise bandwidth).

use rustfft::Fft;
use rustfft::num_complex::Complex64;

/// Lags beyond this are not kept: the exponential window's ρ(d) ≈ T/(πτd) has fallen
/// to 0.01 of ρ(0) here for T/τ = 4, and what is left of Σ Re ρ(d) beyond it, about
/// 2(T/πτ)²/d, is 0.6 % of the sum.
pub const MAX_LAG: usize = 128;

/// Lags where both windows' |ρ(d)| are below this (and beyond) are taken as 0.
const NEGLIGIBLE: f64 = 1e-3;

/// The correlation of the errors of lines k and k + d of a frequency response estimated
/// from windowed records, ρ(d) = E[e_k·conj(e_{k+d})]/(σ_k·σ_{k+d}) for d = 0, 1, …
/// (ρ(0) = 1; ρ(−d) = conj ρ(d); 0 beyond the last kept lag): for the error the
/// response's noise makes (`response`) and for the relative error δH/H the force's noise
/// makes (`force`). Both empty when the lines are independent as far as is known (a
/// measured table, a file). Harris 1978 for the windows; the H1 errors as in
/// Bendat & Piersol, "Random Data", §9.2.
///
/// ```
/// use msd_signal::{Complex64, LineCorrelation};
/// let hann = LineCorrelation {
///     response: vec![Complex64::new(1.0, 0.0), Complex64::new(4.0 / 9.0, 0.0)],
///     force: Vec::new(),
/// };
/// assert_eq!(LineCorrelation::at(&hann.response, -1), Complex64::new(4.0 / 9.0, 0.0));
/// assert_eq!(LineCorrelation::at(&hann.response, 2), Complex64::new(0.0, 0.0));
/// assert_eq!(LineCorrelation::at(&hann.force, 0), Complex64::new(1.0, 0.0));
/// assert!(LineCorrelation::default().is_empty());
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LineCorrelation {
    /// ρ(d) of the errors the response's noise makes, d = 0, 1, ….
    pub response: Vec<Complex64>,
    /// ρ(d) of the relative errors the force's noise makes, d = 0, 1, ….
    pub force: Vec<Complex64>,
}

impl LineCorrelation {
    /// Whether nothing is known of the correlation (the lines taken as independent).
    pub fn is_empty(&self) -> bool {
        self.response.is_empty() && self.force.is_empty()
    }

    /// `kernel` at lag `d` (conjugated for d < 0, 0 beyond its end); 1 at d = 0 for an
    /// empty kernel (independent lines).
    pub fn at(kernel: &[Complex64], d: i64) -> Complex64 {
        if kernel.is_empty() {
            return Complex64::new(if d == 0 { 1.0 } else { 0.0 }, 0.0);
        }
        match kernel.get(d.unsigned_abs() as usize) {
            Some(r) if d < 0 => r.conj(),
            Some(&r) => r,
            None => Complex64::new(0.0, 0.0),
        }
    }

    /// Σ_d Re ρ(d) over every lag of `kernel`: for errors that vary slowly from line to
    /// line relative to the correlation's length, the factor by which a covariance
    /// taken from independent lines is too small (≥ 1 for the kernels of real windows
    /// near it; 1 for an empty kernel).
    pub fn sum(kernel: &[Complex64]) -> f64 {
        match kernel.split_first() {
            None => 1.0,
            Some((first, rest)) => first.re + 2.0 * rest.iter().map(|r| r.re).sum::<f64>(),
        }
    }
}

/// conj(W₂(d))/W₂(0) for d = 0 … L − 1: how a window of L samples correlates the DFT
/// lines of white noise (`fft` the forward transform of length L).
pub(crate) fn window_kernel(window: &[f64], fft: &dyn Fft<f64>) -> Vec<Complex64> {
    let mut buf: Vec<Complex64> = window.iter().map(|w| Complex64::new(w * w, 0.0)).collect();
    fft.process(&mut buf);
    let zero = buf[0].re;
    buf.iter().map(|v| v.conj() / zero).collect()
}

/// The last lag (≤ [`MAX_LAG`], < `bins`) at which either window kernel is not
/// negligible (0 for empty kernels).
pub(crate) fn last_lag(input: &[Complex64], output: &[Complex64], bins: usize) -> usize {
    if input.is_empty() || output.is_empty() {
        return 0;
    }
    let limit = (MAX_LAG.min(bins) + 1)
        .min(input.len())
        .min(output.len())
        .saturating_sub(1);
    (0..=limit)
        .rev()
        .find(|&d| input[d].norm().max(output[d].norm()) >= NEGLIGIBLE)
        .unwrap_or(0)
}

/// The sums over segments of conj(X_k)·X_{k+d}, lines 1 … bins − 1 − d, for the lags
/// 0 ≤ d ≤ `last`: how the force spectra's own lines are related.
pub(crate) struct LagProducts {
    sums: Vec<Complex64>,
}

impl LagProducts {
    pub(crate) fn new(last: usize) -> Self {
        Self {
            sums: vec![Complex64::new(0.0, 0.0); last + 1],
        }
    }

    /// Adds one segment's force spectrum (lines 0 … bins − 1).
    pub(crate) fn add(&mut self, x: &[Complex64]) {
        let bins = x.len();
        for (d, sum) in self.sums.iter_mut().enumerate() {
            for k in 1..bins.saturating_sub(d) {
                *sum += x[k].conj() * x[k + d];
            }
        }
    }

    /// The kernels from the sums, the force's power per line summed over segments
    /// (`power`, lines 0 … bins − 1) and the two windows' kernels.
    pub(crate) fn correlation(
        &self,
        power: &[f64],
        input: &[Complex64],
        output: &[Complex64],
    ) -> LineCorrelation {
        let bins = power.len();
        let total = |from: usize, to: usize| power[from.min(to)..to].iter().sum::<f64>();
        let kappa: Vec<Complex64> = (self.sums.iter().enumerate())
            .map(|(d, s)| {
                let norm = (total(1, bins.saturating_sub(d)) * total(1 + d, bins)).sqrt();
                if norm > 0.0 { s / norm } else { *s * 0.0 }
            })
            .collect();
        let kernel = |window: &[Complex64]| -> Vec<Complex64> {
            kappa.iter().zip(window).map(|(k, w)| k * w).collect()
        };
        LineCorrelation {
            response: kernel(output),
            force: kernel(input),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hann_window_correlates_three_lines() {
        let l = 64;
        let hann: Vec<f64> = (0..l)
            .map(|t| 0.5 - 0.5 * (std::f64::consts::TAU * t as f64 / l as f64).cos())
            .collect();
        let k = window_kernel(&hann, &*rustfft::FftPlanner::new().plan_fft_forward(l));
        // w² = 3/8 − cos(2πt/L)/2 + cos(4πt/L)/8.
        for (d, want) in [(0, 1.0), (1, -2.0 / 3.0), (2, 1.0 / 6.0), (3, 0.0)] {
            assert!(
                (k[d] - Complex64::new(want, 0.0)).norm() < 1e-12,
                "{d}: {}",
                k[d]
            );
        }
        assert_eq!(last_lag(&k, &k, l / 2 + 1), 2);
        assert!(LineCorrelation::sum(&k[..3]).abs() < 1e-12);
    }

    #[test]
    fn the_exponential_window_correlates_about_t_over_tau_lines() {
        // T = 8 s at 256 Hz, τ = 2 s: w² = aᵗ with a = e^(−2/(τ·fs)), so
        // ρ(d) = (1 − a)/(1 − a·e^(jθ)), θ = 2πd/L, exactly; ≈ 1/(1 − jπdτ/T).
        let (l, fs, tau) = (2048, 256.0, 2.0);
        let w: Vec<f64> = (0..l).map(|t| (-(t as f64) / fs / tau).exp()).collect();
        let k = window_kernel(&w, &*rustfft::FftPlanner::new().plan_fft_forward(l));
        let a = (-2.0 / (tau * fs)).exp();
        for (d, got) in k.iter().enumerate().take(MAX_LAG + 1) {
            let theta = std::f64::consts::TAU * d as f64 / l as f64;
            let want = Complex64::new(1.0 - a, 0.0) / (1.0 - a * Complex64::from_polar(1.0, theta));
            assert!((got - want).norm() < 1e-9, "{d}: {got} vs {want}");
        }
        let near = Complex64::new(1.0, -std::f64::consts::PI * 2.0 * tau / 8.0).inv();
        assert!((k[2] - near).norm() < 0.01, "{} vs {near}", k[2]);
        let last = last_lag(&k, &k, l / 2 + 1);
        assert_eq!(last, MAX_LAG);
        // Σ Re ρ ≈ T/τ = 4, plus the floor (1 − a)/(1 + a) ≈ 0.002 per lag that the
        // window's jump at the record's wrap puts on every lag (0.5 over ±128).
        let sum = LineCorrelation::sum(&k[..=last]);
        let floor = (1.0 - a) / (1.0 + a) * 2.0 * MAX_LAG as f64;
        assert!((sum - 4.0 - floor).abs() < 0.05, "{sum}");
    }
}
