//! The modes of a fitted chain with their intervals by the delta method.

use super::problem::Layout;
use super::setup::ChainParameters;
use msd_modal_core::{Dof, Mode, ShapeEntry};
use msd_opt::statistics::Interval;
use msd_opt::statistics::delta_variance;
use msd_signal::Complex64;
use nalgebra::DMatrix;
use std::f64::consts::TAU;

impl ChainParameters {
    /// The underdamped modes of the parameters as given, by frequency (ground
    /// connections included): fn, ζ and the shape over the masses (DOF `i:+1` for mass
    /// i, the real part of each displacement, the largest 1), without uncertainty (a
    /// fit's modes with their intervals are in its
    /// [`ChainUncertainty`](super::ChainUncertainty)).
    ///
    /// ```
    /// use msd_ident::chain::ChainParameters;
    /// let p = ChainParameters { masses: vec![2.5], dampers: vec![1.8], springs: vec![120.0], ..ChainParameters::default() };
    /// let mode = &p.modes()[0];
    /// assert!((mode.natural_frequency_hz.value - 48f64.sqrt() / std::f64::consts::TAU).abs() < 1e-12);
    /// assert!((mode.damping_ratio.value - 1.8 / (2.0 * 300f64.sqrt())).abs() < 1e-12);
    /// assert_eq!((mode.shape[0].re, mode.natural_frequency_hz.standard_error), (1.0, 0.0));
    /// ```
    pub fn modes(&self) -> Vec<Mode> {
        modal_quantities(self)
            .iter()
            .map(|q| {
                let exact = |v| Interval::new(v, 0.0, 0.0);
                mode(q, exact(q[0]), exact(q[1]), |_| 0.0)
            })
            .collect()
    }
}

/// The mode of the quantities `q` (fn, ζ, shape…) with the intervals of fn and ζ and
/// the standard error `shape_se(i)` of each shape entry `q[i]`.
fn mode(
    q: &[f64],
    natural_frequency_hz: Interval,
    damping_ratio: Interval,
    shape_se: impl Fn(usize) -> f64,
) -> Mode {
    let shape = (2..q.len())
        .map(|i| {
            let dof = Dof {
                node: (i - 1) as u32,
                direction: 1,
            };
            ShapeEntry {
                standard_error: Some([shape_se(i), 0.0]),
                ..ShapeEntry::new(dof, Complex64::new(q[i], 0.0))
            }
        })
        .collect();
    Mode::new(natural_frequency_hz, damping_ratio).with_shape(shape)
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
) -> Vec<Mode> {
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
            mode(
                values,
                Interval::positive(fnat.value, fnat.standard_error, t),
                Interval::positive(zeta.value, zeta.standard_error, t),
                |i| interval(i).standard_error,
            )
        })
        .collect()
}
