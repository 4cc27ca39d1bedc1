//! How complex a mode shape is: the modal phase collinearity (MPC) and the mean phase
//! deviation (MPD), reported with every [`Mode`](crate::mode::Mode).

use msd_signal::Complex64;

/// The modal phase collinearity of a shape, from 0 to 1: 1 when every entry has the same
/// phase (up to 180°, a real mode), lower the more complex the shape (Pappa, Elliott &
/// Schenk, J. Guidance 16, 1993): MPC = ((Sxx − Syy)² + 4Sxy²)/(Sxx + Syy)² with
/// Sxx = Σ Re², Syy = Σ Im², Sxy = Σ Re·Im. 0 for a zero shape.
///
/// ```
/// use msd_modal_core::modal_phase_collinearity;
/// use msd_signal::Complex64;
/// let real = [1.0, -0.5, 0.2].map(|x| Complex64::from_polar(x, 0.3));
/// assert!((modal_phase_collinearity(&real) - 1.0).abs() < 1e-14);
/// let travelling = [Complex64::new(1.0, 0.0), Complex64::new(0.0, 1.0)];
/// assert!(modal_phase_collinearity(&travelling).abs() < 1e-15);
/// ```
pub fn modal_phase_collinearity(shape: &[Complex64]) -> f64 {
    let sxx: f64 = shape.iter().map(|x| x.re * x.re).sum();
    let syy: f64 = shape.iter().map(|x| x.im * x.im).sum();
    let sxy: f64 = shape.iter().map(|x| x.re * x.im).sum();
    let total = sxx + syy;
    if total == 0.0 {
        return 0.0;
    }
    ((sxx - syy).powi(2) + 4.0 * sxy * sxy) / (total * total)
}

/// The mean phase deviation of a shape, degrees: the magnitude-weighted mean angle of
/// its entries from the shape's principal direction in the complex plane (taken modulo
/// 180°); 0 for a real mode. 0 for a zero shape.
///
/// ```
/// use msd_modal_core::mean_phase_deviation;
/// use msd_signal::Complex64;
/// let real = [1.0, -0.5, 0.2].map(|x| Complex64::from_polar(x, 1.1));
/// assert!(mean_phase_deviation(&real) < 1e-6);
/// let skew = [Complex64::from_polar(1.0, 0.0), Complex64::from_polar(1.0, 0.2)];
/// assert!((mean_phase_deviation(&skew) - 0.1f64.to_degrees()).abs() < 1e-9);
/// ```
pub fn mean_phase_deviation(shape: &[Complex64]) -> f64 {
    let total: f64 = shape.iter().map(|x| x.norm()).sum();
    if total == 0.0 {
        return 0.0;
    }
    let direction = principal_angle(shape);
    let deviation: f64 = shape
        .iter()
        .map(|x| {
            // The angle between the entry's line and the principal line, in [0, π/2].
            let d = (x.arg() - direction).rem_euclid(std::f64::consts::PI);
            x.norm() * d.min(std::f64::consts::PI - d)
        })
        .sum();
    (deviation / total).to_degrees()
}

/// The angle of the line through the origin that the entries (as points Re, Im) lie
/// closest to: half the angle of Σ x², the principal axis of their second moments.
fn principal_angle(shape: &[Complex64]) -> f64 {
    let sum: Complex64 = shape.iter().map(|x| x * x).sum();
    0.5 * sum.arg()
}
