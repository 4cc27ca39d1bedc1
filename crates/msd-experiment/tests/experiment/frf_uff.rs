//! The UFF file `configs/frf-uff.toml` reads is the one the `frf_uff` example writes.

#[path = "../../examples/frf_uff.rs"]
mod example;

#[test]
fn the_shipped_uff_file_is_what_the_example_writes() {
    let shipped = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/data/frf-2dof.uff"
    );
    let bytes = std::fs::read(shipped).expect("the shipped file");
    let written = msd_uff::to_bytes(&example::frf_2dof(), &Default::default()).expect("bytes");
    assert!(
        bytes == written,
        "configs/data/frf-2dof.uff differs: run the example again"
    );
    // And it reads back as the file's contents (to the 13 digits of its ASCII columns).
    let read = msd_uff::parse(&bytes).expect("reads");
    assert_eq!(read.functions.len(), 1);
    assert_eq!(read.functions[0].len(), 200);
}
