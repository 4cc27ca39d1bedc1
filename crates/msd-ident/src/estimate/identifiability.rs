//! Is the mass identifiable at all? A likelihood-ratio probe of the mass profile.
//!
//! The linearised intervals of [`crate::Uncertainty`] describe the cost near θ̂ only.
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
use crate::{Backend, DataSet, EstimationOptions, FixedParameters, IdentError, InitialState};
use crate::{Method, Parameters, Result};

/// The factors the probes divide the mass by.
const PROBES: [f64; 2] = [1e2, 1e4];
/// χ²₁ at 0.95: the likelihood-ratio threshold of a 95 % interval.
const CHI2_1_95: f64 = 3.841_458_820_694_124;

/// Refuses the estimate when fixing m at m̂/100 explains the data as well (see the
/// module doc). Skipped when the mass is fixed or bounded by the caller (then it is
/// known), and when the probe fit itself fails (no evidence either way).
pub(super) fn check_mass(
    data: &DataSet,
    options: &EstimationOptions,
    estimate: (&Parameters, InitialState, f64),
) -> Result<()> {
    let (theta, initial_state, offset) = estimate;
    if options.fixed.mass.is_some() || options.bounds.mass.is_some() {
        return Ok(());
    }
    let hold = match options.backend {
        Backend::Exact { hold } => hold,
        Backend::Ode45 { .. } => msd_ode::Hold::Cubic,
    };
    // Both costs on the exact simulator, so the backend's own error does not enter Λ.
    let exact = Backend::Exact { hold };
    let layout = Layout::new(options, false);
    let sse = Cost::new(data, &layout, exact).sse(&layout.pack(theta, initial_state, offset));
    let dof = data.len().saturating_sub(layout.len()).max(1);
    let sigma2 = sse / dof as f64;
    if !(sse.is_finite() && sigma2 > 0.0) {
        return Ok(());
    }
    for factor in PROBES {
        let light = theta.mass / factor;
        let statistic = probe(data, options, estimate, light, sse, sigma2);
        if statistic.is_some_and(|s| s < CHI2_1_95) {
            return Err(IdentError::NotIdentifiable {
                reason: refusal(data, theta, light, statistic.unwrap_or_default()),
            });
        }
    }
    Ok(())
}

/// Λ of the fit with m fixed at `light` and the rest refitted (`None` when that fit
/// fails).
fn probe(
    data: &DataSet,
    options: &EstimationOptions,
    estimate: (&Parameters, InitialState, f64),
    light: f64,
    sse: f64,
    sigma2: f64,
) -> Option<f64> {
    let (theta, initial_state, offset) = estimate;
    let hold = match options.backend {
        Backend::Exact { hold } => hold,
        Backend::Ode45 { .. } => msd_ode::Hold::Cubic,
    };
    let exact = Backend::Exact { hold };
    let probe = EstimationOptions {
        method: Method::LevenbergMarquardt,
        backend: exact,
        // The same damping ratio: c scales with √m at fixed k.
        initial_guess: Some(Parameters {
            mass: light,
            damping: theta.damping * (light / theta.mass).sqrt(),
            stiffness: theta.stiffness,
        }),
        fixed: FixedParameters {
            mass: Some(light),
            ..options.fixed
        },
        initial_state,
        offset,
        multistart: None,
        ..options.clone()
    };
    let refit = super::estimate(data, &probe).ok()?;
    Some((refit.cost - sse) / sigma2)
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
pub(super) fn band_warning(data: &DataSet, theta: &Parameters) -> Option<String> {
    let fs = 1.0 / data.excitation.dt();
    let options = msd_signal::WelchOptions::default();
    let psd = msd_signal::welch_psd(data.excitation.samples(), fs, &options).ok()?;
    let total: f64 = psd.values.iter().skip(1).sum();
    if total.is_nan() || total <= 0.0 {
        return None;
    }
    let mut cumulative = 0.0;
    let top = psd
        .frequency
        .iter()
        .zip(&psd.values)
        .skip(1)
        .find(|(_, p)| {
            cumulative += **p;
            cumulative >= 0.999 * total
        })
        .map(|(f, _)| *f)?;
    let fnat = theta.natural_frequency_hz();
    (fnat > 2.0 * top).then(|| {
        format!(
            "the estimated resonance fn = {fnat:.4} Hz lies above the excited band (99.9 % of the input's power is below {top:.4} Hz): m rests on the response's quasi-static roll-off only, and its interval holds only if the model is exact; excite the resonance (a sweep through it) or give the mass"
        )
    })
}
