//! Frequency responses from time records: the H1, H2 and Hv estimators with the
//! ordinary coherence, averaged over records and Welch segments; the windows of an
//! impact test; receptance, mobility and accelerance.
//!
//! ## The estimators
//! From the averaged auto and cross spectra S_xx, S_yy and S_xy = E[conj(X)·Y] of the
//! input x (force) and the output y (response) (see [`spectral`](crate::spectral)):
//!
//! | estimator | formula | unbiased when the noise is on |
//! |---|---|---|
//! | [`Estimator::H1`] | S_xy / S_xx | the output only (input noise biases it low) |
//! | [`Estimator::H2`] | S_yy / S_yx | the input only (output noise biases it high) |
//! | [`Estimator::Hv`] | (S_yy − S_xx + √((S_xx − S_yy)² + 4·\|S_xy\|²)) / (2·S_yx) | both, equally (total least squares) |
//!
//! with S_yx = conj(S_xy) (Bendat & Piersol, "Random Data", 4th ed., §9.2; Rocklin,
//! Crowley & Vold 1985 for Hv). |H1| ≤ |Hv| ≤ |H2|, and H1/H2 = γ², the ordinary
//! coherence γ² = |S_xy|²/(S_xx·S_yy), which is reported with every estimator. Hv
//! weighs the noise of both channels in their own units: scale the records so that
//! their noise levels are comparable before using it.
//!
//! ## Averaging and windows
//! Every record is cut into Welch segments ([`WelchOptions`]); the spectra are averaged
//! over all segments of all records. Random excitation takes the Hann window (the
//! default). An impact test ([`ImpactWindows`]) takes each record (one hit) whole and
//! undetrended (a hit's force has a mean), with
//! - a *force window* on the hammer channel: 1 for the first `force_width` seconds of
//!   the record (pre-trigger and pulse), 0 after, which removes the force channel's
//!   noise after the hit;
//!   that noise, measured there ([`force_channel_noise`]), is the noise the window
//!   keeps under the pulse: it gives each line's share of H's error from the force
//!   ([`FrequencyResponseEstimate::input_noise_variance`]), which the coherence alone
//!   confounds with the response's noise;
//! - an *exponential window* w(t) = e^(−t/τ), t from the start of the record, on the
//!   response, so that a response that has not died out by the end of the record does
//!   not leak. The same exponential multiplies the force channel too (where it is ≈ 1
//!   over the short pulse): then Y_w(s) = Y(s + 1/τ) and X_w(s) = X(s + 1/τ), so the
//!   windowed estimate is exactly H(s + 1/τ), every pole moved left by 1/τ, wherever the
//!   hit lies in the record (Fladung & Rost, "Application and correction of the
//!   exponential window for frequency response functions", MSSP 11, 1997). A mode of
//!   natural frequency ωn appears with the damping ratio raised by about
//!   ζ_added = 1/(ωn·τ); [`FrequencyResponseEstimate::exponential_decay`] records τ so
//!   that a fit can take it off again ([`FrequencyResponseEstimate::added_damping_ratio`]).
//!
//! ## Response quantities
//! The output is a displacement, a velocity or an acceleration per unit force:
//! receptance, mobility or accelerance ([`FrfKind`]), H_mobility = jω·H_receptance,
//! H_accelerance = −ω²·H_receptance; [`FrequencyResponseEstimate::to_kind`] converts.
//!
//! ```
//! use msd_signal::{frf_estimate, gaussian_noise, Estimator, FrfOptions, Record, WelchOptions};
//! // y = 3·u exactly, five records of white noise: H = 3, γ² = 1.
//! let inputs: Vec<Vec<f64>> = (0..5)
//!     .map(|i| gaussian_noise(i, "force", 1.0, 1024))
//!     .collect::<Result<_, _>>()?;
//! let outputs: Vec<Vec<f64>> = inputs.iter().map(|u| u.iter().map(|v| 3.0 * v).collect()).collect();
//! let records: Vec<Record<'_>> = inputs.iter().zip(&outputs)
//!     .map(|(input, output)| Record { input, output })
//!     .collect();
//! let options = FrfOptions {
//!     estimator: Estimator::Hv,
//!     welch: WelchOptions { segment_length: Some(256), ..WelchOptions::default() },
//!     ..FrfOptions::default()
//! };
//! let frf = frf_estimate(&records, 100.0, &options)?;
//! assert_eq!(frf.averages, 5 * 7); // 7 half-overlapping segments of 256 in 1024
//! assert!(frf.h[1..].iter().all(|h| (h.re - 3.0).abs() < 1e-9 && h.im.abs() < 1e-9));
//! assert!(frf.coherence[1..].iter().all(|g| (g - 1.0).abs() < 1e-9));
//! # Ok::<(), msd_signal::SignalError>(())
//! ```

pub(crate) mod correlation;
mod table;

pub use correlation::LineCorrelation;

use rustfft::num_complex::Complex64;
use serde::{Deserialize, Serialize};

use crate::error::{Result, SignalError, check_data, positive, same_length};
use crate::spectral::{
    Detrend, Segmenting, Welch, WelchOptions, Window, coherence_of, segment_step, welch_records,
};

/// Which frequency-response estimator to use (see the [module docs](self)).
///
/// ```
/// use msd_signal::{Estimator, FrfOptions};
/// let options: FrfOptions = toml::from_str(r#"estimator = "Hv""#)?;
/// assert_eq!(options.estimator, Estimator::Hv);
/// assert_eq!(FrfOptions::default().estimator, Estimator::H1);
/// # Ok::<(), toml::de::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Estimator {
    /// S_xy/S_xx: noise on the output only. The default (the usual choice: the force is
    /// measured well and the response is noisy).
    #[default]
    H1,
    /// S_yy/S_yx: noise on the input only (near a resonance, where the force is small).
    H2,
    /// Total least squares between H1 and H2: noise on both channels.
    Hv,
}

/// What the output measures per unit input: the name of the frequency response.
///
/// In TOML also by the response quantity: `"displacement"`, `"velocity"` or
/// `"acceleration"`.
///
/// ```
/// use msd_signal::{FrfKind, FrfOptions};
/// let options: FrfOptions = toml::from_str(r#"kind = "acceleration""#)?;
/// assert_eq!(options.kind, FrfKind::Accelerance);
/// assert_eq!(options.kind.to_string(), "accelerance (acceleration per force)");
/// # Ok::<(), toml::de::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrfKind {
    /// Displacement per force (dynamic compliance). The default.
    #[default]
    #[serde(alias = "displacement")]
    Receptance,
    /// Velocity per force (mobility): jω × receptance.
    #[serde(alias = "velocity")]
    Mobility,
    /// Acceleration per force (inertance): −ω² × receptance.
    #[serde(alias = "acceleration")]
    Accelerance,
}

impl FrfKind {
    /// The power p of jω in H = (jω)^p × receptance.
    ///
    /// ```
    /// use msd_signal::FrfKind;
    /// assert_eq!(FrfKind::Accelerance.power(), 2);
    /// ```
    pub fn power(self) -> i32 {
        match self {
            FrfKind::Receptance => 0,
            FrfKind::Mobility => 1,
            FrfKind::Accelerance => 2,
        }
    }
}

impl std::fmt::Display for FrfKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            FrfKind::Receptance => "receptance (displacement per force)",
            FrfKind::Mobility => "mobility (velocity per force)",
            FrfKind::Accelerance => "accelerance (acceleration per force)",
        })
    }
}

/// The windows of an impact test (see the [module docs](self)): a force window on the
/// hammer channel and an exponential window on both (in TOML: a table with any of these
/// fields).
///
/// ```
/// use msd_signal::ImpactWindows;
/// let windows = ImpactWindows { decay_time: Some(0.5), ..ImpactWindows::default() };
/// windows.validate()?;
/// assert!(ImpactWindows { force_width: Some(-1.0), ..windows }.validate().is_err());
/// # Ok::<(), msd_signal::SignalError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ImpactWindows {
    /// Seconds from the start of each record during which the force is kept (pre-trigger
    /// and pulse); `None` = the first tenth of the record. By default `None`.
    pub force_width: Option<f64>,
    /// Decay time τ of the exponential window e^(−t/τ) in seconds; `None` = a quarter of
    /// the record, so the window ends at e^(−4) ≈ 1.8 %. By default `None`.
    pub decay_time: Option<f64>,
}

impl ImpactWindows {
    /// Checks that the times given are finite and positive.
    pub fn validate(&self) -> Result<()> {
        if let Some(w) = self.force_width {
            positive(|| "impact.force_width".into(), w)?;
        }
        if let Some(tau) = self.decay_time {
            positive(|| "impact.decay_time".into(), tau)?;
        }
        Ok(())
    }

    /// The two windows for records of `l` samples at `fs` Hz, and τ.
    fn coefficients(&self, l: usize, fs: f64) -> (Vec<f64>, Vec<f64>, f64) {
        let seconds = l as f64 / fs;
        let tau = self.decay_time.unwrap_or(seconds / 4.0);
        let exponential: Vec<f64> = (0..l).map(|i| (-(i as f64) / fs / tau).exp()).collect();
        let cut = self.first_cut(l, fs);
        let force = exponential
            .iter()
            .enumerate()
            .map(|(i, e)| if i < cut { *e } else { 0.0 })
            .collect();
        (force, exponential, tau)
    }

    /// The first sample the force window sets to 0 in records of `l` samples at `fs` Hz
    /// (samples at t ≤ the width are kept).
    fn first_cut(&self, l: usize, fs: f64) -> usize {
        let width = self.force_width.unwrap_or(l as f64 / fs / 10.0);
        (0..l).find(|&i| i as f64 / fs > width).unwrap_or(l)
    }
}

/// Options of [`frf_estimate`] (in TOML: a table with any of these fields; missing ones
/// take their defaults, unknown ones are rejected).
///
/// ```
/// use msd_signal::{FrfOptions, FrfKind, ImpactWindows, Window};
/// let random: FrfOptions = toml::from_str("welch = { segment_length = 1024 }")?;
/// assert_eq!((random.welch.segment_length, random.welch.window), (Some(1024), Window::Auto));
/// let hammer: FrfOptions = toml::from_str("kind = \"acceleration\"\nimpact = { decay_time = 0.5 }")?;
/// assert_eq!(hammer.kind, FrfKind::Accelerance);
/// assert_eq!(hammer.impact, Some(ImpactWindows { force_width: None, decay_time: Some(0.5) }));
/// # Ok::<(), toml::de::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FrfOptions {
    /// The estimator. By default [`Estimator::H1`].
    pub estimator: Estimator,
    /// How each record is segmented, windowed and detrended. By default
    /// [`WelchOptions::default()`]: each record whole, Hann, mean removed.
    pub welch: WelchOptions,
    /// Impact-test windows; when given, each record is one segment, not detrended, and
    /// `welch.window` is not used (`welch.segment_length` must then be `None`).
    /// By default `None`.
    pub impact: Option<ImpactWindows>,
    /// What the output measures. By default [`FrfKind::Receptance`].
    pub kind: FrfKind,
}

impl FrfOptions {
    /// Checks the Welch options, the impact windows and that they are not both asked
    /// to cut the records.
    pub fn validate(&self) -> Result<()> {
        self.welch.validate()?;
        if let Some(impact) = &self.impact {
            impact.validate()?;
            if let Some(l) = self.welch.segment_length {
                return Err(SignalError::InvalidParameter {
                    parameter: "welch.segment_length".into(),
                    value: l as f64,
                    expected: "none with impact windows (each hit is one record)",
                });
            }
        }
        Ok(())
    }
}

/// One record pair: the input (force) and the output (response), of equal length.
///
/// ```
/// use msd_signal::Record;
/// let (force, response) = (vec![0.0, 1.0, 0.0], vec![0.0, 0.5, 0.25]);
/// let record = Record { input: &force, output: &response };
/// assert_eq!(record.output[1], 0.5);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Record<'a> {
    /// Input samples.
    pub input: &'a [f64],
    /// Output samples.
    pub output: &'a [f64],
}

/// A frequency response with its coherence: estimated from time records
/// ([`frf_estimate`], [`h1_estimate`](crate::spectral::h1_estimate)) or measured line by line
/// ([`from_magnitude_phase`](Self::from_magnitude_phase),
/// [`from_real_imaginary`](Self::from_real_imaginary)).
///
/// ```
/// use msd_signal::{FrequencyResponseEstimate, FrfKind};
/// // A stepped-sine sweep exported as magnitude and phase, mobility (velocity per force).
/// let mut sweep = FrequencyResponseEstimate::from_magnitude_phase(
///     &[1.0, 1.5, 2.0], &[0.01, 0.05, 0.02], &[80.0, 0.0, -75.0])?;
/// sweep.kind = FrfKind::Mobility;
/// let receptance = sweep.to_kind(FrfKind::Receptance);
/// assert!((receptance.h[1].norm() - 0.05 / (std::f64::consts::TAU * 1.5)).abs() < 1e-15);
/// assert_eq!((sweep.averages, sweep.noise_bandwidth), (1, 1.0));
/// # Ok::<(), msd_signal::SignalError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct FrequencyResponseEstimate {
    /// Frequencies in Hz, increasing.
    pub frequency: Vec<f64>,
    /// The response (output units per input unit). From records: 0 where the input has
    /// no power, where it is undefined (S_xx below 1e-12 of its maximum for
    /// [`frf_estimate`], [`UNEXCITED`]; 1e-24 for [`h1_estimate`](crate::spectral::h1_estimate)).
    pub h: Vec<Complex64>,
    /// γ² = |S_xy|²/(S_xx·S_yy) in [0, 1]; identically 1 with one segment or for a
    /// measured table; 0 where the input or output has no power.
    pub coherence: Vec<f64>,
    /// Number of averaged segments K (1 for a measured table without coherence; 0 when
    /// not known: a measured table's coherence without its count of averages).
    pub averages: usize,
    /// What the response measures. Receptance unless set.
    pub kind: FrfKind,
    /// Variances E|Ĥ − H|² of the lines, when known (a measured table may give them).
    pub variance: Option<Vec<f64>>,
    /// Decay time τ (s) of an exponential window on both channels, if one was applied:
    /// the response is then H(s + 1/τ).
    pub exponential_decay: Option<f64>,
    /// The equivalent noise bandwidth of the output's window in lines, L·Σw²/(Σw)²
    /// (1 rectangular, 1.5 Hann, about T/(2τ) exponential): the errors of about this many
    /// neighbouring lines are correlated, so the lines hold that many times fewer
    /// independent values. 1 for a measured table.
    pub noise_bandwidth: f64,
    /// The estimator that formed `h` from the spectra; `None` for a measured table.
    /// A fit that finds the force's noise in the coherence corrects an H1 for it.
    pub estimator: Option<Estimator>,
    /// How the errors of neighbouring lines are correlated by the windows (empty for a
    /// measured table: independent lines as far as is known).
    pub line_correlation: LineCorrelation,
    /// Per line, the variance of the response's relative error that the input's noise
    /// makes, v_k = E|ΔĤ_k|²/|H_k|² = N_x/(K·S_xx,k) (N_x the input noise's one-sided
    /// density in the spectra's scale), where that noise was measured: an impact test's
    /// force channel after the force window holds nothing but its noise
    /// ([`force_channel_noise`]). H1 is then low by K·v_k at line k. 0 at unexcited
    /// lines; `None` where not measured (random excitation, a table, a force channel
    /// without noise after the window — a record exported already windowed).
    pub input_noise_variance: Option<Vec<f64>>,
}

/// The input power, relative to its largest line, below which [`frf_estimate`] counts a
/// line as unexcited: its response 0 and its coherence 0, so that a fit leaves it out.
/// A periodic input (a multisine over whole periods) leaves the lines between its own
/// with rounding-level power (1e-26 of the largest and below), whose ratio of two
/// roundings is no response; 1e-12 (−120 dB) is below any measured broadband input's
/// dynamic range.
pub const UNEXCITED: f64 = 1e-12;

/// The share of the inputs' power, ‖Σᵣ xᵣ‖²/(R·Σᵣ‖xᵣ‖²) over R ≥ 2 whole records (means
/// removed), at and above which [`Window::Auto`] takes the input to repeat from record to
/// record: 1 for a periodic force whose period divides the record (the records are the
/// same), 1/(1 + s²) with force noise s (0.99 at s = 0.1), about 1/R for an input that
/// does not repeat (random, or a period the record does not hold whole). The records then
/// hold whole periods, whose lines a rectangular window keeps apart and a Hann window
/// would smear into the lines between them.
pub const REPEATING: f64 = 0.9;

/// The frequency response from `records` sampled at `fs` Hz, averaged over every
/// segment of every record, with the coherence.
///
/// Errors on bad options or `fs`, no records, empty or non-finite data, records of
/// different lengths ([`SignalError::RecordLength`]; input and output of a record:
/// [`SignalError::LengthMismatch`]), a segment longer than the records, and with
/// [`SignalError::ZeroInputPower`] when the input has no power.
///
/// ```
/// use msd_signal::{frf_estimate, FrfOptions, ImpactWindows, Record};
/// // A hit on a pure gain of 2 (output = 2·force): every window cancels in the ratio.
/// let force: Vec<f64> = (0..200).map(|i| if (5..8).contains(&i) { 10.0 } else { 0.0 }).collect();
/// let response: Vec<f64> = force.iter().map(|f| 2.0 * f).collect();
/// let options = FrfOptions { impact: Some(ImpactWindows::default()), ..FrfOptions::default() };
/// let frf = frf_estimate(&[Record { input: &force, output: &response }], 100.0, &options)?;
/// assert_eq!(frf.exponential_decay, Some(0.5)); // a quarter of the 2 s record
/// assert!(frf.h.iter().all(|h| (h.re - 2.0).abs() < 1e-12 && h.im.abs() < 1e-12));
/// # Ok::<(), msd_signal::SignalError>(())
/// ```
pub fn frf_estimate(
    records: &[Record<'_>],
    fs: f64,
    options: &FrfOptions,
) -> Result<FrequencyResponseEstimate> {
    options.validate()?;
    positive(|| "fs".into(), fs)?;
    let n = check_records(records)?;
    // A force that never varies has no power at any line (its mean, or DC, aside). Its
    // spectrum after the paired transform would be rounding, 1e-32 of the response's,
    // and H1 of the order of 1e16 with coherence 1.
    if records
        .iter()
        .all(|r| r.input.iter().all(|&x| x == r.input[0]))
    {
        return Err(SignalError::ZeroInputPower { name: "input" });
    }
    let l = options.welch.segment_length.unwrap_or(n);
    if l > n {
        return Err(SignalError::WindowTooLong { window: l, len: n });
    }
    let pairs: Vec<(&[f64], Option<&[f64]>)> =
        records.iter().map(|r| (r.input, Some(r.output))).collect();
    let (welch, decay, noise) = match &options.impact {
        Some(impact) => {
            let (force, exponential, tau) = impact.coefficients(l, fs);
            let segmenting = Segmenting {
                length: l,
                step: l,
                input_window: &force,
                output_window: &exponential,
                detrend: Detrend::None,
            };
            let welch = welch_records(&pairs, fs, &segmenting);
            let sigma = force_channel_noise(records, impact.first_cut(l, fs));
            let noise = sigma.map(|sigma| input_noise_variance(&welch, l, fs, sigma));
            (welch, Some(tau), noise)
        }
        None => {
            let window = resolve_window(options.welch.window, records, l).coefficients(l);
            let segmenting = Segmenting {
                length: l,
                step: segment_step(l, &options.welch),
                input_window: &window,
                output_window: &window,
                detrend: options.welch.detrend,
            };
            (welch_records(&pairs, fs, &segmenting), None, None)
        }
    };
    let mut frf = estimate_from(welch, options.estimator, UNEXCITED)?;
    frf.kind = options.kind;
    frf.exponential_decay = decay;
    frf.input_noise_variance = noise.map(|mut v| {
        v.truncate(frf.h.len());
        for (v, h) in v.iter_mut().zip(&frf.h) {
            if h.norm_sqr() == 0.0 {
                *v = 0.0;
            }
        }
        v
    });
    Ok(frf)
}

/// The fewest samples after the force windows from which [`force_channel_noise`]
/// takes the channel's noise.
const NOISE_SAMPLES: usize = 64;

/// The standard deviation of an impact test's force channel where the force window has
/// cut it off (samples `first` onward of every record): after the hit the channel
/// holds only its noise, the same noise the window keeps under the pulse. Robust: the
/// median absolute deviation of every record's samples from that record's median
/// (× 1.4826, the standard deviation of Gaussian noise), so that an offset, a second
/// touch of the hammer or a spike moves it little. `None` with fewer than
/// 64 samples or a deviation of 0 (a channel without noise there: a
/// record exported already windowed, or quantised flat).
///
/// ```
/// use msd_signal::{force_channel_noise, gaussian_noise, Record};
/// // A hit, then noise of 0.5 N on a 2 N offset, for 4000 samples.
/// let noise = gaussian_noise(3, "force", 0.5, 4096)?;
/// let force: Vec<f64> = (0..4096)
///     .map(|i| 2.0 + noise[i] + if (10..20).contains(&i) { 100.0 } else { 0.0 })
///     .collect();
/// let record = Record { input: &force, output: &force };
/// let sigma = force_channel_noise(&[record], 96).expect("measured");
/// assert!((sigma / 0.5 - 1.0).abs() < 0.06); // about 1.17/√(2·4000) relative
/// let flat = vec![0.0; 4096];
/// assert_eq!(force_channel_noise(&[Record { input: &flat, output: &flat }], 96), None);
/// # Ok::<(), msd_signal::SignalError>(())
/// ```
pub fn force_channel_noise(records: &[Record<'_>], first: usize) -> Option<f64> {
    let mut deviations = Vec::new();
    for r in records {
        let Some(tail) = r.input.get(first..) else {
            continue;
        };
        let median = median_of(tail.to_vec())?;
        deviations.extend(tail.iter().map(|x| (x - median).abs()));
    }
    if deviations.len() < NOISE_SAMPLES {
        return None;
    }
    let mad = median_of(deviations)?;
    (mad > 0.0).then_some(1.4826 * mad)
}

/// The median of `values` (`None` when empty).
fn median_of(mut values: Vec<f64>) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mid = values.len() / 2;
    let (_, m, _) = values.select_nth_unstable_by(mid, f64::total_cmp);
    Some(*m)
}

/// v_k = N_x/(K·S_xx,k) for input noise of standard deviation `sigma` at `fs` Hz:
/// N_x = (2 or 1)·σ²/fs, the one-sided density in the scale of `welch`'s spectra
/// (whose S_xx is (2 or 1)·Σ|X|²/(fs·Σw²·K) with the force window w), so that
/// v_k = σ²·Σw²/Σ|X_k|², the windowed noise's power over the hits' power.
fn input_noise_variance(welch: &Welch, l: usize, fs: f64, sigma: f64) -> Vec<f64> {
    let k = welch.averages as f64;
    (welch.sxx.iter().enumerate())
        .map(|(i, &sxx)| {
            let nyquist = l.is_multiple_of(2) && i == l / 2;
            let one_sided = if i == 0 || nyquist { 1.0 } else { 2.0 };
            let v = one_sided * sigma * sigma / (fs * k * sxx);
            if v.is_finite() { v } else { 0.0 }
        })
        .collect()
}

/// The window that [`Window::Auto`] stands for on these records cut into segments of
/// `l` samples (what [`frf_estimate`] uses); any other window as given.
///
/// ```
/// use msd_signal::{Record, Window, resolve_window};
/// // Two records of the same two periods of a sine: the input repeats.
/// let x: Vec<f64> = (0..64).map(|i| (std::f64::consts::TAU * i as f64 / 32.0).sin()).collect();
/// let y = x.clone();
/// let same = [Record { input: &x, output: &y }, Record { input: &x, output: &y }];
/// assert_eq!(resolve_window(Window::Auto, &same, 64), Window::Rectangular);
/// // One record, or segments shorter than the records: Hann.
/// assert_eq!(resolve_window(Window::Auto, &same[..1], 64), Window::Hann);
/// assert_eq!(resolve_window(Window::Auto, &same, 32), Window::Hann);
/// assert_eq!(resolve_window(Window::Hann, &same, 64), Window::Hann);
/// ```
pub fn resolve_window(window: Window, records: &[Record<'_>], l: usize) -> Window {
    let whole = records.len() >= 2 && records.iter().all(|r| r.input.len() == l);
    match window {
        Window::Auto if whole && repeating_share(records) >= REPEATING => Window::Rectangular,
        Window::Auto => Window::Hann,
        given => given,
    }
}

/// ‖Σᵣ xᵣ‖²/(R·Σᵣ‖xᵣ‖²) of the records' inputs, each with its mean removed (see
/// [`REPEATING`]); 0 for inputs without power.
fn repeating_share(records: &[Record<'_>]) -> f64 {
    let n = records[0].input.len();
    let means: Vec<f64> = records
        .iter()
        .map(|r| r.input.iter().sum::<f64>() / n as f64)
        .collect();
    let (mut sum_power, mut power) = (0.0, 0.0);
    for i in 0..n {
        let mut sum = 0.0;
        for (r, mean) in records.iter().zip(&means) {
            let x = r.input[i] - mean;
            sum += x;
            power += x * x;
        }
        sum_power += sum * sum;
    }
    if power > 0.0 {
        sum_power / (records.len() as f64 * power)
    } else {
        0.0
    }
}

/// Checks every record and returns their common length (at least 2).
fn check_records(records: &[Record<'_>]) -> Result<usize> {
    let first = records
        .first()
        .ok_or(SignalError::EmptyData { name: "records" })?;
    let n = first.input.len();
    for (index, r) in records.iter().enumerate() {
        check_data("input", r.input)?;
        check_data("output", r.output)?;
        same_length("input", r.input, "output", r.output)?;
        if r.input.len() != n {
            return Err(SignalError::RecordLength {
                index,
                len: r.input.len(),
                expected: n,
            });
        }
    }
    if n < 2 {
        return Err(SignalError::TooShort {
            name: "input",
            len: n,
            min: 2,
        });
    }
    Ok(n)
}

/// The estimate by `estimator` and the coherence at the lines of `w.sxy` (the first
/// lines of `w.sxx` and `w.syy`, whose largest values over all lines set the "no power"
/// levels).
pub(crate) fn estimate_from(
    w: Welch,
    estimator: Estimator,
    floor: f64,
) -> Result<FrequencyResponseEstimate> {
    let max_x = w.sxx.iter().fold(0.0f64, |m, &v| m.max(v));
    if max_x <= 0.0 {
        return Err(SignalError::ZeroInputPower { name: "input" });
    }
    let zero = Complex64::new(0.0, 0.0);
    let unexcited = |k: usize| w.sxx[k] <= floor * max_x;
    let h = (0..w.sxy.len())
        .map(|k| {
            let (sxx, syy, sxy) = (w.sxx[k], w.syy[k], w.sxy[k]);
            if unexcited(k) {
                return zero;
            }
            match estimator {
                Estimator::H1 => sxy / sxx,
                Estimator::H2 if sxy == zero => zero,
                Estimator::H2 => syy / sxy.conj(),
                Estimator::Hv if sxy == zero => zero,
                Estimator::Hv => hv_numerator(sxx, syy, sxy.norm_sqr()) / (sxy.conj() * 2.0),
            }
        })
        .collect();
    let mut coherence = coherence_of(&w);
    for (k, g) in coherence.iter_mut().enumerate() {
        if unexcited(k) {
            *g = 0.0;
        }
    }
    let mut frequency = w.frequency;
    frequency.truncate(w.sxy.len());
    Ok(FrequencyResponseEstimate {
        frequency,
        h,
        coherence,
        averages: w.averages,
        kind: FrfKind::Receptance,
        variance: None,
        exponential_decay: None,
        noise_bandwidth: w.noise_bandwidth,
        estimator: Some(estimator),
        line_correlation: w.line_correlation,
        input_noise_variance: None,
    })
}

/// d + √(d² + 4|S_xy|²) with d = S_yy − S_xx, without cancellation when d < 0
/// (= 4|S_xy|²/(√(…) − d) there).
fn hv_numerator(sxx: f64, syy: f64, sxy_sq: f64) -> f64 {
    let d = syy - sxx;
    let r = d.hypot(2.0 * sxy_sq.sqrt());
    if d >= 0.0 {
        d + r
    } else {
        4.0 * sxy_sq / (r - d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hv_numerator_is_stable_and_exact() {
        // d = 1 − 4 = −3, |S_xy|² = 4: d + √(9 + 16) = 2, and 16/(5 + 3) = 2.
        assert_eq!(hv_numerator(4.0, 1.0, 4.0), 2.0);
        assert_eq!(hv_numerator(1.0, 4.0, 4.0), 8.0);
        // Tiny output power (1e-12 of the input's): the naïve form loses every digit.
        let (sxx, syy, sxy_sq) = (1.0, 1e-12, 1e-12 * 0.5);
        let exact = 2.0 * sxy_sq / (sxx - syy); // to first order in sxy_sq/(sxx − syy)²
        assert!((hv_numerator(sxx, syy, sxy_sq) / exact - 1.0).abs() < 1e-11);
    }

    /// A periodic force (ten sines over 64 whole periods, one rectangular segment) with
    /// a trace of noise (1e-9 of its amplitude) on a gain of 2 with 1e-3 output noise:
    /// the lines between the sines' are unexcited (input power ~1e-18 of the largest),
    /// their response and coherence 0 — not the ratio of two noises (about 1e6 there
    /// before, with the 1e-24 floor) — and the excited lines give the gain.
    #[test]
    fn the_lines_between_a_periodic_forces_own_are_left_out() {
        let (periods, per_period) = (64usize, 128usize);
        let n = periods * per_period;
        let force_noise = crate::noise::gaussian_noise(1, "force", 1e-9, n).unwrap();
        let output_noise = crate::noise::gaussian_noise(1, "output", 1e-3, n).unwrap();
        let x: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 / per_period as f64; // in periods
                let sines: f64 = (1..=10)
                    .map(|k| (std::f64::consts::TAU * k as f64 * t + k as f64).sin())
                    .sum();
                sines + force_noise[i]
            })
            .collect();
        let y: Vec<f64> = x
            .iter()
            .zip(&output_noise)
            .map(|(x, e)| 2.0 * x + e)
            .collect();
        let options = FrfOptions {
            welch: WelchOptions {
                window: crate::Window::Rectangular,
                ..WelchOptions::default()
            },
            ..FrfOptions::default()
        };
        let frf = frf_estimate(
            &[Record {
                input: &x,
                output: &y,
            }],
            1.0,
            &options,
        )
        .unwrap();
        for (k, (h, g)) in frf.h.iter().zip(&frf.coherence).enumerate().skip(1) {
            if k % periods == 0 && k / periods <= 10 {
                assert!(
                    (h - Complex64::new(2.0, 0.0)).norm() < 1e-3,
                    "line {k}: {h}"
                );
            } else {
                assert_eq!((*h, *g), (Complex64::new(0.0, 0.0), 0.0), "line {k}");
            }
        }
    }
}
