//! One damping law fitted across all conditions, with the stroke noise carried into its
//! intervals.

use super::DynamometerOptions;
use super::harmonics::derivative;
use super::regression::{
    ACCELERATION, COULOMB, DISPLACEMENT, Normal, ONE, Prepared, QUADRATIC, VELOCITY, row, select,
};
use crate::error::{IdentError, Result};
use crate::law::{DampingForce, DampingLaw};
use crate::metrics::FitMetrics;
use crate::uncertainty::t_975;
use msd_opt::statistics::Interval;
use msd_opt::statistics::Linearization;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// One damping law fitted to every condition together:
/// F = m·x̂″ + f_d(x̂′) + k·x̂ + F₀, linear in the coefficients.
///
/// Displays as one row of the laws table (see [`Dynamometer`](super::Dynamometer)).
///
/// ```
/// use msd_ident::{dynamometer::{dynamometer, DynamometerOptions, synthetic_dynamometer, SyntheticDynamometer}, nonlinear::DampingLaw};
/// let conditions = synthetic_dynamometer(&SyntheticDynamometer::default())?;
/// let options = DynamometerOptions { laws: vec![DampingLaw::QuadraticViscous], ..Default::default() };
/// let fit = &dynamometer(&conditions, &options)?.laws[0];
/// assert_eq!(fit.names, ["mass", "damping", "stiffness", "quadratic_damping", "force_offset"]);
/// let (c, c2) = (fit.value("damping"), fit.value("quadratic_damping"));
/// assert_eq!(fit.damping_force(-1.0), -c - c2);
/// assert!(fit.coefficient("coulomb_force").is_none());
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
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
        named(&self.names, &self.coefficients, name)
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
        let law = DampingForce {
            viscous: self.value("damping"),
            quadratic: self.value("quadratic_damping"),
            coulomb: self.value("coulomb_force"),
            inverse_smoothing: self.smoothing_velocity.map_or(0.0, |vs| 1.0 / vs),
        };
        law.force(v)
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

/// The coefficient called `name` among `names`.
pub(super) fn named<'a>(
    names: &[&str],
    coefficients: &'a [Interval],
    name: &str,
) -> Option<&'a Interval> {
    names
        .iter()
        .position(|n| *n == name)
        .map(|i| &coefficients[i])
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
    if let Some(name) = law.coefficient() {
        columns.push(match law {
            DampingLaw::CoulombViscous => COULOMB,
            _ => QUADRATIC,
        });
        names.push(name);
    }
    if options.force_offset {
        columns.push(ONE);
        names.push("force_offset");
    }
    (columns, names)
}

/// The fitted values the stroke-noise terms need.
struct Coefficients {
    columns: Vec<usize>,
    mass: f64,
    damping: f64,
    stiffness: f64,
    /// c₂ or F_c.
    law_term: f64,
    inverse_smoothing: f64,
}

impl Coefficients {
    fn new(
        columns: &[usize],
        beta: &DVector<f64>,
        known_mass: Option<f64>,
        inverse_smoothing: f64,
    ) -> Self {
        let at = |name: usize| columns.iter().position(|&c| c == name).map(|j| beta[j]);
        Self {
            columns: columns.to_vec(),
            mass: at(ACCELERATION).or(known_mass).unwrap_or(0.0),
            damping: at(VELOCITY).unwrap_or(0.0),
            stiffness: at(DISPLACEMENT).unwrap_or(0.0),
            law_term: at(QUADRATIC).or(at(COULOMB)).unwrap_or(0.0),
            inverse_smoothing,
        }
    }
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
    let linearization = Linearization::from_normal_matrix(&gram).ok()?;
    let condition_number = linearization.condition_number;
    // Regressors this close to collinear leave β to rounding.
    if condition_number >= 1e12 {
        return None;
    }
    let inverse = linearization.covariance(1.0);
    Some(Solved {
        beta: &inverse * rhs,
        inverse,
        condition_number,
    })
}

/// Fits `law` to the prepared conditions (see the module doc for the covariance); with
/// `force_sigma`, the force noise's σ is that instead of the residual's (a plan).
pub(crate) fn fit_law(
    law: DampingLaw,
    prepared: &[Prepared],
    normal: &Normal,
    smoothing_velocity: f64,
    options: &DynamometerOptions,
    force_sigma: Option<f64>,
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
    let fitted = Coefficients::new(
        &columns,
        &solved.beta,
        options.known_mass,
        inverse_smoothing,
    );
    let stroke = stroke_noise(law, prepared, &solved, &fitted);
    // The force noise: the SSE less the stroke noise's expected share of it.
    let sigma2 = force_sigma.map_or_else(
        || (sse - stroke.residual_share).max(0.0) / dof as f64,
        |s| s * s,
    );
    let covariance =
        &solved.inverse * sigma2 + &solved.inverse * stroke.covariance_term * &solved.inverse;
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
/// `law` fitted to `normal` and evaluated on `condition` (smoothing velocity
/// `smoothing_velocity`): its model force over the analysed samples, or `None` where the
/// law's regressors are collinear in `normal`.
pub(crate) fn fitted_force(
    law: DampingLaw,
    normal: &Normal,
    condition: &Prepared,
    smoothing_velocity: f64,
    options: &DynamometerOptions,
) -> Option<Vec<f64>> {
    let (columns, _) = design(law, options);
    let solved = solve(normal, &columns, options.known_mass)?;
    let condition = std::slice::from_ref(condition);
    let (mut forces, _) = model_forces(
        condition,
        &columns,
        &solved.beta,
        options,
        1.0 / smoothing_velocity,
    );
    forces.pop()
}

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

/// The stroke noise's part in the regression: its covariance term
/// Σ_c σ̂ₓ,c²·S_c·(GᵀG)_c⁻¹·S_cᵀ with S_c = Xᵀ·M_c, and its expected share of the SSE,
/// tr((I − H)·M·Cov θ·Mᵀ) = Σ_c σ̂ₓ,c²·tr((GᵀG)_c⁻¹·M_cᵀM_c) − tr((XᵀX)⁻¹·term).
struct StrokeNoise {
    covariance_term: DMatrix<f64>,
    residual_share: f64,
}

/// The stroke noise in each condition's harmonic coefficients θ_c carried through x̂, x̂′
/// and x̂″ into the regression (the delta method on the errors in the variables):
/// Mᵢ = ∂F̂ᵢ/∂θ = gᵢᵀ·A + f_d′(x̂′ᵢ)·gᵢᵀ·Q with A = k·I + m·Q² and f_d′ = c, c + 2c₂|x̂′|
/// or c + (F_c/v_s)·sech²(x̂′/v_s). So S = P·A + (c·P + slope)·Q with P = Σ rᵢ·gᵢᵀ,
/// and MᵀM = A·W₀·A + A·W₁·Q + Qᵀ·W₁·A + Qᵀ·W₂·Q with Wₖ = Σ f_d′ᵏ·gᵢ·gᵢᵀ.
fn stroke_noise(
    law: DampingLaw,
    prepared: &[Prepared],
    solved: &Solved,
    coefficients: &Coefficients,
) -> StrokeNoise {
    let p = solved.beta.len();
    let (mut term, mut share) = (DMatrix::zeros(p, p), 0.0);
    for cond in prepared {
        let width = cond.fit.stroke.len();
        let q = derivative(cond.fit.omega, (width - 1) / 2);
        let projection = select(&cond.projection, &coefficients.columns, width);
        let (slope, [w1, w2]) = law_slopes(law, cond, coefficients, &projection);
        let a =
            DMatrix::identity(width, width) * coefficients.stiffness + &q * &q * coefficients.mass;
        let s = &projection * &a + slope * &q;
        let c = &cond.fit.gram_inverse;
        let sigma2 = cond.fit.stroke_sigma * cond.fit.stroke_sigma;
        term += &s * c * s.transpose() * sigma2;
        let aw1q = &a * w1 * &q;
        let mtm = &a * &cond.fit.gram * &a + &aw1q + aw1q.transpose() + q.transpose() * w2 * &q;
        share += sigma2 * (c * mtm).trace();
    }
    share -= (&solved.inverse * &term).trace();
    StrokeNoise {
        covariance_term: term,
        residual_share: share,
    }
}

/// The law's slope projection c·P + Σ f″-weighted rᵢ·gᵢᵀ, and W₁, W₂ (see
/// [`stroke_noise`]).
fn law_slopes(
    law: DampingLaw,
    cond: &Prepared,
    k: &Coefficients,
    projection: &DMatrix<f64>,
) -> (DMatrix<f64>, [DMatrix<f64>; 2]) {
    let (c, w0) = (k.damping, &cond.fit.gram);
    let width = w0.nrows();
    let (weight, slope, grams) = match law {
        DampingLaw::Viscous => return (projection * c, [w0 * c, w0 * (c * c)]),
        DampingLaw::QuadraticViscous => (
            2.0 * k.law_term,
            &cond.quadratic_slope,
            &cond.quadratic_grams,
        ),
        DampingLaw::CoulombViscous => (
            k.law_term * k.inverse_smoothing,
            &cond.coulomb_slope,
            &cond.coulomb_grams,
        ),
    };
    let slope = projection * c + select(slope, &k.columns, width) * weight;
    let w1 = w0 * c + &grams[0] * weight;
    let w2 = w0 * (c * c) + &grams[0] * (2.0 * c * weight) + &grams[1] * (weight * weight);
    (slope, [w1, w2])
}
