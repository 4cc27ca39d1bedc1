//! `msd inspect FILE`: what a data file holds — its channels or columns, units, lengths,
//! sampling rate, how a text file is written (encoding, delimiter, decimal mark,
//! metadata and units lines, missing values) — and the config lines that read it.

use crate::config::FrequencyUnit;
use crate::data::text::{self, Missing, TextFormat, complex_cell};
use crate::error::{ExperimentError, Result};
use crate::fmt::short;
use msd_signal::Complex64;
use std::fmt::Write;
use std::path::Path;

/// The report of `msd inspect` on the file at `path`.
///
/// ```
/// let dir = tempfile::tempdir().unwrap();
/// let path = dir.path().join("run.csv");
/// std::fs::write(&path, "Rig 2, 2026-11-29\ntime;force;accel\ns;N;m/s²\n0,000;1,5;0,1\n0,001;1,4;0,2\n0,002;1,3;0,3\n").unwrap();
/// let text = msd_experiment::inspect::inspect(&path).unwrap();
/// assert!(text.contains("delimiter = \";\""), "{text}");
/// assert!(text.contains("decimal = \",\""), "{text}");
/// assert!(text.contains("time = \"time\""), "{text}");
/// assert!(text.contains("uniform step 0.001"), "{text}");
/// ```
pub fn inspect(path: &Path) -> Result<String> {
    let survey = survey(path)?;
    if survey.columns.is_empty() {
        // A file of functions (UFF): its description says what reads it.
        return Ok(survey.description);
    }
    Ok(
        survey.description.clone()
            + &config_lines(&survey.file_name, &survey.columns, &survey.keys),
    )
}

/// What a data file holds, as `msd inspect` and `msd init` read it.
pub(crate) struct Survey {
    /// The file's name (the config's `path` beside it).
    pub file_name: String,
    /// How the file is written and its columns, as `msd inspect` prints them.
    pub description: String,
    /// Its columns or channels, in order.
    pub columns: Vec<Column>,
    /// The `[data]` format keys a text file needs (`delimiter`, `decimal`, `missing`).
    pub keys: Vec<String>,
}

/// Reads the file at `path` (a text table, or a format of `msd_files`) into a [`Survey`].
pub(crate) fn survey(path: &Path) -> Result<Survey> {
    let file_name = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    if msd_files::FileFormat::of(path).is_some() {
        let contents =
            msd_files::read(path).map_err(|e| ExperimentError::data(path, e.to_string()))?;
        let columns: Vec<Column> = contents
            .channels
            .iter()
            .map(|c| Column::of(&c.name, c.unit.clone(), &c.values, c.sample_rate_hz))
            .collect();
        return Ok(Survey {
            file_name,
            description: format!("{}: {contents}", path.display()),
            columns,
            keys: Vec::new(),
        });
    }
    let bytes = std::fs::read(path)
        .map_err(|e| ExperimentError::data(path, format!("cannot read the file: {e}")))?;
    if crate::sources::is_universal(path) {
        return universal_file(path, file_name, &bytes);
    }
    text_table(path, file_name, &bytes)
}

/// A Universal File Format file (`.uff`, `.unv`): its datasets as msd-uff lists them,
/// and the `[frequency_response.uff]` lines that read its frequency responses; its time
/// responses as columns (channels named by their DOFs), which the `[data]` lines read.
fn universal_file(path: &Path, file_name: String, bytes: &[u8]) -> Result<Survey> {
    let uff = msd_uff::parse(bytes).map_err(|e| ExperimentError::data(path, e.to_string()))?;
    let (columns, times) = match crate::data::uff::time_channels(&uff) {
        Ok(Some(channels)) => {
            let columns: Vec<Column> = (channels.iter())
                .map(|c| Column::of(&c.name, c.unit.clone(), &c.values, c.sample_rate_hz))
                .collect();
            let said = format!(
                "\nIts {} time responses read as columns named by their DOFs (node:direction):\n",
                columns.len()
            );
            (columns, said)
        }
        Ok(None) => (Vec::new(), String::new()),
        Err(why) => (
            Vec::new(),
            format!("\nIts time responses cannot be read: {why}\n"),
        ),
    };
    let frfs = (uff.functions.iter())
        .filter(|f| f.function_type == msd_uff::FunctionType::FrequencyResponse)
        .count();
    let mut description = format!(
        "{}: a Universal File Format file\n{}\n",
        path.display(),
        uff.to_string().trim_end()
    );
    let _ = match frfs {
        0 if !columns.is_empty() => Ok(()),
        0 => writeln!(
            description,
            "\nNo frequency response function (dataset 58 of type 4) to fit: the modal fits read those."
        ),
        1 => writeln!(
            description,
            "\nConfig lines that read it:\n[frequency_response.uff]\npath = {file_name:?}"
        ),
        n => writeln!(
            description,
            "\nConfig lines that read it ({n} frequency response functions: all as one set of a test; or one of them with `function = N`, N the listing's number + 1):\n[frequency_response.uff]\npath = {file_name:?}\nset = true"
        ),
    };
    if frfs > 0
        && (uff.functions.iter()).any(|f| f.function_type == msd_uff::FunctionType::Coherence)
    {
        description.push_str("# The coherence functions weight their FRFs' lines; say over how many averages they were estimated
# (the analyser's setup) and the residuals are checked against them:
# averages = 16
");
    }
    description.push_str(&times);
    if !columns.is_empty() {
        description.push_str(&column_table(&columns));
    }
    Ok(Survey {
        file_name,
        description,
        columns,
        keys: Vec::new(),
    })
}

/// One column's summary.
pub(crate) struct Column {
    /// Its name in the file (or its 0-based position when the file names none).
    pub name: String,
    /// The unit the file gives.
    pub unit: Option<String>,
    /// Its number of values.
    pub rows: usize,
    /// Its smallest and largest finite value.
    pub range: Option<(f64, f64)>,
    /// The step when the column increases uniformly (within 1 %): a time column.
    pub step: Option<f64>,
    /// The sampling rate the file gives, Hz.
    pub rate: Option<f64>,
    /// The median step of a column that increases with steps that vary by more than
    /// 1 % and no gap (none over three times the median): time stamps of a sensor's
    /// own clock, resampled onto this step when read as the time.
    pub stamps: Option<f64>,
    /// Whether it holds complex numbers as text (`(a+bj)`, `a+bi`): a frequency
    /// response measured line by line; `range` is then that of their magnitudes.
    pub complex: bool,
}

impl Column {
    fn of(name: &str, unit: Option<String>, values: &[f64], rate: Option<f64>) -> Self {
        let finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
        let range = finite.iter().fold(None, |r: Option<(f64, f64)>, &v| {
            Some(r.map_or((v, v), |(a, b)| (a.min(v), b.max(v))))
        });
        let step = (finite.len() == values.len() && values.len() > 2)
            .then(|| (values[values.len() - 1] - values[0]) / (values.len() - 1) as f64)
            .filter(|&dt| {
                dt > 0.0
                    && values
                        .windows(2)
                        .all(|w| ((w[1] - w[0]) - dt).abs() <= 0.01 * dt)
            });
        Self {
            name: name.to_string(),
            unit,
            rows: values.len(),
            range,
            stamps: step.is_none().then(|| stamps(values)).flatten(),
            step,
            rate,
            complex: false,
        }
    }

    /// Whether it counts samples (0, 1, 2, … or from 1: an oscilloscope's `X`, a
    /// logger's `Sample`, an index) and its name or unit does not say time: not a time
    /// axis, whose step of 1 would read as 1 s.
    pub(crate) fn is_counter(&self) -> bool {
        self.step == Some(1.0)
            && self.range.is_some_and(|(first, _)| first.fract() == 0.0)
            && !self.is_time_named()
            && !self.is_frequency_named()
    }

    /// Whether its name or unit says it is a frequency (`Frequency`, `f [Hz]`, `omega`,
    /// a unit in kHz, rad/s or rpm).
    pub(crate) fn is_frequency_named(&self) -> bool {
        let n = self.name.to_ascii_lowercase();
        n.contains("freq")
            || n.contains("hz")
            || n.contains("omega")
            || frequency_unit(self).is_some()
    }

    /// Whether its name or unit says it is time (`t`, `Time (s)`).
    pub(crate) fn is_time_named(&self) -> bool {
        let n = self.name.to_ascii_lowercase();
        n == "t" || n.contains("time") || unit(self) == Some("s")
    }

    /// A column of complex numbers, `range` that of their magnitudes.
    fn complex(name: &str, unit: Option<String>, values: &[Complex64]) -> Self {
        let magnitudes: Vec<f64> = values.iter().map(|z| z.norm()).collect();
        Self {
            complex: true,
            step: None,
            stamps: None,
            ..Self::of(name, unit, &magnitudes, None)
        }
    }
}

/// The median step of strictly increasing `values` with no gap (no step over three
/// times the median).
fn stamps(values: &[f64]) -> Option<f64> {
    let mut steps: Vec<f64> = values.windows(2).map(|w| w[1] - w[0]).collect();
    if values.len() < 3 || !steps.iter().all(|s| s.is_finite() && *s > 0.0) {
        return None;
    }
    steps.sort_by(f64::total_cmp);
    let median = steps[steps.len() / 2];
    (steps[steps.len() - 1] <= 3.0 * median).then_some(median)
}

/// The cells of a text table as numbers (NaN where a cell is not one) and, where every
/// cell of a column is a complex number as text, as complex numbers.
struct Cells {
    names: Vec<String>,
    values: Vec<Vec<f64>>,
    complex: Vec<Vec<Complex64>>,
    rows: usize,
}

impl Cells {
    fn read(path: &Path, bytes: &[u8], format: &TextFormat) -> Result<Self> {
        let mut cells = Cells {
            names: Vec::new(),
            values: Vec::new(),
            complex: Vec::new(),
            rows: 0,
        };
        text::scan(
            path,
            bytes,
            format,
            |h| {
                cells.names = h.map(|h| h.names.clone()).unwrap_or_default();
                Ok(())
            },
            |_, _, r| {
                let width = cells.values.len().max(r.len());
                cells.values.resize(width, Vec::new());
                cells.complex.resize(width, Vec::new());
                for (k, cell) in r.iter().enumerate() {
                    let v = text::parse_cell(cell, format.decimal, Missing::Interpolate)
                        .unwrap_or(f64::NAN);
                    cells.values[k].push(v);
                    if let Some(z) = complex_cell(cell) {
                        cells.complex[k].push(z);
                    }
                }
                cells.rows += 1;
                Ok(())
            },
        )?;
        Ok(cells)
    }

    /// Whether column `k` holds complex numbers: every row one, none a plain number.
    fn is_complex(&self, k: usize) -> bool {
        self.rows > 0 && self.complex[k].len() == self.rows
    }
}

/// A text table: how it is written, its columns, the config lines.
fn text_table(path: &Path, file_name: String, bytes: &[u8]) -> Result<Survey> {
    let (decoded, encoding) = text::decode(bytes);
    let (delimiter, decimal) = text::sniff(&decoded);
    let decoded = text::whitespace_runs(decoded, delimiter);
    let mut format = TextFormat {
        delimiter,
        decimal,
        header: true,
        skip_lines: 0,
        missing: Missing::Interpolate,
    };
    let newlines: Vec<usize> = decoded
        .bytes()
        .enumerate()
        .filter_map(|(i, b)| (b == b'\n').then_some(i))
        .collect();
    let layout = text::layout(decoded.as_bytes(), &newlines, &format);
    // A table with no header: its first line is data.
    let numbers = layout.headless.is_some();
    if numbers {
        format.header = false;
    }
    let mut cells = Cells::read(path, bytes, &format)?;
    // A table of complex numbers with no header: its first line was taken for one.
    let complex = (0..cells.values.len()).any(|k| cells.is_complex(k))
        && cells
            .names
            .iter()
            .all(|n| complex_cell(n).is_some() || text::number(n.trim(), decimal).is_some());
    if complex {
        format.header = false;
        cells = Cells::read(path, bytes, &format)?;
    }
    let headless = numbers || complex;
    // A column with no value at all (a trailing delimiter's) is no channel.
    let empty = |k: usize| !cells.is_complex(k) && cells.values[k].iter().all(|v| v.is_nan());
    let missing = (0..cells.values.len())
        .filter(|&k| !cells.is_complex(k) && !empty(k))
        .map(|k| cells.values[k].iter().filter(|v| v.is_nan()).count())
        .sum::<usize>();
    let rows = cells.rows;
    let rate = sampling_interval(&layout.settings).map(|dt| text::rate_of_step(dt, 1.0));
    let columns: Vec<Column> = (cells.values.iter().enumerate())
        .filter(|&(k, _)| !empty(k))
        .map(|(k, v)| {
            let name = cells.names.get(k).cloned().unwrap_or_else(|| k.to_string());
            let unit = layout.units.get(k).cloned().filter(|u| !u.is_empty());
            if cells.is_complex(k) {
                Column::complex(&name, unit, &cells.complex[k])
            } else {
                Column::of(&name, unit, v, rate)
            }
        })
        .collect();
    let mut out = format!(
        "{}: a text table, {} columns × {rows} rows; delimiter {delimiter:?}, decimal mark {decimal:?}\n",
        path.display(),
        columns.len()
    );
    for note in encoding.iter().chain(&layout.notes) {
        let _ = writeln!(out, "  {note}");
    }
    if headless {
        let _ = writeln!(
            out,
            "  no header: the first line is data{}; the columns are read by number",
            if complex { " (complex numbers)" } else { "" }
        );
    }
    if missing > 0 {
        let _ = writeln!(
            out,
            "  {missing} missing or unreadable cells: missing = \"interpolate\" or \"drop\" passes over missing ones"
        );
    }
    out.push_str(&column_table(&columns));
    let mut keys = Vec::new();
    if delimiter != ',' {
        keys.push(format!("delimiter = {:?}", delimiter.to_string()));
    }
    if decimal != '.' {
        keys.push("decimal = \",\"".to_string());
    }
    if missing > 0 {
        keys.push("missing = \"interpolate\"".to_string());
    }
    if headless {
        keys.push("header = false".to_string());
    }
    Ok(Survey {
        file_name,
        description: out,
        columns,
        keys,
    })
}

pub(crate) fn column_table(columns: &[Column]) -> String {
    let width = columns
        .iter()
        .map(|c| c.name.chars().count())
        .max()
        .unwrap_or(4)
        .max(4);
    let mut out = format!(
        "  {:<width$}  {:<8}  {:>9}  range\n",
        "name", "unit", "values"
    );
    for c in columns {
        let range = c.range.map_or("—".into(), |(a, b)| {
            let of = if c.complex { "complex, |z| " } else { "" };
            format!("{of}{} … {}", short(a), short(b))
        });
        let _ = writeln!(
            out,
            "  {:<width$}  {:<8}  {:>9}  {range}{}",
            c.name,
            c.unit.as_deref().unwrap_or("—"),
            c.rows,
            match (c.step, c.rate) {
                (Some(dt), _) => format!("  (uniform step {})", short(dt)),
                (None, _) if c.stamps.is_some() && c.is_time_named() => format!(
                    "  (time stamps whose steps vary, median {}: resampled onto it when read)",
                    short(c.stamps.unwrap_or_default())
                ),
                (None, Some(r)) => format!("  (sampled at {} Hz)", short(r)),
                (None, None) => String::new(),
            }
        );
    }
    out
}

/// The column's unit: the file's units line (or channel property), else a unit written
/// in the column's name, `accel [g]` or `force (kN)`.
pub(crate) fn unit(column: &Column) -> Option<&str> {
    let given = column
        .unit
        .as_deref()
        .map(str::trim)
        .filter(|u| !u.is_empty());
    given.or_else(|| text::unit_in_name(&column.name))
}

/// The `[frequency_response.table]` lines of a table whose column `f` is a frequency:
/// magnitude and phase by their names, else the first two other columns as real and
/// imaginary parts.
fn table_lines(out: &mut String, name: &str, keys: &[String], f: &Column, others: &[&Column]) {
    let quoted = |c: &Column| column_key(c, keys);
    let _ = writeln!(out, "[frequency_response.table]\npath = {name:?}");
    for k in keys {
        let _ = writeln!(out, "{k}");
    }
    let _ = writeln!(out, "frequency = {}{}", quoted(f), unit_line(f));
    let named = |words: &[&str]| {
        (others.iter()).find(|c| {
            words
                .iter()
                .any(|w| text::name_words(&c.name).any(|n| n == *w))
        })
    };
    match (
        named(&["mag", "magnitude", "amplitude", "db"]),
        named(&["phase", "deg"]),
    ) {
        (Some(m), Some(p)) => {
            let _ = writeln!(out, "magnitude = {}\nphase = {}", quoted(m), quoted(p));
            if text::name_words(&m.name).any(|w| w == "db") {
                let _ = writeln!(out, "magnitude_in_db = true");
            }
            if text::name_words(&p.name).any(|w| w == "rad") {
                let _ = writeln!(out, "phase_in_degrees = false");
            }
        }
        _ => {
            if let [re, im, ..] = others {
                let _ = writeln!(
                    out,
                    "real = {}\nimaginary = {}    # or magnitude = …, phase = …",
                    quoted(re),
                    quoted(im)
                );
            }
        }
    }
    let _ = writeln!(
        out,
        "kind = \"accelerance\"    # or receptance, mobility: what the response measures"
    );
}

/// The sampling interval, s, an oscilloscope's settings give (Rigol's `Increment`,
/// `XINC`, `Sample Interval`, `Delta_X`).
fn sampling_interval(settings: &[(String, f64)]) -> Option<f64> {
    const NAMES: [&str; 6] = [
        "increment",
        "xinc",
        "x increment",
        "sample interval",
        "delta_x",
        "dt",
    ];
    (settings.iter())
        .find(|(n, v)| NAMES.contains(&n.trim().to_ascii_lowercase().as_str()) && *v > 0.0)
        .map(|(_, v)| *v)
}

/// How a config names the column: its name quoted, or without a header (`keys` say
/// `header = false`) its 0-based number.
pub(crate) fn column_key(c: &Column, keys: &[String]) -> String {
    match keys.iter().any(|k| k == "header = false") {
        true => c.name.clone(),
        false => format!("{:?}", c.name),
    }
}

/// The `frequency_unit` line of a frequency column in kHz, rad/s or rpm (the fits work
/// in Hz), with its newline before it; empty in Hz.
fn unit_line(f: &Column) -> String {
    match frequency_unit(f) {
        Some(u) if !u.is_hertz() => format!("\nfrequency_unit = {:?}", u.name()),
        _ => String::new(),
    }
}

/// The frequency unit of a column's unit (units line or name), if it is one.
fn frequency_unit(column: &Column) -> Option<FrequencyUnit> {
    unit(column).and_then(FrequencyUnit::of)
}

/// The sampling rate a time column gives when its unit is not seconds (`Time [ms]`,
/// `t (us)`, `min`), with where it comes from; `None` in seconds or with no unit (the
/// column is then read as the time).
pub(crate) fn rate_of_time(t: &Column) -> Option<(f64, String)> {
    let unit = unit(t)?;
    let seconds = text::seconds_per(unit).filter(|&s| s != 1.0)?;
    let step = t.step?;
    let rate = text::rate_of_step(step, seconds);
    Some((
        rate,
        format!("from the step of {:?}, {} {unit}", t.name, short(step)),
    ))
}

/// The `[data]` lines (or `[frequency_response.table]` lines for a table whose first
/// column is a frequency) that read the file.
pub(crate) fn config_lines(name: &str, columns: &[Column], keys: &[String]) -> String {
    let quoted = |c: &Column| column_key(c, keys);
    let long: Vec<&Column> = columns.iter().filter(|c| c.rows > 1).collect();
    let counter = long.iter().find(|c| c.is_counter()).copied();
    let long: Vec<&Column> = long.into_iter().filter(|c| !c.is_counter()).collect();
    let time = (long.iter().find(|c| c.step.is_some()))
        .or_else(|| {
            long.iter()
                .find(|c| c.stamps.is_some() && c.is_time_named())
        })
        .copied();
    let others: Vec<&Column> = long
        .iter()
        .copied()
        .filter(|c| time.is_none_or(|t| !std::ptr::eq(*c, t)))
        .collect();
    let mut out =
        String::from("\nConfig lines that read it (choose the columns among those above):\n");
    let frequency = time.filter(|t| t.is_frequency_named());
    if let Some(z) = columns.iter().find(|c| c.complex) {
        // A column of complex numbers: a frequency response measured line by line.
        let _ = writeln!(out, "[frequency_response.table]\npath = {name:?}");
        for k in keys {
            let _ = writeln!(out, "{k}");
        }
        match time {
            Some(f) => {
                let _ = writeln!(out, "frequency = {}{}", quoted(f), unit_line(f));
            }
            None => {
                let _ = writeln!(
                    out,
                    "frequency_step_hz = …    # the file gives no frequencies: line i is at frequency_start_hz + i × this"
                );
            }
        }
        let _ = writeln!(
            out,
            "complex = {}\nkind = \"accelerance\"    # or receptance, mobility: what the response measures",
            quoted(z)
        );
        return out;
    }
    if let Some(f) = frequency {
        table_lines(&mut out, name, keys, f, &others);
        return out;
    }
    let _ = writeln!(out, "[data]\npath = {name:?}");
    for k in keys {
        let _ = writeln!(out, "{k}");
    }
    if let Some((rate, from)) = time.and_then(rate_of_time) {
        let _ = writeln!(out, "sample_rate = {rate}    # Hz, {from}");
    } else if let Some(t) = time {
        let _ = writeln!(out, "time = {}", quoted(t));
    } else {
        let rate = long.iter().find_map(|c| c.rate).map_or("…".into(), short);
        let why = counter.map_or(String::new(), |c| {
            format!("    # Hz; {:?} counts samples, it is not a time", c.name)
        });
        let _ = writeln!(out, "sample_rate = {rate}{why}");
    }
    let mut picks = others.iter();
    for role in ["input", "output"] {
        match picks.next() {
            Some(c) => {
                let _ = writeln!(out, "{role} = {}", quoted(c));
            }
            None => {
                let _ = writeln!(out, "{role} = \"…\"");
            }
        }
    }
    out
}
