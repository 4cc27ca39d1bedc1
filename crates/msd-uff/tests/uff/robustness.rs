//! No input makes the reader panic: every prefix of every fixture, single-byte edits, and
//! arbitrary bytes.

use proptest::prelude::*;

use crate::{PYUFF_FIXTURES, fixture_bytes};

const OURS: [&str; 4] = ["ascii_fixed", "ascii_exact", "binary", "data_at_nodes"];

fn all_fixtures() -> Vec<Vec<u8>> {
    let mut files: Vec<Vec<u8>> = PYUFF_FIXTURES
        .iter()
        .map(|n| fixture_bytes(&format!("pyuff/{n}.uff")))
        .collect();
    files.extend(OURS.map(|n| fixture_bytes(&format!("ours/{n}.uff"))));
    files
}

#[test]
fn every_prefix_of_every_fixture_is_read_or_refused() {
    for bytes in all_fixtures() {
        for end in 0..bytes.len() {
            let _ = msd_uff::parse(&bytes[..end]);
        }
        assert!(msd_uff::parse(&bytes).is_ok());
    }
}

#[test]
fn every_single_byte_edit_of_the_mixed_files_is_read_or_refused() {
    for name in [
        "pyuff/mixed.uff",
        "pyuff/binary_trailing.uff",
        "pyuff/ascii_single.uff",
        "pyuff/modes_complex.uff",
        "pyuff/geometry_2411.uff",
    ] {
        let bytes = fixture_bytes(name);
        let mut edited = bytes.clone();
        for i in 0..bytes.len() {
            for b in [0u8, b' ', b'\n', b'\r', b'-', b'1', b'9', b'b', b'x', 0xff] {
                edited[i] = b;
                let _ = msd_uff::parse(&edited);
            }
            edited[i] = bytes[i];
        }
    }
}

proptest! {
    #[test]
    fn arbitrary_bytes_are_read_or_refused(bytes in proptest::collection::vec(any::<u8>(), 0..600)) {
        let _ = msd_uff::parse(&bytes);
    }

    #[test]
    fn arbitrary_lines_after_a_dataset_start_are_read_or_refused(
        number in prop_oneof![Just("    58"), Just("    58b     1     2          11        99999999"),
            Just("   151"), Just("   164"), Just("    82b     2     2           3          40"),
            Just("    55"), Just("    15"), Just("  2411")],
        lines in proptest::collection::vec("[ -~]{0,90}", 0..20),
    ) {
        let text = format!("    -1\n{number}\n{}\n    -1\n", lines.join("\n"));
        let _ = msd_uff::parse(text.as_bytes());
    }

    #[test]
    fn fixtures_with_bytes_spliced_in_are_read_or_refused(
        which in 0..PYUFF_FIXTURES.len() + OURS.len(), at in any::<prop::sample::Index>(), cut in 0..64usize,
        insert in proptest::collection::vec(any::<u8>(), 0..64),
    ) {
        let mut bytes = all_fixtures().swap_remove(which);
        let i = at.index(bytes.len());
        let j = (i + cut).min(bytes.len());
        bytes.splice(i..j, insert);
        let _ = msd_uff::parse(&bytes);
    }
}
