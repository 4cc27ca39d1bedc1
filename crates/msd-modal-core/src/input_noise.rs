//! An H1 estimate corrected for the force's noise its coherence shows.
//!
//! Noise on the force (a load cell's, N_x) adds to S_xx and not to S_xy, so
//! H1 = S_xy/S_xx is low by the factor S_uu/(S_uu + N_x) at every line, whatever the
//! response's noise; H2 = S_yy/S_yx is high by the response's noise instead, and Hv
//! (or the H_s of Wicks & Vold, IMAC 4, 1986, with the noise ratio λ) lies between.
//! The coherence says how much of each: its noise model (Var Ĥ_k ∝ a·|H_k|² +
//! b·ω_k^(−2p), fitted to every line's coherence by
//! [`Lines::smooth_coherence_weights`]) has the force's noise in a, the response's in b.
//! With K averages, q_k = (1 − γ̂²)/(2K·γ̂²)·|Ĥ|², so the force's part of the mean
//! (1 − γ̂²)/γ̂² is 2K·a, and that is H1's relative bias: simulated over 400,000 lines
//! with K = 4, E\[Ĥ1\]/H − 1 = −N_x/S_uu and E\[(1 − γ̂²)/γ̂²\] = (N_x + N_y/|H|²)/S_uu for a
//! random force, and (K − 1)/K of both for a force that repeats from record to record.
//! H1·(1 + 2K·a) is then consistent.
//!
//! The lines are corrected by that one factor rather than turned into H2 or H_s line
//! by line, which would carry each line's own coherence (six degrees of freedom with
//! four averages) into the lines, nonlinearly; the factor rests on the assumption the
//! noise model's weights already make (a force of even power over the band, white noise
//! on both channels). On the shipped shaker config with 10 % force noise (150 seeds) it
//! takes m's bias from +0.68 to −0.13 standard errors and its coverage from 0.89 to 0.93.
//!
//! Where the force's noise was measured — an impact test's force channel after the force
//! window ([`msd_signal::force_channel_noise`]) — each line's share v_k is known, and
//! each line is raised by its own (K − 1)·v_k = 2K·a_k under any window: the leakage
//! that makes the coherence's a ambiguous does not enter a measurement of the channel.
//! (K − 1), not K: the hits' spectra have the same shape, and the noise's correlation
//! with them gives one part in K back (to second order; simulated in msd-signal's tests).

use serde::Serialize;

use crate::lines::{FrfWeighting, Lines};
use msd_signal::Estimator;

/// The force's noise an H1 estimate's coherence shows: how low it made H1, and whether
/// the lines were raised by it.
///
/// ```
/// use msd_modal_core::InputNoise;
/// let n = InputNoise { h1_bias: 0.004, corrected: true, measured: false };
/// assert_eq!(
///     n.to_string(),
///     "the force's noise biased H1 low by 0.40 % (its share of the coherence's noise model): the lines were raised by as much"
/// );
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct InputNoise {
    /// The force's part of the lines' mean (1 − γ̂²)/γ̂², 2K·a: H1 was low by the factor
    /// 1/(1 + this). N_x/S_uu for a random force; (K − 1)/K of it for a force that
    /// repeats from record to record (both measured by simulation).
    pub h1_bias: f64,
    /// Whether the lines were raised by it: only lines without leakage (a rectangular
    /// window, which msd-signal's automatic window takes only over whole periods of a
    /// repeating force). Under a Hann window the resonance's leakage lowers the
    /// coherence in the same shape, and taking it for force noise moved m by 3.6
    /// standard errors on a noise-free random test (K = 31); the bias is then said, not
    /// taken off.
    pub corrected: bool,
    /// Whether the force's noise was measured (an impact test's force channel after the
    /// force window): then each line is raised by its own 2K·a_k = (K − 1)·v_k, under
    /// any window, and `h1_bias` is their mean over the lines in the fit's weights.
    pub measured: bool,
}

impl std::fmt::Display for InputNoise {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let percent = 100.0 * self.h1_bias;
        if self.measured {
            write!(
                f,
                "the force's noise, measured on the force channel after the force window, biased H1 low by {percent:.3} % (in the fit's weights): each line was raised by its own share"
            )
        } else if self.corrected {
            write!(
                f,
                "the force's noise biased H1 low by {percent:.2} % (its share of the coherence's noise model): the lines were raised by as much"
            )
        } else {
            write!(
                f,
                "warning: the coherence's noise model puts noise on the force, or the window's leakage: H1 may be low by up to {percent:.2} %, and m and k high by as much; not corrected, since under this window leakage looks the same — a force that repeats over whole records (rectangular window) lets the fit take it off, or compare with H2"
            )
        }
    }
}

/// The force's noise a is taken to be there when it stands this many standard errors
/// above zero: a ≥ 0 is clipped at zero, so that an estimate near zero would raise the
/// lines by its noise alone (by 0.1 standard error of m, measured, at 3 % force noise).
const SIGNIFICANT: f64 = 2.0;

impl Lines {
    /// Corrects the lines of an H1 estimate for the force's noise the coherence's noise
    /// model finds (a two standard errors above 0): every line × (1 + 2K·a), where the
    /// lines have no leakage (see [`InputNoise::corrected`]). Returns what it found.
    /// Nothing for another estimator, a table, or weights not from the coherence (no
    /// noise model).
    pub fn correct_input_noise(&mut self) -> Option<InputNoise> {
        let noise = self.noise_model?;
        let a = noise.force;
        let k = self.averages as f64;
        if noise.force_measured && self.estimator == Some(Estimator::H1) {
            // (K − 1)·v_k at each line, known: no leakage to confound it with.
            for ((h, s), v) in self
                .h
                .iter_mut()
                .zip(&mut self.sigma)
                .zip(&self.input_noise)
            {
                *h *= 1.0 + (k - 1.0) * v;
                *s *= 1.0 + (k - 1.0) * v;
            }
            return Some(InputNoise {
                h1_bias: 2.0 * k * a,
                corrected: true,
                measured: true,
            });
        }
        if self.estimator != Some(Estimator::H1)
            || self.weighting != FrfWeighting::Coherence
            || self.averages < 2
            // NaN compares false: not significant.
            || a.partial_cmp(&(SIGNIFICANT * noise.force_standard_error))
                != Some(std::cmp::Ordering::Greater)
        {
            return None;
        }
        // The force's part of the mean (1 − γ̂²)/γ̂² = 2K·q/|H|²: H1's relative bias.
        let h1_bias = 2.0 * self.averages as f64 * a;
        // Leakage (any window but a rectangular one over whole periods, or an
        // exponential one) lowers the coherence at the resonance much as force noise does.
        if self.correlated_lines != 1.0 || self.exponential_decay.is_some() {
            return Some(InputNoise {
                h1_bias,
                corrected: false,
                measured: false,
            });
        }
        for h in &mut self.h {
            *h *= 1.0 + h1_bias;
        }
        for s in &mut self.sigma {
            *s *= 1.0 + h1_bias;
        }
        Some(InputNoise {
            h1_bias,
            corrected: true,
            measured: false,
        })
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::TAU;

    use crate::lines::{FrfWeighting, prepare};
    use msd_signal::{Complex64, Estimator, FrequencyResponseEstimate};

    /// One mode's receptance (m 1 kg, fn 1 Hz, ζ 5 %).
    fn mode(f: f64) -> Complex64 {
        let w = std::f64::consts::TAU * f;
        let wn = std::f64::consts::TAU;
        1.0 / Complex64::new(wn * wn - w * w, 2.0 * 0.05 * wn * w)
    }

    /// An H1 estimate whose every line's coherence is what white noise on the force
    /// (ν = N_x/S_uu) and on the response (μ) give, (1 − γ²)/γ² = ν + μ/|H|², and whose
    /// lines are low by 1/(1 + ν): the correction finds ν and restores H.
    #[test]
    fn an_exact_coherence_gives_the_force_noise_and_h_back() {
        let (nu, mu, k) = (0.004, 2e-6, 8);
        let f: Vec<f64> = (1..=80).map(|i| 0.025 * f64::from(i)).collect();
        let h: Vec<Complex64> = f.iter().map(|&f| mode(f) / (1.0 + nu)).collect();
        let mut frf = FrequencyResponseEstimate::new(f.clone(), h).unwrap();
        frf.coherence = f
            .iter()
            .map(|&f| 1.0 / (1.0 + nu + mu / mode(f).norm_sqr()))
            .collect();
        frf.averages = k;
        frf.estimator = Some(Estimator::H1);
        let lines = |frf: &FrequencyResponseEstimate| {
            let mut l = prepare(frf, None, FrfWeighting::Coherence, 4).unwrap();
            // The coherence's q is of the biased lines: the model's |H| is of them too.
            l.smooth_coherence_weights(|w| mode(w / std::f64::consts::TAU) / (1.0 + nu));
            l
        };
        let mut l = lines(&frf);
        let found = l.correct_input_noise().expect("the force's noise is found");
        assert!((found.h1_bias / nu - 1.0).abs() < 1e-6, "{found:?}");
        for (w, h) in l.omega.iter().zip(&l.h) {
            let truth = mode(w / std::f64::consts::TAU);
            assert!((h / truth - 1.0).norm() < nu * nu, "{h} against {truth}");
        }
        // Under a Hann window (leakage) the bias is said, the lines left as they are.
        frf.noise_bandwidth = 1.5;
        let mut l = lines(&frf);
        let before = l.h.clone();
        let said = l.correct_input_noise().expect("said");
        assert!(!said.corrected && (said.h1_bias / nu - 1.0).abs() < 1e-6);
        assert_eq!(l.h, before);
        assert!(said.to_string().starts_with("warning: "));
        frf.noise_bandwidth = 1.0;
        // Another estimator, or a table, is left as it is.
        for estimator in [Some(Estimator::H2), Some(Estimator::Hv), None] {
            frf.estimator = estimator;
            assert_eq!(lines(&frf).correct_input_noise(), None);
        }
    }

    /// A measured force noise v_k that varies over the band (a hammer's spectrum falls
    /// off) and a coherence that shows it and the response's noise b exactly: the weights
    /// take a_k = (K − 1)/(2K)·v_k·c_k² as given (c_k = 1 + (K − 1)·v_k, the lines low by
    /// it while the force's noise scatters about the true H) and b back, each line's
    /// variance is v_k/2·c_k²·|Ĥ|² + K/(K − 1)·b·u_k, and H1 is raised line by line by c_k.
    #[test]
    fn a_measured_force_noise_is_taken_line_by_line() {
        let (b, k) = (3e-7, 5usize);
        let kf = k as f64;
        let f: Vec<f64> = (1..=80).map(|i| 0.025 * f64::from(i)).collect();
        let v: Vec<f64> = f.iter().map(|f| 1e-4 * (1.0 + 2.0 * f)).collect();
        let biased = |i: usize| mode(f[i]) / (1.0 + (kf - 1.0) * v[i]);
        let h: Vec<Complex64> = (0..f.len()).map(biased).collect();
        let mut frf = FrequencyResponseEstimate::new(f.clone(), h).unwrap();
        let c = |i: usize| 1.0 + (kf - 1.0) * v[i];
        frf.coherence = (0..f.len())
            .map(|i| {
                1.0 / (1.0 + (kf - 1.0) * v[i] * c(i).powi(2) + 2.0 * kf * b / biased(i).norm_sqr())
            })
            .collect();
        frf.averages = k;
        frf.estimator = Some(Estimator::H1);
        frf.noise_bandwidth = 3.0;
        frf.exponential_decay = Some(2.0);
        frf.input_noise_variance = Some(v.clone());
        let mut l = prepare(&frf, None, FrfWeighting::Coherence, 4).unwrap();
        let lookup = |w: f64| f.iter().position(|f| (TAU * f - w).abs() < 1e-9).unwrap();
        assert!(l.smooth_coherence_weights(|w| biased(lookup(w))));
        let noise = l.noise_model.expect("fitted");
        assert!(noise.force_measured && (noise.response / b - 1.0).abs() < 1e-9);
        for (i, s) in l.sigma.iter().enumerate() {
            let m = biased(i).norm_sqr();
            let expected = v[i] / 2.0 * c(i).powi(2) * m + kf / (kf - 1.0) * b;
            assert!((s * s / expected - 1.0).abs() < 1e-9, "line {i}");
        }
        let found = l.correct_input_noise().expect("measured");
        assert!(found.corrected && found.measured, "{found:?}");
        assert!(found.to_string().contains("measured on the force channel"));
        for (i, h) in l.h.iter().enumerate() {
            assert!((h / mode(f[i]) - 1.0).norm() < 1e-12, "line {i}: {h}");
        }
    }
}
