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
//! use msd_experiment::{RunOptions, config::{Config, Spec}, frf};
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
//! let outcome = frf::run(Spec::new(config)?, &RunOptions::default())?;
//! let frf::FrfFit::OneMode(fit) = &outcome.fit else { panic!("one mode") };
//! assert!(fit.uncertainty.stiffness.contains(120.0));
//! assert!(outcome.to_string().starts_with("experiment `sweep` (a frequency response: one mode fitted to 40 lines"));
//! # Ok::<(), msd_experiment::ExperimentError>(())
//! ```
//!
//! [`FrequencyResponseSection`]: crate::config::FrequencyResponseSection

mod csv;
mod plots;
mod plots_modes;
mod plots_set;
mod report;
mod report_set;
mod results;
mod shape_files;
mod simulate;
mod source;
mod summary;
mod time_domain;
mod uff;
pub(crate) mod uff_out;
mod verdict;

use crate::config::{ChainPlant, Config, FrequencyResponseSection, Spec};
use crate::{
    error::{ExperimentError, Result},
    options::RunOptions,
};
use msd_ident::{OneModeFit, fit_one_mode};
use msd_modal::{
    Dof, HalfPower, ModalError, ModalFit, ModalParameters, ModeIndicator, ModeSetFit, SetMember,
    StabilizationDiagram, fit_mode_set, fit_modes, half_power, mode_indicator,
};
use msd_signal::{FrequencyResponseEstimate, Window};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

pub use results::to_json;
pub use shape_files::ReferenceShapes;
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

    /// The lines' weighting.
    pub fn weighting(&self) -> msd_modal::FrfWeighting {
        match self {
            FrfFit::OneMode(f) => f.weighting,
            FrfFit::Modes(m) => m.weighting,
            FrfFit::Set(m) => m.weighting,
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
    /// The mode indicator functions of the data (a set's, or the one FRF's) when several
    /// modes were fitted.
    pub indicator: Option<ModeIndicator>,
    /// A set's shapes against those of `reference_shapes`, when the config gives it.
    pub reference_shapes: Option<ReferenceShapes>,
    /// The nodes a set's shapes are drawn on (`geometry`, or the set's UFF file's own),
    /// empty when there are none.
    pub geometry: Vec<msd_uff::Node>,
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
    /// Whether the estimates can be trusted, and why.
    pub verdict: crate::verdict::Verdict,
}

/// Reads or simulates the frequency response of `config`'s `[frequency_response]`
/// section and fits it (nothing is written). `options.seed` overrides the config's.
pub fn run(spec: Spec<FrequencyResponseSection>, options: &RunOptions) -> Result<FrfOutcome> {
    run_keeping(spec, options).map_err(|f| f.error)
}

/// A run's failure, with the stabilization diagram when the mode selection failed (to
/// be drawn for the user: [`write_failure`]).
pub(crate) struct Failure {
    pub(crate) error: ExperimentError,
    kept: Option<Kept>,
}

/// A failed selection's diagram and the data's (summed) magnitude to draw behind it.
type Kept = (Box<StabilizationDiagram>, Vec<(f64, f64)>);

impl From<ExperimentError> for Failure {
    fn from(error: ExperimentError) -> Self {
        Self { error, kept: None }
    }
}

/// As [`run`], keeping the diagram of a failed selection.
pub(crate) fn run_keeping(
    spec: Spec<FrequencyResponseSection>,
    options: &RunOptions,
) -> std::result::Result<FrfOutcome, Failure> {
    let Spec { config, section } = spec;
    let config_path = config.sources.config_file().to_path_buf();
    let seed = options.seed.unwrap_or(config.seed);
    let t = Instant::now();
    let sources = &config.sources;
    let loaded = source::load(&section, sources, seed)?;
    let mut timings = vec![("data", t.elapsed())];
    let t = Instant::now();
    let fail = |e: msd_ident::IdentError| {
        let kept = match &e {
            msd_ident::IdentError::Modal(ModalError::TooFewModes { diagram, .. }) => {
                let members: Vec<_> = loaded.members.iter().map(|m| &m.frf).collect();
                Some((
                    diagram.clone(),
                    plots::summed_magnitude(&loaded.frf, &members),
                ))
            }
            _ => None,
        };
        Failure {
            error: fit_failure(e, &section, &loaded.frf),
            kept,
        }
    };
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
                return Err(Failure::from(ExperimentError::config(
                    format!("frequency_response.reference_modes[{i}].shape"),
                    format!(
                        "{} values: expected one per FRF of the set ({})",
                        r.shape.len(),
                        loaded.members.len()
                    ),
                )));
            }
            FrfFit::Set(Box::new(
                fit_mode_set(&loaded.members, &options).map_err(|e| fail(e.into()))?,
            ))
        }
        Some(options) => FrfFit::Modes(Box::new(
            fit_modes(&loaded.frf, options).map_err(|e| fail(e.into()))?,
        )),
        None => {
            let fit = fit_one_mode(&loaded.frf, &section.one_mode).map_err(fail)?;
            if fit.negative_modal_constant && section.force_scale_known {
                return Err(Failure::from(ExperimentError::config(
                    "frequency_response.force_scale_known",
                    format!(
                        "true, but the mode at {:.4} Hz has a negative modal constant (gain {:.4e}): a point FRF's m, c and k are positive, so this is a transfer FRF or a response of reversed sign; set force_scale_known = false for fn, ζ and the (negative) gain",
                        fit.parameters.natural_frequency_hz(),
                        fit.gain.value
                    ),
                )));
            }
            FrfFit::OneMode(Box::new(fit))
        }
    };
    let classroom = classroom(&loaded.frf, &fit);
    timings.push(("fit", t.elapsed()));
    let indicator = indicator(&loaded.frf, &loaded.members, &fit);
    let (reference_shapes, geometry) = match &fit {
        FrfFit::Set(m) => (
            section
                .reference_shapes
                .as_deref()
                .map(|file| shape_files::reference_shapes(m, file, sources))
                .transpose()?,
            shape_files::geometry(section.geometry.as_deref(), loaded.nodes, sources)?,
        ),
        _ => (None, Vec::new()),
    };
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
    let mut outcome = FrfOutcome {
        command: options.command.clone().unwrap_or_else(|| "msd run".into()),
        config_path,
        config,
        seed,
        source: loaded.description,
        data: loaded.frf,
        members: loaded.members,
        fit,
        indicator,
        reference_shapes,
        geometry,
        classroom,
        truth,
        time_domain,
        timings,
        verdict: crate::verdict::Verdict::of(Vec::new()),
    };
    outcome.verdict = verdict::verdict(&outcome);
    Ok(outcome)
}

/// Writes what a failed mode selection keeps (its stabilization diagram, PNG and SVG,
/// and `failure.md` with the error) into `<target>-failed`, atomically, and returns the
/// error saying so; any other failure is returned as it is. A previous result in
/// `target` stays untouched.
pub(crate) fn write_failure(failure: Failure, target: &Path) -> ExperimentError {
    let Some((diagram, magnitude)) = failure.kept else {
        return failure.error;
    };
    let mut name = target.file_name().unwrap_or_default().to_os_string();
    name.push("-failed");
    let kept = target.with_file_name(name);
    let written = (|| {
        crate::output::check_target(&kept)?;
        let staging = crate::output::Staging::new(&kept)?;
        plots::save_diagram(&diagram, magnitude, staging.path())?;
        let text = format!(
            "# The mode selection failed\n\n{}\n\n`frf_stabilization.png` (and `.svg`) is the stabilization diagram as computed: every order's poles, the data's magnitude behind them, and dashed lines at the modes that were selected ({} of them). Change the keys the message names and run again.\n",
            failure.error,
            diagram.modes.len()
        );
        staging.write("failure.md", text.as_bytes())?;
        staging.commit()
    })();
    match written {
        Ok(()) => ExperimentError::Kept {
            error: Box::new(failure.error),
            kept: kept.join("frf_stabilization.png"),
        },
        Err(_) => failure.error,
    }
}

/// The mode indicator functions of a set, or of the one FRF, when modes were fitted
/// (`None` for one mode).
fn indicator(
    frf: &FrequencyResponseEstimate,
    members: &[SetMember],
    fit: &FrfFit,
) -> Option<ModeIndicator> {
    match fit {
        FrfFit::OneMode(_) => None,
        FrfFit::Set(_) => mode_indicator(members).ok(),
        FrfFit::Modes(_) => {
            let point = Dof {
                node: 1,
                direction: 1,
            };
            let one = SetMember {
                frf: frf.clone(),
                response: point,
                reference: point,
            };
            mode_indicator(&[one]).ok()
        }
    }
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
/// more modes asked for than the diagram holds, no mode selected (a band with no peak,
/// too low orders). Other failures stay run failures.
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
    let count_given = section
        .modes
        .as_ref()
        .is_some_and(|m| m.mode_count.is_some());
    let n = data.frequency.len();
    let range = format!(
        "the data{} hold {n} lines, {}–{} Hz",
        section
            .data_file()
            .map_or(String::new(), |p| format!(" of {}", p.display())),
        data.frequency[0],
        data.frequency[n - 1]
    );
    match e {
        IdentError::Modal(ModalError::TooFewSamples { got, needed, why }) => {
            ExperimentError::config(
                key("band_hz"),
                format!(
                    "{got} {why}: expected at least {needed} ({range}); widen the band, or measure more lines"
                ),
            )
        }
        IdentError::Modal(ModalError::InvalidParameter {
            name,
            value,
            expected,
        }) => ExperimentError::config(key(name), format!("{value}: expected {expected}")),
        // With `mode_count`, the diagram held fewer modes at peaks than it asks for.
        IdentError::Modal(ModalError::TooFewModes { reason, .. }) if count_given => {
            ExperimentError::config(key("mode_count"), reason)
        }
        // The selection found nothing with these settings (the band, the orders, the
        // weighting): the keys to change are in the reason.
        IdentError::Modal(ModalError::TooFewModes { reason, .. }) => ExperimentError::config(
            format!("frequency_response.{part}"),
            format!("{reason} ({range})"),
        ),
        // One mode fitted to lines that hold no resonance (a band beside it, or records
        // too short to resolve it): the data and the band are the user's to change.
        IdentError::NotIdentifiable { reason } if reason.contains("no resonance in the band") => {
            ExperimentError::config(
                key("band_hz"),
                format!(
                    "{reason} ({range}); choose a band around the resonance, or measure longer records (finer lines)"
                ),
            )
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
                msd_modal::mac(&a, &b)
            } else {
                f64::NAN
            }
        })
        .collect()
}

impl FrfOutcome {
    /// Lines of a response estimated from time records whose input has no power there
    /// (below [`msd_signal::UNEXCITED`] of its largest line: the lines between a periodic
    /// input's own): response and coherence 0, left out of the fit. 0 for a table or a
    /// file.
    pub fn unexcited_lines(&self) -> usize {
        if self.time_domain.is_none() {
            return 0;
        }
        let d = &self.data;
        (d.h.iter().zip(&d.coherence))
            .filter(|(h, g)| h.norm_sqr() == 0.0 && **g == 0.0)
            .count()
    }

    /// Whether `welch.window = "auto"` (the default) took the time records with a
    /// rectangular window, their force repeating from record to record
    /// ([`msd_signal::resolve_window`]).
    pub fn chose_rectangular_window(&self) -> bool {
        let options = self
            .config
            .frequency_response
            .as_ref()
            .map(|f| &f.estimator);
        self.time_domain.is_some()
            && options.is_some_and(|e| e.impact.is_none() && e.welch.window == Window::Auto)
            && self.data.noise_bandwidth == 1.0
    }

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

/// The summary the command prints, but for the writer's footer (in the one format of
/// every kind's summary).
impl std::fmt::Display for FrfOutcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&summary::text(self))
    }
}

// The parts the writer (`crate::run`) takes besides `to_json`: the figures and the report.
pub(crate) use plots::write_all as figures;
pub(crate) use report::markdown as report;

impl crate::finished::Finished for FrfOutcome {
    fn config(&self) -> &Config {
        &self.config
    }

    fn figures(&self, dir: &Path) -> Result<Vec<&'static str>> {
        figures(self, dir)
    }

    fn timings(&self) -> &[(&'static str, Duration)] {
        &self.timings
    }

    fn report(&self, figures: &[&str]) -> String {
        report(self, figures)
    }

    fn results(
        &self,
        extra: &[(&'static str, Duration)],
        total: Duration,
    ) -> Result<serde_json::Value> {
        Ok(to_json(self, extra, total))
    }

    fn summary(&self) -> String {
        self.to_string()
    }
}
