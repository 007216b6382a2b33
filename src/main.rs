//! The `proleg` command line: parses the arguments, runs the command
//! ([`proleg::commands`]) and prints what it returns, or its error.

use std::process::ExitCode;

use clap::Parser;

use proleg::commands::{Cli, Commands};

fn main() -> ExitCode {
    let cli = Cli::parse();
    // The user module library: every command sees the plugin modules.
    let commands = Commands::open();
    for message in commands.warnings(&cli) {
        eprintln!("warning: {message}");
    }
    match commands.execute(cli) {
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
