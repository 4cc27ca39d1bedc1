//! `results.json`: every number of a run, the config as read, the seed, the crate
//! version and the solver statistics.
//!
//! The file is deterministic: the same config and seed give the same bytes, whatever
//! the thread count, apart from `timings_ms` (wall times) and the recorded thread
//! counts (`experiment.threads`, `monte_carlo.threads`). Keys are sorted.

use crate::config::Kind;
use crate::pipeline::Outcome;
use msd_ident::{Interval, Parameters};
use serde_json::{Map, Value, json};
use std::time::Duration;

/// The version of the toolkit that wrote a results file.
pub const CRATE_VERSION: &str = env!("CARGO_PKG_VERSION");

fn interval(i: &Interval) -> Value {
    json!({
        "value": i.value,
        "standard_error": i.standard_error,
        "ci95": [i.ci95[0], i.ci95[1]],
    })
}

fn parameters(p: &Parameters) -> Value {
    json!({
        "mass": p.mass,
        "damping": p.damping,
        "stiffness": p.stiffness,
        "natural_frequency_hz": p.natural_frequency_hz(),
        "damping_ratio": p.damping_ratio(),
    })
}

fn stats([accepted, rejected, evaluations]: [usize; 3]) -> Value {
    json!({
        "accepted_steps": accepted,
        "rejected_steps": rejected,
        "rhs_evaluations": evaluations,
    })
}

fn ms(d: Duration) -> f64 {
    (d.as_secs_f64() * 1e6).round() / 1e3
}

/// The JSON document of `outcome`; `extra_timings` are the writing stages (figures,
/// report) and `total` the run's wall time.
pub fn to_json(
    outcome: &Outcome,
    extra_timings: &[(&'static str, Duration)],
    total: Duration,
) -> Value {
    let o = outcome;
    let e = &o.estimate;
    let u = &e.uncertainty;
    let config_file = o
        .config_path
        .file_name()
        .map(|f| f.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut root = Map::new();
    root.insert(
        "experiment".into(),
        json!({
            "name": o.config.name,
            "description": o.config.description,
            "kind": match o.data.kind { Kind::Synthetic => "synthetic", Kind::Measured => "measured" },
            "config_file": config_file,
            "seed": o.seed,
            "threads": o.threads,
            "crate_version": CRATE_VERSION,
            "crate": "msd-experiment (msd-toolkit)",
        }),
    );
    root.insert(
        "config".into(),
        serde_json::to_value(&o.config).unwrap_or(Value::Null),
    );
    root.insert("data".into(), data_json(o));
    if let Some(truth) = &o.data.truth {
        let mut t = parameters(truth);
        // How far the estimate is from the truth, in its own standard errors.
        let z = |est: &Interval, true_value: f64| {
            if est.standard_error > 0.0 {
                (est.value - true_value) / est.standard_error
            } else {
                0.0
            }
        };
        t["error_in_standard_errors"] = json!({
            "mass": z(&u.mass, truth.mass),
            "damping": z(&u.damping, truth.damping),
            "stiffness": z(&u.stiffness, truth.stiffness),
        });
        root.insert("truth".into(), t);
    }
    let correlation: Vec<Vec<f64>> = (0..u.correlation.nrows())
        .map(|r| {
            (0..u.correlation.ncols())
                .map(|c| u.correlation[(r, c)])
                .collect()
        })
        .collect();
    root.insert(
        "estimate".into(),
        json!({
            "mass": interval(&u.mass),
            "damping": interval(&u.damping),
            "stiffness": interval(&u.stiffness),
            "natural_frequency_hz": interval(&u.natural_frequency_hz),
            "damping_ratio": interval(&u.damping_ratio),
            "method": e.method.name(),
            "backend": e.backend.name(),
            "backend_settings": serde_json::to_value(e.backend).unwrap_or(Value::Null),
            "initial_guess": {
                "mass": e.initial_guess.0.mass,
                "damping": e.initial_guess.0.damping,
                "stiffness": e.initial_guess.0.stiffness,
                "source": e.initial_guess.1.to_string(),
            },
            "initial_state": { "displacement": e.initial_state.displacement, "velocity": e.initial_state.velocity },
            "offset": e.offset,
            "iterations": e.iterations,
            "evaluations": e.evaluations,
            "jacobian_evaluations": e.jacobian_evaluations,
            "starts": e.starts,
            // The optimiser's own words; `converged` also asks for a minimum (see StopReason).
            "exit": e.stop.optimiser_reason().to_string(),
            "converged": e.stop.converged(),
            "cost": e.cost,
            "noise_sigma": u.sigma,
            "degrees_of_freedom": u.degrees_of_freedom,
            "condition_number": u.condition_number,
            "correlation": { "names": u.names, "matrix": correlation },
            "warnings": u.warnings,
            "ode45_at_estimate": o.estimation_solver.map(stats),
        }),
    );
    let truth_r2 = |truth: &Option<Vec<f64>>, measured: &[f64]| {
        truth
            .as_ref()
            .map(|t| msd_ident::FitMetrics::new(measured, t).r_squared)
    };
    root.insert(
        "identification".into(),
        json!({
            "r2": e.fit.r_squared,
            "fit_percent": e.fit.fit_percent,
            "residual_rms": e.fit.residual_rms,
            "sse": e.fit.sse,
            "samples": e.fit.samples,
            "r2_of_true_response": truth_r2(&o.data.identification_truth, &o.data.identification.output),
        }),
    );
    let v = &o.validation;
    root.insert(
        "validation".into(),
        json!({
            "r2": v.fit.r_squared,
            "fit_percent": v.fit.fit_percent,
            "residual_rms": v.fit.residual_rms,
            "sse": v.fit.sse,
            "samples": v.fit.samples,
            "scored_from_sample": v.scored_from,
            "backend": v.backend.name(),
            "initial_state": { "displacement": v.initial_state.displacement, "velocity": v.initial_state.velocity },
            "r2_of_true_response": v.truth_fit.map(|f| f.r_squared),
            "residuals": v.residual_analysis.as_ref().map(residuals_json),
            "ode45": v.solver.map(stats),
        }),
    );
    if let Some(r) = &o.residuals {
        root.insert("residuals".into(), residuals_json(r));
    }
    if let Some(f) = &o.frequency {
        root.insert("frequency_check".into(), frequency_json(f));
    }
    if let Some(reason) = &o.frequency_skipped {
        root.insert(
            "frequency_check".into(),
            json!({ "skipped": true, "reason": reason }),
        );
    }
    if let Some(mc) = &o.monte_carlo {
        let width: f64 = mc
            .upper
            .iter()
            .zip(&mc.lower)
            .map(|(h, l)| h - l)
            .sum::<f64>()
            / mc.upper.len().max(1) as f64;
        let max_width = mc
            .upper
            .iter()
            .zip(&mc.lower)
            .map(|(h, l)| h - l)
            .fold(0.0f64, f64::max);
        root.insert(
            "monte_carlo".into(),
            json!({
                "samples": mc.samples,
                "failed_samples": mc.failed_samples,
                "threads": mc.threads,
                "spread": mc.spread,
                "percentiles": mc.percentiles,
                "backend": mc.backend.name(),
                "coverage": mc.coverage,
                "coverage_of_true_response": mc.truth_coverage,
                "mean_band_width": width,
                "max_band_width": max_width,
            }),
        );
    }
    if let Some(n) = &o.nonlinear {
        root.insert("nonlinear".into(), nonlinear_json(n));
    }
    let mut timings = Map::new();
    for (name, d) in o.timings.iter().chain(extra_timings) {
        timings.insert((*name).to_string(), json!(ms(*d)));
    }
    timings.insert("total".into(), json!(ms(total)));
    root.insert("timings_ms".into(), Value::Object(timings));
    Value::Object(root)
}

fn data_json(o: &Outcome) -> Value {
    let set = |d: &msd_ident::DataSet| {
        json!({
            "samples": d.len(),
            "t0": d.excitation.t0(),
            "dt": d.excitation.dt(),
            "input_unit": d.input_unit,
            "output_unit": d.output_unit,
        })
    };
    let source = match &o.data.source {
        crate::data::Source::InMemory => json!({ "kind": "in_memory" }),
        crate::data::Source::Synthetic { sigma } => {
            json!({ "kind": "synthetic", "noise_sigma": sigma,
            "noise_streams": ["identification", "validation"] })
        }
        crate::data::Source::Measured {
            path,
            rows,
            dt,
            estimation_range,
            validation_range,
        } => json!({
            "kind": "measured",
            "file": path.file_name().map(|f| f.to_string_lossy().into_owned()),
            "rows": rows,
            "dt": dt,
            "estimation_range": estimation_range,
            "validation_range": validation_range,
        }),
    };
    json!({
        "source": source,
        "identification": set(&o.data.identification),
        "validation": set(&o.data.validation),
    })
}

fn residuals_json(r: &msd_ident::ResidualAnalysis) -> Value {
    serde_json::to_value(r).unwrap_or(Value::Null)
}

fn frequency_json(f: &msd_ident::FrequencyCheck) -> Value {
    let mut v = serde_json::to_value(f).unwrap_or(Value::Null);
    if let Value::Object(map) = &mut v {
        // One shape whether measured or skipped (then {"skipped": true, "reason": …}).
        map.insert("skipped".into(), json!(false));
        // The curves go to frf.csv; keep the scalars here.
        map.retain(|_, value| !value.is_array() || value.as_array().is_some_and(|a| a.len() <= 2));
        map.insert("points".into(), json!(f.frequency_hz.len()));
    }
    v
}

/// The `nonlinear` object: the candidates ranked by BIC (rank 1 first), each with its
/// parameters (value, standard error, 95 % interval), SSE, AIC, BIC, validation scores
/// and residual tests; the verdict, failures and, for synthetic data, the true plant.
fn nonlinear_json(n: &crate::nonlinear::NonlinearOutcome) -> Value {
    let c = &n.comparison;
    let rows: Vec<Value> = c
        .rows
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let parameters: Map<String, Value> = r
                .names
                .iter()
                .zip(&r.intervals)
                .map(|(name, iv)| (name.clone(), interval(iv)))
                .collect();
            json!({
                "rank": i + 1,
                "model": r.structure.name(),
                "damping": r.structure.damping,
                "stiffness": r.structure.stiffness,
                "parameters": parameters,
                "estimated": r.estimated,
                "samples": r.samples,
                "sse": r.sse,
                "aic": r.aic,
                "bic": r.bic,
                "delta_bic": r.delta_bic,
                "validation": {
                    "residual_rms": r.validation_rms,
                    "fit_percent": r.validation.fit_percent,
                    "r2": r.validation.r_squared,
                    "scored_from_sample": r.scored_from,
                    "whiteness_p_value": r.whiteness_p,
                    "whiteness_passed": r.whiteness_passed,
                    "cross_correlation_passed": r.cross_correlation_passed,
                },
                "converged": r.stop.converged(),
                "simulations": r.simulations,
            })
        })
        .collect();
    let failures: Vec<Value> = c
        .failures
        .iter()
        .map(|f| json!({ "model": f.structure.name(), "reason": f.reason }))
        .collect();
    json!({
        "mode": if n.comparison_asked { "comparison" } else { "model" },
        "rows": rows,
        "best": c.rows.first().map(|r| r.structure.name()),
        "verdict": c.verdict,
        "failures": failures,
        "linear_stage_validation_rms": n.linear_validation_rms,
        "plant": n.plant.as_ref().map(|p| {
            let values: Map<String, Value> = p
                .names()
                .iter()
                .zip(&p.values)
                .map(|(name, v)| ((*name).to_string(), json!(v)))
                .collect();
            json!({ "model": p.structure.name(), "parameters": values })
        }),
    })
}
