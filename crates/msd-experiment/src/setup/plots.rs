//! The figures of a setup run, PNG and SVG in the house style:
//!
//! - `setup_fit`: each channel of the first record, measured and predicted, with the
//!   residuals (no excitation panel for a free decay; the drive on top otherwise), over
//!   a window of 25 periods of fn when the record holds more than 50;
//! - `setup_noise_spectrum`: each channel of the first record, its residual's spectrum
//!   against the noise model's (or the white level the intervals assume);
//! - `setup_loops` (test machine): the force–stroke loop of each condition's last
//!   cycle, measured and fitted;
//! - `setup_force_velocity` (test machine): the damping force F − m·x″ − k·x against
//!   the velocity, every condition's samples and the fitted law.

use super::fit::models;
use super::{SetupFit, SetupOutcome};
use crate::error::Result;
use crate::plots::panel::{Curve, Panel, Stack, Style};
use crate::plots::spectrum::{NoiseSpectra, SpectrumPanel};
use crate::plots::{BLUE, Drawable, RED, register_fonts, save_all};
use msd_ident::RecordsFit;
use plotters::prelude::*;
use std::path::Path;

/// Writes every figure of the setup; returns their base names.
pub(crate) fn write_all(o: &SetupOutcome, dir: &Path) -> Result<Vec<&'static str>> {
    register_fonts();
    let time = o.data.records.first().map(|r| r.recording.times());
    let figures = match &o.fit {
        SetupFit::Records { .. } => vec![time.as_deref().and_then(|t| fit_figure(o, t))],
        SetupFit::Machine(_) => vec![loops(o), force_velocity(o)],
        SetupFit::Stroke(f) => vec![stroke_force(o, f)],
    };
    let spectra = match &o.fit {
        SetupFit::Records { fit, .. } => noise_spectra(o, fit),
        _ => None,
    };
    let drawn: Vec<&dyn Drawable> = (figures.iter().flatten())
        .map(|f| f as &dyn Drawable)
        .chain(spectra.iter().map(|f| f as &dyn Drawable))
        .collect();
    save_all(&drawn, dir)?;
    Ok(drawn.iter().map(|f| f.file_name()).collect())
}

/// The first record on its sample times `time`.
fn fit_figure<'a>(o: &'a SetupOutcome, time: &'a [f64]) -> Option<Stack<'a>> {
    let record = o.data.records.first()?;
    let range = (*time.first()?, *time.last()?);
    let mut panels = Vec::new();
    if let Some(x) = record.recording.inputs.first() {
        panels.push(Panel {
            title: format!("Drive: {}", o.data.setup.excitation.name()),
            x_desc: "time t [s]".into(),
            y_desc: format!(
                "{} [{}]",
                o.data.setup.excitation.name(),
                o.data.setup.excitation.unit()
            ),
            x_range: range,
            curves: vec![Curve {
                label: "measured".into(),
                x: time,
                y: x.samples.clone(),
                style: Style::Line(BLUE, 1),
            }],
            band: None,
            legend: None,
        });
    }
    for ((samples, channel), (_, model)) in (record.recording.responses())
        .zip(&o.data.channels)
        .zip(models(o, 0))
    {
        panels.push(Panel {
            title: format!("{} — {}", channel.channel_name(), record.name()),
            x_desc: "time t [s]".into(),
            y_desc: format!("{} [{}]", channel.quantity, channel.quantity.si_unit()),
            x_range: range,
            curves: vec![
                Curve {
                    label: "measured".into(),
                    x: time,
                    y: samples.to_vec(),
                    style: Style::Points(BLUE, 2),
                },
                Curve {
                    label: "model".into(),
                    x: time,
                    y: model.to_vec(),
                    // Thin, so that the measured points stay visible under it.
                    style: Style::Line(RED, 1),
                },
            ],
            band: None,
            legend: Some(SeriesLabelPosition::UpperRight),
        });
    }
    let stack = Stack {
        name: "setup_fit",
        title: format!("Fit of the first record — {}", o.config.name),
        panels,
    };
    Some(match &o.fit {
        SetupFit::Records { fit, .. } => {
            stack.windowed(range, fit.plant.natural_frequency_hz.value)
        }
        _ => stack,
    })
}

/// The first record's channels: each residual's spectrum against the noise model's.
fn noise_spectra<'a>(o: &'a SetupOutcome, fit: &'a RecordsFit) -> Option<NoiseSpectra<'a>> {
    let first = &fit.whiteness.first()?.record;
    let panels: Vec<SpectrumPanel<'_>> = (fit.whiteness.iter())
        .filter(|c| &c.record == first)
        .zip(&o.data.channels)
        .filter_map(|(check, channel)| {
            Some(SpectrumPanel {
                title: format!("{} — {}", channel.channel_name(), check.record),
                unit: channel.quantity.si_unit().to_string(),
                spectrum: check.spectrum.as_ref()?,
            })
        })
        .collect();
    (!panels.is_empty()).then(|| NoiseSpectra {
        name: "setup_noise_spectrum",
        title: format!(
            "Residual spectra against the noise model — {}",
            o.config.name
        ),
        panels,
    })
}

/// A condition in the legend: its frequency and stroke amplitude.
fn condition_label(c: &msd_ident::dynamometer::ConditionSummary) -> String {
    format!(
        "{} Hz, {} mm",
        crate::fmt::sig(c.frequency_hz, 3),
        crate::fmt::sig(c.amplitude * 1e3, 3)
    )
}

/// Each condition's last whole cycle, measured (points) and fitted (line).
fn loops(o: &SetupOutcome) -> Option<Stack<'_>> {
    let SetupFit::Machine(m) = &o.fit else {
        return None;
    };
    let best = m.laws.get(m.best)?;
    let mut curves = Vec::new();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (i, (c, model)) in m.conditions.iter().zip(&best.model_force).enumerate() {
        let n = c.displacement.len();
        let from = n.saturating_sub(n / c.cycles.max(1) + 1);
        let x = &c.displacement[from..];
        for v in x {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
        let colour = crate::plots::category_colour(i);
        curves.push(Curve {
            label: condition_label(c),
            x,
            y: c.force[from..].to_vec(),
            style: Style::Points(colour, 2),
        });
        curves.push(Curve {
            label: String::new(),
            x,
            y: model[from..].to_vec(),
            style: Style::Line(colour, 2),
        });
    }
    let panel = Panel {
        title: format!(
            "Force–stroke loops, last cycle; lines: {}",
            best.law.formula()
        ),
        x_desc: "stroke x [m]".into(),
        y_desc: "force F [N]".into(),
        x_range: crate::plots::limits([[lo, hi].as_slice()]),
        curves,
        band: None,
        legend: Some(SeriesLabelPosition::UpperLeft),
    };
    Some(Stack {
        name: "setup_loops",
        title: format!("Test machine loops — {}", o.config.name),
        panels: vec![panel],
    })
}

/// The damping force F − m·x″ − k·x (the measured force less the fitted inertia and
/// spring) against the velocity, every condition, and the fitted law.
fn force_velocity(o: &SetupOutcome) -> Option<Stack<'_>> {
    let SetupFit::Machine(m) = &o.fit else {
        return None;
    };
    let best = m.laws.get(m.best)?;
    let mut curves = Vec::new();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (i, (c, model)) in m.conditions.iter().zip(&best.model_force).enumerate() {
        let damping: Vec<f64> = c
            .force
            .iter()
            .zip(model)
            .zip(&c.velocity)
            .map(|((f, fm), v)| f - fm + best.damping_force(*v))
            .collect();
        for v in &c.velocity {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
        curves.push(Curve {
            label: condition_label(c),
            x: &c.velocity,
            y: damping,
            style: Style::Points(crate::plots::category_colour(i), 1),
        });
    }
    // The law along one whole cycle of the fastest condition: the line runs over
    // [−v_max, v_max] and back over itself, as law(v) is a function of v alone.
    let fastest = m
        .conditions
        .iter()
        .max_by(|a, b| a.peak_velocity.total_cmp(&b.peak_velocity))?;
    let n = fastest.velocity.len();
    let cycle = &fastest.velocity[n.saturating_sub(n / fastest.cycles.max(1) + 1)..];
    curves.push(Curve {
        label: format!("fitted law: {}", best.law.formula()),
        x: cycle,
        y: cycle.iter().map(|v| best.damping_force(*v)).collect(),
        style: Style::Line(RED, 3),
    });
    let panel = Panel {
        title: "Damping force against velocity".into(),
        x_desc: "velocity x′ [m/s]".into(),
        y_desc: "F − m·x″ − k·x [N]".into(),
        x_range: crate::plots::limits([[lo, hi].as_slice()]),
        curves,
        band: None,
        legend: Some(SeriesLabelPosition::UpperLeft),
    };
    Some(Stack {
        name: "setup_force_velocity",
        title: format!("Test machine damping law — {}", o.config.name),
        panels: vec![panel],
    })
}

/// Any stroke: each record's force (low-passed) and the best law's prediction from its
/// stroke, the validation records' on fresh data, one panel per record (at most four).
fn stroke_force<'a>(o: &'a SetupOutcome, f: &'a super::stroke::StrokeFit) -> Option<Stack<'a>> {
    let law = f.inverse.laws.get(f.inverse.best)?.law.formula();
    let panels: Vec<Panel<'a>> = f
        .predictions
        .iter()
        .take(4)
        .filter_map(|p| {
            let range = (*p.time.first()?, *p.time.last()?);
            Some(Panel {
                title: format!(
                    "{} ({}): blue measured (low-passed), red model; RMS error {} N of {} N",
                    p.record,
                    if p.validation {
                        "validation, not fitted"
                    } else {
                        "fitted"
                    },
                    crate::fmt::sig(p.rms_error, 3),
                    crate::fmt::sig(p.rms_force, 3)
                ),
                x_desc: "time t [s]".into(),
                y_desc: "force F [N]".into(),
                x_range: range,
                curves: vec![
                    Curve {
                        label: "measured (low-passed)".into(),
                        x: &p.time,
                        y: p.force.measured.clone(),
                        style: Style::Points(BLUE, 2),
                    },
                    Curve {
                        label: format!("model: {law}"),
                        x: &p.time,
                        y: p.force.predicted.clone(),
                        style: Style::Line(RED, 1),
                    },
                ],
                band: None,
                legend: None,
            })
        })
        .collect();
    Some(Stack {
        name: "setup_stroke_force",
        title: format!("Test machine, any stroke — {}", o.config.name),
        panels,
    })
}
