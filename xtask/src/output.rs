//! Atomic output: everything is written into a hidden staging folder next to the
//! target, which replaces the target only once it is complete. A failed run (an error or
//! a panic) removes the staging folder and leaves any previous target untouched.

use crate::{Result, XtaskError};
use std::path::{Path, PathBuf};

/// A staging folder that becomes `target` on [`Staging::commit`] and disappears if
/// dropped before.
///
/// ```
/// let root = tempfile::tempdir().unwrap();
/// let target = root.path().join("run");
/// let staging = xtask::output::Staging::new(&target)?;
/// staging.write("a.txt", b"hello")?;
/// assert!(!target.exists());
/// staging.commit()?;
/// assert_eq!(std::fs::read(target.join("a.txt")).unwrap(), b"hello");
/// # Ok::<(), xtask::XtaskError>(())
/// ```
#[derive(Debug)]
pub struct Staging {
    dir: PathBuf,
    target: PathBuf,
    committed: bool,
}

impl Staging {
    /// Creates the staging folder beside `target` (creating `target`'s parent folders).
    pub fn new(target: &Path) -> Result<Self> {
        let fail = |what: &str, e: std::io::Error| {
            XtaskError::run("write", format!("{what} {}: {e}", target.display()))
        };
        let name = target
            .file_name()
            .ok_or_else(|| {
                XtaskError::run(
                    "write",
                    format!("output folder {} has no name", target.display()),
                )
            })?
            .to_string_lossy()
            .into_owned();
        if target.exists() && !target.is_dir() {
            return Err(XtaskError::run(
                "write",
                format!(
                    "output {} exists and is not a folder: expected a folder to replace",
                    target.display()
                ),
            ));
        }
        let parent = target
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        std::fs::create_dir_all(parent).map_err(|e| fail("cannot create the parent of", e))?;
        let unique = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_nanos())
            .unwrap_or(0);
        let dir = parent.join(format!(".{name}.partial-{}-{unique}", std::process::id()));
        std::fs::create_dir(&dir).map_err(|e| fail("cannot create a staging folder for", e))?;
        Ok(Self {
            dir,
            target: target.to_path_buf(),
            committed: false,
        })
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
        std::fs::write(self.dir.join(name), bytes)
            .map_err(|e| XtaskError::run("write", format!("cannot write {name}: {e}")))
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
                XtaskError::run(
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
        if let Err(e) = std::fs::rename(&self.dir, &self.target) {
            if let Some(old) = &old {
                let _ = std::fs::rename(old, &self.target);
            }
            return Err(XtaskError::run(
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

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}
