//! The `proleg` command line: parses the arguments, runs the command
//! ([`proleg::commands`]) and prints what it returns, or its error. A command that Ctrl-C
//! or SIGTERM stopped exits with the shell's status for it (130, 143); a window a signal
//! closed exits cleanly, as from its close button.

use std::process::ExitCode;

use clap::Parser;

use proleg::commands::{Cli, Commands};

fn main() -> ExitCode {
    let cli = Cli::parse();
    // Before any thread starts: an off-screen renderer on a machine with no session would
    // have Mesa's device-select layer print errors that are none (`gui::video::vulkan`).
    #[cfg(feature = "gui")]
    if let Some((name, value)) = proleg::gui::video::vulkan::headless_setting_here() {
        // SAFETY: the process has one thread yet, so nothing reads the environment meanwhile.
        unsafe { std::env::set_var(name, value) };
    }
    // The user module library: every command sees the plugin modules.
    let commands = Commands::open();
    for message in commands.warnings(&cli) {
        eprintln!("warning: {message}");
    }
    let window = cli.opens_a_window();
    let result = commands.execute(cli);
    let stopped_by = proleg::signal::received().filter(|_| !window);
    match result {
        Ok(text) => print!("{text}"),
        Err(e) if stopped_by.is_some() => eprintln!("stopped: {e}"),
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    }
    match stopped_by {
        Some(signal) => ExitCode::from(proleg::signal::exit_status(signal)),
        None => ExitCode::SUCCESS,
    }
}
