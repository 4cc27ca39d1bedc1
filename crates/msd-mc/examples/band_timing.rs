//! Wall and CPU time of the paper's Monte Carlo band (N = 1000, validation input) for
//! each backend on 1 and 2 threads: medians of repeated runs. CPU time (user + system,
//! all threads, from /proc/self/stat on Linux) is less disturbed by other load on a
//! shared machine than wall time.
//!
//! `cargo run --release -p msd-mc --example band_timing [runs]`
use msd_ident::{Backend, PaperExperiment, Parameters};
use msd_mc::{McOptions, monte_carlo_band};
use std::time::Instant;

/// CPU seconds of this process so far (Linux; 0 elsewhere).
fn cpu_seconds() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return 0.0;
    };
    // Fields after the command name (which is in parentheses): utime is the 14th field
    // of the line, stime the 15th, in clock ticks of 1/100 s.
    let Some(rest) = stat.rsplit(')').next() else {
        return 0.0;
    };
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| {
        fields
            .get(i)
            .and_then(|f| f.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    (ticks(11) + ticks(12)) / 100.0
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let runs: usize = std::env::args().nth(1).map_or(Ok(15), |a| a.parse())?;
    let experiment = PaperExperiment::generate(0)?;
    let validation = &experiment.validation;
    for backend in [Backend::EXACT, Backend::PAPER] {
        for threads in [1, 2] {
            let options = McOptions {
                samples: 1000,
                threads,
                backend,
                ..McOptions::default()
            };
            let band = || {
                monte_carlo_band(
                    &Parameters::PAPER,
                    &validation.excitation,
                    Some(&validation.output),
                    &options,
                )
            };
            band()?; // warm-up
            let (mut wall, mut cpu) = (Vec::new(), Vec::new());
            let cpu_start = cpu_seconds();
            for _ in 0..runs {
                let t = Instant::now();
                std::hint::black_box(band()?);
                wall.push(t.elapsed().as_secs_f64() * 1e3);
            }
            cpu.push((cpu_seconds() - cpu_start) / runs as f64 * 1e3);
            println!(
                "{:<6} {threads} thread(s): wall median {:7.1} ms, CPU {:7.1} ms per run",
                backend.name(),
                median(wall),
                median(cpu)
            );
        }
    }
    Ok(())
}
