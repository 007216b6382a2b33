//! The `proleg` command line.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Design, simulate, optimize and drive chain-like modular robots.
#[derive(Parser)]
#[command(name = "proleg", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Validate a simulation file and everything it includes, and print a summary.
    Check {
        /// A `*.simulation.xml` file.
        config: PathBuf,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Check { config } => match proleg::config::load_simulation(&config) {
            Ok(sim) => {
                print!("{}", proleg::config::summary::summary(&sim));
                println!("ok");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        },
    }
}
