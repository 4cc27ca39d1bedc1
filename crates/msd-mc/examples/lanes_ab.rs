//! TEMPORARY: the paper's ode45 band (N = 1000, validation input) with `Ode45Lanes`
//! against one `Ode45Stepper` per draw, alternating rounds in one process, on 1 and 2
//! threads; checks that both give the same bits. A run during which other processes
//! used the CPU (from /proc/stat, less this process's own time) is discarded and redone.
//!
//! `cargo run --release -p msd-mc --example lanes_ab [rounds] [runs per round]`
use msd_ident::{Backend, ODE45_PER_DRAW, PaperExperiment, Parameters};
use msd_mc::{McOptions, monte_carlo_band};
use std::sync::atomic::Ordering;
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn loadavg() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_default()
}

/// Busy ticks of the whole machine and of this process.
fn ticks() -> (u64, u64) {
    let stat = std::fs::read_to_string("/proc/stat").unwrap_or_default();
    let cpu: Vec<u64> = stat
        .lines()
        .next()
        .unwrap_or("")
        .split_whitespace()
        .skip(1)
        .filter_map(|f| f.parse().ok())
        .collect();
    // user nice system idle iowait irq softirq steal
    let busy = cpu[0] + cpu[1] + cpu[2] + cpu[5] + cpu[6] + cpu[7];
    let own = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let rest = own.rsplit(')').next().unwrap_or("");
    // Fields after the command: state (3rd of the line), …, utime (14th), stime (15th).
    let f: Vec<&str> = rest.split_whitespace().collect();
    let n = |i: usize| f.get(i).and_then(|v| v.parse::<u64>().ok()).unwrap_or(0);
    (busy, n(11) + n(12))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let rounds: usize = args.next().map_or(Ok(5), |a| a.parse())?;
    let runs: usize = args.next().map_or(Ok(5), |a| a.parse())?;
    let experiment = PaperExperiment::generate(0)?;
    let v = &experiment.validation;
    let band = |threads: usize, per_draw: bool| {
        ODE45_PER_DRAW.store(per_draw, Ordering::Relaxed);
        let options = McOptions {
            samples: 1000,
            threads,
            backend: Backend::PAPER,
            ..McOptions::default()
        };
        monte_carlo_band(&Parameters::PAPER, &v.excitation, Some(&v.output), &options)
    };
    let variants = [(1, false), (1, true), (2, false), (2, true)];
    for threads in [1, 2] {
        let (a, b) = (band(threads, false)?, band(threads, true)?);
        let bits = |band: &msd_mc::Band| -> Vec<u64> {
            band.percentiles
                .iter()
                .flat_map(|(_, p)| p.iter().map(|x| x.to_bits()))
                .collect()
        };
        assert_eq!(bits(&a), bits(&b), "both variants give the same bits");
        assert_eq!(a, b);
    }
    println!("same bits: yes; load average at start: {}", loadavg());
    let mut medians = vec![Vec::new(); variants.len()];
    let mut all = vec![Vec::new(); variants.len()];
    let mut discarded = 0;
    let mut loads = Vec::new();
    for round in 0..rounds {
        for (k, &(threads, per_draw)) in variants.iter().enumerate() {
            let mut times = Vec::new();
            while times.len() < runs {
                let (busy0, own0) = ticks();
                let t = Instant::now();
                std::hint::black_box(band(threads, per_draw)?);
                let ms = t.elapsed().as_secs_f64() * 1e3;
                let (busy1, own1) = ticks();
                let others = (busy1 - busy0).saturating_sub(own1 - own0);
                if others > 2 {
                    discarded += 1;
                    std::thread::sleep(std::time::Duration::from_millis(500));
                    continue;
                }
                times.push(ms);
            }
            all[k].extend(&times);
            medians[k].push(median(times));
        }
        loads.push(loadavg());
        println!(
            "round {round}: load {}, discarded so far {discarded}",
            loadavg()
        );
    }
    println!(
        "load average at end: {}; runs discarded (other CPU use > 20 ms): {discarded}",
        loadavg()
    );
    for (k, &(threads, per_draw)) in variants.iter().enumerate() {
        let min = all[k].iter().copied().fold(f64::INFINITY, f64::min);
        let max = all[k].iter().copied().fold(0.0, f64::max);
        println!(
            "{} thread(s), {:<9}: median of round medians {:6.1} ms (rounds {:?}), all runs {:6.1} – {:6.1} ms",
            threads,
            if per_draw { "per-draw" } else { "lanes" },
            median(medians[k].clone()),
            medians[k]
                .iter()
                .map(|m| (m * 10.0f64).round() / 10.0)
                .collect::<Vec<_>>(),
            min,
            max
        );
    }
    // Paired: one run of each variant back to back (order alternating), the saving of
    // each pair, for a fine-grained view under drifting load.
    let pairs: usize = args.next().map_or(Ok(0), |a| a.parse())?;
    for threads in [1, 2] {
        let mut savings = Vec::new();
        let clean = |per_draw: bool| -> Result<f64, Box<dyn std::error::Error>> {
            loop {
                let (busy0, own0) = ticks();
                let t = Instant::now();
                std::hint::black_box(band(threads, per_draw)?);
                let ms = t.elapsed().as_secs_f64() * 1e3;
                let (busy1, own1) = ticks();
                if (busy1 - busy0).saturating_sub(own1 - own0) <= 2 {
                    return Ok(ms);
                }
                std::thread::sleep(std::time::Duration::from_millis(500));
            }
        };
        for i in 0..pairs {
            let (lanes, each) = if i % 2 == 0 {
                let l = clean(false)?;
                (l, clean(true)?)
            } else {
                let e = clean(true)?;
                (clean(false)?, e)
            };
            savings.push(100.0 * (1.0 - lanes / each));
        }
        if pairs > 0 {
            let mut sorted = savings.clone();
            sorted.sort_by(f64::total_cmp);
            println!(
                "{threads} thread(s), {pairs} pairs: saving median {:.1} %, quartiles {:.1} – {:.1} %",
                median(savings),
                sorted[pairs / 4],
                sorted[3 * pairs / 4]
            );
        }
    }
    for threads in [1, 2] {
        let k = if threads == 1 { 0 } else { 2 };
        let (lanes, each) = (median(medians[k].clone()), median(medians[k + 1].clone()));
        println!(
            "{threads} thread(s): lanes save {:.1} % of the per-draw time ({:.2}×)",
            100.0 * (1.0 - lanes / each),
            each / lanes
        );
    }
    Ok(())
}
