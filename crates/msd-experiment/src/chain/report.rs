//! The report of a chain run, and the summary the command prints.

use super::{ChainOutcome, channel_names};
use crate::fmt::sig;
use crate::noise_report;
use crate::summary;
use msd_ident::{
    Interval,
    chain::{ChainFit, ChainUncertainty},
    records::ResidualWhiteness,
};
use std::fmt::Write;

/// `report.md` of `o`, with `figures` embedded.
pub(crate) fn markdown(o: &ChainOutcome, figures: &[&str]) -> String {
    let mut s = String::new();
    // Writing into a String cannot fail.
    let _ = page(&mut s, o, figures);
    s
}

/// The rows (name, truth, estimate) of every physical parameter; no truth for measured
/// records.
fn rows(o: &ChainOutcome, u: &ChainUncertainty) -> Vec<(String, Option<f64>, Option<Interval>)> {
    let chain = &o.chain;
    // The parameters the fit has: the true chain's layout, or the guess's.
    let layout = chain.plant.as_ref().unwrap_or(&chain.guess);
    let truth = chain.plant.as_ref();
    let iv = u.intervals.as_ref();
    let mut out = Vec::new();
    for i in 0..layout.masses.len() {
        out.push((
            format!("m{} [kg]", i + 1),
            truth.map(|t| t.masses[i]),
            iv.map(|v| v.masses[i]),
        ));
        out.push((
            format!("c{} [N·s/m]", i + 1),
            truth.map(|t| t.dampers[i]),
            iv.map(|v| v.dampers[i]),
        ));
        out.push((
            format!("k{} [N/m]", i + 1),
            truth.map(|t| t.springs[i]),
            iv.map(|v| v.springs[i]),
        ));
        let ground = [
            (
                "cg",
                "N·s/m",
                &layout.ground_dampers,
                iv.map(|v| &v.ground_dampers),
            ),
            (
                "kg",
                "N/m",
                &layout.ground_springs,
                iv.map(|v| &v.ground_springs),
            ),
        ];
        for (symbol, unit, values, fitted) in ground {
            if let Some(&t) = values.get(i).filter(|v| **v > 0.0) {
                let interval = fitted.and_then(|f| f.get(i).copied());
                out.push((
                    format!("{symbol}{} [{unit}]", i + 1),
                    truth.map(|_| t),
                    interval,
                ));
            }
        }
    }
    out
}

/// A truth for a table: its value, or "—" for measured records.
fn truth_text(truth: Option<f64>) -> String {
    truth.map_or_else(|| "—".into(), |t| sig(t, 6))
}

/// `## Fit`: the fit's statistics as a table (the estimates and modes are above).
fn fit_section(s: &mut String, o: &ChainOutcome) -> std::fmt::Result {
    let u = &o.fit.uncertainty;
    writeln!(s, "## Fit\n\n| | |\n|---|---|")?;
    writeln!(s, "| degrees of freedom | {} |", u.degrees_of_freedom)?;
    writeln!(
        s,
        "| condition number (scaled JᵀJ) | {} |",
        sig(u.condition_number, 4)
    )?;
    for (name, sigma) in channel_names(o).iter().zip(&o.fit.noise) {
        writeln!(s, "| noise σ̂ of {name} | {} |", sig(*sigma, 4))?;
    }
    for (i, d) in u.delays.iter().enumerate() {
        if let Some(d) = d {
            writeln!(s, "| delay of sensor {} [s] | {} |", i + 1, d)?;
        }
    }
    for (i, c) in u.cutoffs.iter().enumerate() {
        if let Some(c) = c {
            writeln!(s, "| filter cut-off of sensor {} [Hz] | {} |", i + 1, c)?;
        }
    }
    let model = o.fit.noise_model.to_string();
    let model = model.trim_start_matches("noise model: ");
    writeln!(
        s,
        "| noise model | {} |",
        model.replace('|', "\\|").replace('\n', " ")
    )?;
    writeln!(
        s,
        "| solver | {}, {} evaluations of the model |",
        o.fit.exit, o.fit.evaluations
    )?;
    for note in &o.fit.notes {
        writeln!(s, "| note | {} |", note.replace('|', "\\|"))?;
    }
    writeln!(s)
}

fn page(s: &mut String, o: &ChainOutcome, figures: &[&str]) -> std::fmt::Result {
    let chain = &o.chain;
    let run = (&o.config, o.config_path.as_path(), o.command.as_str());
    crate::results::report_head(s, run, &what(o), Some(o.seed), &[])?;
    crate::verdict::section(s, &o.verdict)?;
    writeln!(s, "## Chain\n")?;
    writeln!(
        s,
        "{} masses in a chain from the ground; drive: **{}**; {} samples every {} s ({}).\n",
        chain.size(),
        match chain.drive {
            msd_ident::chain::ChainDrive::Force => format!("force on mass {}", chain.force_at),
            msd_ident::chain::ChainDrive::BaseAcceleration => "base acceleration".into(),
        },
        o.record.len(),
        sig(o.record.dt, 4),
        if chain.plant.is_some() {
            "synthetic"
        } else {
            "measured"
        }
    )?;
    if !chain.known_masses.is_empty() {
        writeln!(s, "Known masses (held): {:?}.\n", chain.known_masses)?;
    }
    sensors(s, o, chain)?;
    writeln!(s, "\n## Estimates\n")?;
    estimates(s, o, &o.fit)?;
    writeln!(s, "\n## Modes\n")?;
    modes(s, o, &o.fit)?;
    if let Some(ideal) = &o.ideal {
        ignoring(s, o, ideal)?;
    }
    writeln!(s)?;
    noise(s, o)?;
    writeln!(s, "## Monte Carlo band\n")?;
    writeln!(
        s,
        "Every m, c and k drawn uniform within ±{} % of the estimate, {} draws; the band is the {}–{} percentile of each sensor's response, the paper's 90 % band (drawn in the figure).\n",
        msd_mc::ChainBandOptions::default().percent,
        o.band.samples,
        o.band.percentiles[0],
        o.band.percentiles[1]
    )?;
    if let Some(coverage) = &o.band.coverage {
        writeln!(
            s,
            "| sensor | share of the record inside the band |\n|---|---|"
        )?;
        for (name, c) in channel_names(o).iter().zip(coverage) {
            writeln!(s, "| {name} | {:.1} % |", 100.0 * c)?;
        }
    }
    writeln!(s)?;
    super::validation::section(s, o)?;
    fit_section(s, o)?;
    writeln!(s, "## Figures\n")?;
    for f in figures {
        let (alt, caption) = match *f {
            "chain_noise_spectrum" => noise_report::SPECTRUM_FIGURE,
            _ => (
                "The chain's fit",
                "The drive, then each sensor measured (blue points) and as the fitted chain predicts it (red line), with the Monte Carlo band (grey).",
            ),
        };
        writeln!(s, "![{alt}]({f}.png)\n\n*{caption}*\n")?;
    }
    Ok(())
}

/// The sensors' table: where each is, its column and scale (measured records) or its
/// noise and true delay (synthetic), the delay in the fit and its filter.
fn sensors(
    s: &mut String,
    o: &ChainOutcome,
    chain: &crate::config::ChainSection,
) -> std::fmt::Result {
    let measured = chain.plant.is_none();
    writeln!(
        s,
        "| sensor | mass | {} | delay in the fit | filter |\n|---|---|---|---|---|---|",
        if measured {
            "column | scale"
        } else {
            "noise σ | true delay [s]"
        }
    )?;
    for ((name, sensor), delay) in channel_names(o)
        .iter()
        .zip(&chain.sensors)
        .zip(&o.fit.uncertainty.delays)
    {
        let fitted = match delay {
            Some(d) => format!("estimated: {}", interval(d)),
            None => sensor
                .delay
                .map_or("none".into(), |d| format!("known, {}", sig(d, 4))),
        };
        let filter = sensor.low_pass.map_or("none".into(), |f| {
            format!("order {} low-pass at {} Hz", f.order, sig(f.cutoff_hz, 4))
        });
        let filter = match o
            .fit
            .uncertainty
            .cutoffs
            .get(sensor_index(o, name))
            .copied()
            .flatten()
        {
            Some(c) => format!("{filter}; cut-off estimated: {}", interval(&c)),
            None => filter,
        };
        let (first, second) = if measured {
            (
                sensor.column.as_ref().map_or("—".into(), |c| c.to_string()),
                sig(sensor.scale, 4),
            )
        } else {
            (
                sig(sensor.sigma, 4),
                sensor.delay.map_or("—".into(), |d| sig(d, 4)),
            )
        };
        writeln!(
            s,
            "| {name} | {} | {first} | {second} | {fitted} | {filter} |",
            sensor.at,
        )?;
    }
    Ok(())
}

fn interval(iv: &Interval) -> String {
    format!(
        "{} ± {} (95 % {} … {})",
        sig(iv.value, 6),
        sig(iv.standard_error, 2),
        sig(iv.ci95[0], 6),
        sig(iv.ci95[1], 6)
    )
}

/// A summary row of `iv`.
fn estimate(label: String, iv: &Interval, truth: Option<f64>) -> summary::Estimate {
    summary::Estimate {
        label,
        value: iv.value,
        interval: Some(iv.ci95),
        truth,
    }
}

fn estimates(s: &mut String, o: &ChainOutcome, fit: &ChainFit) -> std::fmt::Result {
    if fit.uncertainty.intervals.is_none() {
        writeln!(s, "**m, c and k are not identified from these records.**\n")?;
        for reason in &fit.uncertainty.unidentifiable {
            writeln!(s, "- {reason}")?;
        }
        writeln!(s, "\nWhat the records do fix is below: the modes.")?;
        return Ok(());
    }
    writeln!(
        s,
        "| parameter | truth | estimate ± SE (95 % CI) | (estimate − truth)/SE |\n|---|---|---|---|"
    )?;
    for (name, truth, iv) in rows(o, &fit.uncertainty) {
        let Some(iv) = iv else { continue };
        let z = match truth {
            _ if iv.standard_error <= 0.0 => "known".into(),
            Some(t) => format!("{:+.2}", (iv.value - t) / iv.standard_error),
            None => "—".into(),
        };
        writeln!(
            s,
            "| {name} | {} | {} | {z} |",
            truth_text(truth),
            interval(&iv)
        )?;
    }
    Ok(())
}

fn modes(s: &mut String, o: &ChainOutcome, fit: &ChainFit) -> std::fmt::Result {
    let truth = truth_modes(o);
    writeln!(
        s,
        "| mode | fn truth [Hz] | fn [Hz] | ζ truth | ζ | shape (largest = 1) |\n|---|---|---|---|---|---|"
    )?;
    for (i, mode) in fit.uncertainty.modes.iter().enumerate() {
        let (f, z) = truth
            .get(i)
            .map_or(("—".into(), "—".into()), |t| (sig(t.0, 6), sig(t.1, 4)));
        let shape: Vec<String> = mode
            .shape
            .iter()
            .map(|v| {
                let se = v.standard_error.map_or(0.0, |[re, _]| re);
                format!("{:.4} ± {}", v.re, sig(se, 2))
            })
            .collect();
        writeln!(
            s,
            "| {} | {f} | {} | {z} | {} | {} |",
            i + 1,
            interval(&mode.natural_frequency_hz),
            interval(&mode.damping_ratio),
            shape.join(", ")
        )?;
    }
    Ok(())
}

/// Each sensor's whiteness under the report's name for its channel.
pub(super) fn named_whiteness(o: &ChainOutcome) -> Vec<ResidualWhiteness> {
    o.fit
        .whiteness
        .iter()
        .zip(channel_names(o))
        .map(|(c, channel)| ResidualWhiteness {
            record: "the record".into(),
            channel,
            ..c.clone()
        })
        .collect()
}

/// The drive's unit.
fn drive_unit(o: &ChainOutcome) -> &'static str {
    match o.chain.drive {
        msd_ident::chain::ChainDrive::BaseAcceleration => "m/s²",
        msd_ident::chain::ChainDrive::Force => "N",
    }
}

/// The noise model, each sensor's whiteness, and the white-noise intervals it replaced.
fn noise(s: &mut String, o: &ChainOutcome) -> std::fmt::Result {
    let fit = &o.fit;
    let unit = drive_unit(o);
    noise_report::section(s, &fit.noise_model, &named_whiteness(o), unit, "[chain]")?;
    let Some(white) = &fit.white_noise_uncertainty else {
        return Ok(());
    };
    writeln!(
        s,
        "The intervals a white-noise fit would have reported:\n\n| quantity | estimate | 95 % interval |\n|---|---|---|"
    )?;
    let physical = rows(o, white);
    for (label, _, iv) in physical {
        if let Some(iv) = iv.filter(|iv| iv.standard_error > 0.0) {
            noise_report::white_row(s, &label, &iv)?;
        }
    }
    for (i, mode) in white.modes.iter().enumerate() {
        noise_report::white_row(s, &format!("fn{} [Hz]", i + 1), &mode.natural_frequency_hz)?;
        noise_report::white_row(s, &format!("ζ{}", i + 1), &mode.damping_ratio)?;
    }
    writeln!(s)
}

/// What the fit with ideal sensors found, against the fit with the sensors' model.
fn ignoring(s: &mut String, o: &ChainOutcome, ideal: &ChainFit) -> std::fmt::Result {
    writeln!(
        s,
        "\n## What ignoring the sensors' delay and filters costs\n"
    )?;
    writeln!(
        s,
        "The same records fitted as if every sensor were ideal (no delay, no filter). The shift is in standard errors of the fit above.\n"
    )?;
    writeln!(
        s,
        "| quantity | truth | with the sensor model | ideal sensors assumed | shift [SE] |\n|---|---|---|---|---|"
    )?;
    let pairs = rows(o, &o.fit.uncertainty)
        .into_iter()
        .zip(rows(o, &ideal.uncertainty));
    for ((name, truth, proper), (_, _, naive)) in pairs {
        if let (Some(p), Some(n)) = (proper, naive)
            && p.standard_error > 0.0
        {
            writeln!(
                s,
                "| {name} | {} | {} | {} | {:+.1} |",
                truth_text(truth),
                sig(p.value, 6),
                sig(n.value, 6),
                (n.value - p.value) / p.standard_error
            )?;
        }
    }
    let truth = truth_modes(o);
    for (i, (p, n)) in damping_pairs(o, ideal) {
        let t = truth.get(i).map_or("—".into(), |t| sig(t.1, 4));
        writeln!(
            s,
            "| ζ{} | {t} | {} | {} | {:+.1} |",
            i + 1,
            sig(p.value, 6),
            sig(n.value, 6),
            (n.value - p.value) / p.standard_error
        )?;
    }
    Ok(())
}

/// What the run identifies from what, for the summary's and the report's head.
fn what(o: &ChainOutcome) -> String {
    format!(
        "a chain of {}, {}; {}",
        summary::plural(o.chain.size(), "mass", "masses"),
        summary::plural(o.chain.sensors.len(), "sensor", "sensors"),
        summary::data(o.chain.plant.is_some().then_some(o.seed))
    )
}

/// The summary the command prints.
pub(crate) fn summary(o: &ChainOutcome) -> String {
    let mut s = String::new();
    summary::head(&mut s, &o.config.name, &what(o));
    summary::verdict(&mut s, &o.verdict);
    s.push('\n');
    let u = &o.fit.uncertainty;
    let mut table: Vec<summary::Estimate> = Vec::new();
    if u.intervals.is_some() {
        for (label, truth, iv) in rows(o, u) {
            if let Some(iv) = iv {
                table.push(estimate(label, &iv, truth));
            }
        }
    }
    for (i, d) in u.delays.iter().enumerate() {
        if let Some(d) = d {
            table.push(estimate(format!("delay {} [s]", i + 1), d, None));
        }
    }
    for (i, c) in u.cutoffs.iter().enumerate() {
        if let Some(c) = c {
            table.push(estimate(format!("cut-off {} [Hz]", i + 1), c, None));
        }
    }
    summary::estimates(&mut s, &table);
    if u.intervals.is_none() {
        summary::labelled(&mut s, "not identified", &u.unidentifiable.join("\n"));
    }
    s.push('\n');
    let modes: Vec<summary::ModeRow> = u
        .modes
        .iter()
        .map(|m| summary::ModeRow {
            frequency_hz: (m.natural_frequency_hz.value, m.natural_frequency_hz.ci95),
            damping_ratio: (m.damping_ratio.value, m.damping_ratio.ci95),
            note: String::new(),
        })
        .collect();
    summary::modes(&mut s, &modes);
    s.push('\n');
    use msd_ident::chain::{CUTOFF_NOT_SEPARATED, GROUND_AT_ZERO, GROUND_NOT_IN_RECORDS};
    let warnings = [CUTOFF_NOT_SEPARATED, GROUND_NOT_IN_RECORDS, GROUND_AT_ZERO];
    let said = |n: &&String| warnings.iter().any(|w| n.contains(w));
    for note in o.fit.notes.iter().filter(said) {
        summary::labelled(&mut s, "warning", note);
    }
    noise_report::summary(
        &mut s,
        &o.fit.noise_model,
        &named_whiteness(o),
        drive_unit(o),
    );
    super::validation::summary(&mut s, o);
    if let Some(ideal) = &o.ideal {
        for (i, (p, n)) in damping_pairs(o, ideal) {
            summary::labelled(
                &mut s,
                "ideal sensors",
                &format!(
                    "assumed, ζ{} would be {} instead of {} ({:+.1} SE)",
                    i + 1,
                    sig(n.value, 6),
                    sig(p.value, 6),
                    (n.value - p.value) / p.standard_error
                ),
            );
        }
    }
    s
}

/// The true chain's modes.
fn truth_modes(o: &ChainOutcome) -> Vec<(f64, f64)> {
    o.chain
        .plant
        .as_ref()
        .map(|plant| {
            let modes = plant.modes();
            modes
                .iter()
                .map(|m| (m.natural_frequency_hz.value, m.damping_ratio.value))
                .collect()
        })
        .unwrap_or_default()
}

/// Each mode's damping ratio with the sensor model and with ideal sensors.
fn damping_pairs<'a>(
    o: &'a ChainOutcome,
    ideal: &'a ChainFit,
) -> impl Iterator<Item = (usize, (&'a Interval, &'a Interval))> {
    o.fit
        .uncertainty
        .modes
        .iter()
        .zip(&ideal.uncertainty.modes)
        .map(|(p, n)| (&p.damping_ratio, &n.damping_ratio))
        .enumerate()
        // A bias in standard errors needs one to measure it by.
        .filter(|(_, (p, _))| p.standard_error > 0.0 && p.standard_error.is_finite())
}

/// The index of the sensor named `name` in the report's order.
fn sensor_index(o: &ChainOutcome, name: &str) -> usize {
    channel_names(o)
        .iter()
        .position(|n| n == name)
        .unwrap_or(usize::MAX)
}
