//! `proleg worker`: evaluates the pending candidates of every run in a shared PostgreSQL
//! store, on this host's cores, until stopped (Ctrl-C, SIGTERM) or idle for `--idle-exit`.

use std::fmt;
use std::time::Duration;

use crate::cli::error::CliError;
use crate::control::ModuleRegistry;
use crate::optimize::shared::worker::{WorkerOptions, WorkerReport, run_pool};
use crate::optimize::store::StoreLocation;

/// Command-line options of `proleg worker`.
#[derive(clap::Args)]
pub struct WorkerArgs {
    /// The shared store: postgres://USER@HOST[:PORT]/DATABASE[?sslmode=require] (password
    /// from the URL, PGPASSWORD or ~/.pgpass; never printed).
    #[arg(long)]
    pub store: String,
    /// Evaluating threads (default: the number of cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Seconds a claim stays valid without a heartbeat; a killed worker's evaluations are
    /// claimed again this long after its last heartbeat.
    #[arg(long, default_value_t = crate::optimize::settings::DEFAULT_LEASE_S)]
    pub lease: f64,
    /// Exit after this many seconds with nothing to claim (default: run until stopped).
    /// A worker started before its driver waits for the store to appear, up to this long
    /// (without it, until stopped); with it, it also waits this long for a server that
    /// does not answer yet.
    #[arg(long)]
    pub idle_exit: Option<f64>,
    /// No messages on stderr (refused runs, failed episodes).
    #[arg(long)]
    pub quiet: bool,
}

/// What a worker did.
#[derive(Debug, Clone, PartialEq)]
pub struct WorkerRun {
    /// The store, as it may be shown (no password).
    pub store: String,
    /// Evaluating threads.
    pub threads: usize,
    /// What the pool did.
    pub report: WorkerReport,
}

/// Runs the worker the options ask for.
pub fn run(a: &WorkerArgs, registry: &ModuleRegistry) -> Result<WorkerRun, CliError> {
    let StoreLocation::Postgres(target) = StoreLocation::parse(&a.store)? else {
        return Err(CliError::Option {
            option: "--store",
            value: a.store.clone(),
            want: "proleg worker needs a postgres:// store (a SQLite store is evaluated by the optimizing process itself)",
        });
    };
    let seconds = |option: &'static str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(Duration::from_secs_f64(v))
        } else {
            Err(CliError::Option {
                option,
                value: v.to_string(),
                want: "give a number of seconds > 0",
            })
        }
    };
    let threads = a.threads.unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    });
    if threads == 0 {
        return Err(CliError::Option {
            option: "--threads",
            value: "0".into(),
            want: "give at least 1",
        });
    }
    let options = WorkerOptions {
        threads,
        lease: seconds("--lease", a.lease)?,
        idle_exit: a.idle_exit.map(|v| seconds("--idle-exit", v)).transpose()?,
        only_run: None,
    };
    // Ctrl-C / SIGTERM abandon the episodes in flight at once (the episode runner sees the
    // flag between chunks) and hand their claims back; every written result stays.
    let signal = crate::signal::subscribe_with(|| {
        eprintln!(
            "\nworker: stopping: the episodes in flight are abandoned and their claims handed back; every result written stays (Ctrl-C again quits at once)"
        );
    })?;
    let stop = signal.flag();
    let quiet = a.quiet;
    let report = run_pool(&target, registry, &options, &stop, None, &|m| {
        if !quiet {
            eprintln!("worker: {m}");
        }
    })?;
    Ok(WorkerRun {
        store: target.to_string(),
        threads,
        report,
    })
}

impl fmt::Display for WorkerRun {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = &self.report;
        writeln!(
            f,
            "worker on {} ({}, {} thread(s)), {:.1} s: {} evaluations written, {} late results discarded, {} failed episodes",
            self.store,
            if r.encrypted { "TLS" } else { "unencrypted" },
            self.threads,
            r.wall,
            r.evaluated,
            r.discarded,
            r.failed
        )?;
        writeln!(
            f,
            "coordination    {:.2} ms per evaluation (claim + write); {:.0} evaluations/h",
            r.overhead_ms(),
            r.evaluated as f64 / r.wall.max(1e-9) * 3600.0
        )?;
        for line in &r.refused {
            writeln!(f, "{line}")?;
        }
        Ok(())
    }
}
