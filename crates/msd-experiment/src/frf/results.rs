//! `results.json` of a frequency-domain experiment: the library's result types where
//! they are the answer (intervals, modes, the diagram), named sections around them.

use super::{FrfFit, FrfOutcome, Truth};
use crate::config::{ChainPlant, Config};
use crate::results::Header;
use msd_ident::Interval;
use msd_ident::LmExit;
use msd_modal::{
    Dof, HalfPower, MemberFit, ModalParameters, Mode, Roving, StabilizationDiagram,
    WindowCorrection,
};
use serde::Serialize;
use serde_json::Value;
use std::collections::BTreeMap;
use std::time::Duration;

#[derive(Serialize)]
struct Results<'a> {
    experiment: Header<'a>,
    verdict: &'a crate::verdict::Verdict,
    config: &'a Config,
    data: Data<'a>,
    /// One mode.
    #[serde(skip_serializing_if = "Option::is_none")]
    estimate: Option<Estimate>,
    /// Several modes.
    #[serde(skip_serializing_if = "Option::is_none")]
    modes: Option<&'a [Mode]>,
    /// A set's MAC matrix of the shapes.
    #[serde(skip_serializing_if = "Option::is_none")]
    mac: Option<&'a [Vec<f64>]>,
    /// A set's fit of each FRF (on the measured quantity).
    #[serde(skip_serializing_if = "Option::is_none")]
    fit_error: Option<&'a [MemberFit]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    modal_set: Option<SetSummary<'a>>,
    /// MAC of each fitted shape with the config's reference mode of the same rank.
    #[serde(skip_serializing_if = "Option::is_none")]
    reference_mac: Option<Vec<f64>>,
    /// MAC of the fitted shapes with those of the config's `reference_shapes` file.
    #[serde(skip_serializing_if = "Option::is_none")]
    reference_shapes: Option<&'a super::ReferenceShapes>,
    #[serde(skip_serializing_if = "Option::is_none")]
    modal_fit: Option<ModalSummary<'a>>,
    /// Peak picking and half-power bandwidth per mode (null where unreadable).
    classroom: &'a [Option<HalfPower>],
    #[serde(skip_serializing_if = "Option::is_none")]
    truth: Option<TruthSection<'a>>,
    /// The time-domain fit of the same records and the comparison, or why not.
    #[serde(skip_serializing_if = "Option::is_none")]
    time_domain: Option<&'a super::TimeDomain>,
    timings_ms: BTreeMap<String, f64>,
}

#[derive(Serialize)]
struct SetSummary<'a> {
    roving: Roving,
    driving_point: Option<Dof>,
    modal_mass_note: Option<&'a str>,
    band_hz: [f64; 2],
    lines: usize,
    weighting: String,
    noise_sigma: f64,
    degrees_of_freedom: usize,
    iterations: usize,
    /// The fit was made on the data's complex conjugate.
    #[serde(skip_serializing_if = "is_false")]
    conjugated: bool,
    stabilization: &'a StabilizationDiagram,
    /// The residuals against the members' own noise (absent without coherence).
    #[serde(skip_serializing_if = "Option::is_none")]
    noise_check: Option<msd_modal::NoiseCheck>,
    /// How much of the members' force noise is common to them (absent without the
    /// coherence's noise model).
    #[serde(skip_serializing_if = "Option::is_none")]
    shared_force: Option<msd_modal::SharedForce>,
}

#[derive(Serialize)]
struct Data<'a> {
    source: &'a str,
    lines: usize,
    band_hz: [f64; 2],
    quantity: String,
    averages: usize,
    exponential_decay: Option<f64>,
    noise_bandwidth: f64,
    /// The lowest coherence in the fitted band.
    min_coherence: f64,
    /// Lines without force, left out of the fit (from time records).
    #[serde(skip_serializing_if = "is_zero")]
    unexcited_lines: usize,
    /// The smallest and largest relative standard deviation of a line in the fitted band
    /// from the force's noise, where it was measured (an impact test's force channel).
    #[serde(skip_serializing_if = "Option::is_none")]
    force_noise_relative_sd: Option<[f64; 2]>,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

#[derive(Serialize)]
struct Estimate {
    #[serde(skip_serializing_if = "Option::is_none")]
    mass: Option<Interval>,
    #[serde(skip_serializing_if = "Option::is_none")]
    damping: Option<Interval>,
    #[serde(skip_serializing_if = "Option::is_none")]
    stiffness: Option<Interval>,
    natural_frequency_hz: Interval,
    damping_ratio: Interval,
    gain: Interval,
    window_correction: Option<WindowCorrection>,
    band_hz: [f64; 2],
    lines: usize,
    weighting: String,
    noise_sigma: f64,
    degrees_of_freedom: usize,
    relative_error: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    noise_check: Option<msd_modal::NoiseCheck>,
    /// The force's noise the coherence showed on an H1 estimate, taken off the lines.
    #[serde(skip_serializing_if = "Option::is_none")]
    input_noise: Option<msd_modal::InputNoise>,
    /// The resonance the band was chosen around (no band given).
    #[serde(skip_serializing_if = "Option::is_none")]
    dominant_peak: Option<msd_modal::DominantPeak>,
    /// The coherence over the mode's half-power band, when low.
    #[serde(skip_serializing_if = "Option::is_none")]
    low_coherence: Option<msd_ident::frf::LowCoherence>,
    /// The fit was made on the data's complex conjugate.
    #[serde(skip_serializing_if = "is_false")]
    conjugated: bool,
    iterations: usize,
    evaluations: usize,
    exit: LmExit,
}

fn is_false(b: &bool) -> bool {
    !*b
}

#[derive(Serialize)]
struct ModalSummary<'a> {
    lower_residual: Interval,
    upper_residual: Interval,
    band_hz: [f64; 2],
    lines: usize,
    weighting: String,
    noise_sigma: f64,
    degrees_of_freedom: usize,
    relative_error: f64,
    /// The residuals against the FRF's own noise (coherence from two or more averages).
    #[serde(skip_serializing_if = "Option::is_none")]
    noise_check: Option<msd_modal::NoiseCheck>,
    /// The force's noise on an H1 estimate: measured and taken off the lines, or said.
    #[serde(skip_serializing_if = "Option::is_none")]
    input_noise: Option<msd_modal::InputNoise>,
    iterations: usize,
    evaluations: usize,
    exit: LmExit,
    /// The fit was made on the data's complex conjugate.
    #[serde(skip_serializing_if = "is_false")]
    conjugated: bool,
    stabilization: &'a StabilizationDiagram,
}

#[derive(Serialize)]
struct TruthSection<'a> {
    #[serde(flatten)]
    plant: &'a ChainPlant,
    /// m, c, k of a one-mass plant.
    #[serde(skip_serializing_if = "Option::is_none")]
    mass: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    damping: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    stiffness: Option<f64>,
    modes: &'a [ModalParameters],
}

fn ms(d: Duration) -> f64 {
    (d.as_secs_f64() * 1e6).round() / 1e3
}

/// The whole document; `extra` are the writing stages' timings, `total` the wall time.
pub fn to_json(o: &FrfOutcome, extra: &[(&'static str, Duration)], total: Duration) -> Value {
    let one_mass = o.truth.as_ref().filter(|t| t.plant.len() == 1);
    let set = match &o.fit {
        FrfFit::Set(m) => Some(m.as_ref()),
        _ => None,
    };
    let results = Results {
        experiment: Header::new(
            &o.config,
            &o.config_path,
            "frequency_response",
            o.seed,
            None,
        ),
        verdict: &o.verdict,
        config: &o.config,
        data: Data {
            source: &o.source,
            lines: o.data.frequency.len(),
            band_hz: [
                o.data.frequency[0],
                o.data.frequency[o.data.frequency.len() - 1],
            ],
            quantity: o.data.kind.to_string(),
            averages: o.data.averages,
            exponential_decay: o.data.exponential_decay,
            noise_bandwidth: o.data.noise_bandwidth,
            min_coherence: super::report::fitted_band_coherence(o).1,
            unexcited_lines: o.unexcited_lines(),
            force_noise_relative_sd: super::report::force_noise_range(o),
        },
        estimate: one_mode(o),
        modes: match &o.fit {
            FrfFit::Modes(m) => Some(&m.modes),
            FrfFit::Set(m) => Some(&m.modes),
            FrfFit::OneMode(_) => None,
        },
        mac: set.map(|m| m.mac.as_slice()),
        reference_mac: set
            .zip(super::reference_modes(o))
            .map(|(m, r)| super::reference_mac(m, r)),
        reference_shapes: o.reference_shapes.as_ref(),
        fit_error: set.map(|m| m.members.as_slice()),
        modal_set: set.map(|m| SetSummary {
            roving: m.roving,
            driving_point: m.driving_point,
            modal_mass_note: m.modal_mass_note.as_deref(),
            band_hz: m.band_hz,
            lines: m.lines,
            weighting: m.weighting.to_string(),
            noise_sigma: m.sigma,
            degrees_of_freedom: m.degrees_of_freedom,
            iterations: m.iterations,
            conjugated: m.conjugated,
            stabilization: &m.diagram,
            noise_check: m.noise_check,
            shared_force: m.shared_force,
        }),
        modal_fit: modal(o),
        classroom: &o.classroom,
        truth: o.truth.as_ref().map(|t: &Truth| TruthSection {
            plant: &t.plant,
            mass: one_mass.map(|t| t.plant.masses[0]),
            damping: one_mass.map(|t| t.plant.dampers[0]),
            stiffness: one_mass.map(|t| t.plant.springs[0]),
            modes: &t.modes,
        }),
        time_domain: o.time_domain.as_ref(),
        timings_ms: o
            .timings
            .iter()
            .chain(extra)
            .map(|(n, d)| (n.to_string(), ms(*d)))
            .chain(std::iter::once(("total".to_string(), ms(total))))
            .collect(),
    };
    serde_json::to_value(&results).unwrap_or(Value::Null)
}

fn one_mode(o: &FrfOutcome) -> Option<Estimate> {
    let FrfFit::OneMode(f) = &o.fit else {
        return None;
    };
    let u = &f.uncertainty;
    let known = o
        .config
        .frequency_response
        .as_ref()
        .is_none_or(|s| s.force_scale_known);
    Some(Estimate {
        mass: known.then_some(u.mass),
        damping: known.then_some(u.damping),
        stiffness: known.then_some(u.stiffness),
        natural_frequency_hz: u.natural_frequency_hz,
        damping_ratio: u.damping_ratio,
        gain: f.gain,
        window_correction: f.window_correction,
        band_hz: f.band_hz,
        lines: f.lines,
        weighting: f.weighting.to_string(),
        noise_sigma: u.sigma,
        degrees_of_freedom: u.degrees_of_freedom,
        relative_error: f.relative_error,
        noise_check: f.noise_check,
        input_noise: f.input_noise,
        dominant_peak: f.dominant_peak,
        low_coherence: f.low_coherence,
        conjugated: f.conjugated,
        iterations: f.iterations,
        evaluations: f.evaluations,
        exit: f.exit,
    })
}

fn modal(o: &FrfOutcome) -> Option<ModalSummary<'_>> {
    let FrfFit::Modes(m) = &o.fit else {
        return None;
    };
    Some(ModalSummary {
        lower_residual: m.lower_residual,
        upper_residual: m.upper_residual,
        band_hz: m.band_hz,
        lines: m.lines,
        weighting: m.weighting.to_string(),
        noise_sigma: m.sigma,
        degrees_of_freedom: m.degrees_of_freedom,
        relative_error: m.relative_error,
        noise_check: m.noise_check,
        input_noise: m.input_noise,
        iterations: m.iterations,
        evaluations: m.evaluations,
        exit: m.exit,
        conjugated: m.conjugated,
        stabilization: &m.diagram,
    })
}
