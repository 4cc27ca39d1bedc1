//! The plant's intervals from the projected Jacobian: covariance, then m, c, k, fn and ζ
//! by the delta method.
//!
//! Every reported quantity is a monomial of the model's θ = (m, c, k) (m = 1 and c, k
//! per unit mass for the drives that cannot fix the mass; a known mass or stiffness
//! multiplies in): ln q = eᵀ ln θ + const. So Var(ln q) = eᵀ·Cov(ln θ)·e exactly to first
//! order, and SE(q) = q·√(eᵀ·Cov·e); the 95 % intervals use Student's t with the fit's
//! degrees of freedom.

use super::problem::Joint;
use crate::least_squares::SingularError;
use crate::plant::Drive;
use crate::uncertainty::t_975;
use crate::{error::Result, params::KnownParameter};
use msd_opt::statistics::Interval;
use msd_opt::statistics::Linearization;
use nalgebra::{DMatrix, Matrix3};
use serde::Serialize;
use std::f64::consts::PI;

/// What a setup identifies, with 95 % intervals.
///
/// Displays one line per identified quantity, then the note.
///
/// ```
/// use msd_ident::{Interval, records::PlantIntervals};
/// let fixed = |v: f64| Interval { value: v, standard_error: 0.0, ci95: [v, v] };
/// let plant = PlantIntervals {
///     identifiable: vec!["natural_frequency_hz", "damping_ratio"],
///     mass: None, damping: None, stiffness: None,
///     natural_frequency_hz: fixed(1.1), damping_ratio: fixed(0.05),
///     correlation: vec![vec![1.0, -0.1], vec![-0.1, 1.0]],
///     degrees_of_freedom: 100, note: None,
/// };
/// assert!(plant.to_string().starts_with("fn = 1.100000"));
/// assert!(serde_json::to_value(&plant)?["mass"].is_null());
/// # Ok::<(), serde_json::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlantIntervals {
    /// The names of the quantities the setup identifies, among `natural_frequency_hz`,
    /// `damping_ratio`, `mass`, `damping`, `stiffness` (a known one counts, with a zero
    /// standard error).
    pub identifiable: Vec<&'static str>,
    /// m, kg, when identifiable.
    pub mass: Option<Interval>,
    /// c, N·s/m, when identifiable.
    pub damping: Option<Interval>,
    /// k, N/m, when identifiable.
    pub stiffness: Option<Interval>,
    /// fn = ωn/2π, Hz.
    pub natural_frequency_hz: Interval,
    /// ζ.
    pub damping_ratio: Interval,
    /// The estimates' correlation, rows and columns in the order of `identifiable`; a
    /// known quantity (no variance) has a row and column of zeros.
    pub correlation: Vec<Vec<f64>>,
    /// The degrees of freedom of the intervals' Student t: samples minus estimated
    /// quantities (all records and channels), or fewer under the drive's noise model,
    /// whose estimated variances make the standard errors uncertain (Satterthwaite).
    pub degrees_of_freedom: usize,
    /// Why m, c and k are not given, when they are not.
    pub note: Option<String>,
}

impl std::fmt::Display for PlantIntervals {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "fn = {} Hz\nζ  = {}",
            self.natural_frequency_hz, self.damping_ratio
        )?;
        for (name, unit, iv) in [
            ("m ", "kg", &self.mass),
            ("c ", "N·s/m", &self.damping),
            ("k ", "N/m", &self.stiffness),
        ] {
            if let Some(iv) = iv {
                write!(f, "\n{name} = {iv} {unit}")?;
            }
        }
        if let Some(note) = &self.note {
            write!(f, "\nnote: {note}")?;
        }
        Ok(())
    }
}

/// The projected weighted Jacobian at θ and the inverse of its Gram matrix.
pub(crate) struct Linearised {
    /// P⊥·W·∂ŷ/∂ln θ, one column per free parameter.
    pub jacobian: DMatrix<f64>,
    /// (JᵀJ)⁻¹: the white-noise covariance of the free ln θ.
    pub inverse: DMatrix<f64>,
}

/// The projected weighted Jacobian at θ (after `prepare`) and (JᵀJ)⁻¹, refusing a
/// singular one with the reason.
pub(crate) fn linearise(problem: &Joint<'_>, theta: [f64; 3]) -> Result<Linearised> {
    let p = problem.free.len();
    let mut jacobian = DMatrix::<f64>::zeros(problem.rows, p);
    problem.fill_jacobian(theta, &mut jacobian)?;
    let names: Vec<&str> = problem
        .free
        .iter()
        .map(|&i| ["mass", "damping", "stiffness"][i])
        .collect();
    // The Jacobian is weighted by 1/σ̂ per channel: the covariance is (JᵀJ)⁻¹.
    // JᵀJ by dot products: a joint Jacobian has tens of thousands of rows and three
    // columns, where the product through a transposed copy costs milliseconds.
    let inverse = Linearization::from_normal_matrix(&jacobian.tr_mul(&jacobian))
        .map_err(|e| {
            e.error(
                "the records (beyond their initial states and offsets)",
                &names,
            )
        })?
        .covariance(1.0);
    Ok(Linearised { jacobian, inverse })
}

/// The white-noise Cov(ln θ) (3×3, zero rows for fixed parameters) at θ (after
/// `prepare`).
pub(crate) fn log_covariance(problem: &Joint<'_>, theta: [f64; 3]) -> Result<Matrix3<f64>> {
    Ok(embed(problem, &linearise(problem, theta)?.inverse))
}

/// Cov(ln θ) (3×3, zero rows for fixed parameters) from the covariance of the free ones.
pub(crate) fn embed(problem: &Joint<'_>, free: &DMatrix<f64>) -> Matrix3<f64> {
    let mut cov = Matrix3::zeros();
    for (a, &pa) in problem.free.iter().enumerate() {
        for (b, &pb) in problem.free.iter().enumerate() {
            cov[(pa, pb)] = free[(a, b)];
        }
    }
    cov
}

/// The intervals of everything the setup identifies at the model's θ.
pub(crate) fn plant_intervals(
    drive: Drive,
    known: KnownParameter,
    theta: [f64; 3],
    cov: &Matrix3<f64>,
    degrees_of_freedom: usize,
) -> PlantIntervals {
    let t = t_975(degrees_of_freedom);
    let covariance = |a: [f64; 3], b: [f64; 3]| {
        let (a, b) = (nalgebra::Vector3::from(a), nalgebra::Vector3::from(b));
        (a.transpose() * cov * b)[(0, 0)]
    };
    let interval = |value: f64, e: [f64; 3]| {
        let var = covariance(e, e).max(0.0);
        Interval::new(value, value.abs() * var.sqrt(), t)
    };
    let [m, c, k] = theta;
    let wn = (k / m).sqrt();
    let physical = match (drive.estimates_mass(), known) {
        (true, _) => Some([
            (m, [1.0, 0.0, 0.0]),
            (c, [0.0, 1.0, 0.0]),
            (k, [0.0, 0.0, 1.0]),
        ]),
        (false, KnownParameter::Mass(mass)) => Some([
            (mass, [0.0; 3]),
            (mass * c, [0.0, 1.0, 0.0]),
            (mass * k, [0.0, 0.0, 1.0]),
        ]),
        (false, KnownParameter::Stiffness(stiffness)) => Some([
            (stiffness / k, [0.0, 0.0, -1.0]),
            (stiffness * c / k, [0.0, 1.0, -1.0]),
            (stiffness, [0.0; 3]),
        ]),
        (false, KnownParameter::None) => None,
    };
    let mut identifiable = vec!["natural_frequency_hz", "damping_ratio"];
    // ln q = eᵀ ln θ + const for each identifiable quantity, in order.
    let mut exponents = vec![[-0.5, 0.0, 0.5], [-0.5, 1.0, -0.5]];
    if let Some(q) = physical {
        identifiable.extend(["mass", "damping", "stiffness"]);
        exponents.extend(q.map(|(_, e)| e));
    }
    let pick = |i: usize| physical.map(|q| interval(q[i].0, q[i].1));
    PlantIntervals {
        identifiable,
        mass: pick(0),
        damping: pick(1),
        stiffness: pick(2),
        natural_frequency_hz: interval(wn / (2.0 * PI), [-0.5, 0.0, 0.5]),
        damping_ratio: interval(c / (2.0 * (k * m).sqrt()), [-0.5, 1.0, -0.5]),
        correlation: correlation(&exponents, covariance),
        degrees_of_freedom,
        note: physical.is_none().then(|| {
            format!(
                "m, c and k are not separately identifiable from a {} (every plant with the same c/m and k/m moves the same way): give the weighed mass or the static stiffness (`known`) to get them; ωn and ζ are identified",
                drive.setup()
            )
        }),
    }
}

/// The correlation of the quantities ln q = eᵀ ln θ (zero for a quantity without
/// variance) from `covariance(a, b)` = aᵀ·Cov(ln θ)·b.
fn correlation(
    exponents: &[[f64; 3]],
    covariance: impl Fn([f64; 3], [f64; 3]) -> f64,
) -> Vec<Vec<f64>> {
    let sd: Vec<f64> = exponents
        .iter()
        .map(|&e| covariance(e, e).max(0.0).sqrt())
        .collect();
    exponents
        .iter()
        .zip(&sd)
        .map(|(&a, &sa)| {
            exponents
                .iter()
                .zip(&sd)
                .map(|(&b, &sb)| {
                    let s = sa * sb;
                    if s > 0.0 {
                        (covariance(a, b) / s).clamp(-1.0, 1.0)
                    } else {
                        0.0
                    }
                })
                .collect()
        })
        .collect()
}
