//! Minimises Rosenbrock's function from (−1.2, 1) with fminsearch's defaults and
//! prints the result in the wording of fminsearch's output struct.
//!
//! Run with `cargo run -p msd-opt --example rosenbrock` (add `-- --iter` for the
//! iteration trace, like `optimset('Display','iter')`).

use msd_opt::{NelderMeadOptions, TRACE_HEADER, nelder_mead};

fn main() {
    let show_trace = std::env::args().any(|a| a == "--iter");
    let rosenbrock = |x: &[f64]| 100.0 * (x[1] - x[0] * x[0]).powi(2) + (1.0 - x[0]).powi(2);
    let options = NelderMeadOptions {
        trace: show_trace,
        ..NelderMeadOptions::default()
    };
    match nelder_mead(rosenbrock, &[-1.2, 1.0], &options) {
        Ok(result) => {
            if show_trace {
                println!("\n{TRACE_HEADER}");
                for row in &result.trace {
                    println!("{row}");
                }
                println!();
            }
            println!("{result}");
        }
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}
