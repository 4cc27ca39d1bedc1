//! The command line shared by `msd run` and `cargo xtask experiment`: the same
//! arguments, help, messages and exit statuses (0 success, 2 bad config or data, 1 a
//! failure during the run).
//!
//! ```
//! use clap::Parser;
//! use msd_experiment::cli::RunArgs;
//! #[derive(Parser)]
//! struct Cli {
//!     #[command(flatten)]
//!     run: RunArgs,
//! }
//! let cli = Cli::parse_from(["msd", "configs/paper.toml", "--seed", "7", "--quiet"]);
//! assert_eq!(cli.run.seed, Some(7));
//! assert!(cli.run.quiet);
//! ```

use crate::{error::ExperimentError, options::RunOptions, run_experiment};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The long help of the run command.
pub const RUN_HELP: &str = "\
Run an experiment config end to end and write its results.

A config is of one kind, chosen by its sections (docs/guides/ has a guide per kind):
  (none of those below)   the paper's workflow: a force and a displacement, described below
  [setup]                 a lab setup: a force, a shaker table (base excitation), a ring-down \
(free decay), repeats, a damper test machine; any displacement, velocity and acceleration \
channels
  [frequency_response]    frequency responses: one mode or several, sets of FRFs with shapes \
(hammer or shaker records, analyser tables, UFF files)
  [chain]                 a chain of masses: every m, c, k, sensor delays and filters, the modes
  [operational]           output-only modal analysis (no measured input): SSI-cov, SSI-dat, EFDD
Start from your own data file with `msd init FILE`, which writes a config of the right kind.

The paper's workflow: generate (synthetic) or load (measured CSV) data; estimate m, c, k; validate on \
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

Outputs, written atomically into --out, or the config's output.dir, or <name>/ under the \
results folder (msd-results/ in the current folder for `msd run`, target/experiments/ in \
the workspace for `cargo xtask experiment`): report.md (with the figures), results.json \
(every number), identification.csv, validation.csv, residual_correlation.csv, and the \
figures fig2_identification, fig3_validation, fig4_monte_carlo, residual_correlation as PNG \
and SVG; frf.csv and the figure frf_bode when the frequency check measured (it is skipped, \
saying why, on data without a resonance in the excited band, such as a damper at or past \
critical damping); with [nonlinear] also nonlinear.csv and the figure \
nonlinear_residuals. A failed run writes nothing and leaves a previous result untouched. \
An existing output folder is replaced only when it is a previous result (it holds the \
.msd-results marker a run writes) or empty: a folder of other files is refused (exit 2) \
before anything is computed.

Prints a summary on stdout; shows progress on stderr only when it is a terminal and \
--quiet is not given.

Exit status: 0 on success, 2 for a bad config or bad data (the message names the file, \
line or field, the value and what was expected), 1 for a failure during the run.";

/// The arguments of one run.
#[derive(Debug, Clone, clap::Args)]
pub struct RunArgs {
    /// The experiment config (TOML), e.g. configs/paper.toml.
    pub config: PathBuf,
    /// Output folder [default: <name>/ under the results folder].
    // This line is also the --help text, where <name> is meant as written.
    #[allow(rustdoc::invalid_html_tags)]
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Seed of every random draw, instead of the config's `seed`.
    #[arg(long, value_name = "N")]
    pub seed: Option<u64>,
    /// Worker threads of the Monte Carlo (and multistart), instead of the config's.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=msd_mc::MAX_THREADS as u64))]
    pub threads: Option<u64>,
    /// Print nothing but the summary (no progress).
    #[arg(long, short)]
    pub quiet: bool,
}

impl RunArgs {
    /// The run's options; `results_root` and `command` as [`RunOptions`] documents them.
    pub fn options(&self, results_root: Option<PathBuf>, command: &str) -> RunOptions {
        RunOptions {
            out: self.out.clone(),
            results_root,
            command: Some(command.to_string()),
            seed: self.seed,
            threads: self.threads.map(|t| t as usize),
            progress: !self.quiet && std::io::stderr().is_terminal(),
        }
    }
}

/// Runs the experiment, prints its summary, and turns a panic inside the run into an
/// error (exit status 1) rather than an abort.
pub fn run(args: &RunArgs, options: &RunOptions) -> Result<(), ExperimentError> {
    let outcome = std::panic::catch_unwind(|| run_experiment(&args.config, options));
    let run = outcome.map_err(|panic| {
        let why = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".into());
        ExperimentError::run("experiment", format!("internal error: {why}"))
    })??;
    print_stdout(&run.summary);
    Ok(())
}

pub use crate::output::print_stdout;

/// The arguments of `fetch-data`.
///
/// ```
/// use clap::Parser;
/// use msd_experiment::cli::FetchArgs;
/// #[derive(Parser)]
/// struct Cli {
///     #[command(flatten)]
///     fetch: FetchArgs,
/// }
/// let cli = Cli::parse_from(["msd", "silverbox", "--url", "file:///tmp/SilverboxFiles.zip"]);
/// assert_eq!(cli.fetch.url.as_deref(), Some("file:///tmp/SilverboxFiles.zip"));
/// assert!(Cli::try_parse_from(["msd", "silverbox", "--url", "x.zip", "--from", "dir"]).is_err());
/// ```
#[derive(Debug, Clone, clap::Args)]
pub struct FetchArgs {
    /// The data set: silverbox.
    pub set: String,
    /// A local copy of the set's files to take them from [default: ../shared/data/real/SET
    /// beside the workspace, when it exists].
    #[arg(long, value_name = "DIR")]
    pub from: Option<PathBuf>,
    /// Download the set's archive from here instead of the official one: an http(s) URL
    /// (a lab's own mirror), a file:// URL or the path of a zip already downloaded. Used
    /// when no local copy of the files is found, or whenever it is given.
    #[arg(long, value_name = "URL", conflicts_with = "from")]
    pub url: Option<String>,
    /// Where to put them [default: data/SET in the workspace, or in the current folder].
    #[arg(long, value_name = "DIR")]
    pub into: Option<PathBuf>,
}

/// Where `fetch-data` takes a set's files from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FetchSource {
    /// The files are already in place, checked: nothing to take.
    Ready,
    /// A folder holding the files (a local copy).
    Mirror(PathBuf),
    /// The set's archive: a URL, a `file://` URL or a zip's path.
    Archive(String),
}

/// What `fetch-data` will do: the set, where its files go, and where they come from.
///
/// ```
/// use msd_experiment::cli::{FetchArgs, FetchSource, fetch_plan};
/// let dir = tempfile::tempdir().unwrap();
/// let args = FetchArgs { set: "silverbox".into(), from: None, url: None, into: None };
/// // No local copy beside: the official archive, on the web.
/// let plan = fetch_plan(&args, dir.path(), dir.path()).unwrap();
/// assert_eq!(plan.into, dir.path().join("silverbox"));
/// assert!(matches!(&plan.source, FetchSource::Archive(url) if url.contains("drive.google.com")));
/// assert!(plan.needs_http());
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FetchPlan {
    /// The data set.
    pub set: crate::fetch::DataSetFiles,
    /// The folder its files go into.
    pub into: PathBuf,
    /// Where they come from.
    pub source: FetchSource,
}

impl FetchPlan {
    /// Whether carrying it out downloads over HTTP or HTTPS (see
    /// [`HTTP_SUPPORT`](crate::fetch::HTTP_SUPPORT)).
    ///
    /// ```
    /// use msd_experiment::cli::{FetchPlan, FetchSource};
    /// let plan = FetchPlan {
    ///     set: msd_experiment::fetch::SILVERBOX,
    ///     into: "data/silverbox".into(),
    ///     source: FetchSource::Archive("file:///tmp/SilverboxFiles.zip".into()),
    /// };
    /// assert!(!plan.needs_http());
    /// ```
    pub fn needs_http(&self) -> bool {
        matches!(&self.source, FetchSource::Archive(url) if crate::fetch::is_http(url))
    }
}

/// `fetch-data`'s plan: the files go into `into` (else `default_root/<set>`). They are
/// already there when every one passes its check; else they are copied from `from` (an
/// error when it is not a folder), else from `default_from/<set>` when that folder
/// exists; otherwise, or when `url` is given, they are downloaded from the set's archive
/// (`url`, else the official one).
///
/// ```
/// use msd_experiment::cli::{FetchArgs, fetch_plan};
/// let dir = tempfile::tempdir().unwrap();
/// let args = FetchArgs {
///     set: "silverbox".into(),
///     from: Some(dir.path().join("nothing here")),
///     url: None,
///     into: None,
/// };
/// let err = fetch_plan(&args, dir.path(), dir.path()).unwrap_err();
/// assert!(err.to_string().contains("no local copy of the silverbox files here"), "{err}");
/// // An empty --url is refused by name (exit 2), not tried as a file.
/// let empty = FetchArgs { set: "silverbox".into(), from: None, url: Some("".into()), into: None };
/// let err = fetch_plan(&empty, dir.path(), dir.path()).unwrap_err();
/// assert!(err.to_string().starts_with("--url: empty"), "{err}");
/// assert_eq!(err.exit_code(), 2);
/// ```
pub fn fetch_plan(
    args: &FetchArgs,
    default_from: &Path,
    default_root: &Path,
) -> Result<FetchPlan, ExperimentError> {
    let set = crate::fetch::set_named(&args.set)?;
    let into = args
        .into
        .clone()
        .unwrap_or_else(|| default_root.join(set.name));
    if let Some(from) = args.from.as_ref().filter(|from| !from.is_dir()) {
        return Err(ExperimentError::data(
            from,
            format!(
                "no local copy of the {} files here: give --from DIR with {}, or leave --from out to download the official archive",
                set.name,
                files_named(set.files)
            ),
        ));
    }
    if args.url.as_deref().is_some_and(|u| u.trim().is_empty()) {
        return Err(ExperimentError::config(
            "--url",
            format!(
                "empty: expected the {} set's archive as an http(s):// or file:// URL or a local path, or leave --url out for the official one",
                set.name
            ),
        ));
    }
    let ready = (set.files.iter()).all(|f| crate::fetch::verify(&into.join(f.name), f).is_ok());
    let source = match (&args.from, &args.url) {
        _ if ready => FetchSource::Ready,
        (Some(from), _) => FetchSource::Mirror(from.clone()),
        (None, Some(url)) => FetchSource::Archive(url.clone()),
        (None, None) => {
            let mirror = default_from.join(set.name);
            if mirror.is_dir() {
                FetchSource::Mirror(mirror)
            } else {
                FetchSource::Archive(set.archive.url.to_string())
            }
        }
    };
    Ok(FetchPlan { set, into, source })
}

/// Carries out `plan` and says what it did: the files in place, each checked by size
/// and SHA-256.
///
/// ```
/// use msd_experiment::cli::{FetchPlan, FetchSource, run_fetch};
/// let dir = tempfile::tempdir().unwrap();
/// let plan = FetchPlan {
///     set: msd_experiment::fetch::SILVERBOX,
///     into: dir.path().join("silverbox"),
///     source: FetchSource::Mirror(dir.path().join("empty")),
/// };
/// let err = run_fetch(&plan).unwrap_err();
/// assert!(err.to_string().contains("cannot read the silverbox file"), "{err}");
/// assert!(!plan.into.exists());
/// ```
pub fn run_fetch(plan: &FetchPlan) -> Result<(), ExperimentError> {
    let FetchPlan { set, into, source } = plan;
    let placed = match source {
        FetchSource::Ready => set.files.iter().map(|f| into.join(f.name)).collect(),
        FetchSource::Mirror(from) => crate::fetch::fetch(set, from, into)?,
        FetchSource::Archive(url) => {
            let which = if url == set.archive.url {
                "the official archive, "
            } else {
                ""
            };
            eprintln!("downloading {which}{url} …");
            let options = crate::fetch::DownloadOptions::default();
            crate::fetch::download(set, url, into, &options)?
        }
    };
    for path in placed {
        println!("{} (size and SHA-256 checked)", path.display());
    }
    Ok(())
}

/// `fetch-data`: [`run_fetch`] of the [`fetch_plan`].
///
/// ```
/// use msd_experiment::cli::{FetchArgs, fetch_data};
/// let dir = tempfile::tempdir().unwrap();
/// let args = FetchArgs {
///     set: "silverbox".into(),
///     from: None,
///     url: Some(dir.path().join("missing.zip").display().to_string()),
///     into: None,
/// };
/// let err = fetch_data(&args, dir.path(), dir.path()).unwrap_err();
/// assert!(err.to_string().contains("cannot read the archive"), "{err}");
/// assert_eq!(err.exit_code(), 2);
/// assert!(!dir.path().join("silverbox").exists());
/// ```
pub fn fetch_data(
    args: &FetchArgs,
    default_from: &Path,
    default_root: &Path,
) -> Result<(), ExperimentError> {
    run_fetch(&fetch_plan(args, default_from, default_root)?)
}

/// `msd init FILE`'s arguments.
///
/// ```
/// use clap::Parser;
/// #[derive(Parser)]
/// struct Cli { #[command(flatten)] init: msd_experiment::cli::InitArgs }
/// let cli = Cli::try_parse_from(["msd", "run.csv", "--input", "F", "--output", "a1", "--output", "a2"]).unwrap();
/// assert_eq!(cli.init.output, ["a1", "a2"]);
/// ```
#[derive(Debug, Clone, clap::Args)]
pub struct InitArgs {
    /// The data file: a CSV or text export, MATLAB .mat, NumPy .npy/.npz, NI TDMS.
    pub file: PathBuf,
    /// The column that drives the plant (a force, or the base's motion), when its unit
    /// and name do not say.
    #[arg(long, value_name = "COLUMN")]
    pub input: Option<String>,
    /// A response column (repeat for each), when their units and names do not say.
    #[arg(long, value_name = "COLUMN")]
    pub output: Vec<String>,
    /// The sampling rate, Hz, for a file with no time column and no rate of its own.
    #[arg(long, value_name = "HZ")]
    pub sample_rate: Option<f64>,
    /// Where to write the config [default: the data file's name with .toml, beside it].
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Replace the config if it exists.
    #[arg(long)]
    pub overwrite: bool,
}

/// `msd init`: writes the config and prints what was found and the command to run.
pub fn init(args: &InitArgs) -> Result<(), ExperimentError> {
    let options = crate::init::InitOptions {
        input: args.input.clone(),
        outputs: args.output.clone(),
        sample_rate_hz: args.sample_rate,
        config: args.config.clone(),
        overwrite: args.overwrite,
    };
    let done = crate::init::init(&args.file, &options)?;
    crate::output::print_stdout(&done.summary);
    Ok(())
}

/// Prints `result`'s error on stderr as `error: …` and gives the exit status.
pub fn exit(result: Result<(), ExperimentError>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

/// The files of a set in words: both names for two, the first and a count for more.
fn files_named(files: &[crate::fetch::DataFile]) -> String {
    match files {
        [a, b] => format!("{} and {}", a.name, b.name),
        [first, rest @ ..] => format!("{} and {} more files", first.name, rest.len()),
        [] => "no files".to_string(),
    }
}
