//! Lists what a data file holds: `cargo run -p msd-files --example inspect -- FILE`.
//!
//! Without an argument it writes a small `.npy` record to a temporary folder and lists
//! that.

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = match std::env::args().nth(1) {
        Some(p) => std::path::PathBuf::from(p),
        None => {
            let header = "{'descr': '<f8', 'fortran_order': False, 'shape': (4, 2), }";
            let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
            let padded = format!("{header:<117}\n");
            bytes.extend((padded.len() as u16).to_le_bytes());
            bytes.extend(padded.as_bytes());
            for v in [0.0f64, 1.0, 0.1, 0.5, 0.2, -0.5, 0.3, -1.0] {
                bytes.extend(v.to_le_bytes());
            }
            let path = std::env::temp_dir().join("msd-files-example.npy");
            std::fs::write(&path, bytes)?;
            path
        }
    };
    let contents = msd_files::read(&path)?;
    print!("{}: {contents}", path.display());
    Ok(())
}
