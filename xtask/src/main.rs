//! `cargo xtask`: the task runner of the msd toolkit.
//!
//! Following the xtask convention, `main` calls `try_main`, prints any error and exits
//! non-zero: 2 for a bad config or bad data, 1 for a failure during the run.

use clap::{Parser, Subcommand};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use xtask::{RunOptions, XtaskError, run_experiment};

/// Tasks of the msd toolkit (mass–spring–damper identification).
#[derive(Debug, Parser)]
#[command(
    name = "cargo xtask",
    version,
    about = "Tasks of the msd toolkit: identify mass, damping and stiffness from vibration data",
    long_about = "Tasks of the msd toolkit: identify the mass m, damping c and stiffness k of a \
mass–spring–damper from vibration data.\n\n\
Start with the paper's experiment:\n\n    cargo xtask experiment configs/paper.toml\n\n\
It writes target/experiments/paper/ with report.md, results.json, CSV files and figures."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

/// The available tasks.
#[derive(Debug, Subcommand)]
enum Command {
    /// Run an experiment config end to end: data, estimation, validation, residual
    /// diagnostics, frequency check, Monte Carlo; write figures, CSV, report.md and
    /// results.json.
    #[command(long_about = EXPERIMENT_HELP)]
    Experiment(ExperimentArgs),
    /// Measure the paper experiment's speed: one table (median, min–max, multiple of the
    /// floor) printed and written to target/bench/bench.json and bench.md. Builds and
    /// runs the measurements in release mode (the first build takes a few minutes).
    Bench(BenchArgs),
    /// The measuring half of `bench`, run in release by `bench` itself.
    #[command(hide = true)]
    BenchRun(BenchArgs),
    /// Runs a config's stages once (no figures) and prints the peak memory in MiB.
    #[command(hide = true)]
    BenchPeakMemory {
        /// The experiment config.
        config: PathBuf,
    },
}

#[derive(Debug, clap::Args)]
struct BenchArgs {
    /// Fewer repetitions per row (about a third of the time).
    #[arg(long)]
    quick: bool,
}

const EXPERIMENT_HELP: &str = "\
Run an experiment config end to end and write its results.

Stages: generate (synthetic) or load (measured CSV) data; estimate m, c, k; validate on \
fresh data; residual diagnostics (autocorrelation, Ljung–Box, residual–input \
cross-correlation); frequency-consistency check (H1 estimate vs the model); Monte Carlo \
band on the validation input; with a [nonlinear] section, nonlinear models (Coulomb or \
quadratic damping, cubic stiffness) estimated or compared by BIC.

The config (TOML, unknown keys refused) has either synthetic sections [plant], [time], \
[noise], [identification.input], [validation.input] or a [data] section for a measured CSV \
file, plus optional [estimation], [residuals], [frequency_check], [monte_carlo], [output], \
[nonlinear]. \
The configs in configs/ document every field; configs/lab-template.toml is the template \
for your own measurement.

Outputs, written atomically into target/experiments/<name>/ (or --out): report.md (with \
the figures), results.json (every number), identification.csv, validation.csv, \
residual_correlation.csv, and the figures fig2_identification, fig3_validation, \
fig4_monte_carlo, residual_correlation as PNG and SVG; frf.csv and the figure frf_bode when \
the frequency check measured (it is skipped, saying why, on data without a resonance in \
the excited band, such as a damper at or past critical damping); with [nonlinear] also \
nonlinear.csv and the figure nonlinear_residuals. A failed run writes \
nothing and leaves a previous result untouched.

Prints a summary on stdout; shows progress on stderr only when it is a terminal and \
--quiet is not given.

Exit status: 0 on success, 2 for a bad config or bad data (the message names the file, \
line or field, the value and what was expected), 1 for a failure during the run.";

#[derive(Debug, clap::Args)]
struct ExperimentArgs {
    /// The experiment config (TOML), e.g. configs/paper.toml.
    config: PathBuf,
    /// Output folder [default: target/experiments/<name> in the workspace].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Seed of every random draw, instead of the config's `seed`.
    #[arg(long, value_name = "N")]
    seed: Option<u64>,
    /// Worker threads of the Monte Carlo (and multistart), instead of the config's.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=1024))]
    threads: Option<u64>,
    /// Print nothing but the summary (no progress).
    #[arg(long, short)]
    quiet: bool,
}

fn main() -> ExitCode {
    match try_main() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

fn try_main() -> Result<(), XtaskError> {
    let cli = Cli::parse();
    match cli.command {
        None => {
            println!("no task given; run `cargo xtask --help` for the list of tasks");
            Ok(())
        }
        Some(Command::Experiment(args)) => experiment(args),
        Some(Command::Bench(args)) => bench_in_release(&args),
        Some(Command::BenchRun(args)) => bench_run(&args),
        Some(Command::BenchPeakMemory { config }) => {
            println!("{:.1}", xtask::bench::pipeline_peak_memory(&config)?);
            Ok(())
        }
    }
}

fn experiment(args: ExperimentArgs) -> Result<(), XtaskError> {
    let options = RunOptions {
        out: args.out,
        seed: args.seed,
        threads: args.threads.map(|t| t as usize),
        progress: !args.quiet && std::io::stderr().is_terminal(),
    };
    let config = args.config;
    let run =
        std::panic::catch_unwind(|| run_experiment(&config, &options)).map_err(|panic| {
            let why = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            XtaskError::run("experiment", format!("internal error: {why}"))
        })??;
    print!("{}", run.summary);
    Ok(())
}

/// `bench`: build xtask in release and run `bench-run` there (the dev profile would
/// measure unoptimised code).
fn bench_in_release(args: &BenchArgs) -> Result<(), XtaskError> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    eprintln!("building xtask in release (thin LTO; the first build takes a few minutes) …");
    let mut command = std::process::Command::new(cargo);
    command.current_dir(xtask::project_root()).args([
        "run",
        "--release",
        "--quiet",
        "-p",
        "xtask",
        "--",
        "bench-run",
    ]);
    if args.quick {
        command.arg("--quick");
    }
    let status = command
        .status()
        .map_err(|e| XtaskError::run("bench", format!("running cargo: {e}")))?;
    if status.success() {
        Ok(())
    } else {
        Err(XtaskError::run(
            "bench",
            format!("the release run failed ({status})"),
        ))
    }
}

/// `bench-run`: measure, print the table, write target/bench/.
fn bench_run(args: &BenchArgs) -> Result<(), XtaskError> {
    use xtask::bench::{BenchOptions, out_dir, run, write};
    let options = if args.quick {
        BenchOptions::quick()
    } else {
        BenchOptions::default()
    };
    if cfg!(debug_assertions) {
        eprintln!(
            "warning: bench-run in a debug build measures unoptimised code; use `cargo xtask bench`"
        );
    }
    let report = run(&options)?;
    let dir = out_dir();
    write(&report, &dir)?;
    print!("{}", report.text());
    println!(
        "written: {} and {}",
        dir.join("bench.json").display(),
        dir.join("bench.md").display()
    );
    Ok(())
}
