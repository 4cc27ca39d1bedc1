//! The crate's one error type, [`UffError`], and the [`Position`] it points at.
//!
//! A file that cannot be read is refused with where it went wrong (byte offset, line where
//! the place is text, and the number of the dataset being read), what was found there and
//! what the format expects:
//!
//! ```
//! let text = [
//!     "    -1",
//!     "    58",
//!     "NONE", "NONE", "NONE", "NONE", "NONE",
//!     "    4         0    0         0       NONE         1   3       NONE         1   3",
//!     "         7         1         1  0.00000e+00  1.00000e+00  0.00000e+00",
//! ]
//! .join("\n");
//! let err = msd_uff::parse(text.as_bytes()).unwrap_err();
//! assert!(matches!(&err, msd_uff::UffError::Malformed { at, .. }
//!     if at.dataset == Some(58) && at.line == Some(9)));
//! assert_eq!(
//!     err.to_string(),
//!     "dataset 58, byte 129, line 9: record 7, ordinate data type: found \"7\", \
//!      expected 2, 4, 5 or 6 (real or complex, single or double precision)"
//! );
//! ```

use std::fmt;
use std::path::PathBuf;

use serde::Serialize;
use thiserror::Error;

/// Where in a file something was found.
///
/// ```
/// let at = msd_uff::Position { dataset: Some(58), offset: 1234, line: Some(17) };
/// assert_eq!(at.to_string(), "dataset 58, byte 1234, line 17");
/// let binary = msd_uff::Position { dataset: Some(58), offset: 900, line: None };
/// assert_eq!(binary.to_string(), "dataset 58, byte 900");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Position {
    /// The number of the dataset being read (58, 151, …); `None` outside a dataset or
    /// before its number was read.
    pub dataset: Option<u32>,
    /// Byte offset from the start of the file (0-based).
    pub offset: usize,
    /// Line number (1-based); `None` inside binary data, where lines mean nothing.
    pub line: Option<usize>,
}

impl fmt::Display for Position {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(number) = self.dataset {
            write!(f, "dataset {number}, ")?;
        }
        write!(f, "byte {}", self.offset)?;
        if let Some(line) = self.line {
            write!(f, ", line {line}")?;
        }
        Ok(())
    }
}

/// Everything `msd-uff` can refuse, reading or writing.
///
/// ```
/// let err = msd_uff::read("no/such/file.uff").unwrap_err();
/// assert!(matches!(err, msd_uff::UffError::Io { .. }));
/// assert!(std::error::Error::source(&err).is_some()); // the io::Error
/// ```
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum UffError {
    /// The file could not be opened, read or written.
    #[error("cannot {action} {path}: {source}")]
    Io {
        /// `"read"` or `"write"`.
        action: &'static str,
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// A field, line or block is not what the format allows.
    #[error("{at}: {field}: found {found}, expected {expected}")]
    Malformed {
        /// Where the offending field starts.
        at: Position,
        /// Which field or part, as the format names it (e.g. `record 7, number of points`).
        field: &'static str,
        /// What was found (text is quoted).
        found: String,
        /// What the format expects there.
        expected: String,
    },
    /// The file ends in the middle of a dataset.
    #[error("{at}: the file ends in {field}: found {found}, expected {expected}")]
    Truncated {
        /// Where the missing part should start.
        at: Position,
        /// Which part is cut short.
        field: &'static str,
        /// What is there (e.g. `the end of the file`, `100 bytes`).
        found: String,
        /// What should have been there.
        expected: String,
    },
    /// A value in memory cannot be written in the format's fields.
    #[error(
        "cannot write dataset {dataset} (#{index} of its kind): `{field}` = {value}: expected {expected}"
    )]
    Unwritable {
        /// The dataset number (15, 55, 58, 151, 164 or 2411).
        dataset: u32,
        /// Index among the datasets of that kind (`functions[index]` for 58,
        /// `data_at_nodes[index]` for 55), or of the node (`nodes[index]`) for 15 and 2411;
        /// 0 otherwise.
        index: usize,
        /// The field, as named in this crate's types.
        field: &'static str,
        /// The offending value.
        value: String,
        /// What fits the field.
        expected: String,
    },
}
