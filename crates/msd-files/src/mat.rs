//! MATLAB `.mat` files, levels 5 and 7 (compressed), through the `matfile` crate.

use crate::Channel;
use crate::split;
use matfile::NumericData;

/// The numeric variables of a MAT-file as channels, and what was skipped.
pub(crate) fn read(bytes: &[u8]) -> Result<(Vec<Channel>, Vec<String>), String> {
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(116)]);
    if text.starts_with("MATLAB 7.3") {
        return Err(
            "a level 7.3 (HDF5) MAT-file, which this reader does not read: save it \
             with save(file, ..., '-v7') in MATLAB (or read it with h5py)"
                .into(),
        );
    }
    if !text.starts_with("MATLAB 5.0") {
        return Err(
            "no \"MATLAB 5.0 MAT-file\" header: expected a level 5 or 7 MAT-file \
             (a level 4 file: save it again with '-v7')"
                .into(),
        );
    }
    let file = std::panic::catch_unwind(|| matfile::MatFile::parse(bytes))
        .map_err(|_| "the file is corrupt: its structure could not be parsed".to_string())?
        .map_err(|e| format!("{e}: expected a complete level 5 or 7 MAT-file"))?;
    let mut channels = Vec::new();
    let mut skipped = Vec::new();
    for array in file.arrays() {
        let name = array.name();
        let Some((rows, cols)) = split::as_matrix(array.size()) else {
            skipped.push(format!(
                "{name}: an array of size {}: expected a vector or a matrix",
                size_text(array.size())
            ));
            continue;
        };
        let (real, imag) = parts(array.data());
        if real.len() != rows * cols {
            skipped.push(format!(
                "{name}: {} values for a {rows}×{cols} array: the variable is corrupt",
                real.len()
            ));
            continue;
        }
        let mut add = |name: &str, values: &[f64]| {
            // Column-major, as MATLAB stores it.
            let at = |r: usize, c: usize| values[c * rows + r];
            channels.extend(split::channels(name, rows, cols, at).into_iter().map(
                |(name, values)| Channel {
                    name,
                    unit: None,
                    sample_rate_hz: None,
                    values,
                },
            ));
        };
        match imag {
            Some(imag) if imag.len() == real.len() => {
                add(&format!("{name}.re"), &real);
                add(&format!("{name}.im"), &imag);
            }
            _ => add(name, &real),
        }
    }
    if channels.is_empty() && skipped.is_empty() {
        return Err(
            "no numeric variable: expected at least one (text, cells and \
             structures are not read; sparse matrices neither)"
                .into(),
        );
    }
    Ok((channels, skipped))
}

fn size_text(size: &[usize]) -> String {
    size.iter()
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join("×")
}

/// The real and imaginary parts as `f64`.
fn parts(data: &NumericData) -> (Vec<f64>, Option<Vec<f64>>) {
    macro_rules! widen {
        ($real:expr, $imag:expr) => {
            (
                $real.iter().map(|&v| v as f64).collect(),
                $imag
                    .as_ref()
                    .map(|i| i.iter().map(|&v| v as f64).collect()),
            )
        };
    }
    match data {
        NumericData::Int8 { real, imag } => widen!(real, imag),
        NumericData::UInt8 { real, imag } => widen!(real, imag),
        NumericData::Int16 { real, imag } => widen!(real, imag),
        NumericData::UInt16 { real, imag } => widen!(real, imag),
        NumericData::Int32 { real, imag } => widen!(real, imag),
        NumericData::UInt32 { real, imag } => widen!(real, imag),
        NumericData::Int64 { real, imag } => widen!(real, imag),
        NumericData::UInt64 { real, imag } => widen!(real, imag),
        NumericData::Single { real, imag } => widen!(real, imag),
        NumericData::Double { real, imag } => widen!(real, imag),
    }
}
