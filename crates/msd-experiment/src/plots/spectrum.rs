//! The noise-spectrum figure of every time-domain fit of measured data (setups,
//! chains): each channel's residual spectrum, band-averaged, against the noise model's
//! (the sensor's white noise plus the drive's seen through the plant) and the 95 % range
//! a band's mean takes under it. Where the residual leaves that range over several bands,
//! the model leaves colour unexplained.

use super::{
    BLUE, DARK, Draw, Figure, GRAY, ORANGE, RED, draw_legend, house_mesh, log_frequency_axis,
    suptitle, text, title_style,
};
use msd_ident::records::ResidualSpectrum;
use plotters::coord::Shift;
use plotters::prelude::*;

/// One channel's panel.
pub(crate) struct SpectrumPanel<'a> {
    /// The panel's title: the channel and its record.
    pub title: String,
    /// The channel's unit ("m/s²").
    pub unit: String,
    pub spectrum: &'a ResidualSpectrum,
}

/// The figure: one log–log panel per channel, stacked.
pub(crate) struct NoiseSpectra<'a> {
    /// The file's base name.
    pub name: &'static str,
    pub title: String,
    pub panels: Vec<SpectrumPanel<'a>>,
}

impl Figure for NoiseSpectra<'_> {
    fn name(&self) -> &'static str {
        self.name
    }
    fn size(&self) -> (u32, u32) {
        (1400, 120 + 460 * self.panels.len().max(1) as u32)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let area = suptitle(root, &self.title)?;
        let parts = area.split_evenly((self.panels.len().max(1), 1));
        for (panel, part) in self.panels.iter().zip(&parts) {
            panel.draw(part)?;
        }
        Ok(())
    }
}

/// The share of a panel's height (in decades) the data take: the legend sits above them.
const DATA_SHARE: f64 = 0.62;

impl SpectrumPanel<'_> {
    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Draw {
        let s = self.spectrum;
        let f = &s.frequency_hz;
        let (Some(&f0), Some(&f1)) = (f.first(), f.last()) else {
            return Ok(());
        };
        let model = s.model();
        let fitted = s.drive.iter().any(|d| *d > 0.0);
        let positive = (s
            .residual
            .iter()
            .chain(&model)
            .chain(&s.lower)
            .chain(&s.upper))
        .copied()
        .filter(|v| v.is_finite() && *v > 0.0);
        let (lo, hi) = positive.fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
        if !(lo.is_finite() && hi > lo) || f1 <= f0 {
            return Ok(());
        }
        // The data in the lower part of the panel, the legend above them.
        let (lo, hi) = (lo / 1.5, hi * 1.5);
        let top = lo * (hi / lo).powf(1.0 / DATA_SHARE);
        let mut chart = ChartBuilder::on(area)
            .caption(&self.title, title_style())
            .margin(14)
            .margin_right(28)
            .x_label_area_size(52)
            .y_label_area_size(96)
            .build_cartesian_2d(log_frequency_axis(f0, f1), (lo..top).log_scale())
            .map_err(text)?;
        house_mesh(&mut chart.configure_mesh())
            .x_desc("frequency f [Hz]")
            .y_desc(format!("residual PSD [{}/Hz]", squared(&self.unit)))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .x_label_formatter(&|v| format!("{v}"))
            .draw()
            .map_err(text)?;
        let fill = GRAY.mix(0.35);
        let outline: Vec<(f64, f64)> = (f.iter().copied().zip(s.upper.iter().copied()))
            .chain(f.iter().copied().zip(s.lower.iter().copied()).rev())
            .map(|(x, y)| (x, y.clamp(lo, top)))
            .collect();
        chart
            .draw_series(std::iter::once(Polygon::new(outline, fill.filled())))
            .map_err(text)?
            .label("95 % range of a band's mean under the model")
            .legend(move |(x, y)| Rectangle::new([(x, y - 7), (x + 24, y + 7)], fill.filled()));
        let points = f.iter().copied().zip(s.residual.iter().copied());
        chart
            .draw_series(LineSeries::new(
                points.clone(),
                BLUE.mix(0.6).stroke_width(1),
            ))
            .map_err(text)?;
        chart
            .draw_series(points.map(|p| Circle::new(p, 3, BLUE.filled())))
            .map_err(text)?
            .label("residual, averaged over bands of lines")
            .legend(|(x, y)| Circle::new((x + 12, y), 4, BLUE.filled()));
        let (label, parts) = if fitted {
            ("noise model: sensor + drive through the plant", true)
        } else {
            ("white level the intervals assume", false)
        };
        let line = |values: &[f64]| -> Vec<(f64, f64)> {
            (f.iter().copied().zip(values.iter().copied()))
                .filter(|(_, y)| *y >= lo)
                .collect()
        };
        chart
            .draw_series(LineSeries::new(line(&model), RED.stroke_width(2)))
            .map_err(text)?
            .label(label)
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], RED.stroke_width(3)));
        if parts {
            let flat = vec![s.sensor; f.len()];
            for (values, colour, label) in [
                (&flat, DARK, "of which the sensor's white noise"),
                (
                    &s.drive,
                    ORANGE,
                    "of which the drive's noise through the plant",
                ),
            ] {
                chart
                    .draw_series(DashedLineSeries::new(
                        line(values),
                        9,
                        6,
                        colour.stroke_width(2),
                    ))
                    .map_err(text)?
                    .label(label)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 10, y)], colour.stroke_width(3))
                    });
            }
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

/// A unit squared: "m²", "(m/s²)²".
fn squared(unit: &str) -> String {
    if unit.chars().all(char::is_alphabetic) {
        format!("{unit}²")
    } else {
        format!("({unit})²")
    }
}
