//! `msd init FILE`: a config that runs, written beside the user's own data file.
//!
//! The file is read as `msd inspect` reads it (a text export with its delimiter,
//! decimal mark, metadata and units lines; MATLAB, NumPy or TDMS channels). Each column's
//! role comes from its unit first (N, kN → a force; g, m/s² → an acceleration; m, mm →
//! a displacement; m/s → a velocity), then from its name (`force`, `load`; `acc`;
//! `vel`; `disp`, `pos`, `laser`); a uniform column (or the file's sampling rate) is
//! the time. What it finds decides the experiment, with nothing asked:
//!
//! | found | experiment |
//! |---|---|
//! | a force and one or more responses | a force test (`excitation = "force"`), every response a channel, scaled to SI |
//! | a response named `base`, `table` or `shaker` and others | a base excitation (`base_acceleration` or `base_displacement`) |
//! | one response and no force | a free decay (`excitation = "none"`): fn and ζ, m, c, k with a weighed mass |
//!
//! Where the columns cannot say (two forces, no response, units that name no quantity),
//! [`InitOptions::input`] and [`InitOptions::outputs`] choose; the error says so.

use crate::config::Quantity;
use crate::error::{ExperimentError, Result};
use crate::inspect::{Column, Survey, column_key, config_lines, rate_of_time, survey, unit};
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// Standard gravity, m/s² per g.
const STANDARD_GRAVITY: f64 = 9.80665;
/// Newtons per pound-force.
const NEWTONS_PER_LBF: f64 = 4.448_221_615_260_5;

/// Options of [`init`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct InitOptions {
    /// The column that drives the plant (a force, or the base's motion), when the
    /// names and units do not say.
    pub input: Option<String>,
    /// The response columns, when the names and units do not say (each one's quantity
    /// still from its unit or name, else a displacement).
    pub outputs: Vec<String>,
    /// The sampling rate, Hz, for a file with no time column and no rate of its own.
    pub sample_rate_hz: Option<f64>,
    /// Where to write the config. By default `<file stem>.toml` beside the data file.
    pub config: Option<PathBuf>,
    /// Replace an existing config. By default false: an existing file is refused.
    pub overwrite: bool,
}

/// What [`init`] wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct Init {
    /// The config file written.
    pub config_path: PathBuf,
    /// Its text.
    pub text: String,
    /// What was found and chosen, for the terminal.
    pub summary: String,
}

/// What a column is for.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Role {
    /// A force on the mass, with its factor to newtons.
    Force(f64),
    /// A motion, with its factor to SI.
    Motion(Quantity, f64),
}

/// A column with its role.
struct Channel<'a> {
    column: &'a Column,
    role: Role,
    /// Why the role (the unit or the name), for the config's comment.
    because: String,
}

/// Reads the data file at `path`, chooses the experiment its columns describe and
/// writes a commented config that runs beside it (see the module's table).
///
/// ```
/// let dir = tempfile::tempdir().unwrap();
/// let path = dir.path().join("shaker.csv");
/// let mut csv = String::from("Rig 2\ntime;force;accel\ns;N;g\n");
/// for i in 0..400 {
///     let t = i as f64 * 1e-3;
///     csv += &format!("{t};{};{}\n", (7.0 * t).sin(), 0.01 * (7.0 * t).cos()).replace('.', ",");
/// }
/// std::fs::write(&path, csv).unwrap();
/// let init = msd_experiment::init::init(&path, &Default::default()).unwrap();
/// assert_eq!(init.config_path, dir.path().join("shaker.toml"));
/// assert!(init.text.contains("excitation = \"force\""), "{}", init.text);
/// assert!(init.text.contains("scale = 9.80665"), "{}", init.text);
/// assert!(init.text.contains("decimal = \",\""), "{}", init.text);
/// ```
pub fn init(path: &Path, options: &InitOptions) -> Result<Init> {
    let survey = survey(path)?;
    if survey.columns.is_empty() {
        // A file of functions (UFF): what reads it is in its description.
        return Err(ExperimentError::data(
            path,
            format!(
                "msd init writes configs of time records in columns, and this file holds none:\n{}",
                survey.description.trim_end()
            ),
        ));
    }
    if survey.columns.iter().any(|c| c.complex) {
        // A frequency response measured line by line: a config of its own kind.
        return Err(ExperimentError::data(
            path,
            format!(
                "a column of complex numbers: a frequency response, which msd init does not write a config for (it writes those of time records); a config with these lines reads it (fill in what is marked …):\n{}",
                config_lines(&survey.file_name, &survey.columns, &survey.keys)
                    .trim()
                    .split_once('\n')
                    .map_or("", |(_, lines)| lines)
            ),
        ));
    }
    let config_path = options
        .config
        .clone()
        .unwrap_or_else(|| path.with_extension("toml"));
    if config_path == path {
        return Err(ExperimentError::data(
            path,
            "the data file ends in .toml: give the config's path (--config)",
        ));
    }
    if config_path.exists() && !options.overwrite {
        return Err(ExperimentError::data(
            &config_path,
            "a file of this name exists: give another path (--config) or replace it (--overwrite)",
        ));
    }
    let (text, roles) = config_text(path, &survey, options, &config_path)?;
    // The config must read back: a config this command wrote that `msd run` refuses
    // would be the worst first minute.
    crate::config::Config::from_toml_str(&text, &config_path)?;
    std::fs::write(&config_path, &text).map_err(|e| {
        ExperimentError::data(&config_path, format!("cannot write the config: {e}"))
    })?;
    let summary = format!(
        "{}\n{}\nwrote {}; run it with\n    msd run {}\n",
        survey.description.trim_end(),
        roles.join("\n"),
        config_path.display(),
        config_path.display()
    );
    Ok(Init {
        config_path,
        text,
        summary,
    })
}

/// The config's text for the file at `path`, to be written at `config_path`.
fn config_text(
    path: &Path,
    survey: &Survey,
    options: &InitOptions,
    config_path: &Path,
) -> Result<(String, Vec<String>)> {
    let time = time_column(&survey.columns);
    let grid = match (options.sample_rate_hz, time) {
        (Some(rate), _) if !(rate.is_finite() && rate > 0.0) => {
            return Err(ExperimentError::data(
                path,
                format!("--sample-rate {rate}: expected a finite rate > 0 Hz"),
            ));
        }
        (Some(rate), _) => Grid::Rate(rate, "as given to msd init".into()),
        (None, Some(t)) => time_grid(t),
        (None, None) => match survey.columns.iter().find_map(|c| c.rate) {
            Some(rate) => Grid::Rate(rate, "as the file gives it".into()),
            None => {
                let why = match survey.columns.iter().find(|c| c.is_counter()) {
                    Some(c) => format!("{:?} counts samples (it is not a time)", c.name),
                    None => "no column rises by a uniform step".into(),
                };
                return Err(ExperimentError::data(
                    path,
                    format!(
                        "{why} and the file gives no sampling rate: give it (--sample-rate HZ)"
                    ),
                ));
            }
        },
    };
    let others: Vec<&Column> = survey
        .columns
        .iter()
        .filter(|c| c.rows > 1 && c.range.is_some())
        .filter(|c| time.is_none_or(|t| !std::ptr::eq(*c, t)))
        .collect();
    let chosen = choose(path, &others, options)?;
    let mut out = header(path, survey, config_path, &chosen);
    write_setup(&mut out, &chosen, &survey.keys);
    write_data(&mut out, survey, &grid, config_path, path, &chosen);
    out.push_str(ESTIMATION);
    Ok((out, chosen.roles()))
}

/// The record's time: a column, or a sampling rate and where it comes from.
enum Grid<'a> {
    Time(&'a Column),
    Rate(f64, String),
}

/// The grid of a time column: the column itself in seconds (or with no unit), else the
/// sampling rate its step gives in its unit.
fn time_grid(t: &Column) -> Grid<'_> {
    match rate_of_time(t) {
        Some((rate, from)) => Grid::Rate(rate, from),
        None => Grid::Time(t),
    }
}

/// The experiment the columns describe.
struct Chosen<'a> {
    /// "force", "base_acceleration", "base_displacement" or "none".
    excitation: &'static str,
    input: Option<Channel<'a>>,
    responses: Vec<Channel<'a>>,
    /// Columns read by nothing.
    unused: Vec<&'a Column>,
}

impl Chosen<'_> {
    /// Each column's role and why, in sentences.
    fn roles(&self) -> Vec<String> {
        let mut lines = Vec::new();
        if let Some(input) = &self.input {
            let what = match self.excitation {
                "force" => "the force on the mass (the input)",
                "base_acceleration" => "the base's acceleration (the input)",
                _ => "the base's displacement (the input)",
            };
            lines.push(format!(
                "{:?} is {what}, by {}",
                input.column.name, input.because
            ));
        }
        for r in &self.responses {
            if let Role::Motion(q, _) = r.role {
                let what = format!("the mass's {} (a response)", q);
                lines.push(format!("{:?} is {what}, by {}", r.column.name, r.because));
            }
        }
        for c in &self.unused {
            let why = match c.is_counter() {
                true => "it counts samples (the sampling rate gives the time)",
                false => "its unit and name say nothing of what it measures",
            };
            lines.push(format!("{:?} is not read: {why}", c.name));
        }
        if self.excitation == "none" {
            lines
                .push("No input column: the record is taken as a free decay (a ring-down).".into());
        }
        lines
    }
}

/// The time column: uniform, named or measured as time when several are uniform.
/// Else time stamps that vary (a sensor's own clock), named as time.
fn time_column(columns: &[Column]) -> Option<&Column> {
    let uniform = || (columns.iter()).filter(|c| c.step.is_some() && c.rows > 2 && !c.is_counter());
    uniform()
        .find(|c| c.is_time_named())
        .or_else(|| uniform().next())
        .or_else(|| {
            (columns.iter()).find(|c| c.stamps.is_some() && c.is_time_named() && c.rows > 2)
        })
}

/// The role a column's unit gives it.
fn role_of_unit(unit: &str) -> Option<Role> {
    let u = unit.trim().replace(' ', "");
    let motion = |q, s| Some(Role::Motion(q, s));
    match u.as_str() {
        "N" => Some(Role::Force(1.0)),
        "kN" => Some(Role::Force(1e3)),
        "mN" => Some(Role::Force(1e-3)),
        "lbf" => Some(Role::Force(NEWTONS_PER_LBF)),
        "g" | "G" => motion(Quantity::Acceleration, STANDARD_GRAVITY),
        "m/s²" | "m/s^2" | "m/s2" | "ms^-2" | "m*s^-2" => motion(Quantity::Acceleration, 1.0),
        "mm/s²" | "mm/s^2" | "mm/s2" => motion(Quantity::Acceleration, 1e-3),
        "m/s" => motion(Quantity::Velocity, 1.0),
        "mm/s" => motion(Quantity::Velocity, 1e-3),
        "m" => motion(Quantity::Displacement, 1.0),
        "mm" => motion(Quantity::Displacement, 1e-3),
        "µm" | "um" | "μm" => motion(Quantity::Displacement, 1e-6),
        _ => None,
    }
}

/// The role a column's name gives it (in SI: its unit said nothing).
fn role_of_name(name: &str) -> Option<Role> {
    let n = name.to_ascii_lowercase();
    let has = |words: &[&str]| words.iter().any(|w| n.contains(w));
    if has(&["force", "load", "hammer"]) || n == "f" {
        Some(Role::Force(1.0))
    } else if has(&["acc"]) {
        Some(Role::Motion(Quantity::Acceleration, 1.0))
    } else if has(&["vel"]) {
        Some(Role::Motion(Quantity::Velocity, 1.0))
    } else if has(&["disp", "pos", "laser", "lvdt"]) || n == "x" {
        Some(Role::Motion(Quantity::Displacement, 1.0))
    } else {
        None
    }
}

/// The column's role with its reason, if its unit or name gives one.
fn channel(column: &Column) -> Option<Channel<'_>> {
    if let Some(unit) = unit(column)
        && let Some(role) = role_of_unit(unit)
    {
        return Some(Channel {
            column,
            role,
            because: format!("its unit {unit}"),
        });
    }
    let because = match unit(column) {
        Some(unit) => format!(
            "its name (its unit {unit} is not one of the quantity's: set its scale to SI per {unit}, \
             the sensor's sensitivity)"
        ),
        None => "its name (no unit given: SI assumed)".into(),
    };
    role_of_name(&column.name).map(|role| Channel {
        column,
        role,
        because,
    })
}

/// Whether a response column measures the base (a shaker table's sensor).
fn is_base(column: &Column) -> bool {
    let n = column.name.to_ascii_lowercase();
    ["base", "table", "shaker", "ground"]
        .iter()
        .any(|w| n.contains(w))
}

/// The experiment the columns describe, or the error that says what to choose.
fn choose<'a>(path: &Path, others: &[&'a Column], options: &InitOptions) -> Result<Chosen<'a>> {
    let listed = || {
        others
            .iter()
            .map(|c| format!("{:?}", c.name))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let named = |name: &str| {
        others
            .iter()
            .copied()
            .find(|c| c.name == name)
            .ok_or_else(|| {
                ExperimentError::data(
                    path,
                    format!("no column {name:?}: the file's columns are {}", listed()),
                )
            })
    };
    let mut channels: Vec<Channel<'a>> = Vec::new();
    let mut unused = Vec::new();
    if options.input.is_some() || !options.outputs.is_empty() {
        for name in options.input.iter().chain(&options.outputs) {
            let column = named(name)?;
            let found = channel(column);
            let role = match (
                found.as_ref().map(|c| c.role),
                Some(name) == options.input.as_ref(),
            ) {
                (Some(role), _) => role,
                (None, true) => Role::Force(1.0),
                (None, false) => Role::Motion(Quantity::Displacement, 1.0),
            };
            let because =
                found.map_or_else(|| "your choice (SI units assumed)".into(), |c| c.because);
            channels.push(Channel {
                column,
                role,
                because,
            });
        }
        unused.extend(
            others
                .iter()
                .copied()
                .filter(|c| !channels.iter().any(|k| std::ptr::eq(k.column, *c))),
        );
    } else {
        for column in others {
            match channel(column) {
                Some(c) => channels.push(c),
                None => unused.push(*column),
            }
        }
    }
    let input_named = options.input.as_deref();
    let (forces, motions): (Vec<_>, Vec<_>) = channels.into_iter().partition(|c| {
        matches!(c.role, Role::Force(_)) || input_named == Some(c.column.name.as_str())
    });
    let choose_input = |why: String| {
        ExperimentError::data(
            path,
            format!(
                "{why}; the file's columns are {}: name the input (--input COLUMN) and the responses (--output COLUMN, once each)",
                listed()
            ),
        )
    };
    let mut forces = forces.into_iter();
    let (input, mut responses) = match (forces.next(), forces.next()) {
        (Some(_), Some(_)) => {
            return Err(choose_input("two columns or more look like forces".into()));
        }
        (Some(force), None) => (Some(force), motions),
        (None, _) => (None, motions),
    };
    if responses.is_empty() {
        return Err(choose_input(
            "no column is a displacement, velocity or acceleration by its unit or name".into(),
        ));
    }
    let (excitation, input) = match input {
        Some(input) => match input.role {
            Role::Force(_) => ("force", Some(input)),
            Role::Motion(Quantity::Acceleration, _) => ("base_acceleration", Some(input)),
            Role::Motion(Quantity::Displacement, _) => ("base_displacement", Some(input)),
            Role::Motion(_, _) => {
                return Err(choose_input("the input measures a velocity: a base is driven by its acceleration or displacement".into()));
            }
        },
        None => match responses.iter().position(|c| is_base(c.column)) {
            Some(k) if responses.len() > 1 => {
                let base = responses.remove(k);
                match base.role {
                    Role::Motion(Quantity::Acceleration, _) => ("base_acceleration", Some(base)),
                    Role::Motion(Quantity::Displacement, _) => ("base_displacement", Some(base)),
                    _ => {
                        return Err(choose_input(format!(
                            "{:?} looks like the base's sensor but measures neither an acceleration nor a displacement",
                            base.column.name
                        )));
                    }
                }
            }
            _ if responses.len() == 1 => ("none", None),
            _ => {
                return Err(choose_input(
                    "no column looks like a force or the base's motion, and several respond".into(),
                ));
            }
        },
    };
    Ok(Chosen {
        excitation,
        input,
        responses,
        unused,
    })
}

/// The comment block at the top: what was read and chosen.
fn header(path: &Path, survey: &Survey, config_path: &Path, chosen: &Chosen<'_>) -> String {
    let file = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let mut out =
        format!("# Written by `msd init {file}`: a config for that file, as it was read.\n");
    for line in survey.description.lines().skip(1) {
        let _ = writeln!(out, "#{line}");
    }
    let _ = writeln!(out, "#");
    for line in chosen.roles() {
        let _ = writeln!(out, "# {line}");
    }
    let _ = writeln!(
        out,
        "#\n# Run it:  msd run {}\n# Change a column's role by editing below (or: msd init FILE --input COLUMN --output COLUMN).\n",
        config_path.display()
    );
    let stem = path.file_stem().map_or_else(
        || "my-experiment".into(),
        |s| s.to_string_lossy().into_owned(),
    );
    let name: String = stem
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '-'
            }
        })
        .collect();
    let _ = writeln!(
        out,
        "name = {name:?}\ndescription = {:?}\n",
        format!("{file}, read by msd init")
    );
    out
}

/// The `[setup]` section.
fn write_setup(out: &mut String, chosen: &Chosen<'_>, keys: &[String]) {
    let _ = writeln!(out, "[setup]\nexcitation = {:?}", chosen.excitation);
    let _ = writeln!(out, "responses = [");
    for r in &chosen.responses {
        let Role::Motion(quantity, scale) = r.role else {
            continue;
        };
        let unit = unit(r.column).filter(|_| scale != 1.0);
        let unit = unit.map_or_else(String::new, |u| format!(", unit = {u:?}"));
        let _ = writeln!(
            out,
            "    {{ quantity = {:?}, column = {}, scale = {}{unit} }},    # {}",
            quantity.to_string(),
            column_key(r.column, keys),
            scale,
            scale_comment(r.column, quantity, scale),
        );
    }
    let _ = writeln!(out, "]");
    match chosen.excitation {
        "force" => {
            let _ = writeln!(
                out,
                "# known_mass = 1.0    # kg, when the mass is weighed: every other interval tightens"
            );
        }
        _ => {
            let _ = writeln!(
                out,
                "# known_mass = 1.0    # kg, when the mass is weighed: without it, fn and ζ (and k/m, c/m) only"
            );
        }
    }
    let _ = writeln!(
        out,
        "# hold_out = 0.2      # the share at the record's end predicted by the fit to the rest\n"
    );
}

/// The column's unit when it is not one of a quantity's (a voltage): its scale is the
/// sensor's sensitivity, which the file does not give.
fn foreign_unit(column: &Column) -> Option<&str> {
    let unit = unit(column)?;
    role_of_unit(unit).is_none().then_some(unit)
}

/// The comment beside a scale: what it converts, or that it is to be set.
fn scale_comment(column: &Column, quantity: Quantity, scale: f64) -> String {
    match foreign_unit(column) {
        Some(unit) => format!(
            "SET the sensor's sensitivity: {} per {unit} (1 reads the file's numbers as {})",
            si_unit(quantity),
            si_unit(quantity)
        ),
        None => si_comment(quantity, scale),
    }
}

/// The SI unit of `quantity`.
fn si_unit(quantity: Quantity) -> &'static str {
    match quantity {
        Quantity::Displacement => "m",
        Quantity::Velocity => "m/s",
        Quantity::Acceleration => "m/s²",
        Quantity::Force => "N",
    }
}

/// "m/s² (from g)" and the like.
fn si_comment(quantity: Quantity, scale: f64) -> String {
    let si = si_unit(quantity);
    if scale == 1.0 {
        format!("read in {si}")
    } else {
        format!("× {} to {si}", scale)
    }
}

/// The `[data]` section.
fn write_data(
    out: &mut String,
    survey: &Survey,
    grid: &Grid<'_>,
    config_path: &Path,
    path: &Path,
    chosen: &Chosen<'_>,
) {
    let relative = relative_path(path, config_path);
    let _ = writeln!(
        out,
        "[data]\npath = {relative:?}    # relative to this file"
    );
    for key in &survey.keys {
        let _ = writeln!(out, "{key}");
    }
    match grid {
        Grid::Time(t) => {
            let _ = writeln!(out, "time = {}    # s", column_key(t, &survey.keys));
        }
        Grid::Rate(rate, from) => {
            let _ = writeln!(out, "sample_rate = {rate}    # Hz, {from}");
        }
    }
    if let Some(input) = &chosen.input {
        let _ = writeln!(out, "input = {}", column_key(input.column, &survey.keys));
        match input.role {
            Role::Force(scale) => {
                if foreign_unit(input.column).is_some() || scale != 1.0 {
                    let comment = scale_comment(input.column, Quantity::Force, scale);
                    let _ = writeln!(out, "input_scale = {}    # {comment}", scale);
                }
                let _ = writeln!(out, "input_unit = \"N\"");
            }
            Role::Motion(quantity, scale) => {
                if foreign_unit(input.column).is_some() || scale != 1.0 {
                    let _ = writeln!(
                        out,
                        "input_scale = {}    # {}",
                        scale,
                        scale_comment(input.column, quantity, scale)
                    );
                }
            }
        }
    }
    let _ = writeln!(out);
}

/// `path` as the config at `config_path` names it: relative to its folder when the data
/// file sits there or below, else absolute.
fn relative_path(path: &Path, config_path: &Path) -> String {
    let folder = config_path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let absolute = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let (data, folder) = (absolute(path), absolute(folder));
    data.strip_prefix(&folder)
        .map(Path::to_path_buf)
        .unwrap_or(data)
        .to_string_lossy()
        .replace('\\', "/")
}

/// The estimation section every measured record needs.
const ESTIMATION: &str = "[estimation]
initial_guess = \"auto\"          # from the record's own resonance
estimate_initial_state = true   # a measured record need not start at rest
estimate_offset = true          # each channel's constant offset
";

#[cfg(test)]
mod tests {
    use super::*;

    fn column(name: &str, unit: Option<&str>) -> Column {
        Column {
            name: name.into(),
            unit: unit.map(Into::into),
            rows: 10,
            range: None,
            step: None,
            stamps: None,
            rate: None,
            complex: false,
        }
    }

    /// A time column in ms (or µs, min) is read as the sampling rate its step gives:
    /// read as seconds, `Time [ms]` would put every frequency 1000× low. In seconds, or
    /// with no unit, it is the time.
    #[test]
    fn a_time_column_in_milliseconds_gives_the_rate() {
        let timed = |name: &str, unit: Option<&str>, step: f64| Column {
            step: Some(step),
            ..column(name, unit)
        };
        let rate = |c: &Column| match time_grid(c) {
            Grid::Rate(rate, from) => Some((rate, from)),
            Grid::Time(_) => None,
        };
        let (r, from) = rate(&timed("Time [ms]", None, 1.0)).expect("a rate");
        assert_eq!(r, 1000.0);
        assert_eq!(from, "from the step of \"Time [ms]\", 1 ms");
        assert_eq!(
            rate(&timed("t", Some("us"), 50.0)).map(|r| r.0),
            Some(20_000.0)
        );
        assert_eq!(
            rate(&timed("t", Some("min"), 0.5)).map(|r| r.0),
            Some(1.0 / 30.0)
        );
        assert!(rate(&timed("time (s)", None, 1e-3)).is_none());
        assert!(rate(&timed("t", None, 1e-3)).is_none());
    }

    /// A column counting samples (an oscilloscope's `X`, a logger's `Sample`) rises by
    /// a uniform step of 1: taken as the time it would put every frequency at 1 Hz per
    /// sample rate. It is passed over for the time, and the lines ask for the rate;
    /// a time in seconds at 1 Hz named so stays the time.
    #[test]
    fn a_sample_counter_is_not_the_time() {
        let counter = Column {
            step: Some(1.0),
            range: Some((0.0, 9.0)),
            ..column("Sample", None)
        };
        let seconds = Column {
            step: Some(1.0),
            range: Some((0.0, 9.0)),
            ..column("Time (s)", None)
        };
        // A frequency table's lines at 1 Hz, 2 Hz, …: the frequency, not a counter.
        let lines = Column {
            step: Some(1.0),
            range: Some((1.0, 9.0)),
            ..column("Frequency", None)
        };
        assert!(counter.is_counter() && !seconds.is_counter() && !lines.is_counter());
        let frf = config_lines(
            "frf.csv",
            &[lines, column("Re", None), column("Im", None)],
            &[],
        );
        assert!(
            frf.contains(
                "[frequency_response.table]\npath = \"frf.csv\"\nfrequency = \"Frequency\""
            ),
            "{frf}"
        );
        let force = Column {
            range: Some((-1.0, 1.0)),
            ..column("Force", Some("N"))
        };
        let columns = [counter, force, column("Accel", Some("g"))];
        assert!(time_column(&columns).is_none());
        let lines = config_lines("run.csv", &columns, &[]);
        assert!(
            lines.contains(
                "sample_rate = …    # Hz; \"Sample\" counts samples, it is not a time\ninput = \"Force\"\noutput = \"Accel\""
            ),
            "{lines}"
        );
    }

    #[test]
    fn a_unit_in_the_name_counts() {
        let c = column("accel [g]", None);
        assert_eq!(unit(&c), Some("g"));
        assert_eq!(
            channel(&c).unwrap().role,
            Role::Motion(Quantity::Acceleration, STANDARD_GRAVITY)
        );
        assert_eq!(unit(&column("F (kN)", None)), Some("kN"));
        assert_eq!(unit(&column("x", Some("mm"))), Some("mm"));
        assert_eq!(unit(&column("[g]", None)), Some("g"));
        assert_eq!(unit(&column("speed)", None)), None);
    }

    #[test]
    fn units_decide_before_names() {
        // A column named "acc" in mm is a displacement: the unit is the measurement.
        let c = column("acc_sensor", Some("mm"));
        assert_eq!(
            channel(&c).unwrap().role,
            Role::Motion(Quantity::Displacement, 1e-3)
        );
        let c = column("ch3", Some("g"));
        assert_eq!(
            channel(&c).unwrap().role,
            Role::Motion(Quantity::Acceleration, STANDARD_GRAVITY)
        );
        let c = column("Load cell", Some("V"));
        assert_eq!(channel(&c).unwrap().role, Role::Force(1.0));
        assert!(channel(&column("ch1", Some("V"))).is_none());
    }

    #[test]
    fn the_columns_choose_the_experiment() {
        let path = Path::new("x.csv");
        let (f, a, b) = (
            column("force", Some("N")),
            column("accel", Some("g")),
            column("base_acc", Some("g")),
        );
        let chosen = choose(path, &[&f, &a], &InitOptions::default()).unwrap();
        assert_eq!(chosen.excitation, "force");
        let chosen = choose(path, &[&b, &a], &InitOptions::default()).unwrap();
        assert_eq!(
            (chosen.excitation, chosen.responses.len()),
            ("base_acceleration", 1)
        );
        let chosen = choose(path, &[&a], &InitOptions::default()).unwrap();
        assert_eq!(chosen.excitation, "none");
        let two = column("force2", Some("kN"));
        let message = choose(path, &[&f, &two, &a], &InitOptions::default())
            .err()
            .unwrap()
            .to_string();
        assert!(
            message.contains("--input") && message.contains("\"force2\""),
            "{message}"
        );
        let options = InitOptions {
            input: Some("force2".into()),
            outputs: vec!["accel".into()],
            ..Default::default()
        };
        let chosen = choose(path, &[&f, &two, &a], &options).unwrap();
        assert_eq!(chosen.input.unwrap().role, Role::Force(1e3));
        assert_eq!(chosen.unused.len(), 1);
    }
}
