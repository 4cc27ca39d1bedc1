//! `design`: the input that will give the smallest uncertainty of m, c and k within the
//! rig's limits, designed before the test from a synthetic config with a `[design]`
//! section ([`msd_ident::design::design_input`]).
//!
//! The config's `[plant]` is the prior guess, its `[time]` grid, `[noise]` and
//! identification input the reference test the design is compared with. The outputs go
//! into the run's folder: `designed_input.csv` (`t,force`), `designed.toml` (the config
//! with the designed force as its identification input: `cargo xtask experiment` runs
//! it on the prior plant), `design.json`, and the figure `design` (PNG and SVG). With
//! `verify`, that many simulated tests of the design check its prediction. A sequential
//! design takes its prior plant, robust box and noise from a pilot test instead
//! ([`Pilot`], `[pilot]` in the config, as configs/design-sequential.toml).
//!
//! ```
//! use msd_experiment::design::{DesignRunOptions, design};
//! let options = DesignRunOptions { verify: 0, ..DesignRunOptions::default() };
//! let report = design("../../configs/design-paper.toml".as_ref(), &options)?;
//! assert!(report.design.comparison.determinant_ratio <= 0.40);
//! assert!(report.design.peak_stroke <= 0.1115);
//! # Ok::<(), msd_experiment::ExperimentError>(())
//! ```

mod pilot;

pub use crate::config::PilotSection;
pub use pilot::Pilot;

use crate::config::{Config, Noise, Plant};
use crate::error::{ExperimentError, Result};
use msd_ident::{
    IdentError,
    design::{Design, RobustBox},
    estimate,
};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Options of [`design`] and [`run_design`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DesignRunOptions {
    /// Simulated tests to check the prediction with (0: none). By default 0.
    pub verify: usize,
    /// The output folder, instead of `<results_root>/<name>-design`.
    pub out: Option<PathBuf>,
    /// Where result folders go. By default `msd-results` in the current folder.
    pub results_root: Option<PathBuf>,
    /// Whether the design and its check draw progress on stderr. By default false.
    pub progress: bool,
}

/// The spread of simulated tests of the design beside its prediction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verification {
    /// Simulated tests (noise seeds 0 … seeds − 1).
    pub seeds: usize,
    /// The standard deviations of m, c, k over them.
    pub standard_deviations: [f64; 3],
    /// Each over the predicted standard error.
    pub ratios: [f64; 3],
    /// The relative standard error of such a ratio from `seeds` Gaussian draws,
    /// 1/√(2(seeds − 1)): how far from 1 sampling alone moves it (3.5 % for 400).
    pub sampling_error: f64,
}

/// A design, its comparison with the config's input, and its check.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DesignReport {
    /// The config's name.
    pub name: String,
    /// The config as designed: with a pilot, its plant and (without `[noise]`) its noise
    /// are the pilot's.
    #[serde(skip)]
    pub config: Config,
    /// The pilot of a sequential design.
    pub pilot: Option<Pilot>,
    /// The design (signal, peaks, predicted standard errors beside the reference's).
    pub design: Design,
    /// The simulated check, when asked.
    pub verification: Option<Verification>,
    /// Time of the design stage, s.
    pub design_seconds: f64,
}

impl std::fmt::Display for DesignReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "design `{}` (designed in {:.3} s)",
            self.name, self.design_seconds
        )?;
        if let Some(pilot) = &self.pilot {
            writeln!(f, "{pilot}")?;
        }
        writeln!(f, "{}", self.design)?;
        if let Some(v) = &self.verification {
            writeln!(
                f,
                "  simulated over {} seeds: sd of m, c, k = {:.4e}, {:.4e}, {:.4e} ({:.3}, {:.3}, {:.3} × predicted, each ± {:.3} from sampling alone)",
                v.seeds,
                v.standard_deviations[0],
                v.standard_deviations[1],
                v.standard_deviations[2],
                v.ratios[0],
                v.ratios[1],
                v.ratios[2],
                v.sampling_error
            )?;
        }
        Ok(())
    }
}

/// Designs the input of the config at `config_path` (and checks it when asked); writes
/// nothing. With a `[pilot]`, the pilot is run or read first.
pub fn design(config_path: &Path, options: &DesignRunOptions) -> Result<DesignReport> {
    let (config, pilot) = resolve(Config::load(config_path)?, config_path)?;
    let refuse = |why: &str| ExperimentError::config(config_path, why.to_string());
    let Some(design_options) = config.design else {
        return Err(refuse(
            "design needs a [design] section (see configs/design-paper.toml)",
        ));
    };
    let (plant, sigma) = match (&config.plant, &config.noise) {
        (Some(plant), Some(noise)) if noise.sigma > 0.0 && config.identification.is_some() => {
            (plant.parameters(), noise.sigma)
        }
        _ => {
            return Err(refuse(
                "design needs a synthetic config: [plant] (the prior guess) or [pilot], [time], [identification.input] (the reference input) and [noise] with sigma > 0 (or a pilot's noise estimate)",
            ));
        }
    };
    if options.verify > 1 {
        crate::plan::verify_budget(&config, config_path, options.verify)?;
    }
    let reference = crate::data::load(&config, config_path, config.seed)?
        .identification
        .excitation;
    let started = Instant::now();
    let progress = crate::progress::Progress::new(options.progress);
    progress.stage(&format!(
        "design: optimising the input over {} samples",
        reference.len()
    ));
    let design = msd_ident::design::design_input(&plant, &reference, sigma, &design_options)
        .map_err(|e| match e {
            IdentError::InvalidDesign { .. } => ExperimentError::config(config_path, e.to_string()),
            e => ExperimentError::run("design", e),
        })?;
    let design_seconds = started.elapsed().as_secs_f64();
    progress.finish();
    let verification = verify(
        &designed_config(&config, &design),
        config_path,
        &design,
        options,
    )?;
    Ok(DesignReport {
        name: config.name.clone(),
        config,
        pilot,
        design,
        verification,
        design_seconds,
    })
}

/// `config` with its pilot's estimate as the plant, the pilot's σ̂ as the noise when
/// it has no `[noise]`, and the robust box around the estimate (its plants and
/// aggregate as configured).
fn resolve(mut config: Config, config_path: &Path) -> Result<(Config, Option<Pilot>)> {
    let Some(section) = &config.pilot else {
        return Ok((config, None));
    };
    let pilot = Pilot::load(section, config_path)?;
    let p = pilot.plant();
    config.plant = Some(Plant {
        mass: p.mass,
        damping: p.damping,
        stiffness: p.stiffness,
        initial_state: msd_ident::InitialState::REST,
        coulomb_force: 0.0,
        quadratic_damping: 0.0,
        cubic_stiffness: 0.0,
    });
    config.noise = config.noise.or(Some(Noise {
        sigma: pilot.noise_sigma,
    }));
    if let Some(design) = &mut config.design {
        design.robust = RobustBox {
            aggregate: design.robust.aggregate,
            ..RobustBox::around(&pilot.estimate, design.robust.plants)
        };
    }
    Ok((config, Some(pilot)))
}

/// The config that runs the designed test: `config` with the designed force as its
/// identification input, named `<name>-designed`, without `[design]`.
pub fn designed_config(config: &Config, design: &Design) -> Config {
    let mut c = config.clone();
    c.name = format!("{}-designed", config.name);
    c.description = format!(
        "The {} input designed by `design` from {}",
        design.criterion, config.name
    );
    c.identification = Some(crate::config::InputSection {
        input: design.signal.clone(),
    });
    c.design = None;
    c.pilot = None;
    c.output.dir = None;
    c
}

/// The standard deviations of m, c, k over `seeds` simulated tests of `config`.
fn verify(
    config: &Config,
    config_path: &Path,
    design: &Design,
    options: &DesignRunOptions,
) -> Result<Option<Verification>> {
    let seeds = options.verify;
    if seeds == 0 {
        return Ok(None);
    }
    if seeds < 2 {
        return Err(ExperimentError::config(
            config_path,
            "--verify = 1: expected at least 2 simulated tests",
        ));
    }
    // The prediction is of m, c and k estimated from rest without an offset; a check
    // fitted otherwise would compare two different experiments.
    let e = &config.estimation;
    let differs = [
        ("estimation.fixed", e.fixed != Default::default()),
        (
            "estimation.estimate_initial_state",
            e.estimate_initial_state,
        ),
        ("estimation.estimate_offset", e.estimate_offset),
    ];
    if let Some((key, _)) = differs.iter().find(|(_, d)| *d) {
        return Err(ExperimentError::config(
            config_path,
            format!(
                "--verify with {key} set: expected m, c and k all estimated from rest without an offset, as the design's prediction assumes (remove {key} to verify)"
            ),
        ));
    }
    let draws = crate::plan::draws(seeds, "design --verify", options.progress, |seed| {
        let data = crate::data::load(config, config_path, seed)?;
        let p = estimate(&data.identification, &config.estimation)
            .map_err(|e| ExperimentError::run("design --verify", e))?
            .parameters;
        Ok(vec![p.mass, p.damping, p.stiffness])
    })?;
    let sd = crate::plan::standard_deviations(&draws);
    let standard_deviations = [sd[0], sd[1], sd[2]];
    let predicted = design.comparison.design;
    let ratios = std::array::from_fn(|i| standard_deviations[i] / predicted[i]);
    Ok(Some(Verification {
        seeds,
        standard_deviations,
        ratios,
        sampling_error: 1.0 / (2.0 * (seeds - 1) as f64).sqrt(),
    }))
}

/// Writes `report`'s files for `config` into `target` atomically.
pub fn write(report: &DesignReport, config: &Config, target: &Path) -> Result<()> {
    crate::output::check_target(target)?;
    let staging = crate::output::Staging::new(target)?;
    let mut csv = String::from("t,force\n");
    let e = &report.design.excitation;
    for (t, u) in e.times().iter().zip(e.samples()) {
        csv.push_str(&format!("{t},{u}\n"));
    }
    staging.write("designed_input.csv", csv.as_bytes())?;
    let designed = designed_config(config, &report.design);
    let toml = toml::to_string(&designed).map_err(|e| ExperimentError::run("design", e))?;
    let header = "# Written by `design`: the designed test, synthetic on the prior plant.\n# Run it with `cargo xtask experiment designed.toml`.\n\n";
    staging.write("designed.toml", format!("{header}{toml}").as_bytes())?;
    let json =
        serde_json::to_string_pretty(report).map_err(|e| ExperimentError::run("design", e))?;
    staging.write("design.json", format!("{json}\n").as_bytes())?;
    crate::plots::register_fonts();
    crate::plots::save(
        &crate::plots::design::DesignFigure::new(&report.design),
        staging.path(),
    )?;
    staging.commit()
}

/// The arguments of `design` (`msd design`, `cargo xtask design`).
#[derive(Debug, Clone, clap::Args)]
pub struct DesignArgs {
    /// A synthetic config with a [design] section, e.g. configs/design-paper.toml. The
    /// design's cost grows with the record's samples and the robust box's plants (about
    /// 0.3 s for 7,501 samples and one plant, release); both are bounded by the budget
    /// (1.25e7 samples a record, 2e8 samples × plants), and a terminal shows its progress.
    // This line is also the --help text, where [design] is meant as written.
    #[allow(rustdoc::broken_intra_doc_links)]
    pub config: PathBuf,
    /// Output folder [default: <name>-design/ under the results folder].
    #[allow(rustdoc::invalid_html_tags)]
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Check the prediction against N simulated tests of the design (seeds 0 … N−1),
    /// each fitted: N × the test's samples count against a budget of 3e7 samples fitted,
    /// which the largest N accepted runs in about half a minute on two threads, release
    /// build (the largest N is named when it is past it). Progress is drawn on a terminal.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub verify: usize,
}

/// `design`: designs, prints the comparison and writes the files (into `--out`, else
/// `<results_root>/<name>-design`, `results_root` by default `msd-results`).
pub fn run_design(args: &DesignArgs, results_root: Option<PathBuf>) -> Result<()> {
    use std::io::IsTerminal;
    let options = DesignRunOptions {
        verify: args.verify,
        out: args.out.clone(),
        results_root,
        progress: std::io::stderr().is_terminal(),
    };
    let report = design(&args.config, &options)?;
    let config = &report.config;
    let target = options.out.clone().unwrap_or_else(|| {
        let root = options
            .results_root
            .clone()
            .unwrap_or_else(|| PathBuf::from(crate::DEFAULT_RESULTS_ROOT));
        root.join(format!("{}-design", config.name))
    });
    write(&report, config, &target)?;
    crate::output::print_stdout(&format!("{report}written: {}\n", target.display()));
    Ok(())
}
