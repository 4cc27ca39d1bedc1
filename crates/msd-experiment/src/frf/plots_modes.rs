//! The figures of where the modes are and how they move: the mode indicator functions
//! (`frf_mode_indicator`: CMIF and MIF) and a set's shapes drawn over the nodes'
//! coordinates (`frf_shapes_geometry`).

use super::FrfOutcome;
use crate::plots::{
    BLUE, DARK, Draw, Drawable, Figure, GRAY, RED, draw_legend, house_mesh, suptitle, text, tick,
    title_style,
};
use msd_modal::{ModeIndicator, ModeSetFit};
use plotters::coord::Shift;
use plotters::prelude::*;

/// `frf_mode_indicator` when the outcome has mode indicators.
pub(crate) fn indicator(o: &FrfOutcome) -> Option<Box<dyn Drawable + '_>> {
    let indicator = o.indicator.as_ref()?;
    let modes_hz: Vec<f64> = o.fit.poles().iter().map(|p| p.0.value).collect();
    Some(Box::new(Indicator(indicator, modes_hz, o.fit.band_hz())))
}

/// `frf_shapes_geometry` when the set's nodes have coordinates.
pub(crate) fn geometry<'a>(o: &'a FrfOutcome, m: &'a ModeSetFit) -> Option<Box<dyn Drawable + 'a>> {
    let drawn = Geometry::of(&o.geometry, m);
    (!drawn.modes.is_empty()).then(|| Box::new(drawn) as Box<dyn Drawable>)
}

struct Indicator<'a>(&'a ModeIndicator, Vec<f64>, [f64; 2]);

impl Figure for Indicator<'_> {
    fn name(&self) -> &'static str {
        "frf_mode_indicator"
    }
    fn size(&self) -> (u32, u32) {
        (1400, 1000)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let (d, [f0, f1]) = (self.0, self.2);
        let inside: Vec<usize> = (0..d.frequency_hz.len())
            .filter(|&k| (f0..=f1).contains(&d.frequency_hz[k]))
            .collect();
        if inside.len() < 2 {
            return Err("fewer than two lines to draw".into());
        }
        let area = suptitle(root, "Mode indicator functions of the data")?;
        let h = area.dim_in_pixel().1 as i32;
        let (top, bottom) = area.split_vertically(h * 60 / 100);
        let values = || inside.iter().flat_map(|&k| d.cmif[k].iter().copied());
        let hi = values().fold(0.0f64, f64::max);
        let lo = values()
            .filter(|&v| v > 0.0)
            .fold(hi, f64::min)
            .max(hi * 1e-8);
        if hi <= 0.0 {
            return Err("the data are zero in the band".into());
        }
        let mut chart = ChartBuilder::on(&top)
            .caption(
                "CMIF: singular values of the FRF matrix (a peak is a mode)",
                title_style(),
            )
            .margin(14)
            .margin_right(28)
            .x_label_area_size(52)
            .y_label_area_size(96)
            .build_cartesian_2d(f0..f1, (lo * 0.7..hi * 1.5).log_scale())
            .map_err(text)?;
        house_mesh(&mut chart.configure_mesh())
            .x_desc("frequency f [Hz]")
            .y_desc("singular value")
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .x_label_formatter(&tick)
            .draw()
            .map_err(text)?;
        let curves = d.cmif.first().map_or(0, Vec::len);
        for s in 0..curves {
            let colour = if s == 0 { BLUE } else { GRAY };
            let line = inside
                .iter()
                .map(|&k| (d.frequency_hz[k], d.cmif[k][s].max(lo)));
            chart
                .draw_series(LineSeries::new(line, colour.stroke_width(2)))
                .map_err(text)?
                .label(format!("singular value {}", s + 1))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(2))
                });
        }
        mode_lines(&mut chart, &self.1, (lo * 0.7, hi * 1.5))?;
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        let mut chart = ChartBuilder::on(&bottom)
            .caption(
                "MIF: Σ|Re H|·|H| / Σ|H|² of the receptance (a dip is a normal mode)",
                title_style(),
            )
            .margin(14)
            .margin_right(28)
            .x_label_area_size(52)
            .y_label_area_size(96)
            .build_cartesian_2d(f0..f1, 0.0..1.05)
            .map_err(text)?;
        house_mesh(&mut chart.configure_mesh())
            .x_desc("frequency f [Hz]")
            .y_desc("MIF")
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .draw()
            .map_err(text)?;
        let line = inside.iter().map(|&k| (d.frequency_hz[k], d.mif[k]));
        chart
            .draw_series(LineSeries::new(line, RED.stroke_width(2)))
            .map_err(text)?;
        mode_lines(&mut chart, &self.1, (0.0, 1.05))
    }
}

/// Dashed vertical lines at the fitted modes.
fn mode_lines<DB: DrawingBackend, Y: Ranged<ValueType = f64>>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<plotters::coord::types::RangedCoordf64, Y>>,
    modes_hz: &[f64],
    (lo, hi): (f64, f64),
) -> Draw {
    for &fm in modes_hz {
        chart
            .draw_series(DashedLineSeries::new(
                vec![(fm, lo), (fm, hi)],
                8,
                5,
                DARK.stroke_width(1),
            ))
            .map_err(text)?;
    }
    Ok(())
}

/// The nodes in a cabinet projection (x to the right, z up, y receding at 45° and half
/// scale), each mode's deformed positions, and whether the nodes lie on one line.
struct Geometry {
    undeformed: Vec<(f64, f64)>,
    /// Per mode: its caption and (undeformed, deformed) screen points of its measured DOFs.
    modes: Vec<(String, Vec<Moved>)>,
    on_a_line: bool,
}

/// A DOF's point at rest and deformed, on the screen.
type Moved = ((f64, f64), (f64, f64));

/// The cabinet projection of a point.
fn project([x, y, z]: [f64; 3]) -> (f64, f64) {
    let c = 0.5 * std::f64::consts::FRAC_1_SQRT_2;
    (x + c * y, z + c * y)
}

impl Geometry {
    fn of(nodes: &[msd_uff::Node], m: &ModeSetFit) -> Self {
        let at = |label: u32| {
            nodes
                .iter()
                .find(|n| n.label == i64::from(label))
                .map(|n| [n.x, n.y, n.z])
        };
        let span = (0..3)
            .map(|a| {
                let (lo, hi) =
                    nodes
                        .iter()
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), n| {
                            let v = [n.x, n.y, n.z][a];
                            (l.min(v), h.max(v))
                        });
                hi - lo
            })
            .collect::<Vec<f64>>();
        let largest = span.iter().copied().fold(0.0, f64::max);
        let mut sorted = span.clone();
        sorted.sort_by(|a, b| b.total_cmp(a));
        let on_a_line = sorted.get(1).is_some_and(|&s| s <= 1e-9 * largest);
        let modes = m
            .modes
            .iter()
            .enumerate()
            .take(6)
            .filter_map(|(r, mode)| {
                let biggest = mode.shape.iter().map(|e| e.re.abs()).fold(0.0, f64::max);
                let scale = if biggest > 0.0 {
                    0.15 * largest / biggest
                } else {
                    0.0
                };
                let points: Vec<Moved> = mode
                    .shape
                    .iter()
                    .filter_map(|e| {
                        let p = at(e.node)?;
                        let axis = (e.direction.unsigned_abs() as usize).checked_sub(1)?;
                        let mut q = p;
                        *q.get_mut(axis)? += scale * e.re * f64::from(e.direction.signum());
                        Some((project(p), project(q)))
                    })
                    .collect();
                let caption = format!(
                    "mode {}: {:.4} Hz, ζ = {:.2e}",
                    r + 1,
                    mode.natural_frequency_hz.value,
                    mode.damping_ratio.value
                );
                (!points.is_empty() && largest > 0.0).then_some((caption, points))
            })
            .collect();
        Self {
            undeformed: nodes.iter().map(|n| project([n.x, n.y, n.z])).collect(),
            modes,
            on_a_line,
        }
    }
}

impl Figure for Geometry {
    fn name(&self) -> &'static str {
        "frf_shapes_geometry"
    }
    fn size(&self) -> (u32, u32) {
        (1500, 900)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let area = suptitle(
            root,
            "Mode shapes over the nodes (real part; gray: at rest, colour: deformed)",
        )?;
        let all = self.undeformed.iter().chain(
            self.modes
                .iter()
                .flat_map(|(_, p)| p.iter().map(|(_, q)| q)),
        );
        let (mut x0, mut x1, mut y0, mut y1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for &(x, y) in all {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        let pad = 0.08 * (x1 - x0).max(y1 - y0).max(f64::MIN_POSITIVE);
        let columns = self.modes.len().min(3);
        let rows = self.modes.len().div_ceil(columns);
        let panels = area.split_evenly((rows, columns));
        for ((caption, points), panel) in self.modes.iter().zip(&panels) {
            let mut chart = ChartBuilder::on(panel)
                .caption(caption, title_style())
                .margin(10)
                .x_label_area_size(36)
                .y_label_area_size(56)
                .build_cartesian_2d(x0 - pad..x1 + pad, y0 - pad..y1 + pad)
                .map_err(text)?;
            house_mesh(&mut chart.configure_mesh())
                .x_label_formatter(&tick)
                .y_label_formatter(&tick)
                .draw()
                .map_err(text)?;
            chart
                .draw_series(
                    self.undeformed
                        .iter()
                        .map(|&p| Circle::new(p, 4, GRAY.filled())),
                )
                .map_err(text)?;
            chart
                .draw_series(
                    points
                        .iter()
                        .map(|&(p, q)| PathElement::new(vec![p, q], GRAY.stroke_width(1))),
                )
                .map_err(text)?;
            if self.on_a_line {
                let mut line: Vec<(f64, f64)> = points.iter().map(|&(_, q)| q).collect();
                line.sort_by(|a, b| a.0.total_cmp(&b.0));
                chart
                    .draw_series(LineSeries::new(line, BLUE.stroke_width(2)))
                    .map_err(text)?;
            }
            chart
                .draw_series(
                    points
                        .iter()
                        .map(|&(_, q)| Circle::new(q, 5, BLUE.filled())),
                )
                .map_err(text)?;
        }
        Ok(())
    }
}
