//! The summary a frequency-response run prints, in the one format of [`crate::summary`]:
//! the fit's headline, the verdict, the estimates (one mode) or the modes, then what
//! the fit adds under its labels.

use super::report::{covered, one_mode_rows};
use super::{FrfFit, FrfOutcome};
use crate::summary::{self, Estimate, ModeRow};
use msd_ident::frf::OneModeFit;
use msd_modal::{ModalFit, ModeSetFit};

/// The summary's body (the writer adds the footer).
pub(crate) fn text(o: &FrfOutcome) -> String {
    let mut s = String::new();
    let fit = match &o.fit {
        FrfFit::OneMode(fit) => fit.to_string(),
        FrfFit::Modes(fit) => fit.to_string(),
        FrfFit::Set(fit) => fit.to_string(),
    };
    let headline = fit.lines().next().unwrap_or_default();
    summary::head(
        &mut s,
        &o.config.name,
        &format!("a frequency response: {headline}"),
    );
    summary::verdict(&mut s, &o.verdict);
    s.push('\n');
    match &o.fit {
        FrfFit::OneMode(fit) => one_mode(&mut s, o, fit),
        FrfFit::Modes(fit) => modes(&mut s, fit),
        FrfFit::Set(fit) => set(&mut s, fit),
    }
    if let Some(t) = &o.truth {
        summary::labelled(
            &mut s,
            "truth",
            &format!("inside the 95 % intervals: {}", covered(o, t)),
        );
    }
    if let Some(td) = &o.time_domain {
        let text = td.to_string();
        let text = text.strip_prefix("time domain").unwrap_or(&text);
        summary::labelled(&mut s, "time domain", text.trim_start_matches(':').trim());
    }
    s
}

/// One mode: m, c, k (or the gain), fn and ζ; the band, the noise, the checks.
fn one_mode(s: &mut String, o: &FrfOutcome, f: &OneModeFit) {
    let rows: Vec<Estimate> = one_mode_rows(o, f)
        .into_iter()
        .map(|(label, iv, _, truth)| Estimate {
            label: label.into(),
            value: iv.value,
            interval: Some(iv.ci95),
            truth,
        })
        .collect();
    summary::estimates(s, &rows);
    s.push('\n');
    if let Some(peak) = &f.dominant_peak {
        summary::labelled(s, "band", &format!("fitted in {peak}"));
    }
    if f.conjugated {
        summary::labelled(s, "note", msd_modal::lines::CONJUGATED);
    }
    let u = &f.uncertainty;
    summary::labelled(
        s,
        "noise",
        &format!(
            "σ̂ = {:.4e}, {} degrees of freedom, condition number {:.3e}",
            u.sigma, u.degrees_of_freedom, u.condition_number
        ),
    );
    if let Some(check) = &f.noise_check {
        let check = check.to_string();
        match check.strip_prefix("warning: ") {
            Some(warning) => summary::labelled(s, "warning", warning),
            None => summary::labelled(
                s,
                "residuals",
                check.strip_prefix("residuals ").unwrap_or(&check),
            ),
        }
    }
    if let Some(low) = &f.low_coherence {
        summary::labelled(s, "coherence", &low.to_string());
    }
    if let Some(noise) = &f.input_noise {
        summary::labelled(s, "force noise", &noise.to_string());
    }
    if let Some(c) = &f.window_correction {
        summary::labelled(s, "window", &c.to_string());
    }
    if let Some(h) = &f.half_power {
        summary::labelled(s, "classroom", &h.to_string());
    }
    for w in &u.warnings {
        summary::labelled(s, "warning", w);
    }
}

/// Several modes of one FRF: their table, what was refused, the residual terms.
fn modes(s: &mut String, f: &ModalFit) {
    if f.conjugated {
        summary::labelled(s, "note", msd_modal::lines::CONJUGATED);
    }
    let rows: Vec<ModeRow> = (f.modes.iter())
        .map(|m| {
            let note = m.window_correction.as_ref().map(ToString::to_string);
            ModeRow::of(m, note.unwrap_or_default())
        })
        .collect();
    summary::modes(s, &rows);
    s.push('\n');
    checks(s, &f.refused, f.noise_check.as_ref());
    if let Some(noise) = &f.input_noise {
        summary::labelled(s, "force noise", &noise.to_string());
    }
    summary::labelled(
        s,
        "residuals",
        &format!(
            "lower L = {:.4e} [{:.4e}, {:.4e}], upper U = {:.4e} [{:.4e}, {:.4e}]",
            f.lower_residual.value,
            f.lower_residual.ci95[0],
            f.lower_residual.ci95[1],
            f.upper_residual.value,
            f.upper_residual.ci95[0],
            f.upper_residual.ci95[1]
        ),
    );
}

/// Modes common to a set of FRFs: their table with MPC, MPD and modal mass.
fn set(s: &mut String, f: &ModeSetFit) {
    if f.conjugated {
        summary::labelled(s, "note", msd_modal::lines::CONJUGATED);
    }
    let rows: Vec<ModeRow> = (f.modes.iter())
        .map(|m| {
            let mut note = Vec::new();
            if let (Some(mpc), Some(mpd)) = (m.mpc, m.mpd_deg) {
                note.push(format!("MPC {mpc:.3}, MPD {mpd:.1}°"));
            }
            if let Some(mass) = m.modal_mass {
                note.push(format!("modal mass {mass:.4e} kg"));
            }
            ModeRow::of(m, note.join(", "))
        })
        .collect();
    summary::modes(s, &rows);
    let noise = f.largest_input_noise();
    if !f.refused.is_empty() || f.noise_check.is_some() || noise.is_some() {
        s.push('\n');
        checks(s, &f.refused, f.noise_check.as_ref());
    }
    if let Some(noise) = noise {
        let text = format!("{noise} (the largest of the members)");
        summary::labelled(s, "force noise", &text);
    }
    if let Some(shared) = f.shared_force.filter(msd_modal::SharedForce::is_evident) {
        summary::labelled(s, "common errors", &shared.to_string());
    }
}

/// The modes a several-mode fit refused, and its residuals against the FRF's own noise.
fn checks(
    s: &mut String,
    refused: &[msd_modal::RefusedMode],
    check: Option<&msd_modal::NoiseCheck>,
) {
    for r in refused {
        summary::labelled(s, "refused", &r.to_string());
    }
    if let Some(check) = check {
        let check = check.to_string();
        let against = check.strip_prefix("residuals ").unwrap_or(&check);
        summary::labelled(s, "residuals", against);
    }
}
