//! A test machine under any stroke: msd-ident's inverse dynamics on the fitted records,
//! each record's force predicted (the validation records' on fresh data), and its part
//! of `report.md`, of the summary and of the verdict.

use super::SetupData;
use crate::config::SetupSection;
use crate::config::setup::StrokeAnalysis;
use crate::fmt::sig;
use crate::verdict::{Finding, Verdict};
use msd_ident::dynamometer::{
    ForcePrediction, InverseDynamics, InverseOptions, fundamental_share, inverse_dynamics,
};
use msd_signal::Recording;
use serde::Serialize;
use std::fmt::Write;

/// The fit and every record's force as the best law predicts it.
#[derive(Debug, Clone, Serialize)]
pub struct StrokeFit {
    /// The inverse dynamics: every law's coefficients, ranked.
    pub inverse: InverseDynamics,
    /// One per record, the fitted ones first.
    pub predictions: Vec<RecordPrediction>,
}

/// A record's force predicted from its stroke.
#[derive(Debug, Clone, Serialize)]
pub struct RecordPrediction {
    /// The record's name.
    pub record: String,
    /// Whether it was left out of the fit (`data.validation_path`).
    pub validation: bool,
    /// RMS of the measured (filtered) force less the predicted, N.
    pub rms_error: f64,
    /// RMS of the measured (filtered) force, N.
    pub rms_force: f64,
    /// Its time stamps, s.
    #[serde(skip)]
    pub time: Vec<f64>,
    /// The measured (filtered) and predicted force (for the figure).
    #[serde(skip)]
    pub force: ForcePrediction,
}

/// Whether `setup`'s records are analysed as any stroke: asked, or (`auto`) measured
/// records whose acceleration is not ≥ 90 % in its fundamental.
pub(crate) fn any_stroke(setup: &SetupSection, data: &SetupData, measured: bool) -> bool {
    match setup.stroke {
        StrokeAnalysis::Any => true,
        StrokeAnalysis::Harmonic => false,
        StrokeAnalysis::Auto => {
            measured
                && data.records.iter().any(|r| {
                    fundamental_share(r.recording.dt, r.drive()).is_none_or(|share| share < 0.9)
                })
        }
    }
}

/// Fits the records of `data` and predicts every record's force.
pub(crate) fn fit(data: &SetupData) -> msd_ident::Result<StrokeFit> {
    let setup = &data.setup;
    let options = InverseOptions {
        cutoff_hz: setup.cutoff_hz,
        stiffness: setup.stiffness,
        known_mass: setup.known_mass,
        ..InverseOptions::default()
    };
    let fitted: Vec<Recording> = data.records.iter().map(|r| r.recording.clone()).collect();
    let inverse = inverse_dynamics(&fitted, &options)?;
    let mut predictions = Vec::new();
    for (records, validation) in [(&data.records, false), (&data.validation, true)] {
        for r in records.iter() {
            let force = inverse.predict(inverse.best, &r.recording)?;
            predictions.push(RecordPrediction {
                record: r.name().to_string(),
                validation,
                rms_error: force.rms_error,
                rms_force: force.rms_force,
                time: (force.first..force.first + force.predicted.len())
                    .map(|i| r.recording.time(i))
                    .collect(),
                force,
            });
        }
    }
    Ok(StrokeFit {
        inverse,
        predictions,
    })
}

/// The part of `report.md`: the method, the laws ranked, each record's force error.
pub(crate) fn section(s: &mut String, f: &StrokeFit) -> std::fmt::Result {
    let i = &f.inverse;
    writeln!(s, "## Test machine, any stroke: inverse dynamics\n")?;
    writeln!(
        s,
        "F = m·x″ + f_d(x′){} + F₀ over {} samples. The stroke and the force are low-passed alike at {} Hz (a 4th-order Butterworth run forward and backward: no phase shift, and the same filter on both sides of the equation changes no coefficient); x′ and x″ by central differences; the Coulomb and quadratic terms filtered as the force is. The 95 % intervals are the sandwich over {} contiguous blocks of samples with Student's t on {} degrees of freedom: they hold when the residual is coloured (the filter, and what the model leaves out along the stroke), where ordinary least squares would make them several times too narrow.\n",
        if i.stiffness { " + k·x" } else { "" },
        i.samples,
        sig(i.cutoff_hz, 4),
        i.blocks,
        i.blocks - 1
    )?;
    writeln!(
        s,
        "| rank | law | coefficients, 95 % interval | RMS residual [N] | R² | ΔBIC |\n|---|---|---|---|---|---|"
    )?;
    let mut order: Vec<_> = i.laws.iter().collect();
    order.sort_by_key(|l| l.rank);
    for l in order {
        let coefficients: Vec<String> = l
            .coefficients
            .iter()
            .map(|c| {
                let e = &c.estimate;
                format!(
                    "{} = {} {} [{}, {}]",
                    c.name,
                    sig(e.value, 5),
                    c.unit,
                    sig(e.ci95[0], 5),
                    sig(e.ci95[1], 5)
                )
            })
            .collect();
        writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            l.rank,
            l.law.formula().replace('|', "\\|"),
            coefficients.join("; "),
            sig(l.rms_residual, 4),
            sig(l.r2, 5),
            sig(l.delta_bic, 3)
        )?;
    }
    writeln!(s, "\n{}.\n", i.verdict)?;
    writeln!(
        s,
        "| record | use | RMS force error [N] | RMS force [N] | error / force |\n|---|---|---|---|---|"
    )?;
    for p in &f.predictions {
        writeln!(
            s,
            "| {} | {} | {} | {} | {} % |",
            p.record,
            if p.validation {
                "validation (not fitted)"
            } else {
                "fitted"
            },
            sig(p.force.rms_error, 4),
            sig(p.force.rms_force, 4),
            sig(100.0 * p.force.rms_error / p.force.rms_force, 3)
        )?;
    }
    writeln!(s)
}

/// The summary's lines: the method and the validation records' errors.
pub(crate) fn summary(s: &mut String, f: &StrokeFit) {
    crate::summary::labelled(
        s,
        "method",
        &format!(
            "any stroke: inverse dynamics, low-pass {} Hz, {}",
            sig(f.inverse.cutoff_hz, 4),
            f.inverse.verdict
        ),
    );
    for p in f.predictions.iter().filter(|p| p.validation) {
        crate::summary::labelled(
            s,
            "validation",
            &format!(
                "`{}`: RMS force error {} N of {} N RMS",
                p.record,
                sig(p.force.rms_error, 4),
                sig(p.force.rms_force, 4)
            ),
        );
    }
}

/// The verdict: the best law's standing, and the force predicted on fresh records.
pub(crate) fn verdict(f: &StrokeFit) -> Verdict {
    let mut findings = vec![Finding::passed(f.inverse.verdict.clone())];
    let error = |p: &RecordPrediction| p.force.rms_error / p.force.rms_force;
    let fitted = f
        .predictions
        .iter()
        .filter(|p| !p.validation)
        .map(error)
        .fold(0.0, f64::max);
    for p in f.predictions.iter().filter(|p| p.validation) {
        let text = format!(
            "the force of `{}` (not fitted) predicted from its stroke within {} % of its RMS ({} % on the fitted records)",
            p.record,
            sig(100.0 * error(p), 3),
            sig(100.0 * fitted, 3)
        );
        findings.push(if error(p) <= 2.0 * fitted.max(0.01) {
            Finding::passed(text)
        } else {
            Finding::failed(format!(
                "{text}: more than twice the fitted records' error — the model misses what this record holds"
            ))
        });
    }
    Verdict::of(findings)
}
