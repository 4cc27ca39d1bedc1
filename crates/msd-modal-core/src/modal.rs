//! One mode's contribution to a receptance, and its derivatives.

use std::f64::consts::TAU;

use msd_signal::Complex64;
use serde::{Deserialize, Serialize};

/// The parameters of one mode: its contribution to the receptance is
///
/// H_r(ω) = (A + j·B) / (ωn² − ω² + 2j·ζ·ωn·ω),
///
/// with the complex modal constant A + jB (Ewins, "Modal Testing", 2000, §2.3: its
/// phase is constant over the mode). A real mode (one of a proportionally damped
/// structure) has B = 0 and A = φ_i·φ_j (1/m for a single mass on a spring), and is then
/// exactly the viscously damped mode. A complex modal constant rotates the whole mode, as
/// non-proportional damping or a sensor's phase do on measured FRFs; unlike the viscous
/// pole–residue pair R/(jω − λ) + R̄/(jω − λ̄), whose numerator −2·Re(R·λ̄) + 2jω·Re R
/// grows with ω, it does not leak into the lines far from the mode (on a real hammer
/// test the viscous form biased the lowest mode's ζ by 40–50 % against local fits).
///
/// ```
/// use msd_modal_core::ModalParameters;
/// // The paper's plant, m = 2.5 kg, k = 120 N/m, c = 1.8 N·s/m: A = 1/m.
/// let mode = ModalParameters {
///     natural_frequency_hz: (120.0f64 / 2.5).sqrt() / std::f64::consts::TAU,
///     damping_ratio: 1.8 / (2.0 * (2.5f64 * 120.0).sqrt()),
///     modal_constant: 1.0 / 2.5,
///     modal_constant_imaginary: 0.0,
/// };
/// let f = 0.7;
/// let w = std::f64::consts::TAU * f;
/// let direct = 1.0 / msd_signal::Complex64::new(120.0 - 2.5 * w * w, 1.8 * w);
/// assert!((mode.receptance(f) - direct).norm() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModalParameters {
    /// Natural frequency fn = ωn/2π in Hz.
    pub natural_frequency_hz: f64,
    /// Damping ratio ζ.
    pub damping_ratio: f64,
    /// The modal constant's real part A.
    pub modal_constant: f64,
    /// The modal constant's imaginary part B (0 for a real mode).
    #[serde(default)]
    pub modal_constant_imaginary: f64,
}

impl ModalParameters {
    /// This mode's contribution to the receptance at `frequency_hz`.
    #[inline]
    pub fn receptance(&self, frequency_hz: f64) -> Complex64 {
        term(
            &[
                TAU * self.natural_frequency_hz,
                self.damping_ratio,
                self.modal_constant,
                self.modal_constant_imaginary,
            ],
            TAU * frequency_hz,
        )
    }
}

/// The contribution of the mode θ = (ωn, ζ, A, B) at ω.
#[inline]
pub fn term(theta: &[f64], w: f64) -> Complex64 {
    let (wn, zeta, a, b) = (theta[0], theta[1], theta[2], theta[3]);
    Complex64::new(a, b) / Complex64::new(wn * wn - w * w, 2.0 * zeta * wn * w)
}

/// The contribution of the mode θ = (ωn, ζ, A, B) at ω and its derivatives with respect
/// to ωn, ζ, A and B.
#[inline]
pub fn term_with_gradient(theta: &[f64], w: f64) -> (Complex64, [Complex64; 4]) {
    let (wn, zeta, a, b) = (theta[0], theta[1], theta[2], theta[3]);
    let inv_d = Complex64::new(1.0, 0.0) / Complex64::new(wn * wn - w * w, 2.0 * zeta * wn * w);
    let n = Complex64::new(a, b);
    let value = n * inv_d;
    let d_wn = -value * inv_d * Complex64::new(2.0 * wn, 2.0 * zeta * w);
    let d_zeta = -value * inv_d * Complex64::new(0.0, 2.0 * wn * w);
    let d_a = inv_d;
    let d_b = Complex64::new(0.0, 1.0) * inv_d;
    (value, [d_wn, d_zeta, d_a, d_b])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gradient_matches_central_differences() {
        let theta = [40.0, 0.03, 0.7, -0.2];
        for w in [10.0, 39.0, 41.5, 90.0] {
            let (value, gradient) = term_with_gradient(&theta, w);
            assert!((value - term(&theta, w)).norm() < 1e-15 * value.norm());
            for (i, g) in gradient.iter().enumerate() {
                let h = 1e-6 * theta[i].abs();
                let (mut up, mut down) = (theta, theta);
                up[i] += h;
                down[i] -= h;
                let numeric = (term(&up, w) - term(&down, w)) / (2.0 * h);
                assert!(
                    (numeric - g).norm() < 1e-7 * g.norm().max(1e-3),
                    "{i} at {w}: {numeric} vs {g}"
                );
            }
        }
    }

    #[test]
    fn the_modal_constant_is_the_numerator_at_every_frequency() {
        // Ewins' form: (A + jB)/(ωn² − ω² + 2jζωnω), the phase of A + jB constant.
        let (wn, zeta, a, b) = (30.0f64, 0.05, 0.7, -0.2);
        for w in [5.0, 29.0, 31.0, 70.0] {
            let d = Complex64::new(wn * wn - w * w, 2.0 * zeta * wn * w);
            let numerator = term(&[wn, zeta, a, b], w) * d;
            assert!((numerator - Complex64::new(a, b)).norm() < 1e-14);
        }
    }
}
