//! The regression F = m·x̂″ + c·x̂′ + k·x̂ + (law term) + F₀ over all conditions: one
//! pass over the samples gathers what every law needs (the normal equations of six
//! regressor columns, and the projections that carry the stroke noise into the
//! coefficients' covariance).

use super::harmonics::{Basis, HarmonicFit, derivative};
use nalgebra::DMatrix;

/// x̂″, the mass's column.
pub(crate) const ACCELERATION: usize = 0;
/// x̂′, the viscous column.
pub(crate) const VELOCITY: usize = 1;
/// x̂, the stiffness's column.
pub(crate) const DISPLACEMENT: usize = 2;
/// 1, the force offset's column.
pub(crate) const ONE: usize = 3;
/// x̂′|x̂′|, the quadratic damping's column.
pub(crate) const QUADRATIC: usize = 4;
/// tanh(x̂′/v_s), the Coulomb force's column.
pub(crate) const COULOMB: usize = 5;
/// Number of regressor columns.
pub(crate) const COLUMNS: usize = 6;

/// One condition ready for the laws' fits.
#[derive(Debug, Clone)]
pub(crate) struct Prepared {
    /// Its harmonic fit (x̂, x̂′, x̂″, θ, (GᵀG)⁻¹, σ̂ₓ).
    pub fit: HarmonicFit,
    /// The measured force over the analysed samples.
    pub force: Vec<f64>,
    /// Σᵢ rᵢ·gᵢᵀ (COLUMNS × width, row-major): the regressors against the basis.
    pub projection: Vec<f64>,
    /// Σᵢ |x̂′ᵢ|·rᵢ·gᵢᵀ: the quadratic term's slope 2c₂|x̂′| against the basis.
    pub quadratic_slope: Vec<f64>,
    /// Σᵢ sech²(x̂′ᵢ/v_s)·rᵢ·gᵢᵀ: the Coulomb term's slope (F_c/v_s)·sech².
    pub coulomb_slope: Vec<f64>,
}

/// The normal equations of the six columns over all conditions.
#[derive(Debug, Clone, Default)]
pub(crate) struct Normal {
    /// Σ r·rᵀ.
    pub gram: [[f64; COLUMNS]; COLUMNS],
    /// Σ r·F.
    pub rhs: [f64; COLUMNS],
    /// Σ F, Σ F², for R².
    pub force_sum: f64,
    pub force_squares: f64,
    /// Samples.
    pub samples: usize,
}

/// The regressor row r at one sample: [x̂″, x̂′, x̂, 1, x̂′|x̂′|, tanh(x̂′/v_s)];
/// `inverse_smoothing` = 1/v_s, or 0 when no Coulomb law is fitted.
#[inline(always)]
pub(crate) fn row(fit: &HarmonicFit, i: usize, inverse_smoothing: f64) -> [f64; COLUMNS] {
    let v = fit.velocity[i];
    [
        fit.acceleration[i],
        v,
        fit.displacement[i],
        1.0,
        v * v.abs(),
        smoothed_sign(v * inverse_smoothing),
    ]
}

/// tanh(z), as ±1 past |z| = 20 where tanh is 1 to 4e-18 (most samples: v_s is small).
#[inline(always)]
fn smoothed_sign(z: f64) -> f64 {
    if z.abs() > 20.0 { z.signum() } else { z.tanh() }
}

/// Which slope projections the requested laws need.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Needs {
    pub quadratic: bool,
    pub coulomb: bool,
}

impl Prepared {
    /// Adds this condition's samples to `normal` and fills its projections.
    pub fn accumulate(
        &mut self,
        dt: f64,
        inverse_smoothing: f64,
        needs: Needs,
        normal: &mut Normal,
    ) {
        let width = self.fit.stroke.len();
        let harmonics = (width - 1) / 2;
        self.projection = self.harmonic_projection();
        self.quadratic_slope = vec![0.0; if needs.quadratic { COLUMNS * width } else { 0 }];
        self.coulomb_slope = vec![0.0; if needs.coulomb { COLUMNS * width } else { 0 }];
        let mut basis = Basis::new(self.fit.omega * dt, harmonics);
        for (i, &f) in self.force.iter().enumerate() {
            let r = row(&self.fit, i, inverse_smoothing);
            let g = basis.next_row();
            for j in 0..COLUMNS {
                for l in j..COLUMNS {
                    normal.gram[j][l] += r[j] * r[l];
                }
                normal.rhs[j] += r[j] * f;
            }
            normal.force_sum += f;
            normal.force_squares += f * f;
            for law in [QUADRATIC, COULOMB] {
                let out = &mut self.projection[law * width..(law + 1) * width];
                out.iter_mut().zip(g).for_each(|(o, g)| *o += r[law] * g);
            }
            if needs.quadratic {
                add_outer(&mut self.quadratic_slope, r[VELOCITY].abs(), &r, g);
            }
            if needs.coulomb && r[COULOMB].abs() < 1.0 {
                add_outer(
                    &mut self.coulomb_slope,
                    1.0 - r[COULOMB] * r[COULOMB],
                    &r,
                    g,
                );
            }
        }
        normal.samples += self.force.len();
    }

    /// The rows of Σ r·gᵀ for the harmonic columns, from GᵀG (x̂ = G·θ, x̂′ = G·Q·θ,
    /// x̂″ = G·Q²·θ, 1 = G·e₀); the law rows start at zero.
    fn harmonic_projection(&self) -> Vec<f64> {
        let fit = &self.fit;
        let width = fit.stroke.len();
        let q = derivative(fit.omega, (width - 1) / 2);
        let velocity = &q * &fit.stroke;
        let acceleration = &q * &velocity;
        let mut out = vec![0.0; COLUMNS * width];
        for (column, theta) in [
            (ACCELERATION, &acceleration),
            (VELOCITY, &velocity),
            (DISPLACEMENT, &fit.stroke),
        ] {
            let projected = fit.gram.tr_mul(theta);
            out[column * width..(column + 1) * width].copy_from_slice(projected.as_slice());
        }
        for j in 0..width {
            out[ONE * width + j] = fit.gram[(0, j)];
        }
        out
    }
}

/// out += s·r·gᵀ (COLUMNS × width, row-major).
#[inline(always)]
fn add_outer(out: &mut [f64], s: f64, r: &[f64; COLUMNS], g: &[f64]) {
    let width = g.len();
    for (j, rj) in r.iter().enumerate() {
        let w = s * rj;
        let dst = &mut out[j * width..(j + 1) * width];
        dst.iter_mut().zip(g).for_each(|(o, g)| *o += w * g);
    }
}

/// The rows `columns` of a COLUMNS × width row-major projection, as a matrix.
pub(crate) fn select(projection: &[f64], columns: &[usize], width: usize) -> DMatrix<f64> {
    DMatrix::from_fn(columns.len(), width, |r, j| {
        projection[columns[r] * width + j]
    })
}
