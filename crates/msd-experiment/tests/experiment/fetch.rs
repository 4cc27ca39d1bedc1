//! Fetching a data set from a local mirror: good files are put in place, checked; a
//! wrong checksum, a truncated file or a missing one leaves nothing behind (not even the
//! good files: all are checked before any is written) and says what happened.

use msd_experiment::fetch::{Archive, DataFile, DataSetFiles, fetch, verify};
use std::path::Path;

/// A set of two small files made by the test, with their true sizes and SHA-256s
/// (computed independently: `printf 'one\n' | sha256sum`), in the folder `tiny/` of
/// their archive (the download tests serve it; these never read the URL).
pub(crate) const SET: DataSetFiles = DataSetFiles {
    name: "tiny",
    files: &[
        DataFile {
            name: "a.csv",
            bytes: 4,
            sha256: "2c8b08da5ce60398e1f19af0e5dccc744df274b826abe585eaba68c525434806",
        },
        DataFile {
            name: "b.csv",
            bytes: 4,
            sha256: "27dd8ed44a83ff94d557f9fd0412ed5a8cbca69ea04922d88c01184a07300a5a",
        },
    ],
    archive: Archive {
        zipped: true,
        url: "file:///no/such/tiny.zip",
        folder: "tiny",
    },
};

fn mirror(a: &[u8], b: Option<&[u8]>) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("a.csv"), a).unwrap();
    if let Some(b) = b {
        std::fs::write(dir.path().join("b.csv"), b).unwrap();
    }
    dir
}

fn names(dir: &Path) -> Vec<String> {
    let mut n: Vec<String> = std::fs::read_dir(dir)
        .map(|d| {
            d.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    n.sort();
    n
}

#[test]
fn good_files_are_copied_and_checked() {
    let from = mirror(b"one\n", Some(b"two\n"));
    let into = tempfile::tempdir().unwrap();
    let placed = fetch(&SET, from.path(), &into.path().join("tiny")).expect("good files");
    assert_eq!(placed.len(), 2);
    assert_eq!(names(&into.path().join("tiny")), ["a.csv", "b.csv"]);
    verify(&placed[0], &SET.files[0]).expect("still good");
    // Fetching again keeps the good files (nothing to read from the mirror).
    let empty = tempfile::tempdir().unwrap();
    fetch(&SET, empty.path(), &into.path().join("tiny")).expect("already there");
}

#[test]
fn a_wrong_checksum_a_truncated_or_a_missing_file_leaves_nothing() {
    type Case<'a> = (&'a [u8], Option<&'a [u8]>, &'a str);
    let cases: [Case<'_>; 3] = [
        (b"one\n", Some(b"TWO\n"), "SHA-256"),
        (b"on", Some(b"two\n"), "size 2 bytes: expected 4"),
        (b"one\n", None, "cannot read the tiny file"),
    ];
    for (a, b, fragment) in cases {
        let from = mirror(a, b);
        let into = tempfile::tempdir().unwrap();
        let target = into.path().join("tiny");
        let err = fetch(&SET, from.path(), &target).expect_err("a bad mirror");
        assert_eq!(err.exit_code(), 2, "{err}");
        assert!(err.to_string().contains(fragment), "{err}");
        // Every file is checked before any is written: not even the good a.csv is.
        assert!(!target.exists(), "left behind: {:?}", names(&target));
    }
}

#[test]
fn the_published_silverbox_checksums_are_the_shared_copy_s() {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/real/silverbox");
    let Ok(source) = std::fs::read_to_string(shared.join("SOURCE.md")) else {
        assert!(
            std::env::var_os("MSD_REQUIRE_REAL_DATA").is_none(),
            "shared/ is required in CI"
        );
        return;
    };
    for file in msd_experiment::fetch::SILVERBOX.files {
        assert!(
            source.contains(file.sha256),
            "{} not in SOURCE.md",
            file.name
        );
        verify(&shared.join(file.name), file).expect("the shared copy passes");
    }
}

#[test]
fn a_config_whose_real_data_are_missing_says_which_command_fetches_them() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs/silverbox.toml"),
    )
    .unwrap()
    .replace("../data/silverbox/", "data/silverbox/");
    std::fs::write(dir.path().join("silverbox.toml"), text).unwrap();
    let options = msd_experiment::RunOptions {
        out: Some(dir.path().join("out")),
        ..Default::default()
    };
    let err = msd_experiment::run_experiment(&dir.path().join("silverbox.toml"), &options)
        .expect_err("no data");
    assert_eq!(err.exit_code(), 2);
    assert!(
        err.to_string().contains(
            "fetch it with `cargo xtask fetch-data silverbox` (or `msd fetch-data silverbox`)"
        ),
        "{err}"
    );
    assert!(!dir.path().join("out").exists());
}
