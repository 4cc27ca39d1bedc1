//! # msd-uff
//!
//! Read and write Universal File Format (UFF) files: the text-and-binary format in which
//! modal test systems export frequency response functions, spectra, coherences and time
//! records, and modal analysis programs their geometry and mode shapes. A leaf crate: it
//! knows nothing of the mass–spring–damper model.
//!
//! | dataset | what | read | written | here |
//! |---|---|---|---|---|
//! | **58**, **58b** | function at nodal DOF (FRF, spectrum, time record, …), ASCII or binary | yes | yes | [`Function58`] in [`UffFile::functions`] |
//! | **55** | data at nodes (mode shapes, operating deflections, static displacements) | yes | yes | [`Data55`] in [`UffFile::data_at_nodes`] |
//! | **15** | nodes (single precision) | yes | yes | [`Node`] in [`UffFile::nodes`] |
//! | **2411** | nodes (double precision) | yes | yes | [`Node`] in [`UffFile::nodes`] |
//! | **151** | header | yes | yes | [`UffFile::header`] |
//! | **164** | units | yes | yes | [`UffFile::units`] |
//!
//! * [`read`] and [`parse`] give a [`UffFile`]. Every other dataset (trace lines 82,
//!   elements 2412, binary 55b, …) is passed over and listed in [`UffFile::skipped`] with its
//!   byte offset, not refused.
//! * [`write()`] and [`to_bytes`] write them back: functions ASCII or binary, single or double
//!   precision; everything else as text, in the columns pyuff writes and reads.
//! * Bad files are refused with a [`UffError`] that says where (byte offset, line, dataset
//!   number), what was found and what the format expects. No input makes the reader panic.
//!
//! ## Example: read a frequency response, write it back in binary
//! ```
//! use msd_uff::{ByteOrder, Encoding, FunctionType, Ordinate};
//!
//! let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/pyuff/ascii_frf_complex.uff");
//! let mut file = msd_uff::read(path)?;
//! let frf = &file.functions[0];
//! assert_eq!(frf.function_type, FunctionType::FrequencyResponse);
//! assert_eq!((frf.response_node, frf.response_direction), (3, 3)); // node 3, +Z
//! assert_eq!((frf.reference_node, frf.reference_direction), (1, 3));
//! let f = frf.abscissa_values(); // Hz
//! let Ordinate::Complex(h) = &frf.ordinate else { panic!("an FRF is complex") };
//! assert_eq!((f[1], h[0]), (2.0, (2.5e-5, 0.0))); // 1/k at 0 Hz: receptance in m/N
//!
//! // The same function as binary 58b: the data round-trips to the bit.
//! file.functions[0].encoding = Encoding::Binary(ByteOrder::Little);
//! let bytes = msd_uff::to_bytes(&file, &Default::default())?;
//! assert_eq!(msd_uff::parse(&bytes)?, file);
//! # Ok::<(), msd_uff::UffError>(())
//! ```
//!
//! ## Example: the mode shapes of a modal model
//! ```
//! use msd_uff::Analysis55;
//!
//! let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/pyuff/modes_real.uff");
//! let file = msd_uff::read(path)?; // written by pyuff
//! let mode = &file.data_at_nodes[0];
//! let Analysis55::NormalMode { mode: 1, frequency, viscous_damping, .. } = mode.analysis else {
//!     panic!("the first dataset is mode 1")
//! };
//! assert_eq!((frequency, viscous_damping), (28.4705, 0.00782624)); // Hz, ratio
//! for (node, values) in mode.nodes.iter().zip(&mode.values) {
//!     let (z, _im) = values[2]; // direction 3, +Z; real data: im = 0
//!     println!("node {node}: {z:+.4}");
//! }
//! assert_eq!(mode.value(4, 3), Some((0.894427, 0.0))); // node 4, +Z
//! # Ok::<(), msd_uff::UffError>(())
//! ```
//!
//! ## The format
//! A UFF file is a sequence of datasets. Each opens with a line holding `-1` right-aligned
//! in columns 1–6 (`    -1`), then a line with the dataset number in columns 1–6, and
//! closes with another `    -1` line. Records are 80-column text lines read in fixed
//! Fortran columns.
//!
//! **Dataset 58, function at nodal DOF** (records 1–12):
//!
//! | record | Fortran format | content | here |
//! |---|---|---|---|
//! | 1–5 | `80A1` | ID lines (description, run, date and time, load case, …) | [`Function58::ids`] |
//! | 6 | `2(I5,I10),2(1X,10A1,I10,I4)` | function type, id, version, load case; response entity, node, direction; reference entity, node, direction | [`FunctionType`], `response_*`, `reference_*` |
//! | 7 | `3I10,3E13.5` | ordinate data type (2 real single, 4 real double, 5 complex single, 6 complex double), number of points, spacing (0 uneven, 1 even), abscissa minimum, increment, z-axis value | [`Precision`], [`Ordinate`], [`Abscissa`] |
//! | 8–11 | `I10,3I5,2(1X,20A1)` | abscissa, ordinate numerator, ordinate denominator, z axis: specific data type, length, force and temperature unit exponents, label, units label | [`Axis`] |
//! | 12 | see below | the data | [`Abscissa`], [`Ordinate`] |
//!
//! Record 12 holds, per point, the abscissa if spacing is uneven, then the real value or
//! the real and imaginary parts: `6E13.5` for single precision, `4E20.12` for double
//! precision with even spacing, `2(E13.5,E20.12)` for real and `E13.5,2E20.12` for complex
//! double precision with uneven spacing (the abscissa "is always real single precision").
//!
//! **Dataset 58b** (binary, by UC-SDRL, adopted by SDRC) is the same with record 12 in
//! binary: the number line reads `    58b` followed by `Format(I6,1A1,I6,I6,I12,I12,I6,I6,I12,I12)`
//! fields: byte ordering (1 little endian, 2 big endian), floating-point format (2 IEEE 754;
//! 1 DEC VMS and 3 IBM 5/370 are refused), number of ASCII lines that follow (11) and number
//! of bytes after them. Records 1–11 are text; the data follows the line end of record 11
//! directly, in the order of the ASCII record 12, each value a 4-byte (data types 2, 5) or
//! 8-byte (4, 6) float, the abscissa of uneven data included (as pyuff reads and writes it);
//! the closing `    -1` follows the data directly.
//!
//! **Dataset 55, data at nodes**: records 1–5 are ID lines (`40A2`); record 6
//! (`6I10`) the model type, analysis type, data characteristic, specific data type, data type
//! (2 real, 5 complex) and number of values per node; record 7 (`8I10`) the number of
//! integer parameters, the number of real ones, then the integers; record 8 (`6E13.5`) the
//! reals ([`Analysis55`]: for a normal mode the load case and mode number, then frequency,
//! modal mass, viscous and hysteretic damping ratios; for a complex eigenvalue the load case
//! and mode number, then eigenvalue, modal A and modal B, real then imaginary part). Then, per
//! node, record 9 (`I10`) the node number and record 10 (`6E13.5`) its values, real and
//! imaginary part in turn for complex data. Nodes whose values are all zero may be left out.
//!
//! **Datasets 15 and 2411, nodes**: per node the label, two coordinate system numbers, a
//! colour and X, Y, Z: in 15 on one line, `4I10,1P3E13.5`; in 2411 on two, `4I10` then
//! `1P3D25.16`.
//!
//! **Dataset 151** (header): model file name, description, program which created the
//! database; the dates and times the database was created (with two version numbers and a
//! file type) and last saved; the program which wrote the file and when ([`Header151`]).
//! **Dataset 164** (units): units code, description, temperature mode, then four factors
//! in `D25.17` that convert the file's units to SI by division ([`Units164`]).
//!
//! ## How real files deviate, and what the reader accepts
//! * Lines end in LF, CR LF or CR; text is UTF-8, else read as Latin-1; columns count
//!   characters, as pyuff counts them.
//! * An all-numeric record (7, 12, the 58b line, 164's factors) is read by its blank-separated
//!   words when they are all numbers, else by the fixed columns of the format, so both
//!   column-exact files and files written with other widths are read. Numbers may use
//!   `E`, `D` or no exponent letter (`0.12345-100`, Fortran's three-digit exponents), and
//!   blank integer fields in records 6–11 read as 0, as in Fortran.
//! * Binary data is taken by count (number of points × values per point × 4 or 8 bytes),
//!   never by looking for `-1` inside it. The byte count of the 58b line is not trusted:
//!   pyuff writes `num_pts × 8` there even for complex or uneven data, which hold two or
//!   three times more.
//! * Bytes between binary data and the closing `    -1` (a line end, or the `    -1` on a
//!   line of its own, the case of pyuff's `fix_58b`) are passed over and noted in
//!   [`UffFile::trailing`].
//! * Dataset 55 is read by count: after each node number, as many numbers as its values
//!   take, over as many lines as they fill (pyuff wants them on one line, and cannot read 6
//!   complex values per node). Analysis types other than 2, 3, 5 and 7, or with counts other
//!   than the description's, are read generically as [`Analysis55::Other`].
//! * Blank lines between datasets, and between the nodes of 15, 2411 and 55, are passed
//!   over; datasets other than those above (trace lines 82, elements 2412, binary 55b, …)
//!   are passed over, binary ones by their byte count, and listed in [`UffFile::skipped`].
//!
//! ## Writing and precision
//! Binary data is written as it is in memory: double precision round-trips to the bit,
//! single precision rounds to `f32`. Coordinates of 2411 are written in `D25.16`, which holds
//! every `f64`. Other numbers written as text (ASCII data, the abscissa start and step in
//! record 7, the coordinates of 15, the parameters and values of 55) follow
//! [`WriteOptions::ascii`]: by default
//! [`AsciiNumbers::Fixed`], the columns of the description, readable by every reader and
//! exact for numbers with short decimal forms (0.5, 2.5e-3, 1024) but otherwise rounded to
//! the 12 to 14 (in 13 columns, 5 to 7) significant digits the columns hold; [`AsciiNumbers::Exact`] writes every
//! number in 25 columns so that it reads back identically, which readers that split on
//! blanks read and fixed-column ones (pyuff) do not. Text fields keep their characters, not
//! their surrounding blanks.
//!
//! ## Sources
//! * The SDRC (now Siemens) description of *Universal Dataset Number 58: Function at Nodal
//!   DOF*, with UC-SDRL's *Binary 58 Universal File Format* and the 15, 55, 151, 164 and 2411
//!   descriptions, as reproduced in pyuff's `get_structure_58()` and the like
//!   (`pyuff/datasets/dataset_58.py`, `dataset_55.py`, `dataset_15.py`, `dataset_2411.py`,
//!   `dataset_151.py`, `dataset_164.py` in ladisk/pyuff; originally from the University of
//!   Cincinnati Structural Dynamics Research Lab's UFF pages).
//! * pyuff 2.5.8's reader and writer (`_extract58`, `_write58`, `fix_58b`, `_extract55`,
//!   `_write55`, `_write15`, `_write2411`, the block search of `UFF.refresh`), for how files
//!   are written in practice; the fixtures of the tests are written by pyuff
//!   (`fixtures/make_fixtures.py`), which also checks that pyuff reads the files this crate
//!   writes (`python3 fixtures/make_fixtures.py check`).

mod display;
mod error;
mod framing;
mod function_type;
mod nodes;
mod read;
mod read55;
mod read58;
mod text;
mod types;
mod write;
mod write55;

use std::path::Path;

pub use display::direction_name;
pub use error::{Position, UffError};
pub use function_type::FunctionType;
pub use nodes::{Analysis55, Data55, Node};
pub use types::{
    Abscissa, Axis, ByteOrder, Encoding, Function58, Header151, Ordinate, Precision, Skipped,
    TrailingBytes, UffFile, Units164,
};
pub use write::{AsciiNumbers, WriteOptions};

/// Reads a UFF file.
///
/// ```
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/pyuff/mixed.uff");
/// let file = msd_uff::read(path)?;
/// assert_eq!(file.header.as_ref().map(|h| h.model_name.as_str()), Some("msd-uff fixture model"));
/// assert_eq!(file.units.as_ref().map(|u| u.code), Some(1)); // SI
/// assert_eq!(file.functions.len(), 2);
/// assert_eq!(file.nodes.len(), 3); // the geometry, dataset 15
/// let skipped: Vec<(u32, usize)> = file.skipped.iter().map(|s| (s.number, s.offset)).collect();
/// assert_eq!(skipped, [(82, 2177)]); // trace lines, with their byte offset
/// # Ok::<(), msd_uff::UffError>(())
/// ```
pub fn read(path: impl AsRef<Path>) -> Result<UffFile, UffError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| UffError::Io {
        action: "read",
        path: path.into(),
        source,
    })?;
    parse(&bytes)
}

/// Parses the bytes of a UFF file.
///
/// ```
/// let text = "    -1\n   164\n         1                  SI         1\n\
///     1.0D+00 1.0D+00 1.0D+00\n 0.0D+00\n    -1\n";
/// let file = msd_uff::parse(text.as_bytes())?;
/// assert_eq!(file.units.map(|u| (u.code, u.description)), Some((1, "SI".to_string())));
/// # Ok::<(), msd_uff::UffError>(())
/// ```
pub fn parse(bytes: &[u8]) -> Result<UffFile, UffError> {
    read::parse_file(bytes)
}

/// Writes a UFF file: the header (151), the units (164), the nodes (15 or 2411), the data at
/// nodes (55), then the functions (58 or 58b).
///
/// ```
/// use msd_uff::{Abscissa, Function58, FunctionType, Ordinate, UffFile};
///
/// let mut file = UffFile::default();
/// file.functions.push(Function58::new(FunctionType::Coherence,
///     Abscissa::Even { start: 0.0, step: 0.5 }, Ordinate::Real(vec![0.98, 0.99, 0.97])));
/// let path = std::env::temp_dir().join("msd-uff-doc-write.uff");
/// msd_uff::write(&path, &file, &Default::default())?;
/// assert_eq!(msd_uff::read(&path)?, file);
/// # std::fs::remove_file(&path).ok();
/// # Ok::<(), msd_uff::UffError>(())
/// ```
pub fn write(
    path: impl AsRef<Path>,
    file: &UffFile,
    options: &WriteOptions,
) -> Result<(), UffError> {
    let path = path.as_ref();
    let bytes = to_bytes(file, options)?;
    std::fs::write(path, bytes).map_err(|source| UffError::Io {
        action: "write",
        path: path.into(),
        source,
    })
}

/// The bytes [`write()`] would write.
///
/// ```
/// use msd_uff::{Abscissa, Function58, FunctionType, Ordinate, UffFile};
///
/// let mut file = UffFile::default();
/// let mut f = Function58::new(FunctionType::TimeResponse,
///     Abscissa::Even { start: 0.0, step: 1e-3 }, Ordinate::Real(vec![1.5, -0.25]));
/// f.response_entity = "a name longer than ten".into();
/// file.functions.push(f);
/// let err = msd_uff::to_bytes(&file, &Default::default()).unwrap_err();
/// assert_eq!(err.to_string(), "cannot write dataset 58 (#0 of its kind): `response_entity` = \
///     \"a name longer than ten\": expected at most 10 characters");
/// ```
pub fn to_bytes(file: &UffFile, options: &WriteOptions) -> Result<Vec<u8>, UffError> {
    write::file_bytes(file, options)
}
