//! The house style of every figure, written as PNG and SVG by plotters with the bundled
//! DejaVu Sans font (no system fonts or libraries needed): colours, text styles, the
//! mesh, the legend box and the figure title (`house_mesh`, `draw_legend`, `suptitle`),
//! the Bode phase panel, panels of time series (`panel`), the stabilization diagram
//! (`diagram`), the residuals' noise spectra (`spectrum`), and `save` in both
//! formats. Each kind of experiment draws its own figures with them (the paper's in
//! `crate::paper`); the design figure is `design`.
//!
//! Long records are thinned for drawing only: lines keep each pixel column's minimum
//! and maximum (so no peak is lost), markers are subsampled evenly.

pub(crate) mod design;
pub(crate) mod diagram;
pub(crate) mod panel;
pub(crate) mod spectrum;

use crate::error::{ExperimentError, Result};
use plotters::chart::MeshStyle;
use plotters::coord::Shift;
use plotters::coord::combinators::{LogCoord, WithKeyPoints};
use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

/// The font family every figure uses (DejaVu Sans, registered from the `dejavu` crate).
pub const FONT: &str = "sans-serif";

/// Blue of the measurements.
pub(crate) const BLUE: RGBColor = RGBColor(31, 119, 180);
/// Orange of the true response.
pub(crate) const ORANGE: RGBColor = RGBColor(255, 127, 14);
/// Red of the model.
pub(crate) const RED: RGBColor = RGBColor(214, 39, 40);
/// Gray of bands.
pub(crate) const GRAY: RGBColor = RGBColor(150, 150, 150);
/// Dark gray of grid lines and bounds.
pub(crate) const DARK: RGBColor = RGBColor(60, 60, 60);

/// Drawing result with the error as text.
pub(crate) type Draw = std::result::Result<(), String>;

/// Turns any plotters error into text.
pub(crate) fn text<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// Registers the bundled font once per process.
pub fn register_fonts() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The bytes are a well-formed TTF shipped inside the crate; failure is impossible
        // in practice and would only mean text is not drawn.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
        let _ = plotters::style::register_font(FONT, FontStyle::Bold, dejavu::sans::bold());
        let _ = plotters::style::register_font(FONT, FontStyle::Italic, dejavu::sans::oblique());
        let _ = plotters::style::register_font(FONT, FontStyle::Oblique, dejavu::sans::oblique());
    });
}

/// A figure that can draw itself on any plotters backend.
pub(crate) trait Figure {
    /// File name without extension.
    fn name(&self) -> &'static str;
    /// Size in pixels.
    fn size(&self) -> (u32, u32);
    /// Draws the whole figure.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw;
}

/// Writes `figure` as `<name>.png` and `<name>.svg` into `dir` (see [`save_all`]).
pub(crate) fn save(figure: &(impl Figure + Sync), dir: &Path) -> Result<()> {
    save_all(&[figure], dir)
}

/// A figure as the writer sees it: its name and its two files.
pub(crate) trait Drawable: Sync {
    /// File name without extension.
    fn file_name(&self) -> &'static str;
    /// Draws the raster and writes `<name>.png` into `dir`.
    fn png(&self, dir: &Path) -> Draw;
    /// Draws the vector figure and writes `<name>.svg` into `dir`.
    fn svg(&self, dir: &Path) -> Draw;
}

impl<F: Figure + Sync> Drawable for F {
    fn file_name(&self) -> &'static str {
        self.name()
    }

    fn png(&self, dir: &Path) -> Draw {
        let (width, height) = self.size();
        let mut pixels = vec![0u8; 3 * width as usize * height as usize];
        let root = BitMapBackend::with_buffer(&mut pixels, (width, height)).into_drawing_area();
        draw_on(self, &root)?;
        drop(root);
        write_png(
            &dir.join(format!("{}.png", self.name())),
            &pixels,
            (width, height),
        )
    }

    fn svg(&self, dir: &Path) -> Draw {
        let path = dir.join(format!("{}.svg", self.name()));
        draw_on(
            self,
            &SVGBackend::new(&path, self.size()).into_drawing_area(),
        )
    }
}

/// Threads drawing the figures: the machine a run is made for has two cores.
const FIGURE_THREADS: usize = 2;

/// Writes every figure as `<name>.png` and `<name>.svg` into `dir`: the files are drawn
/// as independent jobs on two threads (rasters first, the slow ones), so a run waits
/// for its figures about half as long as drawing them one by one. The first failure in
/// `figures`' order is returned, naming its figure.
pub(crate) fn save_all(figures: &[&dyn Drawable], dir: &Path) -> Result<()> {
    let jobs: Vec<(usize, bool)> = (0..figures.len())
        .map(|i| (i, true))
        .chain((0..figures.len()).map(|i| (i, false)))
        .collect();
    let next = std::sync::atomic::AtomicUsize::new(0);
    let work = || {
        let mut done = Vec::new();
        loop {
            let j = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            let Some(&(i, raster)) = jobs.get(j) else {
                return done;
            };
            let figure = figures[i];
            done.push((
                j,
                if raster {
                    figure.png(dir)
                } else {
                    figure.svg(dir)
                },
            ));
        }
    };
    let mut outcomes = std::thread::scope(|s| {
        let helpers: Vec<_> = (1..FIGURE_THREADS.min(jobs.len()))
            .map(|_| s.spawn(work))
            .collect();
        let mut all = work();
        for helper in helpers {
            all.extend(helper.join().unwrap_or_default());
        }
        all
    });
    outcomes.sort_by_key(|(j, _)| *j);
    if outcomes.len() < jobs.len() {
        return Err(ExperimentError::run("figures", "a drawing thread panicked"));
    }
    for (j, outcome) in outcomes {
        let figure = figures[jobs[j].0];
        outcome
            .map_err(|e| ExperimentError::run("figures", format!("{}: {e}", figure.file_name())))?;
    }
    Ok(())
}

/// Encodes 8-bit RGB `pixels` as a PNG in memory, then writes it to `path` at once.
fn write_png(path: &Path, pixels: &[u8], (width, height): (u32, u32)) -> Draw {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(text)?;
    writer.write_image_data(pixels).map_err(text)?;
    writer.finish().map_err(text)?;
    std::fs::write(path, bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// Fills `root` white, draws `figure` on it and writes it out.
fn draw_on<DB: DrawingBackend>(figure: &impl Figure, root: &DrawingArea<DB, Shift>) -> Draw {
    root.fill(&WHITE).map_err(text)?;
    figure.draw(root)?;
    root.present().map_err(text)
}

/// Title style.
pub(crate) fn title_style() -> TextStyle<'static> {
    (FONT, 24).into_font().style(FontStyle::Bold).color(&BLACK)
}

/// Axis description style.
pub(crate) fn label_style() -> TextStyle<'static> {
    (FONT, 19).into_font().color(&BLACK)
}

/// Tick label style.
pub(crate) fn tick_style() -> TextStyle<'static> {
    (FONT, 16).into_font().color(&DARK)
}

/// Legend style.
pub(crate) fn legend_style() -> TextStyle<'static> {
    (FONT, 16).into_font().color(&BLACK)
}

/// A tick label: the value rounded to 1e-9 relative, shortest form ("8", "0.03").
pub(crate) fn tick(v: &f64) -> String {
    // Axis ticks computed as sums land near, not on, zero.
    if v.abs() < 1e-12 || !v.is_finite() {
        return "0".into();
    }
    let scale = 10f64.powi(9 - v.abs().log10().floor() as i32);
    let r = (v * scale).round() / scale;
    if r.abs() >= 1e6 || r.abs() < 1e-4 {
        format!("{r:e}")
    } else {
        format!("{r}")
    }
}

/// Tick positions on a logarithmic axis from `f0` to `f1`: 1, 2 and 5 per decade, or
/// where those give fewer than three (a span under a decade, as a band around one
/// resonance), about six round values evenly spaced.
pub(crate) fn log_ticks(f0: f64, f1: f64) -> Vec<f64> {
    if !(f0 > 0.0 && f1 > f0 && f1.is_finite()) {
        return Vec::new();
    }
    let (d0, d1) = (f0.log10().floor() as i32, f1.log10().ceil() as i32);
    let decades: Vec<f64> = (d0..=d1)
        .flat_map(|d| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(d)))
        .filter(|v| (f0..=f1).contains(v))
        .collect();
    if decades.len() >= 3 {
        return decades;
    }
    let raw = (f1 - f0) / 6.0;
    let power = 10f64.powi(raw.log10().floor() as i32);
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * power)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * power);
    let first = (f0 / step).ceil() as i64;
    let last = (f1 / step).floor() as i64;
    (first..=last).map(|i| i as f64 * step).collect()
}

/// A logarithmic frequency axis from `f0` to `f1` Hz whose ticks read ([`log_ticks`]).
pub(crate) fn log_frequency_axis(f0: f64, f1: f64) -> WithKeyPoints<LogCoord<f64>> {
    (f0..f1).log_scale().with_key_points(log_ticks(f0, f1))
}

/// A log frequency axis ([`log_frequency_axis`]) against a linear one.
pub(crate) type LogFrequencyPlane = Cartesian2d<WithKeyPoints<LogCoord<f64>>, RangedCoordf64>;

/// The phase panel of a Bode plot in the house style: log frequency from `f0` to `f1`
/// Hz, phase from `lo` to `hi` degrees, captioned and meshed; the caller draws the
/// series (the one panel of the frequency check's and the frequency-response fit's
/// figures).
pub(crate) fn phase_panel<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    (f0, f1): (f64, f64),
    (lo, hi): (f64, f64),
) -> std::result::Result<ChartContext<'a, DB, LogFrequencyPlane>, String> {
    let mut chart = ChartBuilder::on(area)
        .caption("Phase", title_style())
        .margin(14)
        .margin_right(28)
        .x_label_area_size(52)
        .y_label_area_size(96)
        .build_cartesian_2d(log_frequency_axis(f0, f1), lo..hi)
        .map_err(text)?;
    house_mesh(&mut chart.configure_mesh())
        .x_desc("frequency f [Hz]")
        .y_desc("phase ∠H(f) [°]")
        .y_label_formatter(&tick)
        .x_label_formatter(&|x| tick(x))
        .draw()
        .map_err(text)?;
    Ok(chart)
}

/// The house style of a chart's mesh: axis descriptions, tick labels, light and bold
/// grid lines and the axes.
pub(crate) fn house_mesh<'m, 'a, 'b, X, Y, XT, YT, DB>(
    mesh: &'m mut MeshStyle<'a, 'b, X, Y, DB>,
) -> &'m mut MeshStyle<'a, 'b, X, Y, DB>
where
    X: Ranged<ValueType = XT> + ValueFormatter<XT>,
    Y: Ranged<ValueType = YT> + ValueFormatter<YT>,
    DB: DrawingBackend,
{
    mesh.axis_desc_style(label_style())
        .label_style(tick_style())
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(215, 215, 215))
        .axis_style(DARK)
}

/// Ten distinct colours for series of one kind (FRFs of a set, modes), in order.
pub(crate) const CATEGORY_COLOURS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// The colour of series `i`: the ten of [`CATEGORY_COLOURS`], then each of them lighter
/// (halfway to white) for the next ten, and so on.
pub(crate) fn category_colour(i: usize) -> RGBColor {
    let RGBColor(r, g, b) = CATEGORY_COLOURS[i % CATEGORY_COLOURS.len()];
    let round = i / CATEGORY_COLOURS.len();
    let light = |c: u8| 255 - ((255 - u32::from(c)) >> round.min(3)) as u8;
    RGBColor(light(r), light(g), light(b))
}

/// Width in pixels of a key column beside a chart (see [`draw_key`]).
pub(crate) const KEY_WIDTH: u32 = 240;

/// Draws a key — a colour swatch and a label per entry, under `title` — down `area`, a
/// column beside the chart, so that it covers no data. Entries past the column's height
/// end in "… and N more".
pub(crate) fn draw_key<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    entries: &[(String, RGBColor)],
) -> Draw {
    let (_, height) = area.dim_in_pixel();
    let (row, top) = (24i32, 70i32);
    let bold = (FONT, 16).into_font().style(FontStyle::Bold).color(&BLACK);
    area.draw(&Text::new(title.to_string(), (8, top - 34), bold))
        .map_err(text)?;
    let fits = ((height as i32 - top - 40) / row).max(1) as usize;
    let shown = if entries.len() > fits {
        fits - 1
    } else {
        entries.len()
    };
    for (k, (label, colour)) in entries.iter().take(shown).enumerate() {
        let y = top + row * k as i32;
        area.draw(&PathElement::new(
            vec![(8, y), (36, y)],
            colour.stroke_width(3),
        ))
        .map_err(text)?;
        area.draw(&Text::new(label.clone(), (44, y - 9), legend_style()))
            .map_err(text)?;
    }
    if shown < entries.len() {
        let y = top + row * shown as i32;
        let more = format!("… and {} more", entries.len() - shown);
        area.draw(&Text::new(more, (8, y - 9), legend_style()))
            .map_err(text)?;
    }
    Ok(())
}

/// Draws the legend of `chart` at `position` in a light box.
pub(crate) fn draw_legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
) -> Draw {
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.88))
        .border_style(GRAY)
        .label_font(legend_style())
        .margin(12)
        .draw()
        .map_err(text)
}

/// The figure's title above everything; returns the area below it.
pub(crate) fn suptitle<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
) -> Result<DrawingArea<DB, Shift>, String> {
    root.titled(
        title,
        (FONT, 28).into_font().style(FontStyle::Bold).color(&BLACK),
    )
    .map_err(text)
}

/// Lower and upper limits of all values, widened by 5 % (and made non-degenerate).
pub(crate) fn limits<'a>(series: impl IntoIterator<Item = &'a [f64]>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for s in series {
        for &v in s {
            if v.is_finite() {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
    }
    if !lo.is_finite() || !hi.is_finite() {
        return (-1.0, 1.0);
    }
    let span = hi - lo;
    let pad = if span > 0.0 {
        0.05 * span
    } else {
        0.5 * lo.abs().max(1e-12)
    };
    (lo - pad, hi + pad)
}

/// At most about `max` points of the line (x, y) that keep each bucket's minimum and
/// maximum in order, so the drawn envelope equals the full line's.
pub(crate) fn thin_line(x: &[f64], y: &[f64], max: usize) -> Vec<(f64, f64)> {
    let n = x.len().min(y.len());
    if n <= max || max < 4 {
        return x.iter().copied().zip(y.iter().copied()).take(n).collect();
    }
    let buckets = max / 2;
    let mut out = Vec::with_capacity(2 * buckets + 2);
    for b in 0..buckets {
        let (lo, hi) = (
            b * n / buckets,
            ((b + 1) * n / buckets).max(b * n / buckets + 1),
        );
        let slice = &y[lo..hi];
        let (mut imin, mut imax) = (0, 0);
        for (i, v) in slice.iter().enumerate() {
            if *v < slice[imin] {
                imin = i;
            }
            if *v > slice[imax] {
                imax = i;
            }
        }
        let (first, second) = if imin <= imax {
            (imin, imax)
        } else {
            (imax, imin)
        };
        out.push((x[lo + first], y[lo + first]));
        if second != first {
            out.push((x[lo + second], y[lo + second]));
        }
    }
    out
}

/// Every k-th point so that at most `max` markers are drawn.
pub(crate) fn thin_points(x: &[f64], y: &[f64], max: usize) -> Vec<(f64, f64)> {
    let n = x.len().min(y.len());
    let step = n.div_ceil(max.max(1)).max(1);
    (0..n).step_by(step).map(|i| (x[i], y[i])).collect()
}

/// `x` scaled by `factor`.
pub(crate) fn scaled(x: &[f64], factor: f64) -> Vec<f64> {
    x.iter().map(|v| v * factor).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thinning_keeps_the_extremes() {
        let x: Vec<f64> = (0..10_000).map(|i| i as f64).collect();
        let y: Vec<f64> = x.iter().map(|t| (t * 0.37).sin() * t).collect();
        let thin = thin_line(&x, &y, 1000);
        assert!(thin.len() <= 1000);
        let max = y.iter().copied().fold(f64::MIN, f64::max);
        let min = y.iter().copied().fold(f64::MAX, f64::min);
        assert!(thin.iter().any(|p| p.1 == max) && thin.iter().any(|p| p.1 == min));
        assert!(thin.windows(2).all(|w| w[0].0 < w[1].0));
    }

    #[test]
    fn limits_pad_and_survive_constants() {
        assert_eq!(limits([&[0.0, 10.0][..]]), (-0.5, 10.5));
        let (lo, hi) = limits([&[2.0, 2.0][..]]);
        assert!(lo < 2.0 && hi > 2.0);
    }
}
