//! The verdict a frequency-domain fit opens with: its residuals against the FRF's own
//! noise where the coherence gives it (and what the force's noise did), else why that
//! check could not be made; the modes the fit kept and the ones it dropped; for a set,
//! how well every member is reproduced.

use super::report::fitted_band_coherence;
use super::{FrfFit, FrfOutcome};
use crate::fmt::sig;
use crate::verdict::{Finding, Verdict};
use msd_ident::Interval;
use msd_modal::{FrfWeighting, NoiseCheck, RefusedMode};

/// The verdict on the fit of `o`.
pub(crate) fn verdict(o: &FrfOutcome) -> Verdict {
    let mut findings = Vec::new();
    let (check, model, missing) = match &o.fit {
        FrfFit::OneMode(f) => (f.noise_check.as_ref(), "the one-mode model", "another mode"),
        FrfFit::Modes(m) => (m.noise_check.as_ref(), "the modes", "a mode missed"),
        FrfFit::Set(m) => (m.noise_check.as_ref(), "the modes", "a mode missed"),
    };
    findings.push(match check {
        Some(check) => residual_finding(check, model, missing),
        None => Finding::unchecked(format!(
            "{}, so the residual cannot be tested against the data's own noise: the intervals assume that the model leaves only independent noise on each line, at {}",
            unchecked_because(o),
            match o.fit.weighting() {
                FrfWeighting::Uniform => "the level the residuals' own noise model gives it (a part in proportion to |H|, a part flat in the quantity measured)",
                _ => "the residual's own level",
            }
        )),
    });
    match &o.fit {
        FrfFit::OneMode(f) => {
            if let Some(noise) = &f.input_noise {
                findings.push(input_noise_finding(noise, &f.uncertainty.mass));
            }
        }
        FrfFit::Modes(m) => findings.extend(refused_finding(&m.refused)),
        FrfFit::Set(m) => {
            findings.push(members_finding(m));
            findings.extend(refused_finding(&m.refused));
        }
    }
    let ([from, to], low) = fitted_band_coherence(o);
    if low < 0.5 {
        findings.push(Finding::passed(format!(
            "the coherence falls to {} between {} and {} Hz: each line is weighted by what it is worth",
            sig(low, 2),
            sig(from, 4),
            sig(to, 4)
        )));
    }
    Verdict::of(findings)
}

/// The residuals against the coherence's noise.
fn residual_finding(check: &NoiseCheck, model: &str, missing: &str) -> Finding {
    let numbers = format!(
        "SSE/E[SSE] {} on {} effective dof, p = {}",
        sig(check.variance_ratio, 3),
        sig(check.degrees_of_freedom, 3),
        sig(check.p_value, 2)
    );
    if check.passed {
        Finding::passed(format!(
            "{model} leave{} only the noise the FRF's coherence shows ({numbers})",
            if model == "the modes" { "" } else { "s" }
        ))
    } else {
        Finding::failed(format!(
            "the residual exceeds the FRF's own noise ({numbers}): {missing}, a nonlinearity or leakage in the band, and the intervals may be too narrow"
        ))
    }
}

/// Why the residuals were not tested against the FRF's own noise, in words.
fn unchecked_because(o: &FrfOutcome) -> String {
    let weighting = o.fit.weighting();
    let (_, low) = fitted_band_coherence(o);
    let what = if o.members.is_empty() {
        "the FRF carries"
    } else {
        "the set's FRFs carry"
    };
    if low >= 1.0 {
        format!("{what} no coherence")
    } else if o.data.averages == 0 {
        let key = if o.members.is_empty() {
            "frequency_response.table.averages"
        } else {
            "averages in each [[frequency_response.set]]"
        };
        format!("the coherence does not say over how many averages it was estimated ({key})")
    } else if !matches!(weighting, FrfWeighting::Coherence) {
        format!("the lines are weighted {weighting}, not by the coherence's noise")
    } else {
        "the coherence of a single average says nothing of the noise".into()
    }
}

/// How well the worst member of a set is reproduced.
fn members_finding(m: &msd_modal::ModeSetFit) -> Finding {
    let worst = (m.members.iter()).max_by(|a, b| a.relative_error.total_cmp(&b.relative_error));
    let text = match worst {
        Some(w) => format!(
            "{} modes common to the {} FRFs reproduce each within {} % (the worst, response {} by reference {})",
            m.modes.len(),
            m.members.len(),
            sig(100.0 * w.relative_error, 2),
            w.response,
            w.reference
        ),
        None => format!("{} modes common to the set", m.modes.len()),
    };
    Finding::passed(text)
}

/// The columns of the diagram the fit moved away and dropped, when there are any.
fn refused_finding(refused: &[RefusedMode]) -> Option<Finding> {
    let list: Vec<String> = refused
        .iter()
        .map(|r| format!("{:.4} Hz", r.natural_frequency_hz))
        .collect();
    (!list.is_empty()).then(|| {
        Finding::passed(format!(
            "{} more columns of the stabilization diagram ({}) moved away in the fit and were dropped (listed with the modes)",
            list.len(),
            list.join(", ")
        ))
    })
}

/// The force's noise in the verdict: taken off, or a possible bias of H1 in standard
/// errors of m (m and k are high by H1's relative bias). A bias over one standard error
/// takes a 95 % interval's coverage below 83 %: the estimates are then to be used with
/// care.
fn input_noise_finding(noise: &msd_modal::InputNoise, mass: &Interval) -> Finding {
    let percent = sig(100.0 * noise.h1_bias, 2);
    let in_se = noise.h1_bias * mass.value / mass.standard_error;
    if noise.corrected {
        Finding::passed(format!(
            "the force's noise biased H1 low by {percent} % ({} standard errors of m): the lines were corrected",
            sig(in_se, 2)
        ))
    } else if in_se > 1.0 {
        Finding::failed(format!(
            "the coherence shows noise on the force, or the window's leakage: H1 may be low by up to {percent} %, {} standard errors of m and k, not corrected under this window — use a force that repeats over whole records (rectangular window), or compare with H2",
            sig(in_se, 2)
        ))
    } else {
        Finding::passed(format!(
            "the coherence shows at most {percent} % of force noise or leakage, under a standard error of m"
        ))
    }
}
