//! Damaged files are refused with an error naming the file, never a panic or a hang:
//! every reader gets its fixture truncated at every length and with bytes overwritten
//! at seeded random places.

use msd_files::read_bytes;
use std::path::Path;

fn fixture(name: &str) -> Vec<u8> {
    std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("fixtures")
            .join(name),
    )
    .unwrap()
}

/// A small deterministic generator (xorshift64*): the cases are the same on every run.
struct Cases(u64);
impl Cases {
    fn next(&mut self, below: usize) -> usize {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 33) as usize % below
    }
}

fn damaged(name: &str, seed: u64) {
    let good = fixture(name);
    read_bytes(name, &good).unwrap();
    let step = (good.len() / 300).max(1);
    for len in (0..good.len()).step_by(step) {
        if let Err(e) = read_bytes(name, &good[..len]) {
            assert!(e.to_string().starts_with(name), "{e}");
        }
    }
    let mut cases = Cases(seed);
    for _ in 0..2000 {
        let mut bytes = good.clone();
        for _ in 0..1 + cases.next(4) {
            let at = cases.next(bytes.len());
            bytes[at] = cases.next(256) as u8;
        }
        if let Err(e) = read_bytes(name, &bytes) {
            assert!(e.to_string().starts_with(name), "{e}");
        }
    }
}

#[test]
fn damaged_mat_files_are_refused_by_name() {
    damaged("record-v5.mat", 1);
    damaged("record-v7.mat", 2);
    damaged("struct-v5.mat", 6);
}

#[test]
fn damaged_npy_and_npz_files_are_refused_by_name() {
    damaged("record.npy", 3);
    damaged("record.npz", 4);
}

#[test]
fn damaged_tdms_files_are_refused_by_name() {
    damaged("record.tdms", 5);
}

/// A header nested 60 000 brackets deep (as only a crafted file is) is refused by name
/// before the header's recursive parser could exhaust the stack; a record dtype's few
/// levels read as before.
#[test]
fn a_header_nested_too_deep_is_refused_by_name() {
    let header = format!(
        "{{'descr': {}'<f8'{}, 'fortran_order': False, 'shape': (1,), }}",
        "[".repeat(60_000),
        "]".repeat(60_000)
    );
    let mut bytes = b"\x93NUMPY\x02\x00".to_vec();
    bytes.extend((header.len() as u32 + 1).to_le_bytes());
    bytes.extend(header.as_bytes());
    bytes.push(b'\n');
    bytes.extend(1.0f64.to_le_bytes());
    let e = read_bytes("deep.npy", &bytes).unwrap_err().to_string();
    assert!(
        e.starts_with("deep.npy") && e.contains("nests brackets deeper than 32"),
        "{e}"
    );
    read_bytes("record.npy", &fixture("record.npy")).unwrap();
}
