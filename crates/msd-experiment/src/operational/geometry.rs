//! A structure's geometry for drawing its mode shapes: nodes with coordinates and the
//! lines between them, read from whitespace-separated text files as pyOMA ships them
//! (`grid.txt`: node, x, y, z; `lines.txt`: node, node; an optional header line).

use super::read::text;
use crate::config::{GeometrySection, OperationalSection};
use crate::error::{ExperimentError, Result};
use crate::sources::Sources;
use std::path::Path;

/// Nodes and lines.
#[derive(Debug, Clone, PartialEq)]
pub struct Geometry {
    /// Each node's number and coordinates (x, y, z; z up).
    pub nodes: Vec<(u32, [f64; 3])>,
    /// Lines between two nodes.
    pub lines: Vec<(u32, u32)>,
}

impl Geometry {
    /// A node's coordinates.
    pub fn node(&self, node: u32) -> Option<[f64; 3]> {
        self.nodes.iter().find(|(n, _)| *n == node).map(|(_, p)| *p)
    }

    /// The largest extent of the nodes along x, y or z.
    pub fn size(&self) -> f64 {
        (0..3)
            .map(|a| {
                let (lo, hi) = self
                    .nodes
                    .iter()
                    .fold((f64::MAX, f64::MIN), |(lo, hi), (_, p)| {
                        (lo.min(p[a]), hi.max(p[a]))
                    });
                hi - lo
            })
            .fold(0.0, f64::max)
    }
}

/// The geometry `[operational.geometry]` names, read; `None` where it names none.
pub(crate) fn of(section: &OperationalSection, sources: &Sources) -> Result<Option<Geometry>> {
    section
        .geometry
        .as_ref()
        .map(|g| read(g, sources))
        .transpose()
}

/// Reads the section's files; errors name the file, the line and what was expected.
fn read(section: &GeometrySection, sources: &Sources) -> Result<Geometry> {
    let nodes_path = sources.path(&section.nodes);
    let nodes: Vec<(u32, [f64; 3])> = rows(
        &text(sources, &section.nodes, "operational.geometry.nodes")?,
        &nodes_path,
        4,
        "a node number and its x, y, z",
    )?
    .into_iter()
    .map(|v| (v[0] as u32, [v[1], v[2], v[3]]))
    .collect();
    let mut lines = Vec::new();
    if let Some(path) = &section.lines {
        let resolved = sources.path(path);
        let numbers = rows(
            &text(sources, path, "operational.geometry.lines")?,
            &resolved,
            2,
            "two node numbers",
        )?;
        for (row, v) in numbers.iter().enumerate() {
            let (a, b) = (v[0] as u32, v[1] as u32);
            if let Some(missing) = [a, b]
                .into_iter()
                .find(|n| !nodes.iter().any(|(m, _)| m == n))
            {
                return Err(ExperimentError::data(
                    &resolved,
                    format!(
                        "line {}: node {missing} is not in {}",
                        row + 1,
                        nodes_path.display()
                    ),
                ));
            }
            lines.push((a, b));
        }
    }
    Ok(Geometry { nodes, lines })
}

/// The numeric rows of a table of `columns` numbers per line (an optional header line
/// first; blank lines passed over); node numbers must be whole and non-negative.
fn rows(text: &str, path: &Path, columns: usize, expected: &str) -> Result<Vec<Vec<f64>>> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let cells: Vec<&str> = line.split_whitespace().collect();
        if cells.is_empty() {
            continue;
        }
        let numbers: Option<Vec<f64>> = cells.iter().map(|c| c.parse().ok()).collect();
        let fail = |what: String| {
            ExperimentError::data(path, format!("line {}: {what}: expected {expected}", i + 1))
        };
        match numbers {
            None if out.is_empty()
                && i == text.lines().position(|l| !l.trim().is_empty()).unwrap_or(0) =>
            {
                continue; // the header
            }
            None => return Err(fail(format!("\"{}\" is not a number", line.trim()))),
            Some(v) if v.len() != columns => {
                return Err(fail(format!("{} values", v.len())));
            }
            Some(v)
                if !(v[0] >= 0.0 && v[0].fract() == 0.0) || v.iter().any(|x| !x.is_finite()) =>
            {
                return Err(fail(format!("\"{}\"", line.trim())));
            }
            Some(v) => out.push(v),
        }
    }
    if out.is_empty() {
        return Err(ExperimentError::data(
            path,
            format!("no rows: expected {expected} per line"),
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_with_a_header_reads_and_bad_lines_are_named() {
        let p = Path::new("grid.txt");
        let v = rows("node x y z\n 1 0 0 0\n\n 2 1.5e1 0 2\n", p, 4, "x").unwrap();
        assert_eq!(v, vec![vec![1.0, 0.0, 0.0, 0.0], vec![2.0, 15.0, 0.0, 2.0]]);
        let err = rows("node x y z\n1 0 0\n", p, 4, "a node and x, y, z").unwrap_err();
        assert!(err.to_string().contains("line 2: 3 values"), "{err}");
        let err = rows("1 0 0 0\nnode x y z\n", p, 4, "x").unwrap_err();
        assert!(err.to_string().contains("line 2"), "{err}");
        let err = rows("1.5 0 0 0\n", p, 4, "x").unwrap_err();
        assert!(err.to_string().contains("line 1"), "{err}");
    }
}
