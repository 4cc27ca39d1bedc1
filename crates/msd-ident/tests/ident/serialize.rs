//! The result types serialize (for a results file) and display (for a person): the keys
//! and texts a reader relies on.

use msd_ident::{
    Backend, EstimationOptions, Excitation, InitialState, Method, PaperExperiment, Parameters,
    SyntheticOptions, estimate,
    estimate::GuessSource,
    nonlinear::{
        CandidateFailure, Comparison, ComparisonOptions, ModelStructure, NonlinearOptions,
        NonlinearParameters, NonlinearSimulation, NonlinearSolver, assess_estimate,
        estimate_nonlinear, synthetic_nonlinear_data,
    },
};
use msd_signal::{paper_identification_input, paper_validation_input};
use serde_json::{Value, json};

type Outcome = Result<(), Box<dyn std::error::Error>>;

fn rows_of(matrix: &Value) -> Option<Vec<usize>> {
    matrix
        .as_array()?
        .iter()
        .map(|row| row.as_array().map(Vec::len))
        .collect()
}

#[test]
fn an_estimate_serializes_every_field_and_displays_its_intervals() -> Outcome {
    let experiment = PaperExperiment::generate(1)?;
    let e = estimate(&experiment.identification, &EstimationOptions::fast())?;
    let json = serde_json::to_value(&e)?;
    assert_eq!(
        json["parameters"]["stiffness"],
        json!(e.parameters.stiffness)
    );
    assert_eq!(json["initial_guess"][0]["mass"], 2.0);
    assert_eq!(json["initial_guess"][1], "given");
    assert_eq!(json["method"], "levenberg_marquardt");
    assert_eq!(json["backend"]["kind"], "exact");
    assert!(
        json["stop"]["levenberg_marquardt"].is_string(),
        "{}",
        json["stop"]
    );
    assert_eq!(
        rows_of(&json["uncertainty"]["covariance"]),
        Some(vec![3; 3])
    );
    assert_eq!(
        json["uncertainty"]["stiffness"],
        json!(e.uncertainty.stiffness)
    );
    assert_eq!(json["wall_time_s"], json!(e.wall_time.as_secs_f64()));
    assert_eq!(json["residuals"].as_array().map(Vec::len), Some(7501));
    let text = e.to_string();
    assert!(text.starts_with(&format!("method levenberg_marquardt on exact: {}", e.stop)));
    assert!(
        text.contains(&format!("\n  k = {}\n", e.uncertainty.stiffness)),
        "{text}"
    );
    Ok(())
}

#[test]
fn parameters_state_guess_method_and_backend_serialize_and_display() -> Outcome {
    let p = serde_json::to_value(Parameters::PAPER)?;
    assert_eq!(
        (p["mass"].clone(), p["stiffness"].clone()),
        (json!(2.5), json!(120.0))
    );
    let x0 = serde_json::to_value(InitialState {
        displacement: 0.01,
        velocity: 0.0,
    })?;
    assert_eq!(x0["displacement"], 0.01);
    assert_eq!(serde_json::to_value(GuessSource::Automatic)?, "automatic");
    assert_eq!(GuessSource::Given.to_string(), "given");
    assert_eq!(serde_json::to_value(Method::NelderMead)?, "nelder_mead");
    assert_eq!(Method::NelderMead.to_string(), "Nelder–Mead");
    assert_eq!(
        Method::LevenbergMarquardt.to_string(),
        "Levenberg–Marquardt"
    );
    let ode45 = serde_json::to_value(Backend::PAPER)?;
    assert_eq!(
        (ode45["kind"].clone(), ode45["rel_tol"].clone()),
        (json!("ode45"), json!(1e-6))
    );
    assert_eq!(serde_json::to_value(Backend::EXACT)?["hold"], "cubic");
    assert_eq!(
        Backend::PAPER.to_string(),
        "ode45 (RelTol 1e-6, AbsTol 1e-9)"
    );
    assert_eq!(Backend::EXACT.to_string(), "exact (cubic hold)");
    Ok(())
}

/// The simulation options as a config writes them: every key optional, the solver and
/// the hold by name; an unknown solver is refused naming the choices.
#[test]
fn nonlinear_simulation_options_read_and_write_by_name() -> Outcome {
    let default: NonlinearSimulation = serde_json::from_value(json!({}))?;
    assert_eq!(default, NonlinearSimulation::default());
    assert_eq!(
        serde_json::to_value(default)?,
        json!({ "solver": "auto", "hold": "cubic", "rel_tol": 1e-8, "abs_tol": 1e-12,
            "smoothing_velocity": { "relative": 1e-3 } })
    );
    let rk4: NonlinearSimulation =
        serde_json::from_value(json!({ "solver": "rk4", "hold": "first" }))?;
    assert_eq!(
        (rk4.solver, rk4.hold),
        (NonlinearSolver::Rk4, msd_ode::Hold::First)
    );
    let err = serde_json::from_value::<NonlinearSimulation>(json!({ "solver": "euler" }))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("unknown variant `euler`, expected one of `auto`, `rk4`, `ode45`"),
        "{err}"
    );
    Ok(())
}

#[test]
fn a_nonlinear_estimate_its_row_and_a_comparison_serialize_and_display() -> Outcome {
    let plant = NonlinearParameters::from_linear(ModelStructure::LINEAR, &Parameters::PAPER);
    let sim = NonlinearSimulation::default();
    let id = Excitation::from_signal(paper_identification_input(), 0.0, 0.004, 2001)?;
    let val = Excitation::from_signal(paper_validation_input(), 0.0, 0.004, 2001)?;
    let (id, _) = synthetic_nonlinear_data(
        &plant,
        id,
        &sim,
        &SyntheticOptions {
            seed: 3,
            ..SyntheticOptions::named("id")
        },
    )?;
    let (val, _) = synthetic_nonlinear_data(
        &plant,
        val,
        &sim,
        &SyntheticOptions {
            seed: 3,
            ..SyntheticOptions::named("val")
        },
    )?;
    let e = estimate_nonlinear(&id, ModelStructure::LINEAR, &NonlinearOptions::default())?;
    let json = serde_json::to_value(&e)?;
    assert_eq!(
        json["parameters"]["values"].as_array().map(Vec::len),
        Some(3)
    );
    assert_eq!(rows_of(&json["correlation"]), Some(vec![3; 3]));
    assert_eq!(json["stop"], serde_json::to_value(&e.stop)?);
    assert_eq!(json["method"], "levenberg_marquardt");
    assert!(json["wall_time_s"].as_f64().is_some_and(|t| t >= 0.0));
    assert!(e.to_string().contains(&e.stop.to_string()));
    // A known signal: ode45 by default, its Jacobian by RK4 on the cubic hold.
    assert_eq!(
        json["simulation"],
        json!({ "solver": "ode45", "hold": "cubic", "steps_per_sample": 1, "error_estimate": null })
    );
    assert!(
        e.to_string()
            .contains("(ode45, Jacobian by RK4 on the cubic hold with 1 sub-step a sample)"),
        "{e}"
    );

    let row = assess_estimate(&e, &val, &ComparisonOptions::default())?;
    let json = serde_json::to_value(&row)?;
    assert_eq!(json["samples"], 2001);
    assert_eq!(json["simulation"]["solver"], "ode45");
    assert_eq!(json["stop"], serde_json::to_value(&e.stop)?);
    assert!(
        row.to_string().starts_with("viscous+linear: p = 3, SSE = "),
        "{row}"
    );

    let failure = CandidateFailure {
        structure: ModelStructure::LINEAR,
        reason: "it diverged".into(),
    };
    assert_eq!(
        failure.to_string(),
        "viscous+linear: not ranked: it diverged"
    );
    let comparison = Comparison {
        rows: vec![row],
        verdict: "Only one.".into(),
        failures: vec![failure],
    };
    let json = serde_json::to_value(&comparison)?;
    assert_eq!(json["failures"][0]["reason"], "it diverged");
    assert_eq!(json["rows"][0]["delta_bic"], 0.0);
    Ok(())
}
