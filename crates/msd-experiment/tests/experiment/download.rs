//! Downloading a data set's archive, against a server on 127.0.0.1 run by each test with
//! canned answers, and a zip made by the test: a good archive puts the files in place,
//! byte for byte; a wrong checksum, a truncated body, an HTTP error, a refused or stalled
//! connection and a damaged archive leave nothing behind and say what happened.

use crate::fetch::SET;
use msd_experiment::ExperimentError;
use msd_experiment::fetch::{DownloadOptions, download};
use std::io::{Cursor, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::Path;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// `printf 'TWO\n' | sha256sum`.
const SHA256_OF_TWO_UPPER: &str =
    "465a43c7b7b79945ec5bc4dd80b20230ea1a992bd6401fe2ed5f736d67799e0c";

/// Short waits: every test here ends well within a second.
fn options() -> DownloadOptions {
    DownloadOptions {
        connect_timeout: Duration::from_secs(2),
        read_timeout: Duration::from_millis(300),
        max_bytes: 1 << 20,
    }
}

/// A zip holding `members` (path, content), deflated unless `stored`.
fn zip_of(members: &[(&str, &[u8])], stored: bool) -> Vec<u8> {
    let method = if stored {
        zip::CompressionMethod::Stored
    } else {
        zip::CompressionMethod::Deflated
    };
    let options = zip::write::SimpleFileOptions::default().compression_method(method);
    let mut writer = zip::ZipWriter::new(Cursor::new(Vec::new()));
    for (path, content) in members {
        writer.start_file(*path, options).unwrap();
        writer.write_all(content).unwrap();
    }
    writer.finish().unwrap().into_inner()
}

/// The test set's archive, with `b` as the content of `tiny/b.csv`.
fn archive_with_b(b: &[u8]) -> Vec<u8> {
    zip_of(
        &[
            ("tiny/a.csv", b"one\n"),
            ("tiny/b.csv", b),
            ("tiny/README.txt", b"hi"),
        ],
        false,
    )
}

/// An HTTP/1.1 response with `status`, `extra` header lines, and `body`, whose
/// Content-Length is `length` (the body's own unless given).
fn response(status: &str, extra: &str, body: &[u8], length: Option<usize>) -> Vec<u8> {
    let length = length.unwrap_or(body.len());
    let head = format!(
        "HTTP/1.1 {status}\r\nContent-Length: {length}\r\n{extra}Connection: close\r\n\r\n"
    );
    [head.as_bytes(), body].concat()
}

/// What the test server does with one connection.
enum Answer {
    /// Reads the request and sends these bytes, then closes.
    Send(Vec<u8>),
    /// Reads the request and answers nothing until the client hangs up (at most 2 s).
    Stall,
}

/// A server on 127.0.0.1 that takes one connection per answer, in order, and stops by
/// itself (after the last answer, or when no client came within 5 s). Joining it gives
/// the request lines it received.
struct Server {
    url: String,
    thread: JoinHandle<Vec<String>>,
}

impl Server {
    fn start(answers: Vec<Answer>) -> Self {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let url = format!("http://{}", listener.local_addr().unwrap());
        listener.set_nonblocking(true).unwrap();
        let thread = std::thread::spawn(move || {
            let deadline = Instant::now() + Duration::from_secs(5);
            let mut requests = Vec::new();
            for answer in answers {
                let Some(mut stream) = accept_before(&listener, deadline) else {
                    break;
                };
                requests.push(read_request_line(&mut stream));
                match answer {
                    Answer::Send(bytes) => {
                        let _ = stream.write_all(&bytes);
                    }
                    Answer::Stall => {
                        let _ = stream.read(&mut [0; 64]);
                    }
                }
            }
            requests
        });
        Self { url, thread }
    }

    fn requests(self) -> Vec<String> {
        self.thread.join().unwrap()
    }
}

fn accept_before(listener: &TcpListener, deadline: Instant) -> Option<TcpStream> {
    loop {
        match listener.accept() {
            Ok((stream, _)) => {
                stream.set_nonblocking(false).ok()?;
                stream.set_read_timeout(Some(Duration::from_secs(2))).ok()?;
                return Some(stream);
            }
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock && Instant::now() < deadline => {
                std::thread::sleep(Duration::from_millis(2));
            }
            Err(_) => return None,
        }
    }
}

/// Reads a request's head (up to the blank line) and gives its first line.
fn read_request_line(stream: &mut TcpStream) -> String {
    let mut head = Vec::new();
    let mut byte = [0u8; 1];
    while !head.ends_with(b"\r\n\r\n") && head.len() < 8192 {
        match stream.read(&mut byte) {
            Ok(1) => head.push(byte[0]),
            _ => break,
        }
    }
    let head = String::from_utf8_lossy(&head);
    head.lines().next().unwrap_or_default().to_string()
}

/// A fresh folder and the set's target inside it (not created).
fn target() -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("tiny");
    (dir, target)
}

/// `err` is a download error naming `url`, exit status 2, and `into` was not created.
fn assert_refused(err: &ExperimentError, url: &str, into: &Path) {
    assert!(
        matches!(err, ExperimentError::Download { url: u, .. } if u == url),
        "{err:?}"
    );
    assert_eq!(err.exit_code(), 2, "{err}");
    assert!(err.to_string().starts_with(&format!("{url}: ")), "{err}");
    assert!(!err.to_string().contains('\n'), "{err}");
    assert!(!into.exists(), "left behind in {}", into.display());
}

#[test]
fn a_good_archive_puts_the_files_in_place_byte_for_byte() {
    let server = Server::start(vec![Answer::Send(response(
        "200 OK",
        "Content-Type: application/zip\r\n",
        &archive_with_b(b"two\n"),
        None,
    ))]);
    let (_dir, into) = target();
    let url = format!("{}/tiny.zip", server.url);
    let placed = download(&SET, &url, &into, &options()).expect("a good archive");
    assert_eq!(placed, [into.join("a.csv"), into.join("b.csv")]);
    assert_eq!(std::fs::read(into.join("a.csv")).unwrap(), b"one\n");
    assert_eq!(std::fs::read(into.join("b.csv")).unwrap(), b"two\n");
    let mut listing: Vec<String> = std::fs::read_dir(&into)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    listing.sort();
    assert_eq!(
        listing,
        ["a.csv", "b.csv"],
        "only the set's files, no temporary ones"
    );
    assert_eq!(server.requests(), ["GET /tiny.zip HTTP/1.1"]);
    // The files are in place: fetching again asks no server (this URL refuses).
    download(&SET, &refused_url(), &into, &options()).expect("already in place");
}

#[test]
fn a_redirect_is_followed() {
    let server = Server::start(vec![
        Answer::Send(response(
            "302 Found",
            "Location: /moved/tiny.zip\r\n",
            b"",
            None,
        )),
        Answer::Send(response("200 OK", "", &archive_with_b(b"two\n"), None)),
    ]);
    let (_dir, into) = target();
    download(&SET, &format!("{}/tiny.zip", server.url), &into, &options()).expect("redirected");
    assert_eq!(std::fs::read(into.join("b.csv")).unwrap(), b"two\n");
    assert_eq!(
        server.requests(),
        ["GET /tiny.zip HTTP/1.1", "GET /moved/tiny.zip HTTP/1.1"]
    );
}

#[test]
fn a_wrong_checksum_leaves_nothing_and_names_the_file_and_both_checksums() {
    let server = Server::start(vec![Answer::Send(response(
        "200 OK",
        "",
        &archive_with_b(b"TWO\n"),
        None,
    ))]);
    let (_dir, into) = target();
    let url = format!("{}/tiny.zip", server.url);
    let err = download(&SET, &url, &into, &options()).expect_err("a wrong checksum");
    assert_refused(&err, &url, &into);
    assert_eq!(
        err.to_string(),
        format!(
            "{url}: member tiny/b.csv: SHA-256 {SHA256_OF_TWO_UPPER}: expected {} for b.csv (a damaged or different file)",
            SET.files[1].sha256
        )
    );
    server.requests();
}

#[test]
fn a_truncated_body_leaves_nothing_and_says_how_many_bytes_arrived() {
    let archive = archive_with_b(b"two\n");
    let half = archive.len() / 2;
    let server = Server::start(vec![Answer::Send(response(
        "200 OK",
        "",
        &archive[..half],
        Some(archive.len()),
    ))]);
    let (_dir, into) = target();
    let url = format!("{}/tiny.zip", server.url);
    let err = download(&SET, &url, &into, &options()).expect_err("a truncated body");
    assert_refused(&err, &url, &into);
    let message = err.to_string();
    assert!(
        message.contains(&format!(
            "the download broke off: received {half} bytes, expected {} (Content-Length): ",
            archive.len()
        )),
        "{message}"
    );
    assert!(
        std::error::Error::source(&err).is_some(),
        "the cause is kept"
    );
    server.requests();
}

#[test]
fn an_http_error_leaves_nothing_and_names_the_status_and_the_url() {
    let server = Server::start(vec![Answer::Send(response(
        "404 Not Found",
        "Content-Type: text/plain\r\n",
        b"no such file",
        None,
    ))]);
    let (_dir, into) = target();
    let url = format!("{}/missing.zip", server.url);
    let err = download(&SET, &url, &into, &options()).expect_err("a 404");
    assert_refused(&err, &url, &into);
    assert_eq!(
        err.to_string(),
        format!("{url}: HTTP 404 Not Found: expected 200 OK and the archive")
    );
    server.requests();
}

/// A URL on 127.0.0.1 where nothing listens (the port of a listener just closed).
fn refused_url() -> String {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = listener.local_addr().unwrap();
    drop(listener);
    format!("http://{address}/tiny.zip")
}

#[test]
fn a_refused_connection_leaves_nothing_and_keeps_the_cause() {
    let (_dir, into) = target();
    let url = refused_url();
    let err = download(&SET, &url, &into, &options()).expect_err("refused");
    assert_refused(&err, &url, &into);
    let message = err.to_string();
    assert!(
        message.starts_with(&format!("{url}: cannot download the archive: ")),
        "{message}"
    );
    assert!(message.to_lowercase().contains("refused"), "{message}");
    let source = std::error::Error::source(&err).expect("the cause is kept");
    assert!(source.downcast_ref::<ureq::Error>().is_some(), "{source:?}");
}

#[test]
fn a_stalled_server_times_out_and_leaves_nothing() {
    let server = Server::start(vec![Answer::Stall]);
    let (_dir, into) = target();
    let url = format!("{}/tiny.zip", server.url);
    let started = Instant::now();
    let err = download(&SET, &url, &into, &options()).expect_err("a stall");
    assert!(
        started.elapsed() < Duration::from_secs(2),
        "{:?}",
        started.elapsed()
    );
    assert_refused(&err, &url, &into);
    assert!(
        err.to_string().contains(
            "cannot download the archive: no answer in time (2s to connect, 300ms for each read): "
        ),
        "{err}"
    );
    server.requests();
}

#[test]
fn an_archive_larger_than_allowed_is_refused_before_it_is_read() {
    let server = Server::start(vec![Answer::Send(response(
        "200 OK",
        "",
        b"",
        Some(2 << 20),
    ))]);
    let (_dir, into) = target();
    let url = format!("{}/huge.zip", server.url);
    let err = download(&SET, &url, &into, &options()).expect_err("too large");
    assert_refused(&err, &url, &into);
    assert!(
        err.to_string().ends_with(
            "the archive has 2097152 bytes (Content-Length): more than the 1048576 bytes taken"
        ),
        "{err}"
    );
    server.requests();
}

#[test]
fn a_web_page_instead_of_the_archive_is_refused() {
    let page = b"<!DOCTYPE html><html><body>Sign in</body></html>";
    let server = Server::start(vec![Answer::Send(response(
        "200 OK",
        "Content-Type: text/html\r\n",
        page,
        None,
    ))]);
    let (_dir, into) = target();
    let url = format!("{}/tiny.zip", server.url);
    let err = download(&SET, &url, &into, &options()).expect_err("a page");
    assert_refused(&err, &url, &into);
    assert!(
        err.to_string().contains(&format!(
            "not a zip archive ({} bytes, a web page): ",
            page.len()
        )),
        "{err}"
    );
    server.requests();
}

/// Local archives (a path, a `file://` URL) take the same checks; the servers are
/// not needed to damage one.
fn local_zip(dir: &Path, bytes: &[u8]) -> String {
    let path = dir.join("tiny.zip");
    std::fs::write(&path, bytes).unwrap();
    path.display().to_string()
}

#[test]
fn a_local_archive_is_taken_by_path_or_file_url() {
    let dir = tempfile::tempdir().unwrap();
    let path = local_zip(dir.path(), &archive_with_b(b"two\n"));
    for (i, url) in [path.clone(), format!("file://{path}")].iter().enumerate() {
        let into = dir.path().join(format!("into-{i}"));
        download(&SET, url, &into, &options()).expect("a local archive");
        assert_eq!(std::fs::read(into.join("a.csv")).unwrap(), b"one\n");
        assert_eq!(std::fs::read(into.join("b.csv")).unwrap(), b"two\n");
    }
}

#[test]
fn a_damaged_archive_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let good = zip_of(&[("tiny/a.csv", b"one\n"), ("tiny/b.csv", b"two\n")], true);
    // A stored member with one byte changed: its CRC-32 no longer matches.
    let at = good.windows(4).position(|w| w == b"one\n").unwrap();
    let mut flipped = good.clone();
    flipped[at] = b'O';
    let cases: [(&[u8], &str); 3] = [
        (&flipped, "cannot unpack member tiny/a.csv: "),
        (&good[..good.len() / 2], "not a zip archive ("),
        (
            &zip_of(&[("other/a.csv", b"one\n"), ("other/c.csv", b"3\n")], false),
            "no member tiny/b.csv in the archive (2 members: other/a.csv, other/c.csv)",
        ),
    ];
    for (bytes, fragment) in cases {
        let url = local_zip(dir.path(), bytes);
        let into = dir.path().join("tiny");
        let err = download(&SET, &url, &into, &options()).expect_err("a damaged archive");
        assert_refused(&err, &url, &into);
        assert!(err.to_string().contains(fragment), "{err}");
    }
}

#[test]
fn a_member_elsewhere_in_the_archive_is_found_by_its_name() {
    let dir = tempfile::tempdir().unwrap();
    let url = local_zip(
        dir.path(),
        &zip_of(&[("a.csv", b"one\n"), ("x/y/b.csv", b"two\n")], false),
    );
    let into = dir.path().join("tiny");
    download(&SET, &url, &into, &options()).expect("found by name");
    assert_eq!(std::fs::read(into.join("b.csv")).unwrap(), b"two\n");
}

#[test]
fn fetch_data_with_url_downloads_and_checks_against_the_published_checksums() {
    // The command's --url takes a lab's own mirror; this one serves the tiny archive,
    // which is not the Silverbox record: refused, nothing written, exit status 2.
    let server = Server::start(vec![Answer::Send(response(
        "200 OK",
        "",
        &zip_of(&[("SilverboxFiles/SNLS80mV.csv", b"one\n")], false),
        None,
    ))]);
    let dir = tempfile::tempdir().unwrap();
    let url = format!("{}/SilverboxFiles.zip", server.url);
    let args = msd_experiment::cli::FetchArgs {
        set: "silverbox".into(),
        from: None,
        url: Some(url.clone()),
        into: None,
    };
    let err = msd_experiment::cli::fetch_data(&args, dir.path(), dir.path())
        .expect_err("not the Silverbox record");
    assert_refused(&err, &url, &dir.path().join("silverbox"));
    assert!(
        err.to_string()
            .contains("member SilverboxFiles/SNLS80mV.csv: size 4 bytes: expected 2649634 bytes"),
        "{err}"
    );
    server.requests();
}
