//! Real measured records, fetched into one place and checked: `data/<set>/` in the
//! workspace (git-ignored), where the shipped configs look for them.
//!
//! The only set today is the Silverbox benchmark (Wigren & Schoukens, ECC 2013): the two
//! CSV members of its official archive, each checked against its published size and
//! SHA-256 before it is put in place. [`fetch`] copies them from a local mirror (CI keeps
//! one beside the checkout); a file that fails its check, or a copy that fails half-way,
//! leaves nothing behind.
//!
//! ```
//! use msd_experiment::fetch::{SILVERBOX, fetch};
//! let mirror = tempfile::tempdir().unwrap();
//! let into = tempfile::tempdir().unwrap();
//! // A mirror with a damaged file is refused, and nothing is written.
//! for file in &SILVERBOX.files {
//!     std::fs::write(mirror.path().join(file.name), b"not the data").unwrap();
//! }
//! let err = fetch(&SILVERBOX, mirror.path(), into.path()).unwrap_err();
//! assert!(err.to_string().contains("size"), "{err}");
//! assert_eq!(std::fs::read_dir(into.path()).unwrap().count(), 0);
//! ```

use crate::{ExperimentError, Result};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// One file of a data set, as published.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DataFile {
    /// File name.
    pub name: &'static str,
    /// Size in bytes.
    pub bytes: u64,
    /// SHA-256, lowercase hex.
    pub sha256: &'static str,
}

/// A named set of files.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DataSetFiles {
    /// The name `fetch-data` takes, and the folder under `data/`.
    pub name: &'static str,
    /// Its files.
    pub files: [DataFile; 2],
}

/// The Silverbox benchmark's CSV members (nonlinearbenchmark.org, SilverboxFiles.zip).
pub const SILVERBOX: DataSetFiles = DataSetFiles {
    name: "silverbox",
    files: [
        DataFile {
            name: "SNLS80mV.csv",
            bytes: 2_649_634,
            sha256: "ae62d5a91230c10f76e6dd02c8a4fac3c9d4d8a95fbf50e87cb0c4885003e0f1",
        },
        DataFile {
            name: "Schroeder80mV.csv",
            bytes: 2_891_573,
            sha256: "b22cbcba9c59d9b4b1b379967b669dc32959e515b24784da3254505f8563e36c",
        },
    ],
};

/// The known sets, by name.
pub const SETS: [DataSetFiles; 1] = [SILVERBOX];

/// The set called `name`, or a config error listing the known ones.
pub fn set_named(name: &str) -> Result<DataSetFiles> {
    SETS.iter()
        .copied()
        .find(|s| s.name == name)
        .ok_or_else(|| {
            let known: Vec<&str> = SETS.iter().map(|s| s.name).collect();
            ExperimentError::config(
                name,
                format!("unknown data set: expected one of {}", known.join(", ")),
            )
        })
}

/// The command that fetches the set a missing data file belongs to, if any (its folder
/// is named after a known set): for the "missing data file" message.
pub fn command_for(missing: &Path) -> Option<String> {
    let folder = missing.parent()?.file_name()?.to_str()?;
    let set = SETS.iter().find(|s| s.name == folder)?;
    set.files
        .iter()
        .any(|f| missing.file_name().is_some_and(|n| n == f.name))
        .then(|| {
            format!(
                "`cargo xtask fetch-data {0}` (or `msd fetch-data {0}`)",
                set.name
            )
        })
}

/// Copies every file of `set` from the folder `mirror` into `into` (created if needed),
/// each checked against its size and SHA-256 first; returns the files put in place.
/// Files already in `into` that pass the check are left as they are.
pub fn fetch(set: &DataSetFiles, mirror: &Path, into: &Path) -> Result<Vec<PathBuf>> {
    let data_error = |path: &Path, message: String| ExperimentError::data(path, message);
    std::fs::create_dir_all(into)
        .map_err(|e| data_error(into, format!("cannot create the data folder: {e}")))?;
    let mut placed = Vec::new();
    for file in &set.files {
        let target = into.join(file.name);
        if verify(&target, file).is_ok() {
            placed.push(target);
            continue;
        }
        let source = mirror.join(file.name);
        let bytes = std::fs::read(&source)
            .map_err(|e| data_error(&source, format!("cannot read the {} file: {e}", set.name)))?;
        check(&bytes, file).map_err(|why| data_error(&source, why))?;
        let partial = into.join(format!(".{}.partial-{}", file.name, std::process::id()));
        let written =
            std::fs::write(&partial, &bytes).and_then(|()| std::fs::rename(&partial, &target));
        if let Err(e) = written {
            let _ = std::fs::remove_file(&partial);
            return Err(data_error(&target, format!("cannot write: {e}")));
        }
        placed.push(target);
    }
    Ok(placed)
}

/// Checks the file at `path` against `file`'s size and SHA-256.
pub fn verify(path: &Path, file: &DataFile) -> Result<()> {
    let bytes = std::fs::read(path)
        .map_err(|e| ExperimentError::data(path, format!("cannot read: {e}")))?;
    check(&bytes, file).map_err(|why| ExperimentError::data(path, why))
}

fn check(bytes: &[u8], file: &DataFile) -> std::result::Result<(), String> {
    if bytes.len() as u64 != file.bytes {
        return Err(format!(
            "size {} bytes: expected {} bytes for {} (a partial or different file)",
            bytes.len(),
            file.bytes,
            file.name
        ));
    }
    let digest = Sha256::digest(bytes);
    let hex: String = digest.iter().map(|b| format!("{b:02x}")).collect();
    if hex != file.sha256 {
        return Err(format!(
            "SHA-256 {hex}: expected {} for {} (a damaged or different file)",
            file.sha256, file.name
        ));
    }
    Ok(())
}
