//! Diagnostic figures: residual correlations and the frequency-response (Bode) check.

use super::Units;
use crate::plots::{
    BLUE, DARK, Draw, Figure, GRAY, RED, draw_legend, house_mesh, phase_panel, suptitle, text,
    thin_line, tick, title_style,
};
use msd_ident::{ResidualAnalysis, frequency::FrequencyCheck, residuals::CorrelationTest};
use plotters::coord::Shift;
use plotters::coord::combinators::{LogCoord, WithKeyPoints};
use plotters::coord::ranged1d::Ranged;
use plotters::prelude::*;

/// Residual autocorrelation (top) and residual–input cross-correlation (bottom).
pub(crate) struct Correlation<'a> {
    analysis: &'a ResidualAnalysis,
}

impl<'a> Correlation<'a> {
    pub(crate) fn new(analysis: &'a ResidualAnalysis) -> Self {
        Self { analysis }
    }
}

fn stems<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    y_desc: &str,
    test: &CorrelationTest,
    color: RGBColor,
    skip_zero: bool,
) -> Draw {
    // The autocorrelation at lag 0 is 1 by definition: leave it out so the rest shows.
    let keep: Vec<usize> = (0..test.lags.len())
        .filter(|&i| !(skip_zero && test.lags[i] == 0))
        .collect();
    let lags: Vec<i64> = keep.iter().map(|&i| test.lags[i]).collect();
    let values: Vec<f64> = keep.iter().map(|&i| test.values[i]).collect();
    let (first, last) = (
        *lags.first().unwrap_or(&0) as f64,
        *lags.last().unwrap_or(&1) as f64,
    );
    let peak = values
        .iter()
        .fold(test.bound * 1.5, |m, v| m.max(v.abs()))
        .min(1.0);
    let (lo, hi) = (-peak * 1.1, peak * 1.1);
    let mut chart = ChartBuilder::on(area)
        .caption(title, title_style())
        .margin(14)
        .margin_right(28)
        .x_label_area_size(52)
        .y_label_area_size(86)
        .build_cartesian_2d((first - 0.8)..(last + 0.8), lo..hi)
        .map_err(text)?;
    house_mesh(&mut chart.configure_mesh())
        .x_desc("lag k [samples]")
        .y_desc(y_desc)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .draw()
        .map_err(text)?;
    let fill = RGBColor(120, 170, 220).mix(0.25);
    let b = test.bound;
    chart
        .draw_series(std::iter::once(Rectangle::new(
            [(first - 0.8, -b), (last + 0.8, b)],
            fill.filled(),
        )))
        .map_err(text)?
        .label(format!("confidence band ±{b:.4}"))
        .legend(move |(x, y)| Rectangle::new([(x, y - 7), (x + 24, y + 7)], fill.filled()));
    for sign in [-1.0, 1.0] {
        chart
            .draw_series(DashedLineSeries::new(
                vec![(first - 0.8, sign * b), (last + 0.8, sign * b)],
                8,
                5,
                DARK.stroke_width(1),
            ))
            .map_err(text)?;
    }
    chart
        .draw_series(lags.iter().zip(&values).map(|(&k, &v)| {
            PathElement::new(vec![(k as f64, 0.0), (k as f64, v)], color.stroke_width(2))
        }))
        .map_err(text)?;
    chart
        .draw_series(
            lags.iter()
                .zip(&values)
                .map(|(&k, &v)| Circle::new((k as f64, v), 4, color.filled())),
        )
        .map_err(text)?
        .label(if test.passed {
            "correlation (test passed)"
        } else {
            "correlation (test FAILED)"
        })
        .legend(move |(x, y)| Circle::new((x + 12, y), 4, color.filled()));
    draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
}

impl Figure for Correlation<'_> {
    fn name(&self) -> &'static str {
        "residual_correlation"
    }
    fn size(&self) -> (u32, u32) {
        (1400, 950)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let a = self.analysis;
        let area = suptitle(root, "Residual diagnostics (identification data)")?;
        let h = area.dim_in_pixel().1 as i32;
        let (top, bottom) = area.split_vertically(h / 2);
        stems(
            &top,
            &format!(
                "Autocorrelation of the residuals: {} → {}",
                a.ljung_box,
                if a.whiteness_passed {
                    "white"
                } else {
                    "not white"
                }
            ),
            "autocorrelation r(k), k ≥ 1",
            &a.autocorrelation,
            BLUE,
            true,
        )?;
        stems(
            &bottom,
            &format!(
                "Cross-correlation residual–input: max |ρ| = {:.3} → {}",
                a.cross_correlation.max_abs,
                if a.cross_correlation_passed {
                    "independent of the input"
                } else {
                    "correlated with the input"
                }
            ),
            "cross-correlation ρ(k)",
            &a.cross_correlation,
            RED,
            false,
        )
    }
}

/// The data's H1 frequency response beside the model's, magnitude over phase.
pub(crate) struct Bode<'a> {
    check: &'a FrequencyCheck,
    parameters: msd_ident::Parameters,
    units: Units,
    data_name: &'static str,
}

impl<'a> Bode<'a> {
    pub(crate) fn new(
        check: &'a FrequencyCheck,
        parameters: msd_ident::Parameters,
        units: &Units,
        data_name: &'static str,
    ) -> Self {
        Self {
            check,
            parameters,
            units: units.clone(),
            data_name,
        }
    }
}

impl Figure for Bode<'_> {
    fn name(&self) -> &'static str {
        "frf_bode"
    }
    fn size(&self) -> (u32, u32) {
        (1400, 1000)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let area = suptitle(
            root,
            &format!(
                "Frequency response: H1 estimate from the {} data vs the identified model",
                self.data_name
            ),
        )?;
        let h = area.dim_in_pixel().1 as i32;
        let (top, bottom) = area.split_vertically(h * 55 / 100);
        let curves = BodeCurves::new(self.check, &self.parameters)?;
        self.draw_magnitude(&top, &curves)?;
        let phase = PhaseCurves {
            f: &curves.f,
            data: &curves.data_phase,
            model_at_data: &curves.model_phase_at_data,
            dense: &curves.dense,
            model: &curves.model_phase,
        };
        let c = self.check;
        draw_phase(&bottom, &phase, c.band_hz, c.model_natural_frequency_hz)
    }
}

/// The Bode check's curves: the data at positive frequencies with finite values (a log
/// axis), the model on a dense logarithmic grid, and the magnitude axis's range.
struct BodeCurves {
    /// The data's frequencies, Hz.
    f: Vec<f64>,
    /// The data's magnitude.
    data_magnitude: Vec<f64>,
    /// The data's phase, wrapped to within ±180° of the model's at each frequency.
    data_phase: Vec<f64>,
    /// The model's phase at the data's frequencies, degrees.
    model_phase_at_data: Vec<f64>,
    /// The dense grid, Hz.
    dense: Vec<f64>,
    /// The model's magnitude and phase on it.
    model_magnitude: Vec<f64>,
    model_phase: Vec<f64>,
    /// The magnitude axis spans the model and the data inside the fit band (outside it
    /// the input has no power and H1 is noise).
    magnitude_range: (f64, f64),
}

/// How far (a factor) the magnitude axis reaches past the band's data and the model to
/// show out-of-band data.
const OUT_OF_BAND_DECADES: f64 = 100.0;

impl BodeCurves {
    fn new(c: &FrequencyCheck, p: &msd_ident::Parameters) -> std::result::Result<Self, String> {
        let keep: Vec<usize> = (0..c.frequency_hz.len())
            .filter(|&i| {
                c.frequency_hz[i] > 0.0
                    && c.empirical_magnitude[i] > 0.0
                    && c.model_magnitude[i] > 0.0
                    && c.empirical_magnitude[i].is_finite()
            })
            .collect();
        if keep.len() < 2 {
            return Err("fewer than two positive frequencies to draw".into());
        }
        let f: Vec<f64> = keep.iter().map(|&i| c.frequency_hz[i]).collect();
        let data_magnitude: Vec<f64> = keep.iter().map(|&i| c.empirical_magnitude[i]).collect();
        // The model on a dense logarithmic grid (smooth through the resonance).
        let (f0, f1) = (f[0], f[f.len() - 1]);
        let dense: Vec<f64> = (0..=800)
            .map(|i| f0 * (f1 / f0).powf(i as f64 / 800.0))
            .collect();
        let response = |fi: f64| {
            let w = std::f64::consts::TAU * fi;
            let (re, im) = (p.stiffness - p.mass * w * w, p.damping * w);
            (1.0 / re.hypot(im), -im.atan2(re).to_degrees())
        };
        let model_magnitude: Vec<f64> = dense.iter().map(|&fi| response(fi).0).collect();
        let model_phase: Vec<f64> = dense.iter().map(|&fi| response(fi).1).collect();
        let model_phase_at_data: Vec<f64> = f.iter().map(|&fi| response(fi).1).collect();
        let data_phase: Vec<f64> = keep
            .iter()
            .zip(&model_phase_at_data)
            .map(|(&i, m)| m + (c.empirical_phase_deg[i] - m + 180.0).rem_euclid(360.0) - 180.0)
            .collect();
        let [b0, b1] = c.band_hz;
        let in_band = f
            .iter()
            .zip(&data_magnitude)
            .filter(|(fi, _)| **fi >= b0 && **fi <= b1)
            .map(|(_, v)| v);
        let span = |values: &mut dyn Iterator<Item = &f64>| {
            values.fold((f64::INFINITY, 0.0f64), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            })
        };
        let (lo, hi) = span(&mut model_magnitude.iter().chain(in_band));
        // Out-of-band data shown too, within two decades of the band's range: past that it
        // is the noise of lines without input power, drawn as a gap at the axis' edge.
        let (all_lo, all_hi) = span(&mut data_magnitude.iter());
        let magnitude_range = (
            lo.min(all_lo.max(lo / OUT_OF_BAND_DECADES)),
            hi.max(all_hi.min(hi * OUT_OF_BAND_DECADES)),
        );
        Ok(Self {
            f,
            data_magnitude,
            data_phase,
            model_phase_at_data,
            dense,
            model_magnitude,
            model_phase,
            magnitude_range,
        })
    }
}

impl Bode<'_> {
    /// The magnitude panel: the fit band shaded, the data, the model, the model's fn.
    fn draw_magnitude<DB: DrawingBackend>(
        &self,
        top: &DrawingArea<DB, Shift>,
        curves: &BodeCurves,
    ) -> Draw {
        let c = self.check;
        let f = &curves.f;
        let (f0, f1) = (f[0], f[f.len() - 1]);
        let (mlo, mhi) = curves.magnitude_range;
        let [b0, b1] = c.band_hz;
        let fn_model = c.model_natural_frequency_hz;
        let fn_data = c.natural_frequency_hz;
        let unit = format!("{}/{}", self.units_output_raw(), self.units.input);

        let mut chart = ChartBuilder::on(top)
            .caption(
                format!(
                    "Magnitude: fn = {fn_data:.4} Hz, ζ = {:.4} (data) vs fn = {fn_model:.4} Hz, ζ = {:.4} (model) → {}",
                    c.damping_ratio,
                    c.model_damping_ratio,
                    if c.consistent { "consistent" } else { "NOT consistent" }
                ),
                title_style(),
            )
            .margin(14)
            .margin_right(28)
            .x_label_area_size(52)
            .y_label_area_size(96)
            .build_cartesian_2d(
                crate::plots::log_frequency_axis(f0, f1),
                ((mlo * 0.7)..(mhi * 1.5)).log_scale(),
            )
            .map_err(text)?;
        house_mesh(&mut chart.configure_mesh())
            .x_desc("frequency f [Hz]")
            .y_desc(format!("|H(f)| [{unit}]"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .x_label_formatter(&|v| format!("{v}"))
            .draw()
            .map_err(text)?;
        let band = RGBColor(255, 220, 150).mix(0.3);
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(b0.max(f0), mlo * 0.7), (b1.min(f1), mhi * 1.5)],
                band.filled(),
            )))
            .map_err(text)?
            .label("band of the single-mode fit")
            .legend(move |(x, y)| Rectangle::new([(x, y - 7), (x + 24, y + 7)], band.filled()));
        // Beyond the axis a line would be drawn past the plot area: a gap there instead
        // (never a flat line at the edge, which would read as data).
        let inside: Vec<f64> = curves
            .data_magnitude
            .iter()
            .map(|&v| {
                if (mlo * 0.7..=mhi * 1.5).contains(&v) {
                    v
                } else {
                    f64::NAN
                }
            })
            .collect();
        draw_data(&mut chart, f, &inside, [b0, b1], true)?;
        chart
            .draw_series(LineSeries::new(
                curves
                    .dense
                    .iter()
                    .copied()
                    .zip(curves.model_magnitude.iter().copied()),
                RED.stroke_width(3),
            ))
            .map_err(text)?
            .label("model 1/(k − m ω² + j c ω)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], RED.stroke_width(3)));
        if fn_model > f0 && fn_model < f1 {
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(fn_model, mlo * 0.7), (fn_model, mhi * 1.5)],
                    8,
                    5,
                    BLACK.stroke_width(2),
                ))
                .map_err(text)?
                .label(format!("ωn of the model: fn = {fn_model:.4} Hz"))
                .legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 10, y)], BLACK.stroke_width(2))
                });
        }
        draw_legend(&mut chart, SeriesLabelPosition::LowerLeft)
    }
}

/// The curves of the Bode check's phase panel, degrees.
struct PhaseCurves<'a> {
    /// The data's frequencies, Hz.
    f: &'a [f64],
    /// The data's phase, wrapped near the model's.
    data: &'a [f64],
    /// The model's phase at the data's frequencies.
    model_at_data: &'a [f64],
    /// A dense logarithmic grid, Hz.
    dense: &'a [f64],
    /// The model's phase on it.
    model: &'a [f64],
}

/// The Bode check's phase panel: the fit band shaded, the data, the model and its fn.
fn draw_phase<DB: DrawingBackend>(
    bottom: &DrawingArea<DB, Shift>,
    c: &PhaseCurves<'_>,
    [b0, b1]: [f64; 2],
    fn_model: f64,
) -> Draw {
    let (f0, f1) = (c.f[0], c.f[c.f.len() - 1]);
    let band = RGBColor(255, 220, 150).mix(0.3);
    let (plo, phi) = c
        .model_at_data
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    let (plo, phi) = (
        (plo / 45.0).floor() * 45.0 - 60.0,
        (phi / 45.0).ceil() * 45.0 + 60.0,
    );
    let mut chart = phase_panel(bottom, (f0, f1), (plo, phi))?;
    chart
        .draw_series(std::iter::once(Rectangle::new(
            [(b0.max(f0), plo), (b1.min(f1), phi)],
            band.filled(),
        )))
        .map_err(text)?;
    let clamped: Vec<f64> = c.data.iter().map(|v| v.clamp(plo, phi)).collect();
    draw_data(&mut chart, c.f, &clamped, [b0, b1], false)?;
    chart
        .draw_series(LineSeries::new(
            c.dense.iter().copied().zip(c.model.iter().copied()),
            RED.stroke_width(3),
        ))
        .map_err(text)?;
    if fn_model > f0 && fn_model < f1 {
        chart
            .draw_series(DashedLineSeries::new(
                vec![(fn_model, plo), (fn_model, phi)],
                8,
                5,
                BLACK.stroke_width(2),
            ))
            .map_err(text)?;
    }
    Ok(())
}

/// The data's curve: blue inside the excited band, light gray outside (where the input
/// carries no power and H1 is noise).
fn draw_data<DB: DrawingBackend, Y: Ranged<ValueType = f64>>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<WithKeyPoints<LogCoord<f64>>, Y>>,
    f: &[f64],
    v: &[f64],
    [b0, b1]: [f64; 2],
    legend: bool,
) -> Draw {
    let inside = |fi: f64| fi >= b0 && fi <= b1;
    // Runs of one kind (in the band or not), joined to the previous run; a value that is
    // not finite (off the axis) ends a run without joining.
    let mut runs: Vec<(bool, Vec<(f64, f64)>)> = Vec::new();
    let mut broken = false;
    for (&fi, &vi) in f.iter().zip(v) {
        if !vi.is_finite() {
            broken = true;
            continue;
        }
        let flag = inside(fi);
        match runs.last_mut() {
            Some((g, points)) if *g == flag && !broken => points.push((fi, vi)),
            Some((_, points)) if !broken => {
                let last = *points.last().unwrap_or(&(fi, vi));
                runs.push((flag, vec![last, (fi, vi)]));
            }
            _ => runs.push((flag, vec![(fi, vi)])),
        }
        broken = false;
    }
    let (mut labelled_in, mut labelled_out) = (!legend, !legend);
    for (flag, points) in runs {
        let style = if flag {
            BLUE.stroke_width(2)
        } else {
            GRAY.mix(0.7).stroke_width(1)
        };
        let series = chart
            .draw_series(LineSeries::new(
                thin_line(
                    &points.iter().map(|p| p.0).collect::<Vec<_>>(),
                    &points.iter().map(|p| p.1).collect::<Vec<_>>(),
                    3000,
                ),
                style,
            ))
            .map_err(text)?;
        if flag && !labelled_in {
            labelled_in = true;
            series
                .label("data: H1 = S_yu / S_uu")
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], BLUE.stroke_width(2)));
        } else if !flag && !labelled_out {
            labelled_out = true;
            series
                .label("data outside the excited band")
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], GRAY.stroke_width(2)));
        }
    }
    Ok(())
}

impl Bode<'_> {
    /// The output unit of the data (m, not the displayed mm: |H| is in data units).
    fn units_output_raw(&self) -> String {
        if self.units.output == "mm" && self.units.output_factor == 1e3 {
            "m".into()
        } else {
            self.units.output.clone()
        }
    }
}
