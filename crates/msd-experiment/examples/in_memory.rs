//! The whole experiment from a Rust program, on records held in memory: no config file,
//! no data file.
//!
//! The paper's two records (step + multi-level sine for identification, chirp + step for
//! validation; m = 2.5 kg, c = 1.8 N·s/m, k = 120 N/m; 15 s at 500 Hz, σ = 2.5 mm) are
//! generated here as plain `Vec<f64>` columns, as a program would hold its own
//! measurement; options are set in Rust; the summary is printed and every output
//! (report, results.json, CSV, figures) is written to a temporary folder.
//!
//! ```sh
//! cargo run --release -p msd-experiment --example in_memory
//! ```

use msd_experiment::{RunOptions, config::Config, data::ExperimentData, run_in_memory};
use msd_ident::{Backend, DataSet, Excitation, InitialState, Method, Parameters, simulate};
use msd_signal::{Signal, gaussian_noise, paper_identification_input, paper_validation_input};

/// A record's columns: time [s], force [N], displacement [m].
struct Columns {
    time: Vec<f64>,
    force: Vec<f64>,
    displacement: Vec<f64>,
}

/// The plant's noisy response to `input` on 0…15 s at 2 ms, as plain columns.
fn record(input: Signal, stream: &str) -> Result<Columns, Box<dyn std::error::Error>> {
    let (dt, n) = (0.002, 7501);
    let excitation = Excitation::from_signal(input, 0.0, dt, n)?;
    let mut displacement = simulate(
        &Parameters::PAPER,
        &excitation,
        InitialState::REST,
        &Backend::EXACT,
    )?;
    for (x, e) in displacement
        .iter_mut()
        .zip(gaussian_noise(1, stream, 0.0025, n)?)
    {
        *x += e;
    }
    Ok(Columns {
        time: (0..n).map(|i| i as f64 * dt).collect(),
        force: excitation.samples().to_vec(),
        displacement,
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let id = record(paper_identification_input(), "identification")?;
    let val = record(paper_validation_input(), "validation")?;
    let identification =
        DataSet::from_columns("identification", &id.time, id.force, id.displacement)?;
    let validation = DataSet::from_columns("validation", &val.time, val.force, val.displacement)?;

    let mut config = Config::new("in-memory");
    config.description = "The paper's records, built in Rust and run without any file.".into();
    config.estimation.method = Method::LevenbergMarquardt;
    config.monte_carlo.samples = 500;
    let data = ExperimentData::in_memory(identification, validation);
    let outcome = run_in_memory(config, data, &RunOptions::default())?;

    let folder = tempfile::tempdir()?;
    let run = msd_experiment::write_outcome(&outcome, &folder.path().join("in-memory"))?;
    print!("{}", run.summary);
    let files = std::fs::read_dir(&run.out_dir)?.count();
    println!(
        "({files} files written to {}, removed on exit)",
        run.out_dir.display()
    );
    Ok(())
}
