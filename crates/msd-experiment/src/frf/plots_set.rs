//! The figures of a set of FRFs: every FRF with its fitted model (`frf_set_fit`), the MAC
//! matrix (`frf_mac`) and the shapes over the DOFs (`frf_shapes`).

use super::FrfOutcome;
use crate::plots::{
    DARK, Draw, Drawable, Figure, GRAY, KEY_WIDTH, category_colour, draw_key, house_mesh, suptitle,
    text, tick, tick_style,
};
use msd_modal::ModeSetFit;
use plotters::coord::Shift;
use plotters::prelude::*;

/// The set's figures: the fit, the MAC (and against the reference shapes), the shapes
/// (and over the geometry).
pub(crate) fn figures<'a>(o: &'a FrfOutcome, m: &'a ModeSetFit) -> Vec<Box<dyn Drawable + 'a>> {
    let auto = Mac {
        name: "frf_mac",
        title: "MAC of the mode shapes".into(),
        matrix: &m.mac,
        x_desc: "mode".into(),
        y_desc: "mode".into(),
    };
    let mut figures: Vec<Box<dyn Drawable + 'a>> =
        vec![Box::new(SetFit(o, m)), Box::new(auto), Box::new(Shapes(m))];
    if let Some(r) = &o.reference_shapes {
        figures.push(Box::new(Mac {
            name: "frf_mac_reference",
            title: format!(
                "MAC against {}",
                std::path::Path::new(&r.file)
                    .file_name()
                    .map_or_else(|| r.file.clone(), |n| n.to_string_lossy().into_owned())
            ),
            matrix: &r.comparison.mac,
            x_desc: format!("mode of {}", r.file),
            y_desc: "estimated mode".into(),
        }));
    }
    figures.extend(super::plots_modes::geometry(o, m));
    figures
}

/// The measured quantity's magnitude of member `i`'s model at `f`.
fn model_magnitude(o: &FrfOutcome, m: &ModeSetFit, i: usize, f: f64) -> f64 {
    let p = o.data.kind.power();
    m.response(i, f).norm() * (std::f64::consts::TAU * f).powi(p)
}

struct SetFit<'a>(&'a FrfOutcome, &'a ModeSetFit);

impl Figure for SetFit<'_> {
    fn name(&self) -> &'static str {
        "frf_set_fit"
    }
    fn size(&self) -> (u32, u32) {
        (1400, 800)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let (o, m) = (self.0, self.1);
        let area = suptitle(
            root,
            "Every FRF of the set: data (points) and fitted model (lines)",
        )?;
        let [f0, f1] = m.band_hz;
        let data: Vec<Vec<(f64, f64)>> = o
            .members
            .iter()
            .map(|s| {
                (s.frf.frequency.iter().zip(&s.frf.h))
                    .filter(|(f, h)| (f0..=f1).contains(*f) && h.norm() > 0.0)
                    .map(|(f, h)| (*f, h.norm()))
                    .collect()
            })
            .collect();
        let all = data.iter().flatten().map(|p| p.1);
        let (lo, hi) = all.fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
        if !(lo > 0.0 && hi > lo) {
            return Err("no positive magnitude to draw".into());
        }
        let (width, _) = area.dim_in_pixel();
        let (plot, key) = area.split_horizontally(width.saturating_sub(KEY_WIDTH));
        let mut chart = ChartBuilder::on(&plot)
            .margin(14)
            .margin_right(28)
            .x_label_area_size(52)
            .y_label_area_size(96)
            .build_cartesian_2d(f0..f1, (lo * 0.5..hi * 2.0).log_scale())
            .map_err(text)?;
        house_mesh(&mut chart.configure_mesh())
            .x_desc("frequency f [Hz]")
            .y_desc(format!(
                "|H| [{}] ({})",
                super::plots::frf_unit(o.data.kind),
                o.data.kind
            ))
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .draw()
            .map_err(text)?;
        let dense: Vec<f64> = (0..=4000)
            .map(|i| f0 + (f1 - f0) * i as f64 / 4000.0)
            .collect();
        let mut entries = Vec::new();
        for (i, (points, fit)) in data.iter().zip(&m.members).enumerate() {
            let colour = category_colour(i);
            chart
                .draw_series(points.iter().map(|&p| Circle::new(p, 2, colour.filled())))
                .map_err(text)?;
            let line = dense
                .iter()
                .map(|&f| (f, model_magnitude(o, m, i, f).clamp(lo * 0.5, hi * 2.0)));
            chart
                .draw_series(LineSeries::new(line, colour.stroke_width(2)))
                .map_err(text)?;
            entries.push((format!("{} / {}", fit.response, fit.reference), colour));
        }
        draw_key(&key, "response / reference", &entries)
    }
}

/// A MAC matrix as shaded cells, `matrix[i][j]` at row i + 1 (y) and column j + 1 (x).
struct Mac<'a> {
    name: &'static str,
    title: String,
    matrix: &'a [Vec<f64>],
    x_desc: String,
    y_desc: String,
}

impl Figure for Mac<'_> {
    fn name(&self) -> &'static str {
        self.name
    }
    fn size(&self) -> (u32, u32) {
        // About 90 px a cell (a 5 × 5 MAC is not a wall of colour), 900 px at most.
        let cells = self
            .matrix
            .len()
            .max(self.matrix.first().map_or(0, Vec::len)) as u32;
        let side = (160 + 90 * cells).clamp(640, 900);
        (side, side)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let mac = self.matrix;
        let n = mac.len();
        let columns = mac.first().map_or(0, Vec::len);
        if n == 0 || columns == 0 {
            return Err("no mode".into());
        }
        let area = suptitle(root, &self.title)?;
        let mut chart = ChartBuilder::on(&area)
            .margin(20)
            .x_label_area_size(52)
            .y_label_area_size(64)
            .build_cartesian_2d(0.5..columns as f64 + 0.5, 0.5..n as f64 + 0.5)
            .map_err(text)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(columns.min(20))
            .y_labels(n.min(20))
            .x_desc(&self.x_desc)
            .y_desc(&self.y_desc)
            .label_style(tick_style())
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| format!("{v:.0}"))
            .draw()
            .map_err(text)?;
        for (i, row) in mac.iter().enumerate() {
            for (j, &v) in row.iter().enumerate() {
                let (x, y) = ((j + 1) as f64, (i + 1) as f64);
                // A sequential scale from near-white to dark blue; a gap between cells.
                let t = v.clamp(0.0, 1.0);
                let mix = |a: f64, b: f64| (a + (b - a) * t).round() as u8;
                let fill = RGBColor(mix(247.0, 8.0), mix(251.0, 48.0), mix(255.0, 107.0));
                chart
                    .draw_series(std::iter::once(Rectangle::new(
                        [(x - 0.47, y - 0.47), (x + 0.47, y + 0.47)],
                        fill.filled(),
                    )))
                    .map_err(text)?;
                if n.max(columns) <= 12 {
                    let colour = if v > 0.5 { WHITE } else { DARK };
                    chart
                        .draw_series(std::iter::once(Text::new(
                            format!("{v:.2}"),
                            (x - 0.2, y + 0.1),
                            tick_style().color(&colour),
                        )))
                        .map_err(text)?;
                }
            }
        }
        Ok(())
    }
}

struct Shapes<'a>(&'a ModeSetFit);

impl Figure for Shapes<'_> {
    fn name(&self) -> &'static str {
        "frf_shapes"
    }
    fn size(&self) -> (u32, u32) {
        (1400, 700)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let m = self.0;
        let Some(first) = m.modes.first() else {
            return Err("no mode".into());
        };
        let n = first.shape.len();
        let area = suptitle(
            root,
            "Mode shapes over the measured DOFs (real part, largest entry 1)",
        )?;
        let labels: Vec<String> = first
            .shape
            .iter()
            .map(|e| format!("{}:{:+}", e.node, e.direction))
            .collect();
        let (width, _) = area.dim_in_pixel();
        let (plot, key) = area.split_horizontally(width.saturating_sub(KEY_WIDTH));
        let mut chart = ChartBuilder::on(&plot)
            .margin(14)
            .margin_right(28)
            .x_label_area_size(52)
            .y_label_area_size(80)
            .build_cartesian_2d(0.5..n as f64 + 0.5, -1.15..1.15)
            .map_err(text)?;
        house_mesh(&mut chart.configure_mesh())
            .x_labels(n.min(30))
            .x_desc("DOF (node:direction)")
            .y_desc("shape")
            .x_label_formatter(&|v| {
                let i = v.round() as usize;
                labels.get(i.wrapping_sub(1)).cloned().unwrap_or_default()
            })
            .y_label_formatter(&tick)
            .draw()
            .map_err(text)?;
        chart
            .draw_series(LineSeries::new(
                vec![(0.5, 0.0), (n as f64 + 0.5, 0.0)],
                GRAY.stroke_width(1),
            ))
            .map_err(text)?;
        let mut entries = Vec::new();
        for (r, mode) in m.modes.iter().enumerate() {
            let colour = category_colour(r);
            let points: Vec<(f64, f64)> = mode
                .shape
                .iter()
                .enumerate()
                .map(|(i, e)| ((i + 1) as f64, e.re))
                .collect();
            chart
                .draw_series(LineSeries::new(points.clone(), colour.stroke_width(3)))
                .map_err(text)?;
            chart
                .draw_series(
                    points
                        .into_iter()
                        .map(|p| Circle::new(p, 5, colour.filled())),
                )
                .map_err(text)?;
            let hz = crate::fmt::sig(mode.natural_frequency_hz.value, 5);
            entries.push((format!("mode {}: {hz} Hz", r + 1), colour));
        }
        draw_key(&key, "mode", &entries)
    }
}
