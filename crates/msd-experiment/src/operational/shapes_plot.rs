//! `oma_shapes`: every mode's shape drawn on the structure's geometry, one 3-D panel per
//! mode — the undeformed lines in grey, the deformed ones in colour (real part of the
//! shape in x, y and z, scaled so that the largest displacement is an eighth of the
//! structure), nodes with no measured component left in place.

use super::geometry::Geometry;
use crate::fmt::sig;
use crate::plots::{BLUE, Draw, Figure, GRAY, label_style, suptitle, text, tick, tick_style};
use msd_modal::{Mode, ShapeEntry};
use plotters::coord::Shift;
use plotters::prelude::*;

/// A node's x, y, z displacement.
type Move = (u32, [f64; 3]);

/// The figure: the geometry, each mode's title and its nodes' x, y, z displacements.
pub(crate) struct ShapesFigure<'a> {
    pub geometry: &'a Geometry,
    /// The coordinates' unit, for the title.
    pub unit: &'a str,
    pub modes: Vec<(String, Vec<Move>)>,
}

impl<'a> ShapesFigure<'a> {
    /// The modes' x, y, z entries (DOF directions ±1, ±2, ±3; others, such as an oblique
    /// beam not resolved into components, are not drawn).
    pub(crate) fn new(
        geometry: &'a Geometry,
        unit: &'a str,
        modes: &[(Mode, Vec<ShapeEntry>)],
    ) -> Self {
        let modes = modes
            .iter()
            .enumerate()
            .map(|(k, (mode, xyz))| {
                let title = format!(
                    "mode {}: {} Hz, ζ {} %",
                    k + 1,
                    sig(mode.natural_frequency_hz.value, 5),
                    sig(100.0 * mode.damping_ratio.value, 2)
                );
                let mut moves: Vec<Move> = Vec::new();
                for e in xyz.iter().filter(|e| (1..=3).contains(&e.direction.abs())) {
                    let axis = e.direction.unsigned_abs() as usize - 1;
                    let value = e.re * f64::from(e.direction.signum());
                    match moves.iter_mut().find(|(n, _)| *n == e.node) {
                        Some((_, d)) => d[axis] = value,
                        None => {
                            let mut d = [0.0; 3];
                            d[axis] = value;
                            moves.push((e.node, d));
                        }
                    }
                }
                (title, moves)
            })
            .collect();
        Self {
            geometry,
            unit,
            modes,
        }
    }

    fn panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        title: &str,
        moves: &[Move],
    ) -> Draw {
        let g = self.geometry;
        let largest = moves
            .iter()
            .flat_map(|(_, d)| d.iter().map(|v| v.abs()))
            .fold(0.0, f64::max);
        let scale = if largest > 0.0 {
            g.size() / 8.0 / largest
        } else {
            0.0
        };
        let moved = |node: u32, p: [f64; 3]| -> [f64; 3] {
            let d = moves
                .iter()
                .find(|(n, _)| *n == node)
                .map_or([0.0; 3], |(_, d)| *d);
            [
                p[0] + scale * d[0],
                p[1] + scale * d[1],
                p[2] + scale * d[2],
            ]
        };
        let all: Vec<[f64; 3]> = g
            .nodes
            .iter()
            .flat_map(|&(n, p)| [p, moved(n, p)])
            .collect();
        let range = |a: usize| {
            let (lo, hi) = all.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
                (lo.min(p[a]), hi.max(p[a]))
            });
            let pad = 0.05 * (hi - lo).max(1e-9);
            (lo - pad)..(hi + pad)
        };
        let x_range = range(0);
        let x_end = x_range.end - 0.15 * (x_range.end - x_range.start);
        // plotters' y is up: the structure's (x, y, z) is drawn as (x, z, y).
        let mut chart = ChartBuilder::on(area)
            .caption(title, label_style())
            .margin(20)
            // Room for the vertical axis' labels on the left (they were cut).
            .margin_left(44)
            .build_cartesian_3d(range(0), range(2), range(1))
            .map_err(text)?;
        chart.with_projection(|mut p| {
            p.yaw = 0.6;
            p.pitch = 0.25;
            p.scale = 0.8;
            p.into_matrix()
        });
        chart
            .configure_axes()
            .label_style(tick_style())
            .max_light_lines(0)
            .x_labels(3)
            .y_labels(3)
            .z_labels(3)
            // Shortest numbers ("20", not "20.0"): two axes' labels meet at a corner.
            // The x axis ends where the depth axis begins: its last label would sit on
            // the depth axis' first.
            .x_formatter(&|v| if *v > x_end { String::new() } else { tick(v) })
            .y_formatter(&tick)
            .z_formatter(&tick)
            .draw()
            .map_err(text)?;
        let at = |p: [f64; 3]| (p[0], p[2], p[1]);
        for &(a, b) in &g.lines {
            let (Some(pa), Some(pb)) = (g.node(a), g.node(b)) else {
                continue;
            };
            chart
                .draw_series(LineSeries::new([at(pa), at(pb)], GRAY.stroke_width(1)))
                .map_err(text)?;
            chart
                .draw_series(LineSeries::new(
                    [at(moved(a, pa)), at(moved(b, pb))],
                    BLUE.stroke_width(2),
                ))
                .map_err(text)?;
        }
        chart
            .draw_series(
                g.nodes
                    .iter()
                    .filter(|(n, _)| moves.iter().any(|(m, _)| m == n))
                    .map(|&(n, p)| Circle::new(at(moved(n, p)), 3, BLUE.filled())),
            )
            .map_err(text)?;
        Ok(())
    }
}

impl Figure for ShapesFigure<'_> {
    fn name(&self) -> &'static str {
        "oma_shapes"
    }
    fn size(&self) -> (u32, u32) {
        let rows = self.modes.len().div_ceil(4).max(1) as u32;
        (1400, 120 + 420 * rows)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let area = suptitle(
            root,
            &format!(
                "Mode shapes on the geometry (grey at rest, blue the real part; coordinates in {})",
                self.unit
            ),
        )?;
        let rows = self.modes.len().div_ceil(4).max(1);
        let panels = area.split_evenly((rows, 4));
        for ((title, moves), panel) in self.modes.iter().zip(&panels) {
            self.panel(panel, title, moves)?;
        }
        Ok(())
    }
}
