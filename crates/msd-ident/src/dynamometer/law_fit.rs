//! One damping law fitted across all conditions, with the stroke noise carried into its
//! intervals.

use super::DynamometerOptions;
use super::harmonics::derivative;
use super::regression::{
    ACCELERATION, COULOMB, DISPLACEMENT, Normal, ONE, Prepared, QUADRATIC, VELOCITY, row, select,
};
use crate::uncertainty::t_975;
use crate::{DampingLaw, FitMetrics, IdentError, Interval, Result};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// One damping law fitted to every condition together:
/// F = m·x̂″ + f_d(x̂′) + k·x̂ + F₀, linear in the coefficients.
///
/// Displays as one row of the laws table (see [`Dynamometer`](super::Dynamometer)).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LawFit {
    /// The damping law f_d.
    pub law: DampingLaw,
    /// The estimated coefficients' names, in order: `mass` (unless known), `damping`,
    /// `stiffness`, then `coulomb_force` or `quadratic_damping`, then `force_offset`.
    pub names: Vec<&'static str>,
    /// The coefficients with standard errors and 95 % intervals (Student's t).
    pub coefficients: Vec<Interval>,
    /// The known mass, kg, when it was not estimated.
    pub known_mass: Option<f64>,
    /// The Coulomb smoothing velocity v_s, m/s (Coulomb law only).
    pub smoothing_velocity: Option<f64>,
    /// Coefficients' covariance, rows in the order of `names`.
    #[serde(serialize_with = "crate::ser::matrix_rows")]
    pub covariance: DMatrix<f64>,
    /// σ̂ of the force residual, N.
    pub force_sigma: f64,
    /// The fit over every analysed sample.
    pub fit: FitMetrics,
    /// BIC = N·ln(SSE/N) + p·ln N.
    pub bic: f64,
    /// BIC − the lowest BIC among the laws.
    pub delta_bic: f64,
    /// 1 for the lowest BIC.
    pub rank: usize,
    /// Condition number of the column-scaled normal matrix.
    pub condition_number: f64,
    /// The model force at every analysed sample of every condition, N (for the loops).
    #[serde(skip)]
    pub model_force: Vec<Vec<f64>>,
}

impl LawFit {
    /// The coefficient `name`, if estimated.
    pub fn coefficient(&self, name: &str) -> Option<&Interval> {
        self.names
            .iter()
            .position(|n| *n == name)
            .map(|i| &self.coefficients[i])
    }

    /// The value of `name`: estimated, the known mass, or 0 for a term the law lacks.
    pub fn value(&self, name: &str) -> f64 {
        match (name, self.coefficient(name)) {
            (_, Some(c)) => c.value,
            ("mass", None) => self.known_mass.unwrap_or(0.0),
            _ => 0.0,
        }
    }

    /// The fitted damping force f_d(v), N, at velocity `v` (for the F–v curve).
    pub fn damping_force(&self, v: f64) -> f64 {
        let coulomb = match self.smoothing_velocity {
            Some(vs) => self.value("coulomb_force") * (v / vs).tanh(),
            None => 0.0,
        };
        self.value("damping") * v + self.value("quadratic_damping") * v * v.abs() + coulomb
    }
}

impl std::fmt::Display for LawFit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let coefficients: Vec<String> = self
            .names
            .iter()
            .zip(&self.coefficients)
            .map(|(n, c)| format!("{n} = {:.5e} ± {:.2e}", c.value, c.standard_error))
            .collect();
        write!(
            f,
            "| {} | {:?} | {} | {} | {:.4e} | {:.1} | {:.1} |",
            self.rank,
            self.law,
            self.names.len(),
            coefficients.join(", "),
            self.force_sigma,
            self.bic,
            self.delta_bic
        )
    }
}

/// The columns and names of `law`'s regression.
fn design(law: DampingLaw, options: &DynamometerOptions) -> (Vec<usize>, Vec<&'static str>) {
    let mut columns = Vec::with_capacity(5);
    let mut names = Vec::with_capacity(5);
    if options.known_mass.is_none() {
        columns.push(ACCELERATION);
        names.push("mass");
    }
    columns.extend([VELOCITY, DISPLACEMENT]);
    names.extend(["damping", "stiffness"]);
    match law {
        DampingLaw::Viscous => {}
        DampingLaw::CoulombViscous => {
            columns.push(COULOMB);
            names.push("coulomb_force");
        }
        DampingLaw::QuadraticViscous => {
            columns.push(QUADRATIC);
            names.push("quadratic_damping");
        }
    }
    if options.force_offset {
        columns.push(ONE);
        names.push("force_offset");
    }
    (columns, names)
}

/// The solved normal equations: β, (XᵀX)⁻¹ and the scaled condition number.
struct Solved {
    beta: DVector<f64>,
    inverse: DMatrix<f64>,
    condition_number: f64,
}

fn solve(normal: &Normal, columns: &[usize], known_mass: Option<f64>) -> Option<Solved> {
    let p = columns.len();
    let at = |j: usize, l: usize| normal.gram[j.min(l)][j.max(l)];
    let gram = DMatrix::from_fn(p, p, |r, c| at(columns[r], columns[c]));
    let rhs = DVector::from_fn(p, |r, _| {
        normal.rhs[columns[r]] - known_mass.unwrap_or(0.0) * at(columns[r], ACCELERATION)
    });
    let scale = DVector::from_fn(p, |r, _| 1.0 / gram[(r, r)].sqrt());
    let scaled = DMatrix::from_fn(p, p, |r, c| gram[(r, c)] * scale[r] * scale[c]);
    let eigen = scaled.clone().symmetric_eigenvalues();
    let condition_number = eigen.max() / eigen.min();
    if !(condition_number.is_finite() && condition_number > 0.0 && condition_number < 1e12) {
        return None;
    }
    let scaled_inverse = scaled.cholesky()?.inverse();
    let inverse = DMatrix::from_fn(p, p, |r, c| scaled_inverse[(r, c)] * scale[r] * scale[c]);
    Some(Solved {
        beta: &inverse * rhs,
        inverse,
        condition_number,
    })
}

/// Fits `law` to the prepared conditions (see the module doc for the covariance).
pub(crate) fn fit_law(
    law: DampingLaw,
    prepared: &[Prepared],
    normal: &Normal,
    smoothing_velocity: f64,
    options: &DynamometerOptions,
) -> Result<LawFit> {
    let (columns, names) = design(law, options);
    let solved =
        solve(normal, &columns, options.known_mass).ok_or_else(|| IdentError::NotIdentifiable {
            reason: format!(
                "the {law:?} law's regressors ({}) are collinear across the conditions: \
                 test at more frequencies and amplitudes, or fix the mass",
                names.join(", ")
            ),
        })?;
    let inverse_smoothing = 1.0 / smoothing_velocity;
    let (model_force, sse) =
        model_forces(prepared, &columns, &solved.beta, options, inverse_smoothing);
    let (n, p) = (normal.samples, columns.len());
    let dof = n - p;
    let sigma2 = sse / dof as f64;
    let stroke = stroke_noise_term(
        law,
        prepared,
        &columns,
        &solved.beta,
        options,
        inverse_smoothing,
    );
    let covariance = &solved.inverse * sigma2 + &solved.inverse * stroke * &solved.inverse;
    let t = t_975(dof);
    let coefficients = (0..p)
        .map(|j| Interval::new(solved.beta[j], covariance[(j, j)].max(0.0).sqrt(), t))
        .collect();
    let nf = n as f64;
    let sst = normal.force_squares - normal.force_sum * normal.force_sum / nf;
    Ok(LawFit {
        law,
        names,
        coefficients,
        known_mass: options.known_mass,
        smoothing_velocity: (law == DampingLaw::CoulombViscous).then_some(smoothing_velocity),
        covariance,
        force_sigma: sigma2.sqrt(),
        fit: FitMetrics {
            r_squared: 1.0 - sse / sst,
            fit_percent: 100.0 * (1.0 - (sse / sst).sqrt()),
            residual_rms: (sse / nf).sqrt(),
            sse,
            samples: n,
        },
        bic: nf * (sse / nf).ln() + p as f64 * nf.ln(),
        delta_bic: 0.0,
        rank: 0,
        condition_number: solved.condition_number,
        model_force,
    })
}

/// The model force at every sample of every condition, and the SSE.
fn model_forces(
    prepared: &[Prepared],
    columns: &[usize],
    beta: &DVector<f64>,
    options: &DynamometerOptions,
    inverse_smoothing: f64,
) -> (Vec<Vec<f64>>, f64) {
    let mut sse = 0.0;
    let known_mass = options.known_mass.unwrap_or(0.0);
    let forces = prepared
        .iter()
        .map(|c| {
            let mut model = vec![0.0; c.force.len()];
            for (i, (m, f)) in model.iter_mut().zip(&c.force).enumerate() {
                let r = row(&c.fit, i, inverse_smoothing);
                *m = known_mass * r[ACCELERATION]
                    + columns
                        .iter()
                        .zip(beta.iter())
                        .map(|(&j, b)| b * r[j])
                        .sum::<f64>();
                sse += (f - *m) * (f - *m);
            }
            model
        })
        .collect();
    (forces, sse)
}

/// Σ_c σ̂ₓ,c²·S_c·(GᵀG)_c⁻¹·S_cᵀ with S_c = Xᵀ·∂F̂/∂θ_c: the stroke noise in each
/// condition's harmonic coefficients θ_c, carried through x̂, x̂′ and x̂″ into the
/// regression (the delta method on the errors in the variables).
///
/// ∂F̂ᵢ/∂θ = gᵢᵀ·(k·I + m·Q²) + f_d′(x̂′ᵢ)·gᵢᵀ·Q with f_d′ = c, c + 2c₂|x̂′| or
/// c + (F_c/v_s)·sech²(x̂′/v_s), so S = P·(k·I + m·Q²) + (c·P + slope)·Q with
/// P = Σ rᵢ·gᵢᵀ and slope the law's Σ f″-weighted projection (see [`Prepared`]).
fn stroke_noise_term(
    law: DampingLaw,
    prepared: &[Prepared],
    columns: &[usize],
    beta: &DVector<f64>,
    options: &DynamometerOptions,
    inverse_smoothing: f64,
) -> DMatrix<f64> {
    let p = columns.len();
    let at = |name: usize| columns.iter().position(|&c| c == name).map(|j| beta[j]);
    let mass = at(ACCELERATION).or(options.known_mass).unwrap_or(0.0);
    let (c, k) = (at(VELOCITY).unwrap_or(0.0), at(DISPLACEMENT).unwrap_or(0.0));
    let mut total = DMatrix::zeros(p, p);
    for cond in prepared {
        let width = cond.fit.stroke.len();
        let q = derivative(cond.fit.omega, (width - 1) / 2);
        let projection = select(&cond.projection, columns, width);
        let mut slope = &projection * c;
        match law {
            DampingLaw::Viscous => {}
            DampingLaw::QuadraticViscous => {
                let c2 = at(QUADRATIC).unwrap_or(0.0);
                slope += select(&cond.quadratic_slope, columns, width) * (2.0 * c2);
            }
            DampingLaw::CoulombViscous => {
                let fc = at(COULOMB).unwrap_or(0.0);
                slope += select(&cond.coulomb_slope, columns, width) * (fc * inverse_smoothing);
            }
        }
        let stiffness = DMatrix::identity(width, width) * k + &q * &q * mass;
        let s = &projection * stiffness + slope * &q;
        let sigma2 = cond.fit.stroke_sigma * cond.fit.stroke_sigma;
        total += &s * &cond.fit.gram_inverse * s.transpose() * sigma2;
    }
    total
}
