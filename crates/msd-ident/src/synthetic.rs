//! Synthetic test data: the response of a known plant plus seeded Gaussian noise.

use crate::{Backend, DataSet, Excitation, IdentError, InitialState, Parameters, Result, simulate};
use msd_signal::{NoiseStream, paper_identification_input, paper_validation_input};

/// Simulates `plant` (exactly) on `excitation` from `initial` and adds white Gaussian
/// noise of standard deviation `sigma` from the named stream of `seed` (msd-signal's
/// ChaCha streams: the same (seed, stream) gives the same noise on every platform, and
/// different streams are independent).
///
/// Returns the noisy data set and the noise-free response.
///
/// ```
/// use msd_ident::{synthetic_data, Excitation, InitialState, Parameters};
/// use msd_signal::paper_validation_input;
/// let input = Excitation::from_signal(paper_validation_input(), 0.0, 0.002, 7501)?;
/// let (data, truth) = synthetic_data("validation", &Parameters::PAPER, input, InitialState::REST, 0.0025, 42, "validation")?;
/// assert_eq!(data.len(), truth.len());
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn synthetic_data(
    name: &str,
    plant: &Parameters,
    excitation: Excitation,
    initial: InitialState,
    sigma: f64,
    seed: u64,
    stream: &str,
) -> Result<(DataSet, Vec<f64>)> {
    let truth = simulate(plant, &excitation, initial, &Backend::EXACT)?;
    let mut y = truth.clone();
    if !(sigma.is_finite() && sigma >= 0.0) {
        return Err(IdentError::InvalidParameter {
            name: "sigma",
            value: sigma,
            expected: "a finite noise standard deviation >= 0",
        });
    }
    if sigma > 0.0 {
        NoiseStream::new(seed, stream, sigma)?.add_to(&mut y);
    }
    Ok((DataSet::new(name, excitation, y)?, truth))
}

/// The paper experiment (shared/paper-experiment.md) for one seed: identification and
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
        let (identification, identification_truth) = synthetic_data(
            "identification",
            &plant,
            id_input,
            InitialState::REST,
            Self::SIGMA,
            seed,
            "identification",
        )?;
        let (validation, validation_truth) = synthetic_data(
            "validation",
            &plant,
            val_input,
            InitialState::REST,
            Self::SIGMA,
            seed,
            "validation",
        )?;
        Ok(Self {
            identification,
            identification_truth,
            validation,
            validation_truth,
        })
    }
}
