//! `design`: the designed force over time, its lines over the prior plant's frequency
//! response, and its predicted standard errors beside the reference input's.

use super::{
    BLUE, DARK, Draw, Figure, GRAY, ORANGE, RED, draw_legend, house_mesh, limits, suptitle, text,
    thin_line, tick, title_style,
};
use msd_ident::design::Design;
use msd_signal::Signal;
use plotters::coord::Shift;
use plotters::prelude::*;

/// The figure `design`.
pub(crate) struct DesignFigure<'a> {
    design: &'a Design,
}

impl<'a> DesignFigure<'a> {
    pub(crate) fn new(design: &'a Design) -> Self {
        Self { design }
    }

    /// (frequency, amplitude) of every sine of the design.
    fn lines(&self) -> Vec<(f64, f64)> {
        let Signal::Sum { terms } = &self.design.signal else {
            return Vec::new();
        };
        (terms.iter())
            .filter_map(|t| match t {
                Signal::Sine {
                    amplitude,
                    frequency,
                    ..
                } => Some((*frequency, *amplitude)),
                _ => None,
            })
            .collect()
    }
}

impl Figure for DesignFigure<'_> {
    fn name(&self) -> &'static str {
        "design"
    }
    fn size(&self) -> (u32, u32) {
        (1400, 1200)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let d = self.design;
        let title = format!(
            "{} input design: det(cov)^(1/6) ratio {:.3} to the reference",
            d.criterion, d.comparison.determinant_ratio
        );
        let area = suptitle(root, &title)?;
        let h = area.dim_in_pixel().1 as i32;
        let (top, rest) = area.split_vertically(h / 3);
        let (middle, bottom) = rest.split_vertically(h / 3);
        self.force(&top)?;
        self.spectrum(&middle)?;
        self.errors(&bottom)
    }
}

impl DesignFigure<'_> {
    fn force<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Draw {
        let e = &self.design.excitation;
        let (t, u) = (e.times(), e.samples());
        let (lo, hi) = limits([u]);
        let caption = format!(
            "Force: peak {:.3} N, RMS {:.3} N; peak stroke {:.4} m on the prior",
            self.design.peak_force, self.design.rms_force, self.design.peak_stroke
        );
        let mut chart = ChartBuilder::on(area)
            .caption(caption, title_style())
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(80)
            .build_cartesian_2d(t[0]..t[t.len() - 1], lo..hi)
            .map_err(text)?;
        house_mesh(&mut chart.configure_mesh())
            .x_desc("t (s)")
            .y_desc("F (N)")
            .y_label_formatter(&tick)
            .draw()
            .map_err(text)?;
        chart
            .draw_series(LineSeries::new(thin_line(t, u, 2000), BLUE.stroke_width(1)))
            .map_err(text)?;
        Ok(())
    }

    fn spectrum<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Draw {
        let lines = self.lines();
        let top = lines.iter().fold(1e-12f64, |m, l| m.max(l.1));
        let f_max = lines.iter().fold(0.1f64, |m, l| m.max(l.0)) * 1.05;
        let p = self.design.plants[0];
        let magnitude = |f: f64| {
            let w = std::f64::consts::TAU * f;
            1.0 / (p.stiffness - p.mass * w * w).hypot(p.damping * w)
        };
        let dense: Vec<(f64, f64)> = (0..=600)
            .map(|i| f_max * i as f64 / 600.0)
            .map(|f| (f, magnitude(f)))
            .collect();
        let peak = dense.iter().fold(0.0f64, |m, v| m.max(v.1));
        let mut chart = ChartBuilder::on(area)
            .caption(
                "Lines of the design over the prior plant's |H| (scaled to the largest line)",
                title_style(),
            )
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..f_max, 0.0..top * 1.1)
            .map_err(text)?;
        house_mesh(&mut chart.configure_mesh())
            .x_desc("f (Hz)")
            .y_desc("amplitude (N)")
            .y_label_formatter(&tick)
            .draw()
            .map_err(text)?;
        chart
            .draw_series(
                lines
                    .iter()
                    .map(|&(f, a)| PathElement::new(vec![(f, 0.0), (f, a)], BLUE.stroke_width(3))),
            )
            .map_err(text)?
            .label("line amplitude")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE.stroke_width(3)));
        chart
            .draw_series(LineSeries::new(
                dense.iter().map(|&(f, m)| (f, m / peak * top)),
                ORANGE.stroke_width(2),
            ))
            .map_err(text)?
            .label("prior plant |H| (scaled)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], ORANGE.stroke_width(2)));
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    }

    fn errors<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Draw {
        let c = &self.design.comparison;
        let relative = |s: &[f64; 3], i: usize| s[i] / c.reference[i];
        let caption = format!(
            "Predicted standard errors over the reference's: geometric mean {:.3}, worst {:.3}",
            c.geometric_mean_ratio, c.worst_ratio
        );
        let mut chart = ChartBuilder::on(area)
            .caption(caption, title_style())
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(80)
            .build_cartesian_2d(-0.5..2.5, 0.0..1.3 * c.worst_ratio.max(1.0))
            .map_err(text)?;
        let names = ["m", "c", "k"];
        house_mesh(&mut chart.configure_mesh())
            .x_labels(3)
            .x_label_formatter(&|x: &f64| {
                names
                    .get(x.round() as usize)
                    .map_or(String::new(), |n| n.to_string())
            })
            .y_desc("SE / reference SE")
            .y_label_formatter(&tick)
            .draw()
            .map_err(text)?;
        let bar = |i: usize, offset: f64, v: f64| {
            [
                (i as f64 + offset - 0.18, 0.0),
                (i as f64 + offset + 0.18, v),
            ]
        };
        chart
            .draw_series((0..3).map(|i| Rectangle::new(bar(i, -0.2, 1.0), GRAY.filled())))
            .map_err(text)?
            .label("reference input")
            .legend(|(x, y)| Rectangle::new([(x, y - 6), (x + 20, y + 6)], GRAY.filled()));
        chart
            .draw_series(
                (0..3).map(|i| Rectangle::new(bar(i, 0.2, relative(&c.design, i)), RED.filled())),
            )
            .map_err(text)?
            .label("design")
            .legend(|(x, y)| Rectangle::new([(x, y - 6), (x + 20, y + 6)], RED.filled()));
        chart
            .draw_series(
                (0..3).map(|i| {
                    Rectangle::new(bar(i, 0.2, relative(&c.design, i)), DARK.stroke_width(1))
                }),
            )
            .map_err(text)?;
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}
