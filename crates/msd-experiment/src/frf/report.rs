//! `report.md` of a frequency-domain experiment: the data, the fit with its intervals
//! beside the classroom estimates and the truth, the window correction, the figures.

use super::{FrfFit, FrfOutcome, Truth};
use crate::fmt::{count, sig};
use crate::verdict;
use msd_ident::{Interval, OneModeFit};
use msd_modal::{HalfPower, ModalFit, ModalParameters};
use std::fmt::Write;

/// "a of b quantities (names)": how many fitted fn and ζ (and m, c, k of a one-mass
/// plant) have the truth inside their 95 % intervals.
pub(crate) fn covered(o: &FrfOutcome, truth: &Truth) -> String {
    let checks = checks(o, truth);
    let inside: Vec<&str> = checks
        .iter()
        .filter(|(_, i, t)| i.contains(*t))
        .map(|(n, _, _)| n.as_str())
        .collect();
    format!(
        "{} of {} ({})",
        inside.len(),
        checks.len(),
        inside.join(", ")
    )
}

/// (name, interval, true value) of every quantity that has a truth.
fn checks(o: &FrfOutcome, truth: &Truth) -> Vec<(String, Interval, f64)> {
    let mut out = Vec::new();
    match &o.fit {
        FrfFit::OneMode(f) => {
            let u = &f.uncertainty;
            if let ([mode], true) = (truth.modes.as_slice(), truth.plant.len() == 1) {
                if scale_known(o) {
                    let p = &truth.plant;
                    out.push(("m".into(), u.mass, p.masses[0]));
                    out.push(("c".into(), u.damping, p.dampers[0]));
                    out.push(("k".into(), u.stiffness, p.springs[0]));
                }
                out.push((
                    "fn".into(),
                    u.natural_frequency_hz,
                    mode.natural_frequency_hz,
                ));
                out.push(("ζ".into(), u.damping_ratio, mode.damping_ratio));
            }
        }
        FrfFit::Modes(_) | FrfFit::Set(_) => {
            // Each true mode against the fitted mode nearest in frequency: a spurious
            // extra mode is left out, a missing one compared with its neighbour.
            let poles = o.fit.poles();
            for (r, t) in truth.modes.iter().enumerate() {
                let distance =
                    |p: &(Interval, Interval)| (p.0.value - t.natural_frequency_hz).abs();
                let Some(&(f, z)) = poles
                    .iter()
                    .min_by(|a, b| distance(a).total_cmp(&distance(b)))
                else {
                    continue;
                };
                out.push((format!("fn{}", r + 1), f, t.natural_frequency_hz));
                out.push((format!("ζ{}", r + 1), z, t.damping_ratio));
            }
        }
    }
    out
}

fn scale_known(o: &FrfOutcome) -> bool {
    o.config
        .frequency_response
        .as_ref()
        .is_none_or(|s| s.force_scale_known)
}

/// The report; `figures` are the base names written.
pub(crate) fn markdown(o: &FrfOutcome, figures: &[&str]) -> String {
    let mut s = String::new();
    // Writing into a String cannot fail.
    let _ = page(&mut s, o, figures);
    s
}

fn page(w: &mut String, o: &FrfOutcome, figures: &[&str]) -> std::fmt::Result {
    let run = (&o.config, o.config_path.as_path(), o.command.as_str());
    let what = format!("frequency-domain identification from {}", o.source);
    crate::results::report_head(w, run, &what, Some(o.seed), &[])?;
    verdict::section(w, &o.verdict)?;
    data_section(w, o)?;
    match &o.fit {
        FrfFit::OneMode(f) => one_mode_section(w, o, f)?,
        FrfFit::Modes(m) => modes_section(w, o, m)?,
        FrfFit::Set(m) => super::report_set::section(w, o, m)?,
    }
    if let Some(t) = &o.truth {
        writeln!(
            w,
            "The true values lie inside the 95 % intervals for {}.\n",
            covered(o, t)
        )?;
    }
    if let Some(td) = &o.time_domain {
        super::time_domain::markdown(w, td)?;
    }
    for (name, caption) in [
        ("frf_fit_bode", "Bode plot: the data and the fitted model"),
        (
            "frf_fit_nyquist",
            "Nyquist plot: the data and the fitted model",
        ),
        ("frf_coherence", "Ordinary coherence of the estimate"),
        ("frf_stabilization", "Stabilization diagram"),
        (
            "frf_set_fit",
            "Every FRF of the set: the data and the fitted model",
        ),
        ("frf_mac", "MAC of the mode shapes"),
        (
            "frf_mac_reference",
            "MAC of the mode shapes against the reference shapes",
        ),
        ("frf_shapes", "The mode shapes over the measured DOFs"),
        (
            "frf_shapes_geometry",
            "The mode shapes over the nodes' coordinates",
        ),
        (
            "frf_mode_indicator",
            "Mode indicator functions of the data (CMIF and MIF)",
        ),
    ] {
        if figures.contains(&name) {
            writeln!(w, "![{caption}]({name}.png)\n")?;
        }
    }
    Ok(())
}

fn data_section(w: &mut String, o: &FrfOutcome) -> std::fmt::Result {
    let d = &o.data;
    let n = d.frequency.len();
    writeln!(w, "## Data\n")?;
    writeln!(
        w,
        "{n} lines from {} to {} Hz, {}; {}.",
        sig(d.frequency[0], 4),
        sig(d.frequency[n - 1], 4),
        d.kind,
        match d.averages {
            0 => "with the coherence as exported (over how many averages not stated)".to_string(),
            k => format!("averaged over {k} segments"),
        }
    )?;
    if o.chose_rectangular_window() {
        write!(
            w,
            " The force repeats from record to record (a periodic input over whole periods): each record was taken whole with a rectangular window, which keeps its lines apart (`welch.window = \"auto\"`; a Hann window would smear each line into the lines between)."
        )?;
    }
    let unexcited = o.unexcited_lines();
    if unexcited > 0 {
        write!(
            w,
            " {unexcited} of them carry no force (its power there is below 1e-12 of its largest line: lines outside a periodic force's band or between its lines) and are left out of the fit."
        )?;
    }
    if d.averages != 1 {
        let ([from, to], low) = fitted_band_coherence(o);
        write!(
            w,
            " The coherence is at least {} in the fitted band ({}–{} Hz).",
            sig(low, 3),
            sig(from, 4),
            sig(to, 4)
        )?;
    }
    if let Some(tau) = d.exponential_decay {
        write!(
            w,
            " An exponential window e^(−t/τ), τ = {tau} s, was applied: it adds the damping ratio 1/(ωn·τ) to a mode, which the fit takes off (below)."
        )?;
    }
    if let Some([low, high]) = force_noise_range(o) {
        write!(
            w,
            " The force channel's noise was measured after the force window: it makes each line's error {}–{} % of |H| in the fitted band (σ²·Σw²/Σ|F_k|² over the hits), which the weights take as known; the coherence sets only the response's noise.",
            sig(100.0 * low, 2),
            sig(100.0 * high, 2)
        )?;
    }
    writeln!(w, "\n")?;
    Ok(())
}

fn one_mode_section(w: &mut String, o: &FrfOutcome, f: &OneModeFit) -> std::fmt::Result {
    writeln!(w, "## One mode\n\n{}\n", first_line(&f.to_string()))?;
    if let Some(peak) = &f.dominant_peak {
        writeln!(
            w,
            "No band was given: fitted in {peak}. `one_mode.band_hz` sets another.\n"
        )?;
    }
    if f.conjugated {
        writeln!(
            w,
            "{}.\n",
            crate::fmt::capitalised(msd_modal::lines::CONJUGATED)
        )?;
    }
    if let Some(low) = &f.low_coherence {
        writeln!(w, "{}.\n", crate::fmt::capitalised(&low.to_string()))?;
    }
    let classroom = o.classroom.first().copied().flatten();
    writeln!(
        w,
        "| quantity | estimate | 95 % interval | half-power / peak | truth |\n|---|---|---|---|---|"
    )?;
    let rows = one_mode_rows(o, f);
    for (name, i, c, t) in rows {
        row(w, name, i, c, t)?;
    }
    unreliable_note(w, classroom.iter())?;
    writeln!(w)?;
    if let Some(check) = &f.noise_check {
        writeln!(
            w,
            "{}\n",
            weights_sentence(check, "the one-mode model leaves", o)
        )?;
    }
    if let Some(noise) = &f.input_noise {
        let said = crate::fmt::capitalised(&noise.to_string());
        if noise.corrected {
            writeln!(
                w,
                "{said} (noise on the force adds to its auto-spectrum S_xx and not to the cross-spectrum S_xy, so H1 = S_xy/S_xx is low by the force's share of the incoherence at every line; the response's noise biases nothing): the fit is made on H1 × (1 + {:.2e}).\n",
                noise.h1_bias
            )?;
        } else {
            writeln!(w, "{said}\n")?;
        }
    }
    window_note(w, f.window_correction.as_ref(), classroom.as_ref())?;
    Ok(())
}

fn modes_section(w: &mut String, o: &FrfOutcome, m: &ModalFit) -> std::fmt::Result {
    writeln!(w, "## Modes\n\n{}\n", first_line(&m.to_string()))?;
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
        "| mode | fn [Hz] | ζ [-] | modal constant A | B | stable orders | half-power fn, ζ |{}\n|---|---|---|---|---|---|---|{}",
        if truth.is_some() {
            " true fn, ζ |"
        } else {
            ""
        },
        if truth.is_some() { "---|" } else { "" },
    )?;
    for (r, mode) in m.modes.iter().enumerate() {
        let classroom = o.classroom.get(r).copied().flatten();
        let t = truth.map(|t| t.modes[r]);
        let constant = m.modal_constant(r);
        write!(
            w,
            "| {} | {} | {} | {} | {} | {} | {} |",
            r + 1,
            interval(&mode.natural_frequency_hz),
            interval(&mode.damping_ratio),
            constant.map_or("—".into(), |[a, _]| interval(&a)),
            constant.map_or("—".into(), |[_, b]| interval(&b)),
            count(mode.stable_orders),
            classroom_cell(classroom.as_ref()),
        )?;
        if truth.is_some() {
            write!(w, " {} |", truth_cell(t.as_ref()))?;
        }
        w.push('\n');
    }
    unreliable_note(w, o.classroom.iter().flatten())?;
    if let Some(check) = &m.noise_check {
        writeln!(w, "\n{}", weights_sentence(check, "the modes leave", o))?;
    }
    if let Some(noise) = &m.input_noise {
        writeln!(w, "\n{}.", crate::fmt::capitalised(&noise.to_string()))?;
    }
    writeln!(
        w,
        "\nResidual terms: lower L = {} (the modes below the band, −L/ω²), upper U = {} (those above).\n",
        interval(&m.lower_residual),
        interval(&m.upper_residual)
    )?;
    for r in &m.refused {
        writeln!(w, "Refused: the mode selected at {r}.\n")?;
    }
    for (r, mode) in m.modes.iter().enumerate() {
        if let Some(c) = &mode.window_correction {
            writeln!(w, "Mode {}: {c}.\n", r + 1)?;
        }
    }
    Ok(())
}

/// "fn, ζ" of a half-power estimate, marked † when unreliable; "—" without one.
pub(super) fn classroom_cell(c: Option<&HalfPower>) -> String {
    c.map_or("—".into(), |c| {
        format!(
            "{}, {}{}",
            sig(c.natural_frequency_hz, 5),
            sig(c.damping_ratio, 3),
            if c.reliable { "" } else { " †" }
        )
    })
}

/// "fn, ζ" of a true mode; "—" without one.
pub(super) fn truth_cell(t: Option<&ModalParameters>) -> String {
    t.map_or("—".into(), |t| {
        format!(
            "{}, {}",
            sig(t.natural_frequency_hz, 6),
            sig(t.damping_ratio, 4)
        )
    })
}

/// A footnote when a half-power estimate is under-resolved (its † in the table).
pub(super) fn unreliable_note<'a>(
    w: &mut String,
    estimates: impl Iterator<Item = &'a HalfPower>,
) -> std::fmt::Result {
    let few: Vec<usize> = estimates
        .filter(|h| !h.reliable)
        .map(|h| h.lines_inside)
        .collect();
    if !few.is_empty() {
        writeln!(
            w,
            "\n† Half-power estimate unreliable: {} line{} inside the half-power band{} (at least {} needed). {} under-resolved and the half-power ζ comes out too high; the fitted ζ does not rest on the bandwidth.",
            few.iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(", "),
            if few == [1] { "" } else { "s" },
            if few.len() == 1 { "" } else { "s" },
            HalfPower::MIN_LINES,
            if few.len() == 1 {
                "The peak is"
            } else {
                "The peaks are"
            }
        )?;
    }
    Ok(())
}

/// What the exponential window did, stated: ζ as fitted and what was taken off.
fn window_note(
    w: &mut String,
    c: Option<&msd_modal::WindowCorrection>,
    h: Option<&HalfPower>,
) -> std::fmt::Result {
    if let Some(c) = c {
        writeln!(
            w,
            "The exponential window (τ = {} s) raised the fitted ζ to {}; {} of it (≈ 1/(ωn·τ)) was taken off.\n",
            c.decay_time,
            sig(c.damping_ratio_windowed, 4),
            sig(c.damping_ratio_added, 4)
        )?;
    }
    if let Some(h) = h.filter(|h| h.damping_ratio_added > 0.0) {
        writeln!(
            w,
            "The half-power ζ was corrected by the same window: {} taken off.\n",
            sig(h.damping_ratio_added, 4)
        )?;
    }
    Ok(())
}

fn row(
    w: &mut String,
    name: &str,
    i: &Interval,
    classroom: Option<f64>,
    truth: Option<f64>,
) -> std::fmt::Result {
    writeln!(
        w,
        "| {name} | {} | {} … {} | {} | {} |",
        sig(i.value, 6),
        sig(i.ci95[0], 6),
        sig(i.ci95[1], 6),
        classroom.map_or("—".into(), |v| sig(v, 5)),
        truth.map_or("—".into(), |v| sig(v, 6)),
    )?;
    Ok(())
}

/// "value (low … high)" with the digits the interval needs: at least five significant,
/// and enough that its half-width shows with two (108.00014 (107.99968 … 108.00060), not
/// 108.00 (108.00 … 108.00)).
pub(super) fn interval(i: &Interval) -> String {
    let digits = interval_digits(i.value, 0.5 * (i.ci95[1] - i.ci95[0]));
    format!(
        "{} ({} … {})",
        sig(i.value, digits),
        sig(i.ci95[0], digits),
        sig(i.ci95[1], digits)
    )
}

/// Significant digits for `value` so that `half_width` shows with two: 5 to 12.
fn interval_digits(value: f64, half_width: f64) -> usize {
    let ratio = value.abs() / half_width;
    if !(ratio.is_finite() && ratio > 0.0) {
        return 5;
    }
    (ratio.log10().ceil() as i64 + 2).clamp(5, 12) as usize
}

fn first_line(text: &str) -> &str {
    text.lines().next().unwrap_or("")
}

/// The fitted band and the lowest coherence within it, over the lines with force (the
/// lines outside it, or unexcited inside it, carry no force, and their coherence says
/// nothing of the fit).
pub(super) fn fitted_band_coherence(o: &FrfOutcome) -> ([f64; 2], f64) {
    let [from, to] = o.fit.band_hz();
    let d = &o.data;
    let any = o.unexcited_lines() > 0;
    let unexcited = |k: usize| any && d.h[k].norm_sqr() == 0.0;
    let low = (0..d.frequency.len())
        .filter(|&k| (from..=to).contains(&d.frequency[k]) && !unexcited(k))
        .fold(1.0, |low, k| d.coherence[k].min(low));
    ([from, to], low)
}

/// How the lines were weighted and what their residuals say against that noise
/// (`model` the subject of "… only the noise the coherence shows").
pub(super) fn weights_sentence(
    check: &msd_modal::NoiseCheck,
    model: &str,
    o: &FrfOutcome,
) -> String {
    let source = match o.data.input_noise_variance {
        Some(_) => {
            "the force's noise measured on its channel, the response's fitted to every line's coherence"
        }
        None => "fitted to every line's coherence",
    };
    format!(
        "Each line is weighted by its own standard deviation, from a noise model ({source}; white noise on the force and on the response). {}{}.",
        crate::fmt::capitalised(&check.to_string()),
        if check.passed {
            format!(": {model} only the noise the coherence shows")
        } else {
            String::new()
        }
    )
}

/// The smallest and largest relative standard deviation √v_k of a line from the force's
/// noise in the fitted band, where that noise was measured (an impact test).
pub(super) fn force_noise_range(o: &FrfOutcome) -> Option<[f64; 2]> {
    let v = o.data.input_noise_variance.as_ref()?;
    let [from, to] = o.fit.band_hz();
    let inside = (o.data.frequency.iter().zip(v))
        .filter(|&(f, &v)| (from..=to).contains(f) && v > 0.0)
        .map(|(_, v)| v.sqrt());
    inside.fold(None, |range, s| match range {
        None => Some([s, s]),
        Some([low, high]) => Some([s.min(low), s.max(high)]),
    })
}

/// A one-mode fit's quantities: (name with unit, estimate, the half-power or peak
/// estimate, the truth), m, c and k where the force's scale is known, else the gain 1/m.
pub(crate) fn one_mode_rows<'a>(
    o: &FrfOutcome,
    f: &'a OneModeFit,
) -> Vec<(&'static str, &'a Interval, Option<f64>, Option<f64>)> {
    let u = &f.uncertainty;
    let truth = o.truth.as_ref().filter(|t| t.plant.len() == 1);
    let mode = truth.and_then(|t| t.modes.first());
    let classroom = o.classroom.first().copied().flatten();
    let mut rows: Vec<(&str, &Interval, Option<f64>, Option<f64>)> = Vec::new();
    if scale_known(o) {
        let p = truth.map(|t| &t.plant);
        rows.push(("m [kg]", &u.mass, None, p.map(|p| p.masses[0])));
        rows.push(("c [N·s/m]", &u.damping, None, p.map(|p| p.dampers[0])));
        rows.push(("k [N/m]", &u.stiffness, None, p.map(|p| p.springs[0])));
    } else {
        rows.push((
            "gain 1/m [1/kg]",
            &f.gain,
            None,
            truth.map(|t| 1.0 / t.plant.masses[0]),
        ));
    }
    rows.push((
        "fn [Hz]",
        &u.natural_frequency_hz,
        classroom.map(|c| c.natural_frequency_hz),
        mode.map(|m| m.natural_frequency_hz),
    ));
    rows.push((
        "ζ [-]",
        &u.damping_ratio,
        classroom.map(|c| c.damping_ratio),
        mode.map(|m| m.damping_ratio),
    ));
    rows
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_interval_shows_the_digits_its_width_needs() {
        let iv = |value: f64, half: f64| Interval {
            value,
            standard_error: half / 1.96,
            ci95: [value - half, value + half],
        };
        let narrow = interval(&iv(108.000141, 4.6e-4));
        assert_eq!(narrow, "108.00014 (107.99968 … 108.00060)");
        assert_eq!(interval(&iv(2.5, 0.1)), "2.5000 (2.4000 … 2.6000)");
    }
}
