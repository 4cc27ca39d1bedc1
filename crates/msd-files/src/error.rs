//! The crate's one error type.

use crate::FileFormat;
use std::path::PathBuf;
use thiserror::Error;

/// Why a file could not be read; every variant names the file.
///
/// ```
/// let err = msd_files::read_bytes("rig/run.npy", b"not numpy").unwrap_err();
/// assert!(err.to_string().starts_with("rig/run.npy: not a NumPy .npy file"), "{err}");
/// ```
#[derive(Debug, Error)]
pub enum FilesError {
    /// The file could not be opened or read.
    #[error("{}: cannot read the file: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The system's reason.
        #[source]
        source: std::io::Error,
    },
    /// The extension is not one this crate reads.
    #[error("{}: extension {found:?}: expected .mat, .npy, .npz or .tdms", path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// The extension found.
        found: String,
    },
    /// The file is not what its extension says, or is truncated or corrupt.
    #[error("{}: not a {} file that can be read: {why}", path.display(), format.name())]
    Malformed {
        /// The file.
        path: PathBuf,
        /// The format its extension says.
        format: FileFormat,
        /// What was wrong, and what was expected.
        why: String,
    },
}
