//! Mode shapes compared and judged: the modal assurance criterion (MAC) and the
//! complexity of a shape (MPC, MPD).

use msd_signal::Complex64;

/// The modal assurance criterion of two shapes over the same DOFs:
/// MAC = |aᴴb|² / ((aᴴa)(bᴴb)), 1 for shapes that differ only by a complex factor, 0 for
/// orthogonal ones (Allemang & Brown, IMAC 1982). 0 when either shape is zero.
///
/// ```
/// use msd_ident::frf::mac;
/// use msd_signal::Complex64;
/// let a = [1.0, 2.0, -1.0].map(|x| Complex64::new(x, 0.0));
/// let b = a.map(|x| x * Complex64::new(0.0, -3.0)); // the same shape, scaled and rotated
/// assert!((mac(&a, &b) - 1.0).abs() < 1e-15);
/// let c = [1.0, 0.0, 1.0].map(|x| Complex64::new(x, 0.0)); // orthogonal to a
/// assert_eq!(mac(&a, &c), 0.0);
/// ```
pub fn mac(a: &[Complex64], b: &[Complex64]) -> f64 {
    debug_assert_eq!(a.len(), b.len());
    let cross: Complex64 = a.iter().zip(b).map(|(x, y)| x.conj() * y).sum();
    let (aa, bb) = (norm_sqr(a), norm_sqr(b));
    if aa == 0.0 || bb == 0.0 {
        return 0.0;
    }
    cross.norm_sqr() / (aa * bb)
}

/// The MAC of every shape of `a` with every shape of `b`: `matrix[i][j]` = MAC(aᵢ, bⱼ)
/// (the auto-MAC with `b = a`).
///
/// ```
/// use msd_ident::frf::mac_matrix;
/// use msd_signal::Complex64;
/// let shapes = vec![
///     [1.0, 1.0].map(|x| Complex64::new(x, 0.0)).to_vec(),
///     [1.0, -1.0].map(|x| Complex64::new(x, 0.0)).to_vec(),
/// ];
/// assert_eq!(mac_matrix(&shapes, &shapes), vec![vec![1.0, 0.0], vec![0.0, 1.0]]);
/// ```
pub fn mac_matrix(a: &[Vec<Complex64>], b: &[Vec<Complex64>]) -> Vec<Vec<f64>> {
    a.iter()
        .map(|x| b.iter().map(|y| mac(x, y)).collect())
        .collect()
}

/// The modal phase collinearity of a shape, from 0 to 1: 1 when every entry has the same
/// phase (up to 180°, a real mode), lower the more complex the shape (Pappa, Elliott &
/// Schenk, J. Guidance 16, 1993): MPC = ((Sxx − Syy)² + 4Sxy²)/(Sxx + Syy)² with
/// Sxx = Σ Re², Syy = Σ Im², Sxy = Σ Re·Im. 0 for a zero shape.
///
/// ```
/// use msd_ident::frf::modal_phase_collinearity;
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
/// use msd_ident::frf::mean_phase_deviation;
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

/// `shape` scaled so that its largest entry is 1 (real and positive).
///
/// ```
/// use msd_ident::frf::unit_normalised;
/// use msd_signal::Complex64;
/// let shape = [Complex64::new(0.0, 2.0), Complex64::new(0.0, -1.0)];
/// assert_eq!(unit_normalised(&shape), vec![Complex64::new(1.0, 0.0), Complex64::new(-0.5, 0.0)]);
/// ```
pub fn unit_normalised(shape: &[Complex64]) -> Vec<Complex64> {
    let largest = shape
        .iter()
        .copied()
        .max_by(|a, b| a.norm_sqr().total_cmp(&b.norm_sqr()))
        .unwrap_or(Complex64::new(1.0, 0.0));
    if largest.norm_sqr() == 0.0 {
        return shape.to_vec();
    }
    shape.iter().map(|x| x / largest).collect()
}

fn norm_sqr(shape: &[Complex64]) -> f64 {
    shape.iter().map(Complex64::norm_sqr).sum()
}
