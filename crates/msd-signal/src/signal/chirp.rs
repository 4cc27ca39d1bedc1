//! Closed forms of the linear and logarithmic chirp (swept sine).
//!
//! With τ = t − t_start measured from the start of the sweep and T its duration:
//!
//! * linear: f(τ) = f0 + (f1 − f0)·τ/T, phase θ(τ) = 2π·(f0·τ + (f1 − f0)/(2T)·τ²);
//! * logarithmic (exponential): f(τ) = f0·r^(τ/T) with r = f1/f0,
//!   θ(τ) = 2π·f0·T/ln r·(r^(τ/T) − 1), which tends to the constant-frequency phase 2π·f0·τ
//!   as r → 1.
//!
//! The chirp's value is `amplitude · sin(θ(τ) + phase)` on `[t_start, t_start + T)`.

use serde::{Deserialize, Serialize};

/// How a chirp's instantaneous frequency moves from `f0` to `f1`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Sweep {
    /// Frequency linear in time (the paper's validation input). The default.
    #[default]
    Linear,
    /// Frequency exponential in time (equal time per octave); needs `f0 > 0` and `f1 > 0`.
    Logarithmic,
}

/// Below this |ln r| a logarithmic sweep is treated as constant frequency.
pub(crate) const FLAT_LOG_RATIO: f64 = 1e-12;

/// Phase θ(τ) in radians, without the user's phase offset.
#[inline]
pub(crate) fn phase(sweep: Sweep, f0: f64, f1: f64, duration: f64, tau: f64) -> f64 {
    use std::f64::consts::TAU;
    match sweep {
        Sweep::Linear => TAU * (f0 * tau + (f1 - f0) / (2.0 * duration) * tau * tau),
        Sweep::Logarithmic => {
            let ln_r = (f1 / f0).ln();
            if ln_r.abs() < FLAT_LOG_RATIO {
                TAU * f0 * tau
            } else {
                TAU * f0 * duration / ln_r * (tau / duration * ln_r).exp_m1()
            }
        }
    }
}

/// Instantaneous frequency f(τ) = θ'(τ)/(2π) in hertz.
#[inline]
pub(crate) fn frequency(sweep: Sweep, f0: f64, f1: f64, duration: f64, tau: f64) -> f64 {
    match sweep {
        Sweep::Linear => f0 + (f1 - f0) * tau / duration,
        Sweep::Logarithmic => f0 * (f1 / f0).powf(tau / duration),
    }
}
