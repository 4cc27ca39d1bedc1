//! NumPy `.npy` arrays and `.npz` archives, through `npyz` (and `zip` for the archive).

use crate::Channel;
use crate::split;
use npyz::{DType, NpyFile, Order, TypeChar};
use std::io::Read;
use std::path::Path;

/// An array's shape and its values as `f64`, in C order (the last index fastest).
///
/// Floats (2, 4 or 8 bytes are read as `f4`/`f8`), signed and unsigned integers and
/// booleans are read; anything else (text, objects, records, complex) is refused with
/// its dtype.
///
/// ```
/// let header = "{'descr': '<i4', 'fortran_order': True, 'shape': (2, 2), }";
/// let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
/// let padded = format!("{header:<117}\n");
/// bytes.extend((padded.len() as u16).to_le_bytes());
/// bytes.extend(padded.as_bytes());
/// for v in [1i32, 3, 2, 4] { bytes.extend(v.to_le_bytes()); }
/// let (shape, values) = msd_files::npy_array(&bytes).unwrap();
/// assert_eq!((shape, values), (vec![2, 2], vec![1.0, 2.0, 3.0, 4.0]));
/// ```
pub fn npy_array(bytes: &[u8]) -> Result<(Vec<usize>, Vec<f64>), String> {
    header_nesting(bytes)?;
    let npy = NpyFile::new(bytes).map_err(|e| format!("not a NumPy .npy array: {e}"))?;
    let shape: Vec<usize> = npy.shape().iter().map(|&d| d as usize).collect();
    let fortran = npy.order() == Order::Fortran;
    let DType::Plain(t) = npy.dtype() else {
        return Err(format!(
            "dtype {}: expected numbers (a record or sub-array dtype is not read)",
            npy.dtype().descr()
        ));
    };
    let count: usize = shape.iter().product();
    let declared = count.saturating_mul(t.num_bytes().unwrap_or(1));
    if declared > bytes.len() {
        return Err(format!(
            "the header declares {count} values ({declared} bytes) where the file has {} bytes: truncated",
            bytes.len()
        ));
    }
    let values = values_of(npy, t.type_char(), t.size_field())?;
    Ok((shape.clone(), c_order(values, &shape, fortran)))
}

/// The deepest nesting of brackets a header may have: NumPy's own have two (the dict
/// and its shape), a record dtype a few more.
const MAX_NESTING: usize = 32;

/// Refuses a header nested deeper than [`MAX_NESTING`] before its Python-literal parser
/// (recursive) sees it: a crafted file would otherwise exhaust the stack.
fn header_nesting(bytes: &[u8]) -> Result<(), String> {
    let (Some(&major), true) = (bytes.get(6), bytes.starts_with(b"\x93NUMPY")) else {
        return Ok(()); // not a .npy: npyz says what it is not
    };
    let (start, len) = match major {
        1 => (
            10,
            bytes
                .get(8..10)
                .map(|b| u16::from_le_bytes([b[0], b[1]]) as usize),
        ),
        _ => (
            12,
            (bytes.get(8..12)).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize),
        ),
    };
    let header = &bytes[start.min(bytes.len())..(start + len.unwrap_or(0)).min(bytes.len())];
    let mut depth = 0usize;
    for &b in header {
        match b {
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' => depth = depth.saturating_sub(1),
            _ => {}
        }
        if depth > MAX_NESTING {
            return Err(format!(
                "its header nests brackets deeper than {MAX_NESTING}: not a NumPy .npy array's header"
            ));
        }
    }
    Ok(())
}

fn values_of(npy: NpyFile<&[u8]>, kind: TypeChar, size: u64) -> Result<Vec<f64>, String> {
    let descr = npy.dtype().descr();
    let err = |e: std::io::Error| format!("{e} (dtype {descr})");
    macro_rules! widen {
        ($t:ty) => {
            npy.into_vec::<$t>()
                .map_err(err)?
                .into_iter()
                .map(|v| v as f64)
                .collect()
        };
    }
    Ok(match (kind, size) {
        (TypeChar::Float, 8) => npy.into_vec::<f64>().map_err(err)?,
        (TypeChar::Float, 4) => widen!(f32),
        (TypeChar::Int, 1) => widen!(i8),
        (TypeChar::Int, 2) => widen!(i16),
        (TypeChar::Int, 4) => widen!(i32),
        (TypeChar::Int, 8) => widen!(i64),
        (TypeChar::Uint, 1) => widen!(u8),
        (TypeChar::Uint, 2) => widen!(u16),
        (TypeChar::Uint, 4) => widen!(u32),
        (TypeChar::Uint, 8) => widen!(u64),
        (TypeChar::Bool, 1) => npy
            .into_vec::<bool>()
            .map_err(err)?
            .into_iter()
            .map(f64::from)
            .collect(),
        _ => {
            return Err(format!(
                "dtype {descr}: expected real numbers (float16/32/64, integers or booleans)"
            ));
        }
    })
}

/// `values` laid out in C order whatever the file's order.
fn c_order(values: Vec<f64>, shape: &[usize], fortran: bool) -> Vec<f64> {
    let Some((rows, cols)) = split::as_matrix(shape).filter(|_| fortran) else {
        return values; // C order, or a vector (the same in both)
    };
    let mut out = vec![0.0; values.len()];
    for r in 0..rows {
        for c in 0..cols {
            out[r * cols + c] = values[c * rows + r];
        }
    }
    out
}

/// One array's channels, or why it is skipped.
fn channels_of(name: &str, bytes: &[u8]) -> Result<Result<Vec<Channel>, String>, String> {
    let (shape, values) = npy_array(bytes)?;
    let Some((rows, cols)) = split::as_matrix(&shape) else {
        return Ok(Err(format!(
            "{name}: an array of shape {shape:?}: expected a vector or a matrix"
        )));
    };
    let at = |r: usize, c: usize| values[r * cols + c];
    Ok(Ok(split::channels(name, rows, cols, at)
        .into_iter()
        .map(|(name, values)| Channel::new(name, values))
        .collect()))
}

/// A `.npy` file's channels, named after the file.
pub(crate) fn read_npy(path: &Path, bytes: &[u8]) -> Result<(Vec<Channel>, Vec<String>), String> {
    let name = path
        .file_stem()
        .map_or_else(|| "array".into(), |s| s.to_string_lossy().into_owned());
    match channels_of(&name, bytes)? {
        Ok(channels) => Ok((channels, Vec::new())),
        Err(why) => Err(why),
    }
}

/// An `.npz` archive's arrays as channels, each named as its entry.
pub(crate) fn read_npz(bytes: &[u8]) -> Result<(Vec<Channel>, Vec<String>), String> {
    let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes))
        .map_err(|e| format!("not a zip archive: {e}"))?;
    let mut channels = Vec::new();
    let mut skipped = Vec::new();
    for i in 0..archive.len() {
        let mut entry = archive.by_index(i).map_err(|e| format!("entry {i}: {e}"))?;
        let entry_name = entry.name().to_string();
        let Some(name) = entry_name.strip_suffix(".npy") else {
            skipped.push(format!("{entry_name}: not a .npy entry"));
            continue;
        };
        let mut data = Vec::new();
        entry
            .read_to_end(&mut data)
            .map_err(|e| format!("entry {entry_name}: {e}: the archive is corrupt"))?;
        match channels_of(name, &data).map_err(|why| format!("entry {entry_name}: {why}"))? {
            Ok(found) => channels.extend(found),
            Err(why) => skipped.push(why),
        }
    }
    if channels.is_empty() {
        return Err("no array of numbers in the archive: expected at least one".into());
    }
    Ok((channels, skipped))
}
