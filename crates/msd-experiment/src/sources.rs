//! Where a run's data files come from: the disk, relative to the config's folder, unless
//! the program running the experiment gave a file in memory — its bytes (a CSV or UFF
//! file as it would be on disk) or its columns as numbers (a table of named columns, as
//! a notebook holds them). Every reader asks [`Sources`] for its file, so that every
//! experiment kind runs on data held in memory with the same checks and messages.

use crate::error::{ExperimentError, Result};
use std::borrow::Cow;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A column of numbers and its name, as a table given in memory holds it.
pub type NamedColumn = (String, Vec<f64>);

/// Whether `path` names a Universal File Format file (`.uff`, `.unv`).
pub(crate) fn is_universal(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("uff") || e.eq_ignore_ascii_case("unv"))
}

/// A data file given in memory.
#[derive(Debug, Clone, PartialEq)]
pub enum InMemory {
    /// The file's bytes, read as the file would be (its format from the config).
    Bytes(Vec<u8>),
    /// Named columns of numbers, each as long as the others: the config's columns are
    /// found by name (or 0-based position); the format keys (delimiter, header, lines
    /// to skip) do not apply.
    Columns(Vec<(String, Vec<f64>)>),
}

/// The config file a run was read from (its folder resolves relative paths) and the
/// files given in memory, by the path the config writes.
///
/// ```
/// use msd_experiment::sources::Sources;
/// use std::path::Path;
/// let sources = Sources::new("configs/lab.toml")
///     .with_columns("data/run1.csv", vec![("t".into(), vec![0.0, 0.01]), ("F".into(), vec![1.0, 2.0])]);
/// assert_eq!(sources.path(Path::new("data/run1.csv")), Path::new("configs/data/run1.csv"));
/// assert!(sources.columns(Path::new("configs/data/run1.csv")).is_some());
/// assert!(sources.columns(Path::new("configs/data/run2.csv")).is_none());
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Sources {
    config_file: PathBuf,
    memory: Arc<BTreeMap<PathBuf, InMemory>>,
}

impl Sources {
    /// Files on disk beside `config_file`, none in memory.
    pub fn new(config_file: impl Into<PathBuf>) -> Self {
        Self {
            config_file: config_file.into(),
            memory: Arc::default(),
        }
    }

    /// With the file the config names `path` given as `bytes`.
    pub fn with_bytes(self, path: impl Into<PathBuf>, bytes: Vec<u8>) -> Self {
        self.with(path.into(), InMemory::Bytes(bytes))
    }

    /// With the file the config names `path` given as named `columns`.
    pub fn with_columns(self, path: impl Into<PathBuf>, columns: Vec<(String, Vec<f64>)>) -> Self {
        self.with(path.into(), InMemory::Columns(columns))
    }

    fn with(mut self, path: PathBuf, file: InMemory) -> Self {
        let key = self.path(&path);
        Arc::make_mut(&mut self.memory).insert(key, file);
        self
    }

    /// The config file (`config.toml` in the working folder for a config given in
    /// memory without a name).
    pub fn config_file(&self) -> &Path {
        &self.config_file
    }

    /// The folder relative paths start from: the config file's.
    pub fn dir(&self) -> &Path {
        self.config_file.parent().unwrap_or(Path::new(""))
    }

    /// `relative` (as the config writes it) resolved against the config's folder.
    pub fn path(&self, relative: &Path) -> PathBuf {
        self.dir().join(relative)
    }

    /// How many files are held in memory.
    pub fn in_memory(&self) -> usize {
        self.memory.len()
    }

    /// The columns given in memory for the resolved `path`, if it was given so.
    pub fn columns(&self, path: &Path) -> Option<&[(String, Vec<f64>)]> {
        match self.memory.get(path) {
            Some(InMemory::Columns(c)) => Some(c),
            _ => None,
        }
    }

    /// The named columns of the resolved `path` when it is not a text file: given in
    /// memory as columns, or a MATLAB, NumPy or TDMS file by its extension (read by
    /// msd-files: a vector is a column named as its variable, a matrix's columns are
    /// `name[0]`, `name[1]`, …); `None` for a text table. `key` names the file in messages.
    pub fn table(&self, path: &Path, key: &str) -> Result<Option<Cow<'_, [NamedColumn]>>> {
        if let Some(columns) = self.columns(path) {
            return Ok(Some(Cow::Borrowed(columns)));
        }
        if is_universal(path) {
            let bytes = self.bytes(path, key)?;
            let file = msd_uff::parse(&bytes)
                .map_err(|e| ExperimentError::data(path, format!("{key}: {e}")))?;
            let channels = (crate::data::uff::time_channels(&file))
                .map_err(|e| ExperimentError::data(path, format!("{key}: {e}")))?
                .ok_or_else(|| {
                    ExperimentError::data(
                        path,
                        format!("{key}: a Universal File Format file with no time response (dataset 58 of function type 1) to read as columns; its frequency responses read with [frequency_response.uff]"),
                    )
                })?;
            let columns = channels.into_iter().map(|c| (c.name, c.values)).collect();
            return Ok(Some(Cow::Owned(columns)));
        }
        if msd_files::FileFormat::of(path).is_none() {
            return Ok(None);
        }
        let bytes = self.bytes(path, key)?;
        let contents = msd_files::read_bytes(path, &bytes).map_err(|e| match e {
            msd_files::FilesError::Malformed { format, why, .. } => ExperimentError::data(
                path,
                format!(
                    "{key}: not a {} file that can be read: {why}",
                    format.name()
                ),
            ),
            other => ExperimentError::data(path, format!("{key}: {other}")),
        })?;
        Ok(Some(Cow::Owned(contents.into_columns())))
    }

    /// The bytes of the resolved `path`: from memory, else from the disk (a file given
    /// as columns is an `InvalidInput` error: this reader needs the file itself).
    pub fn read(&self, path: &Path) -> std::io::Result<Vec<u8>> {
        match self.memory.get(path) {
            Some(InMemory::Bytes(b)) => Ok(b.clone()),
            Some(InMemory::Columns(_)) => Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "given in memory as columns of numbers, where this source reads the file itself: give its bytes",
            )),
            None => std::fs::read(path),
        }
    }

    /// [`Sources::read`] with the toolkit's message: `key` names the file
    /// (`data.path`) and a data set that `fetch-data` provides says so.
    pub fn bytes(&self, path: &Path, key: &str) -> Result<Vec<u8>> {
        self.read(path).map_err(|e| {
            let hint = crate::fetch::command_for(path)
                .map(|c| format!("; fetch it with {c}"))
                .unwrap_or_default();
            ExperimentError::data(
                path,
                format!("cannot open the data file ({key}): {e}{hint}"),
            )
        })
    }

    /// The UFF file at the resolved `path`, parsed; errors name the file.
    pub fn uff(&self, path: &Path) -> Result<msd_uff::UffFile> {
        let bytes = self.read(path).map_err(|source| msd_uff::UffError::Io {
            action: "read",
            path: path.into(),
            source,
        });
        bytes
            .and_then(|b| msd_uff::parse(&b))
            .map_err(|e| ExperimentError::data(path, e.to_string()))
    }
}
