//! `plan`: the uncertainty a synthetic config's experiment will give, before it is run.
//!
//! The config's `[plant]` is the prior guess of the real plant, its identification
//! input, time grid and noise level the planned test, its `[estimation]` what will be
//! estimated. The prediction is the Cramér–Rao bound from the exact sensitivities
//! ([`msd_ident::predicted_uncertainty`]); beside it, what reaches a target precision
//! (the force scales the standard errors exactly; a longer record is found by search),
//! and with `verify` the spread of that many simulated experiments, to check it.
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

use crate::config::Config;
use crate::{ExperimentError, Result};
use msd_ident::{Uncertainty, estimate, predicted_uncertainty};
use serde::Serialize;
use std::path::Path;

/// Options of [`plan`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PlanOptions {
    /// Target 95 % half-width, relative to the value. By default 0.01 (±1 %).
    pub target: f64,
    /// Simulated experiments to check the prediction with (0: none). By default 0.
    pub verify: usize,
}

impl Default for PlanOptions {
    fn default() -> Self {
        Self {
            target: 0.01,
            verify: 0,
        }
    }
}

/// One predicted quantity.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlannedQuantity {
    /// Its name (`mass`, `damping`, `stiffness`, `natural_frequency_hz`, `damping_ratio`).
    pub name: &'static str,
    /// The prior value.
    pub value: f64,
    /// The predicted standard error.
    pub standard_error: f64,
    /// The 95 % half-width relative to the value.
    pub relative_half_width: f64,
    /// The factor on the force that reaches the target (exact: errors scale as 1/force).
    pub force_factor: f64,
    /// The record length that reaches the target at this force, s (`None` when no record
    /// up to 64 times as long does, e.g. because the input ends).
    pub duration_needed_s: Option<f64>,
    /// The standard deviation over the simulated experiments, when verified.
    pub simulated_standard_deviation: Option<f64>,
}

/// The predicted precision of a planned experiment.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plan {
    /// The config's name.
    pub name: String,
    /// Noise σ, in the output unit.
    pub noise_sigma: f64,
    /// Samples and length of the identification record, s.
    pub samples: usize,
    /// Length of the record, s.
    pub duration_s: f64,
    /// Largest |force| of the input.
    pub peak_force: f64,
    /// The target relative 95 % half-width.
    pub target: f64,
    /// m, c, k, fn and ζ.
    pub quantities: Vec<PlannedQuantity>,
    /// The prediction in full (covariance, correlation, condition number).
    pub uncertainty: Uncertainty,
    /// Simulated experiments run to check the prediction.
    pub verified_with: usize,
}

impl Plan {
    /// The quantity named `name`.
    pub fn quantity(&self, name: &str) -> Option<&PlannedQuantity> {
        self.quantities.iter().find(|q| q.name == name)
    }
}

impl std::fmt::Display for Plan {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "plan `{}`: {} samples over {:.4} s, peak force {:.4}, noise σ = {:.3e}",
            self.name, self.samples, self.duration_s, self.peak_force, self.noise_sigma
        )?;
        let verified = self.verified_with > 0;
        write!(
            f,
            "  {:<22} {:>12} {:>11} {:>9}",
            "quantity", "prior", "std error", "±95 %"
        )?;
        if verified {
            write!(f, " {:>13}", format!("sd of {}", self.verified_with))?;
        }
        writeln!(f)?;
        for q in &self.quantities {
            write!(
                f,
                "  {:<22} {:>12.6} {:>11.3e} {:>8.3} %",
                q.name,
                q.value,
                q.standard_error,
                100.0 * q.relative_half_width
            )?;
            if let Some(sd) = q.simulated_standard_deviation {
                write!(f, " {sd:>13.3e}")?;
            }
            writeln!(f)?;
        }
        for q in self
            .quantities
            .iter()
            .filter(|q| q.relative_half_width > self.target)
        {
            let longer = q.duration_needed_s.map_or_else(
                || "a longer record of this input does not get there".to_string(),
                |d| format!("record {d:.3} s at this force"),
            );
            writeln!(
                f,
                "  {} to ±{} %: {longer}, or raise the force {:.2}× (peak {:.4})",
                q.name,
                100.0 * self.target,
                q.force_factor,
                q.force_factor * self.peak_force
            )?;
        }
        if self
            .quantities
            .iter()
            .all(|q| q.relative_half_width <= self.target)
        {
            writeln!(
                f,
                "  every quantity within ±{} % (95 %)",
                100.0 * self.target
            )?;
        }
        Ok(())
    }
}

/// Predicts the precision of the experiment `config_path` describes (a synthetic
/// config: its `[plant]` as the prior guess).
pub fn plan(config_path: &Path, options: &PlanOptions) -> Result<Plan> {
    let config = Config::load(config_path)?;
    if !(options.target.is_finite() && options.target > 0.0) {
        return Err(ExperimentError::config(
            config_path,
            format!(
                "--target = {}: expected a relative half-width > 0, e.g. 0.01",
                options.target
            ),
        ));
    }
    let (plant, sigma) = match (&config.plant, &config.noise, &config.time) {
        (Some(plant), Some(noise), Some(_)) if noise.sigma > 0.0 => {
            (plant.parameters(), noise.sigma)
        }
        _ => {
            return Err(ExperimentError::config(
                config_path,
                "plan needs a synthetic config: [plant] (the prior guess of the plant), [time], [identification.input] and [noise] with sigma > 0",
            ));
        }
    };
    let predict = |config: &Config| -> Result<(Uncertainty, msd_ident::DataSet)> {
        let data = crate::data::load(config, config_path, config.seed)?;
        let u = predicted_uncertainty(
            &plant,
            &data.identification.excitation,
            sigma,
            &config.estimation,
        )
        .map_err(|e| {
            ExperimentError::config(config_path, format!("the planned experiment: {e}"))
        })?;
        Ok((u, data.identification))
    };
    let (uncertainty, record) = predict(&config)?;
    let names = [
        "mass",
        "damping",
        "stiffness",
        "natural_frequency_hz",
        "damping_ratio",
    ];
    let widths = |u: &Uncertainty| intervals(u).map(|iv| (iv.ci95[1] - iv.value) / iv.value.abs());
    let now = widths(&uncertainty);
    let verified = verify(&config, config_path, options.verify)?;
    let mut quantities = Vec::new();
    for (q, iv) in intervals(&uncertainty).into_iter().enumerate() {
        let duration_needed_s = duration_needed(
            &config,
            now[q],
            |c| Ok(widths(&predict(c)?.0)[q]),
            options.target,
        )?;
        quantities.push(PlannedQuantity {
            name: names[q],
            value: iv.value,
            standard_error: iv.standard_error,
            relative_half_width: now[q],
            force_factor: now[q] / options.target,
            duration_needed_s,
            simulated_standard_deviation: verified.as_ref().map(|v| v[q]),
        });
    }
    Ok(Plan {
        name: config.name.clone(),
        noise_sigma: sigma,
        samples: record.len(),
        duration_s: record.excitation.dt() * (record.len() - 1) as f64,
        peak_force: record
            .excitation
            .samples()
            .iter()
            .fold(0.0, |m, f| m.max(f.abs())),
        target: options.target,
        quantities,
        uncertainty,
        verified_with: options.verify,
    })
}

fn intervals(u: &Uncertainty) -> [msd_ident::Interval; 5] {
    [
        u.mass,
        u.damping,
        u.stiffness,
        u.natural_frequency_hz,
        u.damping_ratio,
    ]
}

/// The shortest record (to 1 %) whose predicted relative half-width `width(config)` is
/// within `target`, given the config's own `now`: doubling the duration up to 64×, then
/// bisection.
fn duration_needed(
    config: &Config,
    now: f64,
    width: impl Fn(&Config) -> Result<f64>,
    target: f64,
) -> Result<Option<f64>> {
    let Some(time) = config.time else {
        return Ok(None);
    };
    let at = |duration: f64| -> Result<f64> {
        let mut c = config.clone();
        c.time = Some(crate::config::TimeGrid { duration, ..time });
        width(&c)
    };
    if now <= target {
        return Ok(Some(time.duration));
    }
    let (mut low, mut high) = (time.duration, time.duration);
    loop {
        high *= 2.0;
        if high > 64.0 * time.duration {
            return Ok(None);
        }
        if at(high)? <= target {
            break;
        }
        low = high;
    }
    while high - low > 0.01 * high {
        let mid = 0.5 * (low + high);
        if at(mid)? <= target {
            high = mid;
        } else {
            low = mid;
        }
    }
    Ok(Some(high))
}

/// The standard deviations of m, c, k, fn and ζ over `seeds` simulated experiments
/// (seeds 0, 1, …), estimated as the config says.
fn verify(config: &Config, config_path: &Path, seeds: usize) -> Result<Option<[f64; 5]>> {
    if seeds == 0 {
        return Ok(None);
    }
    if seeds < 2 {
        return Err(ExperimentError::config(
            config_path,
            "--verify = 1: expected at least 2 simulated experiments (a spread needs two)",
        ));
    }
    let mut values: Vec<Vec<f64>> = (0..5).map(|_| Vec::with_capacity(seeds)).collect();
    for seed in 0..seeds as u64 {
        let data = crate::data::load(config, config_path, seed)?;
        let fit = estimate(&data.identification, &config.estimation)
            .map_err(|e| ExperimentError::run("plan --verify", e))?;
        for (v, iv) in values.iter_mut().zip(intervals(&fit.uncertainty)) {
            v.push(iv.value);
        }
    }
    let sd = |v: &[f64]| {
        let n = v.len() as f64;
        let mean = v.iter().sum::<f64>() / n;
        (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
    };
    Ok(Some([
        sd(&values[0]),
        sd(&values[1]),
        sd(&values[2]),
        sd(&values[3]),
        sd(&values[4]),
    ]))
}

/// The arguments of `plan` (`msd plan`, `cargo xtask plan`).
#[derive(Debug, Clone, clap::Args)]
pub struct PlanArgs {
    /// A synthetic experiment config: its `[plant]` is the prior guess, its input, time
    /// grid, noise and `[estimation]` the planned test.
    pub config: std::path::PathBuf,
    /// Target 95 % half-width, relative (0.01 = ±1 %).
    #[arg(long, default_value_t = 0.01)]
    pub target: f64,
    /// Check the prediction against N simulated experiments (noise seeds 0 … N−1).
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub verify: usize,
}

/// `plan`: prints the prediction (and the check) of `args.config`.
pub fn run_plan(args: &PlanArgs) -> Result<()> {
    let options = PlanOptions {
        target: args.target,
        verify: args.verify,
    };
    print!("{}", plan(&args.config, &options)?);
    Ok(())
}
