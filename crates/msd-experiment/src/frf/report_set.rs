//! The report section of a set of FRFs: the modes with their complexity and modal
//! masses, the fit of each FRF, the shapes and their MAC.

use super::FrfOutcome;
use super::report::{classroom_cell, interval, truth_cell, unreliable_note};
use crate::fmt::{count, sig};
use msd_modal::{ModeSetFit, ShapeEntry};
use std::fmt::Write;

/// `## Modes` for a set.
pub(super) fn section(w: &mut String, o: &FrfOutcome, m: &ModeSetFit) -> std::fmt::Result {
    writeln!(
        w,
        "## Modes common to the set\n\n{}\n",
        first_line(&m.to_string())
    )?;
    if m.conjugated {
        writeln!(
            w,
            "{}.\n",
            crate::fmt::capitalised(msd_modal::lines::CONJUGATED)
        )?;
    }
    writeln!(w, "{}\n", first_line(&m.diagram.to_string()))?;
    let truth = o.truth.as_ref().filter(|t| t.modes.len() == m.modes.len());
    writeln!(
        w,
        "| mode | fn [Hz] | ζ [-] | MPC | MPD [°] | modal mass [kg]¹ | stable orders | half-power fn, ζ (FRF 1) |{}\n|---|---|---|---|---|---|---|---|{}",
        if truth.is_some() {
            " true fn, ζ |"
        } else {
            ""
        },
        if truth.is_some() { "---|" } else { "" },
    )?;
    for (r, mode) in m.modes.iter().enumerate() {
        let classroom = o.classroom.get(r).copied().flatten();
        write!(
            w,
            "| {} | {} | {} | {} | {} | {} | {} | {} |",
            r + 1,
            interval(&mode.natural_frequency_hz),
            interval(&mode.damping_ratio),
            mode.mpc.map_or("—".into(), |x| format!("{x:.3}")),
            mode.mpd_deg.map_or("—".into(), |x| format!("{x:.1}")),
            mode.modal_mass.map_or("—".into(), |x| sig(x, 4)),
            count(mode.stable_orders),
            classroom_cell(classroom.as_ref()),
        )?;
        if let Some(t) = truth {
            write!(w, " {} |", truth_cell(Some(&t.modes[r])))?;
        }
        w.push('\n');
    }
    writeln!(
        w,
        "\n¹ In kg for FRFs in SI units (accelerance in (m/s²)/N, mobility in (m/s)/N, receptance in m/N); otherwise in the FRFs' unit of force per unit of acceleration."
    )?;
    unreliable_note(w, o.classroom.iter().flatten())?;
    if let Some(note) = &m.modal_mass_note {
        writeln!(w, "\nModal masses: {note}.")?;
    }
    if let Some(noise) = m.largest_input_noise() {
        let text = crate::fmt::capitalised(&noise.to_string());
        writeln!(w, "\n{text} (the largest of the members).")?;
    }
    if let Some(check) = &m.noise_check {
        let sentence = super::report::weights_sentence(check, "the modes leave", o);
        let members = match m.shared_force {
            Some(shared) => crate::fmt::capitalised(&shared.to_string()),
            None => "The members' errors are taken as independent of one another".into(),
        };
        writeln!(w, "\n{sentence} {members}.")?;
    } else if let Some(shared) = m.shared_force.filter(msd_modal::SharedForce::is_evident) {
        writeln!(w, "\n{}.", crate::fmt::capitalised(&shared.to_string()))?;
    }
    writeln!(
        w,
        "\n### Fit of each FRF\n\n| response | reference | fit error (measured quantity) | lower residual L | upper residual U |\n|---|---|---|---|---|"
    )?;
    for f in &m.members {
        writeln!(
            w,
            "| {} | {} | {:.2} % | {} | {} |",
            f.response,
            f.reference,
            100.0 * f.relative_error,
            sig(f.lower_residual, 4),
            sig(f.upper_residual, 4)
        )?;
    }
    shapes_table(w, m)?;
    mac_table(w, &m.mac)?;
    reference_section(w, o, m)?;
    reference_shapes_section(w, o)
}

/// The MAC against the shapes of `reference_shapes`, when the config gives it.
fn reference_shapes_section(w: &mut String, o: &FrfOutcome) -> std::fmt::Result {
    let Some(r) = &o.reference_shapes else {
        return Ok(());
    };
    let c = &r.comparison;
    let list = |dofs: &[msd_modal::Dof]| {
        let shown: Vec<String> = dofs.iter().take(6).map(ToString::to_string).collect();
        match dofs.len() {
            0 => "none".to_string(),
            n if n > shown.len() => format!("{n} DOFs: {}, …", shown.join(", ")),
            _ => shown.join(", "),
        }
    };
    writeln!(
        w,
        "### Against the shapes of `{}`

The MAC on the {} DOFs both give (left out: estimated only {}; the file's only {}). Rows: the estimated modes; columns: the file's.
",
        r.file,
        c.shared.len(),
        list(&c.only_first),
        list(&c.only_second)
    )?;
    write!(w, "| |")?;
    for (j, name) in r.modes.iter().enumerate() {
        write!(w, " {} ({name}) |", j + 1)?;
    }
    writeln!(
        w,
        " best match |
|---|{}---|",
        "---|".repeat(r.modes.len())
    )?;
    for (i, (row, best)) in c.mac.iter().zip(c.best_matches()).enumerate() {
        write!(w, "| {} |", i + 1)?;
        for x in row {
            write!(w, " {x:.3} |")?;
        }
        let best = best.map_or("—".into(), |(j, x)| format!("{} (MAC {x:.3})", j + 1));
        writeln!(w, " {best} |")?;
    }
    writeln!(w)
}

/// The comparison with `reference_modes`, when the config gives them.
fn reference_section(w: &mut String, o: &FrfOutcome, m: &ModeSetFit) -> std::fmt::Result {
    let Some(reference) = super::reference_modes(o) else {
        return Ok(());
    };
    writeln!(
        w,
        "### Against the reference modes\n\n| mode | reference fn [Hz] | reference ζ | fn inside its 95 % interval | ζ inside | MAC with the reference shape |\n|---|---|---|---|---|---|"
    )?;
    let macs = super::reference_mac(m, reference);
    let mut inside = 0;
    for (r, (mode, (truth, mac))) in m.modes.iter().zip(reference.iter().zip(&macs)).enumerate() {
        let f_in = mode
            .natural_frequency_hz
            .contains(truth.natural_frequency_hz);
        let z_in = mode.damping_ratio.contains(truth.damping_ratio);
        inside += usize::from(f_in) + usize::from(z_in);
        let yes = |b: bool| if b { "yes" } else { "no" };
        writeln!(
            w,
            "| {} | {} | {} | {} | {} | {mac:.4} |",
            r + 1,
            sig(truth.natural_frequency_hz, 6),
            sig(truth.damping_ratio, 4),
            yes(f_in),
            yes(z_in)
        )?;
    }
    writeln!(
        w,
        "\nThe reference values lie inside the 95 % intervals for {inside} of {}.\n",
        2 * m.modes.len().min(reference.len())
    )
}

/// The unit-normalised shapes, one row per DOF.
fn shapes_table(w: &mut String, m: &ModeSetFit) -> std::fmt::Result {
    let Some(first) = m.modes.first() else {
        return Ok(());
    };
    writeln!(
        w,
        "\n### Mode shapes\n\nEach shape scaled so that its largest entry is 1 (over the {} DOFs); written as UFF datasets 55 to `modes.uff`, and every FRF as the model synthesises it as datasets 58 to `synthesized.uff`.\n",
        match m.roving {
            msd_modal::Roving::Reference => "hammer's",
            msd_modal::Roving::Response => "responses'",
        }
    )?;
    write!(w, "| DOF |")?;
    for r in 0..m.modes.len() {
        write!(w, " mode {} |", r + 1)?;
    }
    writeln!(w, "\n|---|{}", "---|".repeat(m.modes.len()))?;
    for (i, entry) in first.shape.iter().enumerate() {
        write!(w, "| {}:{:+} |", entry.node, entry.direction)?;
        for mode in &m.modes {
            write!(w, " {} |", complex(&mode.shape[i]))?;
        }
        writeln!(w)?;
    }
    Ok(())
}

/// `re ± im j`, four significant digits each.
fn complex(e: &ShapeEntry) -> String {
    let sign = if e.im < 0.0 { "−" } else { "+" };
    format!("{} {sign} {}j", sig(e.re, 4), sig(e.im.abs(), 2))
}

/// The auto-MAC as a table.
fn mac_table(w: &mut String, mac: &[Vec<f64>]) -> std::fmt::Result {
    if mac.is_empty() {
        return Ok(());
    }
    writeln!(w, "\n### MAC of the shapes\n")?;
    write!(w, "| |")?;
    for r in 0..mac.len() {
        write!(w, " {} |", r + 1)?;
    }
    writeln!(w, "\n|---|{}", "---|".repeat(mac.len()))?;
    for (r, row) in mac.iter().enumerate() {
        write!(w, "| {} |", r + 1)?;
        for x in row {
            write!(w, " {x:.3} |")?;
        }
        writeln!(w)?;
    }
    writeln!(w)
}

fn first_line(text: &str) -> &str {
    text.lines().next().unwrap_or("")
}
