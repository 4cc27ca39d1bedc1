//! `nonlinear_residuals`: the validation residuals of every nonlinear candidate over
//! time, overlaid in one panel (worst-ranked first, so the best lies on top) with their
//! RMS in the legend, and a zoomed window for a long record.

use super::Units;
use super::time::zoom_range;
use crate::paper::Outcome;
use crate::plots::panel::{Curve, Panel, PanelFigure, Style};
use crate::plots::{BLUE, GRAY, ORANGE, RED, scaled};
use plotters::prelude::*;

/// Colours of the candidates by rank (the linear model is always gray).
const PALETTE: [RGBColor; 5] = [
    RED,
    BLUE,
    ORANGE,
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
];

/// The figure, when the run estimated nonlinear models.
pub(crate) fn residuals<'a>(o: &'a Outcome, u: &Units) -> Option<PanelFigure<'a>> {
    let n = o.nonlinear.as_ref()?;
    let rows = &n.comparison.rows;
    let t = o.data.validation.excitation.times();
    let last = t.len().checked_sub(1)?;
    let from = rows.first().map_or(0, |r| r.scored_from).min(last);
    let zoom = zoom_range(o, t, from);
    let mut colours = PALETTE.iter().cycle();
    let mut curves: Vec<Curve<'a>> = rows
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let colour = if r.structure.is_linear() {
                GRAY
            } else {
                *colours.next().unwrap_or(&RED)
            };
            Curve {
                label: format!(
                    "#{} {}: RMS {} {}",
                    i + 1,
                    r.structure,
                    crate::fmt::sig(r.validation_rms * u.output_factor, 3),
                    u.output
                ),
                x: &t[from..],
                y: scaled(&r.validation_residuals[from..], u.output_factor),
                // Thin lines: residuals are noisy, and wide polylines spike at sharp turns.
                style: Style::Line(colour, 1),
            }
        })
        .collect();
    curves.reverse();
    let panel = Panel {
        title: if rows.len() > 1 {
            format!(
                "Validation residuals y − ŷ of {} candidate models, ranked by BIC",
                rows.len()
            )
        } else {
            "Validation residuals y − ŷ of the nonlinear model".to_string()
        },
        x_desc: "time t [s]".into(),
        y_desc: format!("residual [{}]", u.output),
        x_range: (t[from], t[last]),
        curves,
        band: None,
        legend: Some(SeriesLabelPosition::UpperRight),
    };
    let zoom = zoom.map(|r| panel.zoomed(r, format!("Zoom: {:.2} s … {:.2} s", r.0, r.1)));
    Some(PanelFigure {
        name: "nonlinear_residuals",
        title: format!("Nonlinear models — {}", o.config.name),
        panel,
        zoom,
    })
}
