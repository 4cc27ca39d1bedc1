//! What a file holds, as a table for a terminal.

use crate::Contents;
use std::fmt;

impl fmt::Display for Contents {
    /// The format, then one line per channel (name, unit, samples, rate, range), then
    /// what was skipped.
    ///
    /// ```
    /// use msd_files::{Channel, Contents, FileFormat};
    /// let contents = Contents {
    ///     format: FileFormat::Tdms,
    ///     channels: vec![Channel {
    ///         name: "Force".into(),
    ///         unit: Some("N".into()),
    ///         sample_rate_hz: Some(1000.0),
    ///         values: vec![-1.5, 2.0, 0.5],
    ///     }],
    ///     skipped: vec!["Rig/Comment: reading String values as numbers not implemented".into()],
    /// };
    /// let text = contents.to_string();
    /// assert!(text.starts_with("NI TDMS, 1 channel"), "{text}");
    /// assert!(text.contains("Force") && text.contains("1000 Hz") && text.contains("-1.5 … 2"), "{text}");
    /// assert!(text.contains("skipped: Rig/Comment"), "{text}");
    /// ```
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = self.channels.len();
        writeln!(
            f,
            "{}, {n} channel{}:",
            self.format.name(),
            if n == 1 { "" } else { "s" }
        )?;
        let width = self
            .channels
            .iter()
            .map(|c| c.name.chars().count())
            .max()
            .unwrap_or(4)
            .max(4);
        writeln!(
            f,
            "  {:<width$}  {:<8}  {:>9}  {:>10}  range",
            "name", "unit", "samples", "rate"
        )?;
        for c in &self.channels {
            let (lo, hi) = c
                .values
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(v), hi.max(v))
                });
            let range = if c.values.is_empty() {
                "—".to_string()
            } else {
                format!("{} … {}", short(lo), short(hi))
            };
            writeln!(
                f,
                "  {:<width$}  {:<8}  {:>9}  {:>10}  {range}",
                c.name,
                c.unit.as_deref().unwrap_or("—"),
                c.values.len(),
                c.sample_rate_hz
                    .map_or_else(|| "—".to_string(), |r| format!("{r} Hz")),
            )?;
        }
        for s in &self.skipped {
            writeln!(f, "  skipped: {s}")?;
        }
        Ok(())
    }
}

/// A number in at most six significant digits.
fn short(v: f64) -> String {
    if v == 0.0 || (1e-3..1e5).contains(&v.abs()) {
        let text = format!("{v:.6}");
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.4e}")
    }
}
