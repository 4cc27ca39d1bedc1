//! Free decay: the mass released from an initial displacement and/or velocity rings down
//! with no input. The response (displacement, velocity or acceleration) is a damped
//! sinusoid around the sensor's offset,
//!
//! y(t) = e^(−ζ·ωn·t)·(A·cos ωd·t + B·sin ωd·t) + offset,  ωd = ωn·√(1 − ζ²),
//!
//! so a free decay identifies ωn and ζ (with the initial state and the offset), never m,
//! c and k apart: scaling all three leaves the record unchanged. A known mass gives
//! k = m·ωn² and c = 2·ζ·ωn·m; a known static stiffness gives m = k/ωn² and c = 2·ζ·k/ωn.
//!
//! [`free_decay`] fits the closed form by Levenberg–Marquardt with its exact Jacobian,
//! started from the classroom estimates ([`ClassroomEstimates`]: the logarithmic
//! decrement of successive peaks and the damped frequency from zero crossings), and
//! gives 95 % intervals from the Gauss–Newton covariance (Student's t, the delta method
//! for derived quantities).

mod classroom;

pub use classroom::ClassroomEstimates;

use crate::params::KnownParameter;
use crate::uncertainty::t_975;
use crate::{
    error::{IdentError, Result},
    metrics::FitMetrics,
};
use msd_opt::statistics::Interval;
use msd_opt::statistics::{Linearization, delta_variance};
use msd_opt::{LeastSquaresProblem, LevenbergMarquardtOptions, levenberg_marquardt};
use msd_signal::ResponseQuantity;
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Options of [`free_decay`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FreeDecayOptions {
    /// What the sensor measures. By default displacement.
    pub response: ResponseQuantity,
    /// A known mass or stiffness. By default none.
    pub known: KnownParameter,
}

impl Default for FreeDecayOptions {
    fn default() -> Self {
        Self {
            response: ResponseQuantity::Displacement,
            known: KnownParameter::None,
        }
    }
}

/// m, c and k of a free decay with a known mass or stiffness (the known one with a zero
/// standard error).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PhysicalParameters {
    /// m, kg.
    pub mass: Interval,
    /// c, N·s/m.
    pub damping: Interval,
    /// k, N/m.
    pub stiffness: Interval,
}

/// The identified free decay.
///
/// ```
/// use msd_ident::{free_decay::{free_decay, FreeDecayOptions}, KnownParameter};
/// // m = 6 kg, k = 5400 N/m, successive peaks in ratio 3 : 2.
/// let (m, k) = (6.0, 5400.0);
/// let delta = 1.5f64.ln();
/// let zeta = delta / (4.0 * std::f64::consts::PI.powi(2) + delta * delta).sqrt();
/// let wn = (k / m as f64).sqrt();
/// let wd = wn * (1.0 - zeta * zeta).sqrt();
/// let dt = 1e-3;
/// let y: Vec<f64> = (0..2000)
///     .map(|i| { let t = i as f64 * dt; 0.01 * (-zeta * wn * t).exp() * (wd * t).cos() })
///     .collect();
/// let options = FreeDecayOptions { known: KnownParameter::Mass(m), ..Default::default() };
/// let fit = free_decay(dt, &y, &options)?;
/// // The textbook's δ = 0.4055, ζ = 0.0644, c = 23.18 N·s/m, to 4 significant digits.
/// assert!((fit.damping_ratio.value - 0.0644).abs() < 5e-5, "{fit}");
/// assert!((fit.classroom.log_decrement - 0.4055).abs() < 5e-5, "{fit}");
/// assert!((fit.classroom.damping_ratio - 0.0644).abs() < 5e-5, "{fit}");
/// let c = fit.parameters.unwrap().damping.value;
/// assert!((c - 23.18).abs() < 0.005, "{c}");
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FreeDecay {
    /// What the sensor measured.
    pub response: ResponseQuantity,
    /// The quantities this record identifies, by name.
    pub identifiable: Vec<&'static str>,
    /// fn = ωn/2π, Hz.
    pub natural_frequency_hz: Interval,
    /// ζ.
    pub damping_ratio: Interval,
    /// fd = ωd/2π, Hz.
    pub damped_frequency_hz: Interval,
    /// Displacement at the first sample, relative to equilibrium, in the unit of
    /// displacement that matches the response's (m for a sensor in m, m/s or m/s²).
    pub initial_displacement: Interval,
    /// Velocity at the first sample.
    pub initial_velocity: Interval,
    /// The sensor's offset (the equilibrium reading), in the response's unit.
    pub offset: Interval,
    /// m, c, k when the mass or the stiffness is known.
    pub parameters: Option<PhysicalParameters>,
    /// The classroom estimates, for comparison.
    pub classroom: ClassroomEstimates,
    /// The fit.
    pub fit: FitMetrics,
    /// σ̂, the residuals' standard deviation.
    pub sigma: f64,
    /// Levenberg–Marquardt iterations.
    pub iterations: usize,
    /// The model's response at every sample.
    #[serde(skip)]
    pub model: Vec<f64>,
    /// Why m, c and k are not given, when they are not.
    pub note: Option<String>,
}

impl std::fmt::Display for FreeDecay {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "free decay ({:?} sensor)", self.response)?;
        writeln!(f, "  fn = {:.6} Hz", self.natural_frequency_hz)?;
        writeln!(f, "  ζ  = {:.6}", self.damping_ratio)?;
        if let Some(p) = &self.parameters {
            writeln!(f, "  m  = {:.6} kg", p.mass)?;
            writeln!(f, "  c  = {:.6} N·s/m", p.damping)?;
            writeln!(f, "  k  = {:.6} N/m", p.stiffness)?;
        }
        writeln!(f, "  {}", self.classroom)?;
        write!(f, "  {}", self.fit)?;
        if let Some(note) = &self.note {
            write!(f, "\n  note: {note}")?;
        }
        Ok(())
    }
}

/// Identifies ωn, ζ, the initial state and the offset of the free decay `response`
/// sampled every `dt` seconds (and m, c, k when `options.known` gives a mass or a
/// stiffness).
///
/// Refused with a message saying why: fewer than 20 samples, a non-finite sample, a
/// constant record, or a record that does not ring down (fewer than two oscillations
/// above the noise, or no decay: ζ ≤ 0 or ζ ≥ 1).
pub fn free_decay(dt: f64, response: &[f64], options: &FreeDecayOptions) -> Result<FreeDecay> {
    check_input(dt, response, options)?;
    let classroom = ClassroomEstimates::from_record(dt, response)?;
    let start = linear_start(dt, response, &classroom);
    let mut problem = DampedSinusoid { dt, y: response };
    let lm = levenberg_marquardt(&mut problem, &start, &LevenbergMarquardtOptions::default())?;
    let [ln_wn, zeta, a, b, offset] = [lm.x[0], lm.x[1], lm.x[2], lm.x[3], lm.x[4]];
    if !(zeta > 0.0 && zeta < 0.999) {
        return Err(not_a_decay(format!("the fit gives ζ = {zeta:.4}")));
    }
    let wn = ln_wn.exp();
    let n = response.len();
    let dof = n - 5;
    let sigma = (lm.cost / dof as f64).sqrt();
    // Covariance in (ωn, ζ, A, B, offset): the residual Jacobian's ln ωn column / ωn.
    let mut j = lm.jacobian.clone();
    j.column_mut(0).scale_mut(1.0 / wn);
    let names = [
        "natural_frequency",
        "damping_ratio",
        "cosine",
        "sine",
        "offset",
    ];
    let cov = Linearization::new(&j)
        .map_err(|e| not_a_decay(e.reason("the record", &names)))?
        .covariance(sigma * sigma);
    let t = t_975(dof);
    let interval = |value: f64, grad: [f64; 5]| {
        Interval::from_variance(value, delta_variance(&grad, |r, c| cov[(r, c)]), t)
    };
    let root = (1.0 - zeta * zeta).sqrt();
    let state = initial_state(options.response, wn, zeta, a, b);
    let state_grad =
        |which: usize| numeric_state_gradient(options.response, [wn, zeta, a, b], which);
    let model: Vec<f64> = response
        .iter()
        .zip(&lm.residuals)
        .map(|(y, r)| y - r)
        .collect();
    let (parameters, note) = physical(options.known, wn, zeta, &interval);
    Ok(FreeDecay {
        response: options.response,
        identifiable: identifiable(options.known),
        natural_frequency_hz: interval(wn / (2.0 * PI), [1.0 / (2.0 * PI), 0.0, 0.0, 0.0, 0.0]),
        damping_ratio: interval(zeta, [0.0, 1.0, 0.0, 0.0, 0.0]),
        damped_frequency_hz: interval(
            wn * root / (2.0 * PI),
            [
                root / (2.0 * PI),
                -wn * zeta / root / (2.0 * PI),
                0.0,
                0.0,
                0.0,
            ],
        ),
        initial_displacement: interval(state[0], state_grad(0)),
        initial_velocity: interval(state[1], state_grad(1)),
        offset: interval(offset, [0.0, 0.0, 0.0, 0.0, 1.0]),
        parameters,
        classroom,
        fit: FitMetrics::new(response, &model),
        sigma,
        iterations: lm.iterations,
        model,
        note,
    })
}

fn not_a_decay(why: String) -> IdentError {
    IdentError::NotIdentifiable {
        reason: format!("the record is not a free decay that rings down: {why}"),
    }
}

fn check_input(dt: f64, response: &[f64], options: &FreeDecayOptions) -> Result<()> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(IdentError::InvalidParameter {
            name: "dt",
            value: dt,
            expected: "a finite sampling interval > 0 s",
        });
    }
    if response.len() < 20 {
        return Err(IdentError::TooFewSamples {
            got: response.len(),
            needed: 20,
            why: "a free decay needs at least two oscillations sampled",
        });
    }
    if let Some((index, &value)) = response.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(IdentError::NonFiniteSample {
            field: "response",
            index,
            value,
        });
    }
    options.known.validate()
}

fn identifiable(known: KnownParameter) -> Vec<&'static str> {
    let mut names = vec!["natural_frequency_hz", "damping_ratio"];
    if known != KnownParameter::None {
        names.extend(["mass", "damping", "stiffness"]);
    }
    names
}

/// m, c, k from ωn, ζ and the known one, with their delta-method intervals.
fn physical(
    known: KnownParameter,
    wn: f64,
    zeta: f64,
    interval: &impl Fn(f64, [f64; 5]) -> Interval,
) -> (Option<PhysicalParameters>, Option<String>) {
    let exact = |v: f64| Interval::new(v, 0.0, 0.0);
    match known {
        KnownParameter::None => (
            None,
            Some(
                "m, c and k are not separately identifiable from a free decay (scaling all \
                 three leaves the record unchanged): give the mass or the static stiffness \
                 to get them; ωn and ζ are identified"
                    .into(),
            ),
        ),
        KnownParameter::Mass(m) => (
            Some(PhysicalParameters {
                mass: exact(m),
                damping: interval(
                    2.0 * zeta * wn * m,
                    [2.0 * zeta * m, 2.0 * wn * m, 0.0, 0.0, 0.0],
                ),
                stiffness: interval(m * wn * wn, [2.0 * m * wn, 0.0, 0.0, 0.0, 0.0]),
            }),
            None,
        ),
        KnownParameter::Stiffness(k) => (
            Some(PhysicalParameters {
                mass: interval(k / (wn * wn), [-2.0 * k / wn.powi(3), 0.0, 0.0, 0.0, 0.0]),
                damping: interval(
                    2.0 * zeta * k / wn,
                    [-2.0 * zeta * k / (wn * wn), 2.0 * k / wn, 0.0, 0.0, 0.0],
                ),
                stiffness: exact(k),
            }),
            None,
        ),
    }
}

/// (x(0), x′(0)) from the fitted (ωn, ζ, A, B) of a `response` sensor: the response and
/// its slope at t = 0 are A and ωd·B − σ·A; the equation of motion x″ = −ωn²·x − 2σ·x′
/// turns them into the state.
fn initial_state(response: ResponseQuantity, wn: f64, zeta: f64, a: f64, b: f64) -> [f64; 2] {
    let sigma = zeta * wn;
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let (y0, dy0) = (a, wd * b - sigma * a);
    let w2 = wn * wn;
    match response {
        ResponseQuantity::Displacement => [y0, dy0],
        ResponseQuantity::Velocity => [(-dy0 - 2.0 * sigma * y0) / w2, y0],
        ResponseQuantity::Acceleration => {
            let v0 = (-dy0 - 2.0 * sigma * y0) / w2;
            [(-y0 - 2.0 * sigma * v0) / w2, v0]
        }
    }
}

/// ∂(initial state component `which`)/∂(ωn, ζ, A, B, offset) by central differences.
fn numeric_state_gradient(response: ResponseQuantity, p: [f64; 4], which: usize) -> [f64; 5] {
    let mut grad = [0.0; 5];
    for (i, g) in grad.iter_mut().take(4).enumerate() {
        let h = 1e-6 * p[i].abs().max(1e-8);
        let (mut up, mut down) = (p, p);
        up[i] += h;
        down[i] -= h;
        let f = |q: [f64; 4]| initial_state(response, q[0], q[1], q[2], q[3])[which];
        *g = (f(up) - f(down)) / (2.0 * h);
    }
    grad
}

/// The start: ωn and ζ from the classroom estimates, A, B and the offset by linear
/// least squares given them.
fn linear_start(dt: f64, y: &[f64], c: &ClassroomEstimates) -> Vec<f64> {
    let zeta = c.damping_ratio.clamp(1e-4, 0.9);
    let wn = 2.0 * PI * c.damped_frequency_hz / (1.0 - zeta * zeta).sqrt();
    let (sigma, wd) = (zeta * wn, wn * (1.0 - zeta * zeta).sqrt());
    let basis = DMatrix::from_fn(y.len(), 3, |i, col| {
        let t = i as f64 * dt;
        let e = (-sigma * t).exp();
        match col {
            0 => e * (wd * t).cos(),
            1 => e * (wd * t).sin(),
            _ => 1.0,
        }
    });
    let coef = basis
        .clone()
        .svd(true, true)
        .solve(&DVector::from_row_slice(y), 1e-12)
        .unwrap_or_else(|_| DVector::zeros(3));
    vec![wn.ln(), zeta, coef[0], coef[1], coef[2]]
}

/// The residual problem in x = (ln ωn, ζ, A, B, offset).
struct DampedSinusoid<'a> {
    dt: f64,
    y: &'a [f64],
}

impl DampedSinusoid<'_> {
    /// (σ, ωd) of x, if ζ ∈ (0, 1).
    fn rates(x: &[f64]) -> Option<(f64, f64, f64)> {
        let (wn, zeta) = (x[0].exp(), x[1]);
        (zeta > 0.0 && zeta < 1.0 && wn.is_finite())
            .then(|| (zeta * wn, wn * (1.0 - zeta * zeta).sqrt(), wn))
    }
}

impl LeastSquaresProblem for DampedSinusoid<'_> {
    fn residual_count(&self) -> usize {
        self.y.len()
    }

    fn residuals(&mut self, x: &[f64], out: &mut [f64]) -> bool {
        let Some((sigma, wd, _)) = Self::rates(x) else {
            return false;
        };
        for (i, (r, y)) in out.iter_mut().zip(self.y).enumerate() {
            let t = i as f64 * self.dt;
            let e = (-sigma * t).exp();
            *r = y - (e * (x[2] * (wd * t).cos() + x[3] * (wd * t).sin()) + x[4]);
        }
        out.iter().all(|r| r.is_finite())
    }

    fn jacobian(&mut self, x: &[f64], out: &mut DMatrix<f64>) -> bool {
        let Some((sigma, wd, wn)) = Self::rates(x) else {
            return false;
        };
        let zeta = x[1];
        let root = (1.0 - zeta * zeta).sqrt();
        let (a, b) = (x[2], x[3]);
        for i in 0..self.y.len() {
            let t = i as f64 * self.dt;
            let e = (-sigma * t).exp();
            let (c, s) = ((wd * t).cos(), (wd * t).sin());
            let d_sigma = -t * e * (a * c + b * s);
            let d_wd = t * e * (-a * s + b * c);
            // ∂/∂ln ωn: σ and ωd scale with ωn; ∂/∂ζ: ∂σ/∂ζ = ωn, ∂ωd/∂ζ = −ωn·ζ/√(1−ζ²).
            out[(i, 0)] = -(d_sigma * sigma + d_wd * wd);
            out[(i, 1)] = -(d_sigma * wn - d_wd * wn * zeta / root);
            out[(i, 2)] = -e * c;
            out[(i, 3)] = -e * s;
            out[(i, 4)] = -1.0;
        }
        out.iter().all(|v| v.is_finite())
    }
}
