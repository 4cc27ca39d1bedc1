//! The report's section on nonlinear models: the ranking table and verdict, every
//! candidate's parameters with their intervals, and the residual figure.

use crate::fmt::{parameter_units, sig};
use crate::paper::Outcome;
use crate::paper::nonlinear::NonlinearOutcome;
use std::fmt::Write;

/// Units of the parameters named `names` for data in `input` and `output` units.
fn units(names: &[String], input: &str, output: &str) -> Vec<String> {
    let linear = parameter_units(input, output);
    let newton_metre = input == "N" && output == "m";
    names
        .iter()
        .enumerate()
        .map(|(i, name)| match name.as_str() {
            _ if i < 3 => linear[i].clone(),
            "coulomb_force" => input.to_string(),
            "quadratic_damping" if newton_metre => "N·s²/m²".into(),
            "quadratic_damping" => format!("{input}·s²/{output}²"),
            "cubic_stiffness" if newton_metre => "N/m³".into(),
            _ => format!("{input}/{output}³"),
        })
        .collect()
}

/// The solver of the estimates, for the section's first sentence.
fn simulator(
    used: Option<msd_ident::nonlinear::SimulationUsed>,
    section: Option<&crate::config::NonlinearSection>,
) -> String {
    let simulation = section.map(|s| s.simulation).unwrap_or_default();
    match used.map(|u| u.solver) {
        Some(msd_ident::nonlinear::NonlinearSolver::Ode45) => format!(
            "ode45 on the continuous force with RelTol {:e} and AbsTol {:e}",
            simulation.rel_tol, simulation.abs_tol
        ),
        _ => "RK4 sample by sample on the hold polynomial of the force".into(),
    }
}

/// " (0.24 % of σ̂)": the RK4 output's error by step doubling against the row's
/// σ̂ = √(SSE/(N − p)); empty under ode45.
fn error_share(r: &msd_ident::nonlinear::ComparisonRow) -> String {
    let sigma = (r.sse / r.samples.saturating_sub(r.estimated).max(1) as f64).sqrt();
    match r.simulation.error_estimate {
        Some(e) if sigma > 0.0 => format!(" ({:.2} % of σ̂)", 100.0 * e / sigma),
        _ => String::new(),
    }
}

/// Appends the section to `w`; `has_figure` says whether `nonlinear_residuals` was drawn.
pub(super) fn section(
    w: &mut String,
    o: &Outcome,
    n: &NonlinearOutcome,
    has_figure: bool,
) -> std::fmt::Result {
    let c = &n.comparison;
    let id = &o.data.identification;
    let options = o.config.nonlinear.as_ref();
    writeln!(w, "## Beyond linear: nonlinear models\n")?;
    writeln!(
        w,
        "{} m·x″ + f_d(x′) + f_s(x) = F(t), estimated by output error on the identification record ({} samples; {} on {}, the Jacobian from the forward sensitivities, from the linear estimate) and predicting the validation record{}. {}\n",
        if n.comparison_asked {
            "Candidate models"
        } else {
            "One model"
        },
        id.len(),
        match options.map(|s| s.method) {
            Some(msd_ident::nonlinear::NonlinearMethod::NelderMead) => "Nelder–Mead",
            _ => "Levenberg–Marquardt",
        },
        simulator(c.rows.first().map(|r| r.simulation), options),
        match c.rows.first().map(|r| r.scored_from) {
            Some(k) if k > 0 => format!(
                " from the initial state fitted to its first {k} samples, which are not scored"
            ),
            _ => " from rest".to_string(),
        },
        if n.comparison_asked {
            "The linear model is always a candidate; the ranking is by BIC = N·ln(SSE/N) + p·ln N on the identification record (AIC = N·ln(SSE/N) + 2p beside it), p counting the estimated initial state too."
        } else {
            "Scored as a comparison would score it (SSE, AIC, BIC on the identification record)."
        }
    )?;
    if let Some(p) = &n.plant {
        let values: Vec<String> = p
            .names()
            .iter()
            .zip(&p.values)
            .map(|(name, v)| format!("{name} = {}", sig(*v, 5)))
            .collect();
        writeln!(
            w,
            "The data were simulated from a plant with nonlinear terms, model `{}`: {}.\n",
            p.structure,
            values.join(", ")
        )?;
    }
    writeln!(w, "{c}")?;
    if c.rows.len() > 1 && !c.best().whiteness_passed {
        writeln!(
            w,
            "BIC assumes independent residuals; the best model's are not white, so the BIC margins overstate the evidence: weigh the validation RMS errors as well.\n"
        )?;
    }
    writeln!(
        w,
        "Parameters of each candidate (95 % intervals from the Gauss–Newton covariance, Student's t):\n"
    )?;
    parameter_table(w, o, n)?;
    writeln!(w, "Simulation of each candidate at its estimate:\n")?;
    for r in &c.rows {
        writeln!(w, "- `{}`: {}{}", r.structure, r.simulation, error_share(r))?;
    }
    writeln!(w)?;
    if has_figure {
        writeln!(
            w,
            "![Validation residuals of the candidate models](nonlinear_residuals.png)\n"
        )?;
        writeln!(
            w,
            "*Validation residuals (measured − model) of each candidate over time, with their RMS in the legend{}.*\n",
            if c.rows.len() > 1 {
                "; the best-ranked drawn last, on top"
            } else {
                ""
            }
        )?;
    }
    Ok(())
}

/// Each candidate's parameters with their intervals (and the truth when known).
fn parameter_table(w: &mut String, o: &Outcome, n: &NonlinearOutcome) -> std::fmt::Result {
    let c = &n.comparison;
    let id = &o.data.identification;
    let with_truth = n.plant.is_some();
    writeln!(
        w,
        "| model | parameter | estimate | standard error | 95 % interval |{}\n|---|---|---|---|---|{}",
        if with_truth { " true |" } else { "" },
        if with_truth { "---|" } else { "" }
    )?;
    for r in &c.rows {
        let units = units(&r.names, &id.input_unit, &id.output_unit);
        for ((name, iv), unit) in r.names.iter().zip(&r.intervals).zip(&units) {
            let truth = n
                .plant
                .as_ref()
                .map(|p| p.get(name).map(|v| sig(v, 5)).unwrap_or_else(|| "0".into()));
            writeln!(
                w,
                "| {} | {name} [{unit}] | {} | {} | [{}, {}] |{}",
                r.structure,
                sig(iv.value, 5),
                sig(iv.standard_error, 3),
                sig(iv.ci95[0], 5),
                sig(iv.ci95[1], 5),
                truth.map(|t| format!(" {t} |")).unwrap_or_default()
            )?;
        }
    }
    writeln!(w)?;
    for r in &c.rows {
        writeln!(w, "{}: {}.\n", r.structure, r.covariance_used)?;
    }
    Ok(())
}
