//! The one format every kind's printed summary takes, the paper's being the model: the
//! experiment's name and what ran; the verdict; the estimates as a table with their 95 %
//! intervals (and the truth where it is known); the modes as a table; what the kind adds
//! (checks, notes, warnings), each line under a label in one column; then the writer's
//! footer, written once for every kind: each stage's time and where the results are.
//!
//! Every number of an estimate and its interval carries the digits its interval's width
//! needs ([`digits`]), so that the two ends of a narrow interval never print alike.

use crate::fmt::{millis, sig};
use crate::verdict::Verdict;
use std::fmt::Write;
use std::path::Path;
use std::time::Duration;

/// The width of the label column.
const LABEL: usize = 14;

/// The summary's first line: `experiment `name` (what)`.
pub(crate) fn head(s: &mut String, name: &str, what: &str) {
    let _ = writeln!(s, "experiment `{name}` ({what})");
}

/// `text` under `label` in the label column; its further lines aligned under its first.
pub(crate) fn labelled(s: &mut String, label: &str, text: &str) {
    for (i, line) in text.lines().enumerate() {
        let label = if i == 0 { label } else { "" };
        let _ = writeln!(s, "  {label:<LABEL$} {line}");
    }
}

/// Where the data came from: `synthetic data, seed N` (with the seed of a synthetic
/// run) or `measured data`.
pub(crate) fn data(synthetic_seed: Option<u64>) -> String {
    synthetic_seed.map_or_else(
        || "measured data".into(),
        |seed| format!("synthetic data, seed {seed}"),
    )
}

/// `n` and the noun it counts, as `1 mass` or `2 masses`.
pub(crate) fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The check on fresh data, under `validation`: how the data were held out (`how`), the
/// worst prediction's R² and fit % (and which it was).
pub(crate) fn fresh_data(
    s: &mut String,
    how: &str,
    worst: &msd_ident::FitMetrics,
    which: Option<&str>,
) {
    let which = which.map_or_else(String::new, |w| format!(" ({w})"));
    labelled(
        s,
        "validation",
        &format!(
            "on fresh data ({how}): worst R² {}{which}, fit {} %",
            sig(worst.r_squared, 5),
            sig(worst.fit_percent, 4)
        ),
    );
}

/// The verdict, under its label.
pub(crate) fn verdict(s: &mut String, v: &Verdict) {
    labelled(s, "verdict", &v.to_string());
}

/// Significant digits for `value` and its interval `[low, high]`: enough that the ends
/// differ in their last two digits, at least 5 and at most 10 (5 where the interval has
/// no width).
///
/// ```ignore
/// assert_eq!(digits(2.4981, [2.4953, 2.5009]), 5);
/// assert_eq!(digits(6.61035, [6.61034, 6.61037]), 7);
/// ```
pub(crate) fn digits(value: f64, [low, high]: [f64; 2]) -> usize {
    let width = high - low;
    let size = value.abs().max(low.abs()).max(high.abs());
    if !(width.is_finite() && width > 0.0 && size.is_finite() && size > 0.0) {
        return 5;
    }
    let d = size.log10().floor() - width.log10().floor() + 2.0;
    (d.max(5.0) as usize).min(10)
}

/// One row of the estimates' table.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Estimate {
    /// The quantity with its unit, as `m [kg]`.
    pub label: String,
    /// The estimate.
    pub value: f64,
    /// Its 95 % interval; `None` for a value held known.
    pub interval: Option<[f64; 2]>,
    /// The true value, where it is known.
    pub truth: Option<f64>,
}

/// The estimates as a table: quantity, the truth (where any is known), the estimate and
/// its 95 % interval.
pub(crate) fn estimates(s: &mut String, rows: &[Estimate]) {
    if rows.is_empty() {
        return;
    }
    let cells: Vec<[String; 3]> = rows.iter().map(estimate_cells).collect();
    let any_truth = rows.iter().any(|r| r.truth.is_some());
    let label = rows
        .iter()
        .map(|r| r.label.chars().count())
        .max()
        .unwrap_or(0);
    let label = label.max(LABEL);
    let [truth, value] = [0, 1].map(|i| cells.iter().map(|c| c[i].len()).max().unwrap_or(0));
    let truth = if any_truth { truth.max(4) } else { 0 };
    let value = value.max(8);
    let _ = writeln!(
        s,
        "  {:<label$} {:>truth$}  {:>value$}   95 % interval",
        "quantity",
        if any_truth { "true" } else { "" },
        "estimate",
    );
    for (row, [t, v, i]) in rows.iter().zip(&cells) {
        let _ = writeln!(s, "  {:<label$} {t:>truth$}  {v:>value$}   {i}", row.label);
    }
}

/// The truth, the estimate and the interval of `row`, to the interval's digits.
fn estimate_cells(row: &Estimate) -> [String; 3] {
    let d = row
        .interval
        .map_or(6, |interval| digits(row.value, interval));
    [
        row.truth.map(|t| sig(t, d)).unwrap_or_default(),
        sig(row.value, d),
        match row.interval {
            Some([low, high]) => format!("[{}, {}]", sig(low, d), sig(high, d)),
            None => "known, held fixed".into(),
        },
    ]
}

/// One row of the modes' table.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ModeRow {
    /// Natural frequency, Hz, and its 95 % interval.
    pub frequency_hz: (f64, [f64; 2]),
    /// Damping ratio and its 95 % interval.
    pub damping_ratio: (f64, [f64; 2]),
    /// What the kind adds at the end of the row (MPC, the records it was found in).
    pub note: String,
}

impl ModeRow {
    /// The row of `mode`, with `note`.
    pub(crate) fn of(mode: &msd_modal::Mode, note: String) -> Self {
        let (f, z) = (&mode.natural_frequency_hz, &mode.damping_ratio);
        Self {
            frequency_hz: (f.value, f.ci95),
            damping_ratio: (z.value, z.ci95),
            note,
        }
    }
}

/// The modes as a table: each mode's fn and ζ with their 95 % intervals, and its note.
pub(crate) fn modes(s: &mut String, rows: &[ModeRow]) {
    if rows.is_empty() {
        return;
    }
    let cells: Vec<[String; 4]> = rows
        .iter()
        .map(|r| {
            let [f, z] = [r.frequency_hz, r.damping_ratio].map(|(v, [lo, hi])| {
                let d = digits(v, [lo, hi]);
                (sig(v, d), format!("[{}, {}]", sig(lo, d), sig(hi, d)))
            });
            [f.0, f.1, z.0, z.1]
        })
        .collect();
    let width = |i: usize, min: usize| cells.iter().map(|c| c[i].len()).max().unwrap_or(0).max(min);
    let w = [width(0, 7), width(1, 13), width(2, 5), width(3, 13)];
    let header = format!(
        "  {:<6} {:>w0$}   {:<w1$}   {:>w2$}   {:<w3$}",
        "mode",
        "fn [Hz]",
        "95 % interval",
        "ζ [-]",
        "95 % interval",
        w0 = w[0],
        w1 = w[1],
        w2 = w[2],
        w3 = w[3],
    );
    let _ = writeln!(s, "{}", header.trim_end());
    for (k, (row, c)) in rows.iter().zip(&cells).enumerate() {
        let line = format!(
            "  {:<6} {:>w0$}   {:<w1$}   {:>w2$}   {:<w3$}   {}",
            k + 1,
            c[0],
            c[1],
            c[2],
            c[3],
            row.note,
            w0 = w[0],
            w1 = w[1],
            w2 = w[2],
            w3 = w[3],
        );
        let _ = writeln!(s, "{}", line.trim_end());
    }
}

/// The stage names as printed.
pub(crate) fn stage_label(name: &str) -> &str {
    match name {
        "frequency_check" => "frequency check",
        "monte_carlo" | "monte carlo" => "Monte Carlo",
        "nonlinear" => "nonlinear models",
        other => other,
    }
}

/// The footer every summary ends with: each stage's time (the kind's `stages`, then the
/// writer's `extra`), the total, and where the results are.
pub(crate) fn footer(
    s: &mut String,
    stages: &[(&'static str, Duration)],
    extra: &[(&'static str, Duration)],
    total: Duration,
    target: &Path,
) {
    let times: Vec<String> = stages
        .iter()
        .chain(extra)
        .map(|(name, d)| format!("{} {}", stage_label(name), millis(*d)))
        .collect();
    if !s.is_empty() && !s.ends_with('\n') {
        s.push('\n');
    }
    s.push('\n');
    labelled(
        s,
        "time [ms]",
        &format!("{} · total {}", times.join(" · "), millis(total)),
    );
    labelled(
        s,
        "report",
        &format!("{} (and report.md)", target.join("report.html").display()),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_digits_resolve_the_interval() {
        assert_eq!(digits(2.4981, [2.4953, 2.5009]), 5);
        assert_eq!(digits(6.61035, [6.61034, 6.61037]), 7);
        assert_eq!(digits(1.0, [1.0, 1.0]), 5);
        assert_eq!(digits(1.0, [f64::NAN, 1.0]), 5);
        assert_eq!(digits(1e6, [1e6 - 1e-9, 1e6 + 1e-9]), 10);
        // The ends of a narrow interval never print alike.
        let (v, lo, hi) = (6.61035, 6.610342, 6.610371);
        let d = digits(v, [lo, hi]);
        assert_ne!(sig(lo, d), sig(hi, d));
    }

    #[test]
    fn the_tables_align_and_say_what_is_known() {
        let mut s = String::new();
        let rows = [
            Estimate {
                label: "m [kg]".into(),
                value: 2.4981,
                interval: Some([2.4953, 2.5009]),
                truth: Some(2.5),
            },
            Estimate {
                label: "k [N/m]".into(),
                value: 120.0,
                interval: None,
                truth: None,
            },
        ];
        estimates(&mut s, &rows);
        let lines: Vec<&str> = s.lines().collect();
        assert_eq!(lines.len(), 3, "{s}");
        assert!(lines[0].contains("true") && lines[0].contains("95 % interval"));
        assert!(lines[1].contains("2.5000") && lines[1].contains("[2.4953, 2.5009]"));
        assert!(lines[2].contains("known, held fixed"), "{s}");
        let column = |l: &str| {
            l.find("95 % interval")
                .or_else(|| l.rfind('['))
                .or_else(|| l.find("known"))
        };
        assert_eq!(column(lines[0]), column(lines[1]));
        let mut s = String::new();
        modes(
            &mut s,
            &[ModeRow {
                frequency_hz: (6.61035, [6.61034, 6.61037]),
                damping_ratio: (0.00752944, [0.00752709, 0.00753179]),
                note: "MPC 1.000".into(),
            }],
        );
        assert!(
            s.contains("[6.610340, 6.610370]") && s.ends_with("MPC 1.000\n"),
            "{s}"
        );
    }
}
