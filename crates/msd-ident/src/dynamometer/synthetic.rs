//! Synthetic test-machine records with known truth, for tests, configs and teaching.

use super::Condition;
use crate::{
    error::{IdentError, Result},
    nonlinear::{DampingLaw, ModelStructure, NonlinearParameters, StiffnessLaw},
};
use msd_signal::gaussian_noise;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// One imposed sine stroke x = X·sin(2π·f·t).
///
/// ```
/// use msd_ident::dynamometer::Stroke;
/// let s = Stroke { frequency_hz: 8.0, amplitude: 0.025 };
/// let peak_velocity = 2.0 * std::f64::consts::PI * s.frequency_hz * s.amplitude;
/// assert!((peak_velocity - 1.2566).abs() < 1e-4);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Stroke {
    /// f, Hz.
    pub frequency_hz: f64,
    /// X, m.
    pub amplitude: f64,
}

/// What [`synthetic_dynamometer`] generates.
///
/// By default a damper of m = 2 kg, c = 400 N·s/m, k = 5000 N/m, c₂ = 600 N·s²/m²
/// (quadratic law) stroked at 1, 2, 3, 5 and 8 Hz with 10 and 25 mm (peak velocities
/// 0.06 to 1.26 m/s, a damper test's usual range), 4 cycles each sampled at 2 kHz, no
/// force offset, force noise 5 N (a 10 kN load cell's 0.05 %), stroke noise 20 µm (an
/// LVDT's), seed 1.
///
/// ```
/// use msd_ident::{dynamometer::SyntheticDynamometer, nonlinear::DampingLaw};
/// let spec = SyntheticDynamometer::default();
/// assert_eq!(spec.plant.structure.damping, DampingLaw::QuadraticViscous);
/// assert_eq!((spec.strokes.len(), spec.cycles, spec.dt), (10, 4, 5e-4));
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SyntheticDynamometer {
    /// The plant: m, c, k and the damping law's coefficient (linear stiffness only).
    /// A Coulomb law's truth is F_c·sign(x′), unsmoothed.
    pub plant: NonlinearParameters,
    /// The test conditions.
    pub strokes: Vec<Stroke>,
    /// Whole cycles per condition.
    pub cycles: usize,
    /// Sampling interval, s.
    pub dt: f64,
    /// The load cell's offset F₀, N.
    pub force_offset: f64,
    /// σ of the white force noise, N.
    pub force_noise: f64,
    /// σ of the white stroke noise, m.
    pub displacement_noise: f64,
    /// Noise seed; condition i draws streams `dynamometer force i` and
    /// `dynamometer displacement i`.
    pub seed: u64,
}

impl Default for SyntheticDynamometer {
    fn default() -> Self {
        let quadratic = ModelStructure {
            damping: DampingLaw::QuadraticViscous,
            stiffness: StiffnessLaw::Linear,
        };
        let strokes = [1.0, 2.0, 3.0, 5.0, 8.0]
            .iter()
            .flat_map(|&f| {
                [0.01, 0.025].map(|x| Stroke {
                    frequency_hz: f,
                    amplitude: x,
                })
            })
            .collect();
        Self {
            plant: NonlinearParameters {
                structure: quadratic,
                values: vec![2.0, 400.0, 5000.0, 600.0],
            },
            strokes,
            cycles: 4,
            dt: 5e-4,
            force_offset: 0.0,
            force_noise: 5.0,
            displacement_noise: 2e-5,
            seed: 1,
        }
    }
}

/// The conditions of `spec`: exact sine strokes, the force of the plant's law
/// F = m·x″ + f_d(x′) + k·x + F₀ from the analytic x′ and x″, white noise added to both
/// channels; deterministic from the seed. Each condition holds round(cycles/(f·dt))
/// samples and is named like `2 Hz, 25 mm`.
///
/// ```
/// use msd_ident::{dynamometer::{synthetic_dynamometer, SyntheticDynamometer}};
/// let conditions = synthetic_dynamometer(&SyntheticDynamometer::default())?;
/// assert_eq!(conditions.len(), 10);
/// assert_eq!(conditions[0].name(), "1 Hz, 10 mm");
/// assert_eq!(conditions[0].displacement().len(), 8000); // 4 cycles of 1 Hz at 2 kHz
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn synthetic_dynamometer(spec: &SyntheticDynamometer) -> Result<Vec<Condition>> {
    spec.plant.validate()?;
    if spec.plant.structure.stiffness != StiffnessLaw::Linear {
        return Err(IdentError::InvalidParameter {
            name: "plant cubic_stiffness",
            value: spec.plant.cubic_stiffness(),
            expected: "a linear spring (the test machine's laws have no k₃)",
        });
    }
    if !(spec.dt.is_finite() && spec.dt > 0.0) {
        return Err(IdentError::InvalidParameter {
            name: "dt",
            value: spec.dt,
            expected: "a finite number > 0 s",
        });
    }
    spec.strokes
        .iter()
        .enumerate()
        .map(|(i, stroke)| condition(spec, i, stroke))
        .collect()
}

/// Condition `i` of `spec`.
fn condition(spec: &SyntheticDynamometer, i: usize, stroke: &Stroke) -> Result<Condition> {
    let Stroke {
        frequency_hz: f,
        amplitude,
    } = *stroke;
    if !(f.is_finite() && f > 0.0 && amplitude.is_finite() && amplitude > 0.0) {
        return Err(IdentError::InvalidParameter {
            name: "stroke frequency_hz × amplitude",
            value: f * amplitude,
            expected: "a finite frequency > 0 Hz and amplitude > 0 m",
        });
    }
    let n = (spec.cycles as f64 / (f * spec.dt)).round() as usize;
    let p = &spec.plant;
    let w = 2.0 * PI * f;
    let mut force = gaussian_noise(
        spec.seed,
        &format!("dynamometer force {i}"),
        spec.force_noise,
        n,
    )?;
    let mut displacement = gaussian_noise(
        spec.seed,
        &format!("dynamometer displacement {i}"),
        spec.displacement_noise,
        n,
    )?;
    for (j, (x, fo)) in displacement.iter_mut().zip(&mut force).enumerate() {
        let (s, c) = (w * j as f64 * spec.dt).sin_cos();
        let (xt, v, a) = (amplitude * s, amplitude * w * c, -amplitude * w * w * s);
        let law = p.damping() * v
            + p.quadratic_damping() * v * v.abs()
            + p.coulomb_force() * if v == 0.0 { 0.0 } else { v.signum() };
        *fo += p.mass() * a + law + p.stiffness() * xt + spec.force_offset;
        *x += xt;
    }
    let name = format!("{f} Hz, {} mm", amplitude * 1e3);
    Ok(Condition::new(name, spec.dt, displacement, force).at_frequency(f))
}
