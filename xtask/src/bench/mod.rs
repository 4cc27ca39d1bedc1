//! `cargo xtask bench`: one performance table of the paper experiment, every row a
//! median over repeated runs with its min–max and its multiple of the floor — a bare
//! 2-state linear recurrence over 7501 samples, measured in the same run (at the start
//! and at the end, so a change of load shows).
//!
//! The rows follow the issue: simulation (exact, ode45 RelTol 1e-6), one cost
//! evaluation, identification (paper and fast method), validation with residual
//! diagnostics and the frequency check, the estimation of each nonlinear model
//! structure, the Silverbox comparison of nonlinear models (when its record is fetched)
//! with one simulation by RK4 and by ode45, a three-mode frequency-domain fit, the
//! measurement setups (free decay, base excitation, the plan), the excitation design
//! (the shipped D-optimal configs, on the prior and robust), Monte Carlo N = 1000 on
//! 1 and 2 threads, the
//! whole pipeline without figures and the figures alone, and scaling in the record
//! length and the number of draws. [`report`] renders the table as text, Markdown and
//! JSON; [`harness`] times the rows.
//!
//! `cargo xtask bench` itself runs in the dev profile; it re-runs xtask in release
//! (`cargo run --release -p xtask -- bench-run`), which does the measuring.
//!
//! ```no_run
//! use xtask::bench::{BenchOptions, run};
//! let report = run(&BenchOptions::quick())?;
//! println!("{}", report.text());
//! # Ok::<(), msd_experiment::ExperimentError>(())
//! ```

mod chain;
mod design;
mod dynamometer;
pub mod first_run;
mod frequency;
mod growth;
pub mod harness;
mod oma;
pub mod report;
mod rows;
mod setups;

use crate::{ExperimentError, Result, project_root};
use harness::{Budget, Samples, measure_batched};
use msd_ident::{Backend, Excitation, InitialState, PaperExperiment, Parameters, simulate_into};
use report::{Report, Row, Target, load_average, machine};
use std::path::{Path, PathBuf};

/// Which rows a run measures and how long.
#[derive(Debug, Clone, PartialEq)]
pub struct BenchOptions {
    /// Time and repetitions per row.
    pub budget: Budget,
    /// Whether this is a `--quick` run (recorded in the report).
    pub quick: bool,
    /// Only the floor and the two simulations (for the smoke test). By default false.
    pub smoke: bool,
    /// Measure the peak memory of the pipeline in a child process running this
    /// executable (`bench-peak-memory`). By default true.
    pub peak_memory: bool,
}

impl Default for BenchOptions {
    fn default() -> Self {
        Self {
            budget: Budget::default(),
            quick: false,
            smoke: false,
            peak_memory: true,
        }
    }
}

impl BenchOptions {
    /// `--quick`: fewer repetitions per row.
    pub fn quick() -> Self {
        Self {
            budget: Budget::quick(),
            quick: true,
            ..Self::default()
        }
    }

    /// The floor and the simulations, one repetition each, no child process.
    pub fn smoke() -> Self {
        Self {
            budget: Budget::single(),
            quick: true,
            smoke: true,
            peak_memory: false,
        }
    }
}

/// Where the results go: `target/bench/` in the workspace.
pub fn out_dir() -> PathBuf {
    project_root().join("target").join("bench")
}

/// Measures every row and returns the report.
pub fn run(options: &BenchOptions) -> Result<Report> {
    let mut machine = machine();
    let experiment =
        PaperExperiment::generate(1).map_err(|e| ExperimentError::run("bench: paper data", e))?;
    let budget = &options.budget;
    let floor_start = floor(budget, &experiment.identification.excitation);

    let mut rows = Vec::new();
    let mut derived = Vec::new();
    rows.extend(rows::simulation(budget, &experiment)?);
    // Cheap enough for the smoke test, which so checks them too.
    rows.extend(setups::setups(budget, &experiment)?);
    rows.extend(dynamometer::dynamometer_rows(budget)?);
    rows.extend(chain::chain_rows(budget)?);
    if !options.smoke {
        rows.extend(rows::identification(budget, &experiment)?);
        rows.extend(rows::nonlinear(budget, &experiment)?);
        let (silverbox, silverbox_derived) = rows::silverbox(budget)?;
        rows.extend(silverbox);
        derived.extend(silverbox_derived);
        rows.extend(frequency::frequency_domain(budget)?);
        rows.extend(oma::oma_rows(budget)?);
        rows.extend(design::design_rows(budget)?);
        rows.extend(design::design_scaling(budget, &out_dir())?);
        rows.extend(growth::growth_rows(budget, &out_dir().join("growth"))?);
        let (mc, mc_derived) = rows::monte_carlo(budget, &experiment)?;
        rows.extend(mc);
        derived.extend(mc_derived);
        rows.extend(rows::pipeline(budget, &out_dir())?);
        let (scaling, scaling_derived) = rows::scaling(budget, &experiment)?;
        rows.extend(scaling);
        derived.extend(scaling_derived);
    }

    let floor_end = floor(budget, &experiment.identification.excitation);
    let floor_samples = floor_start.merged(&floor_end);
    let floor_median = floor_samples.median();
    derived.insert(
        0,
        format!(
            "floor median at the start {}, at the end {}",
            report::duration(floor_start.median()),
            report::duration(floor_end.median())
        ),
    );
    rows.insert(
        0,
        Row::new(
            "floor",
            "bare 2-state recurrence x = Φx + γu, 7501 samples",
            floor_samples,
        )
        .target(Target::FloorMultiple(1.0))
        .note("start and end of the run together"),
    );
    machine.load_end = load_average();
    let peak_memory_mib = if options.peak_memory {
        peak_memory_of_pipeline(&project_root().join("configs").join("paper.toml"))
    } else {
        None
    };
    Ok(Report {
        machine,
        quick: options.quick,
        floor: floor_median,
        rows,
        derived,
        peak_memory_mib,
    })
}

/// Writes `bench.json` and `bench.md` into `dir` (created if missing).
pub fn write(report: &Report, dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| ExperimentError::run("bench: write", e))?;
    let json = serde_json::to_string_pretty(&report.json())
        .map_err(|e| ExperimentError::run("bench: write", e))?;
    std::fs::write(dir.join("bench.json"), format!("{json}\n"))
        .map_err(|e| ExperimentError::run("bench: write", e))?;
    std::fs::write(dir.join("bench.md"), report.markdown())
        .map_err(|e| ExperimentError::run("bench: write", e))?;
    Ok(())
}

/// The floor: x ← Φx + γu over the record's samples, Φ = e^{A·dt} of the paper plant
/// and γ = (1e-6, 1e-3), exactly the recurrence of msd-ode's criterion bench
/// `floor_bare_recurrence` (crates/msd-ode/benches/simulate.rs).
fn floor(budget: &Budget, excitation: &Excitation) -> Samples {
    let phi = transition(&Parameters::PAPER, excitation.dt());
    let gamma = [1e-6, 1e-3];
    let force = excitation.samples();
    measure_batched(budget, 20, || {
        let mut x = [0.0_f64; 2];
        let mut acc = 0.0;
        for &u in std::hint::black_box(force) {
            x = [
                phi[0][0] * x[0] + phi[0][1] * x[1] + gamma[0] * u,
                phi[1][0] * x[0] + phi[1][1] * x[1] + gamma[1] * u,
            ];
            acc += x[0];
        }
        acc
    })
}

/// e^{A·dt} of the plant's state matrix by its Taylor series (‖A·dt‖ is about 0.1 for
/// the paper plant; 30 terms are far past machine precision).
fn transition(parameters: &Parameters, dt: f64) -> [[f64; 2]; 2] {
    let model = parameters.state_space();
    let a = [
        [model.a[(0, 0)] * dt, model.a[(0, 1)] * dt],
        [model.a[(1, 0)] * dt, model.a[(1, 1)] * dt],
    ];
    let mut sum = [[1.0, 0.0], [0.0, 1.0]];
    let mut term = sum;
    for k in 1..30 {
        let mut next = [[0.0; 2]; 2];
        for (i, row) in next.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = (term[i][0] * a[0][j] + term[i][1] * a[1][j]) / k as f64;
            }
        }
        term = next;
        for i in 0..2 {
            for j in 0..2 {
                sum[i][j] += term[i][j];
            }
        }
    }
    sum
}

/// One simulation of `excitation` at the paper plant into `out`; `None` on failure.
fn simulate_once(excitation: &Excitation, backend: &Backend, out: &mut [f64]) -> Option<()> {
    simulate_into(
        &Parameters::PAPER,
        excitation,
        InitialState::REST,
        backend,
        out,
    )
    .ok()
    .map(|_| ())
}

/// Runs this executable's `bench-peak-memory <config>` and reads the peak memory it
/// prints (MiB); `None` if that fails.
fn peak_memory_of_pipeline(config: &Path) -> Option<f64> {
    let exe = std::env::current_exe().ok()?;
    let output = std::process::Command::new(exe)
        .arg("bench-peak-memory")
        .arg(config)
        .output()
        .ok()?;
    if !output.status.success() {
        return None;
    }
    String::from_utf8_lossy(&output.stdout).trim().parse().ok()
}

/// Runs the computing stages of `config` once (no figures) and returns this process's
/// peak resident memory in MiB: the body of the hidden `bench-peak-memory` command.
pub fn pipeline_peak_memory(config: &Path) -> Result<f64> {
    let loaded = crate::config::Config::load(config)?;
    let progress = crate::progress::Progress::new(false);
    crate::paper::run_stages(loaded, config, &crate::RunOptions::default(), &progress)?;
    report::peak_rss_mib()
        .ok_or_else(|| ExperimentError::run("bench", "no VmHWM in /proc/self/status"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transition_matches_the_exact_solution_of_an_undamped_oscillator() {
        // m = 1, c → 0, k = 4: Φ = [[cos 2t, sin 2t / 2], [−2 sin 2t, cos 2t]].
        let p = Parameters {
            mass: 1.0,
            damping: 0.0,
            stiffness: 4.0,
        };
        let dt = 0.01;
        let phi = transition(&p, dt);
        let (c, s) = ((2.0 * dt).cos(), (2.0 * dt).sin());
        let expected = [[c, s / 2.0], [-2.0 * s, c]];
        for i in 0..2 {
            for j in 0..2 {
                assert!((phi[i][j] - expected[i][j]).abs() < 1e-15, "{phi:?}");
            }
        }
    }
}
