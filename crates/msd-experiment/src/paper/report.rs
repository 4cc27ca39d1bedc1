//! The paper workflow's `report.md`: the run told for a person, with the figures
//! embedded.

use super::Outcome;
use crate::config::Kind;
use crate::fmt::{display_output, method_name, parameter_rows, parameter_units, short, sig};
use std::fmt::Write;

mod nonlinear;

/// The paper's reported R² on the identification and validation data.
pub const PAPER_R2: [f64; 2] = [0.9907, 0.9949];

fn yes(b: bool) -> &'static str {
    if b { "yes" } else { "**no**" }
}

/// The markdown report of `outcome` (but for its timings, which the writer adds);
/// `figures` are the base names written.
pub fn markdown(outcome: &Outcome, figures: &[&str]) -> String {
    let id = &outcome.data.identification;
    let (factor, out_unit) = display_output(&id.output_unit);
    let page = Page {
        outcome,
        figures,
        units: parameter_units(&id.input_unit, &id.output_unit),
        factor,
        out_unit,
    };
    let mut s = String::new();
    // Writing into a String cannot fail.
    let _ = sections(&mut s, &page);
    s
}

/// What every section reads: the outcome, the figures written and the output's display
/// unit.
struct Page<'a> {
    outcome: &'a Outcome,
    figures: &'a [&'a str],
    units: [String; 3],
    /// Output values are multiplied by this for display in `out_unit` (m → mm).
    factor: f64,
    out_unit: String,
}

impl Page<'_> {
    /// Whether the figure `name` was written.
    fn has(&self, name: &str) -> bool {
        self.figures.contains(&name)
    }
}

fn sections(w: &mut String, c: &Page<'_>) -> std::fmt::Result {
    header(w, c)?;
    in_short(w, c)?;
    data(w, c)?;
    parameters(w, c)?;
    fit(w, c)?;
    residuals(w, c)?;
    frequency(w, c)?;
    monte_carlo(w, c)?;
    if let Some(n) = &c.outcome.nonlinear {
        nonlinear::section(w, c.outcome, n, c.has("nonlinear_residuals"))?;
    }
    files(w, c)
}

/// The title, the description and the run's table.
fn header(w: &mut String, c: &Page<'_>) -> std::fmt::Result {
    let o = c.outcome;
    let e = &o.estimate;
    let what = format!(
        "identification of mass *m*, damping *c* and stiffness *k* of m·x″ + c·x′ + k·x = F(t) from {}",
        match o.data.kind {
            Kind::Synthetic => "synthetic data generated from a known plant",
            Kind::Measured => "a measured record",
        }
    );
    let method = format!("{} on {}", method_name(e.method), e.backend.name());
    let rows = [
        ("method", method),
        ("worker threads", o.threads.to_string()),
    ];
    let run = (&o.config, o.config_path.as_path(), o.command.as_str());
    let seed = (o.data.kind == Kind::Synthetic).then_some(o.seed);
    crate::results::report_head(w, run, &what, seed, &rows)
}

/// The story in one paragraph: fit, truth, residuals, frequency, Monte Carlo, warnings.
fn in_short(w: &mut String, c: &Page<'_>) -> std::fmt::Result {
    let o = c.outcome;
    let u = &o.estimate.uncertainty;
    let e = &o.estimate;
    writeln!(w, "## In short\n")?;
    let mut verdicts = vec![format!(
        "The model explains {:.2} % of the variance of the identification data (R² = {:.4}) and {:.2} % of the validation data it never saw (R² = {:.4}).",
        100.0 * e.fit.r_squared,
        e.fit.r_squared,
        100.0 * o.validation.fit.r_squared,
        o.validation.fit.r_squared
    )];
    if let Some(t) = &o.data.truth {
        let within: Vec<&str> = [
            ("m", &u.mass, t.mass),
            ("c", &u.damping, t.damping),
            ("k", &u.stiffness, t.stiffness),
        ]
        .iter()
        .filter(|(_, i, v)| i.contains(*v))
        .map(|(n, _, _)| *n)
        .collect();
        verdicts.push(format!(
            "The true values lie inside the 95 % intervals for {} of 3 parameters{}.",
            within.len(),
            if within.is_empty() {
                String::new()
            } else {
                format!(" ({})", within.join(", "))
            }
        ));
    }
    if let Some(r) = &o.residuals {
        verdicts.push(r.verdict.clone());
    }
    if let Some(note) = crate::paper::summary::insignificance(&o.significance) {
        verdicts.push(format!("But {note}."));
    }
    if let Some(f) = o.frequency.check() {
        verdicts.push(f.verdict.clone());
    }
    if let Some(reason) = o.frequency.skipped() {
        verdicts.push(format!("The frequency-domain check was skipped: {reason}."));
    }
    if let Some(mc) = &o.monte_carlo {
        verdicts.push(format!(
            "With every parameter varied within ±{:.0} %, the {:.0} % Monte Carlo band holds {:.1} % of the validation measurements.",
            mc.spread * 100.0,
            mc.percentiles[1] - mc.percentiles[0],
            mc.coverage * 100.0
        ));
    }
    for warning in u.warnings.iter().chain(&o.data.notes) {
        verdicts.push(format!("Warning: {warning}."));
    }
    writeln!(w, "{}\n", verdicts.join(" "))?;
    Ok(())
}

/// Where the records come from, and their grids.
fn data(w: &mut String, c: &Page<'_>) -> std::fmt::Result {
    let o = c.outcome;
    writeln!(w, "## Data\n")?;
    match &o.data.source {
        crate::data::Source::InMemory => {
            writeln!(
                w,
                "Both records were given in memory by the calling program (no file was read).\n"
            )?;
        }
        crate::data::Source::Synthetic { sigma } => {
            writeln!(
                w,
                "Both records are simulated {} and corrupted with white Gaussian noise of σ = {} {} (independent seeded streams \"identification\" and \"validation\").\n",
                match o.config.plant.as_ref().and_then(|p| p.nonlinear()) {
                    Some(p) => format!(
                        "by ode45 (RelTol 1e-8) from the true plant with nonlinear terms ({p})"
                    ),
                    None => "exactly from the true plant".to_string(),
                },
                sig(sigma * c.factor, 3),
                c.out_unit
            )?;
        }
        crate::data::Source::Measured {
            path,
            rows,
            dt,
            estimation_range,
            validation_range,
        } => {
            writeln!(
                w,
                "File `{}`: {rows} rows, dt = {} s ({} Hz) after preprocessing. Estimation samples {}..{}, validation samples {}..{} (0-based, end excluded).\n",
                path.file_name()
                    .map(|f| f.to_string_lossy())
                    .unwrap_or_default(),
                sig(*dt, 6),
                sig(1.0 / dt, 6),
                estimation_range[0],
                estimation_range[1],
                validation_range[0],
                validation_range[1]
            )?;
        }
    }
    writeln!(
        w,
        "| record | samples | t₀ [s] | dt [s] | duration [s] |\n|---|---|---|---|---|"
    )?;
    for d in [&o.data.identification, &o.data.validation] {
        writeln!(
            w,
            "| {} | {} | {} | {} | {} |",
            d.name,
            d.len(),
            short(d.excitation.t0()),
            short(d.excitation.dt()),
            short(d.excitation.dt() * (d.len() - 1) as f64)
        )?;
    }
    writeln!(w)?;
    Ok(())
}

/// The estimates with their intervals, the solver's account and the correlation.
fn parameters(w: &mut String, c: &Page<'_>) -> std::fmt::Result {
    let o = c.outcome;
    let e = &o.estimate;
    let u = &e.uncertainty;
    writeln!(w, "## Estimated parameters\n")?;
    let truth = o.data.truth;
    let header = if truth.is_some() {
        "| quantity | true | estimate | standard error | 95 % interval | error / SE |\n|---|---|---|---|---|---|"
    } else {
        "| quantity | estimate | standard error | 95 % interval |\n|---|---|---|---|"
    };
    writeln!(w, "{header}")?;
    let rows = parameter_rows(u, truth, &c.units);
    for (name, true_value, i) in rows {
        let interval = format!("[{}, {}]", sig(i.ci95[0], 5), sig(i.ci95[1], 5));
        match true_value {
            Some(t) => {
                let z = if i.standard_error > 0.0 {
                    (i.value - t) / i.standard_error
                } else {
                    0.0
                };
                writeln!(
                    w,
                    "| {name} | {} | {} | {} | {interval} | {z:+.2} |",
                    sig(t, 5),
                    sig(i.value, 5),
                    sig(i.standard_error, 3)
                )?;
            }
            None => {
                writeln!(
                    w,
                    "| {name} | {} | {} | {interval} |",
                    sig(i.value, 5),
                    sig(i.standard_error, 3)
                )?;
            }
        }
    }
    writeln!(
        w,
        "\nωn = {} rad/s. Intervals: Gauss–Newton covariance σ̂²(JᵀJ)⁻¹ from the exact sensitivities (σ̂ = {} {}, {} degrees of freedom), Student's t; fn and ζ by the delta method.\n",
        sig(e.parameters.natural_frequency(), 5),
        sig(u.sigma * c.factor, 4),
        c.out_unit,
        u.degrees_of_freedom
    )?;
    writeln!(
        w,
        "Solver: {} ({}): {} iterations, {} cost evaluations{}, {}; final cost Σr² = {}. Condition number of the scaled JᵀJ: {}.\n",
        crate::fmt::solver_start(e),
        match e.initial_guess.1 {
            msd_ident::estimate::GuessSource::Given => "given",
            msd_ident::estimate::GuessSource::Automatic => "automatic ARX guess",
        },
        e.iterations,
        e.evaluations,
        if e.jacobian_evaluations > 0 {
            format!(", {} Jacobians", e.jacobian_evaluations)
        } else {
            String::new()
        },
        if e.stop.converged() {
            format!("converged ({})", e.stop)
        } else {
            format!("**not converged** ({})", e.stop.optimiser_reason())
        },
        sig(e.cost, 5),
        sig(u.condition_number, 3)
    )?;
    if let Some(s) = o.estimation_solver {
        let (a, r, n) = (s.accepted_steps, s.rejected_steps, s.rhs_evaluations);
        write!(
            w,
            "ode45 at θ̂ on the identification record: {a} accepted and {r} rejected steps, {n} right-hand-side evaluations"
        )?;
        match o.validation.solver {
            Some(s) => {
                let (a, r, n) = (s.accepted_steps, s.rejected_steps, s.rhs_evaluations);
                writeln!(w, "; on the validation record: {a}, {r} and {n}.\n")?;
            }
            None => {
                writeln!(w, ".\n")?;
            }
        }
    }
    correlation(w, u)
}

/// The estimates' correlation matrix (one estimated quantity has none).
fn correlation(w: &mut String, u: &msd_ident::Uncertainty) -> std::fmt::Result {
    let names = &u.names;
    if names.len() > 1 {
        writeln!(w, "Correlation of the estimates:\n")?;
        writeln!(w, "| | {} |", names.join(" | "))?;
        writeln!(w, "|---|{}", "---|".repeat(names.len()))?;
        for r in 0..names.len() {
            let cells: Vec<String> = (0..names.len())
                .map(|c| format!("{:+.3}", u.correlation[(r, c)]))
                .collect();
            writeln!(w, "| {} | {} |", names[r], cells.join(" | "))?;
        }
        writeln!(w)?;
    }
    Ok(())
}

/// R², fit % and RMS error on both records, figures 2 and 3.
fn fit(w: &mut String, c: &Page<'_>) -> std::fmt::Result {
    let o = c.outcome;
    let out_unit = &c.out_unit;
    let e = &o.estimate;
    let truth = o.data.truth;
    writeln!(w, "## Fit\n")?;
    writeln!(
        w,
        "| record | R² | fit % | RMS error [{out_unit}] |{}\n|---|---|---|---|{}",
        if truth.is_some() {
            " R² of the true response |"
        } else {
            ""
        },
        if truth.is_some() { "---|" } else { "" }
    )?;
    let ceiling = |t: &Option<Vec<f64>>, y: &[f64]| {
        t.as_ref()
            .map(|t| msd_ident::FitMetrics::new(y, t).r_squared)
    };
    for (name, fit, true_r2) in [
        (
            "identification",
            &e.fit,
            ceiling(&o.data.identification_truth, &o.data.identification.output),
        ),
        (
            "validation",
            &o.validation.fit,
            o.validation.truth_fit.map(|f| f.r_squared),
        ),
    ] {
        writeln!(
            w,
            "| {name} | {:.5} | {:.2} | {} |{}",
            fit.r_squared,
            fit.fit_percent,
            sig(fit.residual_rms * c.factor, 4),
            true_r2.map(|r2| format!(" {r2:.5} |")).unwrap_or_default()
        )?;
    }
    if truth.is_some() {
        writeln!(
            w,
            "\nThe R² of the true (noise-free) response is the best any model can reach on these noisy records. The paper reports R² = {} (identification) and {} (validation).",
            PAPER_R2[0], PAPER_R2[1]
        )?;
    }
    if o.validation.scored_from > 0 {
        writeln!(
            w,
            "\nThe validation prediction starts from the initial state that best explains its first {} samples (parameters held); those samples are not scored.",
            o.validation.scored_from
        )?;
    }
    writeln!(w)?;
    if c.has("fig2_identification") {
        writeln!(
            w,
            "![Figure 2: excitation, measurement and model fit, residuals](fig2_identification.png)\n"
        )?;
        writeln!(
            w,
            "*Figure 2 — identification: the excitation (top), the measurement and the model's fit (middle), the residuals (bottom).*\n"
        )?;
    }
    if c.has("fig3_validation") {
        writeln!(w, "![Figure 3: validation](fig3_validation.png)\n")?;
        writeln!(
            w,
            "*Figure 3 — validation on data never used for fitting: measurements, the model's prediction{}.*\n",
            if o.data.validation_truth.is_some() {
                " and the true response"
            } else {
                ""
            }
        )?;
    }
    Ok(())
}

/// The residual tests.
fn residuals(w: &mut String, c: &Page<'_>) -> std::fmt::Result {
    let o = c.outcome;
    if let Some(r) = &o.residuals {
        writeln!(w, "## Residual diagnostics\n")?;
        writeln!(w, "{}\n", r.verdict)?;
        writeln!(w, "| test | statistic | passed |\n|---|---|---|")?;
        writeln!(
            w,
            "| whiteness (Ljung–Box, {} lags) | Q = {:.2}, p = {:.4} | {} |",
            r.ljung_box.degrees_of_freedom,
            r.ljung_box.q,
            r.ljung_box.p_value,
            yes(r.whiteness_passed)
        )?;
        writeln!(
            w,
            "| autocorrelation inside ±{:.4} | {} of {} lags outside, max \\|r\\| = {:.4} | {} |",
            r.autocorrelation.bound,
            r.autocorrelation.outside,
            r.autocorrelation.lags.len().saturating_sub(1),
            r.autocorrelation.max_abs,
            yes(r.autocorrelation.passed)
        )?;
        writeln!(
            w,
            "| residual–input cross-correlation | max \\|ρ\\| = {:.4}, {} of {} lags outside ±{:.4} | {} |",
            r.cross_correlation.max_abs,
            r.cross_correlation.outside,
            r.cross_correlation.lags.len(),
            r.cross_correlation.bound,
            yes(r.cross_correlation_passed)
        )?;
        if let Some(vr) = &o.validation.residual_analysis {
            writeln!(
                w,
                "| validation residuals: Ljung–Box | Q = {:.2}, p = {:.4} | {} |",
                vr.ljung_box.q,
                vr.ljung_box.p_value,
                yes(vr.whiteness_passed)
            )?;
            writeln!(
                w,
                "| validation residuals: input cross-correlation | max \\|ρ\\| = {:.4} | {} |",
                vr.cross_correlation.max_abs,
                yes(vr.cross_correlation_passed)
            )?;
        }
        writeln!(w)?;
        if c.has("residual_correlation") {
            writeln!(w, "![Residual correlations](residual_correlation.png)\n")?;
        }
    }
    Ok(())
}

/// The frequency-domain check, or why it was skipped.
fn frequency(w: &mut String, c: &Page<'_>) -> std::fmt::Result {
    let o = c.outcome;
    if let Some(f) = o.frequency.check() {
        writeln!(w, "## Frequency-domain consistency\n")?;
        writeln!(w, "{}\n", f.verdict)?;
        writeln!(w, "| | fn [Hz] | ζ |\n|---|---|---|")?;
        writeln!(
            w,
            "| single-mode fit to the {} data's DFT | {} | {} |",
            o.config.frequency_check.data.name(),
            sig(f.natural_frequency_hz, 5),
            sig(f.damping_ratio, 4)
        )?;
        writeln!(
            w,
            "| identified model | {} | {} |",
            sig(f.model_natural_frequency_hz, 5),
            sig(f.model_damping_ratio, 4)
        )?;
        writeln!(
            w,
            "\nFit band {}–{} Hz; normalised output error of the model in the band {:.3}.\n",
            sig(f.band_hz[0], 3),
            sig(f.band_hz[1], 3),
            f.model_relative_error
        )?;
        if c.has("frf_bode") {
            writeln!(w, "![Bode plot](frf_bode.png)\n")?;
        }
    }
    if let Some(reason) = o.frequency.skipped() {
        writeln!(w, "## Frequency-domain consistency\n")?;
        writeln!(
            w,
            "Skipped: {reason}. The check fits one underdamped mode (ζ < 1) to the record's \
             spectrum where the input excites it; without such a resonance there (a damper \
             at or past critical damping, a mode outside the excited band) or without input \
             power it has nothing to measure, and the time-domain results above stand \
             without it.\n"
        )?;
    }
    Ok(())
}

/// The Monte Carlo band.
fn monte_carlo(w: &mut String, c: &Page<'_>) -> std::fmt::Result {
    let o = c.outcome;
    let out_unit = &c.out_unit;
    if let Some(mc) = &o.monte_carlo {
        writeln!(w, "## Monte Carlo robustness\n")?;
        writeln!(
            w,
            "{} parameter sets drawn independently and uniformly within ±{:.0} % of θ̂ ({} on the validation record, {} thread{}), each simulated on the validation input; the pointwise {:.0}th and {:.0}th percentiles form the band.\n",
            mc.samples,
            mc.spread * 100.0,
            mc.backend.name(),
            mc.threads,
            if mc.threads == 1 { "" } else { "s" },
            mc.percentiles[0],
            mc.percentiles[1]
        )?;
        let widths: Vec<f64> = mc.upper.iter().zip(&mc.lower).map(|(h, l)| h - l).collect();
        let mean = widths.iter().sum::<f64>() / widths.len().max(1) as f64;
        let max = widths.iter().copied().fold(0.0, f64::max);
        writeln!(w, "| quantity | value |\n|---|---|")?;
        writeln!(
            w,
            "| measurements inside the band | {:.1} % |",
            mc.coverage * 100.0
        )?;
        if let Some(tc) = mc.truth_coverage {
            writeln!(w, "| true response inside the band | {:.1} % |", tc * 100.0)?;
        }
        writeln!(
            w,
            "| mean band width | {} {out_unit} |",
            sig(mean * c.factor, 3)
        )?;
        writeln!(
            w,
            "| largest band width | {} {out_unit} |",
            sig(max * c.factor, 3)
        )?;
        if mc.failed_samples > 0 {
            writeln!(
                w,
                "| draws that failed to simulate | {} |",
                mc.failed_samples
            )?;
        }
        writeln!(w)?;
        if c.has("fig4_monte_carlo") {
            writeln!(w, "![Figure 4: Monte Carlo band](fig4_monte_carlo.png)\n")?;
            writeln!(
                w,
                "*Figure 4 — Monte Carlo: the band of predictions under ±{:.0} % parameter variation, the nominal prediction and the measurements. The band is widest where the response is most sensitive to the parameters.*\n",
                mc.spread * 100.0
            )?;
        }
    }
    Ok(())
}

/// The files of the result folder.
fn files(w: &mut String, c: &Page<'_>) -> std::fmt::Result {
    let o = c.outcome;
    writeln!(w, "## Files\n")?;
    writeln!(
        w,
        "- `results.json`: every number of this report, the config as read, the seed and version;"
    )?;
    writeln!(
        w,
        "- `identification.csv`, `validation.csv`: t, input, measured, model, residual{}{};",
        if o.data.validation_truth.is_some() {
            ", true response"
        } else {
            ""
        },
        if o.monte_carlo.is_some() {
            ", Monte Carlo band (validation)"
        } else {
            ""
        }
    )?;
    if o.residuals.is_some() {
        writeln!(w, "- `residual_correlation.csv`: the correlation curves;")?;
    }
    if o.frequency.check().is_some() {
        writeln!(w, "- `frf.csv`: the frequency responses;")?;
    }
    if o.nonlinear.is_some() {
        writeln!(
            w,
            "- `nonlinear.csv`: each nonlinear candidate's validation prediction and residuals;"
        )?;
    }
    writeln!(
        w,
        "- figures as PNG and SVG: {}.",
        c.figures
            .iter()
            .map(|f| format!("`{f}`"))
            .collect::<Vec<_>>()
            .join(", ")
    )?;
    Ok(())
}
