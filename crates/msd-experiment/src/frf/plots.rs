//! The figures of a frequency-domain experiment, PNG and SVG in the house style:
//! `frf_fit_bode`, `frf_fit_nyquist`, `frf_coherence` (averaged estimates) and
//! `frf_stabilization` (several modes).

use super::{FrfFit, FrfOutcome};
use crate::error::Result;
use crate::plots::diagram::Stabilization;
use crate::plots::{
    BLUE, DARK, Draw, Drawable, Figure, RED, draw_legend, house_mesh, limits, log_frequency_axis,
    phase_panel, save, save_all, suptitle, text, tick, title_style,
};
use msd_signal::Complex64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Writes every figure the outcome supports (and a set's UFF files); returns the
/// figures' base names.
pub(crate) fn write_all(o: &FrfOutcome, dir: &Path) -> Result<Vec<&'static str>> {
    crate::plots::register_fonts();
    let view = View::of(o);
    let mut figures: Vec<Box<dyn Drawable + '_>> =
        vec![Box::new(Bode(&view)), Box::new(Nyquist(&view))];
    if o.data.averages != 1 {
        figures.push(Box::new(Coherence(o)));
    }
    let members: Vec<_> = o.members.iter().map(|m| &m.frf).collect();
    if let FrfFit::Modes(m) = &o.fit {
        figures.push(Box::new(stabilization(
            &m.diagram,
            summed_magnitude(&o.data, &members),
        )));
    }
    if let FrfFit::Set(m) = &o.fit {
        figures.push(Box::new(stabilization(
            &m.diagram,
            summed_magnitude(&o.data, &members),
        )));
        figures.extend(super::plots_set::figures(o, m));
        super::uff_out::write_all(o, m, dir)?;
    }
    figures.extend(super::plots_modes::indicator(o));
    let drawn: Vec<&dyn Drawable> = figures.iter().map(|f| f.as_ref()).collect();
    save_all(&drawn, dir)?;
    Ok(drawn.iter().map(|f| f.file_name()).collect())
}

/// The stabilization diagram with `magnitude` (frequency, |H|) behind it.
fn stabilization(
    diagram: &msd_modal::StabilizationDiagram,
    magnitude: Vec<(f64, f64)>,
) -> Stabilization<'_> {
    Stabilization {
        diagram,
        behind: magnitude,
        name: "frf_stabilization",
        title: "Stabilization diagram (LSCF poles by model order)",
        behind_label: "the data's magnitude (log scale, summed over the FRFs)",
        view_hz: None,
    }
}

/// Writes `frf_stabilization` (PNG and SVG) into `dir`: the diagram with `magnitude`
/// (frequency, |H|) behind it.
pub(crate) fn save_diagram(
    diagram: &msd_modal::StabilizationDiagram,
    magnitude: Vec<(f64, f64)>,
    dir: &Path,
) -> Result<()> {
    crate::plots::register_fonts();
    save(&stabilization(diagram, magnitude), dir)
}

/// The data in the fitted band beside the model on a dense logarithmic grid.
struct View {
    f: Vec<f64>,
    h: Vec<Complex64>,
    dense: Vec<f64>,
    model: Vec<Complex64>,
    modes_hz: Vec<f64>,
    unit: String,
    /// The Nyquist plot's view: one mode's circle.
    circle: ModeCircle,
}

/// One mode's Nyquist circle: the data lines around it and the model on a grid fine
/// enough to draw it round (a whole band of lightly damped modes draws as a few spikes).
struct ModeCircle {
    /// The mode's number (1-based) and fn, Hz.
    mode: usize,
    natural_frequency_hz: f64,
    h: Vec<Complex64>,
    model: Vec<Complex64>,
}

/// Half-power bandwidths each side of a mode in its Nyquist view.
const CIRCLE_BANDWIDTHS: f64 = 3.0;

impl ModeCircle {
    /// The circle of the mode best resolved by the data (the most lines per half-power
    /// bandwidth): its lines within ± 3 bandwidths (at least 3 line spacings).
    fn of(o: &FrfOutcome, f: &[f64], h: &[Complex64]) -> Self {
        let spacing = f
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min);
        let poles = o.fit.poles();
        let (mode, fnat, zeta) = poles
            .iter()
            .enumerate()
            .map(|(k, (fnat, zeta))| (k, fnat.value, zeta.value))
            .filter(|(_, fnat, zeta)| fnat.is_finite() && zeta.is_finite())
            .max_by(|a, b| (a.1 * a.2).total_cmp(&(b.1 * b.2)))
            .unwrap_or((0, f[f.len() / 2], 0.0));
        let bandwidth = 2.0 * zeta.abs() * fnat;
        let half = (CIRCLE_BANDWIDTHS * bandwidth).max(3.0 * spacing.min(fnat));
        let (low, high) = (fnat - half, fnat + half);
        let inside: Vec<Complex64> = f
            .iter()
            .zip(h)
            .filter(|(x, _)| (low..=high).contains(*x))
            .map(|(_, h)| *h)
            .collect();
        let model = (0..=600)
            .map(|i| o.model_response(low + (high - low) * i as f64 / 600.0))
            .collect();
        Self {
            mode: mode + 1,
            natural_frequency_hz: fnat,
            h: inside,
            model,
        }
    }
}

impl View {
    fn of(o: &FrfOutcome) -> Self {
        let [low, high] = o.fit.band_hz();
        let (f, h): (Vec<f64>, Vec<Complex64>) = o
            .data
            .frequency
            .iter()
            .zip(&o.data.h)
            .filter(|(f, h)| **f >= low && **f <= high && h.norm() > 0.0)
            .map(|(f, h)| (*f, *h))
            .unzip();
        let dense: Vec<f64> = (0..=800)
            .map(|i| low * (high / low).powf(i as f64 / 800.0))
            .collect();
        let model = dense.iter().map(|&x| o.model_response(x)).collect();
        let modes_hz = o.fit.poles().iter().map(|p| p.0.value).collect();
        let circle = ModeCircle::of(o, &f, &h);
        let unit = frf_unit(o.data.kind);
        Self {
            f,
            h,
            dense,
            model,
            modes_hz,
            unit: unit.into(),
            circle,
        }
    }
}

struct Bode<'a>(&'a View);

impl Figure for Bode<'_> {
    fn name(&self) -> &'static str {
        "frf_fit_bode"
    }
    fn size(&self) -> (u32, u32) {
        (1400, 1000)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let v = self.0;
        if v.f.len() < 2 {
            return Err("fewer than two lines to draw".into());
        }
        let area = suptitle(root, "Frequency response: data and fitted model")?;
        let h = area.dim_in_pixel().1 as i32;
        let (top, bottom) = area.split_vertically(h * 55 / 100);
        let (f0, f1) = (v.dense[0], v.dense[v.dense.len() - 1]);
        let mags: Vec<f64> = v.h.iter().chain(&v.model).map(|h| h.norm()).collect();
        let (lo, hi) = mags
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &m| (a.min(m), b.max(m)));
        let (lo, hi) = (lo * 0.7, hi * 1.5);
        let mut chart = ChartBuilder::on(&top)
            .caption("Magnitude", title_style())
            .margin(14)
            .margin_right(28)
            .x_label_area_size(52)
            .y_label_area_size(96)
            .build_cartesian_2d(log_frequency_axis(f0, f1), (lo..hi).log_scale())
            .map_err(text)?;
        house_mesh(&mut chart.configure_mesh())
            .x_desc("frequency f [Hz]")
            .y_desc(format!("|H(f)| [{}]", v.unit))
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .x_label_formatter(&|x| tick(x))
            .draw()
            .map_err(text)?;
        let points =
            v.f.iter()
                .zip(&v.h)
                .map(|(f, h)| (*f, h.norm().clamp(lo, hi)));
        chart
            .draw_series(points.map(|p| Circle::new(p, 4, BLUE.filled())))
            .map_err(text)?
            .label("data")
            .legend(|(x, y)| Circle::new((x + 12, y), 4, BLUE.filled()));
        let line = v
            .dense
            .iter()
            .zip(&v.model)
            .map(|(f, h)| (*f, h.norm().clamp(lo, hi)));
        chart
            .draw_series(LineSeries::new(line, RED.stroke_width(3)))
            .map_err(text)?
            .label("fitted model")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], RED.stroke_width(3)));
        for &fm in &v.modes_hz {
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(fm, lo), (fm, hi)],
                    8,
                    5,
                    DARK.stroke_width(2),
                ))
                .map_err(text)?;
        }
        draw_legend(&mut chart, SeriesLabelPosition::LowerLeft)?;
        // Phase, each data point wrapped to within ±180° of the model's.
        let model_at = |f: f64| {
            let i = v.dense.partition_point(|&x| x < f).min(v.dense.len() - 1);
            v.model[i].arg().to_degrees()
        };
        let phase: Vec<(f64, f64)> =
            v.f.iter()
                .zip(&v.h)
                .map(|(&f, h)| {
                    let m = model_at(f);
                    (
                        f,
                        m + (h.arg().to_degrees() - m + 180.0).rem_euclid(360.0) - 180.0,
                    )
                })
                .collect();
        let model_phase: Vec<(f64, f64)> = v
            .dense
            .iter()
            .zip(&v.model)
            .map(|(f, h)| (*f, h.arg().to_degrees()))
            .collect();
        let ys: Vec<f64> = phase.iter().chain(&model_phase).map(|p| p.1).collect();
        let (plo, phi) = limits([ys.as_slice()]);
        let mut chart = phase_panel(&bottom, (f0, f1), (plo, phi))?;
        chart
            .draw_series(phase.iter().map(|&p| Circle::new(p, 4, BLUE.filled())))
            .map_err(text)?;
        chart
            .draw_series(LineSeries::new(model_phase, RED.stroke_width(3)))
            .map_err(text)?;
        Ok(())
    }
}

struct Nyquist<'a>(&'a View);

impl Figure for Nyquist<'_> {
    fn name(&self) -> &'static str {
        "frf_fit_nyquist"
    }
    fn size(&self) -> (u32, u32) {
        (1100, 1000)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let v = self.0;
        let c = &v.circle;
        let title = if v.modes_hz.len() > 1 {
            format!(
                "Nyquist plot around mode {} (fn = {} Hz): data and fitted model",
                c.mode,
                crate::fmt::sig(c.natural_frequency_hz, 5)
            )
        } else {
            "Nyquist plot: data and fitted model".to_string()
        };
        let area = suptitle(root, &title)?;
        let re: Vec<f64> = c.h.iter().chain(&c.model).map(|h| h.re).collect();
        let im: Vec<f64> = c.h.iter().chain(&c.model).map(|h| h.im).collect();
        let (size_x, size_y) = area.dim_in_pixel();
        let pixels = (f64::from(size_x) - 166.0, f64::from(size_y) - 94.0);
        let ((x0, x1), (y0, y1)) =
            equal_aspect(limits([re.as_slice()]), limits([im.as_slice()]), pixels);
        let mut chart = ChartBuilder::on(&area)
            .margin(14)
            .margin_right(28)
            .x_label_area_size(52)
            .y_label_area_size(110)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(text)?;
        house_mesh(&mut chart.configure_mesh())
            .x_desc(format!("Re H [{}]", v.unit))
            .y_desc(format!("Im H [{}]", v.unit))
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .draw()
            .map_err(text)?;
        chart
            .draw_series(LineSeries::new(
                c.model.iter().map(|h| (h.re, h.im)),
                RED.stroke_width(2),
            ))
            .map_err(text)?
            .label("fitted model")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], RED.stroke_width(2)));
        chart
            .draw_series(
                c.h.iter()
                    .map(|h| Circle::new((h.re, h.im), 5, BLUE.filled())),
            )
            .map_err(text)?
            .label("data")
            .legend(|(x, y)| Circle::new((x + 12, y), 4, BLUE.filled()));
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

/// The SI unit of a frequency response of `kind`, for axes.
pub(crate) fn frf_unit(kind: msd_signal::FrfKind) -> &'static str {
    match kind {
        msd_signal::FrfKind::Receptance => "m/N",
        msd_signal::FrfKind::Mobility => "m/(N·s)",
        msd_signal::FrfKind::Accelerance => "m/(N·s²)",
    }
}

/// Axis ranges with one unit per pixel on both axes (a circle drawn round), each range
/// widened about its centre, for a plot area of `pixels` (width, height).
fn equal_aspect(x: (f64, f64), y: (f64, f64), pixels: (f64, f64)) -> ((f64, f64), (f64, f64)) {
    let per_pixel = ((x.1 - x.0) / pixels.0).max((y.1 - y.0) / pixels.1);
    let widen = |(a, b): (f64, f64), pixels: f64| {
        let (centre, half) = (0.5 * (a + b), 0.5 * per_pixel * pixels);
        (centre - half, centre + half)
    };
    (widen(x, pixels.0), widen(y, pixels.1))
}

struct Coherence<'a>(&'a FrfOutcome);

impl Figure for Coherence<'_> {
    fn name(&self) -> &'static str {
        "frf_coherence"
    }
    fn size(&self) -> (u32, u32) {
        (1400, 600)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let d = &self.0.data;
        let area = suptitle(
            root,
            &match d.averages {
                0 => "Ordinary coherence γ² (as exported)".to_string(),
                k => format!("Ordinary coherence γ² ({k} averages)"),
            },
        )?;
        let (f0, f1) = (d.frequency[0], d.frequency[d.frequency.len() - 1]);
        let mut chart = ChartBuilder::on(&area)
            .margin(14)
            .margin_right(28)
            .x_label_area_size(52)
            .y_label_area_size(80)
            .build_cartesian_2d(f0..f1, 0.0..1.05)
            .map_err(text)?;
        house_mesh(&mut chart.configure_mesh())
            .x_desc("frequency f [Hz]")
            .y_desc("γ² [-]")
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .draw()
            .map_err(text)?;
        let line = d.frequency.iter().copied().zip(d.coherence.iter().copied());
        chart
            .draw_series(LineSeries::new(line, BLUE.stroke_width(2)))
            .map_err(text)?;
        Ok(())
    }
}

/// The magnitudes of `data` (or summed over a set's `members`, when there are any) at
/// every line above 0 Hz.
pub(crate) fn summed_magnitude(
    data: &msd_signal::FrequencyResponseEstimate,
    members: &[&msd_signal::FrequencyResponseEstimate],
) -> Vec<(f64, f64)> {
    let sets: &[&msd_signal::FrequencyResponseEstimate] =
        if members.is_empty() { &[data] } else { members };
    (0..data.frequency.len())
        .filter(|&k| data.frequency[k] > 0.0)
        .map(|k| (data.frequency[k], sets.iter().map(|s| s.h[k].norm()).sum()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_nyquist_plot_has_one_unit_per_pixel_on_both_axes() {
        let ((x0, x1), (y0, y1)) = equal_aspect((-1.0, 1.0), (-10.0, 0.0), (800.0, 400.0));
        assert!(((x1 - x0) / 800.0 - (y1 - y0) / 400.0).abs() < 1e-12);
        // Both data ranges inside, centred.
        assert!(x0 <= -1.0 && x1 >= 1.0 && y0 <= -10.0 && y1 >= 0.0);
        assert!((x0 + x1).abs() < 1e-12 && (y0 + y1 + 10.0).abs() < 1e-12);
    }
}
