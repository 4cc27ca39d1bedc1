//! Data-acquisition files read as named channels of numbers.
//!
//! A lab's records come out of MATLAB (`.mat`, levels 5 and 7), NumPy (`.npy`, `.npz`)
//! and LabVIEW (NI TDMS). [`read`] turns any of them into [`Contents`]: the channels it
//! holds, each a name, a unit where the file gives one, its samples and a sampling rate
//! where the file gives one. The formats themselves are read by well-kept crates
//! (`npyz` with `zip` for NumPy; MATLAB and TDMS as their publishers document them, since
//! the crates for them fail on valid files: `matfile` on every int32 array, `tdms` on a
//! segment of properties only; MATLAB's compressed elements through `flate2`); this crate decides what a channel is and says,
//! naming the file, what it could not read and why.
//!
//! What a channel is:
//! - **MATLAB**: each numeric variable. A vector (N×1 or 1×N) is one channel named as
//!   the variable; a matrix is split along its shorter dimension into channels
//!   `name[0]`, `name[1]`, … (0-based, as every column index of the toolkit); a complex
//!   variable gives `name.re` and `name.im`. A structure's fields are channels named
//!   `s.field` (nested `s.a.b`, in a structure array `s(k).field`, k from 1), as labs and
//!   Simulink save records; a cell array's cells `c{k}` (k from 1). Text and objects
//!   are listed as skipped. Level 7.3 files (HDF5) are refused with the advice to save with `-v7`.
//! - **NumPy**: a `.npy` array is named after its file; an `.npz` archive holds one array
//!   per entry, named as `numpy.savez` named it. Matrices split as MATLAB's are.
//! - **TDMS**: each channel, named `group/channel` (or `channel` where that name is unique
//!   in the file), its unit from `unit_string` and its rate from `wf_increment`.
//!
//! ```
//! # fn main() -> Result<(), msd_files::FilesError> {
//! // A .npy array as numpy.save writes it: 3 samples × 2 channels, float64, C order.
//! let header = "{'descr': '<f8', 'fortran_order': False, 'shape': (3, 2), }";
//! let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
//! let padded = format!("{header:<117}\n");
//! bytes.extend((padded.len() as u16).to_le_bytes());
//! bytes.extend(padded.as_bytes());
//! for v in [0.0f64, 10.0, 1.0, 11.0, 2.0, 12.0] {
//!     bytes.extend(v.to_le_bytes());
//! }
//! let contents = msd_files::read_bytes("run.npy", &bytes)?;
//! assert_eq!(contents.channels.len(), 2);
//! assert_eq!(contents.channels[1].name, "run[1]");
//! assert_eq!(contents.channels[1].values, vec![10.0, 11.0, 12.0]);
//! # Ok(())
//! # }
//! ```

mod error;
mod inventory;
mod mat;
mod numpy;
mod split;
mod tdms_file;

pub use error::FilesError;
pub use numpy::npy_array;

use serde::Serialize;
use std::path::Path;

/// The formats this crate reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FileFormat {
    /// MATLAB `.mat`, level 5 or 7 (compressed).
    Mat,
    /// One NumPy array, `.npy`.
    Npy,
    /// A NumPy archive of arrays, `.npz`.
    Npz,
    /// NI TDMS (LabVIEW), `.tdms`.
    Tdms,
}

impl FileFormat {
    /// The format a file name's extension says (case-insensitive), if this crate reads it.
    ///
    /// ```
    /// use msd_files::FileFormat;
    /// assert_eq!(FileFormat::of(std::path::Path::new("rig/DATA.MAT")), Some(FileFormat::Mat));
    /// assert_eq!(FileFormat::of(std::path::Path::new("run.csv")), None);
    /// ```
    pub fn of(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "mat" => Some(Self::Mat),
            "npy" => Some(Self::Npy),
            "npz" => Some(Self::Npz),
            "tdms" => Some(Self::Tdms),
            _ => None,
        }
    }

    /// The format's name, as users know it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Mat => "MATLAB .mat",
            Self::Npy => "NumPy .npy",
            Self::Npz => "NumPy .npz",
            Self::Tdms => "NI TDMS",
        }
    }
}

/// One channel: a name, its samples as numbers, and what the file says of them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Channel {
    /// The name a config gives to pick it (`qm`, `Y[1]`, `Rig/Force`).
    pub name: String,
    /// Its unit, where the file gives one.
    pub unit: Option<String>,
    /// Its sampling rate in Hz, where the file gives one (TDMS `wf_increment`).
    pub sample_rate_hz: Option<f64>,
    /// The samples, converted to `f64` (integers exactly, `f32` widened).
    pub values: Vec<f64>,
}

impl Channel {
    /// A channel of `values` named `name`, with no unit or rate.
    pub fn new(name: impl Into<String>, values: Vec<f64>) -> Self {
        Self {
            name: name.into(),
            unit: None,
            sample_rate_hz: None,
            values,
        }
    }
}

/// What a file holds: its format, its channels in the file's order, and what was left
/// out (text, structures, arrays of three or more dimensions), each with why.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Contents {
    /// The format read.
    pub format: FileFormat,
    /// The channels, in the file's order.
    pub channels: Vec<Channel>,
    /// What the file holds that is not a channel, each `name: why`.
    pub skipped: Vec<String>,
}

impl Contents {
    /// The channel named `name`.
    pub fn channel(&self, name: &str) -> Option<&Channel> {
        self.channels.iter().find(|c| c.name == name)
    }

    /// The channels as `(name, values)` pairs, the toolkit's in-memory table.
    pub fn into_columns(self) -> Vec<(String, Vec<f64>)> {
        self.channels
            .into_iter()
            .map(|c| (c.name, c.values))
            .collect()
    }
}

/// Reads the file at `path`, its format from its extension.
///
/// Errors name the file: one that cannot be opened, an extension this crate does not
/// read, a file that is not what its extension says, or is truncated or corrupt.
pub fn read(path: &Path) -> Result<Contents, FilesError> {
    let format = format_of(path)?;
    let bytes = std::fs::read(path).map_err(|source| FilesError::Io {
        path: path.into(),
        source,
    })?;
    read_format(path, format, &bytes)
}

/// Reads a file given as its bytes; `name` (a file name or path) gives its format by
/// its extension and names it in errors.
pub fn read_bytes(name: impl AsRef<Path>, bytes: &[u8]) -> Result<Contents, FilesError> {
    let path = name.as_ref();
    let format = format_of(path)?;
    read_format(path, format, bytes)
}

fn format_of(path: &Path) -> Result<FileFormat, FilesError> {
    FileFormat::of(path).ok_or_else(|| FilesError::Format {
        path: path.into(),
        found: path
            .extension()
            .map_or_else(String::new, |e| e.to_string_lossy().into_owned()),
    })
}

fn read_format(path: &Path, format: FileFormat, bytes: &[u8]) -> Result<Contents, FilesError> {
    let bad = |why: String| FilesError::Malformed {
        path: path.into(),
        format,
        why,
    };
    let (channels, skipped) = match format {
        FileFormat::Mat => mat::read(bytes).map_err(bad)?,
        FileFormat::Npy => numpy::read_npy(path, bytes).map_err(bad)?,
        FileFormat::Npz => numpy::read_npz(bytes).map_err(bad)?,
        FileFormat::Tdms => tdms_file::read_bytes(bytes).map_err(bad)?,
    };
    Ok(Contents {
        format,
        channels,
        skipped,
    })
}
