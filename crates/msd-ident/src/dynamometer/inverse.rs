//! A test machine under any stroke: inverse dynamic identification (IDIM-LS, as the EMPS
//! benchmark's reference model is made). The stroke x and the force F are low-pass
//! filtered alike, forward and backward (a 4th-order Butterworth: no phase shift, and
//! the same filter on both sides of F = m·x″ + f_d(x′) + k·x + F₀, so that the filter
//! changes no coefficient); x′ and x″ by central differences; each damping law's
//! coefficients by least squares over every record.
//!
//! The residual of such a fit is coloured (the filter, and whatever the model leaves
//! out along the stroke), so the ordinary least-squares standard errors would be far too
//! small. The covariance is the sandwich over contiguous blocks of samples (batch means:
//! each block's score Σ φᵢ·eᵢ an independent draw when the residual decorrelates within
//! a block), with Student's t on blocks − 1 degrees of freedom.

use super::recording::stroke_and_force;
use crate::error::{IdentError, Result};
use crate::law::{DampingLaw, smoothed_sign};
use crate::nonlinear::bic_evidence;
use crate::residuals::sandwich::block_sandwich;
use msd_opt::statistics::{Interval, t_975};
use msd_signal::Recording;
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

/// Options of [`inverse_dynamics`].
///
/// ```
/// let o = msd_ident::dynamometer::InverseOptions::default();
/// assert_eq!((o.laws.len(), o.stiffness, o.force_offset, o.blocks), (3, false, true, 20));
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct InverseOptions {
    /// The damping laws compared. By default all three.
    pub laws: Vec<DampingLaw>,
    /// The low-pass cut-off, Hz. By default 10× the frequency below which 99 % of the
    /// stroke velocity's power lies (at most a quarter of the sampling rate): far above
    /// the motion, where filtering both sides alike changes no coefficient.
    pub cutoff_hz: Option<f64>,
    /// Whether a stiffness k (a spring, a gas preload that grows with x) is estimated.
    /// By default false.
    pub stiffness: bool,
    /// Whether a constant force F₀ (load-cell zero, gravity on an inclined axis) is
    /// estimated. By default true.
    pub force_offset: bool,
    /// The moving mass, kg, when known (weighed): then not estimated.
    pub known_mass: Option<f64>,
    /// Blocks of the covariance (at least 5). By default 20.
    pub blocks: usize,
}

impl Default for InverseOptions {
    fn default() -> Self {
        Self {
            laws: DampingLaw::ALL.to_vec(),
            cutoff_hz: None,
            stiffness: false,
            force_offset: true,
            known_mass: None,
            blocks: 20,
        }
    }
}

/// One coefficient: its name in results, its unit and its estimate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InverseCoefficient {
    /// `mass`, `damping`, `coulomb_force`, `quadratic_damping`, `stiffness`, `force_offset`.
    pub name: &'static str,
    /// Its unit.
    pub unit: &'static str,
    /// The estimate with its standard error and 95 % interval (blocks − 1 degrees of
    /// freedom).
    pub estimate: Interval,
}

/// One law's fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InverseLaw {
    /// The law.
    pub law: DampingLaw,
    /// Its coefficients (a known mass is not among them).
    pub coefficients: Vec<InverseCoefficient>,
    /// RMS of the residual force (filtered), N.
    pub rms_residual: f64,
    /// Share of the filtered force's variance the model explains.
    pub r2: f64,
    /// Bayesian information criterion n·ln(RSS/n) + p·ln n.
    pub bic: f64,
    /// BIC minus the lowest.
    pub delta_bic: f64,
    /// 1 for the lowest BIC.
    pub rank: usize,
}

impl InverseLaw {
    /// The coefficient `name`'s value (0 where the law has none; a known mass's value).
    pub fn value(&self, name: &str) -> Option<f64> {
        self.coefficients
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.estimate.value)
    }
}

/// The result of [`inverse_dynamics`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InverseDynamics {
    /// The low-pass cut-off used, Hz.
    pub cutoff_hz: f64,
    /// Samples fitted over all records (each record less two periods of the cut-off at
    /// each end, where the forward–backward filter meets it).
    pub samples: usize,
    /// Blocks of the covariance.
    pub blocks: usize,
    /// One fit per law, in the order asked.
    pub laws: Vec<InverseLaw>,
    /// Index in `laws` of the lowest BIC.
    pub best: usize,
    /// Which law the evidence supports and how strongly.
    pub verdict: String,
    /// A known mass, kg.
    pub known_mass: Option<f64>,
    /// Options that shape the regressors: stiffness, offset, the Coulomb term's
    /// smoothing velocity (m/s).
    pub stiffness: bool,
    /// Whether F₀ was estimated.
    pub force_offset: bool,
    /// The Coulomb term's smoothing velocity v_s, m/s: 10⁻³ × the RMS velocity.
    pub smoothing_velocity: f64,
}

/// A record's force as the model predicts it from its stroke.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ForcePrediction {
    /// The record's first sample compared (the ends, where the filter meets them, are
    /// left out: two periods of the cut-off).
    pub first: usize,
    /// The measured force, filtered as in the fit, N.
    pub measured: Vec<f64>,
    /// The model's force, N.
    pub predicted: Vec<f64>,
    /// RMS of measured − predicted, N.
    pub rms_error: f64,
    /// RMS of the measured force, N.
    pub rms_force: f64,
}

/// The filtered stroke's derivatives and the filtered force of one record.
struct Motion {
    dt: f64,
    cutoff_hz: f64,
    displacement: Vec<f64>,
    velocity: Vec<f64>,
    acceleration: Vec<f64>,
    force: Vec<f64>,
}

impl Motion {
    /// The samples kept at each end out of the fit and the prediction's error: two
    /// periods of the cut-off, where a forward–backward filter meets the record's ends
    /// (a force step near an end is reflected there, not smoothed as inside).
    fn edge(&self) -> usize {
        ((2.0 / (self.cutoff_hz * self.dt)).ceil() as usize).min(self.force.len() / 4)
    }

    /// The kept range of samples.
    fn kept(&self) -> std::ops::Range<usize> {
        self.edge()..self.force.len() - self.edge()
    }
}

fn motion(r: &Recording, cutoff_hz: f64) -> Result<Motion> {
    let (stroke, force) = stroke_and_force(r)?;
    let fs = 1.0 / r.dt;
    let filter = |x: &[f64]| msd_signal::lowpass_zero_phase(x, fs, cutoff_hz);
    let displacement = filter(stroke)?;
    let velocity = msd_signal::central_difference(&displacement, r.dt)?;
    let acceleration = msd_signal::central_difference(&velocity, r.dt)?;
    Ok(Motion {
        dt: r.dt,
        cutoff_hz,
        displacement,
        velocity,
        acceleration,
        force: filter(force)?,
    })
}

/// The default cut-off: 10× the frequency below which 99 % of the stroke velocity's
/// power lies, at most fs/4.
fn default_cutoff(records: &[Recording]) -> Result<f64> {
    let r = &records[0];
    let fs = 1.0 / r.dt;
    let v = msd_signal::central_difference(stroke_and_force(r)?.0, r.dt)?;
    let segment = v.len().min(4096);
    let options = msd_signal::WelchOptions {
        segment_length: Some(segment),
        ..Default::default()
    };
    let p = msd_signal::welch_psd(&v, fs, &options)?;
    let total: f64 = p.values.iter().sum();
    let mut sum = 0.0;
    let f99 = p
        .frequency
        .iter()
        .zip(&p.values)
        .find(|(_, q)| {
            sum += **q;
            sum >= 0.99 * total
        })
        .map_or(fs / 4.0, |(&f, _)| f);
    Ok((10.0_f64 * f99).clamp(fs / segment as f64, fs / 4.0))
}

/// Identifies m, the damping law's coefficients, k (if asked) and F₀ from `records` of
/// any stroke (see the module doc); every law of `options` is fitted and ranked by BIC.
///
/// ```
/// use msd_ident::dynamometer::{inverse_dynamics, machine_recording, InverseOptions};
/// // A smooth back-and-forth stroke, force of m = 20 kg, c = 150 N·s/m, F_c = 12 N, F₀ = −2 N.
/// let dt = 1e-3;
/// let x: Vec<f64> = (0..20_000).map(|i| { let t = i as f64 * dt; 0.1 * (1.3 * t).sin() + 0.03 * (4.1 * t).sin() }).collect();
/// let v: Vec<f64> = (0..20_000).map(|i| { let t = i as f64 * dt; 0.13 * (1.3 * t).cos() + 0.123 * (4.1 * t).cos() }).collect();
/// let a: Vec<f64> = (0..20_000).map(|i| { let t = i as f64 * dt; -0.169 * (1.3 * t).sin() - 0.5043 * (4.1 * t).sin() }).collect();
/// let force: Vec<f64> = (0..20_000).map(|i| 20.0 * a[i] + 150.0 * v[i] + 12.0 * v[i].signum() - 2.0).collect();
/// let record = machine_recording("run", dt, x, force);
/// let fit = inverse_dynamics(&[record], &InverseOptions::default())?;
/// let best = &fit.laws[fit.best];
/// assert_eq!(best.law, msd_ident::law::DampingLaw::CoulombViscous);
/// assert!((best.value("mass").unwrap() - 20.0).abs() < 0.2);
/// assert!((best.value("coulomb_force").unwrap() - 12.0).abs() < 0.2);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn inverse_dynamics(
    records: &[Recording],
    options: &InverseOptions,
) -> Result<InverseDynamics> {
    check(records, options)?;
    let cutoff = match options.cutoff_hz {
        Some(f) => f,
        None => default_cutoff(records)?,
    };
    let motions = records
        .iter()
        .map(|r| motion(r, cutoff))
        .collect::<Result<Vec<_>>>()?;
    let samples: usize = motions.iter().map(|m| m.kept().len()).sum();
    let rms_velocity = (motions
        .iter()
        .flat_map(|m| m.velocity.iter())
        .map(|v| v * v)
        .sum::<f64>()
        / samples as f64)
        .sqrt();
    let smoothing = 1e-3 * rms_velocity.max(f64::MIN_POSITIVE);
    let mut laws = options
        .laws
        .iter()
        .map(|&law| fit_law(&motions, law, options, smoothing))
        .collect::<Result<Vec<_>>>()?;
    let best = (0..laws.len())
        .min_by(|&a, &b| laws[a].bic.total_cmp(&laws[b].bic))
        .unwrap_or(0);
    let lowest = laws[best].bic;
    let mut order: Vec<usize> = (0..laws.len()).collect();
    order.sort_by(|&a, &b| laws[a].bic.total_cmp(&laws[b].bic));
    for (rank, &i) in order.iter().enumerate() {
        laws[i].rank = rank + 1;
        laws[i].delta_bic = laws[i].bic - lowest;
    }
    let verdict = match order.get(1) {
        Some(&second) => format!(
            "the {} law fits best; the evidence against the next ({}, ΔBIC {:.1}) is {}",
            laws[best].law.name(),
            laws[second].law.name(),
            laws[second].delta_bic,
            bic_evidence(laws[second].delta_bic)
        ),
        None => format!("the {} law (the only one fitted)", laws[best].law.name()),
    };
    Ok(InverseDynamics {
        cutoff_hz: cutoff,
        samples,
        blocks: options.blocks,
        laws,
        best,
        verdict,
        known_mass: options.known_mass,
        stiffness: options.stiffness,
        force_offset: options.force_offset,
        smoothing_velocity: smoothing,
    })
}

fn check(records: &[Recording], options: &InverseOptions) -> Result<()> {
    let invalid = |name, value: f64, expected| {
        Err(IdentError::InvalidParameter {
            name,
            value,
            expected,
        })
    };
    if records.is_empty() {
        return invalid("records", 0.0, "at least one record");
    }
    if options.laws.is_empty() {
        return invalid("laws", 0.0, "at least one damping law");
    }
    if options.blocks < 5 {
        return invalid("blocks", options.blocks as f64, "at least 5");
    }
    if let Some(m) = options.known_mass
        && !(m.is_finite() && m >= 0.0)
    {
        return invalid("known_mass", m, "a finite number ≥ 0 kg");
    }
    for r in records {
        let (stroke, force) = stroke_and_force(r)?;
        if !(r.dt.is_finite() && r.dt > 0.0) {
            return invalid("dt", r.dt, "a finite step > 0 s");
        }
        if stroke.len() != force.len() || stroke.len() < 20 * options.blocks {
            return invalid(
                "samples",
                stroke.len().min(force.len()) as f64,
                "a stroke and a force of one length, at least 20 samples per block",
            );
        }
        if let Some(i) = stroke.iter().chain(force).position(|v| !v.is_finite()) {
            return invalid("sample", i as f64, "finite strokes and forces");
        }
    }
    Ok(())
}

/// The regressor columns of `law` (and their names and units) at one sample.
fn columns(law: DampingLaw, options: &InverseOptions) -> Vec<(&'static str, &'static str)> {
    let mut c = Vec::new();
    if options.known_mass.is_none() {
        c.push(("mass", "kg"));
    }
    c.push(("damping", "N·s/m"));
    match law {
        DampingLaw::CoulombViscous => c.push(("coulomb_force", "N")),
        DampingLaw::QuadraticViscous => c.push(("quadratic_damping", "N·s²/m²")),
        DampingLaw::Viscous => {}
    }
    if options.stiffness {
        c.push(("stiffness", "N/m"));
    }
    if options.force_offset {
        c.push(("force_offset", "N"));
    }
    c
}

/// The regressor column `name` of one record. A nonlinear term (the Coulomb sign, the
/// quadratic v|v|) is computed from the filtered velocity and then filtered itself, as
/// the force is: otherwise the force's smoothed steps at each reversal would be fitted by
/// sharp ones, and every coefficient would take the difference.
fn column(name: &str, m: &Motion, inverse_smoothing: f64) -> Result<Vec<f64>> {
    let filtered = |term: &dyn Fn(f64) -> f64| {
        let raw: Vec<f64> = m.velocity.iter().map(|&v| term(v)).collect();
        msd_signal::lowpass_zero_phase(&raw, 1.0 / m.dt, m.cutoff_hz)
    };
    Ok(match name {
        "mass" => m.acceleration.clone(),
        "damping" => m.velocity.clone(),
        "coulomb_force" => filtered(&|v| smoothed_sign(v * inverse_smoothing))?,
        "quadratic_damping" => filtered(&|v| v * v.abs())?,
        "stiffness" => m.displacement.clone(),
        _ => vec![1.0; m.force.len()],
    })
}

/// One law by least squares (QR), with the block sandwich covariance.
fn fit_law(
    motions: &[Motion],
    law: DampingLaw,
    options: &InverseOptions,
    smoothing: f64,
) -> Result<InverseLaw> {
    let cols = columns(law, options);
    let (n, p) = (
        motions.iter().map(|m| m.kept().len()).sum::<usize>(),
        cols.len(),
    );
    let known = options.known_mass.unwrap_or(0.0);
    let mut phi = DMatrix::<f64>::zeros(n, p);
    let mut y = DVector::<f64>::zeros(n);
    let mut k = 0;
    for m in motions {
        let kept = m.kept();
        for (j, (name, _)) in cols.iter().enumerate() {
            let values = column(name, m, 1.0 / smoothing)?;
            for (i, v) in values[kept.clone()].iter().enumerate() {
                phi[(k + i, j)] = *v;
            }
        }
        for (i, s) in kept.clone().enumerate() {
            y[k + i] = m.force[s] - known * m.acceleration[s];
        }
        k += kept.len();
    }
    // Columns scaled to unit norm: the QR and the covariance stay well conditioned
    // whatever the units.
    let scale: Vec<f64> = (0..p)
        .map(|j| phi.column(j).norm().max(f64::MIN_POSITIVE))
        .collect();
    for (j, s) in scale.iter().enumerate() {
        phi.column_mut(j).scale_mut(1.0 / s);
    }
    // The scaled normal matrix: its inverse is the sandwich's bread, and a condition
    // number at msd-opt's limit means the data cannot separate the columns.
    let gram = phi.transpose() * &phi;
    let condition = {
        let e = gram.symmetric_eigenvalues();
        e.max() / e.min().max(f64::MIN_POSITIVE)
    };
    let h_inv = gram
        .try_inverse()
        .filter(|_| condition < msd_opt::statistics::SINGULAR_CONDITION)
        .ok_or_else(|| IdentError::NotIdentifiable {
            reason: format!(
                "the {} law's regressors are nearly linearly dependent (condition number {condition:.1e}): a stroke that does not move enough, or a column the data repeat",
                law.name()
            ),
        })?;
    let theta = &h_inv * (phi.transpose() * &y);
    let residual = &y - &phi * &theta;
    let rss = residual.norm_squared();
    let mean = y.mean();
    let tss: f64 = y.iter().map(|v| (v - mean).powi(2)).sum();
    let blocks = options.blocks;
    let cov = block_sandwich(&phi, &residual, &h_inv, blocks);
    let t = t_975(blocks - 1);
    let coefficients = cols
        .iter()
        .enumerate()
        .map(|(j, &(name, unit))| InverseCoefficient {
            name,
            unit,
            estimate: Interval::new(
                theta[j] / scale[j],
                cov[(j, j)].max(0.0).sqrt() / scale[j],
                t,
            ),
        })
        .collect();
    Ok(InverseLaw {
        law,
        coefficients,
        rms_residual: (rss / n as f64).sqrt(),
        r2: if tss > 0.0 { 1.0 - rss / tss } else { 0.0 },
        bic: n as f64 * (rss / n as f64).max(f64::MIN_POSITIVE).ln() + p as f64 * (n as f64).ln(),
        delta_bic: 0.0,
        rank: 0,
    })
}

impl InverseDynamics {
    /// The force law `law` (an index in `laws`) predicts for `record` from its stroke,
    /// beside its measured force filtered as in the fit: validation on a record the fit
    /// did not see.
    pub fn predict(&self, law: usize, record: &Recording) -> Result<ForcePrediction> {
        let l = self.laws.get(law).ok_or(IdentError::InvalidParameter {
            name: "law",
            value: law as f64,
            expected: "an index of the fitted laws",
        })?;
        let m = motion(record, self.cutoff_hz)?;
        let mass = self
            .known_mass
            .unwrap_or_else(|| l.value("mass").unwrap_or(0.0));
        let mut predicted: Vec<f64> = m.acceleration.iter().map(|a| mass * a).collect();
        for c in l.coefficients.iter().filter(|c| c.name != "mass") {
            let x = column(c.name, &m, 1.0 / self.smoothing_velocity)?;
            for (p, x) in predicted.iter_mut().zip(x) {
                *p += c.estimate.value * x;
            }
        }
        let kept = m.kept();
        let (measured, predicted) = (
            m.force[kept.clone()].to_vec(),
            predicted[kept.clone()].to_vec(),
        );
        let n = predicted.len() as f64;
        let rms_error = (measured
            .iter()
            .zip(&predicted)
            .map(|(f, p)| (f - p).powi(2))
            .sum::<f64>()
            / n)
            .sqrt();
        let rms_force = (measured.iter().map(|f| f * f).sum::<f64>() / n).sqrt();
        Ok(ForcePrediction {
            first: kept.start,
            measured,
            predicted,
            rms_error,
            rms_force,
        })
    }
}

impl std::fmt::Display for InverseDynamics {
    /// A Markdown table of the laws, ranked, with their coefficients, then the verdict.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "inverse dynamics of {} samples, stroke and force low-passed at {:.3} Hz (forward–backward), intervals from {} blocks",
            self.samples, self.cutoff_hz, self.blocks
        )?;
        writeln!(
            f,
            "| rank | law | coefficients (95 % interval) | RMS residual N | R² | ΔBIC |"
        )?;
        writeln!(f, "|---|---|---|---|---|---|")?;
        let mut order: Vec<&InverseLaw> = self.laws.iter().collect();
        order.sort_by_key(|l| l.rank);
        for l in order {
            let coefficients: Vec<String> = l
                .coefficients
                .iter()
                .map(|c| {
                    format!(
                        "{} = {:.6} {} [{:.6}, {:.6}]",
                        c.name, c.estimate.value, c.unit, c.estimate.ci95[0], c.estimate.ci95[1]
                    )
                })
                .collect();
            writeln!(
                f,
                "| {} | {} | {} | {:.4} | {:.5} | {:.1} |",
                l.rank,
                l.law.formula(),
                coefficients.join("; "),
                l.rms_residual,
                l.r2,
                l.delta_bic
            )?;
        }
        write!(f, "{}", self.verdict)
    }
}
