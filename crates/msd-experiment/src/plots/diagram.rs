//! The stabilization diagram as a figure, for every method that fills msd-modal's
//! `StabilizationDiagram` (LSCF on frequency responses, SSI on output-only records).

use super::{BLUE, DARK, Draw, Figure, GRAY, RED, draw_legend, house_mesh, suptitle, text, tick};
use plotters::coord::Shift;
use plotters::prelude::*;

/// A stabilization diagram (any method's), with a spectrum of the data drawn behind it
/// on a logarithmic scale spanning the orders' axis; the poles that formed a selected
/// mode (where the selection marks them) drawn apart.
pub(crate) struct Stabilization<'a> {
    /// The diagram.
    pub diagram: &'a msd_modal::StabilizationDiagram,
    /// (frequency, a positive value) drawn behind it.
    pub behind: Vec<(f64, f64)>,
    /// The figure's file name.
    pub name: &'static str,
    /// Its title.
    pub title: &'static str,
    /// The legend of what is drawn behind.
    pub behind_label: &'static str,
    /// The frequencies shown, Hz; `None`: the diagram's band.
    pub view_hz: Option<[f64; 2]>,
}

impl Figure for Stabilization<'_> {
    fn name(&self) -> &'static str {
        self.name
    }
    fn size(&self) -> (u32, u32) {
        (1400, 900)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let d = self.diagram;
        let area = suptitle(root, self.title)?;
        let [f0, f1] = self.view_hz.unwrap_or(d.band_hz);
        let top = d.orders.last().map_or(2, |o| o.order) as f64 + 2.0;
        // Head-room above the highest order for the legend, which then covers no pole.
        let room = 1.3 * top;
        let mut chart = ChartBuilder::on(&area)
            .margin(14)
            .margin_right(28)
            .x_label_area_size(52)
            .y_label_area_size(80)
            .build_cartesian_2d(f0..f1, 0.0..room)
            .map_err(text)?;
        house_mesh(&mut chart.configure_mesh())
            .x_desc("frequency f [Hz]")
            .y_desc("model order")
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .draw()
            .map_err(text)?;
        let pick = |keep: fn(&msd_modal::DiagramPole) -> bool| -> Vec<(f64, f64)> {
            d.orders
                .iter()
                .flat_map(|o| {
                    o.poles
                        .iter()
                        .filter(|p| keep(p) && (f0..=f1).contains(&p.natural_frequency_hz))
                        .map(move |p| (p.natural_frequency_hz, o.order as f64))
                })
                .collect()
        };
        let unstable = pick(|p| !p.stable_frequency);
        let frequency_only = pick(|p| p.stable_frequency && !p.stable);
        let stable = pick(|p| p.stable);
        let of_modes = pick(|p| p.mode.is_some());
        chart
            .draw_series(
                unstable
                    .into_iter()
                    .map(|p| Cross::new(p, 4, GRAY.stroke_width(1))),
            )
            .map_err(text)?
            .label("new pole")
            .legend(|(x, y)| Cross::new((x + 12, y), 4, GRAY.stroke_width(1)));
        chart
            .draw_series(
                frequency_only
                    .into_iter()
                    .map(|p| Circle::new(p, 4, BLUE.stroke_width(2))),
            )
            .map_err(text)?
            .label("stable in frequency")
            .legend(|(x, y)| Circle::new((x + 12, y), 4, BLUE.stroke_width(2)));
        chart
            .draw_series(stable.into_iter().map(|p| Circle::new(p, 5, RED.filled())))
            .map_err(text)?
            .label("stable in frequency and damping")
            .legend(|(x, y)| Circle::new((x + 12, y), 5, RED.filled()));
        if !of_modes.is_empty() {
            chart
                .draw_series(
                    of_modes
                        .into_iter()
                        .map(|p| TriangleMarker::new(p, 6, DARK.filled())),
                )
                .map_err(text)?
                .label("pole of a selected mode")
                .legend(|(x, y)| TriangleMarker::new((x + 12, y), 6, DARK.filled()));
        }
        let behind: Vec<(f64, f64)> = self
            .behind
            .iter()
            .copied()
            .filter(|&(f, h)| (f0..=f1).contains(&f) && h > 0.0)
            .collect();
        let (lo, hi) = behind.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
        if behind.len() > 1 && hi > lo {
            let y = |h: f64| top * (h / lo).ln() / (hi / lo).ln();
            chart
                .draw_series(LineSeries::new(
                    behind.iter().map(|&(f, h)| (f, y(h))),
                    GRAY.mix(0.6).stroke_width(1),
                ))
                .map_err(text)?
                .label(self.behind_label)
                .legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], GRAY.mix(0.6).stroke_width(2))
                });
        }
        for m in &d.modes {
            let fm = m.natural_frequency_hz;
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(fm, 0.0), (fm, top)],
                    8,
                    5,
                    DARK.stroke_width(2),
                ))
                .map_err(text)?;
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)
    }
}
