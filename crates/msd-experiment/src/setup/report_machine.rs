//! The test machine's part of `report.md`: one row per condition, the damping laws
//! ranked by BIC.

use crate::fmt::sig;
use crate::verdict::{Finding, Verdict};
use msd_ident::dynamometer::Dynamometer;
use std::fmt::Write;

/// Writes the conditions table and the law comparison.
pub(crate) fn section(s: &mut String, m: &Dynamometer) -> std::fmt::Result {
    writeln!(
        s,
        "## Test conditions\n\nPer condition, from the harmonic content of the stroke and the force ({} harmonics): the energy dissipated per cycle E = ∮F dx, the equivalent viscous damping c_eq = E/(π·ω·X²), the storage stiffness k′ (in-phase force over X), the loss factor η and the peaks.\n",
        m.harmonics
    )?;
    writeln!(
        s,
        "| condition | f [Hz] | X [m] | E [J] | c_eq [N·s/m] | k′ [N/m] | η | peak F [N] | peak v [m/s] |\n|---|---|---|---|---|---|---|---|---|"
    )?;
    for c in &m.conditions {
        writeln!(
            s,
            "| {} | {}{} | {} | {} | {} | {} | {} | {} | {} |",
            c.name,
            sig(c.frequency_hz, 5),
            if c.frequency_estimated { " (est.)" } else { "" },
            sig(c.amplitude, 4),
            sig(c.energy_per_cycle, 5),
            sig(c.equivalent_damping, 5),
            sig(c.storage_stiffness, 5),
            sig(c.loss_factor, 4),
            sig(c.peak_force, 5),
            sig(c.peak_velocity, 4)
        )?;
    }
    writeln!(
        s,
        "\n## Damping laws\n\nF = m·x″ + k·x + f_d(x′) fitted to every condition at once, ranked by BIC (ΔBIC > 10: very strong evidence against the lower-ranked law).\n\n| rank | law | coefficients (95 % interval) | σ̂ force [N] | R² | ΔBIC |\n|---|---|---|---|---|---|"
    )?;
    for law in &m.laws {
        let coefficients: Vec<String> = law
            .names
            .iter()
            .zip(&law.coefficients)
            .map(|(n, iv)| {
                format!(
                    "{n} = {} [{}, {}]",
                    sig(iv.value, 5),
                    sig(iv.ci95[0], 5),
                    sig(iv.ci95[1], 5)
                )
            })
            .collect();
        writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            law.rank,
            law.law.formula(),
            coefficients.join("; "),
            sig(law.force_sigma, 4),
            sig(law.fit.r_squared, 6),
            sig(law.delta_bic, 4)
        )?;
    }
    writeln!(s, "\n{}\n", m.verdict)?;
    if let Some(predictions) = &m.leave_one_out {
        writeln!(
            s,
            "## Validation on fresh data\n\nEach condition's force predicted by the best law ({}) fitted to the other conditions (leave one condition out).\n\n| condition left out | R² | fit % | RMS error [N] |\n|---|---|---|---|",
            m.best_law().law.formula()
        )?;
        for p in predictions {
            writeln!(
                s,
                "| {} | {} | {} | {} |",
                p.condition,
                sig(p.fit.r_squared, 6),
                sig(p.fit.fit_percent, 4),
                sig(p.fit.residual_rms, 3)
            )?;
        }
        writeln!(s)?;
    }
    Ok(())
}

/// The summary's validation line: the worst condition predicted by the others.
pub(crate) fn summary(s: &mut String, m: &Dynamometer) {
    let worst = (m.leave_one_out.iter().flatten())
        .min_by(|a, b| a.fit.r_squared.total_cmp(&b.fit.r_squared));
    if let Some(p) = worst {
        let how = "leave one condition out";
        crate::summary::fresh_data(s, how, &p.fit, Some(&p.condition));
    }
}

/// The test machine's verdict: the best law's standing against the runner-up (BIC), and
/// each condition predicted by the law fitted to the others.
pub(crate) fn verdict(m: &Dynamometer) -> Verdict {
    let best = m.best_law();
    let mut findings = Vec::new();
    let runner = m.laws.iter().find(|l| l.rank == 2);
    findings.push(Finding::passed(match runner {
        Some(r) => format!(
            "the law {} ranks first, ΔBIC {} over {} (on Kass & Raftery's scale, > 10 is very strong evidence)",
            best.law.formula(),
            sig(r.delta_bic, 3),
            r.law.formula()
        ),
        None => format!("one law fitted: {}", best.law.formula()),
    }));
    if let Some(predictions) = &m.leave_one_out {
        let worst = (predictions.iter()).min_by(|a, b| a.fit.r_squared.total_cmp(&b.fit.r_squared));
        if let Some(p) = worst {
            findings.push(Finding::passed(format!(
                "each condition predicted by the law fitted to the others: worst R² {} ({})",
                sig(p.fit.r_squared, 4),
                p.condition
            )));
        }
        let missed: Vec<String> = (predictions.iter())
            .filter(|p| p.fit.r_squared < 0.5 && p.fit.residual_rms > 1.5 * best.force_sigma)
            .map(|p| format!("`{}`", p.condition))
            .collect();
        if !missed.is_empty() {
            findings.push(Finding::failed(format!(
                "the law fitted to the other conditions does not predict {}: its force error is well above the fit's noise",
                missed.join(", ")
            )));
        }
    }
    Verdict::of(findings)
}
