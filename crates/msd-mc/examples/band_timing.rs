//! Wall and CPU time of the paper's Monte Carlo band (N = 1000, validation input) for
//! each backend on 1 and 2 threads: medians of repeated runs, the four configurations
//! taken in turn. CPU time (user + system, all threads, from /proc/self/stat on Linux,
//! in ticks of 10 ms: a median over many runs) is less disturbed by other load on a
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
    let configs: Vec<McOptions> = [Backend::EXACT, Backend::PAPER]
        .into_iter()
        .flat_map(|backend| {
            [1, 2].map(|threads| McOptions {
                samples: 1000,
                threads,
                backend,
                ..McOptions::default()
            })
        })
        .collect();
    let band = |options: &McOptions| {
        monte_carlo_band(
            &Parameters::PAPER,
            &validation.excitation,
            Some(&validation.output),
            options,
        )
    };
    for options in &configs {
        band(options)?; // warm-up
    }
    // Round-robin, so that the machine's drift falls on every configuration alike,
    // the throughput probe included.
    let mut probe = (Vec::new(), Vec::new());
    let (mut wall, mut cpu) = (
        vec![Vec::new(); configs.len()],
        vec![Vec::new(); configs.len()],
    );
    for _ in 0..runs {
        for (k, options) in configs.iter().enumerate() {
            let (t, c) = (Instant::now(), cpu_seconds());
            std::hint::black_box(band(options)?);
            wall[k].push(t.elapsed().as_secs_f64() * 1e3);
            cpu[k].push((cpu_seconds() - c) * 1e3);
        }
        let (one, two) = throughput_probe();
        probe.0.push(one);
        probe.1.push(two);
    }
    for (k, options) in configs.iter().enumerate() {
        println!(
            "{:<6} {} thread(s): wall median {:7.1} ms, CPU median {:7.1} ms per run",
            options.backend.name(),
            options.threads,
            median(wall[k].clone()),
            median(cpu[k].clone())
        );
    }
    let speedup = |k: usize| median(wall[k].clone()) / median(wall[k + 1].clone());
    println!(
        "2-thread speed-up: exact {:.2}, ode45 {:.2}",
        speedup(0),
        speedup(2)
    );
    println!(
        "the machine's own 2-thread speed-up on an FP-throughput loop: {:.2} (a ceiling for the exact band)",
        2.0 * median(probe.0) / median(probe.1)
    );
    Ok(())
}

/// Vectorisable multiply-adds on an L1-resident array, the kind of work the exact band
/// is made of: seconds for the loop once on one thread, then on two threads at once.
/// Twice the first over the second is the machine's 2-thread speed-up on such work; on
/// a machine whose two vCPUs share a core's floating-point units it is well below 2,
/// and no parallel band can beat it.
fn throughput_probe() -> (f64, f64) {
    fn work(seed: f64) -> f64 {
        let a: Vec<f64> = (0..2048).map(|i| seed + i as f64 * 1e-3).collect();
        let mut acc = [0.0f64; 8];
        // About 70 ms: long enough that starting the second thread (a wake-up of the
        // other vCPU, up to milliseconds here) does not count.
        for _ in 0..200_000 {
            for c in a.chunks_exact(8) {
                for (s, &x) in acc.iter_mut().zip(c) {
                    *s += x * 1.000_000_1 + 0.5;
                }
            }
        }
        acc.iter().sum()
    }
    let t = Instant::now();
    std::hint::black_box(work(1.0));
    let one = t.elapsed().as_secs_f64();
    let t = Instant::now();
    std::thread::scope(|s| {
        let other = s.spawn(|| work(2.0));
        std::hint::black_box(work(1.0));
        std::hint::black_box(other.join().expect("no panic"));
    });
    (one, t.elapsed().as_secs_f64())
}
