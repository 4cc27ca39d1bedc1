//! The modes of a fitted chain with their intervals by the delta method.

use super::problem::Layout;
use super::setup::ChainParameters;
use msd_opt::statistics::Interval;
use msd_opt::statistics::delta_variance;
use msd_signal::Complex64;
use nalgebra::DMatrix;
use serde::Serialize;
use std::f64::consts::TAU;

/// One mode of a chain: its natural frequency, damping ratio and shape (the masses'
/// displacements, scaled so that the largest is 1), each with a 95 % interval.
///
/// ```
/// use msd_ident::{chain::ChainMode, Interval};
/// let fixed = |v| Interval { value: v, standard_error: 0.0, ci95: [v, v] };
/// let mode = ChainMode { natural_frequency_hz: fixed(11.25), damping_ratio: fixed(0.01), shape: vec![fixed(1.0)] };
/// assert!(mode.to_string().starts_with("fn = 11.25"));
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainMode {
    /// fn = |λ|/2π, Hz.
    pub natural_frequency_hz: Interval,
    /// ζ = −Re λ/|λ|.
    pub damping_ratio: Interval,
    /// The real part of each mass's displacement, scaled so that the largest magnitude
    /// is 1 and the first mass that moves at least half as much is positive.
    pub shape: Vec<Interval>,
}

impl std::fmt::Display for ChainMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "fn = {:.6} Hz, ζ = {:.6}, shape [",
            self.natural_frequency_hz, self.damping_ratio
        )?;
        for (i, s) in self.shape.iter().enumerate() {
            let sep = if i == 0 { "" } else { ", " };
            write!(f, "{sep}{:.4} ± {:.1e}", s.value, s.standard_error)?;
        }
        write!(f, "]")
    }
}

impl ChainParameters {
    /// (fn in Hz, ζ) of each underdamped mode, by frequency (ground connections included).
    ///
    /// ```
    /// use msd_ident::chain::ChainParameters;
    /// let p = ChainParameters { masses: vec![2.5], dampers: vec![1.8], springs: vec![120.0], ..ChainParameters::default() };
    /// let (f, zeta) = p.modes()[0];
    /// assert!((f - 48f64.sqrt() / std::f64::consts::TAU).abs() < 1e-12);
    /// assert!((zeta - 1.8 / (2.0 * 300f64.sqrt())).abs() < 1e-12);
    /// ```
    pub fn modes(&self) -> Vec<(f64, f64)> {
        modal_quantities(self)
            .iter()
            .map(|q| (q[0], q[1]))
            .collect()
    }
}

/// (fn, ζ, shape…) of each underdamped mode of the chain, by frequency.
pub(crate) fn modal_quantities(parameters: &ChainParameters) -> Vec<Vec<f64>> {
    let n = parameters.masses.len();
    let [m, mut c, mut k] = parameters.plant(1, 1).matrices();
    // The extra connections to the ground, which the frequency-response plant has not.
    let v = super::problem::values(parameters);
    for i in 0..n {
        c[(i, i)] += v.cg[i];
        k[(i, i)] += v.kg[i];
    }
    super::underdamped_poles(&super::state_matrix(&m, &c, &k))
        .iter()
        .map(|&l| {
            let z = DMatrix::from_fn(n, n, |i, j| {
                l * l * m[(i, j)] + l * c[(i, j)] + Complex64::new(k[(i, j)], 0.0)
            });
            // The shape spans Z(λ)'s null space: the right singular vector of the
            // smallest singular value.
            let svd = z.svd(false, true);
            let v_t = svd.v_t.expect("requested");
            let smallest = svd.singular_values.imin();
            let shape: Vec<Complex64> = (0..n).map(|j| v_t[(smallest, j)].conj()).collect();
            // Scaled by the largest magnitude (continuous), turned so that the first
            // mass moving at least half as much is real and positive: a choice that
            // does not flip between records when two masses move equally.
            let largest = shape.iter().map(|s| s.norm()).fold(0.0, f64::max);
            let reference = shape
                .iter()
                .copied()
                .find(|s| s.norm() >= 0.5 * largest)
                .unwrap_or(Complex64::new(1.0, 0.0));
            let top = reference / reference.norm() * largest;
            let wn = l.norm();
            [wn / TAU, -l.re / wn]
                .into_iter()
                .chain(shape.iter().map(|s| (s / top).re))
                .collect()
        })
        .collect()
}

/// The modes at θ with intervals from `covariance` (of θ) by the delta method, the
/// gradients by central differences of step 1e-6 in the logarithms (the eigenvalues are
/// smooth; the truncation error ~1e-12 relative).
pub(crate) fn modes_with_intervals(
    layout: &Layout,
    theta: &[f64],
    base: &ChainParameters,
    delays: &[f64],
    covariance: &DMatrix<f64>,
    t: f64,
) -> Vec<ChainMode> {
    let at = |theta: &[f64]| modal_quantities(&layout.unpack(theta, base, delays).0);
    let centre = at(theta);
    const H: f64 = 1e-6;
    let free = layout.free.len();
    let mut gradients =
        vec![vec![vec![0.0; free]; centre.first().map_or(0, Vec::len)]; centre.len()];
    for j in 0..free {
        let (mut up, mut down) = (theta.to_vec(), theta.to_vec());
        up[j] += H;
        down[j] -= H;
        let (hi, lo) = (at(&up), at(&down));
        if hi.len() != centre.len() || lo.len() != centre.len() {
            continue;
        }
        for (mode, grads) in gradients.iter_mut().enumerate() {
            for (q, g) in grads.iter_mut().enumerate() {
                g[j] = (hi[mode][q] - lo[mode][q]) / (2.0 * H);
            }
        }
    }
    centre
        .iter()
        .zip(&gradients)
        .map(|(values, grads)| {
            let interval = |q: usize| {
                let var = delta_variance(&grads[q], |r, c| covariance[(r, c)]);
                Interval::from_variance(values[q], var, t)
            };
            let fnat = interval(0);
            let zeta = interval(1);
            ChainMode {
                natural_frequency_hz: Interval::positive(fnat.value, fnat.standard_error, t),
                damping_ratio: Interval::positive(zeta.value, zeta.standard_error, t),
                shape: (2..values.len()).map(interval).collect(),
            }
        })
        .collect()
}
