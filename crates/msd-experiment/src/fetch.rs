//! Real measured records, fetched into one place and checked: `data/<set>/` in the
//! workspace (git-ignored), where the shipped configs look for them.
//!
//! The only set today is the Silverbox benchmark (Wigren & Schoukens, ECC 2013): the two
//! CSV members of its official archive, each checked against its published size and
//! SHA-256 before it is put in place. [`fetch`] copies them from a local mirror (CI keeps
//! one beside the checkout); [`download`] takes them from the official archive (or a
//! copy of it: a URL, a `file://` URL or the path of a zip). Every file is checked before
//! any is written, and each is put in place by a rename: a file that fails its check, a
//! failed download or a copy that fails half-way leaves nothing behind.
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

mod download;

pub use download::{DownloadOptions, direct_url, download, is_http};

use crate::error::{ExperimentError, Result};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// Whether this build downloads over HTTP and HTTPS (msd-experiment's `download` feature,
/// on by default and in the `msd` command; xtask builds without it). Without it,
/// [`download`] takes local archives only.
///
/// ```
/// use msd_experiment::fetch::{HTTP_SUPPORT, SILVERBOX, is_http};
/// // The official archive is on the web: this build fetches it only with HTTP support.
/// assert!(is_http(SILVERBOX.archive.url));
/// println!("can download it: {HTTP_SUPPORT}");
/// ```
pub const HTTP_SUPPORT: bool = cfg!(feature = "download");

/// One file of a data set, as published.
///
/// ```
/// use msd_experiment::fetch::SILVERBOX;
/// let file = SILVERBOX.files[0];
/// assert_eq!((file.name, file.bytes), ("SNLS80mV.csv", 2_649_634));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DataFile {
    /// File name.
    pub name: &'static str,
    /// Size in bytes.
    pub bytes: u64,
    /// SHA-256, lowercase hex.
    pub sha256: &'static str,
}

/// Where a data set's official archive is, and where its files are inside it: a zip, or
/// a folder of plain files on the web (`zipped = false`: file NAME is at
/// `url` + `folder/` + NAME).
///
/// ```
/// use msd_experiment::fetch::SILVERBOX;
/// assert_eq!(SILVERBOX.archive.member_path("SNLS80mV.csv"), "SilverboxFiles/SNLS80mV.csv");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Archive {
    /// The archive (a zip) as its publisher links it; [`download`] takes it from here
    /// unless given another URL. A Google Drive link is turned into a direct download
    /// ([`direct_url`]).
    pub url: &'static str,
    /// The folder of the set's files inside the archive (`""`: at its root).
    pub folder: &'static str,
    /// Whether `url` is a zip holding the files (else the files lie under it).
    pub zipped: bool,
}

impl Archive {
    /// The path of the member `name` inside the archive.
    ///
    /// ```
    /// use msd_experiment::fetch::Archive;
    /// let flat = Archive { url: "file:///tmp/x.zip", folder: "", zipped: true };
    /// assert_eq!(flat.member_path("a.csv"), "a.csv");
    /// ```
    pub fn member_path(&self, name: &str) -> String {
        if self.folder.is_empty() {
            name.to_string()
        } else {
            format!("{}/{name}", self.folder.trim_end_matches('/'))
        }
    }

    /// Where the file `name` is when the set is not zipped: under `url` (a URL, a
    /// `file://` URL or a folder), in `folder`.
    ///
    /// ```
    /// use msd_experiment::fetch::Archive;
    /// let files = Archive { url: "/mirror", folder: "data", zipped: false };
    /// assert_eq!(files.file_url("a.txt"), "/mirror/data/a.txt");
    /// ```
    pub fn file_url(&self, name: &str) -> String {
        self.file_url_under(self.url, name)
    }

    /// [`file_url`](Self::file_url) under another base (a `--url` given by the user).
    pub(crate) fn file_url_under(&self, base: &str, name: &str) -> String {
        format!("{}/{}", base.trim_end_matches('/'), self.member_path(name))
    }
}

/// A named set of files, and the archive they come from.
///
/// ```
/// use msd_experiment::fetch::{SILVERBOX, set_named};
/// assert_eq!(set_named("silverbox").unwrap(), SILVERBOX);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DataSetFiles {
    /// The name `fetch-data` takes, and the folder under `data/`.
    pub name: &'static str,
    /// Its files.
    pub files: [DataFile; 2],
    /// Its official archive.
    pub archive: Archive,
}

/// The Silverbox benchmark's CSV members (nonlinearbenchmark.org, SilverboxFiles.zip).
///
/// The archive is the one the Python package `nonlinear-benchmarks` downloads: its
/// `Silverbox()` (GerbenBeintema/nonlinear_benchmarks, `nonlinear_benchmarks/benchmarks.py`
/// at commit 3be65be159aae5ee69be40753e6eec48e5c60ddc) takes
/// `https://drive.google.com/file/d/17iS-6oBUUgrmiAcrZoG9S5sOaljZnDSy/view` (5,793,999
/// bytes, saved as `SilverboxFiles.zip`) and reads its records from the folder
/// `SilverboxFiles/` of the unpacked archive, where the CSV versions lie beside the
/// `.mat` files. Its `cashed_download` (`nonlinear_benchmarks/utilities.py` at commit
/// 9eec18ce9061234ab0721476406bfee799fbb1da, `download_file_from_google_drive`) turns the
/// link into a direct download the way [`direct_url`] does.
///
/// ```
/// use msd_experiment::fetch::{SILVERBOX, direct_url};
/// assert_eq!(
///     direct_url(SILVERBOX.archive.url),
///     "https://docs.google.com/uc?export=download&id=17iS-6oBUUgrmiAcrZoG9S5sOaljZnDSy"
/// );
/// ```
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
    archive: Archive {
        url: "https://drive.google.com/file/d/17iS-6oBUUgrmiAcrZoG9S5sOaljZnDSy/view",
        folder: "SilverboxFiles",
        zipped: true,
    },
};

/// Two measured accelerance FRFs of a real structure from a roving-hammer test
/// (accelerometer at point 1, hammer at points 1 and 2; 0–1000 Hz every 1 Hz, one
/// complex number per line in Python's notation), from the public repository ladisk/pyuff
/// (MIT licence), `data/meas_point_1.txt` and `data/meas_point_2.txt` at commit
/// 44a12caa81907e2303956dbbb4fbc7267fb77881, taken byte for byte.
///
/// ```
/// use msd_experiment::fetch::{IMPACT_FRF, set_named};
/// assert_eq!(set_named("impact-frf").unwrap(), IMPACT_FRF);
/// assert_eq!(
///     IMPACT_FRF.archive.file_url("meas_point_1.txt"),
///     "https://raw.githubusercontent.com/ladisk/pyuff/44a12caa81907e2303956dbbb4fbc7267fb77881/data/meas_point_1.txt"
/// );
/// ```
pub const IMPACT_FRF: DataSetFiles = DataSetFiles {
    name: "impact-frf",
    files: [
        DataFile {
            name: "meas_point_1.txt",
            bytes: 43_464,
            sha256: "ae99c87c17747ddc0819dffc6fadaf605385b5e5a0eec43415b724aaccf7223a",
        },
        DataFile {
            name: "meas_point_2.txt",
            bytes: 44_383,
            sha256: "872f58a6e812cd9abed390262bec120d9064738524faff082929dd303a17e340",
        },
    ],
    archive: Archive {
        url: "https://raw.githubusercontent.com/ladisk/pyuff/44a12caa81907e2303956dbbb4fbc7267fb77881/",
        folder: "data",
        zipped: false,
    },
};

/// The known sets, by name.
///
/// ```
/// assert_eq!(msd_experiment::fetch::SETS.map(|s| s.name), ["silverbox", "impact-frf"]);
/// ```
pub const SETS: [DataSetFiles; 2] = [SILVERBOX, IMPACT_FRF];

/// The set called `name`, or a config error listing the known ones.
///
/// ```
/// let err = msd_experiment::fetch::set_named("goldbox").unwrap_err();
/// assert!(err.to_string().contains("expected one of silverbox, impact-frf"), "{err}");
/// ```
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
///
/// ```
/// use msd_experiment::fetch::command_for;
/// let command = command_for("data/silverbox/SNLS80mV.csv".as_ref()).unwrap();
/// assert!(command.starts_with("`cargo xtask fetch-data silverbox`"));
/// assert_eq!(command_for("data/mine/run1.csv".as_ref()), None);
/// ```
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
/// Files already in `into` that pass the check are left as they are; the others are
/// all read and checked before any is written.
///
/// ```
/// use msd_experiment::fetch::{SILVERBOX, fetch};
/// let into = tempfile::tempdir().unwrap();
/// let err = fetch(&SILVERBOX, "no/such/mirror".as_ref(), into.path()).unwrap_err();
/// assert!(err.to_string().contains("cannot read the silverbox file"), "{err}");
/// ```
pub fn fetch(set: &DataSetFiles, mirror: &Path, into: &Path) -> Result<Vec<PathBuf>> {
    let mut checked = Vec::new();
    for file in missing(set, into) {
        let source = mirror.join(file.name);
        let bytes = std::fs::read(&source).map_err(|e| {
            ExperimentError::data(&source, format!("cannot read the {} file: {e}", set.name))
        })?;
        check(&bytes, file).map_err(|why| ExperimentError::data(&source, why))?;
        checked.push((file, bytes));
    }
    place(set, into, &checked)
}

/// Checks the file at `path` against `file`'s size and SHA-256.
///
/// ```
/// use msd_experiment::fetch::{DataFile, verify};
/// let dir = tempfile::tempdir().unwrap();
/// std::fs::write(dir.path().join("a.csv"), "one\n").unwrap();
/// let file = DataFile {
///     name: "a.csv",
///     bytes: 4,
///     sha256: "2c8b08da5ce60398e1f19af0e5dccc744df274b826abe585eaba68c525434806",
/// };
/// verify(&dir.path().join("a.csv"), &file).unwrap();
/// ```
pub fn verify(path: &Path, file: &DataFile) -> Result<()> {
    let bytes = std::fs::read(path)
        .map_err(|e| ExperimentError::data(path, format!("cannot read: {e}")))?;
    check(&bytes, file).map_err(|why| ExperimentError::data(path, why))
}

/// The files of `set` not yet in `into` with the right size and SHA-256.
fn missing<'a>(set: &'a DataSetFiles, into: &Path) -> Vec<&'a DataFile> {
    set.files
        .iter()
        .filter(|file| verify(&into.join(file.name), file).is_err())
        .collect()
}

/// Puts the checked `files` into `into` (created if needed), each written beside its
/// target under a hidden name and renamed onto it; returns every file of `set` in `into`.
fn place(set: &DataSetFiles, into: &Path, files: &[(&DataFile, Vec<u8>)]) -> Result<Vec<PathBuf>> {
    if !files.is_empty() {
        std::fs::create_dir_all(into).map_err(|e| {
            ExperimentError::data(into, format!("cannot create the data folder: {e}"))
        })?;
    }
    for (file, bytes) in files {
        let target = into.join(file.name);
        let partial = into.join(format!(".{}.partial-{}", file.name, std::process::id()));
        let written =
            std::fs::write(&partial, bytes).and_then(|()| std::fs::rename(&partial, &target));
        if let Err(e) = written {
            let _ = std::fs::remove_file(&partial);
            return Err(ExperimentError::data(&target, format!("cannot write: {e}")));
        }
    }
    Ok(set.files.iter().map(|f| into.join(f.name)).collect())
}

/// `bytes` against `file`'s size and SHA-256: the reason it is not that file.
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
