//! The figure of an operational run, PNG and SVG in the house style: for SSI,
//! `oma_stabilization` (the poles by model order, the poles that formed each mode marked,
//! the modes' frequencies dashed, the first singular value of the output spectral matrix
//! behind); for EFDD, `oma_singular_values` (the first singular values in dB, the picked
//! peaks and the modes).

use super::shapes_plot::ShapesFigure;
use super::{OperationalOutcome, SeriesOutcome};
use crate::error::Result;
use crate::fmt::sig;
use crate::plots::diagram::Stabilization;
use crate::plots::panel::{Curve, Panel, PanelFigure, Style};
use crate::plots::{
    BLUE, DARK, Draw, Figure, GRAY, ORANGE, RED, house_mesh, legend_style, limits, register_fonts,
    save, suptitle, text, tick,
};
use msd_modal::{SingularSpectrum, node_components, singular_spectrum};
use plotters::prelude::*;
use std::path::Path;

/// Writes the figure; returns its base name.
pub(crate) fn write_all(o: &OperationalOutcome, dir: &Path) -> Result<Vec<&'static str>> {
    register_fonts();
    if let Some(spectrum) = &o.fit.spectrum {
        let mut names = vec!["oma_singular_values"];
        let lines: Vec<[f64; 2]> = o
            .fit
            .modes
            .iter()
            .map(|m| [m.natural_frequency_hz.value; 2])
            .collect();
        save(&singular_values(o, spectrum, &lines), dir)?;
        names.extend(shapes(o, dir)?);
        return Ok(names);
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
            title: if o.fit.method == msd_modal::OmaMethod::SsiDat {
                "Stabilization diagram (SSI-dat poles by model order)"
            } else {
                "Stabilization diagram (SSI-cov poles by model order)"
            },
            behind_label: "first singular value of the output spectral matrix (CMIF, log scale)",
            view_hz: view(o),
        },
        dir,
    )?;
    let mut names = vec!["oma_stabilization"];
    names.extend(shapes(o, dir)?);
    Ok(names)
}

/// `oma_shapes` where the config gives a geometry: each mode's oblique channels
/// resolved into x, y, z at their node.
fn shapes(o: &OperationalOutcome, dir: &Path) -> Result<Option<&'static str>> {
    let (Some(geometry), Some(section)) = (&o.geometry, geometry_section(&o.config)) else {
        return Ok(None);
    };
    let modes: Vec<_> = o
        .fit
        .modes
        .iter()
        .map(|m| (m.clone(), node_components(&o.record, &m.shape)))
        .collect();
    save(&ShapesFigure::new(geometry, &section.unit, &modes), dir)?;
    Ok(Some("oma_shapes"))
}

fn geometry_section(config: &crate::config::Config) -> Option<&crate::config::GeometrySection> {
    config.operational.as_ref()?.geometry.as_ref()
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

/// Writes `oma_tracks` for a run over several records; returns the names written
/// (`modes.uff` is written beside it by the caller).
pub(crate) fn write_tracks(o: &SeriesOutcome, dir: &Path) -> Result<Vec<&'static str>> {
    register_fonts();
    save(&Tracks { o }, dir)?;
    let mut names = vec!["oma_tracks"];
    if let (Some(geometry), Some(section)) = (&o.geometry, geometry_section(&o.config)) {
        let modes: Vec<_> = o
            .merged
            .modes
            .iter()
            .map(|m| (m.clone(), m.shape.clone()))
            .collect();
        save(&ShapesFigure::new(geometry, &section.unit, &modes), dir)?;
        names.push("oma_shapes");
    }
    Ok(names)
}

/// Each mode's fn (as its deviation from the combined fn, %) and ζ (%) record by record,
/// with the records' own 95 % intervals; the key beside the panels.
struct Tracks<'a> {
    o: &'a SeriesOutcome,
}

/// A mode's colour and marker: ten colours, then the same with triangles.
const PALETTE: [RGBColor; 10] = crate::plots::CATEGORY_COLOURS;

impl Tracks<'_> {
    /// Per mode, (record, value, low, high) of fn's deviation in % or of ζ in %.
    fn points(&self, damping: bool) -> Vec<Vec<(f64, f64, f64, f64)>> {
        let o = self.o;
        o.merged
            .found
            .iter()
            .zip(&o.merged.modes)
            .map(|(found, combined)| {
                let f0 = combined.natural_frequency_hz.value;
                found
                    .iter()
                    .enumerate()
                    .filter_map(|(r, i)| {
                        let m = &o.records[r].fit.modes[(*i)?];
                        let (i, scale, offset) = if damping {
                            (&m.damping_ratio, 100.0, 0.0)
                        } else {
                            (&m.natural_frequency_hz, 100.0 / f0, 100.0)
                        };
                        let v = |x: f64| x * scale - offset;
                        Some(((r + 1) as f64, v(i.value), v(i.ci95[0]), v(i.ci95[1])))
                    })
                    .collect()
            })
            .collect()
    }

    fn panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, plotters::coord::Shift>,
        damping: bool,
    ) -> Draw {
        let points = self.points(damping);
        // The axis holds every estimate and the intervals up to twice the estimates'
        // spread beyond them; a longer bar is cut at the axis (its end in tracks.csv).
        let values: Vec<f64> = points.iter().flatten().map(|p| p.1).collect();
        let (v0, v1) = limits([values.as_slice()]);
        let reach = 2.0 * (v1 - v0);
        let ends: Vec<f64> = points
            .iter()
            .flatten()
            .flat_map(|p| [p.2.max(v0 - reach), p.3.min(v1 + reach)])
            .filter(|v| v.is_finite())
            .chain(values.iter().copied())
            .collect();
        let (lo, hi) = limits([ends.as_slice()]);
        let n = self.o.records.len() as f64;
        let mut chart = ChartBuilder::on(area)
            .margin(14)
            .x_label_area_size(50)
            .y_label_area_size(90)
            .build_cartesian_2d(0.5..n + 0.5, lo..hi)
            .map_err(text)?;
        house_mesh(&mut chart.configure_mesh())
            .x_desc("record")
            .y_desc(if damping {
                "damping ratio ζ [%]"
            } else {
                "fn − combined fn [% of fn]"
            })
            .x_labels(self.o.records.len().min(20))
            .x_label_formatter(&|x| {
                let k = x.round() as usize;
                match self.o.records.get(k.wrapping_sub(1)) {
                    Some(r) if (x - k as f64).abs() < 1e-9 => r.label.clone(),
                    _ => String::new(),
                }
            })
            .y_label_formatter(&tick)
            .draw()
            .map_err(text)?;
        for (k, series) in points.iter().enumerate() {
            let colour = PALETTE[k % PALETTE.len()];
            // Modes side by side within a record: the bars do not hide each other.
            let shift = (k as f64 - 0.5 * points.len() as f64) * 0.6 / points.len() as f64;
            for &(x, _, a, b) in series {
                chart
                    .draw_series(LineSeries::new(
                        [(x + shift, a.max(lo)), (x + shift, b.min(hi))],
                        colour.stroke_width(2),
                    ))
                    .map_err(text)?;
            }
            let marker = |p: (f64, f64)| -> DynElement<'static, DB, (f64, f64)> {
                if k < PALETTE.len() {
                    Circle::new(p, 4, colour.filled()).into_dyn()
                } else {
                    TriangleMarker::new(p, 5, colour.filled()).into_dyn()
                }
            };
            chart
                .draw_series(series.iter().map(|&(x, v, ..)| marker((x + shift, v))))
                .map_err(text)?;
        }
        Ok(())
    }
}

impl Figure for Tracks<'_> {
    fn name(&self) -> &'static str {
        "oma_tracks"
    }
    fn size(&self) -> (u32, u32) {
        (1400, 1000)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, plotters::coord::Shift>) -> Draw {
        let area = suptitle(
            root,
            "Each mode record by record (95 % intervals of each record's own fit)",
        )?;
        let width = area.dim_in_pixel().0 as i32;
        let (panels, key) = area.split_horizontally(width - 240);
        let h = panels.dim_in_pixel().1 as i32;
        let (top, bottom) = panels.split_vertically(h / 2);
        self.panel(&top, false)?;
        self.panel(&bottom, true)?;
        for (k, m) in self.o.merged.modes.iter().enumerate() {
            let colour = PALETTE[k % PALETTE.len()];
            let y = 60 + 30 * k as i32;
            let marker: DynElement<'static, DB, (i32, i32)> = if k < PALETTE.len() {
                Circle::new((20, y), 5, colour.filled()).into_dyn()
            } else {
                TriangleMarker::new((20, y), 6, colour.filled()).into_dyn()
            };
            key.draw(&marker).map_err(text)?;
            key.draw(&Text::new(
                format!(
                    "mode {} ({} Hz)",
                    k + 1,
                    sig(m.natural_frequency_hz.value, 4)
                ),
                (36, y - 9),
                legend_style(),
            ))
            .map_err(text)?;
        }
        Ok(())
    }
}
