//! A config resolved, once, to the one experiment it describes: the low-level `Config`
//! (every section optional, as the file wrote it) becomes an [`Experiment`] whose kind's
//! own section is no longer optional. The rule that tells the kind is [`ExperimentKind::of`],
//! the one place it is written: the checks of a config read from a file
//! (`Config::validate`), the run (`run::run_and_write`) and `plan` all follow it.

use super::Config;
use super::chain::ChainSection;
use super::frf::FrequencyResponseSection;
use super::operational::OperationalSection;
use super::setup::SetupSection;
use crate::error::{ExperimentError, Result};

/// What a config runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExperimentKind {
    /// The paper's workflow: identification, validation, residuals, frequency check,
    /// Monte Carlo, nonlinear models.
    Paper,
    /// A lab setup (`[setup]`): any drive, several sensors and records, a test machine.
    Setup,
    /// A frequency response (`[frequency_response]` and no time-domain data).
    FrequencyResponse,
    /// A chain of masses in the time domain (`[chain]`).
    Chain,
    /// Output-only modal analysis (`[operational]`).
    Operational,
}

impl ExperimentKind {
    /// The kind of `config`: `[operational]`, else a `[frequency_response]` with no
    /// time-domain data, else `[chain]`, else `[setup]`, else the paper's workflow.
    ///
    /// ```
    /// use msd_experiment::config::{Config, ExperimentKind};
    /// let config = Config::load("../../configs/free-decay.toml".as_ref())?;
    /// assert_eq!(ExperimentKind::of(&config), ExperimentKind::Setup);
    /// # Ok::<(), msd_experiment::ExperimentError>(())
    /// ```
    pub fn of(config: &Config) -> Self {
        if config.operational.is_some() {
            Self::Operational
        } else if config.frequency_only() {
            Self::FrequencyResponse
        } else if config.chain.is_some() {
            Self::Chain
        } else if config.setup.is_some() {
            Self::Setup
        } else {
            Self::Paper
        }
    }

    /// The kind in words, with the section that makes it.
    pub fn describe(self) -> &'static str {
        match self {
            Self::Paper => "the paper's workflow",
            Self::Setup => "a lab setup ([setup])",
            Self::FrequencyResponse => {
                "a frequency response ([frequency_response] with no time-domain data)"
            }
            Self::Chain => "a chain of masses ([chain])",
            Self::Operational => "output-only modal analysis ([operational])",
        }
    }
}

/// A config with its kind's own section, which the kind's run reads from here (never
/// as an `Option` of the config). `config` is the whole config as read: the header,
/// the shared sections, and the kind's section too (for the checks and budgets written
/// over a `Config`).
///
/// ```
/// use msd_experiment::config::{ChainSection, Config, SetupSection, Spec};
/// let config = Config::load("../../configs/two-storey.toml".as_ref())?;
/// let spec = Spec::<ChainSection>::new(config.clone())?;
/// assert_eq!(spec.section.guess.masses.len(), 2);
/// let err = Spec::<SetupSection>::new(config).unwrap_err().to_string();
/// assert!(err.contains("a [setup] run") && err.contains("[chain]"), "{err}");
/// # Ok::<(), msd_experiment::ExperimentError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Spec<S> {
    /// The config as read.
    pub config: Config,
    /// The kind's section.
    pub section: S,
}

/// The section that makes a config one kind of experiment.
pub trait KindSection: Clone {
    /// The kind it makes.
    const KIND: ExperimentKind;
    /// Its header in a config, as `[setup]`.
    const HEADER: &'static str;
    /// The section in `config`.
    fn of(config: &Config) -> Option<&Self>;
}

macro_rules! kind_section {
    ($section:ty, $kind:ident, $field:ident) => {
        impl KindSection for $section {
            const KIND: ExperimentKind = ExperimentKind::$kind;
            const HEADER: &'static str = concat!("[", stringify!($field), "]");
            fn of(config: &Config) -> Option<&Self> {
                config.$field.as_ref()
            }
        }
    };
}
kind_section!(SetupSection, Setup, setup);
kind_section!(
    FrequencyResponseSection,
    FrequencyResponse,
    frequency_response
);
kind_section!(ChainSection, Chain, chain);
kind_section!(OperationalSection, Operational, operational);

impl<S: KindSection> Spec<S> {
    /// `config` as the experiment its section makes, refused (naming the config and its
    /// kind) when [`ExperimentKind::of`] finds it is another.
    pub fn new(config: Config) -> Result<Self> {
        let kind = ExperimentKind::of(&config);
        match S::of(&config) {
            Some(section) if kind == S::KIND => Ok(Self {
                section: section.clone(),
                config,
            }),
            _ => Err(ExperimentError::config(
                config.sources.config_file(),
                format!(
                    "a {} run needs a config whose experiment is given by {}; this one's is {}",
                    S::HEADER,
                    S::HEADER,
                    kind.describe()
                ),
            )),
        }
    }
}

/// A config resolved to its experiment ([`ExperimentKind::of`]'s rule).
///
/// ```
/// use msd_experiment::config::{Config, Experiment, ExperimentKind};
/// let config = Config::load("../../configs/two-storey.toml".as_ref())?;
/// let Experiment::Chain(spec) = Experiment::from(config) else { panic!("a chain") };
/// assert_eq!(spec.section.guess.masses.len(), 2);
/// # Ok::<(), msd_experiment::ExperimentError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub enum Experiment {
    /// The paper's workflow (its sections are the config's own).
    Paper(Box<Config>),
    /// A lab setup.
    Setup(Box<Spec<SetupSection>>),
    /// A frequency response on its own.
    FrequencyResponse(Box<Spec<FrequencyResponseSection>>),
    /// A chain of masses in the time domain.
    Chain(Box<Spec<ChainSection>>),
    /// Output-only modal analysis of one record.
    Operational(Box<Spec<OperationalSection>>),
    /// Output-only modal analysis of a series of records (`[[operational.records]]`).
    OperationalSeries(Box<Spec<OperationalSection>>),
}

impl From<Config> for Experiment {
    fn from(config: Config) -> Self {
        /// `config` with its section `S` taken as a value, wrapped by `kind`.
        fn spec<S: KindSection>(
            config: Config,
            kind: fn(Box<Spec<S>>) -> Experiment,
        ) -> Experiment {
            match S::of(&config).cloned() {
                Some(section) => kind(Box::new(Spec { config, section })),
                // `of` found the kind by its section, so it is there.
                None => Experiment::Paper(Box::new(config)),
            }
        }
        match ExperimentKind::of(&config) {
            ExperimentKind::Paper => Self::Paper(Box::new(config)),
            ExperimentKind::Setup => spec(config, Self::Setup),
            ExperimentKind::FrequencyResponse => spec(config, Self::FrequencyResponse),
            ExperimentKind::Chain => spec(config, Self::Chain),
            ExperimentKind::Operational
                if config
                    .operational
                    .as_ref()
                    .is_some_and(|o| !o.records.is_empty()) =>
            {
                spec(config, Self::OperationalSeries)
            }
            ExperimentKind::Operational => spec(config, Self::Operational),
        }
    }
}

impl Experiment {
    /// Its kind.
    pub fn kind(&self) -> ExperimentKind {
        match self {
            Self::Paper(_) => ExperimentKind::Paper,
            Self::Setup(_) => ExperimentKind::Setup,
            Self::FrequencyResponse(_) => ExperimentKind::FrequencyResponse,
            Self::Chain(_) => ExperimentKind::Chain,
            Self::Operational(_) | Self::OperationalSeries(_) => ExperimentKind::Operational,
        }
    }

    /// The config as read.
    pub fn config(&self) -> &Config {
        match self {
            Self::Paper(config) => config,
            Self::Setup(s) => &s.config,
            Self::FrequencyResponse(s) => &s.config,
            Self::Chain(s) => &s.config,
            Self::Operational(s) | Self::OperationalSeries(s) => &s.config,
        }
    }
}
