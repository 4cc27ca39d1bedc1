//! The benchmark table: rows with their targets, the machine they ran on, and the three
//! renderings (terminal text, Markdown for `BENCHMARKS.md`, JSON for
//! `target/bench/bench.json`).

use super::harness::Samples;
use crate::fmt;
use serde_json::{Value, json};
use std::fmt::Write as _;

/// A target a row is checked against (by reading the table, never in a test).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// At most this many seconds (median).
    Seconds(f64),
    /// At most this multiple of the floor's median.
    FloorMultiple(f64),
}

impl Target {
    /// The target in words, e.g. "≤ 40 ms" or "≤ 2× floor".
    pub fn text(&self) -> String {
        match *self {
            Target::Seconds(s) => format!("≤ {}", duration(s)),
            Target::FloorMultiple(m) => format!("≤ {m}× floor"),
        }
    }

    /// Whether a row with `median` seconds, `ratio` times the floor, meets the target.
    pub fn met(&self, median: f64, ratio: f64) -> bool {
        match *self {
            Target::Seconds(s) => median <= s,
            Target::FloorMultiple(m) => ratio <= m,
        }
    }
}

/// One row of the table.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Section: "floor", "simulation", "identification", …
    pub group: &'static str,
    /// What is measured.
    pub name: String,
    /// The timed repetitions.
    pub samples: Samples,
    /// Target, if the issue sets one.
    pub target: Option<Target>,
    /// Counts or other facts of the run (evaluations, iterations, samples per draw, …).
    pub note: String,
}

impl Row {
    /// A row without target or note.
    pub fn new(group: &'static str, name: impl Into<String>, samples: Samples) -> Self {
        Self {
            group,
            name: name.into(),
            samples,
            target: None,
            note: String::new(),
        }
    }

    /// With a target.
    pub fn target(mut self, target: Target) -> Self {
        self.target = Some(target);
        self
    }

    /// With a note.
    pub fn note(mut self, note: impl Into<String>) -> Self {
        self.note = note.into();
        self
    }
}

/// The machine and its load around the run.
#[derive(Debug, Clone, PartialEq)]
pub struct Machine {
    /// Logical cores (`available_parallelism`).
    pub cores: usize,
    /// `model name` from /proc/cpuinfo.
    pub cpu: String,
    /// /proc/loadavg (1, 5, 15 min) at the start.
    pub load_start: String,
    /// /proc/loadavg at the end.
    pub load_end: String,
    /// UTC date and time of the start (from `date -u`, else seconds since the epoch).
    pub date: String,
}

/// The whole result of a bench run.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// Where it ran.
    pub machine: Machine,
    /// Whether `--quick` was given.
    pub quick: bool,
    /// The floor's median, seconds (every ratio is to it).
    pub floor: f64,
    /// Every row, in order.
    pub rows: Vec<Row>,
    /// Derived figures (speed-ups, scaling flatness), one line each.
    pub derived: Vec<String>,
    /// Peak resident memory of the whole pipeline (paper method) in MiB, if known.
    pub peak_memory_mib: Option<f64>,
}

/// A duration in the unit that reads best: ns, µs, ms or s, three significant digits.
pub fn duration(seconds: f64) -> String {
    let (value, unit) = if seconds < 1e-6 {
        (seconds * 1e9, "ns")
    } else if seconds < 1e-3 {
        (seconds * 1e6, "µs")
    } else if seconds < 1.0 {
        (seconds * 1e3, "ms")
    } else {
        (seconds, "s")
    };
    format!("{} {unit}", fmt::sig(value, 3))
}

impl Report {
    fn ratio(&self, row: &Row) -> f64 {
        row.samples.median() / self.floor
    }

    fn verdict(&self, row: &Row) -> String {
        match row.target {
            Some(t) if t.met(row.samples.median(), self.ratio(row)) => format!("{} met", t.text()),
            Some(t) => format!("{} MISSED", t.text()),
            None => String::new(),
        }
    }

    fn header(&self) -> String {
        let m = &self.machine;
        format!(
            "{}; {} cores ({}); load average at start {}, at end {}; {}",
            m.date,
            m.cores,
            m.cpu,
            m.load_start,
            m.load_end,
            if self.quick { "--quick" } else { "full run" }
        )
    }

    /// The Markdown table (with the machine line and derived figures), ready for
    /// `BENCHMARKS.md`.
    pub fn markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "Measured {}.\n", self.header());
        s.push_str("| group | row | median | min – max | × floor | reps | target | notes |\n");
        s.push_str("|---|---|---:|---:|---:|---:|---|---|\n");
        for row in &self.rows {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} – {} | {} | {} | {} | {} |",
                row.group,
                row.name,
                duration(row.samples.median()),
                duration(row.samples.min()),
                duration(row.samples.max()),
                fmt::sig(self.ratio(row), 3),
                row.samples.seconds.len(),
                self.verdict(row),
                row.note
            );
        }
        s.push('\n');
        for line in &self.derived {
            let _ = writeln!(s, "- {line}");
        }
        if let Some(mib) = self.peak_memory_mib {
            let _ = writeln!(
                s,
                "- Peak resident memory of the whole paper pipeline (no figures): {mib:.1} MiB"
            );
        }
        s
    }

    /// The plain-text table for the terminal.
    pub fn text(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "cargo xtask bench: {}", self.header());
        let _ = writeln!(
            s,
            "{:<14} {:<58} {:>9} {:>21} {:>8} {:>4}  target",
            "group", "row", "median", "min – max", "× floor", "reps"
        );
        for row in &self.rows {
            let range = format!(
                "{} – {}",
                duration(row.samples.min()),
                duration(row.samples.max())
            );
            let _ = writeln!(
                s,
                "{:<14} {:<58} {:>9} {:>21} {:>8} {:>4}  {}{}",
                row.group,
                row.name,
                duration(row.samples.median()),
                range,
                fmt::sig(self.ratio(row), 3),
                row.samples.seconds.len(),
                self.verdict(row),
                if row.note.is_empty() {
                    String::new()
                } else {
                    format!("  [{}]", row.note)
                }
            );
        }
        for line in &self.derived {
            let _ = writeln!(s, "* {line}");
        }
        if let Some(mib) = self.peak_memory_mib {
            let _ = writeln!(
                s,
                "* peak resident memory, whole paper pipeline (no figures): {mib:.1} MiB"
            );
        }
        s
    }

    /// Every number, for `target/bench/bench.json`.
    pub fn json(&self) -> Value {
        let m = &self.machine;
        let rows: Vec<Value> = self
            .rows
            .iter()
            .map(|row| {
                json!({
                    "group": row.group,
                    "name": row.name,
                    "median_s": row.samples.median(),
                    "min_s": row.samples.min(),
                    "max_s": row.samples.max(),
                    "floor_multiple": self.ratio(row),
                    "repetitions": row.samples.seconds.len(),
                    "samples_s": row.samples.seconds,
                    "target": row.target.map(|t| t.text()),
                    "target_met": row.target.map(|t| t.met(row.samples.median(), self.ratio(row))),
                    "note": row.note,
                })
            })
            .collect();
        json!({
            "date": m.date,
            "cores": m.cores,
            "cpu": m.cpu,
            "load_average_start": m.load_start,
            "load_average_end": m.load_end,
            "quick": self.quick,
            "floor_median_s": self.floor,
            "rows": rows,
            "derived": self.derived,
            "peak_memory_mib": self.peak_memory_mib,
        })
    }
}

/// The machine's description and the current load.
pub fn machine() -> Machine {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let load = load_average();
    Machine {
        cores,
        cpu,
        load_start: load.clone(),
        load_end: load,
        date: now(),
    }
}

/// The 1, 5 and 15 minute load averages from /proc/loadavg ("unknown" elsewhere).
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

fn now() -> String {
    std::process::Command::new("date")
        .args(["-u", "+%Y-%m-%d %H:%M UTC"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|| {
            let secs = std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0, |d| d.as_secs());
            format!("{secs} s since the epoch")
        })
}

/// Peak resident set size (VmHWM) of this process in MiB, from /proc/self/status.
pub fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}
