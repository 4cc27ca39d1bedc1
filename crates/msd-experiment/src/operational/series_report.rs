//! What a run over several records writes: `report.md` (the verdict, the records, the
//! modes over them with the records that found each and how well their references agree,
//! fn and ζ record by record, the figure), `results.json`, `modes.csv` and `shapes.csv`
//! (the combined modes), `tracks.csv` (each mode in each record) and `modes.uff`.

use super::series::{SeriesOutcome, lowest_reference_mac};
use super::{mode_tables, plots};
use crate::config::Config;
use crate::error::{ExperimentError, Result};
use crate::fmt::sig;
use crate::results::Header;
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;
use std::time::Duration;

/// What the run identifies from what, for the summary's and the report's head.
fn what(o: &SeriesOutcome) -> String {
    let method = o.records.first().map(|r| r.fit.method.to_string());
    format!(
        "output-only modal analysis by {}: {} records, each analysed alone and the modes joined; measured data",
        method.unwrap_or_default(),
        o.records.len()
    )
}

fn page(s: &mut String, o: &SeriesOutcome, figures: &[&str]) -> std::fmt::Result {
    let run = (&o.config, o.config_path.as_path(), o.command.as_str());
    crate::results::report_head(s, run, &what(o), None, &[])?;
    crate::verdict::section(s, &o.verdict)?;
    writeln!(s, "## Records\n")?;
    writeln!(
        s,
        "| record | file | channels | samples | modes | left out |\n|---|---|---|---|---|---|"
    )?;
    for r in &o.records {
        writeln!(
            s,
            "| {} | `{}` | {} | {} | {} | {} |",
            r.label,
            r.path.display(),
            r.record.channels().len(),
            r.record.len(),
            r.fit.modes.len(),
            if r.left_out.is_empty() {
                "—".to_string()
            } else {
                r.left_out
                    .iter()
                    .map(|(n, _)| n.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            }
        )?;
    }
    writeln!(s)?;
    modes(s, o)?;
    tracks(s, o)?;
    for f in figures.iter().filter(|f| !f.ends_with(".uff")) {
        writeln!(s, "![{f}]({f}.png)\n")?;
    }
    writeln!(s, "## Method\n")?;
    writeln!(
        s,
        "Each record analysed alone ({}; its own intervals from its own jackknife), then combined (msd-modal's `merge_setups`, PoSER): a mode of one record is a mode of another when their fn are within {} % (the nearest; the higher MAC on the shared DOFs where two qualify); each record's shape is scaled onto the first finder's entries at the DOFs every record measures (the references) and its other DOFs joined. fn and ζ of a mode are the mean over the records that found it, their intervals from the records' scatter (Student's t on n − 1 degrees of freedom); for setups of one structure that is the merged estimate, for a monitored structure the mean over the period (its record-by-record values are in the table above, the figure and `tracks.csv`).\n",
        o.records
            .first()
            .map_or(String::new(), |r| r.fit.method.to_string()),
        sig(
            100.0
                * o.config
                    .operational
                    .as_ref()
                    .map_or(0.01, |c| c.merge_tolerance),
            2
        )
    )?;
    writeln!(s, "## Files\n")?;
    writeln!(
        s,
        "`results.json` (every record's modes and the combined modes), `modes.csv` and `shapes.csv` (the combined modes and their shapes over every DOF), `tracks.csv` (each mode in each record), `modes.uff` (the combined shapes as UFF datasets 55), the figures as PNG and SVG.\n"
    )
}

fn modes(s: &mut String, o: &SeriesOutcome) -> std::fmt::Result {
    let m = &o.merged;
    writeln!(s, "## Modes over the records\n")?;
    writeln!(
        s,
        "Shapes over {} DOFs ({} shared by every record: the references). \n",
        m.modes.first().map_or(0, |m| m.shape.len()),
        m.reference_dofs.len()
    )?;
    writeln!(
        s,
        "| mode | fn [Hz] (95 % CI) | ζ [%] (95 % CI) | found in | lowest reference MAC |\n|---|---|---|---|---|"
    )?;
    for (k, mode) in m.modes.iter().enumerate() {
        let [fv, f0, f1, zv, z0, z1] = cells(mode);
        writeln!(
            s,
            "| {} | {fv} ({f0} … {f1}) | {zv} ({z0} … {z1}) | {} of {} | {} |",
            k + 1,
            m.found[k].iter().flatten().count(),
            o.records.len(),
            lowest_reference_mac(m, k).map_or("—".into(), |v| format!("{v:.3}"))
        )?;
    }
    writeln!(s)
}

/// fn [Hz] and ζ [%] with their intervals' ends, as the report prints them.
fn cells(mode: &msd_modal::Mode) -> [String; 6] {
    let (f, z) = (&mode.natural_frequency_hz, &mode.damping_ratio);
    [
        sig(f.value, 6),
        sig(f.ci95[0], 6),
        sig(f.ci95[1], 6),
        sig(100.0 * z.value, 3),
        sig(100.0 * z.ci95[0], 3),
        sig(100.0 * z.ci95[1], 3),
    ]
}

fn tracks(s: &mut String, o: &SeriesOutcome) -> std::fmt::Result {
    writeln!(
        s,
        "### fn [Hz] record by record (— where a record did not find the mode)\n"
    )?;
    write!(s, "| mode |")?;
    for r in &o.records {
        write!(s, " {} |", r.label)?;
    }
    writeln!(s, "\n|---|{}", "---|".repeat(o.records.len()))?;
    for (k, found) in o.merged.found.iter().enumerate() {
        write!(s, "| {} |", k + 1)?;
        for (r, index) in found.iter().enumerate() {
            match index {
                Some(i) => write!(
                    s,
                    " {} |",
                    sig(o.records[r].fit.modes[*i].natural_frequency_hz.value, 5)
                )?,
                None => write!(s, " — |")?,
            }
        }
        writeln!(s)?;
    }
    writeln!(s)
}

/// `tracks.csv`: one line per mode and record that found it.
fn tracks_csv(o: &SeriesOutcome) -> String {
    let mut t = String::from(
        "mode,record,label,natural_frequency_hz,ci95_low_hz,ci95_high_hz,damping_ratio,damping_ci95_low,damping_ci95_high,reference_mac\n",
    );
    for (k, found) in o.merged.found.iter().enumerate() {
        for (r, index) in found.iter().enumerate() {
            let Some(i) = index else { continue };
            let mode = &o.records[r].fit.modes[*i];
            let (f, z) = (&mode.natural_frequency_hz, &mode.damping_ratio);
            let mac = o.merged.reference_mac[k][r].unwrap_or(f64::NAN);
            t += &format!(
                "{},{},\"{}\",{},{},{},{},{},{},{mac}\n",
                k + 1,
                r + 1,
                o.records[r].label.replace('"', "\"\""),
                f.value,
                f.ci95[0],
                f.ci95[1],
                z.value,
                z.ci95[0],
                z.ci95[1]
            );
        }
    }
    t
}

#[derive(Serialize)]
struct RecordResult<'a> {
    path: String,
    label: &'a str,
    samples: usize,
    channels: Vec<&'a str>,
    left_out: Vec<&'a str>,
    /// The record's own method and settings, modes and unconfirmed columns (its diagram
    /// is left out: ten of them weigh megabytes; one record's run writes it).
    settings: String,
    modes: &'a [msd_modal::Mode],
    unconfirmed: &'a [msd_modal::StableColumn],
}

/// How the records combine: the DOFs every record measured, which record found which
/// mode (its index there) and the MAC of its reference entries (the modes themselves are
/// `modes[]`).
#[derive(Serialize)]
struct Combination<'a> {
    reference_dofs: &'a [msd_modal::Dof],
    found: &'a [Vec<Option<usize>>],
    reference_mac: &'a [Vec<Option<f64>>],
}

#[derive(Serialize)]
struct Results<'a> {
    experiment: Header<'a>,
    command: &'a str,
    verdict: &'a crate::verdict::Verdict,
    records: Vec<RecordResult<'a>>,
    merge_tolerance: f64,
    merged: Combination<'a>,
    modes: &'a [msd_modal::Mode],
    timings_ms: BTreeMap<&'static str, f64>,
}

fn results(
    o: &SeriesOutcome,
    extra: &[(&'static str, Duration)],
    total: Duration,
) -> Result<serde_json::Value> {
    let results = Results {
        experiment: Header::new(&o.config, &o.config_path, "measured", o.config.seed, None),
        command: &o.command,
        verdict: &o.verdict,
        records: o
            .records
            .iter()
            .map(|r| RecordResult {
                path: r.path.display().to_string(),
                label: &r.label,
                samples: r.record.len(),
                channels: r
                    .record
                    .channels()
                    .iter()
                    .map(|c| c.name.as_str())
                    .collect(),
                left_out: r.left_out.iter().map(|(n, _)| n.as_str()).collect(),
                settings: format!("{}: {}", r.fit.method, r.fit.settings()),
                modes: &r.fit.modes,
                unconfirmed: &r.fit.unconfirmed,
            })
            .collect(),
        merge_tolerance: o
            .config
            .operational
            .as_ref()
            .map_or(0.01, |c| c.merge_tolerance),
        merged: Combination {
            reference_dofs: &o.merged.reference_dofs,
            found: &o.merged.found,
            reference_mac: &o.merged.reference_mac,
        },
        modes: &o.merged.modes,
        timings_ms: crate::results::timings_ms(&o.timings, extra, total),
    };
    serde_json::to_value(&results).map_err(|e| ExperimentError::run("write", e))
}

impl crate::finished::Finished for SeriesOutcome {
    fn config(&self) -> &Config {
        &self.config
    }

    fn figures(&self, dir: &Path) -> Result<Vec<&'static str>> {
        super::write_uff(&self.config.name, &self.merged.modes, dir)?;
        plots::write_tracks(self, dir)
    }

    fn tables(&self) -> Vec<(String, String)> {
        let mut tables = mode_tables(&self.merged.modes);
        tables.push(("tracks.csv".into(), tracks_csv(self)));
        tables
    }

    fn timings(&self) -> &[(&'static str, Duration)] {
        &self.timings
    }

    fn report(&self, figures: &[&str]) -> String {
        let mut s = String::new();
        // Writing into a String cannot fail.
        let _ = page(&mut s, self, figures);
        s
    }

    fn results(
        &self,
        extra: &[(&'static str, Duration)],
        total: Duration,
    ) -> Result<serde_json::Value> {
        results(self, extra, total)
    }

    fn summary(&self) -> String {
        let mut s = String::new();
        crate::summary::head(&mut s, &self.config.name, &what(self));
        crate::summary::verdict(&mut s, &self.verdict);
        s.push('\n');
        let rows: Vec<crate::summary::ModeRow> = (self.merged.modes.iter().enumerate())
            .map(|(k, m)| {
                let found = self.merged.found[k].iter().flatten().count();
                let note = format!("in {found} of {} records", self.records.len());
                crate::summary::ModeRow::of(m, note)
            })
            .collect();
        crate::summary::modes(&mut s, &rows);
        s
    }
}
