//! How many block rows: enough columns for every model order, and lags long enough to see
//! the slowest mode. Covariance-driven SSI resolves a mode poorly when the longest lag
//! (2i − 1)/fs is short against its period (its covariance barely turns within the
//! Toeplitz matrix); one period of the lowest mode is the rule used here, the lowest
//! mode taken from the record's spectrum when no band says it.

use msd_signal::{WelchOptions, welch_psd};

use super::options::OmaOptions;

/// The block rows for `references` references: the larger of ⌈n_max/r⌉ + 5 and
/// ⌈fs/(2·f_low)⌉, f_low the band's lower edge or else the lowest clear peak of the
/// channels' summed spectrum (see [`lowest_peak_hz`]); `options.block_rows` where given.
pub(crate) fn block_rows(
    options: &OmaOptions,
    scaled: &[Vec<f64>],
    fs: f64,
    references: usize,
) -> usize {
    if let Some(i) = options.block_rows {
        return i;
    }
    let columns = options.orders[1].div_ceil(references.max(1)) + 5;
    let low = match options.band_hz {
        Some([low, _]) if low > 0.0 => Some(low),
        _ => lowest_peak_hz(scaled, fs),
    };
    low.map_or(columns, |f| columns.max((fs / (2.0 * f)).ceil() as usize))
}

/// The lowest frequency at which the summed spectrum of the (unit-variance) channels has
/// a clear peak: a local maximum at least 4 times the median of the spectrum over ±20 %
/// of its frequency, above the third line (Welch, Hann, segments of about an eighth of
/// the record, a power of two). `None` where no line qualifies.
pub(crate) fn lowest_peak_hz(scaled: &[Vec<f64>], fs: f64) -> Option<f64> {
    let n = scaled.first()?.len();
    let segment = (n / 8).max(64).next_power_of_two().min(n);
    let options = WelchOptions {
        segment_length: Some(segment),
        ..WelchOptions::default()
    };
    let mut sum: Option<(Vec<f64>, Vec<f64>)> = None;
    for x in scaled {
        let psd = welch_psd(x, fs, &options).ok()?;
        match &mut sum {
            None => sum = Some((psd.frequency, psd.values)),
            Some((_, values)) => values
                .iter_mut()
                .zip(&psd.values)
                .for_each(|(s, v)| *s += v),
        }
    }
    let (f, p) = sum?;
    (3..p.len().saturating_sub(1)).find_map(|k| {
        let peak = p[k] >= p[k - 1] && p[k] >= p[k + 1];
        let window: Vec<f64> = (0..p.len())
            .filter(|&j| (f[j] - f[k]).abs() <= 0.2 * f[k])
            .map(|j| p[j])
            .collect();
        (peak && window.len() >= 5 && p[k] >= 4.0 * median(window)).then_some(f[k])
    })
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}
