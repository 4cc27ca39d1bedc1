//! The rows of the table, by section. Each function checks its work once with `?`
//! before timing it, so a failure is an error rather than a fast wrong row.

use super::harness::{Budget, measure, measure_batched};
use super::report::{Row, Target, duration};
use super::simulate_once;
use crate::{ExperimentError, Result, config::Config, paper, progress::Progress};
use msd_ident::{
    Backend, DataSet, Estimate, EstimationOptions, Excitation, InitialState, PaperExperiment,
    Parameters, ResidualOptions, SyntheticOptions, ValidationOptions, estimate,
    frequency::{FrequencyCheckOptions, frequency_check},
    nonlinear::{
        DampingLaw, ModelStructure, NonlinearOptions, NonlinearParameters, NonlinearSimulation,
        NonlinearSolver, StiffnessLaw, estimate_nonlinear, simulate_nonlinear,
    },
    residual_analysis, synthetic_data, validate_model,
};
use msd_mc::{McOptions, monte_carlo_band};
use msd_ode::Hold;
use std::path::Path;

/// A library error as the bench's error, naming what was measured.
pub(super) fn fail<E: Into<msd_ident::IdentError>>(
    what: &'static str,
) -> impl Fn(E) -> ExperimentError {
    move |e| ExperimentError::run(what, e.into())
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
/// default nonlinear options (Levenberg–Marquardt with the sensitivity Jacobian; on this
/// known signal ode45 RelTol 1e-8), from the fast linear estimate, which is computed once
/// outside the timing.
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
                format!("estimate {structure}, LM (sensitivities) + ode45 RelTol 1e-8"),
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

/// The Silverbox comparison of configs/silverbox-models.toml (linear, cubic spring,
/// quadratic damping + cubic spring on the first 8192 training samples, validated on the
/// multisine test): the experiment's nonlinear stage as it runs, its time per
/// simulation, and one simulation of the best candidate on the training record by RK4
/// on the cubic hold and by ode45 RelTol 1e-8. Derived: the RK4 output's error against
/// ode45 at RelTol 1e-10, on the Silverbox estimate (the first-order hold, which ode45
/// interpolates) and on the paper's nonlinear plant (the continuous force). Nothing
/// but a note when the record is not fetched.
pub fn silverbox(budget: &Budget) -> Result<(Vec<Row>, Vec<String>)> {
    let root = crate::project_root();
    if !root.join("data/silverbox/SNLS80mV.csv").exists() {
        let note = "Silverbox rows skipped: `cargo xtask fetch-data silverbox` fetches the record";
        return Ok((Vec::new(), vec![note.into()]));
    }
    let path = root.join("configs").join("silverbox-models.toml");
    let config = Config::load(&path)?;
    let o = paper::run_stages(
        config,
        &path,
        &crate::RunOptions::default(),
        &Progress::new(false),
    )?;
    let section = o.config.nonlinear.as_ref().ok_or_else(|| {
        ExperimentError::run(
            "bench: Silverbox",
            "silverbox-models.toml has no [nonlinear]",
        )
    })?;
    let linear_rms = o.validation.fit.residual_rms;
    let stage = || {
        msd_experiment::paper::nonlinear::run(
            section,
            &o.config,
            &o.data,
            &o.estimate,
            linear_rms,
            o.seed,
            o.threads,
        )
    };
    let first = stage()?;
    let simulations: usize = first.comparison.rows.iter().map(|r| r.simulations).sum();
    let samples = measure(budget, || stage().ok());
    let each = samples.median() / simulations as f64;
    let mut rows = vec![
        Row::new(
            "nonlinear",
            "Silverbox comparison, 3 candidates on 8192 training samples (the experiment's stage)",
            samples,
        )
        .target(Target::Seconds(1.0))
        .note(format!(
            "{simulations} simulations in the estimates: {} a simulation, validation included",
            duration(each)
        )),
    ];
    let best = first.comparison.best();
    let record = &o.data.identification;
    let solvers = [
        ("RK4 on the cubic hold", rk4(Hold::Cubic)),
        ("ode45 RelTol 1e-8", ode45(1e-8, 1e-12)),
    ];
    for (label, simulation) in solvers {
        let (_, stats) = simulate_nonlinear(
            &best.parameters,
            &record.excitation,
            InitialState::REST,
            &simulation,
            1.0,
        )
        .map_err(fail("bench: Silverbox simulation"))?;
        let samples = measure_batched(budget, 5, || {
            simulate_nonlinear(
                &best.parameters,
                &record.excitation,
                InitialState::REST,
                &simulation,
                1.0,
            )
            .ok()
        });
        rows.push(
            Row::new(
                "simulation",
                format!("Silverbox {}, 8192 samples, {label}", best.structure),
                samples,
            )
            .note(format!("{stats}")),
        );
    }
    let sigma = (best.sse / (best.samples - best.estimated) as f64).sqrt();
    let silverbox = fast_path_error(&best.parameters, &record.excitation, Hold::First)?;
    let paper_plant = paper_nonlinear_plant()?;
    let paper_input = Excitation::from_signal(
        msd_signal::paper_identification_input(),
        0.0,
        PaperExperiment::DT,
        7501,
    )
    .map_err(fail("bench: paper input"))?;
    let paper = fast_path_error(&paper_plant, &paper_input, Hold::Cubic)?;
    let derived = vec![
        format!(
            "RK4 (first-order hold) vs ode45 RelTol 1e-10 on the Silverbox estimate {}: {:.3e} V = {:.3} % of σ̂ (target ≤ 1 %)",
            best.structure,
            silverbox,
            100.0 * silverbox / sigma
        ),
        format!(
            "RK4 (cubic hold) vs ode45 RelTol 1e-10 on the paper's nonlinear plant: {:.3e} m = {:.4} % of σ = 2.5 mm (target ≤ 1 %)",
            paper,
            100.0 * paper / 0.0025
        ),
    ];
    Ok((rows, derived))
}

fn rk4(hold: Hold) -> NonlinearSimulation {
    NonlinearSimulation {
        solver: NonlinearSolver::Rk4,
        hold,
        ..NonlinearSimulation::default()
    }
}

fn ode45(rel_tol: f64, abs_tol: f64) -> NonlinearSimulation {
    NonlinearSimulation {
        solver: NonlinearSolver::Ode45,
        rel_tol,
        abs_tol,
        ..NonlinearSimulation::default()
    }
}

/// Largest |RK4 − ode45 RelTol 1e-10| over the record, from rest (no Coulomb law here).
fn fast_path_error(p: &NonlinearParameters, excitation: &Excitation, hold: Hold) -> Result<f64> {
    let run = |simulation: NonlinearSimulation| {
        simulate_nonlinear(p, excitation, InitialState::REST, &simulation, 1.0)
            .map(|(x, _)| x)
            .map_err(fail("bench: fast-path error"))
    };
    let (fast, reference) = (run(rk4(hold))?, run(ode45(1e-10, 1e-14))?);
    Ok(fast
        .iter()
        .zip(&reference)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max))
}

/// configs/paper-nonlinear.toml's plant: c₂ = 3, k₃ = 3000 on the paper's m, c, k.
fn paper_nonlinear_plant() -> Result<NonlinearParameters> {
    let structure = ModelStructure {
        damping: DampingLaw::QuadraticViscous,
        stiffness: StiffnessLaw::Cubic,
    };
    NonlinearParameters::new(structure, vec![2.5, 1.8, 120.0, 3.0, 3000.0])
        .map_err(fail("bench: paper plant"))
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
        let outcome = paper::run_stages(config.clone(), &path, &options, &progress)?;
        let samples = measure(budget, || {
            paper::run_stages(config.clone(), &path, &options, &progress).ok()
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
        let written = crate::paper::figures::write_all(&outcome, &dir)?;
        let samples = measure(budget, || {
            crate::paper::figures::write_all(&outcome, &dir).ok()
        });
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
