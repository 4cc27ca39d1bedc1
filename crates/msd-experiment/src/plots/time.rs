//! The time-domain figures: the paper's Figures 2, 3 and 4.

use super::{
    BLUE, DARK, Draw, Figure, GRAY, ORANGE, RED, Units, draw_legend, house_mesh, limits, scaled,
    suptitle, text, thin_line, thin_points, tick, title_style,
};
use crate::pipeline::Outcome;
use plotters::coord::Shift;
use plotters::prelude::*;

/// Most points of a drawn line (twice the pixel width: min and max per column).
const LINE_POINTS: usize = 8000;
/// Most markers drawn per series.
const MARKERS: usize = 4000;
/// More periods of the natural frequency than this in a record earn a zoomed panel.
const ZOOM_PERIODS: f64 = 60.0;
/// Periods shown in a zoomed panel.
const ZOOM_WINDOW_PERIODS: f64 = 25.0;

/// How a curve is drawn.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Style {
    /// Solid line of a width.
    Line(RGBColor, u32),
    /// Dashed line of a width.
    Dashed(RGBColor, u32),
    /// Markers of a radius.
    Points(RGBColor, u32),
}

/// One curve of a panel.
pub(crate) struct Curve<'a> {
    pub label: String,
    pub x: &'a [f64],
    pub y: Vec<f64>,
    pub style: Style,
}

/// A shaded band between two curves.
pub(crate) struct Band<'a> {
    pub label: String,
    pub x: &'a [f64],
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
}

/// One panel of time series.
pub(crate) struct Panel<'a> {
    pub title: String,
    pub x_desc: String,
    pub y_desc: String,
    pub x_range: (f64, f64),
    pub curves: Vec<Curve<'a>>,
    pub band: Option<Band<'a>>,
    pub legend: Option<SeriesLabelPosition>,
}

fn window<'a>(x: &'a [f64], y: &[f64], range: (f64, f64)) -> (&'a [f64], Vec<f64>) {
    let a = x.partition_point(|t| *t < range.0);
    let b = x.partition_point(|t| *t <= range.1);
    (&x[a..b], y[a..b].to_vec())
}

impl<'a> Panel<'a> {
    /// The same panel restricted to the times in `range`.
    pub(crate) fn zoomed(&self, range: (f64, f64), title: String) -> Panel<'a> {
        Panel {
            title,
            x_desc: self.x_desc.clone(),
            y_desc: self.y_desc.clone(),
            x_range: range,
            curves: self
                .curves
                .iter()
                .map(|c| {
                    let (x, y) = window(c.x, &c.y, range);
                    Curve {
                        label: c.label.clone(),
                        x,
                        y,
                        style: c.style,
                    }
                })
                .collect(),
            band: self.band.as_ref().map(|b| {
                let (x, lower) = window(b.x, &b.lower, range);
                let (_, upper) = window(b.x, &b.upper, range);
                Band {
                    label: b.label.clone(),
                    x,
                    lower,
                    upper,
                }
            }),
            legend: self.legend.clone(),
        }
    }

    /// Draws the panel on `area`.
    pub(crate) fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Draw {
        let band_series: Vec<&[f64]> = self
            .band
            .iter()
            .flat_map(|b| [b.lower.as_slice(), b.upper.as_slice()])
            .collect();
        let (lo, hi) = limits(
            self.curves
                .iter()
                .map(|c| c.y.as_slice())
                .chain(band_series),
        );
        let mut chart = ChartBuilder::on(area)
            .caption(&self.title, title_style())
            .margin(14)
            .margin_right(28)
            .x_label_area_size(52)
            .y_label_area_size(86)
            .build_cartesian_2d(self.x_range.0..self.x_range.1, lo..hi)
            .map_err(text)?;
        house_mesh(&mut chart.configure_mesh())
            .x_desc(self.x_desc.as_str())
            .y_desc(self.y_desc.as_str())
            .x_labels(12)
            .y_labels(7)
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .draw()
            .map_err(text)?;
        if let Some(b) = &self.band {
            let upper = thin_line(b.x, &b.upper, LINE_POINTS);
            let lower = thin_line(b.x, &b.lower, LINE_POINTS);
            let outline: Vec<(f64, f64)> =
                upper.into_iter().chain(lower.into_iter().rev()).collect();
            let fill = GRAY.mix(0.45);
            chart
                .draw_series(std::iter::once(Polygon::new(outline, fill.filled())))
                .map_err(text)?
                .label(b.label.as_str())
                .legend(move |(x, y)| Rectangle::new([(x, y - 7), (x + 24, y + 7)], fill.filled()));
        }
        for c in &self.curves {
            match c.style {
                Style::Points(color, radius) => {
                    let style = color.mix(0.55).filled();
                    let anno = chart
                        .draw_series(
                            thin_points(c.x, &c.y, MARKERS)
                                .into_iter()
                                .map(move |p| Circle::new(p, radius, style)),
                        )
                        .map_err(text)?;
                    // An empty label: no legend entry (e.g. a fit drawn over its data).
                    if !c.label.is_empty() {
                        anno.label(c.label.as_str())
                            .legend(move |(x, y)| Circle::new((x + 12, y), 4, color.filled()));
                    }
                }
                Style::Line(color, width) => {
                    let anno = chart
                        .draw_series(LineSeries::new(
                            thin_line(c.x, &c.y, LINE_POINTS),
                            color.stroke_width(width),
                        ))
                        .map_err(text)?;
                    // An empty label: no legend entry (e.g. a fit drawn over its data).
                    if !c.label.is_empty() {
                        anno.label(c.label.as_str()).legend(move |(x, y)| {
                            PathElement::new(
                                vec![(x, y), (x + 24, y)],
                                color.stroke_width(width + 1),
                            )
                        });
                    }
                }
                Style::Dashed(color, width) => {
                    let anno = chart
                        .draw_series(DashedLineSeries::new(
                            thin_line(c.x, &c.y, LINE_POINTS),
                            9,
                            6,
                            color.stroke_width(width),
                        ))
                        .map_err(text)?;
                    // An empty label: no legend entry (e.g. a fit drawn over its data).
                    if !c.label.is_empty() {
                        anno.label(c.label.as_str()).legend(move |(x, y)| {
                            PathElement::new(
                                vec![(x, y), (x + 10, y)],
                                color.stroke_width(width + 1),
                            )
                        });
                    }
                }
            }
        }
        if let Some(position) = self.legend.clone() {
            draw_legend(&mut chart, position)?;
        }
        Ok(())
    }
}

/// The measurements of a record, in display units.
fn measured<'a>(t: &'a [f64], y: &[f64], u: &Units, style: Style) -> Curve<'a> {
    Curve {
        label: "measured".into(),
        x: t,
        y: scaled(y, u.output_factor),
        style,
    }
}

/// The zoom window of a long record, or `None` when the whole record is readable.
pub(crate) fn zoom_range(outcome: &Outcome, x: &[f64], from: usize) -> Option<(f64, f64)> {
    let fnat = outcome.estimate.parameters.natural_frequency_hz();
    let (first, last) = (*x.first()?, *x.last()?);
    if (last - first) * fnat <= ZOOM_PERIODS || !fnat.is_finite() {
        return None;
    }
    let start = x[from.min(x.len() - 1)];
    Some((start, (start + ZOOM_WINDOW_PERIODS / fnat).min(last)))
}

/// Figure 2: excitation (top), measurement and model fit (middle), residuals (bottom).
pub(crate) struct Identification<'a> {
    panels: [Panel<'a>; 3],
    title: String,
}

impl<'a> Identification<'a> {
    pub(crate) fn new(o: &'a Outcome, u: &Units) -> Self {
        let d = &o.data.identification;
        let t = d.excitation.times();
        let range = (t[0], t[t.len() - 1]);
        let e = &o.estimate;
        let x_desc = "time t [s]".to_string();
        let excitation = Panel {
            title: "Excitation".into(),
            x_desc: x_desc.clone(),
            y_desc: format!("{} [{}]", u.input_name, u.input),
            x_range: range,
            curves: vec![Curve {
                label: "F(t)".into(),
                x: t,
                y: d.excitation.samples().to_vec(),
                style: Style::Line(BLUE, 2),
            }],
            band: None,
            legend: None,
        };
        let fit = Panel {
            title: format!(
                "Model fit to identification data (R² = {:.4}, fit {:.1} %)",
                e.fit.r_squared, e.fit.fit_percent
            ),
            x_desc: x_desc.clone(),
            y_desc: format!("{} [{}]", u.output_name, u.output),
            x_range: range,
            curves: vec![
                measured(t, &d.output, u, Style::Points(BLUE, 2)),
                Curve {
                    label: "model fit".into(),
                    x: t,
                    y: scaled(&e.model_output, u.output_factor),
                    style: Style::Line(RED, 2),
                },
            ],
            band: None,
            legend: Some(SeriesLabelPosition::UpperRight),
        };
        let residuals = Panel {
            title: format!(
                "Residuals r = y − model (RMS {} {})",
                crate::fmt::sig(e.fit.residual_rms * u.output_factor, 3),
                u.output
            ),
            x_desc,
            y_desc: format!("residual [{}]", u.output),
            x_range: range,
            curves: vec![Curve {
                label: "residual".into(),
                x: t,
                y: scaled(&e.residuals, u.output_factor),
                style: Style::Points(DARK, 2),
            }],
            band: None,
            legend: None,
        };
        let mut panels = [excitation, fit, residuals];
        if zoom_range(o, t, 0).is_some() {
            // A long record shows as envelopes: lines instead of markers.
            for panel in &mut panels {
                for c in &mut panel.curves {
                    c.style = match c.style {
                        Style::Points(color, _)
                        | Style::Dashed(color, _)
                        | Style::Line(color, _) => Style::Line(color, 1),
                    };
                }
            }
        }
        Self {
            panels,
            title: format!(
                "Identification — {} by {} on {}",
                o.config.name,
                crate::fmt::method_name(e.method),
                e.backend.name()
            ),
        }
    }
}

impl Figure for Identification<'_> {
    fn name(&self) -> &'static str {
        "fig2_identification"
    }
    fn size(&self) -> (u32, u32) {
        (1400, 1150)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let area = suptitle(root, &self.title)?;
        let h = area.dim_in_pixel().1 as i32;
        let (top, rest) = area.split_vertically(h * 27 / 100);
        let (middle, bottom) = rest.split_vertically(h * 44 / 100);
        self.panels[0].draw(&top)?;
        self.panels[1].draw(&middle)?;
        self.panels[2].draw(&bottom)
    }
}

/// A figure of one time panel, with a zoomed copy below it for a long record.
pub(crate) struct PanelFigure<'a> {
    /// File name without extension.
    pub name: &'static str,
    /// The figure's title.
    pub title: String,
    /// The whole record.
    pub panel: Panel<'a>,
    /// A window of it, for a long record.
    pub zoom: Option<Panel<'a>>,
}

impl Figure for PanelFigure<'_> {
    fn name(&self) -> &'static str {
        self.name
    }
    fn size(&self) -> (u32, u32) {
        if self.zoom.is_some() {
            (1400, 1100)
        } else {
            (1400, 720)
        }
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let area = suptitle(root, &self.title)?;
        match &self.zoom {
            None => self.panel.draw(&area),
            Some(zoom) => {
                let h = area.dim_in_pixel().1 as i32;
                let (top, bottom) = area.split_vertically(h / 2);
                self.panel.draw(&top)?;
                zoom.draw(&bottom)
            }
        }
    }
}

/// Figure 3: validation measurements, model prediction, true response.
pub(crate) fn validation<'a>(o: &'a Outcome, u: &Units) -> PanelFigure<'a> {
    let d = &o.data.validation;
    let v = &o.validation;
    let t = d.excitation.times();
    let mut curves = vec![measured(t, &d.output, u, Style::Points(BLUE, 2))];
    if let Some(truth) = &o.data.validation_truth {
        curves.push(Curve {
            label: "true response".into(),
            x: t,
            y: scaled(truth, u.output_factor),
            style: Style::Line(ORANGE, 3),
        });
    }
    curves.push(Curve {
        label: "model prediction".into(),
        x: t,
        y: scaled(&v.model_output, u.output_factor),
        style: Style::Dashed(BLACK, 2),
    });
    let panel = Panel {
        title: format!(
            "Validation on data never used for fitting (R² = {:.4}, fit {:.1} %, RMS error {} {})",
            v.fit.r_squared,
            v.fit.fit_percent,
            crate::fmt::sig(v.fit.residual_rms * u.output_factor, 3),
            u.output
        ),
        x_desc: "time t [s]".into(),
        y_desc: format!("{} [{}]", u.output_name, u.output),
        x_range: (t[0], t[t.len() - 1]),
        curves,
        band: None,
        legend: Some(SeriesLabelPosition::UpperRight),
    };
    let zoom = zoom_range(o, t, v.scored_from)
        .map(|r| panel.zoomed(r, format!("Zoom: {:.2} s … {:.2} s", r.0, r.1)));
    // A long record shows as envelopes: the measurement and the simulation error.
    let panel = if zoom.is_some() {
        Panel {
            curves: vec![
                measured(t, &d.output, u, Style::Line(BLUE, 1)),
                Curve {
                    label: "simulation error (measured − model)".into(),
                    x: t,
                    y: scaled(&v.residuals, u.output_factor),
                    style: Style::Line(RED, 1),
                },
            ],
            ..panel
        }
    } else {
        panel
    };
    PanelFigure {
        name: "fig3_validation",
        panel,
        zoom,
        title: format!("Validation — {}", o.config.name),
    }
}

/// Figure 4: Monte Carlo band, nominal prediction, measurements.
pub(crate) fn monte_carlo<'a>(o: &'a Outcome, u: &Units) -> Option<PanelFigure<'a>> {
    let mc = o.monte_carlo.as_ref()?;
    let d = &o.data.validation;
    let t = d.excitation.times();
    let [p_lo, p_hi] = mc.percentiles;
    let panel = Panel {
        title: format!(
            "{:.0} % band of {} draws within ±{:.0} % of the estimate: it holds {:.1} % of the measurements",
            p_hi - p_lo,
            mc.samples,
            mc.spread * 100.0,
            mc.coverage * 100.0
        ),
        x_desc: "time t [s]".into(),
        y_desc: format!("{} [{}]", u.output_name, u.output),
        x_range: (t[0], t[t.len() - 1]),
        curves: vec![
            measured(t, &d.output, u, Style::Points(BLUE, 2)),
            Curve {
                label: "nominal prediction (estimate)".into(),
                x: t,
                y: scaled(&mc.nominal, u.output_factor),
                style: Style::Line(BLACK, 2),
            },
        ],
        band: Some(Band {
            label: format!("{p_lo:.0}–{p_hi:.0} percentile band"),
            x: t,
            lower: scaled(&mc.lower, u.output_factor),
            upper: scaled(&mc.upper, u.output_factor),
        }),
        legend: Some(SeriesLabelPosition::UpperRight),
    };
    let zoom = zoom_range(o, t, o.validation.scored_from)
        .map(|r| panel.zoomed(r, format!("Zoom: {:.2} s … {:.2} s", r.0, r.1)));
    // A long record shows deviations from the nominal prediction: the band around
    // zero and the measurements' departure from it.
    let panel = if zoom.is_some() {
        let minus = |v: &[f64]| -> Vec<f64> {
            v.iter()
                .zip(&mc.nominal)
                .map(|(a, n)| (a - n) * u.output_factor)
                .collect()
        };
        Panel {
            title: format!(
                "Deviation from the nominal prediction: the {:.0} % band holds {:.1} % of the measurements",
                p_hi - p_lo,
                mc.coverage * 100.0
            ),
            y_desc: format!("deviation [{}]", u.output),
            curves: vec![Curve {
                label: "measured − nominal".into(),
                x: t,
                y: minus(&d.output),
                style: Style::Line(BLUE, 1),
            }],
            band: Some(Band {
                label: format!("{p_lo:.0}–{p_hi:.0} percentile band − nominal"),
                x: t,
                lower: minus(&mc.lower),
                upper: minus(&mc.upper),
            }),
            ..panel
        }
    } else {
        panel
    };
    Some(PanelFigure {
        name: "fig4_monte_carlo",
        panel,
        zoom,
        title: format!("Monte Carlo robustness — {}", o.config.name),
    })
}
