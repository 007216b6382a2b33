//! A suite run on a shared store's workers (`proleg suite ... --store URL`): the run is a
//! stored run of the store whose evaluations are its episodes
//! ([`crate::optimize::shared::suite_job`]), with the suite and the controller's files
//! stored beside it, so `proleg worker --store URL` on any host runs them with nothing but
//! the URL; this process's own threads run them too. Each result is written to the local
//! journal as it arrives; a run stopped (or a lost machine) resumes from the journal and
//! from the store, whose finished episodes are not run again, wherever they ran.

use std::sync::Mutex;
use std::time::Duration;

use crate::control::ModuleRegistry;
use crate::optimize::error::OptimizeError;
use crate::optimize::shared::driver::LocalWorkers;
use crate::optimize::shared::suite_job::{SuiteJob, episode_entry, episode_key, episode_result};
use crate::optimize::shared::work::RunWork;
use crate::optimize::store::pg_queue::{DONE, Pending};
use crate::optimize::store::{ExperimentStore, PgStore, PgTarget, RunInfo, program_version};
use crate::signal::StopFlag;
use crate::sim::episode::course::EpisodeKey;
use crate::suite::error::SuiteError;
use crate::suite::journal::Journal;
use crate::suite::run::{Progress, SuiteRun, lock};

/// Longest wait between two looks at the store when no result is announced.
const LOOK_EVERY: Duration = Duration::from_secs(1);

/// Where and with what a suite runs on a shared store.
#[derive(Debug, Clone)]
pub struct SharedSuite {
    /// The store.
    pub target: PgTarget,
    /// The suite file's and the controller's files as read (path, text): what workers
    /// load them from.
    pub files: Vec<(String, String)>,
    /// The suite file's path among `files`.
    pub suite: String,
    /// The controller's simulation file's path among `files`.
    pub controller: String,
    /// The lease of a claim (a worker that dies leaves its episode to another after it).
    pub lease: Duration,
}

/// The stored run of `job` (the last one with its identity), or a new one.
fn find_or_start(
    store: &mut PgStore,
    info: &RunInfo,
    files: &[(String, String)],
) -> Result<i64, OptimizeError> {
    match store.latest_run(info)? {
        Some(id) => Ok(id),
        None => Ok(store.start_run(info, &program_version(), files, &[])?),
    }
}

/// Puts what the store holds of `all` into the journal (reporting each); the keys still
/// missing from it.
fn take_stored(
    store: &mut PgStore,
    id: i64,
    run: &SuiteRun<'_>,
    journal: &Mutex<Journal>,
    all: &[EpisodeKey],
    progress: Progress<'_>,
) -> Result<Vec<EpisodeKey>, SuiteError> {
    let stored = store.evaluations(id)?;
    let mut j = lock(journal);
    for eval in &stored {
        let Some(r) = episode_result(run.suite, eval) else {
            let key = episode_key(run.suite, &eval.genome);
            return Err(SuiteError::FailedOnWorker {
                run: id,
                episode: key.map(|k| run.describe(k)).unwrap_or_default(),
            });
        };
        if all.contains(&r.key) && !j.done.contains_key(&r.key) {
            j.append(run.suite, &r)?;
            let done = all.iter().filter(|k| j.done.contains_key(k)).count();
            progress(&r, done, all.len());
        }
    }
    Ok(all
        .iter()
        .copied()
        .filter(|k| !j.done.contains_key(k))
        .collect())
}

/// Runs the episodes of `all` the journal lacks through the store `shared` names, this
/// process's `run.threads` threads among its workers, until every one is in the journal
/// or `stop` is raised.
pub fn run_on_store(
    run: &SuiteRun<'_>,
    shared: &SharedSuite,
    registry: &ModuleRegistry,
    journal: &Mutex<Journal>,
    all: &[EpisodeKey],
    stop: Option<&StopFlag>,
    progress: Progress<'_>,
) -> Result<(), SuiteError> {
    let mut store = PgStore::open(&shared.target, true)?;
    let job = SuiteJob {
        suite: shared.suite.clone(),
        fingerprint: run.fingerprint(),
        engines: run.engines.clone(),
    };
    let seed = run.controller.files.simulation.properties.seed;
    let info = job.info(&shared.controller, seed);
    let id = find_or_start(&mut store, &info, &shared.files)?;
    store.listen(DONE)?;
    let mut missing = take_stored(&mut store, id, run, journal, all, progress)?;
    if missing.is_empty() {
        store.finish_run(id)?;
        return Ok(());
    }
    let pending: Vec<Pending> = missing
        .iter()
        .filter_map(|&k| episode_entry(run.suite, k))
        .map(|(number, genome)| Pending {
            number,
            round: 0,
            values: genome.iter().map(|&g| f64::from(g)).collect(),
            genome,
        })
        .collect();
    store.enqueue(id, seed, &pending)?;
    let spec = store.run_spec(id)?;
    let work =
        RunWork::of(&spec, registry).map_err(|why| OptimizeError::Unevaluable { run: id, why })?;
    let mut local = LocalWorkers::start(&store, registry, work, id, run.threads, shared.lease);
    while !missing.is_empty() && !stop.is_some_and(StopFlag::is_set) {
        local.check()?;
        store.wait_notification(LOOK_EVERY)?;
        missing = take_stored(&mut store, id, run, journal, all, progress)?;
    }
    local.finish(&mut store)?;
    if missing.is_empty() {
        store.finish_run(id)?;
    }
    Ok(())
}
