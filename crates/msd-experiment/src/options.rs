//! Options of a run that do not belong in the config: where it writes, the seed and
//! threads instead of the config's, the command the report names, progress bars.

use std::path::PathBuf;

/// Options of a run that do not belong in the config.
///
/// ```
/// let options = msd_experiment::RunOptions::default();
/// assert_eq!(options.results_root, None); // outputs go to ./msd-results/<name>/
/// assert_eq!(options.command, None); // the report names `msd run`
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunOptions {
    /// Output folder instead of the config's `output.dir` or `<results_root>/<name>`.
    pub out: Option<PathBuf>,
    /// The folder under which a run writes `<name>/` when neither `out` nor the config's
    /// `output.dir` is given. By default `msd-results` in the current folder;
    /// `cargo xtask experiment` sets the workspace's `target/experiments`.
    pub results_root: Option<PathBuf>,
    /// The command the report shows before the config's path. By default `msd run`.
    pub command: Option<String>,
    /// Seed instead of the config's.
    pub seed: Option<u64>,
    /// Worker threads instead of the config's.
    pub threads: Option<usize>,
    /// Draw progress bars on stderr (only sensible on a terminal). By default false.
    pub progress: bool,
}
