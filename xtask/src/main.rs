//! `cargo xtask`: the task runner of the msd toolkit.
//!
//! Following the xtask convention, `main` calls `try_main`, prints any error and exits
//! non-zero: 2 for a bad config or bad data, 1 for a failure during the run.

use clap::{Parser, Subcommand};
use msd_experiment::ExperimentError;
use msd_experiment::cli::{self, RunArgs};
use msd_experiment::fetch;
use std::path::PathBuf;
use std::process::ExitCode;

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
    #[command(long_about = cli::RUN_HELP)]
    Experiment(RunArgs),
    /// Put a real data set (silverbox) into data/SET/ in the workspace, each file
    /// checked by size and SHA-256: copied from ../shared/data/real/SET/ beside the
    /// workspace (or --from DIR), else downloaded from the official archive (or --url).
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
    /// design into target/experiments/<name>-design/; --verify N checks it on N
    /// simulated tests.
    // The lines above are also the --help text, where [design] and <name> are meant as
    // written.
    #[allow(rustdoc::broken_intra_doc_links, rustdoc::invalid_html_tags)]
    Design(msd_experiment::design::DesignArgs),
    /// Measure the paper experiment's speed: one table (median, min–max, multiple of the
    /// floor) printed and written to target/bench/bench.json and bench.md. Builds and
    /// runs the measurements in release mode (the first build takes a few minutes).
    Bench(BenchArgs),
    /// Run every shipped config (configs/*.toml; the paper's first) and open each
    /// report.html in headless Chromium (Debian's `chromium`, or $CHROMIUM):
    /// self-contained, every figure drawn, no table or text block scrolling sideways, no
    /// page wider than a laptop, no console message, a screenshot that is not blank, a
    /// PDF with pages (written to <run>/browser/). A config whose real data set is not
    /// fetched is skipped, saying so (an error under MSD_REQUIRE_REAL_DATA).
    CheckReport {
        /// A result folder to check instead of running the shipped configs.
        dir: Option<PathBuf>,
    },
    /// Time the first run as a new user meets it: git clone of this checkout's committed
    /// state into a temporary folder, then `cargo xtask experiment configs/paper.toml`
    /// there with its own target folder (offline: the crates must be downloaded).
    BenchFirstRun,
    /// Coverage of the 95 % intervals over seeds on simulated lab records whose drive is
    /// measured with noise (0, 0.3, 1 and 3 % of its rms), for the accelerometer,
    /// displacement + accelerometer, base-excitation and repeats setups, with the
    /// default noise model and the white one; written to target/noise-study/. Runs in
    /// release (the first build takes a few minutes).
    NoiseStudy(StudyArgs),
    /// The measuring half of `noise-study`, run in release by it.
    #[command(hide = true)]
    NoiseStudyRun(StudyArgs),
    /// Coverage of output-only analysis's 95 % intervals over seeds: a simulated
    /// five-storey shear building analysed by SSI-cov at default settings, each true
    /// mode's coverage of fn and ζ; written to target/oma-study/. Runs in release.
    OmaStudy(OmaStudyArgs),
    /// The measuring half of `oma-study`, run in release by it.
    #[command(hide = true)]
    OmaStudyRun(OmaStudyArgs),
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

#[derive(Debug, clap::Args)]
struct OmaStudyArgs {
    /// Simulated records.
    #[arg(long, default_value_t = 200)]
    seeds: usize,
    /// Worker threads.
    #[arg(long, default_value_t = 2)]
    threads: usize,
    /// The method: ssi-cov, ssi-dat or efdd.
    #[arg(long, default_value = "ssi-cov")]
    method: String,
}

#[derive(Debug, clap::Args)]
struct StudyArgs {
    /// Seeds per setup and noise level.
    #[arg(long, default_value_t = 400)]
    seeds: usize,
    /// Worker threads.
    #[arg(long, default_value_t = 2)]
    threads: usize,
    /// The drive-noise levels, fractions of its rms (by default 0, 0.003, 0.01, 0.03).
    #[arg(long, value_delimiter = ',')]
    levels: Vec<f64>,
    /// The setups (by default all): accelerometer, displacement_and_accelerometer,
    /// base_excitation, repeats, two_storey.
    #[arg(long, value_delimiter = ',')]
    setups: Vec<String>,
}

fn main() -> ExitCode {
    cli::exit(try_main())
}

fn try_main() -> Result<(), ExperimentError> {
    let cli = Cli::parse();
    match cli.command {
        None => {
            println!("no task given; run `cargo xtask --help` for the list of tasks");
            Ok(())
        }
        Some(Command::Experiment(args)) => experiment(args),
        Some(Command::Plan(args)) => msd_experiment::plan::run_plan(&args),
        Some(Command::Design(args)) => {
            msd_experiment::design::run_design(&args, Some(xtask::results_root()))
        }
        Some(Command::FetchData(args)) => fetch_data(&args),
        Some(Command::Bench(args)) => {
            let quick = args.quick.then(|| "--quick".to_string());
            in_release("bench-run", quick.as_slice())
        }
        Some(Command::NoiseStudy(args)) => {
            let mut forwarded = vec![
                format!("--seeds={}", args.seeds),
                format!("--threads={}", args.threads),
            ];
            if !args.levels.is_empty() {
                let levels: Vec<String> = args.levels.iter().map(f64::to_string).collect();
                forwarded.push(format!("--levels={}", levels.join(",")));
            }
            if !args.setups.is_empty() {
                forwarded.push(format!("--setups={}", args.setups.join(",")));
            }
            in_release("noise-study-run", &forwarded)
        }
        Some(Command::NoiseStudyRun(args)) => noise_study(&args),
        Some(Command::OmaStudy(args)) => in_release(
            "oma-study-run",
            &[
                format!("--seeds={}", args.seeds),
                format!("--threads={}", args.threads),
                format!("--method={}", args.method),
            ],
        ),
        Some(Command::OmaStudyRun(args)) => {
            let method: msd_modal::OmaMethod = serde_json::from_value(serde_json::Value::String(
                args.method.clone(),
            ))
            .map_err(|_| {
                msd_experiment::ExperimentError::run(
                    "oma-study",
                    format!(
                        "--method {}: expected ssi-cov, ssi-dat or efdd",
                        args.method
                    ),
                )
            })?;
            let study = xtask::oma_study::run(args.seeds, args.threads, method)?;
            println!("{study}");
            let dir = xtask::project_root().join("target").join("oma-study");
            xtask::oma_study::write(&study, &dir)?;
            println!("written: {}", dir.display());
            Ok(())
        }
        Some(Command::BenchRun(args)) => bench_run(&args),
        Some(Command::BenchFirstRun) => {
            println!("{}", xtask::bench::first_run::first_run()?);
            Ok(())
        }
        Some(Command::CheckReport { dir }) => check_report(dir),
        Some(Command::BenchPeakMemory { config }) => {
            println!("{:.1}", xtask::bench::pipeline_peak_memory(&config)?);
            Ok(())
        }
    }
}

fn experiment(args: RunArgs) -> Result<(), ExperimentError> {
    let options = args.options(Some(xtask::results_root()), "cargo xtask experiment");
    cli::run(&args, &options)
}

/// Shipped configs that `run` does not take as they are, and why.
const NOT_RUN: [(&str, &str); 2] = [
    ("lab-template.toml", "a template for the user's own file"),
    (
        "design-sequential.toml",
        "run by `design`, which writes the config to run",
    ),
];

/// `check-report`: check the report in `dir`, or run every shipped config and check
/// each report (every failure listed at the end).
fn check_report(dir: Option<PathBuf>) -> Result<(), ExperimentError> {
    if let Some(dir) = dir {
        return check_one(&dir);
    }
    let root = xtask::project_root();
    let folder = root.join("configs");
    let listed = std::fs::read_dir(&folder)
        .map_err(|e| ExperimentError::run("check-report", format!("{}: {e}", folder.display())))?;
    let mut configs: Vec<PathBuf> = listed
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    // The paper's first: msd-py's tests compare msd.run with its results.json.
    configs.sort_by_key(|p| (p.file_name() != Some("paper.toml".as_ref()), p.clone()));
    let mut failures = Vec::new();
    for config in configs {
        let name = config
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        if let Some((_, why)) = NOT_RUN.iter().find(|(n, _)| *n == name) {
            eprintln!("{name}: not checked ({why})");
            continue;
        }
        if let Some(set) = missing_real_data(&root, &config) {
            let fetch = format!("cargo xtask fetch-data {set}");
            if std::env::var_os("MSD_REQUIRE_REAL_DATA").is_some() {
                failures.push(format!(
                    "{name}: the real data set `{set}` is missing ({fetch})"
                ));
            } else {
                eprintln!(
                    "{name}: not checked, the real data set `{set}` is not fetched ({fetch})"
                );
            }
            continue;
        }
        let args = RunArgs {
            config,
            out: None,
            seed: None,
            threads: None,
            quiet: true,
        };
        let options = args.options(Some(xtask::results_root()), "cargo xtask experiment");
        let outcome = msd_experiment::run_experiment(&args.config, &options)
            .and_then(|run| check_one(&run.out_dir));
        if let Err(e) = outcome {
            failures.push(format!("{name}: {e}"));
        }
    }
    if failures.is_empty() {
        Ok(())
    } else {
        Err(ExperimentError::run("check-report", failures.join("\n")))
    }
}

/// The real data set a config reads (`data/<set>/` in its text) when it is not fetched.
fn missing_real_data(root: &std::path::Path, config: &std::path::Path) -> Option<&'static str> {
    let text = std::fs::read_to_string(config).ok()?;
    ["silverbox", "impact-frf", "steel-frame", "emps"]
        .into_iter()
        .find(|set| text.contains(&format!("data/{set}/")) && !root.join("data").join(set).is_dir())
}

/// Checks the report in `dir` and prints what the browser saw.
fn check_one(dir: &std::path::Path) -> Result<(), ExperimentError> {
    let check = xtask::check_report::check(dir)?;
    println!(
        "report.html in headless Chromium: {} figures drawn, no console message, screenshot {:.0} % ink, PDF {} pages ({})",
        check.figures,
        100.0 * check.screenshot_ink,
        check.pdf_pages,
        dir.join("browser").display()
    );
    Ok(())
}

/// `fetch-data`: the library's, into `data/SET/` in the workspace from
/// `../shared/data/real/SET/` beside it; a download goes through the `msd` command when
/// xtask is built without HTTP support (its default, for a lean first build).
fn fetch_data(args: &cli::FetchArgs) -> Result<(), ExperimentError> {
    let root = xtask::project_root();
    let shared = root.join("..").join("shared").join("data").join("real");
    let plan = cli::fetch_plan(args, &shared, &root.join("data"))?;
    match &plan.source {
        cli::FetchSource::Archive(url) if plan.needs_http() && !fetch::HTTP_SUPPORT => {
            fetch_with_msd(&plan, url)
        }
        _ => cli::run_fetch(&plan),
    }
}

/// Runs `msd fetch-data` (msd-experiment's command, built with HTTP support) for `plan`.
fn fetch_with_msd(plan: &cli::FetchPlan, url: &str) -> Result<(), ExperimentError> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    eprintln!("downloading through the `msd` command (its first build takes about a minute) …");
    let status = std::process::Command::new(cargo)
        .current_dir(xtask::project_root())
        .args([
            "run",
            "--quiet",
            "-p",
            "msd-experiment",
            "--bin",
            "msd",
            "--",
        ])
        .args(["fetch-data", plan.set.name, "--url", url, "--into"])
        .arg(&plan.into)
        .status()
        .map_err(|e| ExperimentError::run("fetch-data", format!("running cargo: {e}")))?;
    match status.code() {
        Some(0) => Ok(()),
        // msd said why (on stderr); its exit status is the crate's: a download error.
        Some(2) => Err(ExperimentError::download(
            url,
            "`msd fetch-data` failed (above)",
        )),
        _ => Err(ExperimentError::run(
            "fetch-data",
            format!("`msd fetch-data` failed ({status})"),
        )),
    }
}

/// Builds xtask in release and runs its hidden `task` there with `args` (the dev
/// profile would measure unoptimised code).
fn in_release(task: &'static str, args: &[String]) -> Result<(), ExperimentError> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    eprintln!("building xtask in release (thin LTO; the first build takes a few minutes) …");
    let status = std::process::Command::new(cargo)
        .current_dir(xtask::project_root())
        .args(["run", "--release", "--quiet", "-p", "xtask", "--", task])
        .args(args)
        .status()
        .map_err(|e| ExperimentError::run(task, format!("running cargo: {e}")))?;
    if status.success() {
        Ok(())
    } else {
        Err(ExperimentError::run(
            task,
            format!("the release run failed ({status})"),
        ))
    }
}

/// `noise-study-run`: every setup and drive-noise level, both noise models.
fn noise_study(args: &StudyArgs) -> Result<(), ExperimentError> {
    let dir = xtask::project_root().join("target").join("noise-study");
    let levels = if args.levels.is_empty() {
        xtask::noise_study::LEVELS.to_vec()
    } else {
        args.levels.clone()
    };
    let setups = xtask::noise_study::setups(&args.setups)?;
    let studies = xtask::noise_study::run(args.seeds, args.threads, &levels, &setups, |study| {
        println!("{study}");
    })?;
    xtask::noise_study::write(&studies, &dir)?;
    println!("written: {}", dir.display());
    Ok(())
}

/// `bench-run`: measure, print the table, write target/bench/.
fn bench_run(args: &BenchArgs) -> Result<(), ExperimentError> {
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
    msd_experiment::cli::print_stdout(&format!(
        "{}written: {} and {}\n",
        report.text(),
        dir.join("bench.json").display(),
        dir.join("bench.md").display()
    ));
    Ok(())
}
