//! Taking an exponential window's damping off: the window e^(−t/τ) on both channels
//! turns H(s) into H(s + a), a = 1/τ, moving every pole λ to λ − a; the fit finds the
//! moved pole and this module moves it back.

use serde::{Deserialize, Serialize};

/// What an exponential window did to a mode, and how it was taken off: the fitted
/// pole λ' = −ζ'ωn' + jωn'√(1 − ζ'²) is moved right by a = 1/τ, so the damped frequency
/// is kept and σ = ζ'ωn' − a; then ωn = √(ωd² + σ²), ζ = σ/ωn. To first order
/// ζ_added = ζ' − ζ ≈ 1/(ωn·τ).
///
/// ```
/// use msd_modal_core::WindowCorrection;
/// let c = WindowCorrection { decay_time: 0.5, natural_frequency_hz_windowed: 10.0,
///     damping_ratio_windowed: 0.05, damping_ratio_added: 0.03 };
/// assert_eq!(c.to_string(),
///     "exponential window τ = 0.5 s: ζ = 0.050000 as fitted, 0.030000 of it added by the window");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WindowCorrection {
    /// Decay time τ of the window in seconds.
    pub decay_time: f64,
    /// fn fitted to the windowed response, Hz.
    pub natural_frequency_hz_windowed: f64,
    /// ζ fitted to the windowed response.
    pub damping_ratio_windowed: f64,
    /// What the window added, ζ_windowed − ζ (≈ 1/(ωn·τ)).
    pub damping_ratio_added: f64,
}

impl std::fmt::Display for WindowCorrection {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "exponential window τ = {} s: ζ = {:.6} as fitted, {:.6} of it added by the window",
            self.decay_time, self.damping_ratio_windowed, self.damping_ratio_added
        )
    }
}

/// (ωn, ζ) of the pole of the windowed fit (ωn', ζ') moved right by `a`, and the
/// Jacobian ∂(ωn, ζ)/∂(ωn', ζ') (rows ωn, ζ).
pub fn unshift_pole(wn: f64, zeta: f64, a: f64) -> ([f64; 2], [[f64; 2]; 2]) {
    let sigma = zeta * wn - a;
    let wn_true = (wn * wn - 2.0 * a * zeta * wn + a * a).sqrt();
    let dwn = [(wn - a * zeta) / wn_true, -a * wn / wn_true];
    let s = sigma / (wn_true * wn_true);
    let dzeta = [zeta / wn_true - s * dwn[0], wn / wn_true - s * dwn[1]];
    ([wn_true, sigma / wn_true], [dwn, dzeta])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_damped_frequency_is_kept_and_the_jacobian_is_right() {
        let (wn, zeta, a) = (60.0, 0.04, 0.8);
        let ([wn0, zeta0], jac) = unshift_pole(wn, zeta, a);
        let damped = |w: f64, z: f64| w * (1.0 - z * z).sqrt();
        assert!((damped(wn0, zeta0) - damped(wn, zeta)).abs() < 1e-12);
        assert!((zeta0 * wn0 - (zeta * wn - a)).abs() < 1e-12);
        // First order: ζ_added ≈ a/ωn.
        assert!(((zeta - zeta0) / (a / wn) - 1.0).abs() < 1e-3);
        let h = [1e-6 * wn, 1e-6 * zeta];
        for j in 0..2 {
            let (mut up, mut down) = ([wn, zeta], [wn, zeta]);
            up[j] += h[j];
            down[j] -= h[j];
            let (u, _) = unshift_pole(up[0], up[1], a);
            let (d, _) = unshift_pole(down[0], down[1], a);
            for i in 0..2 {
                let numeric = (u[i] - d[i]) / (2.0 * h[j]);
                assert!((numeric - jac[i][j]).abs() < 1e-7 * jac[i][j].abs().max(1.0));
            }
        }
    }
}
