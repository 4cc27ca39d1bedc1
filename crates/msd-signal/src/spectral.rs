//! Welch spectral estimation: PSD, cross spectrum, H1 frequency response, coherence.
//!
//! ## The algorithm
//! The record is cut into segments of L samples that overlap by `overlap`·L (rounded);
//! each segment is detrended, multiplied by the window w and transformed (rustfft);
//! the periodograms are averaged over the K segments (Welch 1967). Estimates are
//! one-sided, at f_k = k·fs/L for k = 0 … ⌊L/2⌋:
//!
//! S_xy(f_k) = c_k / (fs·Σw²·K) · Σ_segments conj(X_k)·Y_k, with c_k = 2 except at DC
//! and (L even) Nyquist, where c_k = 1.
//!
//! With this scaling the PSD of white noise of variance σ² sampled at fs is 2σ²/fs, and
//! Σ_k S_xx(f_k)·fs/L is the mean power (Parseval). The H1 estimate is
//! H1 = S_xy / S_xx (unbiased under output noise), the coherence
//! γ² = |S_xy|² / (S_xx·S_yy).
//!
//! With one segment (`segment_length: None`, the default) the coherence is identically 1
//! (a single periodogram is always perfectly "coherent"): it says nothing then, and
//! averaging over several segments is needed for it to mean anything. The paper's lightly
//! damped mode (ζ ≈ 0.05 at 1.1 Hz, a 0.11 Hz half-power band) needs the whole 15 s
//! record as one segment to be resolved at all. [`DftPair`] gives the (rectangular) DFTs
//! of such a record pair from one FFT, for work on the raw spectra, and their one-segment
//! Hann H1 without transforming again.
//!
//! ```
//! use msd_signal::{gaussian_noise, welch_psd, WelchOptions};
//! let (sigma, fs) = (0.5, 100.0);
//! let x = gaussian_noise(1, "demo", sigma, 1 << 14)?;
//! let opts = WelchOptions { segment_length: Some(256), ..WelchOptions::default() };
//! let psd = welch_psd(&x, fs, &opts)?;
//! let mean = psd.values[1..128].iter().sum::<f64>() / 127.0;
//! assert!((mean / (2.0 * sigma * sigma / fs) - 1.0).abs() < 0.05);
//! # Ok::<(), msd_signal::SignalError>(())
//! ```

use std::f64::consts::TAU;

use std::cell::RefCell;
use std::sync::Arc;

use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlannerScalar};
use serde::{Deserialize, Serialize};

use crate::error::{Result, SignalError, check_data, positive, same_length};
use crate::frf::correlation::{LagProducts, LineCorrelation, last_lag, window_kernel};

/// The taper applied to each segment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Window {
    /// Chosen from the data, the default: [`Window::Rectangular`] where
    /// [`frf_estimate`](crate::frf::frf_estimate) averages whole records whose input repeats
    /// from record to record (a periodic force over whole periods, which a taper would
    /// only smear into the lines between its own: see [`REPEATING`](crate::frf::REPEATING)),
    /// [`Window::Hann`] everywhere else (a PSD, one record, Welch segments, an input
    /// that does not repeat).
    #[default]
    Auto,
    /// Periodic Hann, `w[n] = ½·(1 − cos(2πn/L))` (as scipy's `welch`).
    Hann,
    /// No taper (w = 1).
    Rectangular,
}

impl Window {
    pub(crate) fn coefficients(self, l: usize) -> Vec<f64> {
        match self {
            Window::Hann | Window::Auto => {
                // w[n] = w[L − n]: compute half, mirror the rest.
                let mut w = vec![0.0; l];
                for n in 0..=l / 2 {
                    let v = 0.5 * (1.0 - (TAU * n as f64 / l as f64).cos());
                    w[n] = v;
                    if n > 0 {
                        w[l - n] = v;
                    }
                }
                w
            }
            Window::Rectangular => vec![1.0; l],
        }
    }

    /// The name as in a config (`"auto"`, `"hann"`, `"rectangular"`).
    pub fn name(self) -> &'static str {
        match self {
            Window::Auto => "auto",
            Window::Hann => "hann",
            Window::Rectangular => "rectangular",
        }
    }
}

/// What is removed from each segment before windowing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Detrend {
    /// Nothing.
    None,
    /// The segment's mean. The default.
    #[default]
    Mean,
    /// The segment's least-squares line.
    Linear,
}

/// Options of the Welch estimators (in TOML: a table with any of these fields; missing
/// ones take their defaults, unknown ones are rejected).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WelchOptions {
    /// Segment length L in samples; `None` = the whole record as one segment.
    /// By default `None`: the paper's lightly damped mode needs the full 15 s resolution.
    pub segment_length: Option<usize>,
    /// Fraction of a segment shared with the next, in [0, 1). By default 0.5 (50 %, the
    /// usual choice for a Hann window, Welch 1967).
    pub overlap: f64,
    /// Segment taper. By default [`Window::Auto`]: Hann, except for an FRF over whole
    /// records whose input repeats (rectangular).
    pub window: Window,
    /// Per-segment detrending. By default [`Detrend::Mean`].
    pub detrend: Detrend,
}

impl Default for WelchOptions {
    /// Whole record as one segment, 50 % overlap (used once segments are set), the
    /// window chosen from the data (Hann but for repeating inputs), mean removed.
    fn default() -> Self {
        WelchOptions {
            segment_length: None,
            overlap: 0.5,
            window: Window::Auto,
            detrend: Detrend::Mean,
        }
    }
}

impl WelchOptions {
    /// Checks `overlap` in [0, 1) and `segment_length ≥ 2` when given.
    pub fn validate(&self) -> Result<()> {
        if !(self.overlap >= 0.0 && self.overlap < 1.0) {
            return Err(SignalError::InvalidParameter {
                parameter: "overlap".into(),
                value: self.overlap,
                expected: "a fraction in [0, 1)",
            });
        }
        if let Some(l) = self.segment_length
            && l < 2
        {
            return Err(SignalError::InvalidParameter {
                parameter: "segment_length".into(),
                value: l as f64,
                expected: "at least 2 samples",
            });
        }
        Ok(())
    }
}

/// A real one-sided spectrum (PSD or coherence).
#[derive(Debug, Clone, PartialEq)]
pub struct Spectrum {
    /// Frequencies in Hz, k·fs/L.
    pub frequency: Vec<f64>,
    /// Values (PSD in units²/Hz, or coherence in [0, 1]).
    pub values: Vec<f64>,
    /// Number of averaged segments K.
    pub averages: usize,
}

/// A complex one-sided cross spectrum S_xy = E[conj(X)·Y] (units_x·units_y/Hz).
#[derive(Debug, Clone, PartialEq)]
pub struct CrossSpectrum {
    /// Frequencies in Hz.
    pub frequency: Vec<f64>,
    /// Cross-spectral density.
    pub values: Vec<Complex64>,
    /// Number of averaged segments K.
    pub averages: usize,
}

pub use crate::frf::FrequencyResponseEstimate;

thread_local! {
    /// One planner per thread: rustfft planners cache their plans, so repeated estimates
    /// of the same length (e.g. in a Monte Carlo loop) do not plan again.
    static PLANNER: RefCell<FftPlannerScalar<f64>> = RefCell::new(FftPlannerScalar::new());
}

fn forward_fft(len: usize) -> Arc<dyn Fft<f64>> {
    PLANNER.with(|p| p.borrow_mut().plan_fft_forward(len))
}

/// Averaged auto and cross spectra of one or more record pairs.
pub(crate) struct Welch {
    pub(crate) frequency: Vec<f64>,
    pub(crate) sxx: Vec<f64>,
    pub(crate) syy: Vec<f64>,
    pub(crate) sxy: Vec<Complex64>,
    pub(crate) averages: usize,
    /// L·Σw²/(Σw)² of the output's window (the input's for one record): over how many
    /// lines the errors of the spectra are correlated.
    pub(crate) noise_bandwidth: f64,
    /// How the lines' errors are correlated (empty for auto spectra alone).
    pub(crate) line_correlation: LineCorrelation,
}

fn detrend_segment(seg: &mut [f64], how: Detrend) {
    match how {
        Detrend::None => {}
        Detrend::Mean => {
            let m = seg.iter().sum::<f64>() / seg.len() as f64;
            seg.iter_mut().for_each(|v| *v -= m);
        }
        Detrend::Linear => {
            let n = seg.len() as f64;
            let am = (n - 1.0) / 2.0;
            let xm = seg.iter().sum::<f64>() / n;
            let (mut sax, mut saa) = (0.0, 0.0);
            for (i, v) in seg.iter().enumerate() {
                sax += (i as f64 - am) * (v - xm);
                saa += (i as f64 - am) * (i as f64 - am);
            }
            let slope = if saa > 0.0 { sax / saa } else { 0.0 };
            for (i, v) in seg.iter_mut().enumerate() {
                *v -= xm + slope * (i as f64 - am);
            }
        }
    }
}

/// Bin k of the DFTs X and Y of two real records from bins k and N − k of the DFT Z of
/// z = x + i·y: X_k = (Z_k + conj Z_{N−k})/2, Y_k = (Z_k − conj Z_{N−k})/(2i).
fn split(zk: Complex64, z_mirror: Complex64) -> (Complex64, Complex64) {
    let zm = z_mirror.conj();
    ((zk + zm) * 0.5, (zk - zm) * Complex64::new(0.0, -0.5))
}

/// How records are cut into segments and tapered: segments of `length` samples every
/// `step` samples, the input's samples multiplied by `input_window` and the output's by
/// `output_window` (both of length `length`) after `detrend`.
pub(crate) struct Segmenting<'a> {
    pub(crate) length: usize,
    pub(crate) step: usize,
    pub(crate) input_window: &'a [f64],
    pub(crate) output_window: &'a [f64],
    pub(crate) detrend: Detrend,
}

impl Segmenting<'_> {
    /// Segments in a record of `n` ≥ `length` samples.
    fn count(&self, n: usize) -> usize {
        (n - self.length) / self.step + 1
    }
}

/// The averaged spectra over every segment of every record (each at least
/// `segmenting.length` long; `y` present in all records or in none). The scale is
/// 1/(fs·Σw²·K) with the input window w, one-sided: a PSD when both windows are equal.
pub(crate) fn welch_records(
    records: &[(&[f64], Option<&[f64]>)],
    fs: f64,
    segmenting: &Segmenting<'_>,
) -> Welch {
    let l = segmenting.length;
    debug_assert!(segmenting.input_window.len() == l && segmenting.output_window.len() == l);
    debug_assert!(
        records
            .iter()
            .all(|(x, y)| x.len() >= l && y.is_none_or(|y| y.len() == x.len()))
    );
    let bins = l / 2 + 1;
    let fft = forward_fft(l);
    let mut scratch = vec![Complex64::new(0.0, 0.0); fft.get_inplace_scratch_len()];
    let mut buf = vec![Complex64::new(0.0, 0.0); l];
    let mut seg_x = vec![0.0; l];
    let mut seg_y = vec![0.0; l];
    let mut w = Welch {
        frequency: (0..bins).map(|k| k as f64 * fs / l as f64).collect(),
        sxx: vec![0.0; bins],
        syy: vec![0.0; bins],
        sxy: vec![Complex64::new(0.0, 0.0); bins],
        averages: records.iter().map(|(x, _)| segmenting.count(x.len())).sum(),
        noise_bandwidth: noise_bandwidth(match records.first() {
            Some((_, Some(_))) => segmenting.output_window,
            _ => segmenting.input_window,
        }),
        line_correlation: LineCorrelation::default(),
    };
    let (wx, wy) = (segmenting.input_window, segmenting.output_window);
    // The lines' correlation, for a cross spectrum only.
    let pair = records.first().is_some_and(|(_, y)| y.is_some());
    let kernels = match pair {
        true => [window_kernel(wx, &*fft), window_kernel(wy, &*fft)],
        false => [Vec::new(), Vec::new()],
    };
    let mut lags = LagProducts::new(last_lag(&kernels[0], &kernels[1], bins));
    let mut xs = vec![Complex64::new(0.0, 0.0); bins];
    for &(x, y) in records {
        for s in 0..segmenting.count(x.len()) {
            let range = s * segmenting.step..s * segmenting.step + l;
            seg_x.copy_from_slice(&x[range.clone()]);
            detrend_segment(&mut seg_x, segmenting.detrend);
            match y {
                None => {
                    for ((b, sx), wi) in buf.iter_mut().zip(&seg_x).zip(wx) {
                        *b = Complex64::new(sx * wi, 0.0);
                    }
                    fft.process_with_scratch(&mut buf, &mut scratch);
                    for (acc, b) in w.sxx.iter_mut().zip(&buf) {
                        *acc += b.norm_sqr();
                    }
                }
                Some(y) => {
                    // Two real records in one complex FFT: z = x + i·y gives
                    // X_k = (Z_k + conj Z_{L−k})/2 and Y_k = (Z_k − conj Z_{L−k})/(2i).
                    seg_y.copy_from_slice(&y[range]);
                    detrend_segment(&mut seg_y, segmenting.detrend);
                    for (i, b) in buf.iter_mut().enumerate() {
                        *b = Complex64::new(seg_x[i] * wx[i], seg_y[i] * wy[i]);
                    }
                    fft.process_with_scratch(&mut buf, &mut scratch);
                    for k in 0..bins {
                        let (xk, yk) = split(buf[k], buf[(l - k) % l]);
                        w.sxx[k] += xk.norm_sqr();
                        w.syy[k] += yk.norm_sqr();
                        w.sxy[k] += xk.conj() * yk;
                        xs[k] = xk;
                    }
                    lags.add(&xs);
                }
            }
        }
    }
    if pair {
        w.line_correlation = lags.correlation(&w.sxx, &kernels[0], &kernels[1]);
    }
    let wss: f64 = wx.iter().map(|v| v * v).sum();
    let base = 1.0 / (fs * wss * w.averages as f64);
    for k in 0..bins {
        let one_sided = if k == 0 || (l.is_multiple_of(2) && k == l / 2) {
            1.0
        } else {
            2.0
        };
        let c = base * one_sided;
        w.sxx[k] *= c;
        w.syy[k] *= c;
        w.sxy[k] *= c;
    }
    w
}

/// The equivalent noise bandwidth of a window in lines, L·Σw²/(Σw)² (1 for the
/// rectangular window, 1.5 for Hann; Harris 1978).
fn noise_bandwidth(window: &[f64]) -> f64 {
    let sum: f64 = window.iter().sum();
    let squares: f64 = window.iter().map(|w| w * w).sum();
    window.len() as f64 * squares / (sum * sum)
}

/// Checks the Welch options, `fs` and the records, and returns the segment length.
fn checked_length(x: &[f64], y: Option<&[f64]>, fs: f64, opts: &WelchOptions) -> Result<usize> {
    opts.validate()?;
    positive(|| "fs".into(), fs)?;
    check_data("x", x)?;
    if let Some(y) = y {
        check_data("y", y)?;
        same_length("x", x, "y", y)?;
    }
    let n = x.len();
    let l = opts.segment_length.unwrap_or(n);
    if n < 2 {
        return Err(SignalError::TooShort {
            name: "x",
            len: n,
            min: 2,
        });
    }
    if l > n {
        return Err(SignalError::WindowTooLong { window: l, len: n });
    }
    Ok(l)
}

/// The segment step of `opts` for segments of `l` samples (at least 1).
pub(crate) fn segment_step(l: usize, opts: &WelchOptions) -> usize {
    (l - (opts.overlap * l as f64).round() as usize).max(1)
}

fn welch(x: &[f64], y: Option<&[f64]>, fs: f64, opts: &WelchOptions) -> Result<Welch> {
    let l = checked_length(x, y, fs, opts)?;
    let window = opts.window.coefficients(l);
    let segmenting = Segmenting {
        length: l,
        step: segment_step(l, opts),
        input_window: &window,
        output_window: &window,
        detrend: opts.detrend,
    };
    Ok(welch_records(&[(x, y)], fs, &segmenting))
}

/// Welch power spectral density of `x` sampled at `fs` Hz (one-sided, units²/Hz).
///
/// Errors on empty or non-finite data, `fs ≤ 0`, bad options, or a segment longer than
/// the record.
pub fn welch_psd(x: &[f64], fs: f64, opts: &WelchOptions) -> Result<Spectrum> {
    let w = welch(x, None, fs, opts)?;
    Ok(Spectrum {
        frequency: w.frequency,
        values: w.sxx,
        averages: w.averages,
    })
}

/// Welch cross spectral density S_xy = E[conj(X)·Y] of two equally long records.
pub fn cross_spectrum(x: &[f64], y: &[f64], fs: f64, opts: &WelchOptions) -> Result<CrossSpectrum> {
    let w = welch(x, Some(y), fs, opts)?;
    Ok(CrossSpectrum {
        frequency: w.frequency,
        values: w.sxy,
        averages: w.averages,
    })
}

/// Relative level below which an auto spectrum counts as "no power".
pub(crate) const NO_POWER: f64 = 1e-24;

/// The coherence at the lines of `w.sxy` (the first lines of `w.sxx`, whose largest
/// value over all lines sets the "no power" level; likewise `w.syy`).
pub(crate) fn coherence_of(w: &Welch) -> Vec<f64> {
    let max_x = w.sxx.iter().fold(0.0f64, |m, &v| m.max(v));
    let max_y = w.syy.iter().fold(0.0f64, |m, &v| m.max(v));
    (0..w.sxy.len())
        .map(|k| {
            let (sxx, syy) = (w.sxx[k], w.syy[k]);
            if sxx > NO_POWER * max_x && syy > NO_POWER * max_y {
                (w.sxy[k].norm_sqr() / (sxx * syy)).clamp(0.0, 1.0)
            } else {
                0.0
            }
        })
        .collect()
}

/// Magnitude-squared coherence γ² of `x` and `y` (identically 1 with one segment).
pub fn coherence(x: &[f64], y: &[f64], fs: f64, opts: &WelchOptions) -> Result<Spectrum> {
    let w = welch(x, Some(y), fs, opts)?;
    Ok(Spectrum {
        values: coherence_of(&w),
        frequency: w.frequency,
        averages: w.averages,
    })
}

/// H1 estimate of the frequency response from `input` to `output` with the coherence.
///
/// Errors like [`welch_psd`], on records of different lengths, and with
/// [`SignalError::ZeroInputPower`] if the (detrended) input is identically zero.
///
/// ```
/// use msd_signal::{gaussian_noise, h1_estimate, WelchOptions};
/// let u = gaussian_noise(3, "input", 1.0, 4096)?;
/// let y: Vec<f64> = u.iter().map(|v| -2.0 * v).collect();
/// let opts = WelchOptions { segment_length: Some(256), ..WelchOptions::default() };
/// let frf = h1_estimate(&u, &y, 50.0, &opts)?;
/// assert!(frf.h[10..].iter().all(|h| (h.re + 2.0).abs() < 1e-9 && h.im.abs() < 1e-9));
/// assert!(frf.coherence[10..].iter().all(|g| (g - 1.0).abs() < 1e-9));
/// # Ok::<(), msd_signal::SignalError>(())
/// ```
pub fn h1_estimate(
    input: &[f64],
    output: &[f64],
    fs: f64,
    opts: &WelchOptions,
) -> Result<FrequencyResponseEstimate> {
    h1_of(welch(input, Some(output), fs, opts)?)
}

/// H1 = S_xy/S_xx and the coherence at the lines of `w.sxy` (see [`coherence_of`]).
fn h1_of(w: Welch) -> Result<FrequencyResponseEstimate> {
    crate::frf::estimate_from(w, crate::frf::Estimator::H1, NO_POWER)
}

/// The DFTs of an input and an output record of equal length, their means removed,
/// from one complex FFT of z = (x − x̄) + i·(y − ȳ) (unnormalised:
/// X_k = Σ_t x_t·e^{−2πikt/N}, k = 0 … N − 1; bin 0 is 0 up to rounding).
///
/// For work that needs the raw spectra beside an H1 estimate (a parametric fit to the
/// DFT, say) from a single transform: [`hann_h1`](Self::hann_h1) gives the one-segment
/// Hann H1 of the same records without transforming again.
///
/// ```
/// use msd_signal::{DftPair, Complex64};
/// // x_t = cos(2πt/8) + 5, y_t = sin(2πt/8): X_1 = 4, Y_1 = −4i.
/// let x: Vec<f64> = (0..8).map(|t| (std::f64::consts::TAU * t as f64 / 8.0).cos() + 5.0).collect();
/// let y: Vec<f64> = (0..8).map(|t| (std::f64::consts::TAU * t as f64 / 8.0).sin()).collect();
/// let pair = DftPair::new(&x, &y)?;
/// assert!((pair.input[1] - Complex64::new(4.0, 0.0)).norm() < 1e-12);
/// assert!((pair.output[1] - Complex64::new(0.0, -4.0)).norm() < 1e-12);
/// assert!(pair.input[0].norm() < 1e-12); // the mean is removed
/// # Ok::<(), msd_signal::SignalError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct DftPair {
    /// DFT of the mean-removed input record, all N bins.
    pub input: Vec<Complex64>,
    /// DFT of the mean-removed output record, all N bins.
    pub output: Vec<Complex64>,
}

impl DftPair {
    /// The DFTs of `input` and `output`, means removed.
    ///
    /// Errors on empty or non-finite data and on records of different lengths.
    pub fn new(input: &[f64], output: &[f64]) -> Result<Self> {
        check_data("input", input)?;
        check_data("output", output)?;
        same_length("input", input, "output", output)?;
        let n = input.len();
        let mean = |x: &[f64]| x.iter().sum::<f64>() / n as f64;
        let (mx, my) = (mean(input), mean(output));
        let mut z: Vec<Complex64> = input
            .iter()
            .zip(output)
            .map(|(&a, &b)| Complex64::new(a - mx, b - my))
            .collect();
        forward_fft(n).process(&mut z);
        // Bin N−k is z[N−k] for k ≥ 1 and z[0] for k = 0 (no modulo in the loop).
        let mirrored = std::iter::once(z[0]).chain(z[1..].iter().rev().copied());
        let (input, output) = z
            .iter()
            .zip(mirrored)
            .map(|(&zk, zm)| split(zk, zm))
            .unzip();
        Ok(Self { input, output })
    }

    /// The H1 estimate with one periodic-Hann segment, from these DFTs, at the lines
    /// k·fs/N up to `max_frequency` Hz (and the Nyquist frequency): what
    /// [`h1_estimate`] gives with [`WelchOptions::default()`] (the whole record, Hann,
    /// mean removed), up to FFT rounding, without another transform. The window is
    /// applied in frequency, where the periodic Hann window is the three-tap kernel
    /// `X_w[k] = ½X[k] − ¼(X[k−1] + X[k+1])` (indices mod N). The conventions are
    /// `h1_estimate`'s: H1 is 0 where the windowed input has less than 1e-24 of its peak
    /// one-sided power over all lines, the coherence is 1 where both records have power
    /// (one segment) and 0 elsewhere.
    ///
    /// Errors on `fs` not finite and positive, `max_frequency` negative or NaN, and with
    /// [`SignalError::ZeroInputPower`] for an input without power after the mean is
    /// removed.
    ///
    /// ```
    /// use msd_signal::{gaussian_noise, h1_estimate, DftPair, WelchOptions};
    /// let u = gaussian_noise(3, "input", 1.0, 1000)?;
    /// let y: Vec<f64> = u.windows(2).map(|w| w[1] - 0.5 * w[0]).chain([0.0]).collect();
    /// let from_dft = DftPair::new(&u, &y)?.hann_h1(100.0, 20.0)?;
    /// let direct = h1_estimate(&u, &y, 100.0, &WelchOptions::default())?;
    /// assert_eq!(from_dft.frequency.len(), 201); // 0, 0.1, …, 20 Hz
    /// for (a, b) in from_dft.h.iter().zip(&direct.h) {
    ///     assert!((a - b).norm() < 1e-9 * b.norm());
    /// }
    /// # Ok::<(), msd_signal::SignalError>(())
    /// ```
    pub fn hann_h1(&self, fs: f64, max_frequency: f64) -> Result<FrequencyResponseEstimate> {
        positive(|| "fs".into(), fs)?;
        if max_frequency.is_nan() || max_frequency < 0.0 {
            return Err(SignalError::InvalidParameter {
                parameter: "max_frequency".into(),
                value: max_frequency,
                expected: "a frequency >= 0 Hz",
            });
        }
        let (x, y) = (&self.input, &self.output);
        let n = x.len();
        let half = n / 2;
        let lines = ((max_frequency / (fs / n as f64)).floor() as usize).min(half) + 1;
        // Only k = 0 wraps around below (X[−1] = X[N−1]), and above only k = N/2 for N ≤ 2.
        let windowed = |x: &[Complex64], k: usize| {
            let below = if k == 0 { x[n - 1] } else { x[k - 1] };
            let above = if k + 1 == n { x[0] } else { x[k + 1] };
            x[k] * 0.5 - (below + above) * 0.25
        };
        // One-sided: every line doubled but DC and Nyquist (a factor 2 is exact, so H1
        // and the coherence are the same bits as from the two-sided values).
        let one_sided = |k: usize| if k != 0 && 2 * k != n { 2.0 } else { 1.0 };
        let mut w = Welch {
            frequency: (0..lines).map(|k| k as f64 * fs / n as f64).collect(),
            sxx: Vec::with_capacity(half + 1),
            syy: Vec::with_capacity(half + 1),
            sxy: Vec::with_capacity(lines),
            averages: 1,
            noise_bandwidth: 1.5, // the periodic Hann window's, exactly
            line_correlation: LineCorrelation::default(),
        };
        let mut xs = Vec::with_capacity(half + 1);
        for k in 0..=half {
            let (a, b) = (windowed(x, k), windowed(y, k));
            let c = one_sided(k);
            w.sxx.push(c * a.norm_sqr());
            w.syy.push(c * b.norm_sqr());
            if k < lines {
                w.sxy.push(a.conj() * b * c);
            }
            xs.push(a);
        }
        // The periodic Hann window's ρ(d), exactly: w² = 3/8 − cos/2 + cos(2·)/8.
        let hann = [1.0, -2.0 / 3.0, 1.0 / 6.0].map(|r| Complex64::new(r, 0.0));
        let mut lags = LagProducts::new(last_lag(&hann, &hann, half + 1));
        lags.add(&xs);
        let power: Vec<f64> = xs.iter().map(|x| x.norm_sqr()).collect();
        w.line_correlation = lags.correlation(&power, &hann, &hann);
        h1_of(w)
    }
}
