//! `report.md` of a setup run and the summary the command prints.

use super::{SetupFit, SetupOutcome};
use crate::fmt::sig;
use crate::noise_report;
use crate::summary;
use msd_ident::{Interval, RecordsFit};
use std::fmt::Write;

/// The identified quantities with their units and the truth (synthetic only), in the
/// order of the tables: (key, label, estimate, truth).
pub(crate) fn estimates(o: &SetupOutcome) -> Vec<(&'static str, String, Interval, Option<f64>)> {
    let truth = o.data.truth;
    match &o.fit {
        SetupFit::Records { fit, .. } => plant_rows(fit, truth.map(|p| p.parameters())),
        SetupFit::Machine(m) => {
            let best = m.best_law();
            best.names
                .iter()
                .zip(&best.coefficients)
                .map(|(name, iv)| {
                    let t = truth.and_then(|p| match *name {
                        "mass" => Some(p.mass),
                        "damping" => Some(p.damping),
                        "stiffness" => Some(p.stiffness),
                        "quadratic_damping" => Some(p.quadratic_damping),
                        "coulomb_force" => Some(p.coulomb_force),
                        _ => None,
                    });
                    (*name, machine_label(name), *iv, t)
                })
                .collect()
        }
        SetupFit::Stroke(f) => {
            let best = &f.inverse.laws[f.inverse.best];
            best.coefficients
                .iter()
                .map(|c| {
                    let label = machine_label(c.name);
                    let label = if label == c.name {
                        format!("{} [{}]", c.name, c.unit)
                    } else {
                        label
                    };
                    (c.name, label, c.estimate, None)
                })
                .collect()
        }
    }
}

/// A test machine's coefficient with its unit, as `c₂ [N·s²/m²]`.
fn machine_label(name: &str) -> String {
    match name {
        "mass" => "m [kg]".into(),
        "damping" => "c [N·s/m]".into(),
        "stiffness" => "k [N/m]".into(),
        "quadratic_damping" => "c₂ [N·s²/m²]".into(),
        "coulomb_force" => "F_c [N]".into(),
        "force_offset" => "force offset [N]".into(),
        other => other.into(),
    }
}

fn plant_rows(
    fit: &RecordsFit,
    truth: Option<msd_ident::Parameters>,
) -> Vec<(&'static str, String, Interval, Option<f64>)> {
    let p = &fit.plant;
    let mut rows = Vec::new();
    for (key, label, iv, t) in [
        ("mass", "m [kg]", p.mass, truth.map(|t| t.mass)),
        ("damping", "c [N·s/m]", p.damping, truth.map(|t| t.damping)),
        (
            "stiffness",
            "k [N/m]",
            p.stiffness,
            truth.map(|t| t.stiffness),
        ),
    ] {
        if let Some(iv) = iv {
            rows.push((key, label.to_string(), iv, t));
        }
    }
    rows.push((
        "natural_frequency_hz",
        "fn [Hz]".into(),
        p.natural_frequency_hz,
        truth.map(|t| t.natural_frequency_hz()),
    ));
    rows.push((
        "damping_ratio",
        "ζ [-]".into(),
        p.damping_ratio,
        truth.map(|t| t.damping_ratio()),
    ));
    rows
}

/// What the run identifies from what, for the summary's and the report's head.
fn what(o: &SetupOutcome) -> String {
    let records = summary::plural(o.data.records.len(), "record", "records");
    let data = summary::data(o.data.files.is_empty().then_some(o.seed));
    format!(
        "a lab setup: {records}, {}, channels {}; {data}",
        match o.data.setup.excitation {
            crate::config::ExcitationKind::None => "a free decay".to_string(),
            other => format!("drive {}", other.name().replace('_', " ")),
        },
        channel_names(o).join(", ")
    )
}

/// The summary the command prints: the setup and the estimates.
pub(crate) fn summary(o: &SetupOutcome) -> String {
    let mut s = String::new();
    summary::head(&mut s, &o.config.name, &what(o));
    summary::verdict(&mut s, &o.verdict);
    s.push('\n');
    let rows: Vec<summary::Estimate> = estimates(o)
        .into_iter()
        .map(|(_, label, iv, truth)| summary::Estimate {
            label,
            value: iv.value,
            interval: (iv.standard_error != 0.0).then_some(iv.ci95),
            truth,
        })
        .collect();
    summary::estimates(&mut s, &rows);
    s.push('\n');
    if let Some(note) = identifiability_note(o) {
        summary::labelled(&mut s, "note", note);
    }
    match &o.fit {
        SetupFit::Records { fit, .. } => {
            noise_report::summary(
                &mut s,
                &fit.noise_model,
                &fit.whiteness,
                o.data.setup.excitation.unit(),
            );
            super::report_validation::summary(&mut s, fit);
        }
        SetupFit::Machine(m) => super::report_machine::summary(&mut s, m),
        SetupFit::Stroke(f) => super::stroke::summary(&mut s, f),
    }
    s.trim_end().to_string()
}

fn channel_names(o: &SetupOutcome) -> Vec<String> {
    o.data.channels.iter().map(|c| c.channel_name()).collect()
}

fn identifiability_note(o: &SetupOutcome) -> Option<&str> {
    match &o.fit {
        SetupFit::Records { fit, .. } => fit.plant.note.as_deref(),
        SetupFit::Machine(_) | SetupFit::Stroke(_) => None,
    }
}

/// `report.md`.
pub(crate) fn markdown(o: &SetupOutcome, figures: &[&str]) -> String {
    let mut s = String::new();
    // Writing into a String cannot fail.
    let _ = page(&mut s, o, figures);
    s
}

fn page(s: &mut String, o: &SetupOutcome, figures: &[&str]) -> std::fmt::Result {
    let run = (&o.config, o.config_path.as_path(), o.command.as_str());
    let seed = o.data.files.is_empty().then_some(o.seed);
    crate::results::report_head(s, run, &what(o), seed, &[])?;
    crate::verdict::section(s, &o.verdict)?;
    setup_section(s, o)?;
    estimate_section(s, o)?;
    match &o.fit {
        SetupFit::Records { fit, classroom } => {
            records_section(s, fit)?;
            noise_section(s, fit, o.data.setup.excitation.unit())?;
            super::report_validation::section(s, fit, &o.data.channels)?;
            if let Some(c) = classroom {
                classroom_section(s, c, &fit.plant)?;
            }
        }
        SetupFit::Machine(m) => super::report_machine::section(s, m)?,
        SetupFit::Stroke(f) => super::stroke::section(s, f)?,
    }
    // The records' fit carries the reader's notes; the test machine's are said here.
    if !matches!(o.fit, SetupFit::Records { .. }) && !o.data.notes.is_empty() {
        writeln!(s, "Notes on the data:\n")?;
        for n in &o.data.notes {
            writeln!(s, "- {n}")?;
        }
        s.push('\n');
    }
    writeln!(s, "## Figures\n")?;
    for f in figures {
        let (alt, caption) = figure_caption(f);
        writeln!(s, "![{alt}]({f}.png)\n\n*{caption}*\n")?;
    }
    Ok(())
}

fn setup_section(s: &mut String, o: &SetupOutcome) -> std::fmt::Result {
    let setup = &o.data.setup;
    writeln!(s, "## Setup\n")?;
    writeln!(
        s,
        "Excitation: **{}**. Records: {} ({}).",
        setup.excitation.name(),
        o.data.records.len(),
        if o.data.files.is_empty() {
            "synthetic"
        } else {
            "measured"
        }
    )?;
    if let Some(m) = setup.known_mass {
        writeln!(s, "Known (weighed) mass: {} kg.", sig(m, 6))?;
    }
    if let Some(k) = setup.known_stiffness {
        writeln!(s, "Known static stiffness: {} N/m.", sig(k, 6))?;
    }
    let synthetic = o.data.files.is_empty();
    writeln!(
        s,
        "\n| channel | quantity | frame | unit |{}\n|---|---|---|---|{}",
        if synthetic { " noise σ added |" } else { "" },
        if synthetic { "---|" } else { "" }
    )?;
    let default_sigma = o.config.noise.map(|n| n.sigma);
    for c in &o.data.channels {
        write!(
            s,
            "| {} | {} | {} | {} |",
            c.channel_name(),
            c.quantity,
            c.frame,
            c.unit.as_deref().unwrap_or(c.quantity.si_unit()),
        )?;
        if synthetic {
            let sigma = c.sigma.or(default_sigma).map_or("—".into(), |v| sig(v, 4));
            write!(s, " {sigma} |")?;
        }
        s.push('\n');
    }
    s.push('\n');
    Ok(())
}

fn estimate_section(s: &mut String, o: &SetupOutcome) -> std::fmt::Result {
    writeln!(s, "## Estimate\n")?;
    let rows = estimates(o);
    let names: Vec<&str> = rows.iter().map(|r| quantity_name(r.0)).collect();
    writeln!(s, "The setup identifies the {}.\n", names.join(", "))?;
    if let Some(note) = identifiability_note(o) {
        writeln!(s, "**Not identifiable:** {note}\n")?;
    }
    let has_truth = rows.iter().any(|r| r.3.is_some());
    write!(
        s,
        "| quantity | estimate | standard error | 95 % interval |"
    )?;
    if has_truth {
        write!(s, " truth | inside |")?;
    }
    writeln!(
        s,
        "\n|---|---|---|---|{}",
        if has_truth { "---|---|" } else { "" }
    )?;
    for (_, label, iv, truth) in rows {
        if iv.standard_error == 0.0 {
            // A known (weighed) mass or static stiffness: given, not estimated.
            write!(s, "| {label} | {} | known, fixed | — |", sig(iv.value, 6))?;
        } else {
            write!(
                s,
                "| {label} | {} | {} | [{}, {}] |",
                sig(iv.value, 6),
                sig(iv.standard_error, 3),
                sig(iv.ci95[0], 6),
                sig(iv.ci95[1], 6)
            )?;
        }
        if has_truth {
            let t = truth.map_or("—".into(), |t| sig(t, 6));
            let inside = truth.map_or("—", |t| if iv.contains(t) { "yes" } else { "**no**" });
            write!(s, " {t} | {inside} |")?;
        }
        s.push('\n');
    }
    s.push('\n');
    Ok(())
}

/// A figure's alt text and caption, as sentences.
fn figure_caption(name: &str) -> (&'static str, &'static str) {
    match name {
        "setup_fit" => (
            "The fit of the first record",
            "The first record: the drive, then each channel measured (blue points) and as the fitted plant predicts it (red line).",
        ),
        "setup_noise_spectrum" => crate::noise_report::SPECTRUM_FIGURE,
        "setup_loops" => (
            "Force–displacement loops",
            "Each condition's force against the imposed displacement: measured and as the best damping law predicts it.",
        ),
        "setup_force_velocity" => (
            "Force against velocity",
            "The damping force against the velocity over every condition: measured and the fitted laws.",
        ),
        "setup_stroke_force" => (
            "Force under the stroke",
            "The measured force under the imposed stroke and as the identified model predicts it, on fresh data.",
        ),
        _ => ("Figure", "Figure."),
    }
}

/// A result key in words: `natural_frequency_hz` → "natural frequency fn".
fn quantity_name(key: &str) -> &str {
    match key {
        "mass" => "mass m",
        "damping" => "damping c",
        "stiffness" => "stiffness k",
        "natural_frequency_hz" => "natural frequency fn",
        "damping_ratio" => "damping ratio ζ",
        "quadratic_damping" => "quadratic damping c₂",
        "coulomb_force" => "Coulomb force F_c",
        "force_offset" => "force offset",
        other => other,
    }
}

fn records_section(s: &mut String, fit: &RecordsFit) -> std::fmt::Result {
    writeln!(
        s,
        "## Channels\n\n| channel | estimated noise σ̂ | samples |\n|---|---|---|"
    )?;
    for n in &fit.noise {
        writeln!(s, "| {} | {} | {} |", n.channel, sig(n.sigma, 4), n.samples)?;
    }
    writeln!(
        s,
        "\n## Records\n\nOne row per record and channel: the fit of the joint estimate.\n"
    )?;
    writeln!(
        s,
        "| record | channel | R² | fit % | offset [channel's unit] | x(t₀) [m] | x′(t₀) [m/s] |\n|---|---|---|---|---|---|---|"
    )?;
    for r in &fit.records {
        for c in &r.channels {
            writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} |",
                r.name,
                c.channel,
                sig(c.fit.r_squared, 6),
                sig(c.fit.fit_percent, 4),
                sig(c.offset, 4),
                sig(r.initial_state.displacement, 4),
                sig(r.initial_state.velocity, 4)
            )?;
        }
    }
    if !fit.notes.is_empty() {
        writeln!(s, "\nNotes:\n")?;
        for n in &fit.notes {
            writeln!(s, "- {n}")?;
        }
    }
    s.push('\n');
    Ok(())
}

/// The noise model, the residuals' whiteness, and the output-error estimate's
/// intervals it replaced (under the noise model when the weighted estimate replaced it,
/// and as a white-noise fit would have reported them).
fn noise_section(s: &mut String, fit: &RecordsFit, unit: &str) -> std::fmt::Result {
    noise_report::section(s, &fit.noise_model, &fit.whiteness, unit, "[setup]")?;
    let tables = [
        (
            &fit.output_error_plant,
            "The output-error estimate (every sample weighted alike) with its intervals under the noise model (`output_error_estimate`):",
        ),
        (
            &fit.white_noise_plant,
            "The output-error estimate with the intervals a white-noise fit would have reported (`white_noise_estimate`):",
        ),
    ];
    for (plant, caption) in tables {
        let Some(plant) = plant else { continue };
        writeln!(
            s,
            "{caption}\n\n| quantity | estimate | 95 % interval |\n|---|---|---|"
        )?;
        let rows = [
            ("m [kg]", plant.mass),
            ("c [N·s/m]", plant.damping),
            ("k [N/m]", plant.stiffness),
            ("fn [Hz]", Some(plant.natural_frequency_hz)),
            ("ζ", Some(plant.damping_ratio)),
        ];
        for (label, iv) in rows {
            if let Some(iv) = iv.filter(|iv| iv.standard_error > 0.0) {
                noise_report::white_row(s, label, &iv)?;
            }
        }
        s.push('\n');
    }
    Ok(())
}

fn classroom_section(
    s: &mut String,
    k: &msd_ident::free_decay::ClassroomEstimates,
    fit: &msd_ident::records::PlantIntervals,
) -> std::fmt::Result {
    let (zeta, fnat) = (fit.damping_ratio.value, fit.natural_frequency_hz.value);
    writeln!(
        s,
        "## Free decay: the classroom estimates\n\nFrom the first record alone, for comparison with the fit.\n\n| | classroom | fit |\n|---|---|---|"
    )?;
    writeln!(
        s,
        "| logarithmic decrement δ | {} | — |",
        sig(k.log_decrement, 5)
    )?;
    writeln!(
        s,
        "| ζ = δ/√(4π² + δ²) | {} | {} |",
        sig(k.damping_ratio, 5),
        sig(zeta, 5)
    )?;
    writeln!(
        s,
        "| damped frequency fd [Hz] (zero crossings) | {} | {} |\n",
        sig(k.damped_frequency_hz, 6),
        sig(fnat * (1.0 - zeta * zeta).max(0.0).sqrt(), 6)
    )?;
    Ok(())
}
