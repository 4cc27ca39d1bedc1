//! The figure of an operational run, PNG and SVG in the house style: `oma_stabilization`
//! (SSI's poles by model order, the poles that formed each mode marked, the modes'
//! frequencies dashed, the record's spectrum behind).

use super::OperationalOutcome;
use crate::error::Result;
use crate::plots::diagram::Stabilization;
use crate::plots::{register_fonts, save};
use msd_signal::{WelchOptions, welch_psd};
use std::path::Path;

/// Writes the figure; returns its base name.
pub(crate) fn write_all(o: &OperationalOutcome, dir: &Path) -> Result<Vec<&'static str>> {
    register_fonts();
    save(
        &Stabilization {
            diagram: &o.fit.diagram,
            behind: summed_spectrum(o),
            name: "oma_stabilization",
            title: "Stabilization diagram (SSI-cov poles by model order)",
            behind_label: "the record's spectrum (log scale, unit-variance channels summed)",
            view_hz: view(o),
        },
        dir,
    )?;
    Ok(vec!["oma_stabilization"])
}

/// The Welch spectra of the channels, each scaled to unit variance, summed (segments of
/// about an eighth of the record, as the block rows' rule reads it).
pub(crate) fn summed_spectrum(o: &OperationalOutcome) -> Vec<(f64, f64)> {
    let n = o.record.len();
    let segment = (n / 8).max(64).next_power_of_two().min(n);
    let options = WelchOptions {
        segment_length: Some(segment),
        ..WelchOptions::default()
    };
    let mut sum: Vec<(f64, f64)> = Vec::new();
    for c in &o.record.channels {
        let mean = c.samples.iter().sum::<f64>() / n as f64;
        let var = c.samples.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n as f64;
        let Ok(psd) = welch_psd(&c.samples, o.record.sample_rate_hz, &options) else {
            continue;
        };
        if sum.is_empty() {
            sum = psd.frequency.iter().map(|&f| (f, 0.0)).collect();
        }
        for (s, v) in sum.iter_mut().zip(&psd.values) {
            s.1 += v / var.max(f64::MIN_POSITIVE);
        }
    }
    sum
}

/// The band the figure shows: up to a third above the highest mode (the whole band
/// when there is none or it is near the top).
fn view(o: &OperationalOutcome) -> Option<[f64; 2]> {
    let [low, high] = o.fit.diagram.band_hz;
    let top = o
        .fit
        .modes
        .iter()
        .map(|m| m.natural_frequency_hz.value)
        .fold(0.0, f64::max);
    (top > 0.0 && 1.33 * top < high).then_some([low, 1.33 * top])
}
