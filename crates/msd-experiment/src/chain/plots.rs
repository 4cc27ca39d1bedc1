//! The figure of a chain run, PNG and SVG in the house style: `chain_fit`, the drive and
//! each sensor, measured and as fitted.

use super::{ChainOutcome, channel_names};
use crate::error::Result;
use crate::plots::panel::{Band, Curve, Panel, Stack, Style};
use crate::plots::{BLUE, RED, register_fonts, save};
use plotters::prelude::SeriesLabelPosition;
use std::path::Path;

/// Writes the figure; returns its base name.
pub(crate) fn write_all(o: &ChainOutcome, dir: &Path) -> Result<Vec<&'static str>> {
    register_fonts();
    let time: Vec<f64> = (0..o.record.len())
        .map(|k| k as f64 * o.record.dt)
        .collect();
    let Some(&end) = time.last() else {
        return Ok(Vec::new());
    };
    let range = (0.0, end);
    let drive = o
        .config
        .chain
        .as_ref()
        .map_or("force [N]", |c| match c.drive {
            msd_ident::chain::ChainDrive::Force => "force [N]",
            msd_ident::chain::ChainDrive::BaseAcceleration => "base acceleration [m/s²]",
        });
    let mut panels = vec![Panel {
        title: "Drive".into(),
        x_desc: "time t [s]".into(),
        y_desc: drive.into(),
        x_range: range,
        curves: vec![Curve {
            label: "measured".into(),
            x: &time,
            y: o.record.input.clone(),
            style: Style::Line(BLUE, 1),
        }],
        band: None,
        legend: None,
    }];
    let bands = o.band.lower.iter().zip(&o.band.upper);
    for (((name, measured), fitted), (lower, upper)) in channel_names(o)
        .iter()
        .zip(&o.record.outputs)
        .zip(&o.fitted)
        .zip(bands)
    {
        panels.push(Panel {
            title: name.replace('_', " on mass "),
            x_desc: "time t [s]".into(),
            y_desc: axis(name),
            x_range: range,
            curves: vec![
                Curve {
                    label: "measured".into(),
                    x: &time,
                    y: measured.clone(),
                    style: Style::Points(BLUE, 2),
                },
                Curve {
                    label: "model".into(),
                    x: &time,
                    y: fitted.clone(),
                    style: Style::Line(RED, 2),
                },
            ],
            band: Some(Band {
                label: format!("Monte Carlo ±10 % ({} draws)", o.band.samples),
                x: &time,
                lower: lower.clone(),
                upper: upper.clone(),
            }),
            legend: Some(SeriesLabelPosition::UpperRight),
        });
    }
    let figure = Stack {
        name: "chain_fit",
        title: format!("Chain fit — {}", o.config.name),
        panels,
    };
    save(&figure, dir)?;
    Ok(vec![figure.name])
}

/// "acceleration [m/s²]" for a channel named "acceleration_2".
fn axis(name: &str) -> String {
    let quantity = name.split('_').next().unwrap_or("response");
    let unit = match quantity {
        "displacement" => "m",
        "velocity" => "m/s",
        _ => "m/s²",
    };
    format!("{quantity} [{unit}]")
}
