//! Frequency-domain experiments (`[frequency_response]`, [`FrequencyResponseSection`]):
//! a frequency response simulated or read, one mode or several fitted to it with 95 %
//! intervals, the classroom peak-picking and half-power estimates beside the fit, and
//! the truth when the plant is known.
//!
//! [`run`] computes an [`FrfOutcome`]; [`crate::run_experiment`] also writes its figures
//! (`frf_fit_bode`, `frf_fit_nyquist`, `frf_coherence`, `frf_stabilization`),
//! `report.md`, `report.html` and `results.json` into one folder atomically, through the
//! one writer of every kind ([`crate::run`]). When the frequency response comes from
//! time records, the same records are also fitted in the time domain and the two
//! estimates compared ([`TimeDomain`]).
//!
//! ```
//! use msd_experiment::{RunOptions, config::Config, frf};
//! let text = r#"
//!     name = "sweep"
//!     [frequency_response.plant]
//!     masses = [2.5]
//!     springs = [120.0]
//!     dampers = [1.8]
//!     [frequency_response.sweep]
//!     band_hz = [0.25, 2.5]
//!     lines = 40
//! "#;
//! let config = Config::from_toml_str(text, "sweep.toml")?;
//! let outcome = frf::run(config, "sweep.toml".as_ref(), &RunOptions::default())?;
//! let frf::FrfFit::OneMode(fit) = &outcome.fit else { panic!("one mode") };
//! assert!(fit.uncertainty.stiffness.contains(120.0));
//! assert!(outcome.to_string().starts_with("sweep: one mode fitted to 40 lines"));
//! # Ok::<(), msd_experiment::ExperimentError>(())
//! ```
//!
//! [`FrequencyResponseSection`]: crate::config::FrequencyResponseSection

mod csv;
mod plots;
mod plots_set;
mod report;
mod report_set;
mod results;
mod simulate;
mod source;
mod time_domain;
mod uff;
mod uff_out;

use crate::config::{ChainPlant, Config};
use crate::{ExperimentError, Result, RunOptions};
use msd_ident::{
    ModalFit, OneModeFit, fit_modes, fit_one_mode,
    frf::{HalfPower, ModalParameters, ModeSetFit, SetMember, fit_mode_set, half_power},
};
use msd_signal::FrequencyResponseEstimate;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

pub use results::to_json;
pub use time_domain::{Difference, TimeDomain, TimeFit};

/// What was fitted: one mode or several.
#[derive(Debug, Clone)]
pub enum FrfFit {
    /// m, c, k (and fn, ζ, the gain) with intervals.
    OneMode(Box<OneModeFit>),
    /// The modes of the stabilization diagram, polished, with intervals.
    Modes(Box<ModalFit>),
    /// Modes common to a set of FRFs, with their shapes.
    Set(Box<ModeSetFit>),
}

impl FrfFit {
    /// The first and last line fitted, Hz.
    pub fn band_hz(&self) -> [f64; 2] {
        match self {
            FrfFit::OneMode(f) => f.band_hz,
            FrfFit::Modes(m) => m.band_hz,
            FrfFit::Set(m) => m.band_hz,
        }
    }

    /// Every fitted mode's fn and ζ with their intervals.
    pub fn poles(&self) -> Vec<(msd_ident::Interval, msd_ident::Interval)> {
        match self {
            FrfFit::OneMode(f) => vec![(
                f.uncertainty.natural_frequency_hz,
                f.uncertainty.damping_ratio,
            )],
            FrfFit::Modes(m) => m
                .modes
                .iter()
                .map(|m| (m.natural_frequency_hz, m.damping_ratio))
                .collect(),
            FrfFit::Set(m) => m
                .modes
                .iter()
                .map(|m| (m.natural_frequency_hz, m.damping_ratio))
                .collect(),
        }
    }
}

/// The known plant of a synthetic config (or the truth a file is compared with).
#[derive(Debug, Clone)]
pub struct Truth {
    /// The plant as configured.
    pub plant: ChainPlant,
    /// Its modes (eigenvalues of the state matrix, modal constants of the receptance
    /// measured), by frequency.
    pub modes: Vec<ModalParameters>,
}

/// Everything a frequency-domain experiment produced.
#[derive(Debug, Clone)]
pub struct FrfOutcome {
    /// The config as read.
    pub config: Config,
    /// The config file as given.
    pub config_path: PathBuf,
    /// The command that ran it, for the report.
    pub command: String,
    /// The seed of the simulated noise.
    pub seed: u64,
    /// Where the frequency response came from, in words.
    pub source: String,
    /// The frequency response (a set's first member).
    pub data: FrequencyResponseEstimate,
    /// A set's FRFs with their DOFs (empty unless the source is a set).
    pub members: Vec<SetMember>,
    /// The fit.
    pub fit: FrfFit,
    /// Peak picking and half-power bandwidth, one per fitted mode (`None` where the peak
    /// cannot be read).
    pub classroom: Vec<Option<HalfPower>>,
    /// The truth, when the plant is given.
    pub truth: Option<Truth>,
    /// The time-domain fit of the same records and the comparison, when the frequency
    /// response was estimated from time records.
    pub time_domain: Option<TimeDomain>,
    /// Wall time of each stage.
    pub timings: Vec<(&'static str, Duration)>,
}

/// Reads or simulates the frequency response of `config`'s `[frequency_response]`
/// section and fits it (nothing is written). `options.seed` overrides the config's.
pub fn run(config: Config, config_path: &Path, options: &RunOptions) -> Result<FrfOutcome> {
    let Some(section) = config.frequency_response.clone() else {
        return Err(ExperimentError::config(
            config_path,
            "frequency_response: missing section",
        ));
    };
    let seed = options.seed.unwrap_or(config.seed);
    let t = Instant::now();
    let dir = config_path.parent().unwrap_or(Path::new(""));
    let loaded = source::load(&section, dir, seed)?;
    let mut timings = vec![("data", t.elapsed())];
    let t = Instant::now();
    let fail = |e: msd_ident::IdentError| fit_failure(e, &section, &loaded.frf);
    let fit = match &section.modes {
        _ if !loaded.members.is_empty() => {
            let options = section.modes.unwrap_or_default();
            if let Some((i, r)) = section
                .reference_modes
                .iter()
                .flatten()
                .enumerate()
                .find(|(_, r)| r.shape.len() != loaded.members.len())
            {
                return Err(ExperimentError::config(
                    format!("frequency_response.reference_modes[{i}].shape"),
                    format!(
                        "{} values: expected one per FRF of the set ({})",
                        r.shape.len(),
                        loaded.members.len()
                    ),
                ));
            }
            FrfFit::Set(Box::new(
                fit_mode_set(&loaded.members, &options).map_err(fail)?,
            ))
        }
        Some(options) => FrfFit::Modes(Box::new(fit_modes(&loaded.frf, options).map_err(fail)?)),
        None => {
            let fit = fit_one_mode(&loaded.frf, &section.one_mode).map_err(fail)?;
            if fit.negative_modal_constant && section.force_scale_known {
                return Err(ExperimentError::config(
                    "frequency_response.force_scale_known",
                    format!(
                        "true, but the mode at {:.4} Hz has a negative modal constant (gain {:.4e}): a point FRF's m, c and k are positive, so this is a transfer FRF or a response of reversed sign; set force_scale_known = false for fn, ζ and the (negative) gain",
                        fit.parameters.natural_frequency_hz(),
                        fit.gain.value
                    ),
                ));
            }
            FrfFit::OneMode(Box::new(fit))
        }
    };
    let classroom = classroom(&loaded.frf, &fit);
    timings.push(("fit", t.elapsed()));
    let truth = section.plant.map(|plant| Truth {
        modes: plant.modes(),
        plant,
    });
    let t = Instant::now();
    let time_domain = loaded.time.as_ref().map(|records| {
        time_domain::compare(records, &fit, truth.as_ref(), section.force_scale_known)
    });
    if time_domain.is_some() {
        timings.push(("time-domain fit", t.elapsed()));
    }
    Ok(FrfOutcome {
        command: options.command.clone().unwrap_or_else(|| "msd run".into()),
        config_path: config_path.to_path_buf(),
        config,
        seed,
        source: loaded.description,
        data: loaded.frf,
        members: loaded.members,
        fit,
        classroom,
        truth,
        time_domain,
        timings,
    })
}

/// The classroom estimates of every fitted mode: the one-mode fit's own, or for several
/// modes each peak in the band between the geometric means of its neighbours' fn.
fn classroom(frf: &FrequencyResponseEstimate, fit: &FrfFit) -> Vec<Option<HalfPower>> {
    match fit {
        FrfFit::OneMode(f) => vec![f.half_power],
        FrfFit::Modes(_) | FrfFit::Set(_) => {
            let f: Vec<f64> = fit.poles().iter().map(|p| p.0.value).collect();
            let [low, high] = fit.band_hz();
            (0..f.len())
                .map(|r| {
                    let from = if r == 0 {
                        low
                    } else {
                        (f[r - 1] * f[r]).sqrt()
                    };
                    let to = f.get(r + 1).map_or(high, |next| (f[r] * next).sqrt());
                    half_power(frf, Some([from, to])).ok()
                })
                .collect()
        }
    }
}

/// A fit's refusal that the config or the data cause, as a config error naming the key
/// with the data's range (exit 2): too few lines in the band, an option out of range,
/// more modes asked for than the diagram holds. Other failures stay run failures.
fn fit_failure(
    e: msd_ident::IdentError,
    section: &crate::config::FrequencyResponseSection,
    data: &FrequencyResponseEstimate,
) -> ExperimentError {
    use msd_ident::IdentError;
    let several = section.modes.is_some()
        || section.set.is_some()
        || section.uff.as_ref().is_some_and(|u| u.set);
    let part = if several { "modes" } else { "one_mode" };
    let key = |name: &str| format!("frequency_response.{part}.{name}");
    let n = data.frequency.len();
    let range = format!(
        "the data hold {n} lines, {}–{} Hz",
        data.frequency[0],
        data.frequency[n - 1]
    );
    match e {
        IdentError::TooFewSamples { got, needed, why } => ExperimentError::config(
            key("band_hz"),
            format!(
                "{got} {why}: expected at least {needed} ({range}); widen the band, or measure more lines"
            ),
        ),
        IdentError::InvalidParameter {
            name,
            value,
            expected,
        } => ExperimentError::config(key(name), format!("{value}: expected {expected}")),
        IdentError::NotIdentifiable { reason } if reason.contains("were asked for") => {
            ExperimentError::config(key("mode_count"), reason)
        }
        e => ExperimentError::run("frequency-response fit", e),
    }
}

/// The config's `reference_modes`, when it gives them.
pub(crate) fn reference_modes(o: &FrfOutcome) -> Option<&[crate::config::ReferenceMode]> {
    o.config
        .frequency_response
        .as_ref()
        .and_then(|s| s.reference_modes.as_deref())
}

/// MAC of each fitted shape with the reference mode of the same rank (as many as both
/// have).
pub fn reference_mac(m: &ModeSetFit, reference: &[crate::config::ReferenceMode]) -> Vec<f64> {
    m.modes
        .iter()
        .zip(reference)
        .map(|(mode, truth)| {
            let a: Vec<msd_signal::Complex64> = mode
                .shape
                .iter()
                .map(|e| msd_signal::Complex64::new(e.re, e.im))
                .collect();
            let b: Vec<msd_signal::Complex64> = truth
                .shape
                .iter()
                .map(|&x| msd_signal::Complex64::new(x, 0.0))
                .collect();
            if a.len() == b.len() {
                msd_ident::frf::mac(&a, &b)
            } else {
                f64::NAN
            }
        })
        .collect()
}

impl FrfOutcome {
    /// The fitted model's response at `frequency_hz`, in the data's quantity
    /// (receptance × (jω)^p), as the data show it (windowed when they are).
    pub fn model_response(&self, frequency_hz: f64) -> msd_signal::Complex64 {
        let receptance = match &self.fit {
            FrfFit::OneMode(f) => f.response(frequency_hz),
            FrfFit::Modes(m) => m.response(frequency_hz),
            FrfFit::Set(m) => m.response(0, frequency_hz),
        };
        let jw = msd_signal::Complex64::new(0.0, std::f64::consts::TAU * frequency_hz);
        receptance * jw.powi(power(self.data.kind))
    }
}

/// The power p of jω in the data's quantity = (jω)^p × receptance.
fn power(kind: msd_signal::FrfKind) -> i32 {
    match kind {
        msd_signal::FrfKind::Receptance => 0,
        msd_signal::FrfKind::Mobility => 1,
        msd_signal::FrfKind::Accelerance => 2,
    }
}

impl std::fmt::Display for FrfOutcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let name = &self.config.name;
        match &self.fit {
            FrfFit::OneMode(fit) => write!(f, "{name}: {fit}")?,
            FrfFit::Modes(fit) => write!(f, "{name}: {fit}")?,
            FrfFit::Set(fit) => write!(f, "{name}: {fit}")?,
        }
        if let Some(t) = &self.truth {
            let covered = report::covered(self, t);
            write!(f, "\ntruth inside the 95 % intervals: {covered}")?;
        }
        if let Some(td) = &self.time_domain {
            write!(f, "\n{td}")?;
        }
        Ok(())
    }
}

// The parts the writer (`crate::run`) takes besides `to_json`: the figures and the report.
pub(crate) use plots::write_all as figures;
pub(crate) use report::markdown as report;
