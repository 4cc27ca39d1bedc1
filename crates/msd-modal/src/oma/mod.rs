//! Output-only (operational) modal analysis: the modes of a structure from records of its
//! response alone, excited by wind, traffic, a fan or its own operation.
//!
//! - [`OutputRecord`]: channels sampled together, each with its DOF, measuring direction
//!   and quantity, and the reference channels;
//! - [`ssi_cov`]: covariance-driven stochastic subspace identification with references,
//!   its stabilization diagram, automatic selection by clustering, and intervals;
//! - [`OmaFit`]: the modes (the crate's one [`Mode`](crate::Mode)), the diagram with
//!   which poles formed which mode, and what the method used.

mod building;
mod covariance;
mod decay;
mod efdd;
mod eigen;
mod horizon;
mod merge;
mod options;
mod record;
mod select;
mod spectrum;
mod ssi;
mod subspace;
mod uncertainty;

use serde::{Deserialize, Serialize};

pub use building::ShearBuilding;
pub use efdd::efdd;
pub use merge::{MergedFit, Setup, merge_setups, node_components};
pub use options::{FddOptions, OmaOptions};
pub use record::{OutputRecord, accelerometer, direction_from_angles};
pub use spectrum::{SingularSpectrum, singular_spectrum};
pub use ssi::{ssi_cov, ssi_dat};

use msd_modal_core::diagram::{StabilizationDiagram, StableColumn};
use msd_modal_core::mode::Mode;

/// The method that found an [`OmaFit`]'s modes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum OmaMethod {
    /// Covariance-driven SSI with reference channels (the default).
    #[default]
    SsiCov,
    /// Data-driven SSI with reference channels.
    SsiDat,
    /// Frequency domain decomposition with EFDD's damping.
    Efdd,
}

impl std::fmt::Display for OmaMethod {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::SsiCov => "SSI-cov/ref",
            Self::SsiDat => "SSI-dat/ref",
            Self::Efdd => "EFDD",
        })
    }
}

/// The modes of an output-only record, the diagram they came from and the settings that
/// mattered (see [`ssi_cov`] for an example).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OmaFit {
    /// The method.
    pub method: OmaMethod,
    /// The selected modes, by frequency, with 95 % intervals on fn, ζ and the shape.
    pub modes: Vec<Mode>,
    /// The stabilization diagram: every order's physical poles with their stability
    /// flags and the mode each formed, the clusters (candidates) and the selected ones.
    pub diagram: StabilizationDiagram,
    /// The block rows of SSI's Toeplitz matrix (`None` for EFDD).
    pub block_rows: Option<usize>,
    /// The blocks of the record the jackknife left out one at a time.
    pub blocks: usize,
    /// The reference channels' names.
    pub references: Vec<String>,
    /// The singular values of the Toeplitz matrix, largest first (their drop suggests the
    /// order).
    pub singular_values: Vec<f64>,
    /// Columns the automatic selection chose that a jackknife replicate lost (the record
    /// less one block has no pole within `cluster_distance` of them), or that split a
    /// larger column's mode (within `frequency_tolerance` of it, MAC ≥ 0.9): too weak,
    /// too fragile or doubled to be reported as modes, listed so that nothing is hidden.
    pub unconfirmed: Vec<StableColumn>,
    /// EFDD's singular value spectrum with the peaks it picked (`None` for SSI: see
    /// [`singular_spectrum`] for its overlay).
    pub spectrum: Option<SingularSpectrum>,
}

impl std::fmt::Display for OmaFit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: {} modes ({})",
            self.method,
            self.modes.len(),
            self.settings()
        )?;
        for (k, m) in self.modes.iter().enumerate() {
            write!(
                f,
                "\n  mode {}: fn = {:.5} Hz, ζ = {:.5}",
                k + 1,
                m.natural_frequency_hz,
                m.damping_ratio
            )?;
            if let Some(n) = m.stable_orders {
                write!(f, ", {n} orders")?;
            }
        }
        for c in &self.unconfirmed {
            write!(
                f,
                "\n  unconfirmed: fn = {:.5} Hz, ζ = {:.5} (lost when a block of the record is left out, or a split of a reported mode)",
                c.natural_frequency_hz, c.damping_ratio
            )?;
        }
        Ok(())
    }
}

impl OmaFit {
    /// The settings that mattered, in words: SSI's orders, block rows and references, or
    /// EFDD's lags.
    pub fn settings(&self) -> String {
        match (self.block_rows, &self.spectrum) {
            (Some(i), _) => format!(
                "orders {}–{}, {i} block rows, references {}",
                self.diagram.orders.first().map_or(0, |o| o.order),
                self.diagram.orders.last().map_or(0, |o| o.order),
                self.references.join(", ")
            ),
            (None, Some(s)) => format!(
                "spectral matrix from {} lags, lines {:.4} Hz apart, {} peaks",
                s.lags,
                s.frequency_hz.get(1).copied().unwrap_or(0.0),
                s.peaks_hz.len()
            ),
            (None, None) => String::new(),
        }
    }
}
