//! The files this crate writes, committed under `fixtures/ours/` with their values as JSON
//! (pyuff read them: `python3 fixtures/make_fixtures.py check`). The test fails if the
//! writer's output changes; `MSD_UFF_BLESS=1 cargo test -p msd-uff` rewrites them.

use msd_uff::{AsciiNumbers, ByteOrder, Encoding, UffFile, WriteOptions};
use serde::Serialize;

use crate::data_at_nodes::sample_modal_file;
use crate::{fixture, sample_file};

#[derive(Serialize)]
struct Golden<'a> {
    options: &'a WriteOptions,
    file: &'a UffFile,
}

fn check(name: &str, encoding: Encoding, ascii: AsciiNumbers) {
    check_file(name, &sample_file(encoding), ascii);
}

fn check_file(name: &str, file: &UffFile, ascii: AsciiNumbers) {
    let options = WriteOptions { ascii };
    let bytes = msd_uff::to_bytes(file, &options).expect("write");
    let json = serde_json::to_string_pretty(&Golden {
        options: &options,
        file,
    })
    .expect("JSON")
        + "\n";
    let (uff_path, json_path) = (
        fixture(&format!("ours/{name}.uff")),
        fixture(&format!("ours/{name}.json")),
    );
    if std::env::var_os("MSD_UFF_BLESS").is_some() {
        std::fs::write(&uff_path, &bytes).expect("bless .uff");
        std::fs::write(&json_path, &json).expect("bless .json");
    }
    let committed = std::fs::read(&uff_path).expect("committed .uff");
    assert!(
        committed == bytes,
        "{name}.uff is not what msd-uff writes today (MSD_UFF_BLESS=1 to rewrite)"
    );
    assert_eq!(
        std::fs::read_to_string(&json_path).expect("committed .json"),
        json,
        "{name}.json"
    );
    assert!(committed.len() < 100_000);
    let back = msd_uff::parse(&committed).expect("read back");
    let exact_text = file.functions.iter().all(|f| f.encoding == Encoding::Ascii);
    if ascii == AsciiNumbers::Exact && exact_text {
        assert_eq!(&back, file);
    }
}

#[test]
fn the_committed_files_are_what_the_writer_writes() {
    check("ascii_fixed", Encoding::Ascii, AsciiNumbers::Fixed);
    check("ascii_exact", Encoding::Ascii, AsciiNumbers::Exact);
    check(
        "binary",
        Encoding::Binary(ByteOrder::Little),
        AsciiNumbers::Fixed,
    );
    // Nodes (15 and 2411) and data at nodes (55), in the columns pyuff reads.
    check_file("data_at_nodes", &sample_modal_file(), AsciiNumbers::Fixed);
}
