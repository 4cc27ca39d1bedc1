//! [`FunctionType`]: what a dataset 58 holds (record 6, field 1).

use std::fmt;

use serde::Serialize;

/// The function type of a dataset 58 (record 6, field 1), with the codes of the SDRC
/// description; a code outside 0–27 is kept as [`FunctionType::Other`].
///
/// ```
/// use msd_uff::FunctionType;
///
/// assert_eq!(FunctionType::from_code(4), FunctionType::FrequencyResponse);
/// assert_eq!(FunctionType::FrequencyResponse.code(), 4);
/// assert_eq!(FunctionType::from_code(6).to_string(), "coherence");
/// assert_eq!(FunctionType::from_code(99), FunctionType::Other(99));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[non_exhaustive]
pub enum FunctionType {
    /// 0: general or unknown.
    General,
    /// 1: time response.
    TimeResponse,
    /// 2: auto spectrum.
    AutoSpectrum,
    /// 3: cross spectrum.
    CrossSpectrum,
    /// 4: frequency response function (FRF).
    FrequencyResponse,
    /// 5: transmissibility.
    Transmissibility,
    /// 6: coherence.
    Coherence,
    /// 7: auto correlation.
    AutoCorrelation,
    /// 8: cross correlation.
    CrossCorrelation,
    /// 9: power spectral density (PSD).
    PowerSpectralDensity,
    /// 10: energy spectral density (ESD).
    EnergySpectralDensity,
    /// 11: probability density function.
    ProbabilityDensity,
    /// 12: spectrum.
    Spectrum,
    /// 13: cumulative frequency distribution.
    CumulativeFrequencyDistribution,
    /// 14: peaks valley.
    PeaksValley,
    /// 15: stress/cycles.
    StressCycles,
    /// 16: strain/cycles.
    StrainCycles,
    /// 17: orbit.
    Orbit,
    /// 18: mode indicator function.
    ModeIndicator,
    /// 19: force pattern.
    ForcePattern,
    /// 20: partial power.
    PartialPower,
    /// 21: partial coherence.
    PartialCoherence,
    /// 22: eigenvalue.
    Eigenvalue,
    /// 23: eigenvector.
    Eigenvector,
    /// 24: shock response spectrum.
    ShockResponseSpectrum,
    /// 25: finite impulse response filter.
    FiniteImpulseResponseFilter,
    /// 26: multiple coherence.
    MultipleCoherence,
    /// 27: order function.
    OrderFunction,
    /// Any other code, kept as found.
    Other(i32),
}

/// The named types in code order: `KNOWN[code]` is the type with that code.
const KNOWN: [(FunctionType, &str); 28] = [
    (FunctionType::General, "general"),
    (FunctionType::TimeResponse, "time response"),
    (FunctionType::AutoSpectrum, "auto spectrum"),
    (FunctionType::CrossSpectrum, "cross spectrum"),
    (
        FunctionType::FrequencyResponse,
        "frequency response function",
    ),
    (FunctionType::Transmissibility, "transmissibility"),
    (FunctionType::Coherence, "coherence"),
    (FunctionType::AutoCorrelation, "auto correlation"),
    (FunctionType::CrossCorrelation, "cross correlation"),
    (FunctionType::PowerSpectralDensity, "power spectral density"),
    (
        FunctionType::EnergySpectralDensity,
        "energy spectral density",
    ),
    (
        FunctionType::ProbabilityDensity,
        "probability density function",
    ),
    (FunctionType::Spectrum, "spectrum"),
    (
        FunctionType::CumulativeFrequencyDistribution,
        "cumulative frequency distribution",
    ),
    (FunctionType::PeaksValley, "peaks valley"),
    (FunctionType::StressCycles, "stress/cycles"),
    (FunctionType::StrainCycles, "strain/cycles"),
    (FunctionType::Orbit, "orbit"),
    (FunctionType::ModeIndicator, "mode indicator function"),
    (FunctionType::ForcePattern, "force pattern"),
    (FunctionType::PartialPower, "partial power"),
    (FunctionType::PartialCoherence, "partial coherence"),
    (FunctionType::Eigenvalue, "eigenvalue"),
    (FunctionType::Eigenvector, "eigenvector"),
    (
        FunctionType::ShockResponseSpectrum,
        "shock response spectrum",
    ),
    (
        FunctionType::FiniteImpulseResponseFilter,
        "finite impulse response filter",
    ),
    (FunctionType::MultipleCoherence, "multiple coherence"),
    (FunctionType::OrderFunction, "order function"),
];

impl FunctionType {
    /// The type with this code; codes outside 0–27 give [`FunctionType::Other`].
    ///
    /// ```
    /// assert_eq!(msd_uff::FunctionType::from_code(1), msd_uff::FunctionType::TimeResponse);
    /// ```
    pub fn from_code(code: i32) -> Self {
        usize::try_from(code)
            .ok()
            .and_then(|i| KNOWN.get(i))
            .map_or(Self::Other(code), |&(kind, _)| kind)
    }

    /// The code written in the file.
    ///
    /// ```
    /// assert_eq!(msd_uff::FunctionType::Other(31).code(), 31);
    /// assert_eq!(msd_uff::FunctionType::Coherence.code(), 6);
    /// ```
    pub fn code(self) -> i32 {
        match self {
            Self::Other(code) => code,
            kind => KNOWN.iter().position(|&(k, _)| k == kind).unwrap_or(0) as i32,
        }
    }
}

impl fmt::Display for FunctionType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Other(code) => write!(f, "function type {code}"),
            kind => {
                let name = KNOWN.iter().find(|(k, _)| k == kind).map_or("", |(_, n)| n);
                f.write_str(name)
            }
        }
    }
}
