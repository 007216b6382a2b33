//! `proleg dashboard STORE`: serves the live web page over a store until stopped (Ctrl-C,
//! SIGTERM); says where at start (with the token for a remote bind, printed only there).

use std::net::SocketAddr;

use crate::cli::error::CliError;
use crate::control::ModuleRegistry;
use crate::dashboard::{DashboardError, DashboardOptions, serve};
use crate::optimize::store::StoreLocation;

/// Command-line options of `proleg dashboard`.
#[derive(clap::Args, Debug)]
pub struct DashboardArgs {
    /// The store: a SQLite file or postgres://USER@HOST[:PORT]/DATABASE (password from
    /// PGPASSWORD or ~/.pgpass; never shown). Only read.
    pub store: String,
    /// Address and port to listen on. Loopback needs no token; any other address gets a
    /// token, printed once at start, that every request must present.
    #[arg(long, default_value = "127.0.0.1:8080")]
    pub bind: String,
    /// Where evaluations' videos and data files are kept once made (default:
    /// ~/.cache/proleg/dashboard, or $XDG_CACHE_HOME/proleg/dashboard).
    #[arg(long)]
    pub cache: Option<std::path::PathBuf>,
}

/// What a dashboard did.
#[derive(Debug, Clone, PartialEq)]
pub struct DashboardRun {
    /// The store it showed (no password).
    pub store: String,
}

impl std::fmt::Display for DashboardRun {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "dashboard over {} stopped", self.store)
    }
}

/// Serves the dashboard the options ask for until stopped, its videos rendered by
/// `renderer` (none: a build without renderer).
pub fn run(
    a: &DashboardArgs,
    renderer: Option<std::sync::Arc<dyn crate::dashboard::media::VideoRenderer>>,
    registry: &ModuleRegistry,
) -> Result<DashboardRun, CliError> {
    let bind: SocketAddr = a.bind.parse().map_err(|_| {
        CliError::Dashboard(DashboardError::BadBind {
            given: a.bind.clone(),
        })
    })?;
    let location = StoreLocation::parse(&a.store)?;
    let signal = crate::signal::subscribe()?;
    let stop = signal.flag().0;
    let mut store = String::new();
    serve(
        &DashboardOptions {
            location,
            bind,
            cache: a
                .cache
                .clone()
                .unwrap_or_else(crate::dashboard::media::default_cache),
            renderer,
        },
        registry,
        &stop,
        |ready| {
            store = ready.store.clone();
            println!(
                "proleg dashboard over {}: open {}   (Ctrl-C stops it)",
                ready.store,
                ready.url()
            );
        },
    )
    .map_err(CliError::Dashboard)?;
    Ok(DashboardRun { store })
}
