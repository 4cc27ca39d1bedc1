//! The report of an operational run, and the summary the command prints.

use super::OperationalOutcome;
use crate::fmt::sig;
use crate::summary;
use msd_modal::Mode;
use std::fmt::Write;

/// `report.md` of `o`, with `figures` embedded.
pub(crate) fn markdown(o: &OperationalOutcome, figures: &[&str]) -> String {
    let mut s = String::new();
    // Writing into a String cannot fail.
    let _ = page(&mut s, o, figures);
    s
}

fn page(s: &mut String, o: &OperationalOutcome, figures: &[&str]) -> std::fmt::Result {
    let simulated = o.section.simulate.is_some();
    let run = (&o.config, o.config_path.as_path(), o.command.as_str());
    crate::results::report_head(s, run, &what(o), simulated.then_some(o.seed), &[])?;
    crate::verdict::section(s, &o.verdict)?;
    record(s, o)?;
    modes(s, o)?;
    for f in figures {
        writeln!(s, "![{f}]({f}.png)\n")?;
    }
    method(s, o)?;
    writeln!(s, "## Files\n")?;
    writeln!(
        s,
        "`results.json` (every mode with its intervals and shape, the diagram's poles), `modes.csv`, `shapes.csv`, `modes.uff` (the shapes as UFF datasets 55, a node's oblique channels resolved into x, y, z), the figures as PNG and SVG.\n"
    )
}

fn record(s: &mut String, o: &OperationalOutcome) -> std::fmt::Result {
    let r = &o.record;
    let what = if o.truth.is_some() {
        "simulated (a shear building, the truth known)"
    } else {
        "measured"
    };
    writeln!(s, "## Record\n")?;
    writeln!(
        s,
        "{} channels, {} samples at {} Hz ({} s), {what}.\n",
        r.channels().len(),
        r.len(),
        sig(r.sample_rate_hz(), 6),
        sig(r.len() as f64 / r.sample_rate_hz(), 4)
    )?;
    writeln!(
        s,
        "| channel | DOF | direction | quantity | reference |\n|---|---|---|---|---|"
    )?;
    let refs = r.reference_indices();
    for (i, c) in r.channels().iter().enumerate() {
        let direction = c.direction.map_or_else(
            || format!("{:+}", c.dof.unwrap_or_default().direction),
            |[x, y, z]| format!("oblique ({x:.3}, {y:.3}, {z:.3})"),
        );
        let quantity = c.quantity;
        let reference = if refs.contains(&i) { "yes" } else { "" };
        writeln!(
            s,
            "| {} | {} | {direction} | {quantity} | {reference} |",
            c.name,
            c.dof.unwrap_or_default().node
        )?;
    }
    writeln!(s)?;
    for (name, why) in &o.left_out {
        writeln!(s, "Left out: **{name}** — {why}.\n")?;
    }
    Ok(())
}

fn modes(s: &mut String, o: &OperationalOutcome) -> std::fmt::Result {
    writeln!(s, "## Modes\n")?;
    let truth = o.truth.as_deref();
    let true_col = if truth.is_some() {
        " true fn [Hz] |"
    } else {
        ""
    };
    writeln!(
        s,
        "| mode | fn [Hz] (95 % interval) | ζ [%] (95 % interval) | MPC | orders | spread of fn over its poles [Hz] |{true_col}\n|---|---|---|---|---|---|{}",
        if truth.is_some() { "---|" } else { "" }
    )?;
    for (k, m) in o.fit.modes.iter().enumerate() {
        let f = &m.natural_frequency_hz;
        let z = &m.damping_ratio;
        let spread = m
            .cluster_spread
            .map_or("—".to_string(), |[sf, _]| sig(sf, 2));
        let [fv, f0, f1] = digits(f, 1.0, 6);
        let [zv, z0, z1] = digits(z, 100.0, 3);
        write!(
            s,
            "| {} | {fv} ({f0} … {f1}) | {zv} ({z0} … {z1}) | {} | {} | {spread} |",
            k + 1,
            m.mpc.map_or("—".into(), |v| format!("{v:.3}")),
            m.stable_orders.map_or("—".into(), |n| n.to_string()),
        )?;
        if let Some(truth) = truth {
            let nearest = truth
                .iter()
                .map(|(t, _)| *t)
                .min_by(|a, b| (a - f.value).abs().total_cmp(&(b - f.value).abs()));
            write!(s, " {} |", nearest.map_or("—".into(), |t| sig(t, 6)))?;
        }
        writeln!(s)?;
    }
    writeln!(s)?;
    if !o.fit.unconfirmed.is_empty() {
        writeln!(
            s,
            "Not reported as modes (the record less one block lost them, or they split a reported mode: within 1 % and MAC ≥ 0.9 of it): {}.\n",
            o.fit
                .unconfirmed
                .iter()
                .map(|c| match c.stable_orders {
                    0 => format!(
                        "{} Hz (ζ {} %)",
                        sig(c.natural_frequency_hz, 5),
                        sig(100.0 * c.damping_ratio, 2)
                    ),
                    n => format!(
                        "{} Hz (ζ {} %, {n} orders)",
                        sig(c.natural_frequency_hz, 5),
                        sig(100.0 * c.damping_ratio, 2)
                    ),
                })
                .collect::<Vec<_>>()
                .join("; ")
        )?;
    }
    shapes(s, o)
}

fn shapes(s: &mut String, o: &OperationalOutcome) -> std::fmt::Result {
    let modes: &[Mode] = &o.fit.modes;
    if modes.is_empty() {
        return Ok(());
    }
    writeln!(
        s,
        "### Shapes (displacement, largest entry 1; real part ± its standard error)\n"
    )?;
    // One row per mode, one column per channel: the table stays narrow.
    write!(s, "| mode |")?;
    for (c, channel) in o.record.channels().iter().enumerate() {
        // An oblique channel's DOF has direction 0: its name tells the three apart.
        let dof = modes[0].shape.get(c).map(|e| e.dof());
        match (channel.direction, dof) {
            (Some(_), Some(d)) => write!(s, " {} ({}, oblique) |", channel.name, d.node)?,
            (_, Some(d)) => write!(s, " {} ({d}) |", channel.name)?,
            (_, None) => write!(s, " {} |", channel.name)?,
        }
    }
    writeln!(s, "\n|---|{}", "---|".repeat(o.record.channels().len()))?;
    for (k, m) in modes.iter().enumerate() {
        write!(s, "| {} |", k + 1)?;
        for entry in &m.shape {
            let se = entry
                .standard_error
                .map_or(String::new(), |[re, _]| format!(" ± {}", sig(re, 2)));
            write!(s, " {}{se} |", sig(entry.re, 3))?;
        }
        writeln!(s)?;
    }
    writeln!(s)
}

fn method(s: &mut String, o: &OperationalOutcome) -> std::fmt::Result {
    let f = &o.fit;
    writeln!(s, "## Method\n")?;
    let jackknife = format!(
        "Each interval comes from the same analysis of the record less one of its {} blocks in turn (the jackknife), with Student's t on {} degrees of freedom.",
        f.blocks,
        f.blocks.saturating_sub(1)
    );
    match (f.block_rows, &f.spectrum) {
        (Some(i), _) => writeln!(
            s,
            "{}: the covariances of every channel with the references ({}) at lags 1 … {} fill a block Toeplitz matrix of {i} block rows{}; its SVD gives the poles and shapes at model orders {}–{}. A pole is stable when the order before has one within 1 % in fn and MAC ≥ 0.98; the stable poles are clustered (average linkage on |Δf|/f + 1 − MAC) and a cluster with poles at enough orders is a mode, its estimate the mean of its poles at every fourth order. {jackknife} Every threshold is an option of `[operational.ssi]` (configs/README.md).\n",
            f.method,
            f.references.join(", "),
            2 * i - 1,
            if f.method == msd_modal::OmaMethod::SsiDat {
                ", weighted on the right by the inverse Cholesky factor of the past references' covariance matrix (the data-driven algorithm's projection of the future outputs on the past references)"
            } else {
                ""
            },
            f.diagram.orders.first().map_or(0, |o| o.order),
            f.diagram.orders.last().map_or(0, |o| o.order),
        ),
        (None, Some(spectrum)) => writeln!(
            s,
            "{}: the spectral matrix of the channels (each quantity scaled to unit variance) from their covariances at lags 0 … {} under an exponential window, its singular values line by line ({} Hz apart). Each clear peak of the first singular value is a mode, its shape the first singular vector there; the lines around it whose vectors keep MAC ≥ 0.85 form its SDOF bell, whose inverse transform (the window divided out) is the mode's correlation function: fn from its zero crossings, ζ from the logarithmic decrement of its extremes. EFDD is the quick look: modes closer than a few half-power bandwidths pull each other's fn and ζ (SSI-cov, the default method, does not). {jackknife} Every threshold is an option of `[operational.efdd]` (configs/README.md).\n",
            f.method,
            spectrum.lags - 1,
            sig(spectrum.frequency_hz.get(1).copied().unwrap_or(0.0), 3),
        ),
        (None, None) => Ok(()),
    }
}

/// What the run identifies from what, for the summary's and the report's head.
fn what(o: &OperationalOutcome) -> String {
    format!(
        "output-only modal analysis by {}: {} channels at {} Hz; {}",
        o.fit.method,
        o.record.channels().len(),
        o.record.sample_rate_hz(),
        summary::data(o.truth.is_some().then_some(o.seed))
    )
}

/// What the command prints: what was analysed, the verdict, the modes.
pub(crate) fn summary(o: &OperationalOutcome) -> String {
    let mut s = String::new();
    summary::head(&mut s, &o.config.name, &what(o));
    summary::verdict(&mut s, &o.verdict);
    s.push('\n');
    let rows: Vec<summary::ModeRow> = (o.fit.modes.iter())
        .map(|m| summary::ModeRow::of(m, String::new()))
        .collect();
    summary::modes(&mut s, &rows);
    s
}

/// An estimate and its interval's ends, times `scale`, to `digits` significant digits.
fn digits(i: &msd_ident::Interval, scale: f64, digits: usize) -> [String; 3] {
    [i.value, i.ci95[0], i.ci95[1]].map(|v| sig(scale * v, digits))
}
