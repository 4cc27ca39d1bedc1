//! The paper's time-domain figures: Figures 2, 3 and 4.

use super::Units;
use crate::paper::Outcome;
use crate::plots::panel::{Band, Curve, Panel, PanelFigure, Style};
use crate::plots::{BLUE, DARK, Draw, Figure, ORANGE, RED, scaled, suptitle};
use plotters::coord::Shift;
use plotters::prelude::*;

/// More periods of the natural frequency than this in a record earn a zoomed panel.
const ZOOM_PERIODS: f64 = 60.0;
/// Periods shown in a zoomed panel.
const ZOOM_WINDOW_PERIODS: f64 = 25.0;

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
