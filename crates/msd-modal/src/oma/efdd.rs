//! Frequency domain decomposition and its enhanced form (EFDD): the peaks of the output
//! spectral matrix's first singular value picked automatically, each peak's SDOF bell
//! turned back into a correlation function whose zero crossings give fn and whose decay
//! gives ζ, and jackknife intervals.

use msd_opt::statistics::t_975;
use msd_signal::Complex64;
use rayon::prelude::*;

use super::covariance::{BlockCovariances, Lags};
use super::decay::decay;
use super::options::FddOptions;
use super::record::OutputRecord;
use super::record::order;
use super::select::Physical;
use super::spectrum::{Line, SingularSpectrum, decompose, default_lags, spectral_matrix};
use super::uncertainty::{mode_with_errors, standard_errors};
use super::{OmaFit, OmaMethod};
use crate::shapes::mac;
use msd_modal_core::diagram::{StabilizationDiagram, StableColumn};
use msd_modal_core::error::{ModalError, Result};

/// The modes of an output-only record by EFDD, the peaks picked automatically (or nearest
/// the named frequencies), with 95 % intervals on fn, ζ and every shape entry.
///
/// ## The method
/// Each channel centred and scaled to unit variance; the spectral matrix G(f) from the
/// covariances at lags 0 … N − 1 under an exponential window (to 1 % at lag N), and its
/// singular values line by line (FDD; Brincker, Zhang & Andersen, Smart Mater. Struct.
/// 10, 2001). A peak of the first singular value is a mode when it stands
/// `min_peak_ratio` times above its neighbourhood's median and `min_prominence` times above
/// the troughs around it; its shape is the first singular vector there (as displacement in
/// the channels' units, largest entry 1). EFDD (Brincker, Ventura & Andersen, IMAC 19,
/// 2001): the lines around the peak whose first singular vector has MAC ≥ `bell_mac` with
/// the peak's form the SDOF bell; its inverse transform, the window divided out, is the
/// mode's correlation function; fn from the regression of its zero crossings, ζ from the
/// logarithmic decrement of its extremes (from the `skip_extremes`-th, down to
/// `min_correlation`, at most `max_extremes`, within the first quarter of the lags where
/// the window is above 30 %). The intervals: the leave-one-block-out jackknife over
/// `blocks` blocks, each replicate repeating the peak, bell and fit; Student's t on
/// `blocks` − 1 degrees of freedom. A peak whose bell yields no decay, or that a replicate
/// loses, is listed `unconfirmed` (the first in [`SingularSpectrum::peaks_hz`] only).
///
/// Errors: a bad record ([`OutputRecord::check`]), bad options, a record shorter than
/// four times the lags, no peak.
///
/// ```
/// use msd_modal::{Channel, Dof, FddOptions, OutputRecord, Quantity, efdd};
/// // Two channels of one 4 Hz mode with 2 % damping driven by noise (an AR(2) process).
/// let (fs, f, zeta) = (50.0_f64, 4.0_f64, 0.02_f64);
/// let w = std::f64::consts::TAU * f / fs;
/// let (a1, a2) = (2.0 * (-zeta * w).exp() * (w * (1.0 - zeta * zeta).sqrt()).cos(), -(-2.0 * zeta * w).exp());
/// let mut x = vec![0.0; 40_000];
/// let mut seed = 1_u64;
/// for t in 2..x.len() {
///     seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
///     x[t] = a1 * x[t - 1] + a2 * x[t - 2] + ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5);
/// }
/// let channel = |node: u32, gain: f64| Channel::new(format!("d{node}"), Quantity::Displacement,
///     x.iter().map(|v| gain * v).collect()).at(Dof { node, direction: 1 });
/// let record = OutputRecord::new(fs, vec![channel(1, 1.0), channel(2, -0.5)]);
/// let fit = efdd(&record, &FddOptions::default())?;
/// assert_eq!(fit.modes.len(), 1);
/// let mode = &fit.modes[0];
/// assert!((mode.natural_frequency_hz.value / 4.0 - 1.0).abs() < 0.005);
/// let [low, high] = mode.damping_ratio.ci95;
/// assert!(low < 0.02 && 0.02 < high, "{low} {high}");
/// assert!((mode.shape[1].re + 0.5).abs() < 0.01);
/// # Ok::<(), msd_modal::ModalError>(())
/// ```
pub fn efdd(record: &OutputRecord, options: &FddOptions) -> Result<OmaFit> {
    record.check()?;
    options.validate()?;
    let fs = record.sample_rate_hz();
    let (scaled, scales) = record.standardised_by_quantity();
    let lags = options
        .lags
        .unwrap_or_else(|| default_lags(&scaled, fs, options.band_hz));
    let band = options.band_hz.unwrap_or([0.0, 0.5 * fs]);
    check_sizes(record, options, lags)?;
    let all: Vec<usize> = (0..scaled.len()).collect();
    let lag_range = Lags {
        first: 0,
        last: lags - 1,
    };
    let covariances = BlockCovariances::with_lags(&scaled, &all, lag_range, options.blocks);
    let matrices = spectral_matrix(&covariances.covariances(None), fs);
    let df = fs / (2 * lags) as f64;
    let lines: Vec<Line> = matrices.iter().map(decompose).collect();
    let first = ((band[0] / df).ceil() as usize).max(3);
    let last = ((band[1] / df).floor() as usize).min(lags);
    let peaks = pick_peaks(&lines, first..=last, options);
    if peaks.is_empty() {
        return Err(ModalError::EstimationFailed {
            reason: format!(
                "no peak of the first singular value stands {} times above its neighbourhood \
                 and {} times above its troughs between {:.4} and {:.4} Hz",
                options.min_peak_ratio,
                options.min_prominence,
                first as f64 * df,
                last as f64 * df
            ),
        });
    }
    let chosen = chosen_peaks(&peaks, df, options);
    let windows: Vec<[usize; 2]> = chosen
        .iter()
        .map(|&p| search_window(&peaks, p, first, last))
        .collect();
    let context = Context {
        record,
        scales: &scales,
        lags,
        fs,
        options,
    };
    let estimates: Vec<Option<Physical>> = windows
        .iter()
        .map(|&[a, b]| context.estimate(&lines[a..=b], a))
        .collect();
    let replicates = jackknife(&covariances, &windows, &estimates, &context);
    let t975 = t_975(options.blocks - 1);
    let (mut modes, mut unconfirmed) = (Vec::new(), Vec::new());
    for (k, estimate) in estimates.iter().enumerate() {
        let Some(estimate) = estimate else { continue };
        let reps: Option<Vec<Physical>> = replicates.iter().map(|r| r[k].clone()).collect();
        match reps {
            Some(reps) => {
                let se = standard_errors(estimate, &reps);
                modes.push(mode_with_errors(estimate, record, &se, t975));
            }
            None => unconfirmed.push(column_of(estimate)),
        }
    }
    let columns: Vec<StableColumn> = estimates.iter().flatten().map(column_of).collect();
    let peaks_hz = chosen.iter().map(|&p| p as f64 * df).collect();
    let spectrum = SingularSpectrum::of(&lines, fs, lags, peaks_hz);
    Ok(OmaFit {
        method: OmaMethod::Efdd,
        diagram: StabilizationDiagram {
            orders: Vec::new(),
            modes: modes.iter().map(column_of_mode).collect(),
            candidates: columns,
            band_hz: band,
        },
        modes,
        block_rows: None,
        blocks: options.blocks,
        references: Vec::new(),
        singular_values: Vec::new(),
        unconfirmed,
        spectrum: Some(spectrum),
    })
}

/// What every estimate needs: the record's channels, their scales, the lags, the rate
/// and the options.
struct Context<'a> {
    record: &'a OutputRecord,
    scales: &'a [f64],
    lags: usize,
    fs: f64,
    options: &'a FddOptions,
}

impl Context<'_> {
    /// The mode in a search window of decomposed lines starting at line `start`: the
    /// highest line, its bell, the decay fit and the peak's shape (`None` where the bell
    /// is narrower than three lines or yields no decay within the damping limit).
    fn estimate(&self, window: &[Line], start: usize) -> Option<Physical> {
        let p = (0..window.len())
            .max_by(|&a, &b| window[a].values[0].total_cmp(&window[b].values[0]))?;
        let within = |j: usize| mac(&window[j].first, &window[p].first) >= self.options.bell_mac;
        let mut a = p;
        while a > 0 && within(a - 1) {
            a -= 1;
        }
        let mut b = p;
        while b + 1 < window.len() && within(b + 1) {
            b += 1;
        }
        if b - a < 2 {
            return None;
        }
        let bell: Vec<f64> = window[a..=b].iter().map(|line| line.values[0]).collect();
        let (cycles_per_lag, zeta) = decay(&bell, start + a, self.lags, self.options)?;
        if zeta > self.options.max_damping_ratio {
            return None;
        }
        let frequency_hz = cycles_per_lag * self.fs / (1.0 - zeta * zeta).sqrt();
        let shape = self.displacement(&window[p].first, frequency_hz)?;
        Some(Physical {
            order_index: 0,
            frequency_hz,
            damping_ratio: zeta,
            shape,
            stable: true,
        })
    }

    /// A singular vector as a displacement shape in the channels' units, largest entry 1
    /// (a velocity entry divided by iω, an acceleration's by (iω)²).
    fn displacement(&self, vector: &[Complex64], frequency_hz: f64) -> Option<Vec<Complex64>> {
        let s = Complex64::new(0.0, std::f64::consts::TAU * frequency_hz);
        let shape: Vec<Complex64> = vector
            .iter()
            .zip(self.scales.iter().zip(self.record.channels()))
            .map(|(v, (scale, c))| v * *scale / s.powi(order(c.quantity)))
            .collect();
        let largest = shape
            .iter()
            .copied()
            .max_by(|a, b| a.norm().total_cmp(&b.norm()))?;
        (largest.norm() > 0.0).then(|| shape.iter().map(|v| v / largest).collect())
    }
}

/// Each replicate's estimate of every mode (the record less one block): its spectral
/// matrix, decomposed only in the modes' search windows. Side by side on rayon, gathered
/// in block order.
fn jackknife(
    covariances: &BlockCovariances,
    windows: &[[usize; 2]],
    estimates: &[Option<Physical>],
    context: &Context<'_>,
) -> Vec<Vec<Option<Physical>>> {
    (0..covariances.blocks())
        .into_par_iter()
        .map(|left_out| {
            let matrices = spectral_matrix(&covariances.covariances(Some(left_out)), context.fs);
            windows
                .iter()
                .zip(estimates)
                .map(|(&[a, b], full)| {
                    full.as_ref()?;
                    let lines: Vec<Line> = matrices[a..=b].iter().map(decompose).collect();
                    context.estimate(&lines, a)
                })
                .collect()
        })
        .collect()
}

/// The peaks of the first singular value among `lines`: a local maximum standing
/// `min_peak_ratio` times above the median over ±50 % of its frequency (at least ±16
/// lines) and `min_prominence` times above the higher of the lowest lines between it and
/// the next higher line on either side, whose neighbours' first singular vectors have
/// MAC ≥ `bell_mac` with its own (a mode's shape holds across its peak; noise's does
/// not).
fn pick_peaks(
    lines: &[Line],
    range: std::ops::RangeInclusive<usize>,
    options: &FddOptions,
) -> Vec<usize> {
    let s: Vec<f64> = lines.iter().map(|l| l.values[0]).collect();
    let (first, last) = (*range.start(), *range.end());
    let mut peaks = Vec::new();
    for k in first.max(1)..last.min(s.len() - 1) {
        if !(s[k] > s[k - 1] && s[k] >= s[k + 1]) {
            continue;
        }
        let coherent = |j: usize| mac(&lines[j].first, &lines[k].first) >= options.bell_mac;
        let left = trough(s[first..=k].iter().rev(), s[k]);
        let right = trough(s[k..=last].iter(), s[k]);
        if !(s[k] >= options.min_prominence * left.max(right) && coherent(k - 1) && coherent(k + 1))
        {
            continue;
        }
        // The median last: only the few prominent maxima pay for its sort.
        let half = ((0.5 * k as f64).round() as usize).max(16);
        let neighbourhood: Vec<f64> =
            s[k.saturating_sub(half)..=(k + half).min(s.len() - 1)].to_vec();
        if s[k] >= options.min_peak_ratio * median(neighbourhood) {
            peaks.push(k);
        }
    }
    peaks
}

/// The lowest value from a peak until a higher one (or the end).
fn trough<'a>(from_peak: impl Iterator<Item = &'a f64>, peak: f64) -> f64 {
    from_peak
        .skip(1)
        .take_while(|&&v| v <= peak)
        .fold(peak, |low, &v| low.min(v))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Every peak, or the peak nearest each named frequency (each once).
fn chosen_peaks(peaks: &[usize], df: f64, options: &FddOptions) -> Vec<usize> {
    if options.frequencies_hz.is_empty() {
        return peaks.to_vec();
    }
    let mut chosen: Vec<usize> = options
        .frequencies_hz
        .iter()
        .filter_map(|&f| {
            peaks.iter().copied().min_by(|&a, &b| {
                (a as f64 * df - f)
                    .abs()
                    .total_cmp(&(b as f64 * df - f).abs())
            })
        })
        .collect();
    chosen.sort_unstable();
    chosen.dedup();
    chosen
}

/// The lines a peak's bell may span: halfway to the neighbouring peaks, within ±20 %
/// of its frequency and the band.
fn search_window(peaks: &[usize], p: usize, first: usize, last: usize) -> [usize; 2] {
    let half = ((0.2 * p as f64).round() as usize).max(2);
    let below = peaks.iter().copied().filter(|&q| q < p).max();
    let above = peaks.iter().copied().filter(|&q| q > p).min();
    let low = below
        .map_or(first, |q| (q + p).div_ceil(2))
        .max(p.saturating_sub(half))
        .max(first);
    let high = above.map_or(last, |q| (q + p) / 2).min(p + half).min(last);
    [low, high]
}

fn column_of(p: &Physical) -> StableColumn {
    StableColumn {
        natural_frequency_hz: p.frequency_hz,
        damping_ratio: p.damping_ratio,
        stable_orders: 0,
        at_peak: true,
    }
}

fn column_of_mode(m: &msd_modal_core::mode::Mode) -> StableColumn {
    StableColumn {
        natural_frequency_hz: m.natural_frequency_hz.value,
        damping_ratio: m.damping_ratio.value,
        stable_orders: 0,
        at_peak: true,
    }
}

/// The record long enough for the lags, the band below Nyquist.
fn check_sizes(record: &OutputRecord, options: &FddOptions, lags: usize) -> Result<()> {
    let needed = 4 * lags;
    if record.len() < needed {
        return Err(ModalError::TooFewSamples {
            got: record.len(),
            needed,
            why: "the record must hold at least four times the spectral matrix's lags",
        });
    }
    record.check_band(options.band_hz)
}
