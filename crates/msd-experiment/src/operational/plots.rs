//! The figure of an operational run, PNG and SVG in the house style: for SSI,
//! `oma_stabilization` (the poles by model order, the poles that formed each mode marked,
//! the modes' frequencies dashed, the first singular value of the output spectral matrix
//! behind); for EFDD, `oma_singular_values` (the first singular values in dB, the picked
//! peaks and the modes).

use super::OperationalOutcome;
use crate::error::Result;
use crate::plots::diagram::Stabilization;
use crate::plots::panel::{Curve, Panel, PanelFigure, Style};
use crate::plots::{BLUE, DARK, GRAY, ORANGE, RED, register_fonts, save};
use msd_modal::{SingularSpectrum, singular_spectrum};
use plotters::prelude::SeriesLabelPosition;
use std::path::Path;

/// Writes the figure; returns its base name.
pub(crate) fn write_all(o: &OperationalOutcome, dir: &Path) -> Result<Vec<&'static str>> {
    register_fonts();
    if let Some(spectrum) = &o.fit.spectrum {
        let lines: Vec<[f64; 2]> = o
            .fit
            .modes
            .iter()
            .map(|m| [m.natural_frequency_hz.value; 2])
            .collect();
        save(&singular_values(o, spectrum, &lines), dir)?;
        return Ok(vec!["oma_singular_values"]);
    }
    let behind = singular_spectrum(&o.record, None, Some(o.fit.diagram.band_hz))
        .map(|s| {
            s.frequency_hz
                .iter()
                .copied()
                .zip(s.singular_values[0].iter().copied())
                .collect()
        })
        .unwrap_or_default();
    save(
        &Stabilization {
            diagram: &o.fit.diagram,
            behind,
            name: "oma_stabilization",
            title: "Stabilization diagram (SSI-cov poles by model order)",
            behind_label: "first singular value of the output spectral matrix (CMIF, log scale)",
            view_hz: view(o),
        },
        dir,
    )?;
    Ok(vec!["oma_stabilization"])
}

/// EFDD's figure: the singular values in dB over the band shown, the peaks picked
/// (markers) and each mode's fn (a dashed line).
fn singular_values<'a>(
    o: &OperationalOutcome,
    spectrum: &'a SingularSpectrum,
    mode_lines: &'a [[f64; 2]],
) -> PanelFigure<'a> {
    let [low, high] = view(o).unwrap_or(o.fit.diagram.band_hz);
    // dB, no lower than 80 dB under the first singular value's highest line in view.
    let in_view = |f: &f64| (low..=high).contains(f);
    let top = spectrum
        .frequency_hz
        .iter()
        .zip(&spectrum.singular_values[0])
        .filter(|(f, _)| in_view(f))
        .map(|(_, v)| 10.0 * v.max(1e-300).log10())
        .fold(f64::MIN, f64::max);
    let db = |v: &[f64]| -> Vec<f64> {
        v.iter()
            .map(|x| (10.0 * x.max(1e-300).log10()).max(top - 80.0))
            .collect()
    };
    let colours = [BLUE, ORANGE, GRAY];
    let mut curves: Vec<Curve<'a>> = spectrum
        .singular_values
        .iter()
        .zip(colours)
        .enumerate()
        .map(|(k, (values, colour))| Curve {
            label: format!("singular value {}", k + 1),
            x: &spectrum.frequency_hz,
            y: db(values),
            style: Style::Line(colour, if k == 0 { 2 } else { 1 }),
        })
        .collect();
    let visible = |y: &[f64]| -> Vec<f64> {
        spectrum
            .frequency_hz
            .iter()
            .zip(y)
            .filter(|(f, _)| (low..=high).contains(*f))
            .map(|(_, v)| *v)
            .collect()
    };
    let first = curves[0].y.clone();
    let bottom = curves
        .iter()
        .flat_map(|c| visible(&c.y))
        .fold(f64::MAX, f64::min);
    let at_peaks: Vec<f64> = spectrum
        .peaks_hz
        .iter()
        .map(|f| {
            let j = spectrum.frequency_hz.partition_point(|x| x < f);
            first.get(j).copied().unwrap_or(top)
        })
        .collect();
    curves.push(Curve {
        label: "peaks picked".into(),
        x: &spectrum.peaks_hz,
        y: at_peaks,
        style: Style::Points(DARK, 5),
    });
    for (k, x) in mode_lines.iter().enumerate() {
        curves.push(Curve {
            label: if k == 0 {
                "modes (EFDD fn)".into()
            } else {
                String::new()
            },
            x,
            y: vec![bottom, top + 3.0],
            style: Style::Dashed(RED, 1),
        });
    }
    PanelFigure {
        name: "oma_singular_values",
        title: "Singular values of the output spectral matrix (FDD), peaks and EFDD modes".into(),
        panel: Panel {
            title: String::new(),
            x_desc: "frequency f [Hz]".into(),
            y_desc: "singular value [dB re 1/Hz, unit-variance channels]".into(),
            x_range: (low, high),
            curves,
            band: None,
            legend: Some(SeriesLabelPosition::LowerRight),
        },
        zoom: None,
    }
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
