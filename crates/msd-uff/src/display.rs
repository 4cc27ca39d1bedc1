//! `Display` for [`UffFile`], [`Function58`] and [`Data55`]: one line per dataset 55 and
//! per function, then the notes.

use std::fmt;

use crate::{
    nodes::{Analysis55, Data55},
    types::{Abscissa, ByteOrder, Encoding, Function58, Ordinate, Precision, UffFile},
};

/// `+X`, `-RZ`, `scalar`, … for a direction code (record 6, fields 7 and 10), as the
/// listings write it.
///
/// ```
/// assert_eq!(msd_uff::direction_name(3), "+Z");
/// assert_eq!(msd_uff::direction_name(-6), "-RZ");
/// assert_eq!(msd_uff::direction_name(0), "scalar");
/// ```
pub fn direction_name(code: i32) -> String {
    const AXES: [&str; 6] = ["X", "Y", "Z", "RX", "RY", "RZ"];
    match code {
        0 => "scalar".into(),
        c if (1..=6).contains(&c.abs()) => {
            let sign = if c > 0 { '+' } else { '-' };
            format!("{sign}{}", AXES[c.unsigned_abs() as usize - 1])
        }
        c => format!("direction {c}"),
    }
}

impl fmt::Display for Function58 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}, response {}:{}, reference {}:{}, {} {} points, ",
            self.function_type,
            self.response_node,
            direction_name(self.response_direction),
            self.reference_node,
            direction_name(self.reference_direction),
            self.len(),
            match self.ordinate {
                Ordinate::Real(_) => "real",
                Ordinate::Complex(_) => "complex",
            },
        )?;
        match &self.abscissa {
            Abscissa::Even { start, step } => write!(f, "abscissa {start} + {step}·k")?,
            Abscissa::Uneven(x) => match (x.first(), x.last()) {
                (Some(first), Some(last)) => write!(f, "uneven abscissa {first} … {last}")?,
                _ => f.write_str("uneven abscissa")?,
            },
        }
        f.write_str(match self.precision {
            Precision::Single => ", single precision",
            Precision::Double => ", double precision",
        })?;
        f.write_str(match self.encoding {
            Encoding::Ascii => ", ASCII",
            Encoding::Binary(ByteOrder::Little) => ", binary (little endian)",
            Encoding::Binary(ByteOrder::Big) => ", binary (big endian)",
        })
    }
}

impl fmt::Display for Data55 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.analysis {
            Analysis55::NormalMode {
                mode, frequency, ..
            } => write!(f, "normal mode {mode} at {frequency} Hz")?,
            Analysis55::ComplexEigenvalue {
                second_order,
                mode,
                eigenvalue: (re, im),
                ..
            } => {
                let order = if *second_order { "second" } else { "first" };
                write!(
                    f,
                    "complex mode {mode} ({order} order), eigenvalue {re} {} {}i",
                    if im.is_sign_negative() { '-' } else { '+' },
                    im.abs()
                )?;
            }
            Analysis55::FrequencyResponse {
                frequency_step,
                frequency,
                ..
            } => write!(
                f,
                "frequency response, step {frequency_step} at {frequency} Hz"
            )?,
            Analysis55::Other { analysis_type, .. } => write!(f, "analysis type {analysis_type}")?,
        }
        write!(
            f,
            ", {} nodes × {} {} values",
            self.nodes.len(),
            self.values_per_node,
            if self.complex { "complex" } else { "real" }
        )
    }
}

impl fmt::Display for UffFile {
    /// ```
    /// let text = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/pyuff/mixed.uff"))?;
    /// let file = msd_uff::parse(&text)?;
    /// println!("{file}");
    /// assert!(file.to_string().starts_with("UFF file: 2 functions, header \"msd-uff fixture model\""));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "UFF file: {} functions", self.functions.len())?;
        if let Some(header) = &self.header {
            write!(f, ", header {:?}", header.model_name)?;
        }
        if let Some(units) = &self.units {
            write!(f, ", units {:?} (code {})", units.description, units.code)?;
        }
        if !self.nodes.is_empty() {
            write!(f, ", {} nodes", self.nodes.len())?;
        }
        for (i, data) in self.data_at_nodes.iter().enumerate() {
            write!(f, "\n  data at nodes {i}: {data}")?;
        }
        for (i, function) in self.functions.iter().enumerate() {
            write!(f, "\n  {i}: {function}")?;
        }
        for s in &self.skipped {
            let binary = if s.binary { "b" } else { "" };
            write!(
                f,
                "\n  skipped dataset {}{binary} at byte {} (line {}): {}",
                s.number, s.offset, s.line, s.note
            )?;
        }
        for t in &self.trailing {
            write!(
                f,
                "\n  {} trailing bytes after the data of function {}, at byte {}",
                t.len, t.function, t.offset
            )?;
        }
        Ok(())
    }
}
