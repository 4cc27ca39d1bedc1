//! The figures of a chain run, PNG and SVG in the house style: `chain_fit`, the drive
//! and each sensor, measured and as fitted; `chain_noise_spectrum`, each sensor's
//! residual spectrum against the noise model's.

use super::{ChainOutcome, channel_names};
use crate::error::Result;
use crate::plots::panel::{Band, Curve, Panel, Stack, Style};
use crate::plots::spectrum::{NoiseSpectra, SpectrumPanel};
use crate::plots::{BLUE, Drawable, RED, register_fonts, save_all};
use plotters::prelude::SeriesLabelPosition;
use std::path::Path;

/// Writes the figures; returns their base names.
pub(crate) fn write_all(o: &ChainOutcome, dir: &Path) -> Result<Vec<&'static str>> {
    register_fonts();
    let time: Vec<f64> = (0..o.record.len())
        .map(|k| k as f64 * o.record.dt)
        .collect();
    let Some(&end) = time.last() else {
        return Ok(Vec::new());
    };
    let range = (0.0, end);
    let drive = o
        .config
        .chain
        .as_ref()
        .map_or("force [N]", |c| match c.drive {
            msd_ident::chain::ChainDrive::Force => "force [N]",
            msd_ident::chain::ChainDrive::BaseAcceleration => "base acceleration [m/s²]",
        });
    let mut panels = vec![Panel {
        title: "Drive".into(),
        x_desc: "time t [s]".into(),
        y_desc: drive.into(),
        x_range: range,
        curves: vec![Curve {
            label: "measured".into(),
            x: &time,
            y: o.record.input().to_vec(),
            style: Style::Line(BLUE, 1),
        }],
        band: None,
        legend: None,
    }];
    let bands = o.band.lower.iter().zip(&o.band.upper);
    for (((name, measured), fitted), (lower, upper)) in channel_names(o)
        .iter()
        .zip(o.record.responses())
        .zip(&o.fitted)
        .zip(bands)
    {
        panels.push(Panel {
            title: name.replace('_', " on mass "),
            x_desc: "time t [s]".into(),
            y_desc: axis(name),
            x_range: range,
            curves: vec![
                Curve {
                    label: "measured".into(),
                    x: &time,
                    y: measured.to_vec(),
                    style: Style::Points(BLUE, 2),
                },
                Curve {
                    label: "model".into(),
                    x: &time,
                    y: fitted.clone(),
                    // Thin, so that the measured points stay visible under it.
                    style: Style::Line(RED, 1),
                },
            ],
            band: Some(Band {
                label: format!("Monte Carlo ±10 % ({} draws)", o.band.samples),
                x: &time,
                lower: lower.clone(),
                upper: upper.clone(),
            }),
            legend: Some(SeriesLabelPosition::UpperRight),
        });
    }
    let lowest = (o.fit.parameters.modes().iter())
        .map(|m| m.natural_frequency_hz.value)
        .filter(|f| f.is_finite() && *f > 0.0)
        .fold(f64::INFINITY, f64::min);
    let figure = Stack {
        name: "chain_fit",
        title: format!("Chain fit — {}", o.config.name),
        panels,
    }
    .windowed(range, lowest);
    let spectra = noise_spectra(o);
    let drawn: Vec<&dyn Drawable> = std::iter::once(&figure as &dyn Drawable)
        .chain(spectra.iter().map(|f| f as &dyn Drawable))
        .collect();
    save_all(&drawn, dir)?;
    Ok(drawn.iter().map(|f| f.file_name()).collect())
}

/// Each sensor's residual spectrum against the noise model's.
fn noise_spectra(o: &ChainOutcome) -> Option<NoiseSpectra<'_>> {
    let panels: Vec<SpectrumPanel<'_>> = (o.fit.whiteness.iter())
        .zip(channel_names(o))
        .filter_map(|(check, name)| {
            Some(SpectrumPanel {
                title: name.replace('_', " on mass "),
                unit: unit(&name).into(),
                spectrum: check.spectrum.as_ref()?,
            })
        })
        .collect();
    (!panels.is_empty()).then(|| NoiseSpectra {
        name: "chain_noise_spectrum",
        title: format!(
            "Residual spectra against the noise model — {}",
            o.config.name
        ),
        panels,
    })
}

/// "acceleration [m/s²]" for a channel named "acceleration_2".
fn axis(name: &str) -> String {
    let quantity = name.split('_').next().unwrap_or("response");
    format!("{quantity} [{}]", unit(name))
}

/// "m/s²" for a channel named "acceleration_2".
fn unit(name: &str) -> &'static str {
    match name.split('_').next() {
        Some("displacement") => "m",
        Some("velocity") => "m/s",
        _ => "m/s²",
    }
}
