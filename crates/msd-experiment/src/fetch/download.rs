//! A data set from its archive: the zip is read whole into memory (over HTTP or HTTPS, or
//! from a local file), its members are found, read and checked, and only then written.

use super::{DataFile, DataSetFiles, check, missing, place};
use crate::error::{ExperimentError, Result};
use std::borrow::Cow;
use std::io::{Cursor, Read};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// How [`download`] waits and how much it takes.
///
/// ```
/// use msd_experiment::fetch::DownloadOptions;
/// use std::time::Duration;
/// let options = DownloadOptions::default();
/// assert_eq!(options.connect_timeout, Duration::from_secs(30));
/// assert_eq!(options.read_timeout, Duration::from_secs(60));
/// assert_eq!(options.max_bytes, 64 << 20);
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DownloadOptions {
    /// The longest wait for the server to accept the connection. By default, 30 s.
    pub connect_timeout: Duration,
    /// The longest wait for any one read (the response's head, or the next bytes of the
    /// body) before giving up on a stalled server. By default, 60 s.
    pub read_timeout: Duration,
    /// The largest archive taken, in bytes: a larger one is refused before it fills the
    /// memory. By default, 64 MiB (the Silverbox archive has 5,793,999 bytes).
    pub max_bytes: u64,
}

impl Default for DownloadOptions {
    fn default() -> Self {
        Self {
            connect_timeout: Duration::from_secs(30),
            read_timeout: Duration::from_secs(60),
            max_bytes: 64 << 20,
        }
    }
}

/// Takes every file of `set` from its archive at `url` into `into` (created if needed);
/// returns the set's files in `into`.
///
/// `url` is an `http://` or `https://` URL (a Google Drive link is turned into a direct
/// download by [`direct_url`]; redirects are followed; only with the `download` feature,
/// see [`HTTP_SUPPORT`](super::HTTP_SUPPORT)), a `file://` URL or the path of a zip
/// already downloaded; pass `set.archive.url` for the official archive. Each file is
/// the member [`Archive::member_path`](super::Archive::member_path) of the zip (or, when
/// that path is absent, the one member of the same file name). Files already in `into`
/// that pass their check are left as they are, and when all do nothing is downloaded.
///
/// Every member is checked against its size and SHA-256 before any file is written. A
/// failed connection, an HTTP status other than success, a body shorter than its
/// `Content-Length`, a stalled server ([`DownloadOptions`]), an archive that is not a zip
/// or a damaged or wrong member is an [`ExperimentError::Download`] naming the URL and
/// what happened, and leaves `into` as it was.
///
/// ```
/// use msd_experiment::fetch::{DownloadOptions, SILVERBOX, download};
/// let into = tempfile::tempdir().unwrap();
/// let target = into.path().join("silverbox");
/// let err = download(&SILVERBOX, "no/such/archive.zip", &target, &DownloadOptions::default())
///     .unwrap_err();
/// assert!(err.to_string().starts_with("no/such/archive.zip: cannot read the archive: "), "{err}");
/// assert!(!target.exists());
/// ```
pub fn download(
    set: &DataSetFiles,
    url: &str,
    into: &Path,
    options: &DownloadOptions,
) -> Result<Vec<PathBuf>> {
    let wanted = missing(set, into);
    if wanted.is_empty() {
        return place(set, into, &[]);
    }
    if !set.archive.zipped {
        return download_files(set, url, &wanted, into, options);
    }
    let archive = if is_http(url) {
        http_get(&direct_url(url), options)?
    } else {
        read_local(url, options)?
    };
    let mut zip = zip::ZipArchive::new(Cursor::new(archive.as_slice()))
        .map_err(|e| ExperimentError::download_failed(url, not_a_zip(&archive), e))?;
    let mut checked = Vec::new();
    for file in wanted {
        let member =
            member_name(&zip, set, file).map_err(|why| ExperimentError::download(url, why))?;
        let bytes = read_member(&mut zip, &member, file).map_err(|e| {
            ExperimentError::download_failed(url, format!("cannot unpack member {member}"), e)
        })?;
        check(&bytes, file)
            .map_err(|why| ExperimentError::download(url, format!("member {member}: {why}")))?;
        checked.push((file, bytes));
    }
    place(set, into, &checked)
}

/// The plain files `wanted` of `set`, each from `base` + its path (see
/// [`Archive::file_url`](super::Archive::file_url)), all checked before any is written.
fn download_files(
    set: &DataSetFiles,
    base: &str,
    wanted: &[&DataFile],
    into: &Path,
    options: &DownloadOptions,
) -> Result<Vec<PathBuf>> {
    let mut checked = Vec::new();
    for &file in wanted {
        let url = set.archive.file_url_under(base, file.name);
        let bytes = if is_http(&url) {
            http_get(&url, options)?
        } else {
            read_local(&url, options)?
        };
        check(&bytes, file).map_err(|why| ExperimentError::download(&url, why))?;
        checked.push((file, bytes));
    }
    place(set, into, &checked)
}

/// Whether `url` is taken over the network (`http://` or `https://`), which needs the
/// `download` feature, rather than from a file.
///
/// ```
/// use msd_experiment::fetch::is_http;
/// assert!(is_http("https://drive.google.com/file/d/ID/view"));
/// assert!(!is_http("file:///tmp/SilverboxFiles.zip"));
/// assert!(!is_http("SilverboxFiles.zip"));
/// ```
pub fn is_http(url: &str) -> bool {
    url.starts_with("http://") || url.starts_with("https://")
}

/// The direct download of a Google Drive link
/// (`https://drive.google.com/file/d/ID/view` → `https://docs.google.com/uc?export=download&id=ID`),
/// as `nonlinear-benchmarks`' `download_file_from_google_drive` does (it takes the path
/// segment before the last as the file's ID); any other URL as it is.
///
/// ```
/// use msd_experiment::fetch::direct_url;
/// assert_eq!(
///     direct_url("https://drive.google.com/file/d/ABC_12-x/view?usp=sharing"),
///     "https://docs.google.com/uc?export=download&id=ABC_12-x"
/// );
/// assert_eq!(direct_url("http://lab.example/silverbox.zip"), "http://lab.example/silverbox.zip");
/// ```
pub fn direct_url(url: &str) -> Cow<'_, str> {
    let id = url
        .split_once("://drive.google.com/file/d/")
        .and_then(|(_, rest)| rest.split(['/', '?', '#']).next())
        .filter(|id| !id.is_empty());
    match id {
        Some(id) => format!("https://docs.google.com/uc?export=download&id={id}").into(),
        None => url.into(),
    }
}

/// The body of a GET of `url`: the whole of it, or an error saying what went wrong.
#[cfg(feature = "download")]
fn http_get(url: &str, options: &DownloadOptions) -> Result<Vec<u8>> {
    let agent: ureq::Agent = ureq::Agent::config_builder()
        .http_status_as_error(false)
        .timeout_connect(Some(options.connect_timeout))
        .timeout_per_read(Some(options.read_timeout))
        .build()
        .into();
    let mut response = agent
        .get(url)
        .call()
        .map_err(|e| {
            let why = match e {
                ureq::Error::Timeout(_) => format!(
                    "cannot download the archive: no answer in time ({:?} to connect, {:?} for each read)",
                    options.connect_timeout, options.read_timeout
                ),
                _ => "cannot download the archive".to_string(),
            };
            ExperimentError::download_failed(url, why, e)
        })?;
    let status = response.status();
    if !status.is_success() {
        let reached = ureq::ResponseExt::get_uri(&response).to_string();
        let via = if reached == url {
            String::new()
        } else {
            format!(" (from {reached})")
        };
        return Err(ExperimentError::download(
            url,
            format!(
                "HTTP {} {}{via}: expected 200 OK and the archive",
                status.as_u16(),
                status.canonical_reason().unwrap_or("")
            ),
        ));
    }
    let announced = response
        .headers()
        .get("content-length")
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.trim().parse::<u64>().ok());
    if let Some(n) = announced.filter(|&n| n > options.max_bytes) {
        return Err(ExperimentError::download(
            url,
            format!(
                "the archive has {n} bytes (Content-Length): more than the {} bytes taken",
                options.max_bytes
            ),
        ));
    }
    let mut body = Vec::with_capacity(announced.unwrap_or(0) as usize);
    let read = response
        .body_mut()
        .with_config()
        .limit(options.max_bytes)
        .reader()
        .read_to_end(&mut body);
    let expected =
        announced.map_or_else(String::new, |n| format!(", expected {n} (Content-Length)"));
    if let Err(e) = read {
        let why = format!(
            "the download broke off: received {} bytes{expected}",
            body.len()
        );
        return Err(ExperimentError::download_failed(url, why, e));
    }
    if let Some(n) = announced.filter(|&n| n != body.len() as u64) {
        return Err(ExperimentError::download(
            url,
            format!(
                "received {} bytes, expected {n} (Content-Length)",
                body.len()
            ),
        ));
    }
    Ok(body)
}

/// Without the `download` feature: an error saying so, and what to do instead.
#[cfg(not(feature = "download"))]
fn http_get(url: &str, _: &DownloadOptions) -> Result<Vec<u8>> {
    Err(ExperimentError::download(
        url,
        "this build cannot download (msd-experiment without its `download` feature): \
         use the `msd` command, or download the archive yourself and give its path",
    ))
}

/// The bytes of the zip at the local path or `file://` URL `url`.
fn read_local(url: &str, options: &DownloadOptions) -> Result<Vec<u8>> {
    let path = Path::new(url.strip_prefix("file://").unwrap_or(url));
    let fail =
        |e: std::io::Error| ExperimentError::download_failed(url, "cannot read the archive", e);
    let size = std::fs::metadata(path).map_err(fail)?.len();
    if size > options.max_bytes {
        return Err(ExperimentError::download(
            url,
            format!(
                "the archive has {size} bytes: more than the {} bytes taken",
                options.max_bytes
            ),
        ));
    }
    std::fs::read(path).map_err(fail)
}

/// Why `bytes` did not open as a zip, saying when it is a web page (a server's error or
/// sign-in page sent with status 200).
fn not_a_zip(bytes: &[u8]) -> String {
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(256)]).to_lowercase();
    let page = if head.contains("<html") || head.contains("<!doctype") {
        ", a web page"
    } else {
        ""
    };
    format!("not a zip archive ({} bytes{page})", bytes.len())
}

/// The member of `zip` that holds `file`: at the set's member path, or else the only
/// member of that file name.
fn member_name(
    zip: &zip::ZipArchive<Cursor<&[u8]>>,
    set: &DataSetFiles,
    file: &DataFile,
) -> std::result::Result<String, String> {
    let path = set.archive.member_path(file.name);
    if zip.index_for_name(&path).is_some() {
        return Ok(path);
    }
    let mut members: Vec<&str> = zip.file_names().collect();
    members.sort_unstable();
    let same_name: Vec<&str> = members
        .iter()
        .copied()
        .filter(|n| n.rsplit('/').next() == Some(file.name))
        .collect();
    if let [only] = same_name.as_slice() {
        return Ok((*only).to_string());
    }
    let count = members.len();
    let more = if count > 12 { ", …" } else { "" };
    members.truncate(12);
    Err(format!(
        "no member {path} in the archive ({count} members: {}{more})",
        members.join(", ")
    ))
}

/// The bytes of `member`, at most one more than `file`'s size (so a larger member is
/// refused by its size without being read whole).
fn read_member(
    zip: &mut zip::ZipArchive<Cursor<&[u8]>>,
    member: &str,
    file: &DataFile,
) -> std::result::Result<Vec<u8>, Box<dyn std::error::Error + Send + Sync>> {
    let entry = zip.by_name(member)?;
    let mut bytes = Vec::with_capacity(file.bytes as usize);
    entry
        .take(file.bytes.saturating_add(1))
        .read_to_end(&mut bytes)?;
    Ok(bytes)
}
