//! The one error type of msd-experiment, split by who has to act: the user (a bad config, bad
//! data or data that could not be downloaded, exit status 2) or the toolkit (a failure during
//! the run, exit status 1).

use std::path::Path;

/// Everything that can stop an experiment run (`msd run`, `cargo xtask experiment`).
///
/// Each message is one line that names the file (and line, column or field), the value
/// found and what was expected.
///
/// ```
/// use msd_experiment::ExperimentError;
/// let e = ExperimentError::config("configs/x.toml", "plant.mass = -2.5: expected a finite number > 0");
/// assert_eq!(e.exit_code(), 2);
/// assert_eq!(e.to_string(), "configs/x.toml: plant.mass = -2.5: expected a finite number > 0");
/// ```
#[derive(Debug, thiserror::Error)]
pub enum ExperimentError {
    /// The config file cannot be read, parsed or has a value out of range.
    #[error("{file}: {message}")]
    Config {
        /// The config file (as given).
        file: String,
        /// What is wrong, naming line/column or field, the value and what was expected.
        message: String,
    },
    /// A measured data file cannot be read or holds bad values.
    #[error("{file}: {message}")]
    Data {
        /// The data file (as given in the config, resolved).
        file: String,
        /// What is wrong, naming line and column, the value and what was expected.
        message: String,
    },
    /// A data set's archive could not be downloaded or read, or what arrived is not the
    /// published data (`fetch-data`).
    #[error("{url}: {message}")]
    Download {
        /// Where the archive was taken from: the URL, or the local path of a zip.
        url: String,
        /// What happened: the HTTP status, the bytes expected and received, or the member
        /// and both checksums; it ends with the cause's own text when there is one.
        message: String,
        /// The cause, when there is one: the HTTP client's error (`ureq::Error`), an I/O
        /// error, or the zip reader's (`zip::result::ZipError`).
        #[source]
        source: Option<Box<dyn std::error::Error + Send + Sync>>,
    },
    /// A stage failed while running (estimation, simulation, plotting, writing).
    #[error("{stage} failed: {source}")]
    Run {
        /// The stage that failed.
        stage: &'static str,
        /// Why: the library's own error where there is one (downcast it, e.g. to
        /// `msd_ident::IdentError`), else a message.
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// A failure after which the run kept something to look at in a folder of its own
    /// beside the results (the stabilization diagram of a failed mode selection); any
    /// previous result stays untouched.
    #[error("{error}; kept for inspection: {}", kept.display())]
    Kept {
        /// The failure itself.
        #[source]
        error: Box<ExperimentError>,
        /// The folder written, with a `failure.md` saying what it holds.
        kept: std::path::PathBuf,
    },
}

impl ExperimentError {
    /// A config error for `file`.
    pub fn config(file: impl AsRef<Path>, message: impl Into<String>) -> Self {
        Self::Config {
            file: file.as_ref().display().to_string(),
            message: message.into(),
        }
    }

    /// A data error for `file`.
    pub fn data(file: impl AsRef<Path>, message: impl Into<String>) -> Self {
        Self::Data {
            file: file.as_ref().display().to_string(),
            message: message.into(),
        }
    }

    /// A download error for the archive at `url`: `message` says what happened.
    ///
    /// ```
    /// use msd_experiment::ExperimentError;
    /// let e = ExperimentError::download("http://127.0.0.1:9/x.zip", "HTTP 404 Not Found");
    /// assert_eq!(e.exit_code(), 2);
    /// assert_eq!(e.to_string(), "http://127.0.0.1:9/x.zip: HTTP 404 Not Found");
    /// ```
    pub fn download(url: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Download {
            url: url.into(),
            message: message.into(),
            source: None,
        }
    }

    /// A download error for the archive at `url` with its cause, whose text ends the
    /// message (`"{message}: {cause}"`) and which stays the error's source.
    ///
    /// ```
    /// use msd_experiment::ExperimentError;
    /// use std::error::Error as _;
    /// let cause = std::io::Error::from(std::io::ErrorKind::ConnectionRefused);
    /// let e = ExperimentError::download_failed("http://127.0.0.1:9/x.zip", "cannot download", cause);
    /// assert_eq!(e.to_string(), "http://127.0.0.1:9/x.zip: cannot download: connection refused");
    /// assert!(e.source().unwrap().downcast_ref::<std::io::Error>().is_some());
    /// ```
    pub fn download_failed(
        url: impl Into<String>,
        message: impl std::fmt::Display,
        source: impl Into<Box<dyn std::error::Error + Send + Sync>>,
    ) -> Self {
        let source = source.into();
        Self::Download {
            url: url.into(),
            message: format!("{message}: {source}"),
            source: Some(source),
        }
    }

    /// A failure of `stage`, keeping its cause: a library error (kept as the source) or a
    /// message.
    ///
    /// ```
    /// use msd_experiment::ExperimentError;
    /// use std::error::Error as _;
    /// let cause = msd_ident::IdentError::EstimationFailed { reason: "no finite cost".into() };
    /// let e = ExperimentError::run("estimation", cause);
    /// assert_eq!(e.exit_code(), 1);
    /// assert!(e.to_string().starts_with("estimation failed: "));
    /// assert!(e.source().unwrap().downcast_ref::<msd_ident::IdentError>().is_some());
    /// ```
    pub fn run(
        stage: &'static str,
        source: impl Into<Box<dyn std::error::Error + Send + Sync>>,
    ) -> Self {
        Self::Run {
            stage,
            source: source.into(),
        }
    }

    /// The process exit status: 2 for a bad config, bad data or a failed download (the
    /// user has to act: fix the URL or the network, or give a local copy), 1 for a failure
    /// during the run.
    pub fn exit_code(&self) -> u8 {
        match self {
            Self::Config { .. } | Self::Data { .. } | Self::Download { .. } => 2,
            Self::Run { .. } => 1,
            Self::Kept { error, .. } => error.exit_code(),
        }
    }

    /// Whether the user has to fix their input (config or data, or fetch the data).
    pub fn is_input_error(&self) -> bool {
        self.exit_code() == 2
    }
}

/// Shorthand for results of msd-experiment.
pub type Result<T, E = ExperimentError> = std::result::Result<T, E>;
