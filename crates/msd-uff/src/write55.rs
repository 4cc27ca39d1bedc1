//! Writing the nodes (datasets 15 and 2411) and data at nodes (dataset 55), in the columns
//! pyuff writes and reads them.

use crate::text::format_real;
use crate::write::Out;
use crate::{
    error::UffError,
    nodes::{Data55, Node},
    types::Precision,
    write::{AsciiNumbers, WriteOptions},
};

/// The nodes, each run of consecutive nodes of one precision as one dataset: 15
/// (Format(4I10,1P3E13.5)) for single precision, 2411 (Format(4I10) then
/// Format(1P3D25.16)) for double.
pub(crate) fn write_nodes(
    out: &mut Out,
    nodes: &[Node],
    options: &WriteOptions,
) -> Result<(), UffError> {
    let width = if options.ascii == AsciiNumbers::Exact {
        25
    } else {
        13
    };
    let mut first = 0;
    for run in nodes.chunk_by(|a, b| a.precision == b.precision) {
        let Some(head) = run.first() else { continue };
        let number = match head.precision {
            Precision::Single => 15,
            Precision::Double => 2411,
        };
        out.dataset = number;
        let mut lines = vec!["    -1".to_string(), format!("{number:>6}")];
        for (k, node) in run.iter().enumerate() {
            out.index = first + k;
            let ints = format!(
                "{}{}{}{}",
                out.int("label", node.label, 10)?,
                out.int("definition_cs", node.definition_cs, 10)?,
                out.int("displacement_cs", node.displacement_cs, 10)?,
                out.int("color", node.color, 10)?,
            );
            let xyz = [node.x, node.y, node.z];
            match node.precision {
                Precision::Single => {
                    let coordinates: String =
                        xyz.iter().map(|&v| format_real(v, width, 'E')).collect();
                    lines.push(ints + &coordinates);
                }
                Precision::Double => {
                    lines.push(ints);
                    lines.push(xyz.iter().map(|&v| format_real(v, 25, 'D')).collect());
                }
            }
        }
        lines.push("    -1".to_string());
        lines.iter().for_each(|l| out.line(l));
        first += run.len();
    }
    Ok(())
}

/// One dataset 55: records 1–8, then per node its number (I10) and its values (6E13.5, six
/// numbers a line, so one line for 3 complex or up to 6 real values, as pyuff writes them).
pub(crate) fn write55(out: &mut Out, d: &Data55, options: &WriteOptions) -> Result<(), UffError> {
    let width = if options.ascii == AsciiNumbers::Exact {
        25
    } else {
        13
    };
    let real = |v: f64| format_real(v, width, 'E');
    let (integers, reals) = (d.analysis.integers(), d.analysis.reals());
    if integers.len() > 10 {
        return Err(out.refuse(
            "analysis",
            format!("{} integer parameters", integers.len()),
            "at most 10 (record 7)",
        ));
    }
    if reals.len() > 12 {
        return Err(out.refuse(
            "analysis",
            format!("{} real parameters", reals.len()),
            "at most 12 (record 8)",
        ));
    }
    if d.values.len() != d.nodes.len() {
        return Err(out.refuse(
            "values",
            format!("{} lists of values", d.values.len()),
            format!("one per node ({} nodes)", d.nodes.len()),
        ));
    }
    let mut lines = vec!["    -1".to_string(), format!("{:>6}", 55)];
    let id_fields = ["ids[0]", "ids[1]", "ids[2]", "ids[3]", "ids[4]"];
    for (id, field) in d.ids.iter().zip(id_fields) {
        lines.push(out.text_line(field, id)?);
    }
    let ndv = i64::try_from(d.values_per_node).unwrap_or(i64::MAX);
    lines.push(format!(
        "{}{}{}{}{:>10}{}",
        out.int("model_type", d.model_type, 10)?,
        out.int("analysis", d.analysis.code(), 10)?,
        out.int("data_characteristic", d.data_characteristic, 10)?,
        out.int("specific_data_type", d.specific_data_type, 10)?,
        if d.complex { 5 } else { 2 },
        out.int("values_per_node", ndv, 10)?,
    ));
    let mut record7 = vec![integers.len() as i64, reals.len() as i64];
    record7.extend(&integers);
    for chunk in record7.chunks(8) {
        let mut line = String::new();
        for &v in chunk {
            line += &out.int("analysis", v, 10)?;
        }
        lines.push(line);
    }
    for chunk in reals.chunks(6) {
        lines.push(chunk.iter().map(|&v| real(v)).collect());
    }
    for (&node, values) in d.nodes.iter().zip(&d.values) {
        if node == -1 {
            return Err(out.refuse(
                "nodes",
                "-1".into(),
                "a node number other than -1: a line ending in \"    -1\" closes a dataset \
                 for readers that look for it (pyuff among them)",
            ));
        }
        if values.len() != d.values_per_node {
            return Err(out.refuse(
                "values",
                format!("{} values at node {node}", values.len()),
                format!("values_per_node = {}", d.values_per_node),
            ));
        }
        if let Some(&(re, im)) = values.iter().find(|v| !d.complex && v.1 != 0.0) {
            return Err(out.refuse(
                "values",
                format!("({re}, {im}) at node {node}"),
                "imaginary parts 0 in a real dataset (complex = false)",
            ));
        }
        lines.push(out.int("nodes", node, 10)?);
        let numbers: Vec<f64> = if d.complex {
            values.iter().flat_map(|&(re, im)| [re, im]).collect()
        } else {
            values.iter().map(|v| v.0).collect()
        };
        for chunk in numbers.chunks(6) {
            lines.push(chunk.iter().map(|&v| real(v)).collect());
        }
    }
    lines.push("    -1".to_string());
    lines.iter().for_each(|l| out.line(l));
    Ok(())
}
