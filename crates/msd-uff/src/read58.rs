//! Reading dataset 58 (ASCII) and 58b (binary): records 1–11, then the data of record 12.

use crate::framing::{BinaryId, IdLine, missing_close, record};
use crate::text::{FieldReader, Line, Lines, columns, data_numbers, numeric_fields};
use crate::{
    error::{Position, UffError},
    function_type::FunctionType,
    types::{Abscissa, Axis, ByteOrder, Encoding, Function58, Ordinate, Precision},
};

/// How record 12 is laid out: the eight cases of the SDRC description.
#[derive(Clone, Copy)]
pub(crate) struct Layout {
    pub complex: bool,
    pub even: bool,
    pub precision: Precision,
}

impl Layout {
    /// Numbers per point: the abscissa (if uneven), then one or two ordinate parts.
    pub fn per_point(self) -> usize {
        usize::from(!self.even) + if self.complex { 2 } else { 1 }
    }

    /// The field widths of one ASCII line (cases 1–8 of record 12).
    pub fn widths(self) -> &'static [usize] {
        match (self.precision, self.even, self.complex) {
            (Precision::Single, _, _) => &[13; 6],
            (Precision::Double, true, _) => &[20; 4],
            (Precision::Double, false, false) => &[13, 20, 13, 20],
            (Precision::Double, false, true) => &[13, 20, 20],
        }
    }

    /// Record 7, field 1.
    pub fn ordinate_data_type(self) -> i64 {
        match (self.complex, self.precision) {
            (false, Precision::Single) => 2,
            (false, Precision::Double) => 4,
            (true, Precision::Single) => 5,
            (true, Precision::Double) => 6,
        }
    }

    fn describe(self) -> &'static str {
        match (self.even, self.complex) {
            (true, false) => "one real value per point",
            (true, true) => "re, im per point",
            (false, false) => "x, value per point",
            (false, true) => "x, re, im per point",
        }
    }
}

const DATASET: Option<u32> = Some(58);

/// Reads one dataset 58 or 58b after its id line, through its closing `    -1`. Also
/// returns, for binary data, the bytes passed over before the closing line.
pub(crate) fn read58(
    lines: &mut Lines<'_>,
    id: &IdLine,
) -> Result<(Function58, Option<(usize, usize)>), UffError> {
    let mut ids: [String; 5] = Default::default();
    let names = [
        "record 1 (ID line 1)",
        "record 2 (ID line 2)",
        "record 3 (ID line 3)",
        "record 4 (ID line 4)",
        "record 5 (ID line 5)",
    ];
    for (id_text, name) in ids.iter_mut().zip(names) {
        *id_text = record(lines, 58, name)?.text.trim_end().to_string();
    }
    let mut f = Function58::new(
        FunctionType::General,
        Abscissa::Uneven(Vec::new()),
        Ordinate::Real(Vec::new()),
    );
    f.ids = ids;
    dof_identification(&record(lines, 58, "record 6 (DOF identification)")?, &mut f)?;
    let r7 = record(lines, 58, "record 7 (data form)")?;
    let (layout, num_pts) = data_form(&r7, &mut f)?;
    f.abscissa_axis = axis(&record(
        lines,
        58,
        "record 8 (abscissa data characteristics)",
    )?)?;
    f.ordinate_axis = axis(&record(
        lines,
        58,
        "record 9 (ordinate data characteristics)",
    )?)?;
    f.denominator_axis = axis(&record(
        lines,
        58,
        "record 10 (ordinate denominator data characteristics)",
    )?)?;
    f.z_axis = axis(&record(
        lines,
        58,
        "record 11 (z-axis data characteristics)",
    )?)?;
    let expected = num_pts.checked_mul(layout.per_point()).ok_or_else(|| {
        FieldReader {
            line: &r7,
            dataset: DATASET,
        }
        .malformed(
            10,
            "record 7, number of points",
            &num_pts.to_string(),
            "a count that fits in memory",
        )
    })?;
    let (values, trailing) = match &id.binary {
        Some(binary) => {
            let data = read_binary(lines, binary, layout, expected)?;
            f.encoding = Encoding::Binary(data.byte_order);
            (data.values, Some(data.trailing))
        }
        None => (read_ascii(lines, layout, expected)?, None),
    };
    assemble(&values, layout, &mut f);
    Ok((f, trailing))
}

/// Record 6, Format(2(I5,I10),2(1X,10A1,I10,I4)).
fn dof_identification(line: &Line<'_>, f: &mut Function58) -> Result<(), UffError> {
    let c = columns(line, &[5, 10, 5, 10, 11, 10, 4, 11, 10, 4], false);
    let r = FieldReader {
        line,
        dataset: DATASET,
    };
    f.function_type = FunctionType::from_code(r.int(c[0], "record 6, function type")?);
    f.function_id = r.int(c[1], "record 6, function identification number")?;
    f.version = r.int(c[2], "record 6, version number")?;
    f.load_case = r.int(c[3], "record 6, load case identification number")?;
    f.response_entity = c[4].1.into();
    f.response_node = r.int(c[5], "record 6, response node")?;
    f.response_direction = r.int(c[6], "record 6, response direction")?;
    f.reference_entity = c[7].1.into();
    f.reference_node = r.int(c[8], "record 6, reference node")?;
    f.reference_direction = r.int(c[9], "record 6, reference direction")?;
    Ok(())
}

/// Record 7, Format(3I10,3E13.5): the layout and the number of points; an even abscissa
/// and the z value go into `f`.
fn data_form(line: &Line<'_>, f: &mut Function58) -> Result<(Layout, usize), UffError> {
    let c = numeric_fields(line, &[10, 10, 10, 13, 13, 13]);
    let r = FieldReader {
        line,
        dataset: DATASET,
    };
    let ordinate_type: i64 = r.int(c[0], "record 7, ordinate data type")?;
    let (complex, precision) = match ordinate_type {
        2 => (false, Precision::Single),
        4 => (false, Precision::Double),
        5 => (true, Precision::Single),
        6 => (true, Precision::Double),
        _ => {
            return Err(r.malformed(
                c[0].0,
                "record 7, ordinate data type",
                c[0].1,
                "2, 4, 5 or 6 (real or complex, single or double precision)",
            ));
        }
    };
    let num_pts: usize = r.int(c[1], "record 7, number of points").map_err(|_| {
        r.malformed(
            c[1].0,
            "record 7, number of points",
            c[1].1,
            "a count (an integer >= 0)",
        )
    })?;
    let spacing: i64 = r.int(c[2], "record 7, abscissa spacing")?;
    let even = match spacing {
        0 => false,
        1 => true,
        _ => {
            return Err(r.malformed(
                c[2].0,
                "record 7, abscissa spacing",
                c[2].1,
                "0 (uneven) or 1 (even)",
            ));
        }
    };
    let start = r.real(c[3], "record 7, abscissa minimum")?;
    let step = r.real(c[4], "record 7, abscissa increment")?;
    f.z_axis_value = r.real(c[5], "record 7, z-axis value")?;
    f.precision = precision;
    if even {
        f.abscissa = Abscissa::Even { start, step };
    }
    let layout = Layout {
        complex,
        even,
        precision,
    };
    Ok((layout, num_pts))
}

/// Records 8–11, Format(I10,3I5,2(1X,20A1)).
fn axis(line: &Line<'_>) -> Result<Axis, UffError> {
    let c = columns(line, &[10, 5, 5, 5, 21, 21], false);
    let r = FieldReader {
        line,
        dataset: DATASET,
    };
    Ok(Axis {
        data_type: r.int(c[0], "records 8-11, specific data type")?,
        length_exponent: r.int(c[1], "records 8-11, length units exponent")?,
        force_exponent: r.int(c[2], "records 8-11, force units exponent")?,
        temperature_exponent: r.int(c[3], "records 8-11, temperature units exponent")?,
        label: c[4].1.into(),
        units: c[5].1.into(),
    })
}

/// Record 12 in ASCII: numbers up to the closing `    -1`, exactly `expected` of them.
fn read_ascii(
    lines: &mut Lines<'_>,
    layout: Layout,
    expected: usize,
) -> Result<Vec<f64>, UffError> {
    let mut values = Vec::with_capacity(expected.min(1 << 16));
    let count = |n: usize| format!("{n} values");
    let wanted = || format!("{expected} values ({})", layout.describe());
    loop {
        if lines.numbers_line(&mut values, expected) {
            continue;
        }
        let Some(line) = lines.next_line() else {
            return Err(UffError::Truncated {
                at: lines.here(DATASET, true),
                field: "record 12 (data values)",
                found: format!("the end of the file after {}", count(values.len())),
                expected: format!("{} and the closing \"    -1\"", wanted()),
            });
        };
        if line.is_delimiter() {
            if values.len() != expected {
                return Err(UffError::Malformed {
                    at: line.at(DATASET, 0),
                    field: "record 12 (data values)",
                    found: count(values.len()),
                    expected: wanted(),
                });
            }
            return Ok(values);
        }
        data_numbers(&line, layout.widths(), &mut values).map_err(|(col, text)| {
            FieldReader {
                line: &line,
                dataset: DATASET,
            }
            .malformed(col, "record 12, data value", &text, "a number")
        })?;
        if values.len() > expected {
            return Err(UffError::Malformed {
                at: line.at(DATASET, 0),
                field: "record 12 (data values)",
                found: format!("more than {expected} values by this line"),
                expected: wanted(),
            });
        }
    }
}

/// Record 12 of a 58b dataset.
struct BinaryData {
    values: Vec<f64>,
    byte_order: ByteOrder,
    /// Offset and length of the bytes between the data and the closing line.
    trailing: (usize, usize),
}

/// Record 12 in binary: `expected` numbers right after record 11, then the closing line.
fn read_binary(
    lines: &mut Lines<'_>,
    id: &BinaryId,
    layout: Layout,
    expected: usize,
) -> Result<BinaryData, UffError> {
    let field_at = |column: usize| Position {
        dataset: DATASET,
        offset: id.offset + column,
        line: Some(id.line),
    };
    let bad = |column, field, found: i64, expected: &str| UffError::Malformed {
        at: field_at(column),
        field,
        found: found.to_string(),
        expected: expected.into(),
    };
    let byte_order = match id.byte_order {
        1 => ByteOrder::Little,
        2 => ByteOrder::Big,
        b => {
            return Err(bad(
                7,
                "binary id line, byte ordering",
                b,
                "1 (little endian) or 2 (big endian)",
            ));
        }
    };
    if id.float_format != 2 {
        return Err(bad(
            13,
            "binary id line, floating-point format",
            id.float_format,
            "2 (IEEE 754); 1 (DEC VMS) and 3 (IBM 5/370) are not read",
        ));
    }
    if id.ascii_lines != 11 {
        return Err(bad(
            19,
            "binary id line, number of ASCII lines",
            id.ascii_lines,
            "11, as for every dataset 58b",
        ));
    }
    let size = match layout.precision {
        Precision::Single => 4,
        Precision::Double => 8,
    };
    let start = lines.pos;
    let available = lines.bytes.len() - start;
    let needed = expected
        .checked_mul(size)
        .filter(|&n| n <= available)
        .ok_or_else(|| UffError::Truncated {
            at: Position {
                dataset: DATASET,
                offset: start,
                line: None,
            },
            field: "record 12 (binary data)",
            found: format!("{available} bytes before the end of the file"),
            expected: format!(
                "{} bytes: {expected} values ({}) of {size} bytes",
                expected.saturating_mul(size),
                layout.describe()
            ),
        })?;
    let data = &lines.bytes[start..start + needed];
    let values = match (layout.precision, byte_order) {
        (Precision::Single, ByteOrder::Little) => data
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64)
            .collect(),
        (Precision::Single, ByteOrder::Big) => data
            .chunks_exact(4)
            .map(|b| f32::from_be_bytes([b[0], b[1], b[2], b[3]]) as f64)
            .collect(),
        (Precision::Double, ByteOrder::Little) => data
            .chunks_exact(8)
            .map(|b| f64::from_le_bytes(eight(b)))
            .collect(),
        (Precision::Double, ByteOrder::Big) => data
            .chunks_exact(8)
            .map(|b| f64::from_be_bytes(eight(b)))
            .collect(),
    };
    lines.skip_to(start + needed);
    let trailing = lines
        .close_binary()
        .ok_or_else(|| missing_close(lines, 58))?;
    Ok(BinaryData {
        values,
        byte_order,
        trailing,
    })
}

fn eight(b: &[u8]) -> [u8; 8] {
    [b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]
}

/// Splits the numbers of record 12 into the uneven abscissa (if it is) and the ordinate.
fn assemble(values: &[f64], layout: Layout, f: &mut Function58) {
    let points = values.chunks_exact(layout.per_point());
    if !layout.even {
        f.abscissa = Abscissa::Uneven(points.clone().map(|p| p[0]).collect());
    }
    let first = usize::from(!layout.even);
    f.ordinate = if layout.complex {
        Ordinate::Complex(points.map(|p| (p[first], p[first + 1])).collect())
    } else {
        Ordinate::Real(points.map(|p| p[first]).collect())
    };
}
