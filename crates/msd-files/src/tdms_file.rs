//! NI TDMS files (LabVIEW), as NI documents them ("TDMS File Format Internal
//! Structure"): segments of a 28-byte lead-in, metadata (objects, their raw-data indices
//! and properties) and raw data, contiguous or interleaved, little- or big-endian.
//!
//! Written here rather than through the `tdms` crate (0.3): that reader loops without
//! end, allocating, on valid files with a segment of properties only (as npTDMS and
//! LabVIEW write when a property is set after the data) and on many damaged ones. Every
//! read here is bounds-checked against the file, so a damaged file is an error.

use crate::Channel;

const LEAD_IN: usize = 28;
const TOC_METADATA: u32 = 1 << 1;
const TOC_NEW_OBJECT_LIST: u32 = 1 << 2;
const TOC_RAW_DATA: u32 = 1 << 3;
const TOC_INTERLEAVED: u32 = 1 << 5;
const TOC_BIG_ENDIAN: u32 = 1 << 6;
const TOC_DAQMX: u32 = 1 << 7;

/// A channel as the segments build it up.
#[derive(Default)]
struct Object {
    path: String,
    /// The data type code and values per chunk of the last raw-data index.
    index: Option<(u32, u64)>,
    values: Vec<f64>,
    unit: Option<String>,
    increment: Option<f64>,
    unread: Option<String>,
}

/// The channels of a TDMS file given as bytes, and what was skipped.
pub(crate) fn read_bytes(bytes: &[u8]) -> Result<(Vec<Channel>, Vec<String>), String> {
    let mut objects: Vec<Object> = Vec::new();
    let mut list: Vec<usize> = Vec::new(); // the objects with raw data, in order
    let mut at = 0usize;
    let mut index = 0usize;
    while at < bytes.len() {
        let where_ = format!("segment {index} at byte {at}");
        at = segment(bytes, at, &mut objects, &mut list)
            .map_err(|why| format!("{where_}: {why}"))?;
        index += 1;
    }
    let channels: Vec<&Object> = objects
        .iter()
        .filter(|o| o.path.matches("'/'").count() == 1)
        .collect();
    if channels.is_empty() {
        return Err("no channel: expected at least one group with a channel".into());
    }
    Ok(named(&channels))
}

/// Channel names: `channel`, or `group/channel` where another group has a channel of
/// that name.
fn named(objects: &[&Object]) -> (Vec<Channel>, Vec<String>) {
    let parts: Vec<(String, String)> = objects.iter().map(|o| split_path(&o.path)).collect();
    let mut channels = Vec::new();
    let mut skipped = Vec::new();
    for (o, (group, name)) in objects.iter().zip(&parts) {
        let unique = parts.iter().filter(|(_, n)| n == name).count() == 1;
        let label = if unique {
            name.clone()
        } else {
            format!("{group}/{name}")
        };
        match &o.unread {
            Some(why) => skipped.push(format!("{group}/{name}: {why}")),
            None => channels.push(Channel {
                name: label,
                unit: o.unit.clone().filter(|u| !u.is_empty()),
                sample_rate_hz: o
                    .increment
                    .filter(|d| d.is_finite() && *d > 0.0)
                    .map(|d| 1.0 / d),
                values: o.values.clone(),
            }),
        }
    }
    (channels, skipped)
}

/// `/'Group'/'Channel'` as (`Group`, `Channel`), with `''` read as `'`.
fn split_path(path: &str) -> (String, String) {
    let inner = path.trim_start_matches("/'").trim_end_matches('\'');
    let (group, name) = inner.split_once("'/'").unwrap_or(("", inner));
    (group.replace("''", "'"), name.replace("''", "'"))
}

/// Reads the segment at `at`; returns where the next one starts.
fn segment(
    bytes: &[u8],
    at: usize,
    objects: &mut Vec<Object>,
    list: &mut Vec<usize>,
) -> Result<usize, String> {
    let lead = bytes
        .get(at..at + LEAD_IN)
        .ok_or("the lead-in is cut short: the file is truncated")?;
    if &lead[..4] != b"TDSm" {
        return Err(format!(
            "found {:?} where a segment starts with \"TDSm\"",
            String::from_utf8_lossy(&lead[..4])
        ));
    }
    let mut r = Reader {
        bytes: lead,
        at: 4,
        big: false,
    };
    let toc = r.u32()?;
    let _version = r.u32()?;
    let (next, raw_offset) = (r.u64()?, r.u64()?);
    let start = at + LEAD_IN;
    // An unfinished segment (next = all ones) runs to the end of the file.
    let end = if next == u64::MAX {
        bytes.len()
    } else {
        usize::try_from(next)
            .ok()
            .and_then(|n| start.checked_add(n))
            .filter(|&e| e <= bytes.len())
            .ok_or_else(|| format!("the next segment at +{next} lies past the end of the file ({} bytes): truncated or corrupt", bytes.len()))?
    };
    let raw_start = usize::try_from(raw_offset)
        .ok()
        .and_then(|n| start.checked_add(n))
        .filter(|&s| s <= end)
        .ok_or_else(|| format!("raw data at +{raw_offset} past the segment's end"))?;
    if toc & TOC_DAQMX != 0 {
        return Err("DAQmx raw data (as DAQmx logging writes it), which this reader does not read: convert the file to standard TDMS (LabVIEW's TDMS Convert Format) or export its channels with npTDMS".into());
    }
    let big = toc & TOC_BIG_ENDIAN != 0;
    if toc & TOC_NEW_OBJECT_LIST != 0 {
        list.clear();
    }
    if toc & TOC_METADATA != 0 {
        let mut r = Reader {
            bytes: &bytes[..raw_start],
            at: start,
            big,
        };
        metadata(&mut r, objects, list)?;
    }
    if toc & TOC_RAW_DATA != 0 {
        let r = Reader {
            bytes: &bytes[..end],
            at: raw_start,
            big,
        };
        raw_data(r, objects, list, toc & TOC_INTERLEAVED != 0)?;
    }
    Ok(end.max(at + LEAD_IN))
}

/// The objects of a segment's metadata: their raw-data indices and properties.
fn metadata(
    r: &mut Reader<'_>,
    objects: &mut Vec<Object>,
    list: &mut Vec<usize>,
) -> Result<(), String> {
    let count = r.u32()?;
    for _ in 0..count {
        let path = r.string()?;
        let i = match objects.iter().position(|o| o.path == path) {
            Some(i) => i,
            None => {
                objects.push(Object {
                    path,
                    ..Object::default()
                });
                objects.len() - 1
            }
        };
        let index_length = r.u32()?;
        match index_length {
            0xFFFF_FFFF => list.retain(|&k| k != i),
            0 => {
                if objects[i].index.is_none() {
                    return Err(format!(
                        "object {}: \"same index as before\" with no index before",
                        objects[i].path
                    ));
                }
                if !list.contains(&i) {
                    list.push(i);
                }
            }
            0x6912_0000 | 0x6913_0000 => {
                return Err(
                    "DAQmx raw data index: not read (convert the file to standard TDMS)".into(),
                );
            }
            _ => {
                let kind = r.u32()?;
                let _dimension = r.u32()?;
                let values = r.u64()?;
                if kind == 0x20 {
                    let _bytes = r.u64()?;
                }
                objects[i].index = Some((kind, values));
                if !list.contains(&i) {
                    list.push(i);
                }
            }
        }
        let properties = r.u32()?;
        for _ in 0..properties {
            let name = r.string()?;
            let kind = r.u32()?;
            let value = r.value(kind)?;
            let o = &mut objects[i];
            match (name.as_str(), value) {
                ("unit_string", Value::Text(t)) => o.unit = Some(t),
                ("wf_increment", Value::Number(v)) => o.increment = Some(v),
                _ => {}
            }
        }
    }
    Ok(())
}

/// A segment's raw data appended to its objects' values: whole chunks, each holding
/// every listed object's values (one after the other, or interleaved).
fn raw_data(
    mut r: Reader<'_>,
    objects: &mut [Object],
    list: &[usize],
    interleaved: bool,
) -> Result<(), String> {
    let mut layout = Vec::new();
    for &i in list {
        let Some((kind, values)) = objects[i].index else {
            continue;
        };
        let size = fixed_size(kind).ok_or_else(|| {
            format!(
                "object {}: data type 0x{kind:x} in raw data: expected fixed-size numbers",
                objects[i].path
            )
        });
        match size {
            Ok(size) => layout.push((i, kind, size, values)),
            Err(why) => {
                // A channel of text or another type: its segment is not laid out, and no
                // channel of it keeps values that would miss that segment's.
                for &k in list {
                    objects[k].unread.get_or_insert_with(|| {
                        format!("shares its data with a channel this reader does not read ({why})")
                    });
                }
                objects[i].unread = Some(why);
                return Ok(());
            }
        }
    }
    let chunk: u64 = layout
        .iter()
        .try_fold(0u64, |sum, &(_, _, size, n)| {
            (size as u64)
                .checked_mul(n)
                .and_then(|b| sum.checked_add(b))
        })
        .ok_or("the raw-data index declares more values than can be counted: corrupt")?;
    let available = (r.bytes.len() - r.at) as u64;
    if chunk == 0 || chunk > available {
        return match chunk {
            0 => Ok(()),
            _ => Err(format!(
                "the raw-data index declares a chunk of {chunk} bytes where the segment holds {available}: truncated or corrupt"
            )),
        };
    }
    for _ in 0..available / chunk {
        if interleaved {
            let n = layout.iter().map(|l| l.3).max().unwrap_or(0);
            for _ in 0..n {
                for &(i, kind, _, _) in &layout {
                    let v = r.number(kind)?;
                    objects[i].values.push(v);
                }
            }
        } else {
            for &(i, kind, _, n) in &layout {
                for _ in 0..n {
                    let v = r.number(kind)?;
                    objects[i].values.push(v);
                }
            }
        }
    }
    Ok(())
}

/// The size in bytes of a value of data type `kind` that reads as a number.
fn fixed_size(kind: u32) -> Option<usize> {
    match kind {
        1 | 5 | 0x21 => Some(1),
        2 | 6 => Some(2),
        3 | 7 | 9 | 0x19 => Some(4),
        4 | 8 | 10 | 0x1A => Some(8),
        _ => None,
    }
}

enum Value {
    Number(f64),
    Text(String),
    Other,
}

/// Bounds-checked reads from `bytes` at `at`, in the segment's byte order.
struct Reader<'b> {
    bytes: &'b [u8],
    at: usize,
    big: bool,
}

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> Result<[u8; N], String> {
        let b = self.bytes.get(self.at..self.at + N).ok_or_else(|| {
            format!(
                "byte {}: the data end before a {N}-byte value (truncated or corrupt)",
                self.at
            )
        })?;
        self.at += N;
        let mut out: [u8; N] = b.try_into().map_err(|_| "short read".to_string())?;
        if self.big {
            out.reverse();
        }
        Ok(out)
    }

    fn u32(&mut self) -> Result<u32, String> {
        self.take::<4>().map(u32::from_le_bytes)
    }

    fn u64(&mut self) -> Result<u64, String> {
        self.take::<8>().map(u64::from_le_bytes)
    }

    fn string(&mut self) -> Result<String, String> {
        let n = self.u32()? as usize;
        let b = self
            .bytes
            .get(self.at..self.at.saturating_add(n))
            .ok_or_else(|| {
                format!(
                    "byte {}: a text of {n} bytes runs past the metadata (corrupt)",
                    self.at
                )
            })?;
        self.at += n;
        Ok(String::from_utf8_lossy(b).into_owned())
    }

    fn value(&mut self, kind: u32) -> Result<Value, String> {
        Ok(match kind {
            0x20 => Value::Text(self.string()?),
            0x44 => {
                self.take::<16>()?;
                Value::Other
            }
            0x0008_000C => {
                self.take::<8>()?;
                Value::Other
            }
            0x0010_000D => {
                self.take::<16>()?;
                Value::Other
            }
            k if fixed_size(k).is_some() => Value::Number(self.number(k)?),
            k => {
                return Err(format!(
                    "byte {}: property data type 0x{k:x}: not a TDMS type",
                    self.at
                ));
            }
        })
    }

    /// A value of the fixed-size numeric type `kind`, as `f64`.
    fn number(&mut self, kind: u32) -> Result<f64, String> {
        Ok(match kind {
            1 => i8::from_le_bytes(self.take()?) as f64,
            2 => i16::from_le_bytes(self.take()?) as f64,
            3 => i32::from_le_bytes(self.take()?) as f64,
            4 => i64::from_le_bytes(self.take()?) as f64,
            5 | 0x21 => u8::from_le_bytes(self.take()?) as f64,
            6 => u16::from_le_bytes(self.take()?) as f64,
            7 => u32::from_le_bytes(self.take()?) as f64,
            8 => u64::from_le_bytes(self.take()?) as f64,
            9 | 0x19 => f32::from_le_bytes(self.take()?) as f64,
            10 | 0x1A => f64::from_le_bytes(self.take()?),
            k => return Err(format!("data type 0x{k:x}: not a number")),
        })
    }
}
