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

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Bench {
            config,
            seconds,
            batches,
        } => match proleg::bench::report(&config, seconds, &batches) {
            Ok(text) => {
                print!("{text}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        },
        Command::Run {
            config,
            duration,
            seed,
            realtime,
        } => match cli_run::run(&config, duration, seed, realtime) {
            Ok(text) => {
                print!("{text}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        },
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
