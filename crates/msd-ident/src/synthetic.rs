//! Synthetic test data: the response of a known plant plus seeded Gaussian noise.

use crate::{
    data::{DataSet, Excitation},
    error::{IdentError, Result},
    params::{InitialState, Parameters},
    simulate::{Backend, simulate},
};
use msd_signal::{NoiseStream, paper_identification_input, paper_validation_input};
use serde::{Deserialize, Serialize};

/// How [`synthetic_data`] and
/// [`synthetic_nonlinear_data`](crate::nonlinear::synthetic_nonlinear_data) make a record: the
/// data set's name, the initial state, and white Gaussian noise of standard deviation
/// `sigma` from the named stream of `seed` (msd-signal's ChaCha streams: the same
/// (seed, stream) gives the same noise on every platform, and different streams are
/// independent).
///
/// By default a record named "synthetic" from rest with the paper's noise: σ = 2.5 mm
/// ([`PaperExperiment::SIGMA`]), seed 1, stream "synthetic".
///
/// ```
/// use msd_ident::{InitialState, SyntheticOptions};
/// let options = SyntheticOptions { sigma: 0.0, ..SyntheticOptions::named("noise-free") };
/// assert_eq!((options.name.as_str(), options.stream.as_str()), ("noise-free", "noise-free"));
/// assert_eq!(options.initial_state, InitialState::REST);
/// assert!(options.validate().is_ok());
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SyntheticOptions {
    /// Name of the data set. By default "synthetic".
    pub name: String,
    /// The initial state of the plant. By default at rest.
    pub initial_state: InitialState,
    /// Standard deviation of the output noise (finite, ≥ 0; 0 for none). By default
    /// 0.0025, the paper's 2.5 mm.
    pub sigma: f64,
    /// Seed of the noise. By default 1.
    pub seed: u64,
    /// Name of the noise stream within the seed. By default "synthetic".
    pub stream: String,
}

impl Default for SyntheticOptions {
    fn default() -> Self {
        Self::named("synthetic")
    }
}

impl SyntheticOptions {
    /// The defaults with the data set and its noise stream both called `name`.
    ///
    /// ```
    /// use msd_ident::SyntheticOptions;
    /// let id = SyntheticOptions::named("identification");
    /// assert_eq!((id.name.as_str(), id.stream.as_str()), ("identification", "identification"));
    /// assert_eq!((id.sigma, id.seed), (0.0025, 1));
    /// ```
    pub fn named(name: &str) -> Self {
        Self {
            name: name.to_string(),
            initial_state: InitialState::REST,
            sigma: PaperExperiment::SIGMA,
            seed: 1,
            stream: name.to_string(),
        }
    }

    /// Checks the noise level and the initial state.
    ///
    /// ```
    /// use msd_ident::{IdentError, SyntheticOptions};
    /// let options = SyntheticOptions { sigma: -1.0, ..SyntheticOptions::default() };
    /// assert!(matches!(options.validate(), Err(IdentError::InvalidParameter { name: "sigma", .. })));
    /// ```
    pub fn validate(&self) -> Result<()> {
        if !(self.sigma.is_finite() && self.sigma >= 0.0) {
            return Err(IdentError::InvalidParameter {
                name: "sigma",
                value: self.sigma,
                expected: "a finite noise standard deviation >= 0",
            });
        }
        crate::params::require_finite(self.initial_state.named())
    }

    /// The noisy data set: `response` plus the noise, on `excitation`.
    pub(crate) fn data_set(
        &self,
        excitation: Excitation,
        mut response: Vec<f64>,
    ) -> Result<DataSet> {
        if self.sigma > 0.0 {
            NoiseStream::new(self.seed, &self.stream, self.sigma)?.add_to(&mut response);
        }
        DataSet::new(&self.name, excitation, response)
    }
}

/// Simulates `plant` (exactly) on `excitation` from `options.initial_state` and adds
/// the noise of `options` (see [`SyntheticOptions`]).
///
/// Returns the noisy data set and the noise-free response.
///
/// ```
/// use msd_ident::{synthetic_data, Excitation, Parameters, SyntheticOptions};
/// use msd_signal::paper_validation_input;
/// let input = Excitation::from_signal(paper_validation_input(), 0.0, 0.002, 7501)?;
/// let options = SyntheticOptions { seed: 42, ..SyntheticOptions::named("validation") };
/// let (data, truth) = synthetic_data(&Parameters::PAPER, input, &options)?;
/// assert_eq!(data.len(), truth.len());
/// assert_eq!(data.name, "validation");
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn synthetic_data(
    plant: &Parameters,
    excitation: Excitation,
    options: &SyntheticOptions,
) -> Result<(DataSet, Vec<f64>)> {
    options.validate()?;
    let truth = simulate(plant, &excitation, options.initial_state, &Backend::EXACT)?;
    Ok((options.data_set(excitation, truth.clone())?, truth))
}

/// The paper experiment (docs/paper-experiment.md) for one seed: identification and
/// validation data sets with their noise-free responses.
#[derive(Debug, Clone)]
pub struct PaperExperiment {
    /// Identification data (step + multi-level sinusoid), noise stream "identification".
    pub identification: DataSet,
    /// Noise-free identification response.
    pub identification_truth: Vec<f64>,
    /// Validation data (chirp + small step), noise stream "validation".
    pub validation: DataSet,
    /// Noise-free validation response.
    pub validation_truth: Vec<f64>,
}

impl PaperExperiment {
    /// Plant m = 2.5, c = 1.8, k = 120; 0…15 s at 2 ms (7501 samples); σ = 2.5 mm.
    pub const SIGMA: f64 = 0.0025;
    /// Sampling interval.
    pub const DT: f64 = 0.002;
    /// Samples per record.
    pub const SAMPLES: usize = 7501;

    /// Generates both data sets from `seed`.
    ///
    /// ```
    /// use msd_ident::PaperExperiment;
    /// let a = PaperExperiment::generate(7)?;
    /// let b = PaperExperiment::generate(7)?;
    /// assert_eq!(a.identification.output, b.identification.output);
    /// # Ok::<(), msd_ident::IdentError>(())
    /// ```
    pub fn generate(seed: u64) -> Result<Self> {
        let plant = Parameters::PAPER;
        let id_input =
            Excitation::from_signal(paper_identification_input(), 0.0, Self::DT, Self::SAMPLES)?;
        let val_input =
            Excitation::from_signal(paper_validation_input(), 0.0, Self::DT, Self::SAMPLES)?;
        let noise = |name| SyntheticOptions {
            seed,
            ..SyntheticOptions::named(name)
        };
        let (identification, identification_truth) =
            synthetic_data(&plant, id_input, &noise("identification"))?;
        let (validation, validation_truth) =
            synthetic_data(&plant, val_input, &noise("validation"))?;
        Ok(Self {
            identification,
            identification_truth,
            validation,
            validation_truth,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validate_names_the_first_bad_field() {
        let state = |displacement, velocity| SyntheticOptions {
            initial_state: InitialState {
                displacement,
                velocity,
            },
            ..SyntheticOptions::default()
        };
        let err = state(0.0, f64::NAN).validate().unwrap_err();
        assert!(
            matches!(err, IdentError::InvalidParameter { name: "initial_state.velocity", value, .. } if value.is_nan())
        );
        let err = state(f64::INFINITY, f64::NAN).validate().unwrap_err();
        assert_eq!(
            err.to_string(),
            "invalid initial_state.displacement = inf: expected a finite number"
        );
        assert_eq!(state(0.01, -0.2).validate(), Ok(()));
        let noisy = SyntheticOptions {
            sigma: f64::NAN,
            ..state(f64::NAN, 0.0)
        };
        assert!(matches!(
            noisy.validate(),
            Err(IdentError::InvalidParameter { name: "sigma", .. })
        ));
    }
}
