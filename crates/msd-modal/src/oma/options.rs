//! The options of output-only modal analysis: the subspace's size, the diagram's
//! tolerances, the automatic selection and the uncertainty.

use serde::{Deserialize, Serialize};

use crate::options::{check_fractions, check_orders};
use msd_modal_core::error::{ModalError, Result};

/// Options of [`ssi_cov`](crate::ssi_cov) (in TOML: a table with any of these fields).
/// Every threshold of the automatic selection is here, with the reason for its default.
///
/// ```
/// use msd_modal::OmaOptions;
/// let options: OmaOptions = toml::from_str("orders = [2, 60]\nblock_rows = 30")?;
/// assert_eq!((options.orders, options.block_rows), ([2, 60], Some(30)));
/// assert_eq!(options.frequency_tolerance, 0.01);
/// # Ok::<(), toml::de::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OmaOptions {
    /// Block rows i of the Toeplitz matrix (lags 1 … 2i − 1). By default the larger of
    /// ⌈n_max/r⌉ + 5 (enough columns for every order n_max with r references) and
    /// ⌈fs/(2·f_low)⌉ (the longest lag one period of the lowest mode f_low: the band's
    /// lower edge, or the lowest clear peak of the record's spectrum).
    pub block_rows: Option<usize>,
    /// The lowest and highest model order. By default [2, 80].
    #[serde(deserialize_with = "msd_signal::pair::exactly_two")]
    pub orders: [usize; 2],
    /// The step between orders. By default 2 (the poles come in conjugate pairs).
    pub order_step: usize,
    /// Only modes in this band, Hz; by default `None` (0 to Nyquist).
    #[serde(default, deserialize_with = "msd_signal::pair::optional")]
    pub band_hz: Option<[f64; 2]>,
    /// Hard criterion: poles more damped than this are not physical. By default 0.2.
    pub max_damping_ratio: f64,
    /// Hard criterion: a pole's shape must have at least this modal phase collinearity
    /// (1 for a real, normal mode; noise poles scatter in phase). By default 0.5.
    pub min_mpc: f64,
    /// Soft criterion: relative change of fn from the nearest pole of the order before
    /// that counts as stable. By default 0.01 (1 %, the usual; Peeters & De Roeck 1999).
    pub frequency_tolerance: f64,
    /// Relative change of ζ that counts as stable in damping (drawn, not required: ζ
    /// scatters more than fn on ambient data). By default 0.05.
    pub damping_tolerance: f64,
    /// Soft criterion: 1 − MAC with that pole's shape that counts as stable. By default
    /// 0.02 (MAC ≥ 0.98).
    pub mac_tolerance: f64,
    /// Clustering: stable poles closer than this in |Δf|/f + (1 − MAC) form one mode
    /// (average linkage). By default 0.02.
    pub cluster_distance: f64,
    /// A cluster is a mode when it has a pole at this share of the orders. By default
    /// 0.3.
    pub min_stable_share: f64,
    /// Blocks the record is cut into for the uncertainty (leave-one-block-out
    /// jackknife). By default 8: over 200 simulated buildings (`cargo xtask oma-study`), 8
    /// blocks covered fn and ζ of every mode 0.94–0.99 of the time, 16 blocks 0.90–1.00
    /// (the jackknife's upward bias, which grows with the number of blocks, makes the
    /// strongest modes' intervals too wide; fewer blocks leave too few degrees of
    /// freedom).
    pub blocks: usize,
    /// Frequencies the user names, Hz: the mode nearest each is reported instead of the
    /// automatic selection. By default none.
    pub frequencies_hz: Vec<f64>,
}

impl Default for OmaOptions {
    fn default() -> Self {
        Self {
            block_rows: None,
            orders: [2, 80],
            order_step: 2,
            band_hz: None,
            max_damping_ratio: 0.2,
            min_mpc: 0.5,
            frequency_tolerance: 0.01,
            damping_tolerance: 0.05,
            mac_tolerance: 0.02,
            cluster_distance: 0.02,
            min_stable_share: 0.3,
            blocks: 8,
            frequencies_hz: Vec::new(),
        }
    }
}

impl OmaOptions {
    /// Checks every option, naming the first out of range.
    pub fn validate(&self) -> Result<()> {
        msd_modal_core::lines::check_band(self.band_hz)?;
        check_orders(self.orders, self.order_step)?;
        check_fractions(&[
            ("max_damping_ratio", self.max_damping_ratio),
            ("frequency_tolerance", self.frequency_tolerance),
            ("damping_tolerance", self.damping_tolerance),
            ("mac_tolerance", self.mac_tolerance),
            ("cluster_distance", self.cluster_distance),
            ("min_stable_share", self.min_stable_share),
        ])?;
        let invalid = |name, value: f64, expected| {
            Err(ModalError::InvalidParameter {
                name,
                value,
                expected,
            })
        };
        if self.block_rows.is_some_and(|i| i < 2) {
            return invalid("block_rows", 1.0, "at least 2 block rows");
        }
        if !(2..=1000).contains(&self.blocks) {
            return invalid("blocks", self.blocks as f64, "2 to 1000 blocks");
        }
        if !(0.0..=1.0).contains(&self.min_mpc) {
            return invalid("min_mpc", self.min_mpc, "a number in [0, 1]");
        }
        for &f in &self.frequencies_hz {
            if !(f.is_finite() && f > 0.0) {
                return invalid("frequencies_hz", f, "positive frequencies");
            }
        }
        Ok(())
    }
}

/// Options of [`efdd`](crate::efdd) (in TOML: a table with any of these fields): the
/// spectral matrix, the peak picking, the bell and the decay fit.
///
/// ```
/// use msd_modal::FddOptions;
/// let options: FddOptions = toml::from_str("lags = 4096\nbell_mac = 0.8")?;
/// assert_eq!((options.lags, options.bell_mac), (Some(4096), 0.8));
/// assert_eq!(options.min_correlation, 0.3);
/// # Ok::<(), toml::de::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FddOptions {
    /// Covariance lags N of the spectral matrix (lines fs/2N apart). By default 40
    /// periods of the lowest mode (the band's lower edge, else the record's lowest clear
    /// spectral peak) as a power of two, 256 to a quarter of the record.
    pub lags: Option<usize>,
    /// Only modes in this band, Hz; by default `None` (0 to Nyquist).
    #[serde(default, deserialize_with = "msd_signal::pair::optional")]
    pub band_hz: Option<[f64; 2]>,
    /// A peak of the first singular value must stand this many times above its median
    /// over ±50 % of its frequency. By default 4.
    pub min_peak_ratio: f64,
    /// And this many times above the higher of the troughs that separate it from higher
    /// lines on either side (its prominence; ripples on a mode's flank have little). By
    /// default 2.
    pub min_prominence: f64,
    /// The SDOF bell: the lines around a peak whose first singular vector has at least
    /// this MAC with the peak's. By default 0.85 (pyOMA2's; Brincker suggests 0.8).
    pub bell_mac: f64,
    /// Extremes of the bell's correlation function left out before the decay fit (the
    /// first holds the noise in the bell). By default 1.
    pub skip_extremes: usize,
    /// At most this many extremes in the fit. By default 100 (the early extremes alone
    /// understate the decay: the bell's truncation flattens the correlation near lag 0).
    pub max_extremes: usize,
    /// The fit stops at the first extreme below this share of the correlation at lag 0
    /// (where the noise takes over). By default 0.3.
    pub min_correlation: f64,
    /// Modes more damped than this are not reported. By default 0.2.
    pub max_damping_ratio: f64,
    /// Blocks the record is cut into for the leave-one-block-out jackknife. By default 8
    /// (as SSI's).
    pub blocks: usize,
    /// Frequencies the user names, Hz: the peak nearest each is analysed instead of every
    /// peak. By default none.
    pub frequencies_hz: Vec<f64>,
}

impl Default for FddOptions {
    fn default() -> Self {
        Self {
            lags: None,
            band_hz: None,
            min_peak_ratio: 4.0,
            min_prominence: 2.0,
            bell_mac: 0.85,
            skip_extremes: 1,
            max_extremes: 100,
            min_correlation: 0.3,
            max_damping_ratio: 0.2,
            blocks: 8,
            frequencies_hz: Vec::new(),
        }
    }
}

impl FddOptions {
    /// Checks every option, naming the first out of range.
    pub fn validate(&self) -> Result<()> {
        msd_modal_core::lines::check_band(self.band_hz)?;
        check_fractions(&[
            ("bell_mac", self.bell_mac),
            ("min_correlation", self.min_correlation),
            ("max_damping_ratio", self.max_damping_ratio),
        ])?;
        let invalid = |name, value: f64, expected| {
            Err(ModalError::InvalidParameter {
                name,
                value,
                expected,
            })
        };
        if self.lags.is_some_and(|n| n < 16) {
            return invalid("lags", self.lags.unwrap_or(0) as f64, "at least 16 lags");
        }
        for (name, v) in [
            ("min_peak_ratio", self.min_peak_ratio),
            ("min_prominence", self.min_prominence),
        ] {
            if !(v.is_finite() && v >= 1.0) {
                return invalid(name, v, "a ratio of at least 1");
            }
        }
        if self.max_extremes < 4 {
            return invalid(
                "max_extremes",
                self.max_extremes as f64,
                "at least 4 extremes",
            );
        }
        if !(2..=1000).contains(&self.blocks) {
            return invalid("blocks", self.blocks as f64, "2 to 1000 blocks");
        }
        for &f in &self.frequencies_hz {
            if !(f.is_finite() && f > 0.0) {
                return invalid("frequencies_hz", f, "positive frequencies");
            }
        }
        Ok(())
    }
}
