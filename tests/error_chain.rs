//! Errors keep their causes: a command's error exposes the error beneath it through
//! `std::error::Error::source`, down to the system's error, so a caller can tell a missing
//! file from a bad value without reading the message.

use std::error::Error;
use std::sync::Arc;

use proleg::cli::error::CliError;
use proleg::cli::run::{RunRequest, run};
use proleg::config::ConfigError;
use proleg::config::error::ErrorKind;
use proleg::control::ModuleRegistry;

#[test]
fn a_missing_simulation_file_is_a_chain_from_the_command_to_the_system_error() {
    let missing = std::env::temp_dir().join("proleg-no-such.simulation.xml");
    let req = RunRequest::of(missing.clone());
    let err = run(&req, &ModuleRegistry::standard()).expect_err("no such file");
    assert!(matches!(err, CliError::Config(_)), "{err:?}");
    let mut chain: Vec<&(dyn Error + 'static)> = vec![&err];
    let mut next = err.source();
    while let Some(e) = next {
        chain.push(e);
        next = e.source();
    }
    assert_eq!(chain.len(), 3, "command, file, system: {chain:?}");
    let file = chain[1]
        .downcast_ref::<ConfigError>()
        .expect("the file's error beneath the command's");
    assert_eq!(file.file, missing);
    assert_eq!(file.kind, ErrorKind::MissingFile);
    let system = chain[2]
        .downcast_ref::<Arc<std::io::Error>>()
        .expect("the system's error beneath the file's");
    assert_eq!(system.kind(), std::io::ErrorKind::NotFound);
    // The message printed is the file's, named with its path.
    assert!(
        err.to_string().contains("proleg-no-such.simulation.xml"),
        "{err}"
    );
}
