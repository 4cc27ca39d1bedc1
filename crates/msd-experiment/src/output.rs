//! Atomic output: everything is written into a hidden staging folder next to the
//! target, which replaces the target only once it is complete. A failed run (an error or
//! a panic) removes the staging folder and leaves any previous target untouched.
//!
//! A run that is killed (Ctrl-C, `kill -9`, a power cut) cannot clean up: it leaves its
//! hidden staging folder `.<name>.partial-<pid>-<n>` beside the target (the target itself
//! is untouched, or complete). The next run into the same target removes such leftovers
//! of processes that are no longer running, and puts back a previous result that a kill
//! caught while it was moved aside (`.<name>.old-<pid>`).
//!
//! For tests of these failure paths, [`inject_fault`] makes this thread's writes fail as
//! a full disk, a panic or a kill would.

use crate::error::{ExperimentError, Result};
use std::cell::RefCell;
use std::path::{Path, PathBuf};

/// A fault for tests of the failure paths, armed on the current thread by
/// [`inject_fault`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Fault {
    /// Writing `file` (a name given to [`Staging::write`]) stores half of its bytes and
    /// then fails as a full disk does (`ENOSPC`, "No space left on device").
    DiskFull {
        /// The file name inside the output folder, e.g. `"results.json"`.
        file: String,
    },
    /// Writing `file` panics, as a bug in a writer would.
    Panic {
        /// The file name inside the output folder.
        file: String,
    },
    /// Writing `file` ends the whole process after half of its bytes, as `kill -9` would:
    /// exit status 137, no destructor runs, the staging folder stays behind.
    Kill {
        /// The file name inside the output folder.
        file: String,
    },
    /// Moving the finished staging folder onto the target fails (after a previous
    /// target was moved aside), as a rename across a vanished or full file system would.
    Commit,
}

thread_local! {
    static FAULT: RefCell<Option<Fault>> = const { RefCell::new(None) };
}

/// Arms `fault` for the output written on this thread until the returned guard is
/// dropped. Only tests use this.
///
/// ```
/// use msd_experiment::output::{Fault, Staging, inject_fault};
/// let root = tempfile::tempdir().unwrap();
/// let staging = Staging::new(&root.path().join("run"))?;
/// let _fault = inject_fault(Fault::DiskFull { file: "a.txt".into() });
/// let err = staging.write("a.txt", b"hello").unwrap_err();
/// assert!(err.to_string().contains("cannot write a.txt"));
/// # Ok::<(), msd_experiment::ExperimentError>(())
/// ```
pub fn inject_fault(fault: Fault) -> FaultGuard {
    FAULT.with(|f| *f.borrow_mut() = Some(fault));
    FaultGuard { _private: () }
}

/// Disarms the fault of [`inject_fault`] when dropped.
#[derive(Debug)]
pub struct FaultGuard {
    _private: (),
}

impl Drop for FaultGuard {
    fn drop(&mut self) {
        FAULT.with(|f| *f.borrow_mut() = None);
    }
}

impl Fault {
    /// The file it targets (`None` for `Commit`).
    fn file(&self) -> Option<&str> {
        match self {
            Fault::DiskFull { file } | Fault::Panic { file } | Fault::Kill { file } => Some(file),
            Fault::Commit => None,
        }
    }
}

/// The armed fault, if it is `Commit` (`file` = `None`) or targets `file`.
fn armed(file: Option<&str>) -> Option<Fault> {
    FAULT.with(|f| f.borrow().clone().filter(|fault| fault.file() == file))
}

fn no_space() -> std::io::Error {
    #[cfg(unix)]
    {
        std::io::Error::from_raw_os_error(28) // ENOSPC
    }
    #[cfg(not(unix))]
    {
        std::io::Error::from(std::io::ErrorKind::StorageFull)
    }
}

/// The marker file a run writes into every result folder. A run replaces an existing
/// folder only when it holds this marker (a previous result) or nothing at all: never a
/// folder of the user's own files.
pub const MARKER: &str = ".msd-results";

const MARKER_TEXT: &str =
    "A results folder of the msd toolkit: the next run into this folder replaces it whole.\n";

/// Checks, before anything is computed, that a run may write `target`: it does not exist,
/// is an empty folder, or is a previous result (it holds [`MARKER`], or only the files
/// runs wrote before the marker existed). Anything else is
/// refused as a bad output choice (exit status 2), naming the folder, a few of the
/// files that would be lost and what to do.
///
/// ```
/// use msd_experiment::output::check_target;
/// let root = tempfile::tempdir().unwrap();
/// assert!(check_target(&root.path().join("new")).is_ok());
/// std::fs::write(root.path().join("measurement.csv"), "t,f,x\n").unwrap();
/// let err = check_target(root.path()).unwrap_err();
/// assert_eq!(err.exit_code(), 2);
/// assert!(err.to_string().contains("measurement.csv"));
/// ```
pub fn check_target(target: &Path) -> Result<()> {
    if !target.exists() {
        return Ok(());
    }
    let refuse = |message: String| Err(ExperimentError::config(target, message));
    if !target.is_dir() {
        return refuse(
            "the output exists and is not a folder: expected a new, empty or previous result folder (choose another --out)".into(),
        );
    }
    let entries = std::fs::read_dir(target).map_err(|e| {
        ExperimentError::config(target, format!("cannot read the output folder: {e}"))
    })?;
    let mut names: Vec<String> = entries
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    if names.iter().any(|n| n == MARKER) {
        return Ok(());
    }
    names.retain(|n| !is_legacy_output(n));
    if names.is_empty() {
        return Ok(());
    }
    names.sort();
    let shown = names.iter().take(3).cloned().collect::<Vec<_>>().join(", ");
    let more = names.len().saturating_sub(3);
    let more = if more > 0 {
        format!(" and {more} more")
    } else {
        String::new()
    };
    refuse(format!(
        "the output folder holds files a run did not write ({shown}{more}) and no {MARKER} marker: a run replaces its output folder whole, so it refuses this one; choose a new or empty folder with --out (or output.dir)"
    ))
}

/// Whether `name` is a file that runs wrote before result folders had the marker (a
/// folder of only such files is an old result, replaced as before).
fn is_legacy_output(name: &str) -> bool {
    const TABLES: [&str; 7] = [
        "results.json",
        "report.md",
        "identification.csv",
        "validation.csv",
        "residual_correlation.csv",
        "frf.csv",
        "nonlinear.csv",
    ];
    const FIGURES: [&str; 6] = [
        "fig2_identification",
        "fig3_validation",
        "fig4_monte_carlo",
        "residual_correlation",
        "frf_bode",
        "nonlinear_residuals",
    ];
    TABLES.contains(&name)
        || FIGURES.iter().any(|f| {
            name.strip_prefix(f)
                .is_some_and(|ext| ext == ".png" || ext == ".svg")
        })
}

/// A staging folder that becomes `target` on [`Staging::commit`] and disappears if
/// dropped before.
///
/// ```
/// let root = tempfile::tempdir().unwrap();
/// let target = root.path().join("run");
/// let staging = msd_experiment::output::Staging::new(&target)?;
/// staging.write("a.txt", b"hello")?;
/// assert!(!target.exists());
/// staging.commit()?;
/// assert_eq!(std::fs::read(target.join("a.txt")).unwrap(), b"hello");
/// # Ok::<(), msd_experiment::ExperimentError>(())
/// ```
#[derive(Debug)]
pub struct Staging {
    dir: PathBuf,
    target: PathBuf,
    committed: bool,
}

impl Staging {
    /// Creates the staging folder beside `target` (creating `target`'s parent folders),
    /// with the [`MARKER`] in it; refuses a `target` that [`check_target`] refuses.
    pub fn new(target: &Path) -> Result<Self> {
        check_target(target)?;
        let fail = |what: &str, e: std::io::Error| {
            ExperimentError::run("write", format!("{what} {}: {e}", target.display()))
        };
        let name = target
            .file_name()
            .ok_or_else(|| {
                ExperimentError::run(
                    "write",
                    format!("output folder {} has no name", target.display()),
                )
            })?
            .to_string_lossy()
            .into_owned();
        let parent = target
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        std::fs::create_dir_all(parent).map_err(|e| fail("cannot create the parent of", e))?;
        recover_leftovers(parent, &name, target);
        let unique = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_nanos())
            .unwrap_or(0);
        let dir = parent.join(format!(".{name}.partial-{}-{unique}", std::process::id()));
        std::fs::create_dir(&dir).map_err(|e| fail("cannot create a staging folder for", e))?;
        let staging = Self {
            dir,
            target: target.to_path_buf(),
            committed: false,
        };
        std::fs::write(staging.dir.join(MARKER), MARKER_TEXT)
            .map_err(|e| fail("cannot write the marker of", e))?;
        Ok(staging)
    }

    /// The staging folder (write here).
    pub fn path(&self) -> &Path {
        &self.dir
    }

    /// The final folder.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Writes `bytes` to `name` inside the staging folder.
    pub fn write(&self, name: &str, bytes: &[u8]) -> Result<()> {
        let path = self.dir.join(name);
        let fail =
            |e: std::io::Error| ExperimentError::run("write", format!("cannot write {name}: {e}"));
        match armed(Some(name)) {
            Some(Fault::DiskFull { .. }) => {
                std::fs::write(&path, &bytes[..bytes.len() / 2]).map_err(fail)?;
                Err(fail(no_space()))
            }
            Some(Fault::Panic { .. }) => panic!("injected fault: a panic while writing {name}"),
            Some(Fault::Kill { .. }) => {
                let _ = std::fs::write(&path, &bytes[..bytes.len() / 2]);
                std::process::exit(137)
            }
            _ => std::fs::write(path, bytes).map_err(fail),
        }
    }

    /// Moves the staging folder onto the target, replacing a previous one.
    pub fn commit(mut self) -> Result<()> {
        let old = if self.target.exists() {
            let name = self
                .target
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let old = self
                .dir
                .with_file_name(format!(".{name}.old-{}", std::process::id()));
            std::fs::rename(&self.target, &old).map_err(|e| {
                ExperimentError::run(
                    "write",
                    format!(
                        "cannot move the previous {} aside: {e}",
                        self.target.display()
                    ),
                )
            })?;
            Some(old)
        } else {
            None
        };
        let moved = match armed(None) {
            Some(_) => Err(no_space()),
            None => std::fs::rename(&self.dir, &self.target),
        };
        if let Err(e) = moved {
            if let Some(old) = &old {
                let _ = std::fs::rename(old, &self.target);
            }
            return Err(ExperimentError::run(
                "write",
                format!(
                    "cannot move the results into {}: {e}",
                    self.target.display()
                ),
            ));
        }
        self.committed = true;
        if let Some(old) = old {
            let _ = std::fs::remove_dir_all(old);
        }
        Ok(())
    }
}

/// Cleans up after killed runs into `target` (named `name`, in `parent`): removes the
/// staging folders of processes that no longer run, and puts back a previous result that
/// a kill left moved aside (or removes it when the target is there). Best effort: a
/// leftover that cannot be removed is left alone; nothing of a running process is touched.
fn recover_leftovers(parent: &Path, name: &str, target: &Path) {
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    let partial = format!(".{name}.partial-");
    let old = format!(".{name}.old-");
    for entry in entries.flatten() {
        let file_name = entry.file_name().to_string_lossy().into_owned();
        let (rest, is_old) = if let Some(rest) = file_name.strip_prefix(&partial) {
            (rest, false)
        } else if let Some(rest) = file_name.strip_prefix(&old) {
            (rest, true)
        } else {
            continue;
        };
        let pid = rest.split('-').next().and_then(|p| p.parse::<u32>().ok());
        if pid.is_none_or(process_is_running) {
            continue;
        }
        let path = entry.path();
        if is_old && !target.exists() {
            let _ = std::fs::rename(&path, target);
        } else {
            let _ = std::fs::remove_dir_all(&path);
        }
    }
}

/// Whether process `pid` is running (this one always is). Where that cannot be told
/// (outside Linux), every process counts as running, so nothing is removed.
fn process_is_running(pid: u32) -> bool {
    if pid == std::process::id() {
        return true;
    }
    if cfg!(target_os = "linux") {
        Path::new("/proc").join(pid.to_string()).exists()
    } else {
        true
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}

/// Prints `text` on standard output; a reader that has gone (`msd plan … | head`) ends
/// the printing quietly instead of a panic.
///
/// ```
/// msd_experiment::output::print_stdout("plan `paper`: …\n");
/// ```
pub fn print_stdout(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}
