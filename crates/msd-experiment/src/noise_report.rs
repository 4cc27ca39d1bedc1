//! The noise model's part of a report and a summary, for every kind whose fit carries
//! an [`NoiseModelFit`] (one-mass setups, chains): the treatment, the drive's noise
//! found, each channel's whiteness, and the warnings.

use crate::fmt::sig;
use crate::summary::labelled;
use msd_ident::Interval;
use msd_ident::records::{NoiseModelFit, ResidualWhiteness};
use std::fmt::Write;

/// The noise-spectrum figure's alt text and caption, in every kind's report.
pub(crate) const SPECTRUM_FIGURE: (&str, &str) = (
    "Residual spectra against the noise model",
    "Each channel's residual (blue), averaged over bands of DFT lines, against the noise model's spectrum (red: the sensor's white noise plus the drive's noise through the plant, dashed; under the white treatment the flat level the intervals assume) and the 95 % range of a band's mean under the model (grey). A run of bands outside the range is colour the model leaves unexplained; at the resonance the residual may dip below the model where the fit absorbed part of the noise.",
);

/// The noise model's line and a warning per channel left coloured, for the summary;
/// `unit` is the drive's.
pub(crate) fn summary(
    s: &mut String,
    m: &NoiseModelFit,
    whiteness: &[ResidualWhiteness],
    unit: &str,
) {
    if let (Some(sigma), Some(fraction)) = (m.input_noise_sigma, m.input_noise_fraction) {
        labelled(
            s,
            "noise model",
            &format!(
                "{}: the drive's noise σ̂_u = {} {unit} ({} % of its rms); intervals ×{} the white-noise ones",
                m.treatment,
                sig(sigma, 3),
                sig(100.0 * fraction, 2),
                sig(m.interval_ratio, 3)
            ),
        );
        if let Some(low) = m.output_error_efficiency.values().copied().reduce(f64::min) {
            let gain = (1.0 / low).sqrt();
            let compared = if gain < 1.05 {
                "within 5 % of these".to_string()
            } else {
                format!("up to ×{} wider", sig(gain, 2))
            };
            labelled(
                s,
                "",
                &format!(
                    "estimate weighted by each frequency line's noise (frequency-domain maximum likelihood): the output-error fit's intervals were {compared} (report.md, Noise)"
                ),
            );
        } else if let Some(low) = m.efficiency.values().copied().reduce(f64::min) {
            labelled(
                s,
                "",
                &format!(
                    "efficiency against the Cramér–Rao bound of this noise model: ≥ {low:.2} (report.md, Noise)"
                ),
            );
        }
    }
    for c in whiteness.iter().filter(|c| !c.passed) {
        let test = c.ljung_box_under_noise_model.unwrap_or(c.ljung_box);
        labelled(
            s,
            "warning",
            &format!(
                "record `{}`, channel `{}`: the residual is not white under the noise model (Ljung–Box p = {}): the model leaves structure unexplained; the intervals may be too narrow (report.md, Noise)",
                c.record,
                c.channel,
                sig(test.p_value, 2)
            ),
        );
    }
}

/// The "Noise" section's heading, the treatment in words and the whiteness table;
/// `unit` is the drive's, `section` the config section whose `noise_model` key chose
/// the treatment.
pub(crate) fn section(
    s: &mut String,
    m: &NoiseModelFit,
    whiteness: &[ResidualWhiteness],
    unit: &str,
    section: &str,
) -> std::fmt::Result {
    writeln!(s, "## Noise\n")?;
    match (m.input_noise_sigma, m.input_noise_fraction, m.p_value) {
        (Some(sigma), Some(fraction), Some(p)) => writeln!(
            s,
            "The intervals assume white noise on each sensor plus white noise on the measured drive, seen through the plant (errors-in-variables; msd-ident's `NoiseModel::InputNoise`): the drive's noise σ̂_u = {} {unit}, {} % of its rms (likelihood ratio against a noise-free drive {}, p = {}). They are {}× the intervals that take the drive as exact{}.\n",
            sig(sigma, 3),
            sig(100.0 * fraction, 2),
            sig(m.likelihood_ratio.unwrap_or(0.0), 3),
            sig(p, 2),
            sig(m.interval_ratio, 3),
            m.degrees_of_freedom
                .filter(|nu| nu.is_finite())
                .map_or(String::new(), |nu| format!(", with Student's t on {nu:.0} degrees of freedom (Satterthwaite: the noise levels behind them are estimated too)"))
        )?,
        _ => writeln!(
            s,
            "The intervals assume white noise on each sensor and take the drive (if any) as exact: `{section} noise_model = \"white\"`, the default for a synthetic drive without noise (exact by construction) and the only model of a free decay.\n"
        )?,
    }
    efficiency(s, m)?;
    writeln!(
        s,
        "Each channel's residual tested for whiteness (Ljung–Box, 25 lags, level 1 %): as fitted, and whitened by the noise model. A residual that stays coloured under the model means structure the model does not explain.\n\n| record | channel | p as fitted | p under the noise model | white |\n|---|---|---|---|---|"
    )?;
    for c in whiteness {
        writeln!(
            s,
            "| {} | {} | {} | {} | {} |",
            c.record,
            c.channel,
            sig(c.ljung_box.p_value, 3),
            c.ljung_box_under_noise_model
                .map_or("—".into(), |l| sig(l.p_value, 3)),
            if c.passed { "yes" } else { "**no**" }
        )?;
    }
    s.push('\n');
    if whiteness.iter().any(|c| c.spectrum.is_some()) {
        writeln!(
            s,
            "The residual spectra against the noise model's are drawn in the noise-spectrum figure (Figures): where the residual leaves the model's 95 % range over a stretch of frequency, the model misses something there.\n"
        )?;
    }
    Ok(())
}

/// The efficiency of each estimate against the Cramér–Rao bound, when the model was
/// fitted.
fn efficiency(s: &mut String, m: &NoiseModelFit) -> std::fmt::Result {
    if m.efficiency.is_empty() {
        return Ok(());
    }
    // m, c, k, then the rest (fn, ζ; a chain's m1, m2, …, c1, …).
    let symbol = |name: &str| match name {
        "mass" => (0, "m".to_string()),
        "damping" => (1, "c".into()),
        "stiffness" => (2, "k".into()),
        "natural_frequency_hz" => (3, "fn".into()),
        "damping_ratio" => (4, "ζ".into()),
        other => (
            5 + other
                .chars()
                .next()
                .and_then(|c| "mck".find(c))
                .unwrap_or(3),
            other.into(),
        ),
    };
    let list = |efficiency: &std::collections::BTreeMap<String, f64>| {
        let mut rows: Vec<((usize, String), f64)> =
            efficiency.iter().map(|(n, e)| (symbol(n), *e)).collect();
        rows.sort_by(|a, b| a.0.cmp(&b.0));
        let rows: Vec<String> = (rows.iter())
            .map(|((_, name), e)| format!("{name} {e:.2}"))
            .collect();
        rows.join(", ")
    };
    if m.estimator == "weighted" {
        return writeln!(
            s,
            "The estimate weights each frequency line by its noise: the frequency-domain maximum-likelihood estimator of this errors-in-variables model (Pintelon and Schoukens' SML), started from the output-error fit, the noise levels as found. Its cost over its expectation is {} (near 1: the noise model describes the residuals); its intervals are the sandwich of its estimating equations under the noise model, against the Cramér–Rao bound: {}. The output-error estimate, which weights every line alike, reached only {} of the bound (its intervals are in `output_error_estimate` and below).\n",
            sig(m.cost_ratio.unwrap_or(f64::NAN), 3),
            list(&m.efficiency),
            list(&m.output_error_efficiency)
        );
    }
    writeln!(
        s,
        "Efficiency against the Cramér–Rao bound of this noise model (the bound's variance over the reported one; 1: nothing to gain): {}. The fit weights every frequency line alike; where the drive's noise shows (p < 0.01) and the residuals are white under the noise model, a fit of records is replaced by the estimate that weights each line by its noise; here it is not. The reported intervals hold either way: they are those of the estimate that was made.\n",
        list(&m.efficiency)
    )
}

/// One row of the white-noise intervals' table: label, estimate, interval.
pub(crate) fn white_row(s: &mut String, label: &str, iv: &Interval) -> std::fmt::Result {
    writeln!(
        s,
        "| {label} | {} | [{}, {}] |",
        sig(iv.value, 6),
        sig(iv.ci95[0], 6),
        sig(iv.ci95[1], 6)
    )
}
