//! `plan`: the uncertainty a synthetic config's experiment will give, before it is run.
//!
//! The config's `[plant]` is the prior guess of the real plant; its input, time grid,
//! noise levels, `[setup]` and `[estimation]` the planned test. The prediction is the
//! Cramér–Rao bound from the exact sensitivities: [`msd_ident::predicted_uncertainty`]
//! for the paper's setup (a force, one displacement channel),
//! [`msd_ident::records::predicted_records_uncertainty`] for a `[setup]` (any drive, several
//! channels and records), and the least-squares covariance of the damping law's
//! coefficients for a test machine ([`msd_ident::dynamometer::predicted_dynamometer`]). Beside it,
//! what reaches a target precision — the drive's amplitude (the errors scale exactly as
//! 1/amplitude), repeats (as 1/√records), a longer record (by search) — and with
//! `verify` the spread of that many simulated experiments, fitted as the run fits them.
//!
//! ```
//! use msd_experiment::plan::{PlanOptions, plan};
//! let options = PlanOptions { verify: 20, ..PlanOptions::default() };
//! let plan = plan("../../configs/paper-fast.toml".as_ref(), &options)?;
//! let zeta = plan.quantity("damping_ratio").unwrap();
//! assert!(zeta.relative_half_width < 0.01);
//! let spread = zeta.simulated_standard_deviation.unwrap();
//! assert!((spread / zeta.standard_error - 1.0).abs() < 0.5); // 20 seeds: ±16 % (1σ)
//! # Ok::<(), msd_experiment::ExperimentError>(())
//! ```

mod chain;
mod display;
mod force;
mod machine;
mod search;

pub(crate) use search::{draws, standard_deviations};
mod setup;

use crate::config::{Config, ExcitationKind, ExperimentKind};
use crate::error::{ExperimentError, Result};
use serde::Serialize;
use std::path::Path;

/// The quantities of a plant's plan, in the order they are shown.
const NAMES: [&str; 5] = [
    "mass",
    "damping",
    "stiffness",
    "natural_frequency_hz",
    "damping_ratio",
];

/// Options of [`plan`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PlanOptions {
    /// Target 95 % half-width, relative to the value. By default 0.01 (±1 %).
    pub target: f64,
    /// Simulated experiments to check the prediction with (0: none, else at least 2).
    /// By default 0.
    pub verify: usize,
    /// Whether the record-length search and the check draw progress on stderr. By
    /// default false.
    #[serde(skip)]
    pub progress: bool,
}

impl Default for PlanOptions {
    fn default() -> Self {
        Self {
            target: 0.01,
            verify: 0,
            progress: false,
        }
    }
}

/// One predicted quantity.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlannedQuantity {
    /// Its name (`mass`, `damping`, `stiffness`, `natural_frequency_hz`,
    /// `damping_ratio`; a test machine's law coefficients).
    pub name: &'static str,
    /// The prior value.
    pub value: f64,
    /// The predicted standard error.
    pub standard_error: f64,
    /// The 95 % half-width relative to the value (infinite for a value of 0).
    pub relative_half_width: f64,
    /// The factor on the drive's amplitude that reaches the target (exact for a linear
    /// plant: the drive and the initial state scaled together scale the response, and so
    /// the standard errors as 1/amplitude); `None` for a test machine.
    pub amplitude_factor: Option<f64>,
    /// The record length that reaches the target at this amplitude, s (`None` when no
    /// record up to 64 times as long does, e.g. because the input ends, or for a test
    /// machine).
    pub duration_needed_s: Option<f64>,
    /// The records (for a test machine: the cycles per condition) that reach the target
    /// (exact: the information of identical repeats adds up, so the errors scale as
    /// 1/√records); `None` for the paper's single-record setup.
    pub repeats_needed: Option<usize>,
    /// The standard deviation over the simulated experiments, when verified.
    pub simulated_standard_deviation: Option<f64>,
    /// The fraction of the simulated experiments whose 95 % interval holds the prior
    /// value, when verified (a `[chain]` plan).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub coverage: Option<f64>,
}

/// The planned test, as the plan read it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlannedTest {
    /// `setup.excitation` (`force` for the paper's setup).
    pub excitation: &'static str,
    /// Records (a test machine: conditions).
    pub records: usize,
    /// Samples of each record (a test machine: of all conditions together).
    pub samples: usize,
    /// Length of each record, s (a test machine: of all conditions together).
    pub duration_s: f64,
    /// What the amplitude factor scales (`force`, `base acceleration`, `initial state`,
    /// `stroke`) and its peak, in `drive_unit`.
    pub drive: &'static str,
    /// The drive's peak: the largest |sample|, or for a free decay the largest |initial
    /// displacement| or |initial velocity|.
    pub peak_drive: f64,
    /// The drive's unit.
    pub drive_unit: &'static str,
    /// What a repeat is: `records` or `cycles` (per condition).
    pub repeats: &'static str,
    /// Repeats planned.
    pub repeats_planned: usize,
    /// Each channel's name, noise σ and unit.
    pub channels: Vec<(String, f64, &'static str)>,
}

/// The predicted correlation of the estimated quantities.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Correlation {
    /// The quantities, in the order of the rows and columns.
    pub names: Vec<&'static str>,
    /// The matrix (a known quantity's row and column are zeros).
    pub matrix: Vec<Vec<f64>>,
}

/// The predicted precision of a planned experiment.
///
/// Displays as the table of quantities, the correlation, the notes and, for each
/// quantity short of the target, what reaches it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plan {
    /// The config's name.
    pub name: String,
    /// The planned test.
    pub test: PlannedTest,
    /// The target relative 95 % half-width.
    pub target: f64,
    /// The quantities the setup identifies, with their predicted errors.
    pub quantities: Vec<PlannedQuantity>,
    /// Their correlation.
    pub correlation: Correlation,
    /// What the setup cannot identify, and what the prediction leaves out.
    pub notes: Vec<String>,
    /// Simulated experiments run to check the prediction.
    pub verified_with: usize,
}

impl Plan {
    /// The quantity named `name`.
    pub fn quantity(&self, name: &str) -> Option<&PlannedQuantity> {
        self.quantities.iter().find(|q| q.name == name)
    }
}

/// Predicts the precision of the experiment `config_path` describes (a synthetic
/// config: its `[plant]` as the prior guess).
///
/// Refused (exit 2, naming the config and the key): a measured config (no `[plant]`), a
/// channel without noise, a target ≤ 0, `verify` = 1, a setup that cannot identify
/// what it is asked.
pub fn plan(config_path: &Path, options: &PlanOptions) -> Result<Plan> {
    let config = Config::load(config_path)?;
    plan_config(&config, config_path, options)
}

/// [`plan`] of a config already read; `config_path` names it in messages and anchors
/// its relative paths.
///
/// ```
/// use msd_experiment::{config::Config, plan::{PlanOptions, plan_config}};
/// let path = std::path::Path::new("../../configs/free-decay.toml");
/// let plan = plan_config(&Config::load(path)?, path, &PlanOptions::default())?;
/// assert_eq!(plan.test.drive, "initial state");
/// assert!(plan.quantity("damping").is_some()); // the mass is weighed
/// # Ok::<(), msd_experiment::ExperimentError>(())
/// ```
pub fn plan_config(config: &Config, config_path: &Path, options: &PlanOptions) -> Result<Plan> {
    if !(options.target.is_finite() && options.target > 0.0) {
        return Err(ExperimentError::config(
            config_path,
            format!(
                "--target = {}: expected a relative half-width > 0, e.g. 0.01",
                options.target
            ),
        ));
    }
    if options.verify == 1 {
        return Err(ExperimentError::config(
            config_path,
            "--verify = 1: expected 0 or at least 2 simulated experiments (a spread needs two)",
        ));
    }
    verify_budget(config, config_path, options.verify)?;
    match (ExperimentKind::of(config), &config.setup) {
        (ExperimentKind::Chain, _) => chain::plan(config, config_path, options),
        (ExperimentKind::Setup, Some(s)) if s.excitation == ExcitationKind::ImposedDisplacement => {
            machine::plan(config, config_path, options)
        }
        (ExperimentKind::Setup, _) => setup::plan(config, config_path, options),
        (ExperimentKind::Paper, _) => force::plan(config, config_path, options),
        (kind @ (ExperimentKind::FrequencyResponse | ExperimentKind::Operational), _) => {
            Err(ExperimentError::config(
                config_path,
                format!(
                    "plan predicts a time-domain test from a prior plant (the paper's, a [setup] or a [chain]); this config is {}",
                    kind.describe()
                ),
            ))
        }
    }
}

/// `--verify N` against the budget of samples fitted ([`crate::budget`]): N simulated
/// experiments of `config`, each fitted.
pub(crate) fn verify_budget(config: &Config, config_path: &Path, draws: usize) -> Result<()> {
    let per_draw = crate::budget::samples_per_experiment(config);
    crate::budget::check(
        "--verify",
        draws as f64,
        per_draw,
        crate::budget::Budget::Verified,
    )
    .map_err(|(key, message)| ExperimentError::config(config_path, format!("{key}{message}")))
}

/// The arguments of `plan` (`msd plan`, `cargo xtask plan`).
#[derive(Debug, Clone, clap::Args)]
pub struct PlanArgs {
    /// A synthetic experiment config: its `[plant]` is the prior guess, its input, time
    /// grid, noise, `[setup]` and `[estimation]` the planned test.
    pub config: std::path::PathBuf,
    /// Target 95 % half-width, relative (0.01 = ±1 %). The record length that reaches it
    /// is searched up to 64× the record (and 5e7 samples held): at most 13 predictions.
    #[arg(long, default_value_t = 0.01)]
    pub target: f64,
    /// Check the prediction against N simulated experiments (noise seeds 0 … N−1), each
    /// fitted: N × the experiment's samples (a chain's weighted by its size) count
    /// against a budget of 3e7 samples fitted, which the largest N accepted runs in
    /// about half a minute on two threads, release build (the largest N is named when
    /// it is past it). Progress is drawn on a terminal.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub verify: usize,
}

/// `plan`: prints the prediction (and the check) of `args.config`.
pub fn run_plan(args: &PlanArgs) -> Result<()> {
    use std::io::IsTerminal;
    let options = PlanOptions {
        target: args.target,
        verify: args.verify,
        progress: std::io::stderr().is_terminal(),
    };
    crate::output::print_stdout(&plan(&args.config, &options)?.to_string());
    Ok(())
}
