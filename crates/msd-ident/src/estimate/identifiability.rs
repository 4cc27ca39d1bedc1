//! Is the mass identifiable at all? A likelihood-ratio probe of the mass profile.
//!
//! The linearised intervals of [`crate::uncertainty::Uncertainty`] describe the cost near θ̂ only.
//! When the record does not excite the mass line — no dynamics at all (a constant force
//! at equilibrium), or a resonance far above the excited band or beyond the Nyquist
//! frequency — the cost is flat in m over orders of magnitude, the optimiser stops
//! anywhere on that plateau, and the curvature there can still give a tight interval
//! around a wrong value. The profile likelihood sees it: fix m at a hundredth of m̂,
//! refit everything else, and compare the costs. Under Gaussian noise the statistic
//! Λ = (S(m̂/100) − S(θ̂)) / σ̂² is χ²₁ when m̂/100 is as true as m̂ (Wilks), so
//! Λ < χ²₁(0.95) = 3.84 means the data cannot tell m̂ from a mass a hundred times
//! smaller: m is not identifiable, and the estimate is refused with what to do instead.

use super::Cost;
use super::layout::Layout;
use crate::{
    data::DataSet, error::IdentError, estimate::EstimationOptions, params::InitialState,
    simulate::Backend,
};
use crate::{error::Result, estimate::Method, params::Parameters};

/// The factors the probes divide the mass by.
const PROBES: [f64; 2] = [1e2, 1e4];
/// χ²₁ at 0.95: the likelihood-ratio threshold of a 95 % interval.
const CHI2_1_95: f64 = 3.841_458_820_694_124;

/// χ²₁ at 0.90 and 0.99: a Wald endpoint whose Λ lies between them sits between the
/// 90 % and 99 % likelihood intervals, close enough to the 95 % one to be trusted.
const CHI2_1_90: f64 = 2.705_543_454_095_404;
const CHI2_1_99: f64 = 6.634_896_601_021_214;
/// Relative standard error below which the linearised intervals are not probed: the
/// cost's curvature changes by a few per cent over ±2 standard errors there.
const PROBE_RELATIVE_SE: f64 = 0.02;

/// An estimate (θ̂, initial state, offset).
type At<'a> = (&'a Parameters, InitialState, f64);

/// The exact simulator's cost at the estimate and σ̂² = S/(n − p): the reference of
/// every Λ (the backend's own error does not enter it).
struct Reference {
    sse: f64,
    sigma2: f64,
}

fn exact(options: &EstimationOptions) -> Backend {
    match options.backend {
        Backend::Exact { hold } => Backend::Exact { hold },
        Backend::Ode45 { .. } => Backend::Exact {
            hold: msd_ode::Hold::Cubic,
        },
    }
}

fn reference(data: &DataSet, options: &EstimationOptions, at: At<'_>) -> Option<Reference> {
    let (theta, initial_state, offset) = at;
    let layout = Layout::new(options, false);
    let sse =
        Cost::new(data, &layout, exact(options)).sse(&layout.pack(theta, initial_state, offset));
    let dof = data.len().saturating_sub(layout.len()).max(1);
    let sigma2 = sse / dof as f64;
    (sse.is_finite() && sigma2 > 0.0).then_some(Reference { sse, sigma2 })
}

/// Λ = (S(θ_i = value) − S(θ̂)) / σ̂² with parameter `which` (0 m, 1 c, 2 k) fixed at
/// `value` and the rest refitted by Levenberg–Marquardt on the exact simulator; `None`
/// when that fit fails (no evidence either way).
fn profile(
    data: &DataSet,
    options: &EstimationOptions,
    at: At<'_>,
    which: usize,
    value: f64,
    reference: &Reference,
) -> Option<f64> {
    let (theta, initial_state, offset) = at;
    let mut start = *theta;
    let mut fixed = options.fixed;
    match which {
        0 => {
            // The same damping ratio: c scales with √m at fixed k.
            start.damping *= (value / theta.mass).sqrt();
            start.mass = value;
            fixed.mass = Some(value);
        }
        1 => {
            start.damping = value;
            fixed.damping = Some(value);
        }
        _ => {
            start.stiffness = value;
            fixed.stiffness = Some(value);
        }
    }
    let probe = EstimationOptions {
        method: Method::LevenbergMarquardt,
        backend: exact(options),
        initial_guess: Some(start),
        fixed,
        initial_state,
        offset,
        multistart: None,
        ..options.clone()
    };
    let refit = super::fit(data, &probe, super::Checks::None).ok()?;
    Some((refit.cost - reference.sse) / reference.sigma2)
}

/// The reference cost of every Λ, simulated once and only when a probe needs it.
type LazyReference<'a> = dyn Fn() -> Option<&'a Reference> + 'a;

/// Every check on an estimate: [`check_mass`] and [`check_intervals`], which refuse it,
/// and [`band_warning`]'s note, which is returned. The input's spectrum and the
/// reference cost are computed once, and only when needed.
pub(super) fn check(
    data: &DataSet,
    options: &EstimationOptions,
    at: At<'_>,
    uncertainty: &crate::uncertainty::Uncertainty,
) -> Result<Option<String>> {
    let mass_given = options.fixed.mass.is_some();
    let top = if mass_given { None } else { excited_top(data) };
    let cell = std::cell::OnceCell::new();
    let lazy = || cell.get_or_init(|| reference(data, options, at)).as_ref();
    if !mass_given && options.bounds.mass.is_none() {
        check_mass(data, options, at, uncertainty, top, &lazy)?;
    }
    check_intervals(data, options, at, uncertainty, &lazy)?;
    Ok(if mass_given {
        None
    } else {
        top.and_then(|top| band_warning(at.0, top))
    })
}

/// Refuses the estimate when fixing m at m̂/100 (or m̂/10⁴) explains the data as well
/// (see the module doc). Not called when the mass is fixed or bounded by the caller
/// (then it is known).
///
/// The probes cost two fits, so they run only where the mass line may be unexcited: the
/// estimated resonance lies beyond the Nyquist frequency or above twice the excited band
/// (99.9 % of the input's power, or no input power at all), or a parameter's relative
/// standard error exceeds 2 %. A resonance inside the excited band with tight intervals
/// is the data's own evidence for m, and the probes would only confirm it.
fn check_mass<'a>(
    data: &DataSet,
    options: &EstimationOptions,
    at: At<'_>,
    uncertainty: &crate::uncertainty::Uncertainty,
    band_top: Option<f64>,
    reference: &LazyReference<'a>,
) -> Result<()> {
    let theta = at.0;
    let fnat = theta.natural_frequency_hz();
    let beyond_nyquist = fnat > 0.5 / data.excitation.dt();
    let above_band = band_top.is_none_or(|top| fnat > 2.0 * top);
    let loose = [uncertainty.mass, uncertainty.damping, uncertainty.stiffness]
        .iter()
        .any(|iv| iv.standard_error > PROBE_RELATIVE_SE * iv.value.abs());
    if !(beyond_nyquist || above_band || loose) {
        return Ok(());
    }
    let Some(reference) = reference() else {
        return Ok(());
    };
    for factor in PROBES {
        let light = theta.mass / factor;
        let statistic = profile(data, options, at, 0, light, reference);
        if let Some(statistic) = statistic.filter(|s| *s < CHI2_1_95) {
            return Err(IdentError::NotIdentifiable {
                reason: refusal(data, theta, light, statistic),
            });
        }
    }
    Ok(())
}

/// Refuses intervals that do not hold: when some free parameter's relative standard
/// error exceeds 2 %, the cost is probed at each end of its linearised 95 % interval
/// (that parameter fixed there, the rest refitted). For a model linear in its
/// parameters Λ there is t²₀.₉₇₅ ≈ 3.84; an end whose Λ falls outside [2.71, 6.63]
/// (χ²₁ at 90 % and 99 %), or that leaves the physical range (m or k ≤ 0), means the
/// cost is too curved at this noise level for the interval to mean what it says, and
/// the estimate is refused as not identifiable at this noise level.
fn check_intervals<'a>(
    data: &DataSet,
    options: &EstimationOptions,
    at: At<'_>,
    uncertainty: &crate::uncertainty::Uncertainty,
    reference: &LazyReference<'a>,
) -> Result<()> {
    let intervals = [uncertainty.mass, uncertainty.damping, uncertainty.stiffness];
    let fixed = options.fixed.as_array();
    let bounded = options.bounds.as_array();
    let names = ["m", "c", "k"];
    let probed = (0..3).filter(|&i| {
        let iv = intervals[i];
        fixed[i].is_none()
            && bounded[i].is_none()
            && iv.standard_error > PROBE_RELATIVE_SE * iv.value.abs()
    });
    let probed: Vec<usize> = probed.collect();
    if probed.is_empty() {
        return Ok(());
    }
    let Some(reference) = reference() else {
        return Ok(());
    };
    for i in probed {
        let [low, high] = intervals[i].ci95;
        for (end, value) in [("lower", low), ("upper", high)] {
            if value <= 0.0 {
                if i == 1 {
                    continue; // c = 0 is a plant (undamped), not an impossibility
                }
                return Err(low_snr(names[i], intervals[i].ci95, end, None));
            }
            let statistic = profile(data, options, at, i, value, reference);
            if let Some(s) = statistic.filter(|s| !(CHI2_1_90..=CHI2_1_99).contains(s)) {
                return Err(low_snr(names[i], intervals[i].ci95, end, Some(s)));
            }
        }
    }
    Ok(())
}

fn low_snr(name: &str, ci95: [f64; 2], end: &str, statistic: Option<f64>) -> IdentError {
    let why = match statistic {
        Some(s) => format!(
            "the cost at its {end} end rises by Λ = {s:.2}, where an interval that holds gives 2.71–6.63 (χ²₁ at 90–99 %)"
        ),
        None => format!("its {end} end is not physical"),
    };
    IdentError::NotIdentifiable {
        reason: format!(
            "m, c and k are not identifiable at this noise level: the linearised 95 % interval of {name}, [{:.4e}, {:.4e}], does not hold ({why}). Record longer, excite harder or measure with less noise; the estimate is not reported because its intervals would mislead",
            ci95[0], ci95[1]
        ),
    }
}

fn refusal(data: &DataSet, theta: &Parameters, light: f64, statistic: f64) -> String {
    let factor = theta.mass / light;
    let nyquist = 0.5 / data.excitation.dt();
    let fnat = theta.natural_frequency_hz();
    let beyond = if fnat > nyquist {
        format!(", beyond the record's Nyquist frequency {nyquist:.4} Hz")
    } else {
        String::new()
    };
    format!(
        "the mass is not identifiable from these data: with m fixed at {light:.4e} (the estimate {:.4e} divided by {:.0e}) and the rest refitted, the data are explained as well (likelihood ratio {statistic:.2} < 3.84, the 95 % χ² point), so any interval around the estimate would not hold. The record does not excite the mass line: no dynamics, or a resonance far above the excited band (the estimate puts fn at {fnat:.4} Hz{beyond}). Give the mass (fixed.mass; with a resonance beyond the record, the damping too) to estimate the rest, or excite the resonance (a sweep through it, a step)",
        theta.mass, factor
    )
}

/// A warning when the estimated resonance lies above the excited band: more than twice
/// the frequency below which 99.9 % of the input's power lies (Welch, Hann, whole
/// record). There the mass enters only through the quasi-static roll-off
/// 1 − (f/fn)² of the response, a term the probes above may still not be able to
/// refuse (a feature of the noise or of aliasing that a resonance outside the band
/// happens to fit).
fn band_warning(theta: &Parameters, top: f64) -> Option<String> {
    let fnat = theta.natural_frequency_hz();
    (fnat > 2.0 * top).then(|| {
        format!(
            "the estimated resonance fn = {fnat:.4} Hz lies above the excited band (99.9 % of the input's power is below {top:.4} Hz): m rests on the response's quasi-static roll-off only, and its interval holds only if the model is exact; excite the resonance (a sweep through it) or give the mass"
        )
    })
}

/// The frequency below which 99.9 % of the input's power lies (Welch, Hann, whole
/// record, DC left out); `None` for an input without power above DC.
fn excited_top(data: &DataSet) -> Option<f64> {
    let fs = 1.0 / data.excitation.dt();
    let options = msd_signal::WelchOptions::default();
    let psd = msd_signal::welch_psd(data.excitation.samples(), fs, &options).ok()?;
    let total: f64 = psd.values.iter().skip(1).sum();
    if total.is_nan() || total <= 0.0 {
        return None;
    }
    let mut cumulative = 0.0;
    psd.frequency
        .iter()
        .zip(&psd.values)
        .skip(1)
        .find(|(_, p)| {
            cumulative += **p;
            cumulative >= 0.999 * total
        })
        .map(|(f, _)| *f)
}
