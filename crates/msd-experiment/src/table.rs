//! CSV tables written in Rust's shortest round-trip form (so the files are exact and
//! deterministic): one type for every CSV file a run writes.

use std::fmt::Write;

/// A CSV table: the header and columns of equal length (`None` cells are left empty).
pub(crate) struct Table {
    header: Vec<String>,
    columns: Vec<Vec<Option<f64>>>,
}

impl Table {
    pub(crate) fn new() -> Self {
        Self {
            header: Vec::new(),
            columns: Vec::new(),
        }
    }

    pub(crate) fn column(&mut self, name: impl Into<String>, values: &[f64]) {
        self.header.push(name.into());
        self.columns
            .push(values.iter().copied().map(Some).collect());
    }

    pub(crate) fn sparse(&mut self, name: impl Into<String>, values: Vec<Option<f64>>) {
        self.header.push(name.into());
        self.columns.push(values);
    }

    pub(crate) fn render(&self) -> String {
        let rows = self.columns.iter().map(Vec::len).max().unwrap_or(0);
        let mut s = String::with_capacity(rows * 16 * self.columns.len().max(1));
        s.push_str(&self.header.join(","));
        s.push('\n');
        for r in 0..rows {
            for (c, column) in self.columns.iter().enumerate() {
                if c > 0 {
                    s.push(',');
                }
                if let Some(Some(v)) = column.get(r) {
                    let _ = write!(s, "{v}");
                }
            }
            s.push('\n');
        }
        s
    }
}
