//! `cargo xtask`: the task runner of the msd toolkit.
//!
//! Following the xtask convention, `main` calls `try_main`, prints any error and exits
//! non-zero. Tasks arrive as they are built (see the README).

use clap::Parser;
use std::process::ExitCode;

/// Tasks of the msd toolkit.
#[derive(Debug, Parser)]
#[command(name = "cargo xtask", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

/// The available tasks.
#[derive(Debug, clap::Subcommand)]
enum Command {}

fn main() -> ExitCode {
    match try_main() {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn try_main() -> Result<(), String> {
    let cli = Cli::parse();
    match cli.command {
        None => {
            println!("no task given; run `cargo xtask --help` for the list of tasks");
            Ok(())
        }
    }
}
