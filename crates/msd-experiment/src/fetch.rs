//! Real measured records, fetched into one place and checked: `data/<set>/` in the
//! workspace (git-ignored), where the shipped configs look for them.
//!
//! The sets: the Silverbox benchmark (Wigren & Schoukens, ECC 2013: the two CSV members
//! of its official archive), a real hammer test's two FRFs and a real steel frame's ten
//! ambient setups, each file checked against its published size and SHA-256 before it
//! is put in place. [`fetch`] copies them from a local mirror (CI keeps
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
//! for file in SILVERBOX.files {
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
    /// Its files (a name may hold a sub-folder: `measurement_1/measurement_1.npy`).
    pub files: &'static [DataFile],
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
    files: &[
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
    files: &[
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

/// A real five-floor steel frame under a fan (no measured input), ten setups of 240 s at
/// 256 Hz for output-only analysis: each `measurement_<n>/` holds the record
/// (`measurement_<n>.npy`, 61,440 samples × 6 channels), its channels' nodes and measuring
/// directions (`channel_dofs.txt`) and its rate, references and quantities
/// (`setup_info.txt`); beside them the geometry (`grid.txt`, `lines.txt`) and the origin's
/// own merged SSI result (`merged_setups_poser.npz`). Byte-for-byte copies of
/// `tests/files/` of the public repository pyOMA-dev/pyOMA at commit
/// c0e17452b284f7ed7ae7321189f3b907666e0207 (data by S. Marwitz, V. Zabel, A. Udrea,
/// Bauhaus-Universität Weimar; GPL-3.0: fetched, never copied into this repository).
///
/// ```
/// use msd_experiment::fetch::{STEEL_FRAME, set_named};
/// assert_eq!(set_named("steel-frame").unwrap(), STEEL_FRAME);
/// assert_eq!(STEEL_FRAME.files.len(), 33);
/// assert_eq!(
///     STEEL_FRAME.archive.file_url("measurement_3/setup_info.txt"),
///     "https://raw.githubusercontent.com/pyOMA-dev/pyOMA/c0e17452b284f7ed7ae7321189f3b907666e0207/tests/files/measurement_3/setup_info.txt"
/// );
/// ```
pub const STEEL_FRAME: DataSetFiles = DataSetFiles {
    name: "steel-frame",
    files: &STEEL_FRAME_FILES,
    archive: Archive {
        url: "https://raw.githubusercontent.com/pyOMA-dev/pyOMA/c0e17452b284f7ed7ae7321189f3b907666e0207/",
        folder: "tests/files",
        zipped: false,
    },
};

const STEEL_FRAME_FILES: [DataFile; 33] = [
    DataFile {
        name: "grid.txt",
        bytes: 1_334,
        sha256: "be1e89fbaca1deb0ff36b5c555c17dd7c7a752ab07924a252d61e8926a4e9f91",
    },
    DataFile {
        name: "lines.txt",
        bytes: 480,
        sha256: "c49ee2f6593579ab16bf6eeda6e6635bf2e1eb99c78ec8529659244981925842",
    },
    DataFile {
        name: "merged_setups_poser.npz",
        bytes: 33_965,
        sha256: "24845a04ac0a5defab5394812eb4fa964baa53a91a53ebadb898d3dfc64148cd",
    },
    DataFile {
        name: "measurement_1/measurement_1.npy",
        bytes: 2_949_248,
        sha256: "ab728cf6e8136b89574bbd4216714a38678c75b6806d8af0d9fe7b628c5a45bc",
    },
    DataFile {
        name: "measurement_1/channel_dofs.txt",
        bytes: 251,
        sha256: "16e38300cff8f8a8e593764a825d1a3946760d1b3b63132067f7f76a79b4680b",
    },
    DataFile {
        name: "measurement_1/setup_info.txt",
        bytes: 351,
        sha256: "f9b4187a94235aef5a6a5fa67bb58a04d4619c8a6c4b7083f038ddc9c8a72846",
    },
    DataFile {
        name: "measurement_2/measurement_2.npy",
        bytes: 2_949_248,
        sha256: "a82de90ef33dc5ad587bab46dc900ec78ce5da0f6366002b29c97789e49f92ce",
    },
    DataFile {
        name: "measurement_2/channel_dofs.txt",
        bytes: 250,
        sha256: "4e7fad34b5db61c26a229a79106b57bb5e19b4c893173b20ffd0bd17e40ca3f1",
    },
    DataFile {
        name: "measurement_2/setup_info.txt",
        bytes: 351,
        sha256: "c5d15d9bc3603c359de6bba4eafa61a7734910a7a003a335d37e55885b97e889",
    },
    DataFile {
        name: "measurement_3/measurement_3.npy",
        bytes: 2_949_248,
        sha256: "906ea326c49b7696ab1194141d599c1828d5673c4d084c801742be2f112f82bb",
    },
    DataFile {
        name: "measurement_3/channel_dofs.txt",
        bytes: 250,
        sha256: "2a39e266755a9bde4d9d1f148183feacb94d3b80c8664dbe0ba7d9774c69b908",
    },
    DataFile {
        name: "measurement_3/setup_info.txt",
        bytes: 351,
        sha256: "c84f7d503abe3e98c79c8dbe75f3c8060a1940d095e4c4b45efbc2645b2c1726",
    },
    DataFile {
        name: "measurement_4/measurement_4.npy",
        bytes: 2_949_248,
        sha256: "8d9ea239f6c4771ef9adfa963d7b278d1fea8910ef78a7342a6885e8476a9c50",
    },
    DataFile {
        name: "measurement_4/channel_dofs.txt",
        bytes: 253,
        sha256: "ce312624bf9980c0e9d4aaa6068235e42432e66ffd300d412767156236c01e76",
    },
    DataFile {
        name: "measurement_4/setup_info.txt",
        bytes: 351,
        sha256: "dfaa93f88554209078a47038a8bfc98f385a794237256ff80645cbc9a8c26b48",
    },
    DataFile {
        name: "measurement_5/measurement_5.npy",
        bytes: 2_949_248,
        sha256: "f3685a2d2565c014c9992ccfb4b1aa5ebea3e27992947e4e21a5fff60f87fd49",
    },
    DataFile {
        name: "measurement_5/channel_dofs.txt",
        bytes: 256,
        sha256: "e87103e3ecd9aa6188f488f17728a1b19c3c6779d161ad063c41ca373a3a9bbd",
    },
    DataFile {
        name: "measurement_5/setup_info.txt",
        bytes: 351,
        sha256: "09acd0df74617a8f338c32e9591e96e20fc1cc66d13bb6d7b140dd6975c4b2e3",
    },
    DataFile {
        name: "measurement_6/measurement_6.npy",
        bytes: 2_949_248,
        sha256: "1d4dfabe4b480feae8c9339fb0203fed37e4907ea6832e8d404af5fe38fc2b4f",
    },
    DataFile {
        name: "measurement_6/channel_dofs.txt",
        bytes: 255,
        sha256: "27fe10cb43af1da4f495003cbd39b56f24cf2713b103394b6da0b2aa6b75167c",
    },
    DataFile {
        name: "measurement_6/setup_info.txt",
        bytes: 351,
        sha256: "e9ac28ffe590cb5ec298220d4fcc9024fcfc1f157dfe0d01f6281017282abff2",
    },
    DataFile {
        name: "measurement_7/measurement_7.npy",
        bytes: 2_949_248,
        sha256: "5b9b59e1f7c2f1cb84366636ae21f0259ef4cfe5e0a5fc11cc11b3697a5a155a",
    },
    DataFile {
        name: "measurement_7/channel_dofs.txt",
        bytes: 256,
        sha256: "1db001af1562f7bd4467bba8fb3c8988c4701d079f1c18069372899a433bc72a",
    },
    DataFile {
        name: "measurement_7/setup_info.txt",
        bytes: 351,
        sha256: "67143b8f11d4b7d44403d0af823be728a358615cbe095cd50d31ae8cd665b4ca",
    },
    DataFile {
        name: "measurement_8/measurement_8.npy",
        bytes: 2_949_248,
        sha256: "da40277b161dc49b39f51307776bc1e52961ccb6737215734ee759fb63d79670",
    },
    DataFile {
        name: "measurement_8/channel_dofs.txt",
        bytes: 256,
        sha256: "a80af65ff63424d32d093a67f2bff90fbff5dd452751819a3c8a9c8345b0819b",
    },
    DataFile {
        name: "measurement_8/setup_info.txt",
        bytes: 351,
        sha256: "c341d9da8b48a5bf8b11ed1eea99702e93f3fef90d97ecb2ce935f734b0ba62d",
    },
    DataFile {
        name: "measurement_9/measurement_9.npy",
        bytes: 2_949_248,
        sha256: "26b6a8969e2d3456c46e2005fdc9b978d722257bd9e9b8c14d29e871e404652e",
    },
    DataFile {
        name: "measurement_9/channel_dofs.txt",
        bytes: 255,
        sha256: "06c0216ce8427f1262b34f63ee5730886c37fac19121c2d4a849581edbc3856d",
    },
    DataFile {
        name: "measurement_9/setup_info.txt",
        bytes: 351,
        sha256: "07df15619e2da936a4d685b4839d50b32c086fdc8e515264a9a3bd7916b31013",
    },
    DataFile {
        name: "measurement_10/measurement_10.npy",
        bytes: 2_949_248,
        sha256: "46d9cbb632867ed95568f3b066ac7e920836e30d955dbfc99871e6afdde6ca35",
    },
    DataFile {
        name: "measurement_10/channel_dofs.txt",
        bytes: 254,
        sha256: "7c3b127c61b38a6289199485f32eb0f8a1ecfa04b95dcd256dcd8c3b6542abd9",
    },
    DataFile {
        name: "measurement_10/setup_info.txt",
        bytes: 352,
        sha256: "c66ef970bc8de2d7e753856de3588d0b6b77bf5b2b8f7802d10718003fcba259",
    },
];

/// The EMPS benchmark (A. Janot, M. Gautier, M. Brunot, "Data set and reference models
/// of EMPS", 2019): a real electro-mechanical positioning system, one moving mass with
/// viscous and Coulomb friction, MATLAB v5 files (`t`, `qm` the measured position, `vir`
/// the drive voltage, `gtau` the gain: force = gtau·vir); an estimation record and a
/// validation record with force pulses. Taken byte for byte from the public repository
/// forgi86/sysid-neural-continuous (Apache-2.0), `examples/EMPS/data/` at commit
/// 956aa7ecd73061b0321c6f6098d74c9e4a7ce67a, which redistributes them.
///
/// ```
/// use msd_experiment::fetch::{EMPS, set_named};
/// assert_eq!(set_named("emps").unwrap(), EMPS);
/// assert_eq!(
///     EMPS.archive.file_url("DATA_EMPS.mat"),
///     "https://raw.githubusercontent.com/forgi86/sysid-neural-continuous/956aa7ecd73061b0321c6f6098d74c9e4a7ce67a/examples/EMPS/data/DATA_EMPS.mat"
/// );
/// ```
pub const EMPS: DataSetFiles = DataSetFiles {
    name: "emps",
    files: &[
        DataFile {
            name: "DATA_EMPS.mat",
            bytes: 626_039,
            sha256: "6cf6814ae14618795da0101aae2bb97ff0c6351b0501b5492751b02b07facf7e",
        },
        DataFile {
            name: "DATA_EMPS_PULSES.mat",
            bytes: 630_990,
            sha256: "0eab75bb1f6b16228ee78791343a88bf9bfd9a51036ac9807d7b5fc11c0e1704",
        },
    ],
    archive: Archive {
        url: "https://raw.githubusercontent.com/forgi86/sysid-neural-continuous/956aa7ecd73061b0321c6f6098d74c9e4a7ce67a/",
        folder: "examples/EMPS/data",
        zipped: false,
    },
};

/// The known sets, by name.
///
/// ```
/// assert_eq!(msd_experiment::fetch::SETS.map(|s| s.name), ["silverbox", "impact-frf", "steel-frame", "emps"]);
/// ```
pub const SETS: [DataSetFiles; 4] = [SILVERBOX, IMPACT_FRF, STEEL_FRAME, EMPS];

/// The set called `name`, or a config error listing the known ones.
///
/// ```
/// let err = msd_experiment::fetch::set_named("goldbox").unwrap_err();
/// assert!(err.to_string().contains("expected one of silverbox, impact-frf, steel-frame, emps"), "{err}");
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
/// let npy = "data/steel-frame/measurement_4/measurement_4.npy";
/// assert!(command_for(npy.as_ref()).unwrap().contains("fetch-data steel-frame"));
/// ```
pub fn command_for(missing: &Path) -> Option<String> {
    // The nearest folder named after a set, and the file's path below it.
    let set = missing.ancestors().skip(1).find_map(|folder| {
        let name = folder.file_name()?.to_str()?;
        let set = SETS.iter().find(|s| s.name == name)?;
        let below = missing.strip_prefix(folder).ok()?;
        set.files
            .iter()
            .any(|f| Path::new(f.name) == below)
            .then_some(set)
    })?;
    Some(format!(
        "`cargo xtask fetch-data {0}` (or `msd fetch-data {0}`)",
        set.name
    ))
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
        let folder = target.parent().unwrap_or(into);
        std::fs::create_dir_all(folder).map_err(|e| {
            ExperimentError::data(folder, format!("cannot create the data folder: {e}"))
        })?;
        let base = target
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or("file");
        let partial = folder.join(format!(".{base}.partial-{}", std::process::id()));
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
