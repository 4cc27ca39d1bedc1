//! Automatic initial guess: a second-order ARX model mapped to continuous m, c, k.
//!
//! ## The algorithm
//! 1. Fit yₖ = −a₁yₖ₋₁ − a₂yₖ₋₂ + b₀uₖ + b₁uₖ₋₁ + b₂uₖ₋₂ (+ d) by least squares.
//! 2. Output noise makes that equation error coloured and biases the fit, badly so when
//!    the sample rate is far above the resonance (poles crowd z = 1). So the fit is
//!    refined by instrumental variables: the instruments are the noise-free outputs
//!    simulated by the previous ARX model (three passes, as in the classic IV4 idea).
//! 3. Steps 1–2 are repeated on the record decimated by 2, 4, 8, … (msd-signal's
//!    anti-aliased `decimate`, while at least 100 samples remain): a resonance far below
//!    the sample rate is fitted well only at a coarser rate, and which rate suits is not
//!    known in advance. Each candidate is simulated on the full-rate data and the one with
//!    the smallest output error (means removed) wins.
//! 4. The discrete poles z map to s = ln(z)/dt, giving ωn = |s| and ζ = −Re(s)/|s| (or
//!    the two real poles of an over-damped system); the static gain G = Σb/(1 + a₁ + a₂)
//!    is 1/k. Then m = k/ωn² and c = 2ζ√(mk).
//!
//! Everything is relative, so it works in any units (a plant with m ≈ 1e-6 in volts as
//! well as the paper's kilograms). It is only a starting point for the estimators.

use crate::{
    data::DataSet,
    error::{IdentError, Result},
    params::{InitialState, Parameters},
    simulate::{Backend, simulate},
};
use nalgebra::{DMatrix, DVector};

/// Estimates (m, c, k) from the data by instrumental-variable ARX(2, 3) fits at several
/// sample rates, keeping the candidate that best reproduces the measured output.
///
/// ```
/// use msd_ident::{simulate, Backend, DataSet, Excitation, InitialState, Parameters, arx::arx_initial_guess};
/// use msd_signal::paper_identification_input;
/// let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
/// let y = simulate(&Parameters::PAPER, &input, InitialState::REST, &Backend::EXACT)?;
/// let guess = arx_initial_guess(&DataSet::new("noise-free", input, y)?)?;
/// assert!((guess.stiffness / 120.0 - 1.0).abs() < 0.05);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn arx_initial_guess(data: &DataSet) -> Result<Parameters> {
    let mut u = data.excitation.samples().to_vec();
    let mut y = data.output.clone();
    let mut dt = data.excitation.dt();
    let mut best: Option<(f64, Parameters)> = None;
    let mut last_error = None;
    loop {
        match fit(&u, &y, dt) {
            Ok(candidate) => {
                let score = output_error(data, &candidate);
                if best.is_none_or(|(b, _)| score < b) {
                    best = Some((score, candidate));
                }
            }
            Err(e) => last_error = Some(e),
        }
        if y.len() / 2 < MIN_DECIMATED {
            break;
        }
        u = msd_signal::decimate(&u, 2)?;
        y = msd_signal::decimate(&y, 2)?;
        dt *= 2.0;
    }
    match (best, last_error) {
        (Some((_, p)), _) => Ok(p),
        (None, Some(e)) => Err(e),
        (None, None) => Err(IdentError::NotIdentifiable {
            reason: "the ARX initial guess found no candidate; give an initial guess".into(),
        }),
    }
}

/// Shortest decimated record the cascade fits.
const MIN_DECIMATED: usize = 100;

/// Output error of a candidate on the full-rate data, means removed (so an unknown sensor
/// offset does not decide), +∞ if it cannot be simulated.
fn output_error(data: &DataSet, candidate: &Parameters) -> f64 {
    let Ok(x) = simulate(
        candidate,
        &data.excitation,
        InitialState::REST,
        &Backend::EXACT,
    ) else {
        return f64::INFINITY;
    };
    let n = x.len() as f64;
    let (mx, my) = (
        x.iter().sum::<f64>() / n,
        data.output.iter().sum::<f64>() / n,
    );
    let sse: f64 = x
        .iter()
        .zip(&data.output)
        .map(|(a, b)| ((b - my) - (a - mx)).powi(2))
        .sum();
    if sse.is_finite() { sse } else { f64::INFINITY }
}

/// Regressor row k: (−yₖ₋₁, −yₖ₋₂, uₖ, uₖ₋₁, uₖ₋₂, 1).
fn row(w: &[f64], u: &[f64], k: usize) -> [f64; 6] {
    [-w[k - 1], -w[k - 2], u[k], u[k - 1], u[k - 2], 1.0]
}

fn fit(u: &[f64], y: &[f64], dt: f64) -> Result<Parameters> {
    to_parameters(&coefficients(u, y)?, dt)
}

/// ωn and ζ of the ARX(2, 3) poles of `y` against `u` (least squares refined by
/// instrumental variables), whatever the output's static gain: a guess for records whose
/// output is a velocity, an acceleration or a base-excited motion.
pub(crate) fn arx_poles(u: &[f64], y: &[f64], dt: f64) -> Result<(f64, f64)> {
    poles(&coefficients(u, y)?, dt)
}

/// The ARX coefficients (a₁, a₂, b₀, b₁, b₂, d).
fn coefficients(u: &[f64], y: &[f64]) -> Result<[f64; 6]> {
    let n = y.len();
    if n < 12 {
        return Err(IdentError::TooFewSamples {
            got: n,
            needed: 12,
            why: "the ARX initial guess",
        });
    }
    // Ordinary least squares, then instrumental-variable passes.
    let mut theta = solve(u, y, y)?;
    for _ in 0..3 {
        let simulated = simulate_arx(&theta, u, y);
        if simulated.iter().any(|v| !v.is_finite()) {
            break;
        }
        match solve(u, y, &simulated) {
            Ok(t) => theta = t,
            Err(_) => break,
        }
    }
    Ok(theta)
}

/// Solves Σ zₖφₖᵀ θ = Σ zₖyₖ with instruments built from `w` (w = y gives least squares).
fn solve(u: &[f64], y: &[f64], w: &[f64]) -> Result<[f64; 6]> {
    let mut zphi = DMatrix::<f64>::zeros(6, 6);
    let mut zy = DVector::<f64>::zeros(6);
    // Column scaling keeps the normal equations well conditioned in any units.
    let ys = y
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    let us = u
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    let scale = [ys, ys, us, us, us, ys];
    for k in 2..y.len() {
        let phi = row(y, u, k);
        let z = row(w, u, k);
        for r in 0..6 {
            let zr = z[r] / scale[r];
            for c in 0..6 {
                zphi[(r, c)] += zr * phi[c] / scale[c];
            }
            zy[r] += zr * y[k] / ys;
        }
    }
    let solution = zphi
        .clone()
        .lu()
        .solve(&zy)
        .filter(|s| s.iter().all(|v| v.is_finite()))
        .ok_or_else(|| IdentError::NotIdentifiable {
            reason: "the ARX regression is singular: the input does not excite the system".into(),
        })?;
    Ok(std::array::from_fn(|i| solution[i] * ys / scale[i]))
}

fn simulate_arx(theta: &[f64; 6], u: &[f64], y: &[f64]) -> Vec<f64> {
    let mut w = vec![0.0; y.len()];
    w[0] = y[0];
    w[1] = y[1];
    for k in 2..y.len() {
        let phi = row(&w, u, k);
        w[k] = phi.iter().zip(theta).map(|(p, t)| p * t).sum();
    }
    w
}

fn to_parameters(theta: &[f64; 6], dt: f64) -> Result<Parameters> {
    let (a1, a2) = (theta[0], theta[1]);
    let gain_den = 1.0 + a1 + a2;
    let gain = (theta[2] + theta[3] + theta[4]) / gain_den;
    let fail = |reason: &str| IdentError::NotIdentifiable {
        reason: format!("the ARX initial guess failed: {reason}; give an initial guess"),
    };
    if !(gain.is_finite() && gain > 0.0) {
        return Err(fail("the static gain is not positive"));
    }
    let (wn, zeta) = poles(theta, dt)?;
    let k = 1.0 / gain;
    let m = k / (wn * wn);
    let c = 2.0 * zeta * (m * k).sqrt();
    Parameters::new(m, c, k).map_err(|_| fail("the mapped parameters are not physical"))
}

/// ωn and ζ of the poles of z² + a₁z + a₂ (continuous time s = ln(z)/dt).
fn poles(theta: &[f64; 6], dt: f64) -> Result<(f64, f64)> {
    let (a1, a2) = (theta[0], theta[1]);
    let fail = |reason: &str| IdentError::NotIdentifiable {
        reason: format!("the ARX initial guess failed: {reason}; give an initial guess"),
    };
    // Poles: z² + a1 z + a2 = 0.
    let disc = a1 * a1 - 4.0 * a2;
    let (wn, zeta) = if disc < 0.0 {
        let re = -a1 / 2.0;
        let im = (-disc).sqrt() / 2.0;
        let r = (re * re + im * im).sqrt();
        if r >= 1.0 {
            return Err(fail("the identified poles are unstable"));
        }
        let s_re = r.ln() / dt;
        let s_im = im.atan2(re) / dt;
        let wn = (s_re * s_re + s_im * s_im).sqrt();
        (wn, -s_re / wn)
    } else {
        let root = disc.sqrt();
        let (z1, z2) = ((-a1 + root) / 2.0, (-a1 - root) / 2.0);
        if !(z1 > 0.0 && z1 < 1.0 && z2 > 0.0 && z2 < 1.0) {
            return Err(fail(
                "the identified poles are not those of a damped oscillator",
            ));
        }
        let (s1, s2) = (z1.ln() / dt, z2.ln() / dt);
        let wn = (s1 * s2).sqrt();
        (wn, -(s1 + s2) / (2.0 * wn))
    };
    if !(wn.is_finite() && wn > 0.0 && zeta.is_finite() && zeta > 0.0) {
        return Err(fail(
            "the identified poles are not those of a damped oscillator",
        ));
    }
    Ok((wn, zeta))
}
