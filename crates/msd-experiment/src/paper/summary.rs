//! The concise summary printed after a run: parameters with intervals, fit on both
//! records, residual, frequency and Monte Carlo verdicts, and the time of each stage.

use crate::fmt::{display_output, parameter_rows, parameter_units, sig};
use crate::paper::Outcome;
use crate::summary;
use std::fmt::Write;

/// The summary text of a finished run, but for the writer's footer (the stages' times,
/// where the report is).
pub fn text(outcome: &Outcome) -> String {
    let mut s = String::new();
    // Writing into a String cannot fail.
    let _ = sections(&mut s, outcome);
    s
}

fn sections(w: &mut String, o: &Outcome) -> std::fmt::Result {
    let set = &o.data.identification;
    let (factor, out_unit) = display_output(&set.output_unit);
    header(w, o)?;
    parameters(w, o)?;
    fits(w, o, factor, &out_unit)?;
    checks(w, o, factor, &out_unit)
}

/// The experiment's name and data, and how the solver ended.
fn header(w: &mut String, o: &Outcome) -> std::fmt::Result {
    let e = &o.estimate;
    let kind = match o.data.kind {
        crate::config::Kind::Synthetic => format!("synthetic data, seed {}", o.seed),
        crate::config::Kind::Measured if o.data.source == crate::data::Source::InMemory => {
            "data given in memory".to_string()
        }
        crate::config::Kind::Measured => "measured data".to_string(),
    };
    summary::head(w, &o.config.name, &format!("the paper's workflow: {kind}"));
    let solver = format!(
        "{}{}: {} iterations, {} evaluations, {}",
        crate::fmt::solver_start(e),
        if e.initial_guess.1 == msd_ident::estimate::GuessSource::Automatic {
            " (automatic)"
        } else {
            ""
        },
        e.iterations,
        e.evaluations,
        if e.stop.converged() {
            "converged".to_string()
        } else {
            format!("NOT converged ({})", e.stop.optimiser_reason())
        }
    );
    summary::labelled(w, "estimation", &solver);
    Ok(())
}

/// The parameters with their intervals (and the truth), ωn and the warnings.
fn parameters(w: &mut String, o: &Outcome) -> std::fmt::Result {
    let e = &o.estimate;
    let u = &e.uncertainty;
    let set = &o.data.identification;
    let units = parameter_units(&set.input_unit, &set.output_unit);
    writeln!(w)?;
    let rows: Vec<summary::Estimate> = parameter_rows(u, o.data.truth, &units)
        .into_iter()
        .map(|(label, truth, i)| summary::Estimate {
            label,
            value: i.value,
            interval: Some(i.ci95),
            truth,
        })
        .collect();
    summary::estimates(w, &rows);
    summary::labelled(
        w,
        "ωn",
        &format!("{} rad/s", sig(e.parameters.natural_frequency(), 5)),
    );
    let insignificant = insignificance(&o.significance);
    for warning in u.warnings.iter().chain(&o.data.notes).chain(&insignificant) {
        summary::labelled(w, "warning", warning);
    }
    Ok(())
}

/// R², fit % and RMS error on both records.
fn fits(w: &mut String, o: &Outcome, factor: f64, out_unit: &str) -> std::fmt::Result {
    let e = &o.estimate;
    writeln!(w)?;
    writeln!(
        w,
        "  {:<14} {:>8} {:>7} {:>12}",
        "data", "R²", "fit %", "RMS error"
    )?;
    let v = &o.validation;
    for (name, fit) in [("identification", &e.fit), ("validation", &v.fit)] {
        writeln!(
            w,
            "  {:<14} {:>8.5} {:>7.2} {:>9} {}",
            name,
            fit.r_squared,
            fit.fit_percent,
            sig(fit.residual_rms * factor, 4),
            out_unit
        )?;
    }
    if v.scored_from > 0 {
        writeln!(
            w,
            "  (validation scored after the first {} samples, which set the initial state)",
            v.scored_from
        )?;
    }
    Ok(())
}

/// The residual tests, the frequency check, the Monte Carlo band, the nonlinear models.
fn checks(w: &mut String, o: &Outcome, factor: f64, out_unit: &str) -> std::fmt::Result {
    writeln!(w)?;
    if let Some(r) = &o.residuals {
        writeln!(
            w,
            "  residuals      {}: {}; {}",
            r.ljung_box,
            if r.whiteness_passed {
                "white"
            } else {
                "NOT white"
            },
            if r.cross_correlation_passed {
                "uncorrelated with the input"
            } else {
                "correlated with the input"
            }
        )?;
    }
    if let Some(f) = o.frequency.check() {
        // The check's own rendering: the numbers on one line, its verdict on the next.
        for (i, line) in f.to_string().lines().enumerate() {
            let label = if i == 0 { "frequency" } else { "" };
            writeln!(w, "  {label:<14} {line}")?;
        }
    }
    if let Some(reason) = o.frequency.skipped() {
        writeln!(w, "  frequency      skipped: {reason}")?;
    }
    if let Some(mc) = &o.monte_carlo {
        writeln!(
            w,
            "  Monte Carlo    {} draws within ±{:.0} % on {} thread{}: the {:.0} % band holds {:.1} % of the validation measurements",
            mc.samples,
            mc.spread * 100.0,
            mc.threads,
            if mc.threads == 1 { "" } else { "s" },
            mc.percentiles[1] - mc.percentiles[0],
            mc.coverage * 100.0
        )?;
    }
    if let Some(n) = &o.nonlinear {
        writeln!(
            w,
            "  nonlinear      {}",
            nonlinear_line(n, factor, out_unit)
        )?;
    }
    Ok(())
}

/// One line on the nonlinear models: the winner, its BIC margin and validation RMS
/// against the linear model's (or the one model's scores).
fn nonlinear_line(
    n: &crate::paper::nonlinear::NonlinearOutcome,
    factor: f64,
    unit: &str,
) -> String {
    let c = &n.comparison;
    let best = c.best();
    let rms = |v: f64| format!("{} {unit}", sig(v * factor, 4));
    let mut line = if !n.comparison_asked {
        format!(
            "{}: validation RMS {} vs {} for the linear estimate; residuals {}",
            best.structure,
            rms(best.validation_rms),
            rms(n.linear_validation_rms),
            if best.whiteness_passed {
                "white"
            } else {
                "NOT white"
            }
        )
    } else if let Some(runner) = c.rows.get(1) {
        let linear = c.rows.iter().find(|r| r.structure.is_linear());
        format!(
            "{} ranks first of {} by BIC (ΔBIC {:.1} over {}: {}); validation RMS {}{}",
            best.structure,
            c.rows.len(),
            runner.delta_bic,
            runner.structure,
            msd_ident::nonlinear::bic_evidence(runner.delta_bic),
            rms(best.validation_rms),
            linear
                .filter(|l| !l.structure.eq(&best.structure))
                .map(|l| format!(" vs {} linear", rms(l.validation_rms)))
                .unwrap_or_default()
        )
    } else {
        format!(
            "only {} could be ranked: validation RMS {}",
            best.structure,
            rms(best.validation_rms)
        )
    };
    if !c.failures.is_empty() {
        line.push_str(&format!("; {} not ranked", c.failures.len()));
    }
    line
}

/// The words for a fit that does not explain the data significantly better than their
/// mean (`None` when it does).
///
/// ```
/// use msd_ident::FitMetrics;
/// let flat = FitMetrics::new(&[1.0, 2.0, 1.0, 2.0], &[1.5, 1.6, 1.5, 1.4]).f_test(3);
/// let text = msd_experiment::paper::summary::insignificance(&flat).unwrap();
/// assert!(text.contains("not explain the data significantly better than their mean"));
/// ```
pub fn insignificance(test: &msd_ident::FTest) -> Option<String> {
    (!test.significant).then(|| {
        format!(
            "the model does not explain the data significantly better than their mean (F = {:.3} with {} and {} dof, p = {:.3}): its white residuals are the data themselves, not evidence that the model is adequate",
            test.statistic, test.degrees_of_freedom[0], test.degrees_of_freedom[1], test.p_value
        )
    })
}
