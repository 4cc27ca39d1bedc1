//! What one test condition shows without a model: its loop, dissipated energy,
//! equivalent viscous damping, storage stiffness and loss factor.

use super::harmonics::HarmonicFit;
use serde::Serialize;
use std::f64::consts::PI;

/// One test condition, model-free: from the harmonic content of its stroke x and force F
/// over whole cycles.
///
/// With x = Σₕ (aₕ·cos hωt + bₕ·sin hωt) and F = Σₕ (pₕ·cos hωt + qₕ·sin hωt):
/// - the energy dissipated per cycle E = ∮F dx = π·Σₕ h·(pₕ·bₕ − qₕ·aₕ) (the
///   harmonics are orthogonal over a cycle, so this is exact for any F when the stroke
///   has no harmonic beyond H);
/// - the complex stiffness of the fundamental K* = F₁/x₁ = k′ + i·k″ with
///   k′ = (p₁a₁ + q₁b₁)/X² (storage) and k″ = (p₁b₁ − q₁a₁)/X² (loss), X = √(a₁² + b₁²);
/// - the equivalent viscous damping c_eq = E/(π·ω·X²) and the loss factor η = k″/k′.
///
/// For the linear plant F = m·x″ + c·x′ + k·x: k′ = k − m·ω², k″ = c·ω, c_eq = c and
/// E = π·c·ω·X²; for a quadratic damper F = c₂·x′|x′|, E = (8/3)·c₂·ω²·X³.
///
/// Displays as one row of the conditions table (see [`Dynamometer`](super::Dynamometer)).
///
/// ```
/// use msd_ident::{dynamometer::{dynamometer, DynamometerOptions, Stroke, synthetic_dynamometer, SyntheticDynamometer}, nonlinear::{DampingLaw, ModelStructure, NonlinearParameters}, Parameters};
/// // A linear plant, noise-free: c_eq = c and k′ = k − m·ω².
/// let (m, c, k) = (2.0, 400.0, 5000.0);
/// let plant = NonlinearParameters::from_linear(ModelStructure::LINEAR, &Parameters::new(m, c, k)?);
/// let strokes = vec![Stroke { frequency_hz: 2.0, amplitude: 0.02 }, Stroke { frequency_hz: 5.0, amplitude: 0.02 }];
/// let spec = SyntheticDynamometer { plant, strokes, force_noise: 0.0, displacement_noise: 0.0,
///     ..SyntheticDynamometer::default() };
/// let result = dynamometer(&synthetic_dynamometer(&spec)?, &DynamometerOptions::default())?;
/// let s = &result.conditions[1];
/// let w = 2.0 * std::f64::consts::PI * 5.0;
/// assert!((s.equivalent_damping / c - 1.0).abs() < 1e-9);
/// assert!((s.storage_stiffness / (k - m * w * w) - 1.0).abs() < 1e-9);
/// assert!((s.energy_per_cycle / (std::f64::consts::PI * c * w * 0.02 * 0.02) - 1.0).abs() < 1e-9);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConditionSummary {
    /// The condition's name.
    pub name: String,
    /// The stroke frequency f, Hz.
    pub frequency_hz: f64,
    /// Whether f was estimated from the stroke (not given).
    pub frequency_estimated: bool,
    /// Whole cycles analysed.
    pub cycles: usize,
    /// Samples analysed (the whole cycles from the start).
    pub samples: usize,
    /// Stroke amplitude X of the fundamental, m.
    pub amplitude: f64,
    /// Mean stroke, m.
    pub stroke_offset: f64,
    /// Energy dissipated per cycle E = ∮F dx, J.
    pub energy_per_cycle: f64,
    /// Equivalent viscous damping c_eq = E/(π·ω·X²), N·s/m.
    pub equivalent_damping: f64,
    /// Storage stiffness k′, N/m.
    pub storage_stiffness: f64,
    /// Loss stiffness k″, N/m.
    pub loss_stiffness: f64,
    /// Loss factor η = k″/k′.
    pub loss_factor: f64,
    /// Largest measured |F|, N (noise included).
    pub peak_force: f64,
    /// Largest |x̂′| of the harmonic fit, m/s.
    pub peak_velocity: f64,
    /// σ̂ of the measured stroke about its harmonic fit, m: the displacement noise that
    /// the coefficients' intervals account for.
    pub stroke_noise: f64,
    /// The measured stroke over the analysed samples, m (for the F–x loop).
    #[serde(skip)]
    pub displacement: Vec<f64>,
    /// The velocity x̂′ from the harmonic fit, m/s (for the F–v curve).
    #[serde(skip)]
    pub velocity: Vec<f64>,
    /// The measured force over the analysed samples, N.
    #[serde(skip)]
    pub force: Vec<f64>,
}

impl ConditionSummary {
    /// The summary of a fit over `samples` of `x` and `force` with `cycles` whole cycles.
    pub(crate) fn new(
        name: &str,
        fit: &HarmonicFit,
        (cycles, frequency_estimated): (usize, bool),
        x: &[f64],
        force: &[f64],
    ) -> Self {
        let harmonics = (fit.stroke.len() - 1) / 2;
        let energy: f64 = (1..=harmonics)
            .map(|h| {
                let ([a, b], [p, q]) = fit.harmonic(h);
                PI * h as f64 * (p * b - q * a)
            })
            .sum();
        let ([a, b], [p, q]) = fit.harmonic(1);
        let x2 = a * a + b * b;
        let (storage, loss) = ((p * a + q * b) / x2, (p * b - q * a) / x2);
        let peak = |v: &[f64]| v.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        Self {
            name: name.to_string(),
            frequency_hz: fit.omega / (2.0 * PI),
            frequency_estimated,
            cycles,
            samples: x.len(),
            amplitude: x2.sqrt(),
            stroke_offset: fit.stroke[0],
            energy_per_cycle: energy,
            equivalent_damping: energy / (PI * fit.omega * x2),
            storage_stiffness: storage,
            loss_stiffness: loss,
            loss_factor: loss / storage,
            peak_force: peak(force),
            peak_velocity: peak(&fit.velocity),
            stroke_noise: fit.stroke_sigma,
            displacement: x.to_vec(),
            velocity: fit.velocity.clone(),
            force: force.to_vec(),
        }
    }
}

impl std::fmt::Display for ConditionSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "| {} | {:.4}{} | {:.3} | {:.4e} | {:.4e} | {:.4e} | {:.4} | {:.4e} | {:.4} |",
            self.name,
            self.frequency_hz,
            if self.frequency_estimated { "*" } else { "" },
            1e3 * self.amplitude,
            self.energy_per_cycle,
            self.equivalent_damping,
            self.storage_stiffness,
            self.loss_factor,
            self.peak_force,
            self.peak_velocity,
        )
    }
}
