#![allow(missing_docs)]
use msd_ident::{Backend, PaperExperiment, Parameters};
use msd_mc::{McOptions, monte_carlo_band};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let backend = if args[1] == "exact" {
        Backend::EXACT
    } else {
        Backend::PAPER
    };
    let threads: usize = args[2].parse().unwrap();
    let runs: usize = args[3].parse().unwrap();
    let experiment = PaperExperiment::generate(0).unwrap();
    let v = &experiment.validation;
    let options = McOptions {
        samples: 1000,
        threads,
        backend,
        ..McOptions::default()
    };
    for _ in 0..runs {
        let t = std::time::Instant::now();
        std::hint::black_box(
            monte_carlo_band(&Parameters::PAPER, &v.excitation, Some(&v.output), &options).unwrap(),
        );
        eprintln!("band {:?}", t.elapsed());
    }
}
