//! Sequential design: the prior plant, the robust box and the noise level from a pilot
//! test instead of a guess.
//!
//! A design config with a `[pilot]` section has no `[plant]`: the pilot's estimate of m,
//! c and k is the prior, the box is three of its largest relative standard errors wide
//! ([`msd_ident::design::RobustBox::around`]), and without a `[noise]` section the pilot's noise
//! estimate σ̂ is the planned test's noise. The pilot is either a config, run first
//! (its data generated or read and m, c, k estimated, as `experiment` does), or the
//! `results.json` of a pilot run already made.
//!
//! ```
//! use msd_experiment::design::{PilotSection, Pilot};
//! let section = PilotSection { config: Some("paper-fast.toml".into()), results: None };
//! let pilot = Pilot::load(&section, "../../configs/design-sequential.toml".as_ref())?;
//! assert_eq!(pilot.name, "paper-fast");
//! // The paper's test pins the plant (m = 2.5, c = 1.8, k = 120) to a fraction of a percent.
//! assert!((pilot.plant().stiffness / 120.0 - 1.0).abs() < 0.005);
//! # Ok::<(), msd_experiment::ExperimentError>(())
//! ```

use crate::config::{Config, PilotSection};
use crate::error::{ExperimentError, Result};
use msd_ident::{Interval, Parameters};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A pilot's estimate, as a sequential design uses it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Pilot {
    /// The pilot experiment's name.
    pub name: String,
    /// The file it was read from (the config run, or the results file).
    pub source: PathBuf,
    /// Its m, c, k with their standard errors and 95 % intervals.
    pub estimate: [Interval; 3],
    /// Its estimate σ̂ of the noise, in the output unit.
    pub noise_sigma: f64,
}

impl Pilot {
    /// Runs or reads the pilot of `section`; `design_config` resolves its path and names
    /// the design config in errors.
    pub fn load(section: &PilotSection, design_config: &Path) -> Result<Self> {
        let folder = design_config.parent().unwrap_or(Path::new(""));
        match (&section.config, &section.results) {
            (Some(config), None) => run(&folder.join(config), design_config),
            (None, Some(results)) => read(&folder.join(results)),
            _ => Err(ExperimentError::config(
                design_config,
                "pilot: expected exactly one of `config` and `results`",
            )),
        }
    }

    /// The pilot itself if it can be a prior: a physical plant, σ̂ > 0 and finite
    /// standard errors ≥ 0; otherwise an error naming its source and the value.
    fn checked(self) -> Result<Self> {
        let bad = |what: String| ExperimentError::data(&self.source, format!("the pilot's {what}"));
        self.plant()
            .validate()
            .map_err(|err| bad(format!("estimate: {err}")))?;
        if !(self.noise_sigma.is_finite() && self.noise_sigma > 0.0) {
            return Err(bad(format!(
                "estimate.noise_sigma = {}: expected a finite σ̂ > 0",
                self.noise_sigma
            )));
        }
        for (name, iv) in ["mass", "damping", "stiffness"].iter().zip(&self.estimate) {
            if !(iv.standard_error.is_finite() && iv.standard_error >= 0.0) {
                return Err(bad(format!(
                    "estimate.{name}.standard_error = {}: expected a finite value ≥ 0",
                    iv.standard_error
                )));
            }
        }
        Ok(self)
    }

    /// The estimate as the design's prior plant.
    pub fn plant(&self) -> Parameters {
        let [m, c, k] = self.estimate;
        Parameters {
            mass: m.value,
            damping: c.value,
            stiffness: k.value,
        }
    }
}

impl std::fmt::Display for Pilot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let [m, c, k] = self.estimate;
        write!(
            f,
            "  prior from the pilot `{}` ({}): m {:.5} ± {:.2e}, c {:.5} ± {:.2e}, k {:.4} ± {:.2e}, σ̂ {:.3e}",
            self.name,
            self.source.display(),
            m.value,
            m.standard_error,
            c.value,
            c.standard_error,
            k.value,
            k.standard_error,
            self.noise_sigma
        )
    }
}

/// Loads the pilot config at `path`, generates or reads its identification record and
/// estimates m, c, k as the config says.
fn run(path: &Path, design_config: &Path) -> Result<Pilot> {
    let config = Config::load(path)?;
    if config.setup.is_some() || config.frequency_response.is_some() || config.pilot.is_some() {
        return Err(ExperimentError::config(
            design_config,
            format!(
                "pilot.config = {:?}: a [setup], [frequency_response] or [pilot] config: expected a force-and-displacement experiment (as configs/paper-fast.toml)",
                path.display().to_string()
            ),
        ));
    }
    let data = crate::data::load(&config, path, config.seed)?;
    let fit = msd_ident::estimate(&data.identification, &config.estimation)
        .map_err(|e| ExperimentError::run("design: pilot estimation", e))?;
    let u = &fit.uncertainty;
    Pilot {
        name: config.name,
        source: path.to_path_buf(),
        estimate: [u.mass, u.damping, u.stiffness],
        noise_sigma: u.sigma,
    }
    .checked()
}

/// The parts of a `results.json` a design reads.
#[derive(Deserialize)]
struct Results {
    experiment: ExperimentName,
    estimate: Estimate,
}

#[derive(Deserialize)]
struct ExperimentName {
    name: String,
    /// `synthetic` or `measured` (a time-domain run), `frequency_response`.
    #[serde(default)]
    kind: Option<String>,
}

#[derive(Deserialize)]
struct Estimate {
    mass: Interval,
    damping: Interval,
    stiffness: Interval,
    noise_sigma: f64,
}

/// Reads a pilot run's `results.json`.
fn read(path: &Path) -> Result<Pilot> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        ExperimentError::data(path, format!("cannot read the pilot's results: {e}"))
    })?;
    let results: Results = serde_json::from_str(&text).map_err(|e| {
        ExperimentError::data(
            path,
            format!("{e}: expected the results.json of a force-and-displacement run (`cargo xtask experiment`), with experiment.name and estimate.mass, .damping, .stiffness, .noise_sigma"),
        )
    })?;
    if results.experiment.kind.as_deref() == Some("frequency_response") {
        return Err(ExperimentError::data(
            path,
            "pilot.results: the results.json of a frequency-response run (experiment.kind = \"frequency_response\"): its noise_sigma is a relative error of the FRF, not the displacement noise a design needs; expected the results.json of a force-and-displacement run (`cargo xtask experiment`)",
        ));
    }
    let e = results.estimate;
    Pilot {
        name: results.experiment.name,
        source: path.to_path_buf(),
        estimate: [e.mass, e.damping, e.stiffness],
        noise_sigma: e.noise_sigma,
    }
    .checked()
}
