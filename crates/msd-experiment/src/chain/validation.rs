//! The chain report's and summary's check on fresh data: the record's last fifth
//! predicted by the chain fitted to the rest.

use super::{ChainOutcome, channel_names};
use crate::fmt::sig;
use crate::verdict::{self, Evidence, Fresh, Verdict};
use std::fmt::Write;

/// `## Validation on fresh data`: one row per sensor (R², fit %, RMS error, the residual
/// tests), or why there is none.
pub(super) fn section(s: &mut String, o: &ChainOutcome) -> std::fmt::Result {
    writeln!(s, "## Validation on fresh data\n")?;
    let v = match &o.validation {
        Ok(v) => v,
        Err(reason) => return writeln!(s, "No check on fresh data: {reason}.\n"),
    };
    writeln!(
        s,
        "Held out: {}. Its residuals are tested as the paper's are (Ljung–Box whiteness, and the largest residual–drive cross-correlation against its 99 % band).\n",
        v.source
    )?;
    writeln!(
        s,
        "| sensor | R² | fit % | RMS error | whiteness p | max \\|ρ\\| with the drive |\n|---|---|---|---|---|---|"
    )?;
    let mut failed = false;
    for (name, p) in channel_names(o).iter().zip(&v.sensors) {
        let (white, cross, bad) = crate::fmt::residual_cells(p.residual_analysis.as_ref());
        failed |= bad;
        writeln!(
            s,
            "| {name} | {} | {} | {} | {white} | {cross} |",
            sig(p.fit.r_squared, 6),
            sig(p.fit.fit_percent, 4),
            sig(p.fit.residual_rms, 3)
        )?;
    }
    if failed {
        writeln!(
            s,
            "\n✗: the residual correlates with the drive on samples the chain was not fitted to: part of the drive's effect is not explained (a missing mass or connection, a sensor delay or filter, a nonlinearity)."
        )?;
    }
    if o.fit.noise_model.p_value.is_some_and(|p| p < 0.01) {
        writeln!(
            s,
            "\nThe whiteness p is of the residual as it is: the drive's own noise, seen through the chain, colours it (the Noise section), so a small p here is expected and says nothing against the chain."
        )?;
    }
    writeln!(s)
}

/// The summary's validation line, and a warning per sensor whose fresh residual
/// correlates with the drive.
pub(super) fn summary(s: &mut String, o: &ChainOutcome) {
    let v = match &o.validation {
        Ok(v) => v,
        Err(reason) => {
            crate::summary::labelled(
                s,
                "validation",
                &format!("no check on fresh data: {reason}"),
            );
            return;
        }
    };
    if let Some(worst) = v
        .sensors
        .iter()
        .min_by(|a, b| a.fit.r_squared.total_cmp(&b.fit.r_squared))
    {
        crate::summary::fresh_data(s, "held-out end", &worst.fit, None);
    }
    for (name, p) in channel_names(o).iter().zip(&v.sensors) {
        if let Some(a) = p
            .residual_analysis
            .as_ref()
            .filter(|a| !a.cross_correlation_passed)
        {
            crate::summary::labelled(
                s,
                "warning",
                &format!(
                    "validation: sensor `{name}`: the residual correlates with the drive on fresh data (max |ρ| = {}): part of its effect is not explained (report.md, Validation)",
                    sig(a.cross_correlation.max_abs, 2)
                ),
            );
        }
    }
}

/// The verdict on a chain fit: identifiability, each sensor's whiteness under the noise
/// model, the held-out end, the drive's noise.
pub(super) fn verdict(o: &ChainOutcome) -> Verdict {
    let names = channel_names(o);
    let fresh = o.validation.as_ref().map_err(Clone::clone).map(|v| {
        let rows: Vec<_> = names.iter().zip(&v.sensors).zip(&o.fit.noise).collect();
        Fresh {
            what: "the held-out end".into(),
            worst: (v.sensors.iter())
                .map(|p| (p.fit.r_squared, p.fit.fit_percent))
                .min_by(|a, b| a.0.total_cmp(&b.0)),
            unpredicted: (rows.iter())
                .filter(|((_, p), sigma)| {
                    p.fit.r_squared < 0.5 && p.fit.residual_rms > 1.5 * **sigma
                })
                .map(|((name, _), _)| format!("`{name}`"))
                .collect(),
            correlated: (rows.iter())
                .filter(|((_, p), _)| {
                    (p.residual_analysis.as_ref()).is_some_and(|a| !a.cross_correlation_passed)
                })
                .map(|((name, _), _)| format!("`{name}`"))
                .collect(),
        }
    });
    verdict::verdict(&Evidence {
        unidentified: o.fit.uncertainty.unidentifiable.clone(),
        whiteness: &super::report::named_whiteness(o),
        noise_model: &o.fit.noise_model,
        fresh,
    })
}
