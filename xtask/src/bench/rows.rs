//! The rows of the table, by section. Each function checks its work once with `?`
//! before timing it, so a failure is an error rather than a fast wrong row.

use super::harness::{Budget, measure, measure_batched};
use super::report::{Row, Target, duration};
use super::simulate_once;
use crate::{ExperimentError, Result, config::Config, pipeline, progress::Progress};
use msd_ident::{
    Backend, DataSet, Estimate, EstimationOptions, Excitation, FrequencyCheckOptions, FrfWeighting,
    InitialState, ModalOptions, ModalParameters, ModelStructure, NonlinearOptions, PaperExperiment,
    Parameters, ResidualOptions, SyntheticOptions, ValidationOptions, estimate, estimate_nonlinear,
    fit_modes, frequency_check, residual_analysis, synthetic_data, synthetic_frequency_response,
    validate_model,
};
use msd_mc::{McOptions, monte_carlo_band};
use std::path::Path;

fn fail(what: &'static str) -> impl Fn(msd_ident::IdentError) -> ExperimentError {
    move |e| ExperimentError::run(what, e)
}

/// One simulation (exact, ode45 RelTol 1e-6) and one cost evaluation (simulation + SSE)
/// of the identification record.
pub fn simulation(budget: &Budget, experiment: &PaperExperiment) -> Result<Vec<Row>> {
    let data = &experiment.identification;
    let excitation = &data.excitation;
    let mut out = vec![0.0; excitation.len()];
    let mut rows = Vec::new();
    for backend in [Backend::EXACT, Backend::PAPER] {
        msd_ident::simulate_into(
            &Parameters::PAPER,
            excitation,
            InitialState::REST,
            &backend,
            &mut out,
        )
        .map_err(fail("bench: simulation"))?;
    }
    let exact = measure_batched(budget, 20, || {
        simulate_once(excitation, &Backend::EXACT, &mut out)
    });
    rows.push(
        Row::new("simulation", "exact (cubic hold), 7501 samples", exact)
            .target(Target::FloorMultiple(2.0))
            .note("discretisation included"),
    );
    let ode45 = measure_batched(budget, 5, || {
        simulate_once(excitation, &Backend::PAPER, &mut out)
    });
    rows.push(
        Row::new(
            "simulation",
            "ode45 RelTol 1e-6 AbsTol 1e-9, 7501 samples",
            ode45,
        )
        .target(Target::Seconds(150e-6)),
    );
    for (backend, inner) in [(Backend::EXACT, 20), (Backend::PAPER, 5)] {
        let cost = measure_batched(budget, inner, || {
            simulate_once(excitation, &backend, &mut out)?;
            Some(sse(&data.output, &out))
        });
        rows.push(Row::new(
            "cost",
            format!("one cost evaluation, {} (simulation + SSE)", backend.name()),
            cost,
        ));
    }
    Ok(rows)
}

fn sse(y: &[f64], model: &[f64]) -> f64 {
    y.iter().zip(model).map(|(a, b)| (a - b) * (a - b)).sum()
}

fn counts(e: &Estimate) -> String {
    let mut note = format!("{} evaluations, {} iterations", e.evaluations, e.iterations);
    if e.jacobian_evaluations > 0 {
        note.push_str(&format!(", {} Jacobians", e.jacobian_evaluations));
    }
    note
}

/// Identification with the paper's and the fast method, and the validation stage.
pub fn identification(budget: &Budget, experiment: &PaperExperiment) -> Result<Vec<Row>> {
    let data = &experiment.identification;
    let mut rows = Vec::new();
    let paper = EstimationOptions::paper();
    let fast = EstimationOptions::fast();
    let e_paper = estimate(data, &paper).map_err(fail("bench: paper identification"))?;
    let e_fast = estimate(data, &fast).map_err(fail("bench: fast identification"))?;
    rows.push(
        Row::new(
            "identification",
            "paper method: Nelder–Mead + ode45",
            measure(budget, || estimate(data, &paper).ok()),
        )
        .target(Target::Seconds(40e-3))
        .note(counts(&e_paper)),
    );
    rows.push(
        Row::new(
            "identification",
            "fast method: Levenberg–Marquardt + exact",
            measure(budget, || estimate(data, &fast).ok()),
        )
        .target(Target::Seconds(3e-3))
        .note(counts(&e_fast)),
    );
    let validation_stage = || -> msd_ident::Result<bool> {
        let residual = ResidualOptions::default();
        let v = validate_model(
            &e_paper.parameters,
            &experiment.validation,
            &ValidationOptions {
                backend: Backend::PAPER,
                residuals: residual,
                ..ValidationOptions::default()
            },
        )?;
        let r = residual_analysis(&e_paper.residuals, data.excitation.samples(), &residual)?;
        let f = frequency_check(
            &experiment.validation,
            &e_paper.parameters,
            Some(&e_paper.uncertainty),
            &FrequencyCheckOptions::default(),
        )?;
        Ok(v.residual_analysis.whiteness_passed && r.whiteness_passed && f.consistent)
    };
    validation_stage().map_err(fail("bench: validation"))?;
    rows.push(
        Row::new(
            "validation",
            "ode45 prediction + residual diagnostics + frequency check",
            measure(budget, || validation_stage().ok()),
        )
        .note("validation and identification residuals, H1 check on validation"),
    );
    Ok(rows)
}

/// Estimation of each of the six nonlinear model structures on the paper's
/// identification record (7501 samples, the linear plant, seed 1) with msd-ident's
/// default nonlinear options (Levenberg–Marquardt, central differences, ode45 RelTol
/// 1e-8), from the fast linear estimate, which is computed once outside the timing.
pub fn nonlinear(budget: &Budget, experiment: &PaperExperiment) -> Result<Vec<Row>> {
    let data = &experiment.identification;
    let start = estimate(data, &EstimationOptions::fast())
        .map_err(fail("bench: nonlinear models"))?
        .parameters;
    let options = NonlinearOptions {
        linear_start: Some(start),
        ..NonlinearOptions::default()
    };
    let mut rows = Vec::new();
    for structure in ModelStructure::all() {
        let e = estimate_nonlinear(data, structure, &options)
            .map_err(fail("bench: nonlinear models"))?;
        let samples = measure(budget, || {
            estimate_nonlinear(data, structure, &options).ok()
        });
        rows.push(
            Row::new(
                "nonlinear",
                format!("estimate {structure}, LM + ode45 RelTol 1e-8"),
                samples,
            )
            .note(format!(
                "{} simulations, {} iterations{}",
                e.simulations,
                e.iterations,
                if e.stop.converged() {
                    ""
                } else {
                    ", NOT converged"
                }
            )),
        );
    }
    Ok(rows)
}

/// Three modes (fn 10, 23, 41 Hz; ζ 1 %, 2 %, 0.5 %) in 2000 lines with 1 % noise:
/// the stabilization diagram over orders 2–40 and the polish of every modal parameter
/// (msd-ident's criterion bench `frf` measures the same).
pub fn frequency_domain(budget: &Budget) -> Result<Vec<Row>> {
    let modes = [(10.0, 0.01, 1.0), (23.0, 0.02, -0.6), (41.0, 0.005, 0.4)].map(|(f, z, a)| {
        ModalParameters {
            natural_frequency_hz: f,
            damping_ratio: z,
            modal_constant: a,
            modal_constant_imaginary: 0.0,
        }
    });
    let f: Vec<f64> = (1..=2000).map(|i| 0.025 * i as f64).collect();
    let frf =
        synthetic_frequency_response(&f, 0.01, 1, |f| modes.iter().map(|m| m.receptance(f)).sum())
            .map_err(fail("bench: frequency response"))?;
    let options = ModalOptions {
        weighting: FrfWeighting::Relative,
        ..ModalOptions::default()
    };
    let fit = fit_modes(&frf, &options).map_err(fail("bench: modal fit"))?;
    let samples = measure(budget, || fit_modes(&frf, &options).ok());
    Ok(vec![
        Row::new(
            "frequency domain",
            "three modes, 2000 lines: stabilization diagram orders 2–40 + polish",
            samples,
        )
        .target(Target::Seconds(20e-3))
        .note(format!(
            "{} modes found, {} iterations",
            fit.modes.len(),
            fit.iterations
        )),
    ])
}

fn band_options(samples: usize, threads: usize, backend: Backend) -> McOptions {
    McOptions {
        samples,
        threads,
        backend,
        seed: 1,
        ..McOptions::default()
    }
}

/// Monte Carlo N = 1000 on the validation record, exact and ode45, 1 and 2 threads,
/// with the speed-ups as derived lines.
pub fn monte_carlo(
    budget: &Budget,
    experiment: &PaperExperiment,
) -> Result<(Vec<Row>, Vec<String>)> {
    let set = &experiment.validation;
    let mut rows = Vec::new();
    let mut derived = Vec::new();
    for (backend, target) in [(Backend::EXACT, 20e-3), (Backend::PAPER, 70e-3)] {
        let mut medians = [0.0; 2];
        for (slot, threads) in [1, 2].into_iter().enumerate() {
            let options = band_options(1000, threads, backend);
            monte_carlo_band(
                &Parameters::PAPER,
                &set.excitation,
                Some(&set.output),
                &options,
            )
            .map_err(|e| ExperimentError::run("bench: Monte Carlo", e))?;
            let samples = measure(budget, || {
                monte_carlo_band(
                    &Parameters::PAPER,
                    &set.excitation,
                    Some(&set.output),
                    &options,
                )
                .ok()
            });
            medians[slot] = samples.median();
            let mut row = Row::new(
                "monte carlo",
                format!("N = 1000, {}, {threads} thread(s)", backend.name()),
                samples,
            );
            if threads == 2 {
                row = row.target(Target::Seconds(target));
            }
            rows.push(row);
        }
        let speedup = medians[0] / medians[1];
        derived.push(format!(
            "Monte Carlo N = 1000 {}: speed-up 1 → 2 threads {:.2} (target ≥ 1.8: {})",
            backend.name(),
            speedup,
            if speedup >= 1.8 { "met" } else { "MISSED" }
        ));
    }
    Ok((rows, derived))
}

/// The whole pipeline without figures (fast and paper configs) and the figures alone
/// (all five, PNG and SVG, of the paper run), written under `out/figures`.
pub fn pipeline(budget: &Budget, out: &Path) -> Result<Vec<Row>> {
    let root = crate::project_root().join("configs");
    let progress = Progress::new(false);
    let options = crate::RunOptions::default();
    let mut rows = Vec::new();
    let mut paper_outcome = None;
    for (file, target) in [("paper-fast.toml", 25e-3), ("paper.toml", 100e-3)] {
        let path = root.join(file);
        let config = Config::load(&path)?;
        let outcome = pipeline::run_stages(config.clone(), &path, &options, &progress)?;
        let samples = measure(budget, || {
            pipeline::run_stages(config.clone(), &path, &options, &progress).ok()
        });
        rows.push(
            Row::new(
                "pipeline",
                format!("whole pipeline without figures, configs/{file}"),
                samples,
            )
            .target(Target::Seconds(target))
            .note(format!(
                "{}; Monte Carlo {} draws",
                crate::fmt::method_name(outcome.estimate.method),
                outcome.monte_carlo.as_ref().map_or(0, |m| m.samples)
            )),
        );
        paper_outcome = Some(outcome);
    }
    if let Some(outcome) = paper_outcome {
        let dir = out.join("figures");
        std::fs::create_dir_all(&dir).map_err(|e| ExperimentError::run("bench: figures", e))?;
        let written = crate::plots::write_all(&outcome, &dir)?;
        let samples = measure(budget, || crate::plots::write_all(&outcome, &dir).ok());
        rows.push(
            Row::new("pipeline", "figures alone (PNG and SVG)", samples)
                .target(Target::Seconds(1.5))
                .note(format!("{} figures", written.len())),
        );
    }
    Ok(rows)
}

/// Identification record of `n` samples at the paper's 2 ms (the paper input continues
/// past 15 s with its 1.4 Hz sine), seed 1.
fn long_record(n: usize) -> Result<DataSet> {
    let excitation = Excitation::from_signal(
        msd_signal::paper_identification_input(),
        0.0,
        PaperExperiment::DT,
        n,
    )
    .map_err(fail("bench: scaling data"))?;
    let (data, _) = synthetic_data(
        &Parameters::PAPER,
        excitation,
        &SyntheticOptions::named("identification"),
    )
    .map_err(fail("bench: scaling data"))?;
    Ok(data)
}

/// Time per sample of the fast identification against the record length, and of the
/// exact Monte Carlo (2 threads) against the number of draws.
pub fn scaling(budget: &Budget, experiment: &PaperExperiment) -> Result<(Vec<Row>, Vec<String>)> {
    let mut rows = Vec::new();
    let mut derived = Vec::new();
    let fast = EstimationOptions::fast();
    let mut per_sample = Vec::new();
    for n in [7_501, 75_001, 750_001] {
        let data = long_record(n)?;
        let e = estimate(&data, &fast).map_err(fail("bench: scaling"))?;
        let samples = measure(budget, || estimate(&data, &fast).ok());
        let each = samples.median() / n as f64;
        per_sample.push((n, each));
        rows.push(
            Row::new(
                "scaling",
                format!("fast identification, {n} samples"),
                samples,
            )
            .note(format!("{} per sample; {}", duration(each), counts(&e))),
        );
    }
    derived.push(flatness("fast identification per sample", &per_sample));
    let set = &experiment.validation;
    let mut per_draw = Vec::new();
    for n in [100, 1_000, 10_000] {
        let options = band_options(n, 2, Backend::EXACT);
        let samples = measure(budget, || {
            monte_carlo_band(
                &Parameters::PAPER,
                &set.excitation,
                Some(&set.output),
                &options,
            )
            .ok()
        });
        let each = samples.median() / n as f64;
        per_draw.push((n, each));
        rows.push(
            Row::new(
                "scaling",
                format!("Monte Carlo exact, 2 threads, N = {n}"),
                samples,
            )
            .note(format!("{} per draw", duration(each))),
        );
    }
    derived.push(flatness(
        "Monte Carlo (exact, 2 threads) per draw",
        &per_draw,
    ));
    Ok((rows, derived))
}

/// "flat" when every per-unit time is within 20 % of the smallest size's.
fn flatness(what: &str, points: &[(usize, f64)]) -> String {
    let Some(&(_, base)) = points.first() else {
        return format!("{what}: no points");
    };
    let worst = points
        .iter()
        .map(|&(_, t)| t / base - 1.0)
        .fold(0.0_f64, |a, d| if d.abs() > a.abs() { d } else { a });
    let list: Vec<String> = points
        .iter()
        .map(|&(n, t)| format!("{n}: {}", duration(t)))
        .collect();
    format!(
        "{what}: {} — largest change {:+.0} % vs the smallest size ({})",
        list.join(", "),
        worst * 100.0,
        if worst.abs() <= 0.2 {
            "flat within 20 %"
        } else {
            "NOT flat within 20 %"
        }
    )
}
