//! Frequency responses measured line by line (a stepped-sine sweep: one line per
//! excitation frequency), variances, and conversion between response quantities.

use std::f64::consts::TAU;

use rustfft::num_complex::Complex64;

use super::correlation::LineCorrelation;
use super::{FrequencyResponseEstimate, FrfKind};
use crate::error::{Result, SignalError, check_data, same_length};

impl FrequencyResponseEstimate {
    /// A measured frequency response: complex values `h` at the `frequency` lines (Hz,
    /// finite, ≥ 0, strictly increasing, not necessarily evenly spaced); coherence 1,
    /// one average, receptance (set [`kind`](Self::kind) for another quantity), no
    /// variances (see [`with_variance`](Self::with_variance)).
    ///
    /// Errors on empty or non-finite data, frequencies that are negative or do not
    /// increase ([`SignalError::NonIncreasingFrequency`]), and lengths that differ.
    ///
    /// ```
    /// use msd_signal::{Complex64, FrequencyResponseEstimate, SignalError};
    /// let frf = FrequencyResponseEstimate::new(vec![1.0, 2.0], vec![Complex64::new(1.0, -1.0); 2])?;
    /// assert_eq!((frf.averages, frf.coherence.clone()), (1, vec![1.0, 1.0]));
    /// let err = FrequencyResponseEstimate::new(vec![2.0, 2.0], vec![Complex64::new(1.0, 0.0); 2]);
    /// assert!(matches!(err, Err(SignalError::NonIncreasingFrequency { index: 1, .. })));
    /// # Ok::<(), SignalError>(())
    /// ```
    pub fn new(frequency: Vec<f64>, h: Vec<Complex64>) -> Result<Self> {
        check_frequencies(&frequency)?;
        if frequency.len() != h.len() {
            return Err(SignalError::LengthMismatch {
                left: "frequency",
                left_len: frequency.len(),
                right: "h",
                right_len: h.len(),
            });
        }
        if let Some((index, bad)) = h
            .iter()
            .enumerate()
            .find(|(_, v)| !(v.re.is_finite() && v.im.is_finite()))
        {
            let value = if bad.re.is_finite() { bad.im } else { bad.re };
            return Err(SignalError::NonFinite {
                name: "h",
                index,
                value,
            });
        }
        let lines = frequency.len();
        Ok(Self {
            frequency,
            h,
            coherence: vec![1.0; lines],
            averages: 1,
            kind: FrfKind::Receptance,
            variance: None,
            exponential_decay: None,
            noise_bandwidth: 1.0,
            estimator: None,
            line_correlation: LineCorrelation::default(),
            input_noise_variance: None,
        })
    }

    /// A measured frequency response from a table of magnitudes and phases (degrees),
    /// as [`new`](Self::new); magnitudes must be ≥ 0.
    ///
    /// ```
    /// use msd_signal::FrequencyResponseEstimate;
    /// let frf = FrequencyResponseEstimate::from_magnitude_phase(&[0.5, 1.0], &[2.0, 1.0], &[0.0, -90.0])?;
    /// assert!((frf.h[1].im + 1.0).abs() < 1e-15 && frf.h[1].re.abs() < 1e-15);
    /// # Ok::<(), msd_signal::SignalError>(())
    /// ```
    pub fn from_magnitude_phase(
        frequency: &[f64],
        magnitude: &[f64],
        phase_deg: &[f64],
    ) -> Result<Self> {
        check_data("magnitude", magnitude)?;
        check_data("phase", phase_deg)?;
        same_length("magnitude", magnitude, "phase", phase_deg)?;
        if let Some((index, &value)) = magnitude.iter().enumerate().find(|(_, m)| **m < 0.0) {
            return Err(SignalError::InvalidParameter {
                parameter: format!("magnitude[{index}]"),
                value,
                expected: "a magnitude >= 0",
            });
        }
        let h = magnitude
            .iter()
            .zip(phase_deg)
            .map(|(&m, &p)| Complex64::from_polar(m, p.to_radians()))
            .collect();
        Self::new(frequency.to_vec(), h)
    }

    /// A measured frequency response from a table of real and imaginary parts, as
    /// [`new`](Self::new).
    ///
    /// ```
    /// use msd_signal::FrequencyResponseEstimate;
    /// let frf = FrequencyResponseEstimate::from_real_imaginary(&[1.0, 3.0], &[1.0, 0.0], &[0.0, -2.0])?;
    /// assert_eq!(frf.h[1].im, -2.0);
    /// # Ok::<(), msd_signal::SignalError>(())
    /// ```
    pub fn from_real_imaginary(frequency: &[f64], real: &[f64], imaginary: &[f64]) -> Result<Self> {
        check_data("real", real)?;
        check_data("imaginary", imaginary)?;
        same_length("real", real, "imaginary", imaginary)?;
        let h = real
            .iter()
            .zip(imaginary)
            .map(|(&re, &im)| Complex64::new(re, im))
            .collect();
        Self::new(frequency.to_vec(), h)
    }

    /// The same response with the variances E|Ĥ − H|² of its lines (finite, > 0, one
    /// per line), for a fit weighted by them.
    ///
    /// ```
    /// use msd_signal::FrequencyResponseEstimate;
    /// let frf = FrequencyResponseEstimate::from_real_imaginary(&[1.0], &[1.0], &[0.0])?;
    /// assert!(frf.clone().with_variance(vec![0.0]).is_err());
    /// assert_eq!(frf.with_variance(vec![1e-4])?.variance, Some(vec![1e-4]));
    /// # Ok::<(), msd_signal::SignalError>(())
    /// ```
    pub fn with_variance(mut self, variance: Vec<f64>) -> Result<Self> {
        check_data("variance", &variance)?;
        if variance.len() != self.h.len() {
            return Err(SignalError::LengthMismatch {
                left: "variance",
                left_len: variance.len(),
                right: "h",
                right_len: self.h.len(),
            });
        }
        if let Some((index, &value)) = variance.iter().enumerate().find(|(_, v)| **v <= 0.0) {
            return Err(SignalError::InvalidParameter {
                parameter: format!("variance[{index}]"),
                value,
                expected: "a variance > 0",
            });
        }
        self.variance = Some(variance);
        Ok(self)
    }

    /// The response as another quantity: multiplied by (jω)^p with p the difference of
    /// the powers (receptance 0, mobility 1, accelerance 2), the variances by ω^(2p).
    /// A line at 0 Hz that would be divided by zero becomes 0 with coherence 0 and
    /// infinite variance: it carries no information.
    ///
    /// ```
    /// use msd_signal::{Complex64, FrequencyResponseEstimate, FrfKind};
    /// let receptance = FrequencyResponseEstimate::new(vec![0.0, 1.0 / std::f64::consts::TAU],
    ///     vec![Complex64::new(2.0, 0.0); 2])?; // ω = 0 and 1 rad/s
    /// let accelerance = receptance.to_kind(FrfKind::Accelerance);
    /// assert_eq!(accelerance.h[1], Complex64::new(-2.0, 0.0));
    /// let back = accelerance.to_kind(FrfKind::Receptance);
    /// assert_eq!((back.h[0], back.coherence[0]), (Complex64::new(0.0, 0.0), 0.0));
    /// assert!((back.h[1] - receptance.h[1]).norm() < 1e-15);
    /// # Ok::<(), msd_signal::SignalError>(())
    /// ```
    pub fn to_kind(&self, kind: FrfKind) -> Self {
        let p = kind.power() - self.kind.power();
        let mut out = self.clone();
        out.kind = kind;
        for (k, &f) in self.frequency.iter().enumerate() {
            let omega = TAU * f;
            if p < 0 && omega == 0.0 {
                out.h[k] = Complex64::new(0.0, 0.0);
                out.coherence[k] = 0.0;
                if let Some(v) = &mut out.variance {
                    v[k] = f64::INFINITY;
                }
                continue;
            }
            out.h[k] *= Complex64::new(0.0, omega).powi(p);
            if let Some(v) = &mut out.variance {
                v[k] *= omega.powi(2 * p);
            }
        }
        out
    }

    /// Whether the coherence says something about the lines above 0 Hz within
    /// `[low, high]` Hz: averaged over K ≠ 1 segments (0: a table's coherence over an
    /// unknown count) and below 1 on one of them, so that it can weight the lines.
    ///
    /// ```
    /// use msd_signal::{Complex64, FrequencyResponseEstimate};
    /// let mut frf = FrequencyResponseEstimate::new(vec![1.0, 2.0], vec![Complex64::new(1.0, 0.0); 2])?;
    /// assert!(!frf.has_coherence_in([0.0, f64::INFINITY])); // a table: γ² = 1
    /// (frf.coherence[1], frf.averages) = (0.5, 0);
    /// assert!(frf.has_coherence_in([0.0, f64::INFINITY]) && !frf.has_coherence_in([0.0, 1.5]));
    /// # Ok::<(), msd_signal::SignalError>(())
    /// ```
    pub fn has_coherence_in(&self, [low, high]: [f64; 2]) -> bool {
        self.averages != 1
            && (self.frequency.iter().zip(&self.coherence))
                .any(|(&f, &g)| f > 0.0 && f >= low && f <= high && g < 1.0 - 1e-6)
    }

    /// The complex conjugate of the response, in its own quantity: a frequency response
    /// written with the other phase convention (e^(−jωt), or H = S_xy/S_xx with MATLAB's
    /// `cpsd(x, y)` = X·conj(Y)), whose phase rises through a resonance, back to the
    /// convention every fit here assumes (H = S_yx/S_xx, phase falling through a
    /// resonance). Coherence and variances are unchanged.
    ///
    /// ```
    /// use msd_signal::{Complex64, FrequencyResponseEstimate};
    /// let frf = FrequencyResponseEstimate::new(vec![1.0], vec![Complex64::new(1.0, -2.0)])?;
    /// assert_eq!(frf.conjugate().h[0], Complex64::new(1.0, 2.0));
    /// # Ok::<(), msd_signal::SignalError>(())
    /// ```
    pub fn conjugate(&self) -> Self {
        let mut out = self.clone();
        out.h.iter_mut().for_each(|h| *h = h.conj());
        out
    }

    /// The damping ratio the exponential window added to a mode of natural frequency
    /// `natural_frequency_hz`, to first order: ζ_added = 1/(ωn·τ) (0 without the window).
    ///
    /// ```
    /// use msd_signal::{Complex64, FrequencyResponseEstimate};
    /// let mut frf = FrequencyResponseEstimate::new(vec![1.0], vec![Complex64::new(1.0, 0.0)])?;
    /// assert_eq!(frf.added_damping_ratio(2.0), 0.0);
    /// frf.exponential_decay = Some(0.5);
    /// assert_eq!(frf.added_damping_ratio(1.0 / std::f64::consts::TAU), 2.0);
    /// # Ok::<(), msd_signal::SignalError>(())
    /// ```
    pub fn added_damping_ratio(&self, natural_frequency_hz: f64) -> f64 {
        self.exponential_decay
            .map_or(0.0, |tau| 1.0 / (TAU * natural_frequency_hz * tau))
    }
}

/// Frequencies: non-empty, finite, ≥ 0 and strictly increasing.
fn check_frequencies(frequency: &[f64]) -> Result<()> {
    check_data("frequency", frequency)?;
    if frequency[0] < 0.0 {
        return Err(SignalError::InvalidParameter {
            parameter: "frequency[0]".into(),
            value: frequency[0],
            expected: "a frequency >= 0 Hz",
        });
    }
    match frequency.windows(2).position(|w| w[1] <= w[0]) {
        Some(i) => Err(SignalError::NonIncreasingFrequency {
            index: i + 1,
            previous: frequency[i],
            current: frequency[i + 1],
        }),
        None => Ok(()),
    }
}
