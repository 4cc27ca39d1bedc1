//! Panels of time series (curves, a shaded band, a legend, a zoomed copy) and the
//! figure of one panel: the pieces of every time-domain figure.

use super::{
    Draw, Figure, GRAY, draw_legend, house_mesh, limits, suptitle, text, thin_line, thin_points,
    tick, title_style,
};
use plotters::coord::Shift;
use plotters::prelude::*;

/// Most points of a drawn line (twice the pixel width: min and max per column).
const LINE_POINTS: usize = 8000;
/// Most markers drawn per series.
const MARKERS: usize = 4000;
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
        let limits = limits(
            self.curves
                .iter()
                .map(|c| c.y.as_slice())
                .chain(band_series),
        );
        let (legend, (lo, hi)) = match self.legend.clone() {
            Some(preferred) => {
                let (position, limits) = self.legend_place(area.dim_in_pixel(), limits, preferred);
                (Some(position), limits)
            }
            None => (None, limits),
        };
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
        if let Some(position) = legend {
            draw_legend(&mut chart, position)?;
        }
        Ok(())
    }

    /// Where the legend covers no data, and the y-limits that make room for it: the
    /// `preferred` corner when it is clear, else the clearest corner with no point under
    /// it, else the upper right with the axis raised above the data by the legend's
    /// height (a legend never hides data). `area` is the panel's size in pixels.
    fn legend_place(
        &self,
        (width, height): (u32, u32),
        (lo, hi): (f64, f64),
        preferred: SeriesLabelPosition,
    ) -> (SeriesLabelPosition, (f64, f64)) {
        let labels: Vec<&str> = (self.band.iter().map(|b| b.label.as_str()))
            .chain(self.curves.iter().map(|c| c.label.as_str()))
            .filter(|l| !l.is_empty())
            .collect();
        let longest = labels.iter().map(|l| l.chars().count()).max().unwrap_or(0);
        // The plot area and the legend box (its margin included), in pixels, as the
        // chart above lays them out (label areas, margins, the caption's line).
        let plot_w = f64::from(width.saturating_sub(86 + 28 + 28)).max(1.0);
        let plot_h = f64::from(height.saturating_sub(52 + 28 + 34)).max(1.0);
        let box_w = (12.0 + 34.0 + 9.0 * longest as f64 + 24.0) / plot_w;
        let box_h = (22.0 * labels.len() as f64 + 14.0 + 12.0) / plot_h;
        if labels.is_empty() || box_w >= 1.0 || box_h >= 0.6 {
            return (preferred, (lo, hi));
        }
        let (x0, x1) = self.x_range;
        let covered = |right: bool, upper: bool| {
            let (xa, xb) = if right {
                (x1 - box_w * (x1 - x0), x1)
            } else {
                (x0, x0 + box_w * (x1 - x0))
            };
            let (ya, yb) = if upper {
                (hi - box_h * (hi - lo), hi)
            } else {
                (lo, lo + box_h * (hi - lo))
            };
            let inside = |x: f64, y: f64| (xa..=xb).contains(&x) && (ya..=yb).contains(&y);
            let bands = self.band.iter().flat_map(|b| {
                let rows = b.x.iter().zip(b.lower.iter().zip(&b.upper));
                rows.filter(move |(x, (l, u))| {
                    inside(**x, **l)
                        || inside(**x, **u)
                        || ((xa..=xb).contains(*x) && **l <= ya && **u >= yb)
                })
            });
            let points = self
                .curves
                .iter()
                .flat_map(|c| c.x.iter().zip(&c.y))
                .filter(|(x, y)| inside(**x, **y));
            points.count() + bands.count()
        };
        use SeriesLabelPosition::{LowerLeft, LowerRight, UpperLeft, UpperRight};
        let corner = |p: &SeriesLabelPosition| match p {
            UpperRight => Some((true, true)),
            UpperLeft => Some((false, true)),
            LowerRight => Some((true, false)),
            LowerLeft => Some((false, false)),
            _ => None,
        };
        let order = [
            preferred.clone(),
            UpperRight,
            UpperLeft,
            LowerRight,
            LowerLeft,
        ];
        if let Some(clear) = order
            .into_iter()
            .find(|p| corner(p).is_some_and(|(right, upper)| covered(right, upper) == 0))
        {
            return (clear, (lo, hi));
        }
        // Room above the data: the legend's height is a share box_h of the new range.
        (UpperRight, (lo, hi + box_h * (hi - lo) / (1.0 - box_h)))
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

/// A figure of panels stacked vertically.
pub(crate) struct Stack<'a> {
    /// The file's base name.
    pub name: &'static str,
    /// The figure's title.
    pub title: String,
    /// The panels, top to bottom.
    pub panels: Vec<Panel<'a>>,
}

/// Periods of the lowest mode past which a record is drawn in a window.
const WINDOW_PERIODS: f64 = 25.0;

impl Stack<'_> {
    /// The stack drawn over a window of a long record, its title saying so: 25 periods
    /// of the lowest natural frequency `lowest_hz`, from 40 % of the record's `span` (a
    /// long broadband record drawn whole is a solid mass of lines, the data hidden
    /// under the model). Unchanged when the record holds fewer than 50 periods.
    pub(crate) fn windowed(mut self, span: (f64, f64), lowest_hz: f64) -> Self {
        let (start, end) = span;
        let length = WINDOW_PERIODS / lowest_hz;
        if !(length.is_finite() && length > 0.0 && length < 0.5 * (end - start)) {
            return self;
        }
        let from = start + 0.4 * (end - start);
        let to = (from + length).min(end);
        self.panels = (self.panels.iter())
            .map(|p| p.zoomed((from, to), p.title.clone()))
            .collect();
        self.title = format!(
            "{}: t = {}–{} s of the {} s record",
            self.title,
            crate::fmt::sig(from, 3),
            crate::fmt::sig(to, 3),
            crate::fmt::sig(end - start, 3)
        );
        self
    }
}

impl Figure for Stack<'_> {
    fn name(&self) -> &'static str {
        self.name
    }
    fn size(&self) -> (u32, u32) {
        (1400, 120 + 380 * self.panels.len().max(2) as u32)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let area = suptitle(root, &self.title)?;
        let parts = area.split_evenly((self.panels.len(), 1));
        for (panel, part) in self.panels.iter().zip(&parts) {
            panel.draw(part)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn panel<'a>(x: &'a [f64], y: Vec<f64>) -> Panel<'a> {
        Panel {
            title: String::new(),
            x_desc: String::new(),
            y_desc: String::new(),
            x_range: (x[0], x[x.len() - 1]),
            curves: vec![Curve {
                label: "measured".into(),
                x,
                y,
                style: Style::Points(super::super::BLUE, 2),
            }],
            band: None,
            legend: Some(SeriesLabelPosition::UpperRight),
        }
    }

    /// A long record is drawn over 25 periods of its lowest mode from 40 % of it, the
    /// title saying which; a short one whole.
    #[test]
    fn a_long_record_is_drawn_over_a_window() {
        let x: Vec<f64> = (0..10_001).map(|i| i as f64 / 100.0).collect();
        let stack = |x| Stack {
            name: "fit",
            title: "Fit".into(),
            panels: vec![panel(x, x.to_vec())],
        };
        let long = stack(&x).windowed((0.0, 100.0), 10.0);
        assert_eq!(long.panels[0].x_range, (40.0, 42.5));
        let shown = &long.panels[0].curves[0].x;
        assert!(shown.len() == 251 && shown[0] == 40.0, "{}", shown.len());
        assert_eq!(long.title, "Fit: t = 40.0–42.5 s of the 100 s record");
        // 50 periods or fewer: whole.
        let short = stack(&x).windowed((0.0, 100.0), 0.5);
        assert_eq!(short.panels[0].x_range, (0.0, 100.0));
        assert_eq!(short.title, "Fit");
    }

    #[test]
    fn the_legend_goes_where_no_data_is() {
        let x: Vec<f64> = (0..1000).map(|i| i as f64 / 100.0).collect();
        // A rising ramp: its upper right is full, its upper left empty.
        let p = panel(&x, x.clone());
        let (position, limits) =
            p.legend_place((1400, 420), (0.0, 10.0), SeriesLabelPosition::UpperRight);
        assert!(
            matches!(position, SeriesLabelPosition::UpperLeft),
            "{position:?}"
        );
        assert_eq!(limits, (0.0, 10.0));
        // Noise over the whole panel: no corner is clear, the axis rises above the data.
        let y: Vec<f64> = (0..1000)
            .map(|i| ((i * 7919) % 1000) as f64 / 100.0)
            .collect();
        let p = panel(&x, y);
        let (position, (lo, hi)) =
            p.legend_place((1400, 420), (0.0, 10.0), SeriesLabelPosition::UpperRight);
        assert!(
            matches!(position, SeriesLabelPosition::UpperRight),
            "{position:?}"
        );
        assert_eq!(lo, 0.0);
        assert!(hi > 10.0);
        // With the raised axis the upper right holds no point.
        let (again, limits) =
            p.legend_place((1400, 420), (lo, hi), SeriesLabelPosition::UpperRight);
        assert!(matches!(again, SeriesLabelPosition::UpperRight) && limits == (lo, hi));
    }
}
