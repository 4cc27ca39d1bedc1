//! The report's and the summary's validation on fresh data: each record predicted by
//! the others, a single record's held-out end, or the `data.validation` parts.

use crate::config::Response;
use crate::fmt::sig;
use crate::verdict::{self, Evidence, Fresh, Verdict};
use msd_ident::RecordsFit;
use msd_ident::records::LeftOut;
use std::fmt::Write;

/// What was predicted and by which plant, with its predictions; `None` without fresh data.
fn fresh(fit: &RecordsFit) -> Option<(String, &[LeftOut])> {
    if let Some(v) = &fit.validation {
        return Some((
            format!("{}.", crate::fmt::capitalised(&v.source)),
            &v.predictions,
        ));
    }
    fit.leave_one_out.as_deref().map(|l| {
        (
            "Each record predicted by the plant fitted to the others (leave one record out)."
                .into(),
            l,
        )
    })
}

/// `## Validation on fresh data`: the source, one row per record and channel (the
/// predicting plant's fn and ζ, R², fit %, the RMS error in the channel's unit, the
/// residual tests), then what a failed test means.
pub(super) fn section(s: &mut String, fit: &RecordsFit, sensors: &[Response]) -> std::fmt::Result {
    let Some((source, predictions)) = fresh(fit) else {
        return Ok(());
    };
    writeln!(
        s,
        "## Validation on fresh data\n\n{source} Each predicted record's initial state and offsets are fitted with the plant held, as MATLAB's `compare`; its residuals are tested as the paper's are (Ljung–Box whiteness, and the largest residual–drive cross-correlation against its 99 % band).\n"
    )?;
    writeln!(
        s,
        "| record | channel | fn [Hz] | ζ | R² | fit % | RMS error | whiteness p | max \\|ρ\\| with the drive |\n|---|---|---|---|---|---|---|---|---|"
    )?;
    let mut failed = false;
    for p in predictions {
        for (c, tests) in p.channels.iter().zip(&p.residual_analysis) {
            let unit = sensors
                .iter()
                .find(|r| r.channel_name() == c.channel)
                .map_or("", |r| r.quantity.si_unit());
            let (white, cross, bad) = crate::fmt::residual_cells(tests.as_ref());
            failed |= bad;
            writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} {unit} | {white} | {cross} |",
                p.record,
                c.channel,
                sig(p.natural_frequency_hz, 6),
                sig(p.damping_ratio, 4),
                sig(c.fit.r_squared, 6),
                sig(c.fit.fit_percent, 4),
                sig(c.fit.residual_rms, 3)
            )?;
        }
    }
    writeln!(
        s,
        "\n{}\n",
        if failed {
            "✗: the residual correlates with the drive beyond its band on data the plant was not fitted to: part of the drive's effect is not explained (a missing mode, a sensor delay, a nonlinearity, a wrong unit or drive). Look at the residuals; a model with what is missing (a chain, a delay, a nonlinear law) may be needed."
        } else {
            "No residual correlates with the drive beyond its band: the plant explains the drive's effect on fresh data. (A small whiteness p on fresh data is expected where the noise is coloured — the drive's own noise seen through the plant; the Noise section says whether it is.)"
        }
    )
}

/// One line for the summary: the worst prediction's R² and fit %, or a warning per
/// channel whose fresh residual correlates with the drive.
pub(super) fn summary(s: &mut String, fit: &RecordsFit) {
    let Some((_, predictions)) = fresh(fit) else {
        return;
    };
    let what = match &fit.validation {
        Some(v) if v.source.starts_with("the last") => "held-out end",
        Some(_) => "validation records",
        None => "leave one record out",
    };
    let rows = predictions.iter().flat_map(|p| {
        p.channels
            .iter()
            .zip(&p.residual_analysis)
            .map(move |(c, a)| (p, c, a))
    });
    let worst = rows
        .clone()
        .min_by(|a, b| a.1.fit.r_squared.total_cmp(&b.1.fit.r_squared));
    if let Some((_, c, _)) = worst {
        crate::summary::fresh_data(s, what, &c.fit, None);
    }
    for (p, c, a) in rows {
        if let Some(a) = a.as_ref().filter(|a| !a.cross_correlation_passed) {
            crate::summary::labelled(
                s,
                "warning",
                &format!(
                    "validation: record `{}`, channel `{}`: the residual correlates with the drive on fresh data (max |ρ| = {}): part of its effect is not explained (report.md, Validation)",
                    p.record,
                    c.channel,
                    sig(a.cross_correlation.max_abs, 2)
                ),
            );
        }
    }
}

/// The verdict on a setup's fit: for records, identifiability, whiteness under the noise
/// model, fresh data and the drive's noise; for the test machine, its laws' ranking and
/// each condition predicted by the others.
pub(super) fn verdict(fit: &super::SetupFit) -> Verdict {
    let fit = match fit {
        super::SetupFit::Records { fit, .. } => fit,
        super::SetupFit::Machine(m) => return super::report_machine::verdict(m),
        super::SetupFit::Stroke(f) => return super::stroke::verdict(f),
    };
    let sigma = |channel: &str| {
        (fit.noise.iter())
            .find(|n| n.channel == channel)
            .map_or(0.0, |n| n.sigma)
    };
    let fresh = match fresh(fit) {
        None => Err(
            "one record and nothing held out (`setup.hold_out = 0`), or too short to hold a part out (the notes say which)"
                .to_string(),
        ),
        Some((_, predictions)) => {
            let rows: Vec<_> = (predictions.iter())
                .flat_map(|p| {
                    p.channels
                        .iter()
                        .zip(&p.residual_analysis)
                        .map(move |c| (p, c))
                })
                .collect();
            Ok(Fresh {
                what: match &fit.validation {
                    Some(v) if v.source.starts_with("the last") => "the held-out end".into(),
                    Some(_) => "the validation records".into(),
                    None => "each record predicted by the others".into(),
                },
                worst: (rows.iter())
                    .map(|(_, (c, _))| (c.fit.r_squared, c.fit.fit_percent))
                    .min_by(|a, b| a.0.total_cmp(&b.0)),
                unpredicted: (rows.iter())
                    .filter(|(_, (c, _))| {
                        c.fit.r_squared < 0.5 && c.fit.residual_rms > 1.5 * sigma(&c.channel)
                    })
                    .map(|(p, (c, _))| format!("`{}` of `{}`", c.channel, p.record))
                    .collect(),
                correlated: (rows.iter())
                    .filter(|(_, (_, a))| a.as_ref().is_some_and(|a| !a.cross_correlation_passed))
                    .map(|(p, (c, _))| format!("`{}` of `{}`", c.channel, p.record))
                    .collect(),
            })
        }
    };
    verdict::verdict(&Evidence {
        unidentified: fit.plant.note.iter().cloned().collect(),
        whiteness: &fit.whiteness,
        noise_model: &fit.noise_model,
        fresh,
    })
}
