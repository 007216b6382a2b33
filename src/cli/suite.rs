//! `proleg suite SUITE CONTROLLER`: a controller (a simulation file: its robot, control and
//! physics properties; or, with `--run R`, a store's run whose best candidate is exported
//! into the output folder) scored on every task's held-out test courses of a suite, on
//! both engines, in parallel, with progress; the table printed, and written as CSV and
//! JSON beside the journal it resumes from.

use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::config::simulation::EngineKind;
use crate::config::source::normalize;
use crate::config::{FsSource, RecordingSource, load_simulation_with};
use crate::control::ModuleRegistry;
use crate::optimize::export::export_candidate;
use crate::optimize::store::{Store, StoreLocation};
use crate::suite::run::journal_path;
use crate::suite::shared::SharedSuite;
use crate::suite::{SuiteError, SuiteReport, SuiteRun};

/// Command-line options of `proleg suite`.
#[derive(clap::Args)]
pub struct SuiteArgs {
    /// The suite file (`configs/suites/locomotion.suite.xml`).
    pub suite: PathBuf,
    /// The controller: a simulation file (its robot and actuation; the suite gives the
    /// ground), or with `--run` an experiment store (SQLite file or postgres:// URL).
    pub controller: PathBuf,
    /// The controller is this run's best candidate in the store CONTROLLER names (written
    /// into OUT/controller/ as `proleg results --export-robot best` writes it).
    #[arg(long)]
    pub run: Option<i64>,
    /// The engines every course runs on (comma-separated; default: every engine here).
    #[arg(long, value_delimiter = ',')]
    pub engines: Vec<EngineKind>,
    /// Only these tasks (comma-separated names).
    #[arg(long, value_delimiter = ',')]
    pub tasks: Vec<String>,
    /// Episodes run at once here (default: the cores; with `--store` 0 leaves every
    /// episode to the workers).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Run the episodes through this shared store, on `proleg worker --store URL` of any
    /// host beside this process's threads: postgres://USER@HOST[:PORT]/DATABASE (password
    /// from the URL, PGPASSWORD or ~/.pgpass; never printed). A run stopped resumes from
    /// what the store holds.
    #[arg(long)]
    pub store: Option<String>,
    /// With `--store`: seconds a claim stays valid without a heartbeat (a killed worker's
    /// episode is run again this long after its last one).
    #[arg(long, default_value_t = crate::optimize::settings::DEFAULT_LEASE_S)]
    pub lease: f64,
    /// The output folder: the journal (`episodes.csv`), `suite.csv`, `suite.json`, `suite.png`
    /// (default: `suite-results/SUITE-CONTROLLER`, with `--run R` `...-runR`).
    #[arg(short = 'o', long = "out")]
    pub out: Option<PathBuf>,
    /// No line per finished episode.
    #[arg(long)]
    pub quiet: bool,
}

/// Why a suite run failed.
#[derive(Debug, thiserror::Error)]
pub enum SuiteCommandError {
    /// The suite run.
    #[error("{0}")]
    Suite(#[from] SuiteError),
    /// The suite or the controller does not load.
    #[error("{0}")]
    Config(#[from] crate::config::ConfigError),
    /// Ctrl-C cannot be handled.
    #[error("{0}")]
    Signal(#[from] crate::signal::SignalError),
    /// The table cannot be written.
    #[error("{0}")]
    Write(#[from] crate::config::bundle::BundleError),
    /// The table cannot be put as JSON.
    #[error("the table as JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// The store's run cannot be read or exported.
    #[error("{0}")]
    Store(#[from] crate::optimize::error::OptimizeError),
    /// The store's location is not one.
    #[error("{0}")]
    Location(#[from] crate::optimize::error::BadChoice),
    /// `--store` names a store that is not shared (a SQLite file).
    #[error(
        "--store {0}: a suite runs on the workers of a PostgreSQL store (postgres://...), not of a file"
    )]
    NotShared(String),
}

/// The report and where it was written.
#[derive(Debug)]
pub struct SuiteOutcome {
    /// The table.
    pub report: SuiteReport,
    /// The output folder.
    pub out: PathBuf,
}

impl std::fmt::Display for SuiteOutcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.report)?;
        writeln!(
            f,
            "wrote {0}/suite.csv, {0}/suite.json, {0}/suite.png (episodes: {0}/episodes.csv)",
            self.out.display()
        )
    }
}

/// Run `run`'s best candidate of the store at `location`, exported into `OUT/controller/`;
/// the simulation file that runs it.
fn export_best(
    location: &StoreLocation,
    run: i64,
    out: &std::path::Path,
    registry: &ModuleRegistry,
) -> Result<PathBuf, SuiteCommandError> {
    let mut store =
        Store::open_existing(location).map_err(crate::optimize::error::OptimizeError::from)?;
    Ok(export_candidate(
        &mut store,
        run,
        None,
        &out.join("controller"),
        registry,
    )?)
}

fn stem(p: &std::path::Path) -> String {
    let name = p
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    name.split('.').next().unwrap_or("run").to_string()
}

/// Where and with what files the suite runs on a shared store.
fn shared_suite(
    url: &str,
    a: &SuiteArgs,
    controller: &Path,
    recording: &RecordingSource,
) -> Result<SharedSuite, SuiteCommandError> {
    let StoreLocation::Postgres(target) = StoreLocation::parse(url)? else {
        return Err(SuiteCommandError::NotShared(url.to_string()));
    };
    if !a.lease.is_finite() || a.lease <= 0.0 {
        return Err(crate::optimize::error::BadChoice::Lease(a.lease).into());
    }
    let path = |p: &Path| normalize(p).display().to_string();
    Ok(SharedSuite {
        target: *target,
        files: recording.files(),
        suite: path(&a.suite),
        controller: path(controller),
        lease: Duration::from_secs_f64(a.lease),
    })
}

/// Runs the suite the options name.
pub fn run(a: &SuiteArgs, registry: &ModuleRegistry) -> Result<SuiteOutcome, SuiteCommandError> {
    let recording = RecordingSource::new(&FsSource);
    let suite = crate::config::suite::load_suite(&recording, &a.suite)?;
    let engines = if a.engines.is_empty() {
        crate::sim::engine::ready_engines()
    } else {
        a.engines.clone()
    };
    let out = a.out.clone().unwrap_or_else(|| {
        let run = a.run.map_or(String::new(), |r| format!("-run{r}"));
        PathBuf::from("suite-results").join(format!(
            "{}-{}{run}",
            stem(&a.suite),
            stem(&a.controller)
        ))
    });
    std::fs::create_dir_all(&out).map_err(|source| SuiteError::Journal {
        path: out.clone(),
        source,
    })?;
    let (controller_file, label) = match a.run {
        None => (a.controller.clone(), a.controller.display().to_string()),
        Some(run) => {
            // The label names the store as its Display does: never a URL's password.
            let location = StoreLocation::parse(&a.controller.to_string_lossy())?;
            let file = export_best(&location, run, &out, registry)?;
            (file, format!("{location} run {run}"))
        }
    };
    let controller = load_simulation_with(&recording, &controller_file, registry)?;
    let shared = match &a.store {
        None => None,
        Some(url) => Some(shared_suite(url, a, &controller_file, &recording)?),
    };
    let run = SuiteRun {
        path: a.suite.clone(),
        suite: &suite,
        controller: &controller,
        label,
        engines,
        tasks: SuiteRun::select(&suite, &a.tasks)?,
        threads: a
            .threads
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())),
        journal: journal_path(&out),
        shared,
    };
    let signal = crate::signal::subscribe_with(|| {
        eprintln!(
            "stopping: the episodes in flight are abandoned; the finished ones are in the journal (run the same command again to go on)"
        );
    })?;
    let stop = signal.flag();
    let quiet = a.quiet;
    let progress = |r: &crate::sim::episode::course::EpisodeResult, done: usize, total: usize| {
        if !quiet {
            eprintln!(
                "[{done}/{total}] {} seed {} on {}: {:.3} m{}",
                suite.tasks[r.key.task].name,
                r.key.seed,
                r.key.engine.name(),
                r.distance,
                if r.crossed { ", crossed the goal" } else { "" }
            );
        }
    };
    let report = run.run(registry, Some(&stop), &progress)?;
    crate::config::bundle::write_file(&out.join("suite.csv"), &report.csv())?;
    let json = serde_json::to_string_pretty(&report)?;
    crate::config::bundle::write_file(&out.join("suite.json"), &json)?;
    let goals: Vec<f64> = report
        .tasks
        .iter()
        .filter_map(|row| suite.task(&row.task).map(|t| t.goal))
        .collect();
    crate::suite::chart::plot(&report, &goals, &out.join("suite.png"), (1200, 650))?;
    Ok(SuiteOutcome { report, out })
}
