//! The contents of a UFF file: [`UffFile`] and the datasets it holds.

use serde::Serialize;

use crate::{
    function_type::FunctionType,
    nodes::{Data55, Node},
};

/// Everything read from, or to be written to, one UFF file.
///
/// Reading fills `functions` (datasets 58 and 58b in file order), `header` (the first
/// dataset 151), `units` (the first dataset 164), `nodes` (datasets 15 and 2411) and
/// `data_at_nodes` (datasets 55), and notes what it passed over in `skipped` and
/// `trailing`. Writing writes the header, the units, the nodes (consecutive nodes of the
/// same [`Node::precision`] as one dataset 15 or 2411), the data at nodes and the
/// functions, in that order; `skipped` and `trailing` are not written.
///
/// ```
/// use msd_uff::{Abscissa, Function58, FunctionType, Ordinate, UffFile};
///
/// let mut file = UffFile::default();
/// file.functions.push(Function58::new(
///     FunctionType::TimeResponse,
///     Abscissa::Even { start: 0.0, step: 0.01 },
///     Ordinate::Real(vec![0.0, 0.5, 1.0]),
/// ));
/// let bytes = msd_uff::to_bytes(&file, &Default::default())?;
/// assert_eq!(msd_uff::parse(&bytes)?, file);
/// # Ok::<(), msd_uff::UffError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct UffFile {
    /// The file header (dataset 151), if the file has one.
    pub header: Option<Header151>,
    /// The units (dataset 164), if the file has them.
    pub units: Option<Units164>,
    /// The nodes of the geometry (datasets 15 and 2411), in file order.
    pub nodes: Vec<Node>,
    /// Data at nodes, e.g. mode shapes (datasets 55), in file order.
    pub data_at_nodes: Vec<Data55>,
    /// The functions (datasets 58 and 58b), in file order.
    pub functions: Vec<Function58>,
    /// The datasets passed over while reading.
    pub skipped: Vec<Skipped>,
    /// Bytes found between binary data and the line that closes its dataset.
    pub trailing: Vec<TrailingBytes>,
}

/// A function at a nodal degree of freedom: dataset 58 (ASCII) or 58b (binary).
///
/// Field by field it follows records 1–12 of the SDRC description (see the crate docs).
/// Text fields are kept without their surrounding blanks.
///
/// ```
/// use msd_uff::{Abscissa, Function58, FunctionType, Ordinate};
///
/// let mut frf = Function58::new(
///     FunctionType::FrequencyResponse,
///     Abscissa::Even { start: 0.0, step: 0.5 },
///     Ordinate::Complex(vec![(1.0, 0.0), (0.9, -0.1), (0.5, -0.4)]),
/// );
/// frf.response_node = 3;
/// frf.response_direction = 3; // +Z
/// frf.reference_node = 1;
/// frf.reference_direction = 3;
/// assert_eq!(frf.len(), 3);
/// assert_eq!(frf.abscissa_values(), [0.0, 0.5, 1.0]);
/// assert_eq!(frf.to_string(), "frequency response function, response 3:+Z, reference 1:+Z, \
///     3 complex points, abscissa 0 + 0.5·k, double precision, ASCII");
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Function58 {
    /// ID lines 1–5 (records 1–5, up to 80 characters each). By convention: 1 a
    /// description, 3 the date and time of creation; `"NONE"` when unused.
    pub ids: [String; 5],
    /// Record 6, field 1.
    pub function_type: FunctionType,
    /// Record 6, field 2: function identification number.
    pub function_id: i64,
    /// Record 6, field 3: version or sequence number.
    pub version: i64,
    /// Record 6, field 4: load case identification number (0: single point excitation).
    pub load_case: i64,
    /// Record 6, field 5: response entity name (up to 10 characters, `"NONE"` if unused).
    pub response_entity: String,
    /// Record 6, field 6: response node.
    pub response_node: i64,
    /// Record 6, field 7: response direction: 0 scalar, ±1 ±X, ±2 ±Y, ±3 ±Z translation,
    /// ±4 ±X, ±5 ±Y, ±6 ±Z rotation.
    pub response_direction: i32,
    /// Record 6, field 8: reference entity name (up to 10 characters).
    pub reference_entity: String,
    /// Record 6, field 9: reference node.
    pub reference_node: i64,
    /// Record 6, field 10: reference direction, coded as `response_direction`.
    pub reference_direction: i32,
    /// The abscissa (record 7, fields 3–5, and for uneven spacing record 12).
    pub abscissa: Abscissa,
    /// The ordinate values (record 12); their count is record 7, field 2.
    pub ordinate: Ordinate,
    /// Precision of the data in the file (record 7, field 1).
    pub precision: Precision,
    /// ASCII (dataset 58) or binary (58b).
    pub encoding: Encoding,
    /// Record 7, field 6: z-axis value (0 if unused).
    pub z_axis_value: f64,
    /// Record 8: the abscissa's data characteristics.
    pub abscissa_axis: Axis,
    /// Record 9: the ordinate's (or the ordinate numerator's) data characteristics.
    pub ordinate_axis: Axis,
    /// Record 10: the ordinate denominator's data characteristics.
    pub denominator_axis: Axis,
    /// Record 11: the z axis's data characteristics.
    pub z_axis: Axis,
}

impl Function58 {
    /// A function with the given data and the format's "unused" values elsewhere: ID lines
    /// and entity names `"NONE"`, nodes, directions and numbers 0, [`Axis::default`] on
    /// all four axes, double precision, ASCII.
    ///
    /// ```
    /// use msd_uff::{Abscissa, Encoding, Function58, FunctionType, Ordinate, Precision};
    ///
    /// let f = Function58::new(FunctionType::Coherence, Abscissa::Uneven(vec![1.0, 3.0]),
    ///     Ordinate::Real(vec![0.9, 0.95]));
    /// assert_eq!(f.ids[0], "NONE");
    /// assert_eq!((f.precision, f.encoding), (Precision::Double, Encoding::Ascii));
    /// ```
    pub fn new(function_type: FunctionType, abscissa: Abscissa, ordinate: Ordinate) -> Self {
        let none = || "NONE".to_string();
        Self {
            ids: [none(), none(), none(), none(), none()],
            function_type,
            function_id: 0,
            version: 0,
            load_case: 0,
            response_entity: none(),
            response_node: 0,
            response_direction: 0,
            reference_entity: none(),
            reference_node: 0,
            reference_direction: 0,
            abscissa,
            ordinate,
            precision: Precision::Double,
            encoding: Encoding::Ascii,
            z_axis_value: 0.0,
            abscissa_axis: Axis::default(),
            ordinate_axis: Axis::default(),
            denominator_axis: Axis::default(),
            z_axis: Axis::default(),
        }
    }

    /// The number of points (ordinate values).
    ///
    /// ```
    /// # use msd_uff::{Abscissa, Function58, FunctionType, Ordinate};
    /// let f = Function58::new(FunctionType::General, Abscissa::Even { start: 0.0, step: 1.0 },
    ///     Ordinate::Complex(vec![(1.0, 2.0); 7]));
    /// assert_eq!(f.len(), 7);
    /// ```
    pub fn len(&self) -> usize {
        self.ordinate.len()
    }

    /// Whether the function has no points.
    ///
    /// ```
    /// # use msd_uff::{Abscissa, Function58, FunctionType, Ordinate};
    /// let f = Function58::new(FunctionType::General, Abscissa::Uneven(vec![]),
    ///     Ordinate::Real(vec![]));
    /// assert!(f.is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The abscissa value of every point: for even spacing `start + k·step` (k = 0, 1, …,
    /// computed as pyuff and numpy do, so the values agree to the bit), else the stored
    /// values.
    ///
    /// ```
    /// # use msd_uff::{Abscissa, Function58, FunctionType, Ordinate};
    /// let f = Function58::new(FunctionType::General, Abscissa::Even { start: 10.0, step: 0.25 },
    ///     Ordinate::Real(vec![0.0; 3]));
    /// assert_eq!(f.abscissa_values(), [10.0, 10.25, 10.5]);
    /// ```
    pub fn abscissa_values(&self) -> Vec<f64> {
        match &self.abscissa {
            Abscissa::Even { start, step } => {
                (0..self.len()).map(|k| start + k as f64 * step).collect()
            }
            Abscissa::Uneven(x) => x.clone(),
        }
    }
}

/// The abscissa of a [`Function58`].
///
/// ```
/// use msd_uff::Abscissa;
/// let even = Abscissa::Even { start: 0.0, step: 0.5 }; // 0, 0.5, 1, … Hz
/// let uneven = Abscissa::Uneven(vec![1.0, 2.0, 4.0]);   // one value per ordinate value
/// assert_ne!(even, uneven);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Abscissa {
    /// Evenly spaced: value k is `start + k·step` (record 7, fields 4 and 5).
    Even {
        /// The first value (abscissa minimum).
        start: f64,
        /// The spacing (abscissa increment).
        step: f64,
    },
    /// Unevenly spaced: one stored value per point, interleaved with the ordinate in
    /// record 12.
    Uneven(Vec<f64>),
}

/// The ordinate values of a [`Function58`].
///
/// ```
/// use msd_uff::Ordinate;
/// let frf = Ordinate::Complex(vec![(1.0, 0.0), (0.0, -1.0)]); // (re, im)
/// assert_eq!(frf.len(), 2);
/// assert_eq!(Ordinate::Real(vec![]).len(), 0);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Ordinate {
    /// Real values (ordinate data type 2 or 4).
    Real(Vec<f64>),
    /// Complex values as `(re, im)` (ordinate data type 5 or 6).
    Complex(Vec<(f64, f64)>),
}

impl Ordinate {
    /// The number of values.
    ///
    /// ```
    /// assert_eq!(msd_uff::Ordinate::Real(vec![1.0, 2.0]).len(), 2);
    /// ```
    pub fn len(&self) -> usize {
        match self {
            Self::Real(v) => v.len(),
            Self::Complex(v) => v.len(),
        }
    }

    /// Whether there are no values.
    ///
    /// ```
    /// assert!(msd_uff::Ordinate::Complex(vec![]).is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The precision of the data in the file (record 7, field 1).
///
/// Values are `f64` in memory either way. Writing in single precision rounds them to
/// `f32` in binary and to the 13 columns of `E13.5` in ASCII (see [`crate::write::AsciiNumbers`]).
///
/// ```
/// assert_eq!(msd_uff::Precision::default(), msd_uff::Precision::Double);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub enum Precision {
    /// 4-byte floats; ordinate data type 2 (real) or 5 (complex).
    Single,
    /// 8-byte floats; ordinate data type 4 (real) or 6 (complex).
    #[default]
    Double,
}

/// How a dataset 58 stores its data.
///
/// ```
/// use msd_uff::{ByteOrder, Encoding};
/// assert_eq!(Encoding::default(), Encoding::Ascii);
/// let binary = Encoding::Binary(ByteOrder::Little); // dataset 58b, as pyuff writes it
/// assert_ne!(binary, Encoding::Binary(ByteOrder::Big));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub enum Encoding {
    /// Dataset 58: numbers as text in fixed columns.
    #[default]
    Ascii,
    /// Dataset 58b: IEEE 754 numbers in this byte order.
    Binary(ByteOrder),
}

/// Byte order of binary data (field 3 of the 58b line).
///
/// ```
/// assert_ne!(msd_uff::ByteOrder::Little, msd_uff::ByteOrder::Big);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ByteOrder {
    /// Code 1: little endian (x86, ARM).
    Little,
    /// Code 2: big endian.
    Big,
}

/// The data characteristics of one axis (records 8–11).
///
/// ```
/// let frequency = msd_uff::Axis {
///     data_type: 18, // frequency
///     label: "Frequency".into(),
///     units: "Hz".into(),
///     ..Default::default()
/// };
/// assert_eq!(frequency.length_exponent, 0);
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Axis {
    /// Specific data type: 0 unknown, 1 general, 2 stress, 3 strain, 5 temperature,
    /// 6 heat flux, 8 displacement, 9 reaction force, 11 velocity, 12 acceleration,
    /// 13 excitation force, 15 pressure, 16 mass, 17 time, 18 frequency, 19 rpm, 20 order.
    pub data_type: i32,
    /// Length units exponent (relevant for data type 1, general).
    pub length_exponent: i32,
    /// Force units exponent.
    pub force_exponent: i32,
    /// Temperature units exponent.
    pub temperature_exponent: i32,
    /// Axis label (up to 20 characters, `"NONE"` if unused).
    pub label: String,
    /// Axis units label (up to 20 characters, `"NONE"` if unused).
    pub units: String,
}

impl Default for Axis {
    /// Data type 0 (unknown), exponents 0, labels `"NONE"`.
    fn default() -> Self {
        Self {
            data_type: 0,
            length_exponent: 0,
            force_exponent: 0,
            temperature_exponent: 0,
            label: "NONE".into(),
            units: "NONE".into(),
        }
    }
}

/// The file header: dataset 151.
///
/// ```
/// let header = msd_uff::Header151 { model_name: "beam".into(), ..Default::default() };
/// assert_eq!(header.file_type, 0); // universal
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize)]
pub struct Header151 {
    /// Record 1: model file name.
    pub model_name: String,
    /// Record 2: model file description.
    pub description: String,
    /// Record 3: program which created the database.
    pub db_program: String,
    /// Record 4, field 1: date the database was created (DD-MMM-YY).
    pub db_created_date: String,
    /// Record 4, field 2: time the database was created (HH:MM:SS).
    pub db_created_time: String,
    /// Record 4, field 3: version from the database.
    pub db_version1: i64,
    /// Record 4, field 4: version from the database.
    pub db_version2: i64,
    /// Record 4, field 5: file type: 0 universal, 1 archive, 2 other.
    pub file_type: i64,
    /// Record 5, field 1: date the database was last saved.
    pub db_saved_date: String,
    /// Record 5, field 2: time the database was last saved.
    pub db_saved_time: String,
    /// Record 6: program which created the universal file.
    pub program: String,
    /// Record 7, field 1: date the universal file was written.
    pub written_date: String,
    /// Record 7, field 2: time the universal file was written.
    pub written_time: String,
}

/// The units: dataset 164.
///
/// To convert a value from the file's units to SI, divide it by the factor.
///
/// ```
/// let mm = msd_uff::Units164 { code: 5, description: "MM".into(), length: 1000.0,
///     force: 1000.0, ..Default::default() };
/// assert_eq!(2500.0 / mm.length, 2.5); // 2500 mm is 2.5 m
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Units164 {
    /// Units code: 1 SI (meter, newton), 2 BG (foot, pound f), 3 MG (meter, kilogram f),
    /// 4 BA (foot, poundal), 5 MM (mm, milli newton), 6 CM (cm, centi newton),
    /// 7 IN (inch, pound f), 8 GM (mm, kilogram f), 9 US (user defined).
    pub code: i32,
    /// Units description (up to 20 characters, for documentation only).
    pub description: String,
    /// Temperature mode: 1 absolute, 2 relative.
    pub temperature_mode: i32,
    /// Length factor.
    pub length: f64,
    /// Force factor.
    pub force: f64,
    /// Temperature factor.
    pub temperature: f64,
    /// Temperature offset.
    pub temperature_offset: f64,
}

impl Default for Units164 {
    /// SI: code 1, description `"SI"`, absolute temperature, all factors 1, offset 0.
    fn default() -> Self {
        Self {
            code: 1,
            description: "SI".into(),
            temperature_mode: 1,
            length: 1.0,
            force: 1.0,
            temperature: 1.0,
            temperature_offset: 0.0,
        }
    }
}

/// A dataset passed over while reading: one this crate does not read, or a second 151 or
/// 164 (the first is kept).
///
/// ```
/// let text = b"    -1\n    82\n         1         2         0\nNONE\n         1         2\n    -1\n";
/// let file = msd_uff::parse(text)?;
/// assert_eq!(file.skipped[0].number, 82);
/// assert_eq!((file.skipped[0].offset, file.skipped[0].line), (0, 1));
/// # Ok::<(), msd_uff::UffError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Skipped {
    /// The dataset number.
    pub number: u32,
    /// Byte offset of the `    -1` line that opens it.
    pub offset: usize,
    /// Line number (1-based) of that line.
    pub line: usize,
    /// Whether it was a binary dataset (a `b` after its number).
    pub binary: bool,
    /// Why it was skipped.
    pub note: String,
}

/// Bytes between the end of binary data and the `    -1` that closes the dataset.
///
/// The 58b description wants the `    -1` right after the data, but some acquisition
/// systems write a line end or padding first; the reader passes over them and notes them
/// here.
///
/// ```
/// let t = msd_uff::TrailingBytes { function: 0, offset: 1000, len: 2 };
/// assert_eq!(t.offset + t.len, 1002); // where the closing line starts
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct TrailingBytes {
    /// Index in [`UffFile::functions`] of the function they follow.
    pub function: usize,
    /// Byte offset of the first of them.
    pub offset: usize,
    /// How many.
    pub len: usize,
}
