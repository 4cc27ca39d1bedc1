//! `msd`: identify the mass, damping and stiffness of a mass–spring–damper from
//! vibration data, from any folder.
//!
//! `msd run configs/paper.toml` runs an experiment config and writes its results into
//! `./msd-results/<name>/`; the same as `cargo xtask experiment` inside the workspace.

use clap::{Parser, Subcommand};
use msd_experiment::cli::{self, RunArgs};
use std::process::ExitCode;

/// msd: identify mass, damping and stiffness from vibration data.
#[derive(Debug, Parser)]
#[command(
    name = "msd",
    version,
    about = "Identify the mass, damping and stiffness of a mass–spring–damper from vibration data",
    long_about = "Identify the mass m, damping c and stiffness k of a mass–spring–damper from \
vibration data.\n\nStart from your own data file (CSV or text export, .mat, .npy/.npz, TDMS):\n\n    \
msd init my-test.csv      # writes my-test.toml beside it\n    msd run my-test.toml\n\n\
Run an experiment config:\n\n    msd run experiment.toml\n\n\
It writes msd-results/<name>/ in the current folder with report.md, results.json, CSV files \
and figures."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run an experiment config end to end: data, estimation, validation, residual
    /// diagnostics, frequency check, Monte Carlo; write figures, CSV, report.md and
    /// results.json.
    #[command(long_about = cli::RUN_HELP)]
    Run(RunArgs),
    /// Put a real data set (silverbox) into ./data/SET/, each file checked by size and
    /// SHA-256: copied from ../shared/data/real/SET/ (or --from DIR) when it exists, else
    /// downloaded from the official archive (or --url).
    FetchData(cli::FetchArgs),
    /// Predict the precision of a planned test before running it (Cramér–Rao bound from
    /// the exact sensitivities), for the paper's setup and every setup section: standard
    /// errors and 95 % half-widths of what the setup identifies, their correlation, and
    /// the record length, drive amplitude or repeats that reach the target; --verify N
    /// checks it on N simulated tests.
    Plan(msd_experiment::plan::PlanArgs),
    /// Design the input that minimises the predicted uncertainty of m, c, k within the
    /// rig's limits (peak and RMS force, stroke, band), from a config with a [design]
    /// section; write designed_input.csv, designed.toml, design.json and the figure
    /// design into msd-results/<name>-design/; --verify N checks it on N simulated tests.
    // The lines above are also the --help text, where [design] and <name> are meant as
    // written.
    #[allow(rustdoc::broken_intra_doc_links, rustdoc::invalid_html_tags)]
    Design(msd_experiment::design::DesignArgs),
    /// List what a data file holds (a CSV or text export, MATLAB .mat, NumPy .npy/.npz,
    /// NI TDMS): its channels or columns, units, lengths and sampling rate, how a text
    /// file is written (encoding, delimiter, decimal mark, metadata and units lines,
    /// missing values), and print the config lines that read it.
    Inspect {
        /// The data file.
        file: std::path::PathBuf,
    },
    /// Start from your own data file: read it as inspect does, choose the experiment its
    /// columns describe (a force and responses → a force test; a base sensor → base
    /// excitation; one response → a free decay), scale each column to SI from its unit
    /// (g → 9.80665 m/s², mm → 1e-3 m, kN → 1000 N) and write a commented config
    /// beside it that `msd run` runs.
    Init(cli::InitArgs),
}

fn main() -> ExitCode {
    let Cli { command } = Cli::parse();
    match command {
        Command::Run(args) => cli::exit(cli::run(&args, &args.options(None, "msd run"))),
        Command::Plan(args) => cli::exit(msd_experiment::plan::run_plan(&args)),
        Command::Design(args) => cli::exit(msd_experiment::design::run_design(&args, None)),
        Command::Inspect { file } => {
            cli::exit(msd_experiment::inspect::inspect(&file).map(|text| cli::print_stdout(&text)))
        }
        Command::Init(args) => cli::exit(cli::init(&args)),
        Command::FetchData(args) => cli::exit(cli::fetch_data(
            &args,
            std::path::Path::new("../shared/data/real"),
            std::path::Path::new("data"),
        )),
    }
}
