//! MATLAB `.mat` files, levels 5 and 7 (compressed elements), as MathWorks documents
//! them ("MAT-File Format", level 5): a 128-byte header, then data elements — each a
//! matrix, or a zlib-compressed matrix (level 7) inflated through flate2.
//!
//! Written here rather than through the `matfile` crate (0.5), which refuses every
//! `int32` array (it expects the class's data as `uint32`). Every read is bounds-checked,
//! so a damaged file is an error.

use crate::Channel;
use crate::split;
use std::io::Read;

const MI_MATRIX: u32 = 14;
const MI_COMPRESSED: u32 = 15;
/// The most a compressed element may inflate to (a damaged or hostile stream stops there).
const MAX_INFLATED: u64 = 1 << 32;

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
    if !text.starts_with("MATLAB 5.0") || bytes.len() < 128 {
        return Err(
            "no \"MATLAB 5.0 MAT-file\" header: expected a level 5 or 7 MAT-file \
             (a level 4 file: save it again with '-v7')"
                .into(),
        );
    }
    let big = match &bytes[126..128] {
        b"IM" => false,
        b"MI" => true,
        other => {
            return Err(format!(
                "endian indicator {:?} at byte 126: expected \"IM\" or \"MI\"",
                String::from_utf8_lossy(other)
            ));
        }
    };
    let mut channels = Vec::new();
    let mut skipped = Vec::new();
    let mut r = Reader {
        bytes,
        at: 128,
        big,
    };
    while r.at < bytes.len() {
        let start = r.at;
        let (kind, data) = r.element()?;
        let matrix = match kind {
            MI_MATRIX => Variable::parse(data, big),
            MI_COMPRESSED => {
                let inflated = inflate(data).map_err(|e| format!("byte {start}: {e}"))?;
                let mut inner = Reader {
                    bytes: &inflated,
                    at: 0,
                    big,
                };
                match inner.element()? {
                    (MI_MATRIX, data) => Variable::parse(data, big),
                    (other, _) => Err(format!(
                        "a compressed element holding type {other}: expected a matrix (14)"
                    )),
                }
            }
            _ => continue, // not a variable (e.g. a subsystem's data): passed over
        }
        .map_err(|why| format!("the variable at byte {start}: {why}"))?;
        matrix.collect(&mut channels, &mut skipped);
    }
    if channels.is_empty() {
        return Err(match skipped.is_empty() {
            true => "no variable: expected at least one numeric vector or matrix".into(),
            false => format!("no numeric variable: {}", skipped.join("; ")),
        });
    }
    Ok((channels, skipped))
}

fn inflate(data: &[u8]) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    flate2::read::ZlibDecoder::new(data)
        .take(MAX_INFLATED)
        .read_to_end(&mut out)
        .map_err(|e| {
            format!("a compressed variable does not inflate ({e}): the file is corrupt")
        })?;
    Ok(out)
}

/// One variable: its name, class, dimensions and parts; a structure's fields as
/// variables named `s.field` (`s(k).field` in a structure array, k from 1).
struct Variable {
    name: String,
    class: u8,
    dims: Vec<usize>,
    real: Vec<f64>,
    imag: Option<Vec<f64>>,
    fields: Vec<Variable>,
}

/// How deep structures may nest (a damaged or hostile file stops there).
const MAX_DEPTH: usize = 8;
/// The most fields a structure (array) may hold in all.
const MAX_FIELDS: usize = 1 << 16;

impl Variable {
    /// A matrix element's sub-elements: array flags, dimensions, name, real and
    /// imaginary parts (numeric classes only).
    fn parse(data: &[u8], big: bool) -> Result<Self, String> {
        Self::parse_at(data, big, 0, None)
    }

    /// [`Self::parse`] at a structure's `depth`, named `given` (a field's name with its
    /// structure's) rather than by its own (empty) name element.
    fn parse_at(
        data: &[u8],
        big: bool,
        depth: usize,
        given: Option<String>,
    ) -> Result<Self, String> {
        let mut r = Reader {
            bytes: data,
            at: 0,
            big,
        };
        if data.is_empty() {
            return Ok(Self {
                name: String::new(),
                class: 0,
                dims: Vec::new(),
                real: Vec::new(),
                imag: None,
                fields: Vec::new(),
            });
        }
        let flags = r.element()?.1;
        let flags = Reader {
            bytes: flags,
            at: 0,
            big,
        }
        .u32()?;
        let (class, complex) = ((flags & 0xff) as u8, flags & 0x0800 != 0);
        let dims_data = r.element()?.1;
        let dims = (0..dims_data.len() / 4)
            .map(|i| {
                let mut d = Reader {
                    bytes: dims_data,
                    at: 4 * i,
                    big,
                };
                d.u32().map(|v| v as i32 as usize)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let own = String::from_utf8_lossy(r.element()?.1).into_owned();
        let name = given.unwrap_or(own);
        let mut v = Self {
            name,
            class,
            dims,
            real: Vec::new(),
            imag: None,
            fields: Vec::new(),
        };
        match class {
            1 => v.fields = v.cells(&mut r, big, depth)?,
            2 => v.fields = v.struct_fields(&mut r, big, depth)?,
            _ => {}
        }
        if (6..=15).contains(&class) {
            let (kind, part) = r.element()?;
            v.real = numbers(kind, part, big)?;
            if complex {
                let (kind, part) = r.element()?;
                v.imag = Some(numbers(kind, part, big)?);
            }
        }
        Ok(v)
    }

    /// A structure's fields, element by element (MATLAB's order: each element's fields
    /// in turn), each named after it.
    fn struct_fields(
        &self,
        r: &mut Reader<'_>,
        big: bool,
        depth: usize,
    ) -> Result<Vec<Variable>, String> {
        if depth >= MAX_DEPTH {
            return Err(format!(
                "structures nested deeper than {MAX_DEPTH}: not read"
            ));
        }
        let length = r.element()?.1;
        let length = Reader {
            bytes: length,
            at: 0,
            big,
        }
        .u32()? as usize;
        let names = r.element()?.1;
        let names: Vec<String> = match length {
            0 => Vec::new(),
            n => (names.chunks(n))
                .map(|c| {
                    let end = c.iter().position(|&b| b == 0).unwrap_or(c.len());
                    String::from_utf8_lossy(&c[..end]).into_owned()
                })
                .collect(),
        };
        let count = (self.dims.iter()).try_fold(1usize, |a, &d| a.checked_mul(d));
        let count = count
            .filter(|c| c.saturating_mul(names.len()) <= MAX_FIELDS)
            .ok_or_else(|| {
                format!(
                    "a structure of size {} with {} fields: more than {MAX_FIELDS} in all",
                    size_text(&self.dims),
                    names.len()
                )
            })?;
        let mut fields = Vec::with_capacity(count * names.len());
        for k in 0..count {
            for field in &names {
                let (kind, data) = r.element()?;
                if kind != MI_MATRIX {
                    return Err(format!(
                        "field {field}: type {kind}, expected a matrix (14)"
                    ));
                }
                let name = match count {
                    1 => format!("{}.{field}", self.name),
                    _ => format!("{}({}).{field}", self.name, k + 1),
                };
                fields.push(Variable::parse_at(data, big, depth + 1, Some(name))?);
            }
        }
        Ok(fields)
    }

    /// A cell array's cells, in MATLAB's (column-major) order, each named `c{k}` (k from
    /// 1).
    fn cells(&self, r: &mut Reader<'_>, big: bool, depth: usize) -> Result<Vec<Variable>, String> {
        if depth >= MAX_DEPTH {
            return Err(format!("cells nested deeper than {MAX_DEPTH}: not read"));
        }
        let count = (self.dims.iter()).try_fold(1usize, |a, &d| a.checked_mul(d));
        let count = count.filter(|&c| c <= MAX_FIELDS).ok_or_else(|| {
            format!(
                "a cell array of size {}: more than {MAX_FIELDS} cells",
                size_text(&self.dims)
            )
        })?;
        (0..count)
            .map(|k| {
                let (kind, data) = r.element()?;
                if kind != MI_MATRIX {
                    return Err(format!(
                        "cell {}: type {kind}, expected a matrix (14)",
                        k + 1
                    ));
                }
                let name = format!("{}{{{}}}", self.name, k + 1);
                Variable::parse_at(data, big, depth + 1, Some(name))
            })
            .collect()
    }

    /// Its channels into `out` (a structure's field by field, a cell array's cell by
    /// cell), or why not into `skipped`.
    fn collect(&self, out: &mut Vec<Channel>, skipped: &mut Vec<String>) {
        if matches!(self.class, 1 | 2) {
            for field in &self.fields {
                field.collect(out, skipped);
            }
            return;
        }
        match self.channels() {
            Ok(found) => out.extend(found),
            Err(why) => skipped.push(format!("{}: {why}", self.name)),
        }
    }

    /// The variable as channels, or why it is not one.
    fn channels(&self) -> Result<Vec<Channel>, String> {
        let what = match self.class {
            6..=15 => None,
            1 | 2 => Some("a cell array or structure (read by its parts)"),
            3 => Some("an object"),
            4 => Some("text"),
            5 => Some("a sparse matrix"),
            _ => Some("an unknown class"),
        };
        if let Some(what) = what {
            return Err(format!("{what}: not read (expected numbers)"));
        }
        let Some((rows, cols)) = split::as_matrix(&self.dims) else {
            return Err(format!(
                "an array of size {}: expected a vector or a matrix",
                size_text(&self.dims)
            ));
        };
        let count = rows.saturating_mul(cols);
        let parts = std::iter::once(("", &self.real)).chain(self.imag.iter().map(|i| (".im", i)));
        let mut out = Vec::new();
        for (suffix, values) in parts {
            if values.len() != count {
                return Err(format!(
                    "{} values for a {rows}×{cols} array: the variable is corrupt",
                    values.len()
                ));
            }
            let name = match (suffix, &self.imag) {
                ("", Some(_)) => format!("{}.re", self.name),
                _ => format!("{}{suffix}", self.name),
            };
            // Column-major, as MATLAB stores it.
            let at = |r: usize, c: usize| values[c * rows + r];
            out.extend(
                split::channels(&name, rows, cols, at)
                    .into_iter()
                    .map(|(name, values)| Channel::new(name, values)),
            );
        }
        Ok(out)
    }
}

fn size_text(size: &[usize]) -> String {
    size.iter()
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join("×")
}

/// A numeric sub-element's values as `f64` (MATLAB may store a class's data in a
/// smaller type: an int32 array's small values as int8, say).
fn numbers(kind: u32, data: &[u8], big: bool) -> Result<Vec<f64>, String> {
    let size = match kind {
        1 | 2 => 1,
        3 | 4 => 2,
        5..=7 => 4,
        9 | 12 | 13 => 8,
        other => return Err(format!("data type {other}: expected a numeric type")),
    };
    Ok(data
        .chunks_exact(size)
        .map(|c| {
            let mut b = [0u8; 8];
            b[..size].copy_from_slice(c);
            if big {
                b[..size].reverse();
            }
            match kind {
                1 => b[0] as i8 as f64,
                2 => b[0] as f64,
                3 => i16::from_le_bytes([b[0], b[1]]) as f64,
                4 => u16::from_le_bytes([b[0], b[1]]) as f64,
                5 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                6 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                7 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                9 => f64::from_le_bytes(b),
                12 => i64::from_le_bytes(b) as f64,
                _ => u64::from_le_bytes(b) as f64,
            }
        })
        .collect())
}

/// Bounds-checked reads of data elements.
struct Reader<'b> {
    bytes: &'b [u8],
    at: usize,
    big: bool,
}

impl<'b> Reader<'b> {
    fn u32(&mut self) -> Result<u32, String> {
        let b: [u8; 4] = self
            .bytes
            .get(self.at..self.at + 4)
            .and_then(|b| b.try_into().ok())
            .ok_or_else(|| format!("byte {}: the data end inside a tag (truncated)", self.at))?;
        self.at += 4;
        Ok(if self.big {
            u32::from_be_bytes(b)
        } else {
            u32::from_le_bytes(b)
        })
    }

    /// The next data element: its type and data (the small format of 4 bytes or less
    /// read too); the position moves past its padding to 8 bytes.
    fn element(&mut self) -> Result<(u32, &'b [u8]), String> {
        let first = self.u32()?;
        if first >> 16 != 0 {
            let (kind, n) = (first & 0xffff, (first >> 16) as usize);
            let data = self
                .bytes
                .get(self.at..self.at + n.min(4))
                .ok_or("a small element cut short (truncated)")?;
            self.at += 4;
            return Ok((kind, data));
        }
        let n = self.u32()? as usize;
        let start = self.at;
        let data = start
            .checked_add(n)
            .and_then(|end| self.bytes.get(start..end))
            .ok_or_else(|| format!("byte {}: an element of {n} bytes runs past the end ({} bytes): truncated or corrupt", start - 8, self.bytes.len()))?;
        // Compressed elements are not padded; the others are, to a multiple of 8.
        let padded = if first == MI_COMPRESSED {
            n
        } else {
            n.div_ceil(8) * 8
        };
        self.at = (start + padded).min(self.bytes.len());
        Ok((first, data))
    }
}
