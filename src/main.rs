//! The `proleg` command line.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod cli_run;

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
    /// Throughput figures of the reference scenario (robot-steps per second, real-time factors).
    Bench {
        /// The reference simulation.
        #[arg(long, default_value = "configs/demo.simulation.xml")]
        config: PathBuf,
        /// Simulated seconds per figure.
        #[arg(long, default_value_t = 30.0)]
        seconds: f64,
        /// Batch sizes (robots sharing one world) to measure besides 1.
        #[arg(long, value_delimiter = ',', default_values_t = vec![8, 31])]
        batches: Vec<usize>,
    },
    /// Run one simulation headless and print what the robot did.
    Run {
        /// A `*.simulation.xml` file.
        config: PathBuf,
        /// Simulated seconds (default: the file's duration).
        #[arg(long)]
        duration: Option<f64>,
        /// Random seed (default: the file's seed).
        #[arg(long)]
        seed: Option<u64>,
        /// Pace to real time times this factor (default 0: as fast as possible).
        #[arg(long, default_value_t = 0.0)]
        realtime: f64,
    },
}

/// Prints a command's output, or its error, and gives the exit code.
fn finish(result: Result<String, String>) -> ExitCode {
    match result {
        Ok(text) => {
            print!("{text}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    finish(match cli.command {
        Command::Bench {
            config,
            seconds,
            batches,
        } => proleg::bench::report(&config, seconds, &batches),
        Command::Run {
            config,
            duration,
            seed,
            realtime,
        } => cli_run::run(&config, duration, seed, realtime),
        Command::Check { config } => proleg::config::load_simulation(&config)
            .map(|sim| format!("{}ok\n", proleg::config::summary::summary(&sim)))
            .map_err(|e| e.to_string()),
    })
}
