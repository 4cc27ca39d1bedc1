//! The regression F = m·x̂″ + c·x̂′ + k·x̂ + (law term) + F₀ over all conditions: one
//! pass over the samples gathers what every law needs (the normal equations of six
//! regressor columns, and the projections that carry the stroke noise into the
//! coefficients' covariance).

use super::harmonics::{Basis, HarmonicFit, derivative, from_sums};
use crate::law::DampingLaw;
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
    /// Σᵢ |x̂′ᵢ|·rᵢ·gᵢᵀ: the quadratic term's slope 2c₂|x̂′| against the basis (its tanh
    /// row zero: no law has both terms).
    pub quadratic_slope: Vec<f64>,
    /// Σᵢ sech²(x̂′ᵢ/v_s)·rᵢ·gᵢᵀ: the Coulomb term's slope (F_c/v_s)·sech² (its
    /// quadratic row zero).
    pub coulomb_slope: Vec<f64>,
    /// Σᵢ |x̂′ᵢ|·gᵢ·gᵢᵀ and Σᵢ x̂′ᵢ²·gᵢ·gᵢᵀ (quadratic law only): for the stroke noise's
    /// force in the residual.
    pub quadratic_grams: [DMatrix<f64>; 2],
    /// Σᵢ sech²·gᵢ·gᵢᵀ and Σᵢ sech⁴·gᵢ·gᵢᵀ (Coulomb law only).
    pub coulomb_grams: [DMatrix<f64>; 2],
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
    // Each law's regression term, as crate::law defines it.
    let term = |law: DampingLaw| law.term(v, inverse_smoothing).unwrap_or(0.0);
    [
        fit.acceleration[i],
        v,
        fit.displacement[i],
        1.0,
        term(DampingLaw::QuadraticViscous),
        term(DampingLaw::CoulombViscous),
    ]
}

/// Which slope projections the requested laws need.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Needs {
    pub quadratic: bool,
    pub coulomb: bool,
}

impl Prepared {
    /// Adds this condition's samples to `normal` and fills its projections. The basis
    /// runs to 2H harmonics: its first 2H + 1 entries are g, and the weighted sums of the
    /// whole row give the weighted Gram matrices ([`from_sums`]).
    pub fn accumulate(
        &mut self,
        dt: f64,
        inverse_smoothing: f64,
        needs: Needs,
        normal: &mut Normal,
    ) {
        let width = self.fit.stroke.len();
        let harmonics = (width - 1) / 2;
        // Σ wᵢ·rᵢ·gᵢᵀ for the law columns (r = x̂′|x̂′| or tanh), w = 1, |x̂′|, sech².
        let mut law_rows = vec![vec![0.0; width]; 4];
        let mut sums = vec![vec![0.0; 4 * harmonics + 1]; 4];
        let mut basis = Basis::new(self.fit.omega * dt, 2 * harmonics);
        for (i, &f) in self.force.iter().enumerate() {
            let r = row(&self.fit, i, inverse_smoothing);
            let doubled = basis.next_row();
            let g = &doubled[..width];
            normal.add(&r, f);
            add_scaled(&mut law_rows[0], r[QUADRATIC], g);
            add_scaled(&mut law_rows[1], r[COULOMB], g);
            if needs.quadratic {
                let speed = r[VELOCITY].abs();
                add_scaled(&mut law_rows[2], speed * r[QUADRATIC], g);
                add_scaled(&mut sums[0], speed, doubled);
                add_scaled(&mut sums[1], speed * speed, doubled);
            }
            if needs.coulomb && r[COULOMB].abs() < 1.0 {
                let sech2 = 1.0 - r[COULOMB] * r[COULOMB];
                add_scaled(&mut law_rows[3], sech2 * r[COULOMB], g);
                add_scaled(&mut sums[2], sech2, doubled);
                add_scaled(&mut sums[3], sech2 * sech2, doubled);
            }
        }
        let grams = |a: &[f64], b: &[f64], needed: bool| match needed {
            true => [from_sums(a, harmonics), from_sums(b, harmonics)],
            false => [DMatrix::zeros(0, 0), DMatrix::zeros(0, 0)],
        };
        self.quadratic_grams = grams(&sums[0], &sums[1], needs.quadratic);
        self.coulomb_grams = grams(&sums[2], &sums[3], needs.coulomb);
        self.projection = self.projection_rows(&self.fit.gram, [&law_rows[0], &law_rows[1]]);
        if needs.quadratic {
            let w = &self.quadratic_grams[0];
            self.quadratic_slope = self.projection_rows(w, [&law_rows[2], &vec![0.0; width]]);
        }
        if needs.coulomb {
            let w = &self.coulomb_grams[0];
            self.coulomb_slope = self.projection_rows(w, [&vec![0.0; width], &law_rows[3]]);
        }
    }

    /// Σ wᵢ·rᵢ·gᵢᵀ (COLUMNS × width, row-major) from W = Σ wᵢ·gᵢ·gᵢᵀ for the harmonic
    /// columns (x̂ = G·θ, x̂′ = G·Q·θ, x̂″ = G·Q²·θ, 1 = G·e₀, so their rows are W·θⱼ)
    /// and from the accumulated `law` rows for x̂′|x̂′| and tanh.
    fn projection_rows(&self, w: &DMatrix<f64>, law: [&[f64]; 2]) -> Vec<f64> {
        let fit = &self.fit;
        let width = fit.stroke.len();
        let q = derivative(fit.omega, (width - 1) / 2);
        let velocity = &q * &fit.stroke;
        let acceleration = &q * &velocity;
        let mut one = nalgebra::DVector::zeros(width);
        one[0] = 1.0;
        let mut out = vec![0.0; COLUMNS * width];
        for (column, theta) in [
            (ACCELERATION, &acceleration),
            (VELOCITY, &velocity),
            (DISPLACEMENT, &fit.stroke),
            (ONE, &one),
        ] {
            let projected = w * theta;
            out[column * width..(column + 1) * width].copy_from_slice(projected.as_slice());
        }
        out[QUADRATIC * width..(QUADRATIC + 1) * width].copy_from_slice(law[0]);
        out[COULOMB * width..(COULOMB + 1) * width].copy_from_slice(law[1]);
        out
    }
}

impl Normal {
    /// Adds one sample: regressor row `r`, force `f`.
    #[inline(always)]
    fn add(&mut self, r: &[f64; COLUMNS], f: f64) {
        for j in 0..COLUMNS {
            for l in j..COLUMNS {
                self.gram[j][l] += r[j] * r[l];
            }
            self.rhs[j] += r[j] * f;
        }
        self.force_sum += f;
        self.force_squares += f * f;
        self.samples += 1;
    }
}

/// out += s·row.
#[inline(always)]
fn add_scaled(out: &mut [f64], s: f64, row: &[f64]) {
    out.iter_mut().zip(row).for_each(|(o, r)| *o += s * r);
}

/// The rows `columns` of a COLUMNS × width row-major projection, as a matrix.
pub(crate) fn select(projection: &[f64], columns: &[usize], width: usize) -> DMatrix<f64> {
    DMatrix::from_fn(columns.len(), width, |r, j| {
        projection[columns[r] * width + j]
    })
}
