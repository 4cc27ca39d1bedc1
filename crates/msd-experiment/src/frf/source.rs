//! The frequency response of a `[frequency_response]` section: simulated (a stepped sine;
//! hammer hits and shaker records in `simulate.rs`) or read (a CSV table, a UFF file, CSV
//! time records).

use super::csv::{self, Request};
use super::simulate;
use super::time_domain::TimeRecords;
use crate::config::{
    ChainPlant, Column, FrequencyResponseSection, FrequencyUnit, RecordsSource, Spacing,
    SweepSource, TableSource, UffSource,
};
use crate::data::text::{name_words, unit_in_name};
use crate::error::{ExperimentError, Result};
use crate::sources::Sources;
use msd_ident::Hold;
use msd_modal::{Dof, SetMember};
use msd_signal::{FrequencyResponseEstimate, FrfOptions, Record, frf_estimate};
use std::path::Path;

/// A frequency response and where it came from.
pub(crate) struct Loaded {
    pub frf: FrequencyResponseEstimate,
    /// One line for the report: the source and its size.
    pub description: String,
    /// The time records it was estimated from, if it was.
    pub time: Option<TimeRecords>,
    /// A set's members (`frf` is the first), empty otherwise.
    pub members: Vec<SetMember>,
    /// The nodes (datasets 15 or 2411) of a set's UFF file, empty otherwise.
    pub nodes: Vec<msd_uff::Node>,
}

/// The section's frequency response; `sources` gives the files, `seed` the noise.
pub(crate) fn load(
    section: &FrequencyResponseSection,
    sources: &Sources,
    seed: u64,
) -> Result<Loaded> {
    let plant = section.plant.as_ref();
    let plant_of =
        || plant.ok_or_else(|| ExperimentError::config("frequency_response", "plant: missing"));
    if let Some(s) = &section.sweep {
        return sweep(s, plant_of()?, seed);
    }
    if let Some(h) = &section.hammer {
        return simulate::hammer(h, plant_of()?, &section.estimator, seed);
    }
    if let Some(s) = &section.shaker {
        return simulate::shaker(s, plant_of()?, &section.estimator, seed);
    }
    if let Some(t) = &section.table {
        return table(t, sources, &sources.path(&t.path));
    }
    if let Some(set) = &section.set {
        return members(set, sources);
    }
    if let Some(u) = section.uff.as_ref().filter(|u| u.set) {
        return uff_set(
            u,
            sources.uff(&sources.path(&u.path))?,
            &sources.path(&u.path),
        );
    }
    if let Some(u) = &section.uff {
        return uff(
            u,
            sources.uff(&sources.path(&u.path))?,
            &sources.path(&u.path),
        );
    }
    if let Some(r) = &section.records {
        return records(r, sources, &sources.path(&r.path), &section.estimator);
    }
    Err(ExperimentError::config("frequency_response", "no source"))
}

pub(super) fn run_error(e: impl Into<Box<dyn std::error::Error + Send + Sync>>) -> ExperimentError {
    ExperimentError::run("frequency response", e)
}

fn sweep(s: &SweepSource, plant: &ChainPlant, seed: u64) -> Result<Loaded> {
    let [low, high] = s.band_hz;
    let step = |i: usize| i as f64 / (s.lines - 1) as f64;
    let f: Vec<f64> = (0..s.lines)
        .map(|i| match s.spacing {
            Spacing::Logarithmic => low * (high / low).powf(step(i)),
            Spacing::Linear => low + (high - low) * step(i),
        })
        .collect();
    let frf = msd_modal::synthetic_frequency_response(&f, s.relative_noise, seed, |f| {
        plant.receptance(f)
    })
    .map_err(run_error)?;
    Ok(Loaded {
        frf,
        time: None,
        description: format!(
            "a stepped sine simulated on the plant: {} {} spaced frequencies, {low}–{high} Hz, {} % complex noise",
            s.lines,
            match s.spacing {
                Spacing::Logarithmic => "logarithmically",
                Spacing::Linear => "evenly",
            },
            100.0 * s.relative_noise
        ),
        members: Vec::new(),
        nodes: Vec::new(),
    })
}

fn table(t: &TableSource, sources: &Sources, path: &Path) -> Result<Loaded> {
    let key = |k: &str| format!("frequency_response.table.{k}");
    let mut columns = Vec::new();
    for (name, c) in [
        ("frequency", &t.frequency),
        ("magnitude", &t.magnitude),
        ("phase", &t.phase),
        ("real", &t.real),
        ("imaginary", &t.imaginary),
        ("coherence", &t.coherence),
    ] {
        if let Some(c) = c {
            columns.push((key(name), c));
        }
    }
    let read = csv::read(&Request {
        sources,
        path,
        path_key: "frequency_response.table.path",
        format: t.text_format(),
        columns,
        complex: t.complex.as_ref().map(|c| (key("complex"), c)),
    })?;
    let rows = read.lines.len();
    let mut values = read.values.iter().map(Vec::as_slice);
    let f: Vec<f64> = match (&t.frequency, t.frequency_step_hz) {
        (Some(column), _) => {
            named_unit(path, column, t.frequency_unit)?;
            let to_hz = t.frequency_unit.hertz();
            let f: Vec<f64> = values.next().unwrap_or_default().to_vec();
            increasing(path, &f, &read.lines, column, t.frequency_unit.name())?;
            f.iter().map(|f| f * to_hz).collect()
        }
        (None, step) => {
            let step = step.unwrap_or(1.0);
            (0..rows)
                .map(|i| t.frequency_start_hz + i as f64 * step)
                .collect()
        }
    };
    let fail = |e: msd_signal::SignalError| ExperimentError::data(path, e.to_string());
    let (a, b) = (
        values.next().unwrap_or_default(),
        values.next().unwrap_or_default(),
    );
    let (mut frf, what) = if t.complex.is_some() {
        let frf = FrequencyResponseEstimate::new(f.clone(), read.complex.clone()).map_err(fail)?;
        (frf, "complex numbers")
    } else if let Some(column) = &t.magnitude {
        let phase: Vec<f64> = if t.phase_in_degrees {
            b.to_vec()
        } else {
            b.iter().map(|p| p.to_degrees()).collect()
        };
        let a = linear_magnitude(path, column, t.magnitude_in_db, a, &read.lines)?;
        let frf = FrequencyResponseEstimate::from_magnitude_phase(&f, &a, &phase).map_err(fail)?;
        (frf, "magnitude and phase")
    } else {
        let frf = FrequencyResponseEstimate::from_real_imaginary(&f, a, b).map_err(fail)?;
        (frf, "real and imaginary parts")
    };
    frf.kind = t.kind;
    if let Some(column) = &t.coherence {
        let coherence = if t.complex.is_some() {
            a
        } else {
            values.next().unwrap_or_default()
        };
        frf.coherence = checked_coherence(path, coherence, &read.lines, column)?;
        frf.averages = t.averages.unwrap_or(0);
    }
    check_values(&frf, path, |k| format!("line {}", read.lines[k]))?;
    Ok(Loaded {
        time: None,
        description: format!(
            "the table {} ({} lines, {}–{} Hz, {what}){}",
            path.display(),
            f.len(),
            f[0],
            f[f.len() - 1],
            notes_text(&read.notes)
        ),
        frf,
        members: Vec::new(),
        nodes: Vec::new(),
    })
}

/// The tables of a set, each with its DOFs; the files must share their lines.
fn members(set: &[TableSource], sources: &Sources) -> Result<Loaded> {
    let mut members = Vec::new();
    for (i, t) in set.iter().enumerate() {
        let path = sources.path(&t.path);
        let loaded = table(t, sources, &path)?;
        let (Some(response), Some(reference)) = (t.response, t.reference) else {
            return Err(ExperimentError::config(
                format!("frequency_response.set[{i}]"),
                "response and reference: missing",
            ));
        };
        if let Some(first) = members.first().map(|m: &SetMember| &m.frf)
            && (first.frequency != loaded.frf.frequency || first.kind != loaded.frf.kind)
        {
            return Err(ExperimentError::data(
                &path,
                format!(
                    "frequency_response.set[{i}]: {} lines {}–{} Hz of {}, but set[0] has {} lines {}–{} Hz of {}: the FRFs of a set share their lines and their quantity",
                    loaded.frf.frequency.len(),
                    loaded.frf.frequency[0],
                    loaded.frf.frequency[loaded.frf.frequency.len() - 1],
                    loaded.frf.kind,
                    first.frequency.len(),
                    first.frequency[0],
                    first.frequency[first.frequency.len() - 1],
                    first.kind
                ),
            ));
        }
        if let Some(j) = members
            .iter()
            .position(|m| (m.response, m.reference) == (response, reference))
        {
            return Err(ExperimentError::config(
                format!("frequency_response.set[{i}]"),
                format!(
                    "response {response} and reference {reference} are those of set[{j}]: each pair of DOFs once"
                ),
            ));
        }
        members.push(SetMember {
            frf: loaded.frf,
            response,
            reference,
        });
    }
    let first = &members[0].frf;
    Ok(Loaded {
        frf: first.clone(),
        description: format!(
            "a set of {} FRFs ({} lines each, {}–{} Hz, {})",
            members.len(),
            first.frequency.len(),
            first.frequency[0],
            first.frequency[first.frequency.len() - 1],
            first.kind
        ),
        time: None,
        members,
        nodes: Vec::new(),
    })
}

/// The magnitude column as |H|: from decibels (20·log₁₀|H|) with `in_db`; without it, a
/// column whose name says dB is refused, and so is a negative magnitude, which only a
/// decibel column holds.
fn linear_magnitude(
    path: &Path,
    column: &Column,
    in_db: bool,
    a: &[f64],
    lines: &[usize],
) -> Result<Vec<f64>> {
    if in_db {
        return Ok(a.iter().map(|db| 10f64.powf(db / 20.0)).collect());
    }
    let key = "frequency_response.table.magnitude";
    let named_db = matches!(column, Column::Name(n) if name_words(n).any(|w| w == "db"));
    let negative = a.iter().position(|&m| m < 0.0);
    if named_db || negative.is_some() {
        let why = match negative {
            Some(i) => format!("holds {} on line {}", a[i], lines[i]),
            None => "is named in dB".to_string(),
        };
        return Err(ExperimentError::data(
            path,
            format!(
                "{key} = {column}: the column {why}: a magnitude in decibels? set magnitude_in_db = true (20·log₁₀|H|), or give |H| itself"
            ),
        ));
    }
    Ok(a.to_vec())
}

/// The smallest non-zero magnitude a response value may have (the mirror of
/// [`LARGEST_VALUE`](crate::data::LARGEST_VALUE)): the squares a fit sums stay normal
/// numbers (1e-100² = 1e-200 > 2.2e-308). A value beyond either is a unit or scale
/// error, refused where it is read.
const SMALLEST_VALUE: f64 = 1e-100;

/// Refuses response values whose squares overflow or underflow, and a response that is
/// zero everywhere; `place(k)` names value k's place in the file.
fn check_values(
    frf: &FrequencyResponseEstimate,
    path: &Path,
    place: impl Fn(usize) -> String,
) -> Result<()> {
    let largest = crate::data::LARGEST_VALUE;
    for (k, h) in frf.h.iter().enumerate() {
        let m = h.norm();
        if m > largest || (m > 0.0 && m < SMALLEST_VALUE) {
            return Err(ExperimentError::data(
                path,
                format!(
                    "{}: |H| = {m:e}: expected a magnitude from {SMALLEST_VALUE:e} to {largest:e} (or 0); a value beyond them is a unit or scale error, whose squares the fit cannot sum",
                    place(k)
                ),
            ));
        }
    }
    if frf.h.iter().all(|h| h.norm() == 0.0) {
        return Err(ExperimentError::data(
            path,
            format!(
                "every one of the {} values is zero: expected a measured response",
                frf.h.len()
            ),
        ));
    }
    Ok(())
}

/// A coherence column's values, each in [0, 1] (a little above 1 from rounding is
/// clamped), else refused naming the line.
fn checked_coherence(path: &Path, g: &[f64], lines: &[usize], column: &Column) -> Result<Vec<f64>> {
    if let Some(k) = g.iter().position(|g| !(-1e-6..=1.0 + 1e-6).contains(g)) {
        return Err(ExperimentError::data(
            path,
            format!(
                "line {}, column {column} (frequency_response.table.coherence): {}: expected an ordinary coherence γ² from 0 to 1",
                lines[k], g[k]
            ),
        ));
    }
    Ok(g.iter().map(|g| g.clamp(0.0, 1.0)).collect())
}

/// Refuses a frequency column whose name states a unit other than `unit` (a column in
/// kHz or rad/s read as Hz puts every mode 1000× or 2π× off, silently).
fn named_unit(path: &Path, column: &Column, unit: FrequencyUnit) -> Result<()> {
    let Column::Name(name) = column else {
        return Ok(());
    };
    let named = unit_in_name(name).and_then(FrequencyUnit::of);
    match named {
        Some(named) if named != unit => Err(ExperimentError::data(
            path,
            format!(
                "frequency_response.table.frequency = {column}: its name says {}, frequency_unit is {:?}: set frequency_unit = {:?}",
                named.name(),
                unit.name(),
                named.name()
            ),
        )),
        _ => Ok(()),
    }
}

/// Refuses frequencies that are negative or do not increase, naming the line.
fn increasing(path: &Path, f: &[f64], lines: &[usize], column: &Column, unit: &str) -> Result<()> {
    if f[0] < 0.0 {
        return Err(ExperimentError::data(
            path,
            format!(
                "line {}, column {column}: {} {unit}: expected a frequency >= 0",
                lines[0], f[0]
            ),
        ));
    }
    match f.windows(2).position(|w| w[1] <= w[0]) {
        Some(i) => Err(ExperimentError::data(
            path,
            format!(
                "line {}, column {column} (frequency_response.table.frequency): {} {unit} is not above the previous line's {} {unit}: expected increasing frequencies, one row per line",
                lines[i + 1],
                f[i + 1],
                f[i]
            ),
        )),
        None => Ok(()),
    }
}

fn uff(u: &UffSource, file: msd_uff::UffFile, path: &Path) -> Result<Loaded> {
    let fail = |message: String| ExperimentError::data(path, message);
    let (index, function) = super::uff::pick(&file, u.function).map_err(fail)?;
    let (frf, coherence) = uff_function(function, index, u, path, &file)?;
    let paired: Vec<usize> = coherence.into_iter().collect();
    Ok(Loaded {
        time: None,
        description: format!(
            "dataset 58 #{} of {} ({}, response {}:{}, reference {}:{}, {} lines, {}{}){}",
            index + 1,
            path.display(),
            function.function_type,
            function.response_node,
            function.response_direction,
            function.reference_node,
            function.reference_direction,
            function.len(),
            frf.kind,
            coherence.map_or(String::new(), |j| format!(
                ", its coherence dataset 58 #{}",
                j + 1
            )),
            not_read(&file.functions, &paired)
        ),
        frf,
        members: Vec::new(),
        nodes: Vec::new(),
    })
}

/// The datasets 58 of a file that are neither frequency responses nor their coherences
/// (`paired`, by index), said after a source's description ("; not read: dataset 58 #2
/// (time response)"), or nothing.
fn not_read(functions: &[msd_uff::Function58], paired: &[usize]) -> String {
    let others: Vec<String> = functions
        .iter()
        .enumerate()
        .filter(|(i, f)| {
            f.function_type != msd_uff::FunctionType::FrequencyResponse && !paired.contains(i)
        })
        .map(|(i, f)| format!("#{} ({})", i + 1, f.function_type))
        .collect();
    match others.len() {
        0 => String::new(),
        n if n <= 5 => format!(
            "; not frequency responses, not read: dataset 58 {}",
            others.join(", ")
        ),
        n => format!(
            "; not frequency responses, not read: {n} datasets 58 ({}, …)",
            others[..3].join(", ")
        ),
    }
}

/// Dataset 58 number `index` (from 0) of `file` as a frequency response, its values
/// checked, with its coherence function where the file holds one (and its index).
fn uff_function(
    function: &msd_uff::Function58,
    index: usize,
    u: &UffSource,
    path: &Path,
    file: &msd_uff::UffFile,
) -> Result<(FrequencyResponseEstimate, Option<usize>)> {
    let mut frf = super::uff::to_estimate(function, u.kind).map_err(|e| {
        ExperimentError::data(
            path,
            format!("dataset 58 #{} (frequency_response.uff): {e}", index + 1),
        )
    })?;
    check_values(&frf, path, |k| {
        format!(
            "dataset 58 #{}, value {} ({} Hz)",
            index + 1,
            k + 1,
            frf.frequency[k]
        )
    })?;
    let coherence = super::uff::coherence_of(file, function, index)
        .map_err(|e| ExperimentError::data(path, e))?;
    Ok(match coherence {
        Some((j, coherence)) => {
            (frf.coherence, frf.averages) = (coherence, u.averages.unwrap_or(0));
            (frf, Some(j))
        }
        None => (frf, None),
    })
}

/// Every frequency response function of a UFF file as a set, each with its DOFs.
fn uff_set(u: &UffSource, file: msd_uff::UffFile, path: &Path) -> Result<Loaded> {
    let fail = |message: String| ExperimentError::data(path, message);
    let mut members = Vec::new();
    let mut paired = Vec::new();
    for (index, function) in file.functions.iter().enumerate() {
        if function.function_type != msd_uff::FunctionType::FrequencyResponse {
            continue;
        }
        let (frf, coherence) = uff_function(function, index, u, path, &file)?;
        paired.push(coherence);
        let dof = |node: i64, direction: i32| {
            u32::try_from(node)
                .map(|node| Dof { node, direction })
                .map_err(|_| {
                    fail(format!(
                        "dataset 58 #{}: node {node}: expected a node number from 0",
                        index + 1
                    ))
                })
        };
        members.push((
            index,
            SetMember {
                frf,
                response: dof(function.response_node, function.response_direction)?,
                reference: dof(function.reference_node, function.reference_direction)?,
            },
        ));
    }
    let Some((_, first)) = members.first() else {
        return Err(fail(
            "frequency_response.uff.set = true: the file holds no frequency response function (dataset 58 of function type 4)".into(),
        ));
    };
    for (index, m) in &members[1..] {
        if m.frf.frequency != first.frf.frequency || m.frf.kind != first.frf.kind {
            return Err(fail(format!(
                "dataset 58 #{} ({} / {}) has other lines or another quantity than the first FRF: the FRFs of a set share their lines and their quantity",
                index + 1,
                m.response,
                m.reference
            )));
        }
        if let Some((j, _)) = members
            .iter()
            .find(|(j, o)| j < index && (o.response, o.reference) == (m.response, m.reference))
        {
            return Err(fail(format!(
                "datasets 58 #{} and #{} are both response {} / reference {}: each pair of DOFs once",
                j + 1,
                index + 1,
                m.response,
                m.reference
            )));
        }
    }
    let mut members: Vec<SetMember> = members.into_iter().map(|(_, m)| m).collect();
    let coherences = set_coherences(&mut members, &paired);
    let paired: Vec<usize> = paired.into_iter().flatten().collect();
    let first = &members[0].frf;
    Ok(Loaded {
        frf: first.clone(),
        description: format!(
            "the {} frequency response functions of {} as a set ({} lines each, {}{coherences}){}",
            members.len(),
            path.display(),
            first.frequency.len(),
            first.kind,
            not_read(&file.functions, &paired)
        ),
        time: None,
        members,
        nodes: file.nodes,
    })
}

/// What the description says of a set's coherence functions (`paired[o]`, member o's
/// dataset index): with every member's, the set is weighted by them; with only some
/// members', none is used (the members would be weighted unalike) and the description
/// says which member has none.
fn set_coherences(members: &mut [SetMember], paired: &[Option<usize>]) -> String {
    match paired.iter().position(Option::is_none) {
        _ if paired.iter().all(Option::is_none) => String::new(),
        None => ", each with its coherence function".into(),
        Some(o) => {
            for m in members.iter_mut() {
                (m.frf.coherence, m.frf.averages) = (vec![1.0; m.frf.frequency.len()], 1);
            }
            format!(
                "; their coherence functions not used: response {} / reference {} has none, and the members are weighted alike",
                members[o].response, members[o].reference
            )
        }
    }
}

fn records(
    r: &RecordsSource,
    sources: &Sources,
    path: &Path,
    options: &FrfOptions,
) -> Result<Loaded> {
    let key = |k: &str, i: usize| format!("frequency_response.records.{k}[{i}]");
    let mut columns = Vec::new();
    for (i, (f, x)) in r.force.iter().zip(&r.response).enumerate() {
        columns.push((key("force", i), f));
        columns.push((key("response", i), x));
    }
    let read = csv::read(&Request {
        sources,
        path,
        path_key: "frequency_response.records.path",
        format: r.text_format(),
        columns,
        complex: None,
    })?;
    for (i, pair) in read.values.chunks_exact(2).enumerate() {
        if pair[0].iter().all(|&v| v == pair[0][0]) {
            return Err(ExperimentError::data(
                path,
                format!(
                    "frequency_response.records.force[{i}] (column {}) is {} on every line: expected the measured force (a constant force drives nothing)",
                    r.force[i], pair[0][0]
                ),
            ));
        }
    }
    let records: Vec<Record<'_>> = read
        .values
        .chunks_exact(2)
        .map(|pair| Record {
            input: &pair[0],
            output: &pair[1],
        })
        .collect();
    let frf = frf_estimate(&records, r.sample_rate, options).map_err(|e| {
        let hint = match e {
            msd_signal::SignalError::ZeroInputPower { .. } => format!(
                " (frequency_response.records.force = {:?}: every force column is constant; expected the measured force)",
                r.force
            ),
            _ => String::new(),
        };
        ExperimentError::data(path, format!("{e}{hint}"))
    })?;
    let description = format!(
        "{} records of {} samples at {} Hz from {} ({}){}",
        records.len(),
        read.lines.len(),
        r.sample_rate,
        path.display(),
        options.kind,
        notes_text(&read.notes)
    );
    let mut values = read.values.into_iter();
    let mut channels = Vec::new();
    while let (Some(force), Some(response)) = (values.next(), values.next()) {
        channels.push([force, response]);
    }
    Ok(Loaded {
        description,
        frf,
        // Measured: the force between samples is not known, cubic as the library's default.
        time: Some(TimeRecords {
            channels,
            sample_rate: r.sample_rate,
            kind: options.kind,
            hold: Hold::Cubic,
        }),
        members: Vec::new(),
        nodes: Vec::new(),
    })
}

/// What the reader said of the file, after its description: "; lines 1–9 read as …".
fn notes_text(notes: &[String]) -> String {
    notes.iter().map(|n| format!("; {n}")).collect()
}
