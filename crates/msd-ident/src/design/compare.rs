//! Two inputs side by side: their predicted standard errors of m, c and k on one plant,
//! and the ratios the design criteria are judged by.

use crate::{
    data::Excitation,
    error::Result,
    estimate::{EstimationOptions, predicted_uncertainty},
    params::Parameters,
    uncertainty::Uncertainty,
};
use serde::Serialize;

/// The predicted standard errors of m, c, k for a designed and a reference input, and
/// the design's over the reference's.
///
/// ```
/// use msd_ident::{Excitation, Parameters, design::InputComparison};
/// use msd_signal::{Signal, paper_identification_input};
/// let paper = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
/// let twice = Signal::Scaled { gain: 2.0, signal: Box::new(paper_identification_input()) };
/// let doubled = Excitation::from_signal(twice, 0.0, 0.002, 7501)?;
/// let c = InputComparison::new(&Parameters::PAPER, &doubled, &paper, 2.5e-3)?;
/// // Twice the force, half the standard errors: every ratio is 1/2.
/// assert!((c.determinant_ratio - 0.5).abs() < 1e-9 && (c.worst_ratio - 0.5).abs() < 1e-9);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InputComparison {
    /// The plant they are predicted on.
    pub plant: Parameters,
    /// Noise σ of the displacement, m.
    pub noise_sigma: f64,
    /// The design's standard errors of m, c, k.
    pub design: [f64; 3],
    /// The reference's standard errors of m, c, k.
    pub reference: [f64; 3],
    /// design / reference, per parameter.
    pub ratios: [f64; 3],
    /// det(covariance)^(1/6) of the design over the reference's (the D criterion).
    pub determinant_ratio: f64,
    /// √trace of the relative covariance, design over reference (the A criterion).
    pub trace_ratio: f64,
    /// The geometric mean of the three ratios.
    pub geometric_mean_ratio: f64,
    /// The largest ratio: is every parameter better?
    pub worst_ratio: f64,
    /// The largest relative standard error of the design over the reference's (the
    /// minimax criterion).
    pub minimax_ratio: f64,
}

impl InputComparison {
    /// Predicts both inputs on `plant` with noise `sigma` (Cramér–Rao, m, c, k estimated
    /// from rest: [`EstimationOptions::default`]) and compares them.
    pub fn new(
        plant: &Parameters,
        design: &Excitation,
        reference: &Excitation,
        sigma: f64,
    ) -> Result<Self> {
        let options = EstimationOptions::default();
        let d = predicted_uncertainty(plant, design, sigma, &options)?;
        let r = predicted_uncertainty(plant, reference, sigma, &options)?;
        let (sd, sr) = (standard_errors(&d), standard_errors(&r));
        let ratios: [f64; 3] = std::array::from_fn(|i| sd[i] / sr[i]);
        let theta = [plant.mass, plant.damping, plant.stiffness];
        let relative_trace = |u: &Uncertainty| {
            (0..3)
                .map(|i| u.covariance[(i, i)] / (theta[i] * theta[i]))
                .sum::<f64>()
        };
        let worst_relative = |s: &[f64; 3]| (0..3).map(|i| s[i] / theta[i]).fold(0.0, f64::max);
        Ok(Self {
            plant: *plant,
            noise_sigma: sigma,
            design: sd,
            reference: sr,
            ratios,
            determinant_ratio: (determinant(&d) / determinant(&r)).powf(1.0 / 6.0),
            trace_ratio: (relative_trace(&d) / relative_trace(&r)).sqrt(),
            geometric_mean_ratio: ratios.iter().product::<f64>().cbrt(),
            worst_ratio: ratios.iter().copied().fold(0.0, f64::max),
            minimax_ratio: worst_relative(&sd) / worst_relative(&sr),
        })
    }

    /// When the design leaves a parameter's predicted relative standard error above
    /// [`InputComparison::USEFUL_RELATIVE_SE`] (the input is at or below the noise), what
    /// that means in words; `None` otherwise.
    ///
    /// ```
    /// use msd_ident::{Parameters, design::InputComparison};
    /// let plant = Parameters::PAPER;
    /// let comparison = InputComparison {
    ///     plant, noise_sigma: 1e-3, design: [0.01, 0.9, 40.0], reference: [0.01, 0.05, 1.0],
    ///     ratios: [1.0, 18.0, 40.0], determinant_ratio: 1.0, trace_ratio: 1.0,
    ///     geometric_mean_ratio: 1.0, worst_ratio: 40.0, minimax_ratio: 1.0,
    /// };
    /// let warning = comparison.below_noise().expect("c and k are not identified");
    /// assert!(warning.contains("damping 50 %") && warning.contains("stiffness 33 %"), "{warning}");
    /// ```
    pub fn below_noise(&self) -> Option<String> {
        let theta = [self.plant.mass, self.plant.damping, self.plant.stiffness];
        let relative: Vec<(&str, f64)> = ["mass", "damping", "stiffness"]
            .into_iter()
            .zip((0..3).map(|i| self.design[i] / theta[i].abs()))
            .collect();
        if relative.iter().all(|(_, r)| *r <= Self::USEFUL_RELATIVE_SE) {
            return None;
        }
        let list: Vec<String> = relative
            .iter()
            .map(|(name, r)| format!("{name} {:.0} %", 100.0 * r))
            .collect();
        Some(format!(
            "the limits leave this input below the noise: predicted relative standard errors {}; a parameter whose standard error exceeds {:.0} % of its value is not usefully identified (its 95 % interval spans more than ±60 % of it, and from ±100 % on reaches zero). Allow a larger force or stroke, or plan for less noise",
            list.join(", "),
            100.0 * Self::USEFUL_RELATIVE_SE
        ))
    }

    /// The largest predicted relative standard error of a parameter the test identifies
    /// usefully (0.3: its 95 % interval, ±1.96 SE, spans at most ±60 % of the value).
    pub const USEFUL_RELATIVE_SE: f64 = 0.3;
}

fn standard_errors(u: &Uncertainty) -> [f64; 3] {
    [
        u.mass.standard_error,
        u.damping.standard_error,
        u.stiffness.standard_error,
    ]
}

fn determinant(u: &Uncertainty) -> f64 {
    u.covariance.view((0, 0), (3, 3)).determinant()
}

impl std::fmt::Display for InputComparison {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "  {:<10} {:>12} {:>12} {:>12} {:>8}",
            "parameter", "prior", "design SE", "reference SE", "ratio"
        )?;
        let theta = [self.plant.mass, self.plant.damping, self.plant.stiffness];
        for (i, name) in ["mass", "damping", "stiffness"].iter().enumerate() {
            writeln!(
                f,
                "  {name:<10} {:>12.6} {:>12.4e} {:>12.4e} {:>8.3}",
                theta[i], self.design[i], self.reference[i], self.ratios[i]
            )?;
        }
        writeln!(
            f,
            "  det(cov)^(1/6) ratio {:.3}, geometric mean of the ratios {:.3}, worst ratio {:.3}",
            self.determinant_ratio, self.geometric_mean_ratio, self.worst_ratio
        )?;
        write!(
            f,
            "  √trace ratio (A) {:.3}, worst relative SE ratio (minimax) {:.3}",
            self.trace_ratio, self.minimax_ratio
        )?;
        if let Some(warning) = self.below_noise() {
            write!(f, "\n  WARNING: {warning}")?;
        }
        Ok(())
    }
}
