//! The evaluating end of a shared store: threads that claim pending evaluations, run each
//! in a world of its own and write the score, and a heartbeat that renews their leases.
//! `proleg worker` runs one such pool; the driver runs another on its own cores.

use std::collections::{HashMap, VecDeque};
use std::sync::mpsc::{RecvTimeoutError, TryRecvError, channel};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use crate::control::ModuleRegistry;
use crate::optimize::error::OptimizeError;
use crate::optimize::evaluate::{CandidateScore, EvalError};
use crate::optimize::shared::work::RunWork;
use crate::optimize::store::pg_queue::{Claim, ClaimResult, PENDING};
use crate::optimize::store::{ExperimentStore, PgStore, PgTarget, StoreError};
use crate::signal::StopFlag;

/// Longest wait between two looks for work when no notification comes (an expired lease
/// announces itself to no one).
const IDLE_POLL: Duration = Duration::from_secs(1);

/// How often a worker looks again for a store that is not there yet.
const STORE_POLL: Duration = Duration::from_secs(1);

/// How a pool of workers runs.
#[derive(Debug, Clone)]
pub struct WorkerOptions {
    /// Evaluating threads (each with its own connection).
    pub threads: usize,
    /// Lease of a claim; the heartbeat renews it every third of it.
    pub lease: Duration,
    /// Exit after this long with nothing to claim (`None`: run until stopped).
    pub idle_exit: Option<Duration>,
    /// Claim only this run's evaluations (the driver's own threads).
    pub only_run: Option<i64>,
}

/// What a pool did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WorkerReport {
    /// Results written.
    pub evaluated: u64,
    /// Results discarded because their claim's lease had run out.
    pub discarded: u64,
    /// Episodes that failed to build (stored as failed, scored `-inf` by the driver).
    pub failed: u64,
    /// Why runs were refused (one line each).
    pub refused: Vec<String>,
    /// Seconds spent in successful claims and in writing results (the coordination).
    pub coordination: f64,
    /// Wall seconds of the pool.
    pub wall: f64,
    /// Whether the connections are encrypted (TLS).
    pub encrypted: bool,
}

impl WorkerReport {
    /// Milliseconds of claim and write per evaluation.
    pub fn overhead_ms(&self) -> f64 {
        let n = (self.evaluated + self.discarded).max(1);
        self.coordination * 1000.0 / n as f64
    }
}

/// This process's name in claims: host, process id and start time (a reused pid differs).
pub fn worker_id() -> String {
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_string())
        .unwrap_or_else(|_| "host".into());
    let nonce = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.subsec_nanos())
        .unwrap_or(0);
    format!("{host}/{}/{nonce:08x}", std::process::id())
}

/// How long workers and the driver try to reach a store that went away before giving up.
pub const OUTAGE: Duration = Duration::from_secs(300);

/// An evaluated claim whose score is still to be written.
struct Unsent {
    claim: Claim,
    score: CandidateScore,
    wall: f64,
}

/// What one evaluating thread keeps between claims.
struct ThreadState {
    /// The work of the runs seen, by run.
    works: HashMap<i64, Arc<RunWork>>,
    /// Since when there was nothing to claim.
    idle_since: Instant,
    /// Claims taken and not evaluated yet (one batch).
    claimed: VecDeque<Claim>,
    /// Results not written yet: the batch's, or those the store could not take (its
    /// connection was lost).
    unsent: Vec<Unsent>,
    /// Mean wall seconds of an episode here, once one ran (sizes the claim batches).
    episode_seconds: Option<f64>,
}

impl ThreadState {
    /// How many evaluations to claim at once: about [`BATCH_SECONDS`] of work at this
    /// thread's measured speed (one until it has measured one), at most [`MAX_BATCH`].
    fn batch(&self) -> i64 {
        match self.episode_seconds {
            Some(s) if s > 0.0 => ((BATCH_SECONDS / s).floor() as i64).clamp(1, MAX_BATCH),
            _ => 1,
        }
    }
}

/// Seconds of work a thread claims at once: short episodes go in batches (one claim and
/// one write per batch instead of per evaluation), long ones one by one, so that a round's
/// last evaluations are not held by one thread while others wait.
const BATCH_SECONDS: f64 = 0.25;

/// Most evaluations claimed at once.
const MAX_BATCH: i64 = 64;

/// What the threads of a pool share.
struct Pool<'a> {
    target: &'a PgTarget,
    registry: &'a ModuleRegistry,
    options: &'a WorkerOptions,
    id: String,
    stop: &'a StopFlag,
    preloaded: Option<(i64, Arc<RunWork>)>,
    refused: Mutex<Vec<i64>>,
    report: Mutex<WorkerReport>,
    on_message: &'a (dyn Fn(&str) + Sync),
}

/// Runs a pool until `stop` is set, or it has been idle for `idle_exit`; `preloaded` is the
/// work of one run already built (the driver's), `on_message` hears refusals and failed
/// episodes.
pub fn run_pool(
    target: &PgTarget,
    registry: &ModuleRegistry,
    options: &WorkerOptions,
    stop: &StopFlag,
    preloaded: Option<(i64, Arc<RunWork>)>,
    on_message: &(dyn Fn(&str) + Sync),
) -> Result<WorkerReport, OptimizeError> {
    let t = Instant::now();
    let pool = Pool {
        target,
        registry,
        options,
        id: worker_id(),
        stop,
        preloaded,
        refused: Mutex::new(Vec::new()),
        report: Mutex::new(WorkerReport::default()),
        on_message,
    };
    let Some(mut heartbeat_store) = open_when_ready(target, options.idle_exit, stop, on_message)?
    else {
        return Ok(WorkerReport::default());
    };
    let encrypted = heartbeat_store.encrypted()?;
    let (alive, beats) = channel::<()>();
    // The heartbeat hears nothing but the close of this channel when the last thread ends.
    let results = std::thread::scope(|s| {
        let pool = &pool;
        let threads: Vec<_> = (0..options.threads.max(1))
            .map(|_| {
                let alive = alive.clone();
                s.spawn(move || {
                    let r = pool.evaluate_loop();
                    drop(alive);
                    r
                })
            })
            .collect();
        drop(alive);
        let beat = heartbeat(&mut heartbeat_store, &pool.id, options.lease, &beats);
        let mut results: Vec<Result<(), OptimizeError>> = threads
            .into_iter()
            .map(|h| h.join().unwrap_or(Err(OptimizeError::Panicked)))
            .collect();
        results.push(beat);
        results
    });
    let mut report = pool.report.into_inner().unwrap_or_default();
    report.wall = t.elapsed().as_secs_f64();
    report.encrypted = encrypted;
    match results.into_iter().find_map(Result::err) {
        Some(e) => Err(e),
        None => Ok(report),
    }
}

/// Opens the store, waiting while it is not there yet — the database holds no store because
/// no driver has created it (a worker started before its driver), or, within `idle_exit`,
/// no server answers (a host that boots first) — and saying once that it waits. Gives up
/// with the last error after `idle_exit`; `None` when stopped while waiting.
fn open_when_ready(
    target: &PgTarget,
    idle_exit: Option<Duration>,
    stop: &StopFlag,
    on_message: &(dyn Fn(&str) + Sync),
) -> Result<Option<PgStore>, OptimizeError> {
    let started = Instant::now();
    let mut said = false;
    loop {
        match PgStore::open(target, false) {
            Ok(store) => {
                if said {
                    on_message("the store is there: starting");
                }
                return Ok(Some(store));
            }
            // No server at all is waited for only within `--idle-exit` (a host that boots
            // first); without it, a wrong address is said at once.
            Err(e @ StoreError::NoServer { .. }) if idle_exit.is_none() => {
                return Err(e.into());
            }
            Err(e @ (StoreError::NotAStore { .. } | StoreError::NoServer { .. })) => {
                if idle_exit.is_some_and(|limit| started.elapsed() >= limit) {
                    return Err(e.into());
                }
                if !said {
                    on_message(&format!("waiting for the store to appear ({e})"));
                    said = true;
                }
            }
            Err(e) => return Err(e.into()),
        }
        let again = Instant::now() + STORE_POLL;
        while Instant::now() < again {
            if stop.is_set() {
                return Ok(None);
            }
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

/// Renews the pool's leases every third of a lease until every thread has ended (the
/// channel closes).
fn heartbeat(
    store: &mut PgStore,
    id: &str,
    lease: Duration,
    beats: &std::sync::mpsc::Receiver<()>,
) -> Result<(), OptimizeError> {
    loop {
        if let Err(RecvTimeoutError::Disconnected) = beats.recv_timeout(lease / 3) {
            return Ok(());
        }
        if let Err(e) = store.renew(id, lease) {
            if !store.is_closed() {
                return Err(e.into());
            }
            let threads_ended = || matches!(beats.try_recv(), Err(TryRecvError::Disconnected));
            if let Err(e) = store.reconnect(OUTAGE, &threads_ended)
                && !threads_ended()
            {
                return Err(e.into());
            }
        }
    }
}

impl Pool<'_> {
    /// One thread: claim, evaluate, write, until stopped or idle long enough. A lost
    /// connection (the server restarted) is made again, for up to [`OUTAGE`]; a result
    /// that could not be written then is written after it, if its lease still holds.
    fn evaluate_loop(&self) -> Result<(), OptimizeError> {
        let mut store = PgStore::open(self.target, false)?;
        store.listen(PENDING)?;
        let mut thread = ThreadState {
            works: HashMap::new(),
            idle_since: Instant::now(),
            claimed: VecDeque::new(),
            unsent: Vec::new(),
            episode_seconds: None,
        };
        if let Some((run, e)) = &self.preloaded {
            thread.works.insert(*run, e.clone());
        }
        while !self.stop.is_set() {
            match self.step(&mut store, &mut thread) {
                Ok(true) => {}
                Ok(false) => return self.finish(&mut store, &mut thread),
                Err(e) if store.is_closed() => {
                    (self.on_message)(&format!("lost the store ({e}); connecting again"));
                    store.reconnect(OUTAGE, &|| self.stop.is_set())?;
                    (self.on_message)("connected again");
                }
                Err(e) => return Err(e),
            }
        }
        self.finish(&mut store, &mut thread)
    }

    /// Leaving: the results written, the claims not evaluated given back.
    fn finish(&self, store: &mut PgStore, thread: &mut ThreadState) -> Result<(), OptimizeError> {
        self.flush(store, thread)?;
        for claim in thread.claimed.drain(..) {
            store.release(&self.id, &claim)?;
        }
        Ok(())
    }

    /// One evaluation of the batch claimed (claiming the next batch, after writing the last
    /// one's results, when it is done), or a wait for work; `false` when idle long enough.
    fn step(&self, store: &mut PgStore, thread: &mut ThreadState) -> Result<bool, OptimizeError> {
        if thread.claimed.is_empty() {
            self.flush(store, thread)?;
            let refused = self.refused.lock().map(|r| r.clone()).unwrap_or_default();
            let t = Instant::now();
            let claims = store.claim(
                &self.id,
                self.options.lease,
                self.options.only_run,
                &refused,
                thread.batch(),
            )?;
            if !claims.is_empty() {
                self.count_coordination(t.elapsed().as_secs_f64());
            }
            thread.claimed.extend(claims);
        }
        let Some(claim) = thread.claimed.pop_front() else {
            if self
                .options
                .idle_exit
                .is_some_and(|limit| thread.idle_since.elapsed() >= limit)
            {
                return Ok(false);
            }
            store.wait_notification(IDLE_POLL)?;
            return Ok(true);
        };
        let work = match self.work(store, &mut thread.works, claim.run) {
            Ok(e) => e,
            Err(e) if store.is_closed() => {
                thread.claimed.push_front(claim);
                return Err(e);
            }
            Err(why) => {
                self.refuse(claim.run, &why);
                let (theirs, rest): (VecDeque<Claim>, VecDeque<Claim>) =
                    std::mem::take(&mut thread.claimed)
                        .into_iter()
                        .partition(|c| c.run == claim.run);
                thread.claimed = rest;
                for c in std::iter::once(claim).chain(theirs) {
                    store.release(&self.id, &c)?;
                }
                return Ok(true);
            }
        };
        let Some(result) = self.evaluate(&work, claim.clone()) else {
            // Stopped mid-episode: the claim goes back with the others (`finish`), for
            // another worker now rather than when its lease runs out.
            thread.claimed.push_front(claim);
            return Ok(true);
        };
        thread.episode_seconds = Some(match thread.episode_seconds {
            Some(mean) => 0.8 * mean + 0.2 * result.wall,
            None => result.wall,
        });
        thread.unsent.push(result);
        thread.idle_since = Instant::now();
        Ok(true)
    }

    /// Writes the results not written yet, in one statement, and counts them; kept for
    /// the next try when the store cannot take them.
    fn flush(&self, store: &mut PgStore, thread: &mut ThreadState) -> Result<(), OptimizeError> {
        if thread.unsent.is_empty() {
            return Ok(());
        }
        let t = Instant::now();
        let results: Vec<ClaimResult> = thread
            .unsent
            .iter()
            .map(|u| ClaimResult {
                claim: &u.claim,
                score: &u.score,
                wall: u.wall,
            })
            .collect();
        let accepted = store.submit_many(&self.id, &results)?;
        self.count_coordination(t.elapsed().as_secs_f64());
        if let Ok(mut r) = self.report.lock() {
            for (u, taken) in thread.unsent.iter().zip(accepted) {
                if !taken {
                    r.discarded += 1;
                } else {
                    r.evaluated += 1;
                    if u.score.score.is_nan() {
                        r.failed += 1;
                    }
                }
            }
        }
        thread.unsent.clear();
        Ok(())
    }

    /// Adds seconds spent claiming or writing to the report.
    fn count_coordination(&self, seconds: f64) {
        if let Ok(mut r) = self.report.lock() {
            r.coordination += seconds;
        }
    }

    /// Runs one claimed episode; `None` when the pool was stopped before it ended.
    fn evaluate(&self, work: &RunWork, claim: Claim) -> Option<Unsent> {
        let t = Instant::now();
        let failed = CandidateScore::single(f64::NAN);
        let score = match work.score(&claim.genome) {
            Ok(score) => score,
            Err(EvalError::Stopped) => return None,
            Err(e) => {
                (self.on_message)(&format!(
                    "run {} evaluation {}: the episode failed: {e}",
                    claim.run, claim.number
                ));
                failed
            }
        };
        Some(Unsent {
            claim,
            score,
            wall: t.elapsed().as_secs_f64(),
        })
    }

    /// The work of `run`, built from the store on its first claim.
    fn work(
        &self,
        store: &mut PgStore,
        cache: &mut HashMap<i64, Arc<RunWork>>,
        run: i64,
    ) -> Result<Arc<RunWork>, OptimizeError> {
        if let Some(e) = cache.get(&run) {
            return Ok(e.clone());
        }
        let spec = store.run_spec(run)?;
        let e = Arc::new(
            RunWork::of(&spec, self.registry)
                .map_err(|why| OptimizeError::Unevaluable { run, why })?
                .with_stop(self.stop.clone()),
        );
        cache.insert(run, e.clone());
        Ok(e)
    }

    /// Leaves `run` to other workers from now on, saying why once.
    fn refuse(&self, run: i64, why: &OptimizeError) {
        let Ok(mut refused) = self.refused.lock() else {
            return;
        };
        if refused.contains(&run) {
            return;
        }
        refused.push(run);
        let line = match why {
            OptimizeError::Unevaluable { why, .. } => format!("refusing run {run}: {why}"),
            other => format!("refusing run {run}: {other}"),
        };
        (self.on_message)(&line);
        if let Ok(mut r) = self.report.lock() {
            r.refused.push(line);
        }
    }
}
