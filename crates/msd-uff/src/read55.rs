//! Reading dataset 55 (data at nodes) and the nodes of datasets 15 and 2411.

use crate::framing::record;
use crate::text::{FieldReader, Line, Lines, data_numbers, integer_fields, numeric_fields, words};
use crate::{
    error::UffError,
    nodes::{Analysis55, Data55, Node},
    types::Precision,
};

const DATASET: Option<u32> = Some(55);

/// The numbers of one record of dataset 55 that may take several lines (records 8 and 10):
/// what [`take_reals`] reads, and how its errors name them.
struct Wanted {
    /// The record (e.g. `record 8 (real parameters)`).
    record: &'static str,
    /// One number of it (e.g. `record 8, real parameter`).
    value: &'static str,
    /// How many numbers.
    count: usize,
    /// What they are, after "N numbers" (e.g. `for node 3: 3 real values`).
    what: String,
}

/// Reads one dataset 55 after its id line, through its closing `    -1`.
pub(crate) fn read55(lines: &mut Lines<'_>) -> Result<Data55, UffError> {
    let mut d = Data55::default();
    let names = [
        "record 1 (ID line 1)",
        "record 2 (ID line 2)",
        "record 3 (ID line 3)",
        "record 4 (ID line 4)",
        "record 5 (ID line 5)",
    ];
    for (id_text, name) in d.ids.iter_mut().zip(names) {
        *id_text = record(lines, 55, name)?.text.trim_end().to_string();
    }
    let r6 = record(lines, 55, "record 6 (data definition parameters)")?;
    let c = numeric_fields(&r6, &[10; 6]);
    let r = reader(&r6);
    d.model_type = r.int(c[0], "record 6, model type")?;
    let analysis_type = r.int(c[1], "record 6, analysis type")?;
    d.data_characteristic = r.int(c[2], "record 6, data characteristic")?;
    d.specific_data_type = r.int(c[3], "record 6, specific data type")?;
    d.complex = match r.int::<i64>(c[4], "record 6, data type")? {
        2 => false,
        5 => true,
        _ => {
            return Err(r.malformed(
                c[4].0,
                "record 6, data type",
                c[4].1,
                "2 (real) or 5 (complex)",
            ));
        }
    };
    d.values_per_node = r
        .int(c[5], "record 6, number of data values per node")
        .map_err(|_| {
            r.malformed(
                c[5].0,
                "record 6, number of data values per node",
                c[5].1,
                "a count (an integer >= 0)",
            )
        })?;
    let (integers, n_reals) = record7(lines)?;
    let reals = take_reals(
        lines,
        &Wanted {
            record: "record 8 (real parameters)",
            value: "record 8, real parameter",
            count: n_reals,
            what: "as record 7 says".into(),
        },
    )?;
    d.analysis = Analysis55::from_parameters(analysis_type, integers, reals);
    let per_node = d
        .values_per_node
        .checked_mul(if d.complex { 2 } else { 1 })
        .ok_or_else(|| {
            r.malformed(
                c[5].0,
                "record 6, number of data values per node",
                c[5].1,
                "a count that fits in memory",
            )
        })?;
    let kind = if d.complex {
        "complex values, each re then im"
    } else {
        "real values"
    };
    loop {
        let line = match lines.next_line() {
            None => {
                return Err(UffError::Truncated {
                    at: lines.here(DATASET, true),
                    field: "record 9 (node number)",
                    found: "the end of the file".into(),
                    expected: "a node number, or \"    -1\", the line that closes a dataset".into(),
                });
            }
            Some(line) if line.is_delimiter() => break,
            Some(line) if line.text.trim().is_empty() => continue,
            Some(line) => line,
        };
        let node = node_number(&line)?;
        let numbers = take_reals(
            lines,
            &Wanted {
                record: "record 10 (data at a node)",
                value: "record 10, data value",
                count: per_node,
                what: format!("for node {node}: {} {kind}", d.values_per_node),
            },
        )?;
        d.values.push(if d.complex {
            numbers.chunks_exact(2).map(|p| (p[0], p[1])).collect()
        } else {
            numbers.iter().map(|&v| (v, 0.0)).collect()
        });
        d.nodes.push(node);
    }
    Ok(d)
}

fn reader<'l, 'a>(line: &'l Line<'a>) -> FieldReader<'l, 'a> {
    FieldReader {
        line,
        dataset: DATASET,
    }
}

/// Record 7, Format(8I10): the number of integer parameters, the number of real ones, then
/// the integers (on a second line when there are more than 6).
fn record7(lines: &mut Lines<'_>) -> Result<(Vec<i64>, usize), UffError> {
    const RECORD: &str = "record 7 (integer parameters)";
    const VALUE: &str = "record 7, integer parameter";
    let first = record(lines, 55, RECORD)?;
    let r = reader(&first);
    let fields = integer_fields(&first, 10)
        .map_err(|(col, text)| r.malformed(col, VALUE, &text, "an integer"))?;
    let [n_int, n_real, ..] = fields[..] else {
        return Err(r.malformed(
            0,
            RECORD,
            first.text.trim(),
            "the number of integer parameters, the number of real ones, then the integers \
             (Format 8I10)",
        ));
    };
    let n_int: usize = r
        .int(n_int, "record 7, number of integer parameters")
        .ok()
        .filter(|n| *n <= 10)
        .ok_or_else(|| {
            r.malformed(
                n_int.0,
                "record 7, number of integer parameters",
                n_int.1,
                "0 to 10",
            )
        })?;
    let n_real: usize = r
        .int(n_real, "record 7, number of real parameters")
        .ok()
        .filter(|n| *n <= 12)
        .ok_or_else(|| {
            r.malformed(
                n_real.0,
                "record 7, number of real parameters",
                n_real.1,
                "0 to 12",
            )
        })?;
    let mut integers = Vec::with_capacity(n_int);
    for &field in &fields[2..] {
        integers.push(r.int(field, VALUE)?);
    }
    let mut at = first.at(DATASET, 0);
    while integers.len() < n_int {
        let line = record(lines, 55, RECORD)?;
        at = line.at(DATASET, 0);
        let r = reader(&line);
        for field in integer_fields(&line, 10)
            .map_err(|(col, text)| r.malformed(col, VALUE, &text, "an integer"))?
        {
            integers.push(r.int(field, VALUE)?);
        }
    }
    if integers.len() > n_int {
        return Err(UffError::Malformed {
            at,
            field: RECORD,
            found: format!("{} integer parameters by this line", integers.len()),
            expected: format!("{n_int}, as field 1 says"),
        });
    }
    Ok((integers, n_real))
}

/// Reads the next lines until they have given `want.count` numbers (Format 6E13.5).
fn take_reals(lines: &mut Lines<'_>, want: &Wanted) -> Result<Vec<f64>, UffError> {
    let mut out = Vec::new();
    let expected = || format!("{} numbers {}", want.count, want.what);
    while out.len() < want.count {
        let line = match lines.next_line() {
            Some(line) if !line.is_delimiter() => line,
            Some(line) => {
                return Err(UffError::Malformed {
                    at: line.at(DATASET, 0),
                    field: want.record,
                    found: format!("the closing \"    -1\" after {} numbers", out.len()),
                    expected: expected(),
                });
            }
            None => {
                return Err(UffError::Truncated {
                    at: lines.here(DATASET, true),
                    field: want.record,
                    found: format!("the end of the file after {} numbers", out.len()),
                    expected: format!("{} and the closing \"    -1\"", expected()),
                });
            }
        };
        data_numbers(&line, &[13; 6], &mut out)
            .map_err(|(col, text)| reader(&line).malformed(col, want.value, &text, "a number"))?;
        if out.len() > want.count {
            return Err(UffError::Malformed {
                at: line.at(DATASET, 0),
                field: want.record,
                found: format!("{} numbers by this line", out.len()),
                expected: expected(),
            });
        }
    }
    Ok(out)
}

/// Record 9, Format(I10): a node number alone on its line.
fn node_number(line: &Line<'_>) -> Result<i64, UffError> {
    const FIELD: &str = "record 9, node number";
    let r = reader(line);
    match words(line)[..] {
        [(col, text)] => text
            .parse()
            .map_err(|_| r.malformed(col, FIELD, text, "a node number (an integer, Format I10)")),
        [(col, _), ..] => {
            let text: String = line.text.trim().chars().take(40).collect();
            Err(r.malformed(
                col,
                FIELD,
                &text,
                "a node number alone on its line (Format I10), its values on the next lines",
            ))
        }
        [] => Err(r.malformed(0, FIELD, "", "a node number")),
    }
}

/// Dataset 15, Format(4I10,1P3E13.5) per node, through the closing `    -1`.
pub(crate) fn read15(lines: &mut Lines<'_>) -> Result<Vec<Node>, UffError> {
    let mut nodes = Vec::new();
    while let Some(line) = node_line(lines, 15)? {
        let c = numeric_fields(&line, &[10, 10, 10, 10, 13, 13, 13]);
        let r = FieldReader {
            line: &line,
            dataset: Some(15),
        };
        nodes.push(Node {
            label: r.int(c[0], "record 1, node label")?,
            definition_cs: r.int(c[1], "record 1, definition coordinate system number")?,
            displacement_cs: r.int(c[2], "record 1, displacement coordinate system number")?,
            color: r.int(c[3], "record 1, colour")?,
            x: r.real(c[4], "record 1, x coordinate")?,
            y: r.real(c[5], "record 1, y coordinate")?,
            z: r.real(c[6], "record 1, z coordinate")?,
            precision: Precision::Single,
        });
    }
    Ok(nodes)
}

/// Dataset 2411, Format(4I10) then Format(1P3D25.16) per node, through the closing `    -1`.
pub(crate) fn read2411(lines: &mut Lines<'_>) -> Result<Vec<Node>, UffError> {
    let mut nodes = Vec::new();
    while let Some(first) = node_line(lines, 2411)? {
        let c = numeric_fields(&first, &[10; 4]);
        let r = FieldReader {
            line: &first,
            dataset: Some(2411),
        };
        let (label, definition_cs, displacement_cs, color) = (
            r.int(c[0], "record 1, node label")?,
            r.int(c[1], "record 1, export coordinate system number")?,
            r.int(c[2], "record 1, displacement coordinate system number")?,
            r.int(c[3], "record 1, colour")?,
        );
        let second = record(lines, 2411, "record 2 (node coordinates)")?;
        let c = numeric_fields(&second, &[25; 3]);
        let r = FieldReader {
            line: &second,
            dataset: Some(2411),
        };
        nodes.push(Node {
            label,
            definition_cs,
            displacement_cs,
            color,
            x: r.real(c[0], "record 2, x coordinate")?,
            y: r.real(c[1], "record 2, y coordinate")?,
            z: r.real(c[2], "record 2, z coordinate")?,
            precision: Precision::Double,
        });
    }
    Ok(nodes)
}

/// The next non-blank line of a node dataset, `None` at its closing `    -1`.
fn node_line<'a>(lines: &mut Lines<'a>, number: u32) -> Result<Option<Line<'a>>, UffError> {
    loop {
        match lines.next_line() {
            Some(line) if line.is_delimiter() => return Ok(None),
            Some(line) if line.text.trim().is_empty() => {}
            Some(line) => return Ok(Some(line)),
            None => {
                return Err(UffError::Truncated {
                    at: lines.here(Some(number), true),
                    field: "record 1 (node)",
                    found: "the end of the file".into(),
                    expected: "a node, or \"    -1\", the line that closes a dataset".into(),
                });
            }
        }
    }
}
